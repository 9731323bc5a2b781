//! `splineskin deform --flexible` and the scenes' `flexible` key through the command line: a
//! scene asking for flexible junctions (or the flag) deforms and says so; a malformed key and
//! an authors' pinned joint fail cleanly, naming the scene and what was wrong, and write
//! nothing.

mod common;

use std::process::Output;

use common::test_dir::TestDir;

/// A drawing with a smooth (G¹) junction of unequal tangents at (50, 50).
const SVG: &str = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100">
  <path d="M10 50 C20 30 40 50 50 50 C70 50 80 30 90 50"/>
</svg>"#;

/// A fresh folder holding `scene.json` (with `scene`) and `drawing.svg`.
fn folder(name: &str, scene: &str) -> TestDir {
    let dir = TestDir::new(&format!("splineskin-flexible-cli-{name}-"));
    std::fs::write(dir.join("drawing.svg"), SVG).unwrap();
    std::fs::write(dir.join("scene.json"), scene).unwrap();
    dir
}

fn deform(dir: &std::path::Path, extra: &[&str]) -> Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_splineskin"))
        .current_dir(dir)
        .args(["deform", "scene.json", "-o", "out.json"])
        .args(extra)
        .output()
        .unwrap()
}

fn ours(extra: &str) -> String {
    format!(
        r#"{{"splineskin_scene": 1, "svg": "drawing.svg",
  "handles": [{{"position": [10, 50]}}, {{"position": [90, 50]}}],
  "pose": [{{"rotate": 0}}, {{"rotate": 30}}]{extra}}}"#
    )
}

#[test]
fn deform_flexible_scene_key_and_flag() {
    for (name, scene, flags) in [
        ("key", ours(r#", "flexible": true"#), &[][..]),
        ("flag", ours(""), &["--flexible"][..]),
        (
            "flag-compat",
            ours(""),
            &["--flexible", "--compat", "vectorskinning"][..],
        ),
    ] {
        let dir = folder(name, &scene);
        let out = deform(&dir, flags);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{name}: {stderr}");
        assert!(
            stderr.contains("flexible: 1 junctions on 1 paths"),
            "{name}: {stderr}"
        );
        assert!(dir.join("out.json").is_file(), "{name}");
    }
    // Without key or flag the fit is the linear one, and says nothing about flexibility.
    let dir = folder("none", &ours(""));
    let out = deform(&dir, &[]);
    assert!(out.status.success());
    assert!(!String::from_utf8_lossy(&out.stderr).contains("flexible"));
}

#[test]
fn deform_flexible_malformed() {
    let svg = serde_json::to_string(SVG).unwrap();
    let identity = r#"{"a": 1, "b": 0, "c": 0, "d": 1, "e": 0, "f": 0}"#;
    let authors_pinned = format!(
        r#"{{"gInputSVGText": {svg}, "gHandles": [{{"pos": [10, 50], "transform": {identity}}}],
  "gPathsControlPointConstraints": [[{{"continuity": "None", "fixed": false}},
    {{"continuity": "G1", "fixed": true}}, {{"continuity": "None", "fixed": false}}]]}}"#
    );
    for (name, scene, expected) in [
        (
            "not-bool",
            ours(r#", "flexible": "yes""#),
            // serde names the place (line and column), not the key.
            &["scene.json", "expected a boolean", "line 3"][..],
        ),
        (
            "pinned",
            authors_pinned,
            &[
                "scene.json",
                "gPathsControlPointConstraints[0][1]",
                "fixed (pinned) joint",
                "not implemented",
            ][..],
        ),
    ] {
        let dir = folder(name, &scene);
        let out = deform(&dir, &["--flexible"]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{name}: succeeded");
        assert!(!stderr.contains("panicked"), "{name}: {stderr}");
        for e in expected {
            assert!(stderr.contains(e), "{name}: {stderr:?} lacks {e:?}");
        }
        assert!(!dir.join("out.json").exists(), "{name}: output written");
    }
}
