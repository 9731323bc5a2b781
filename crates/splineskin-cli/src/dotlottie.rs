//! `.lottie` (dotLottie 2.0, <https://dotlottie.io/spec/2.0/>): a zip archive holding a
//! `manifest.json` that lists the animations and each animation's Lottie JSON as
//! `a/{id}.json`, deflated. The dotLottie players (`@lottiefiles/dotlottie-web` and the apps
//! built on ThorVG) open it; the JSON inside is what `splineskin::drawing::lottie::write_lottie`
//! writes (`animate -o anim.lottie`).

use std::io::Write;

use serde_json::json;
use zip::write::SimpleFileOptions;

use splineskin::drawing::lottie::LottieError;

/// A `.lottie` archive of the Lottie document `json`, its animation named `id` (letters,
/// digits, `-` and `_` kept, anything else written `_`; `animation` when nothing is left).
///
pub fn dotlottie(json: &str, id: &str) -> Result<Vec<u8>, LottieError> {
    let id = archive_id(id);
    let manifest = json!({
        "version": "2",
        "generator": concat!("splineskin ", env!("CARGO_PKG_VERSION")),
        "animations": [{"id": id}],
    });
    let mut archive = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let options = SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated);
    let failed = |e: &dyn std::fmt::Display| LottieError::Invalid {
        what: format!("writing the .lottie archive: {e}"),
    };
    for (name, text) in [
        ("manifest.json".to_string(), manifest.to_string()),
        (format!("a/{id}.json"), json.to_string()),
    ] {
        archive.start_file(name, options).map_err(|e| failed(&e))?;
        archive.write_all(text.as_bytes()).map_err(|e| failed(&e))?;
    }
    let cursor = archive.finish().map_err(|e| failed(&e))?;
    Ok(cursor.into_inner())
}

/// `name` as an animation id of the archive (module doc).
fn archive_id(name: &str) -> String {
    let id: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if id.chars().all(|c| c == '_') {
        "animation".to_string()
    } else {
        id
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Read;

    #[test]
    fn the_archive_holds_the_manifest_and_the_animation_as_written() {
        let json = r#"{"v":"5.12.0","w":10,"h":10,"fr":30,"ip":0,"op":1,"layers":[]}"#;
        let bytes = dotlottie(json, "fish & chips").unwrap();
        let mut archive = zip::ZipArchive::new(std::io::Cursor::new(bytes)).unwrap();
        let mut read = |name: &str| {
            let mut text = String::new();
            archive
                .by_name(name)
                .unwrap()
                .read_to_string(&mut text)
                .unwrap();
            text
        };
        let manifest: serde_json::Value = serde_json::from_str(&read("manifest.json")).unwrap();
        assert_eq!(manifest["version"], "2");
        assert_eq!(manifest["animations"][0]["id"], "fish___chips");
        assert_eq!(read("a/fish___chips.json"), json);
        assert_eq!(archive_id("  "), "animation");
    }
}
