//! `splineskin animate` through the command line: an animated SVG with one `<animate>` per
//! deformed element, a frames folder with the expected files (and PNGs), the authors' zooming
//! animation, and errors that name the scene and the element, exit non-zero and leave nothing.

mod common;

use std::path::Path;
use std::process::Output;

use common::cli::{ok, words};
use common::test_dir::TestDir;

const SVG: &str = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100">
  <path id="a" d="M10 50 C20 30 40 50 50 50 C70 50 80 30 90 50"/>
  <rect id="b" x="20" y="60" width="30" height="20"/>
</svg>"#;

fn scene(animation: &str) -> String {
    format!(
        r#"{{"splineskin_scene": 1, "svg": "drawing.svg",
  "handles": [{{"position": [10, 50]}}, {{"position": [90, 50]}}],
  "poses": [{{"name": "bend", "transforms": [{{}}, {{"rotate": 60}}]}}],
  "animation": {animation}}}"#
    )
}

const GOOD: &str = r#"{"fps": 10, "keyframes": [{"time": 0, "pose": [{}, {}]}, {"time": 0.3, "pose": "bend"}, {"time": 1, "pose": [{}, {"rotate": -90}]}]}"#;

/// A fresh folder holding `scene.json` and `drawing.svg`.
fn folder(name: &str, scene: &str) -> TestDir {
    let dir = TestDir::new(&format!("splineskin-animate-cli-{name}-"));
    std::fs::write(dir.join("drawing.svg"), SVG).unwrap();
    std::fs::write(dir.join("scene.json"), scene).unwrap();
    dir
}

fn animate(dir: &Path, args: &[&str]) -> Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_splineskin"))
        .current_dir(dir)
        .arg("animate")
        .args(args)
        .output()
        .unwrap()
}

/// The value of attribute `name` in `tag` (the text of one start tag).
fn attribute<'t>(tag: &'t str, name: &str) -> &'t str {
    let start = tag.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
    let len = tag[start..].find('"').unwrap();
    &tag[start..start + len]
}

/// Each `<path …><animate …/>` pair of `text`: the path's start tag and the animate's.
fn animated_paths(text: &str) -> Vec<(&str, &str)> {
    text.match_indices("<path ")
        .map(|(i, _)| {
            let path_end = i + text[i..].find('>').unwrap() + 1;
            let rest = &text[path_end..];
            assert!(rest.starts_with("<animate "), "{}", &text[i..path_end]);
            (&text[i..path_end], &rest[..rest.find("/>").unwrap()])
        })
        .collect()
}

fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn animate_cli_writes_animated_png_and_gif() {
    let dir = folder("images", &scene(GOOD));
    ok(&animate(
        &dir,
        &words("scene.json -o anim.png --image-size 80"),
    ));
    ok(&animate(
        &dir,
        &words("scene.json -o anim.gif --image-size 80"),
    ));
    ok(&animate(&dir, &words("scene.json -o frames")));
    // 1 s at 10 fps: 11 frames, 0.1 s each (the last one too), 80 × 80 (a square viewBox).
    let mut reader = png::Decoder::new(std::io::BufReader::new(
        std::fs::File::open(dir.join("anim.png")).unwrap(),
    ))
    .read_info()
    .unwrap();
    let control = reader.info().animation_control.unwrap();
    assert_eq!((control.num_frames, control.num_plays), (11, 0));
    assert_eq!((reader.info().width, reader.info().height), (80, 80));
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let mut apng = Vec::new();
    for _ in 0..11 {
        reader.next_frame(&mut buf).unwrap();
        let fc = reader.info().frame_control.unwrap();
        assert_eq!((fc.delay_num, fc.delay_den), (100, 1000));
        apng.push(buf.clone());
    }
    // Each APNG frame is the SVG frame of that time rendered at that size.
    for f in [0, 3, 10] {
        let svg = std::fs::read_to_string(dir.join(format!("frames/frame-{f:04}.svg"))).unwrap();
        let want = splineskin::render::render_rgba(&svg, 80).unwrap();
        assert_eq!(apng[f], want.data, "frame {f}");
    }
    assert_ne!(apng[0], apng[3], "the frames move");
    let mut options = gif::DecodeOptions::new();
    options.set_color_output(gif::ColorOutput::RGBA);
    let mut decoder = options
        .read_info(std::fs::File::open(dir.join("anim.gif")).unwrap())
        .unwrap();
    let mut n = 0;
    while let Some(frame) = decoder.read_next_frame().unwrap() {
        assert_eq!(frame.delay, 10);
        n += 1;
    }
    assert_eq!(n, 11);
    let out = animate(&dir, &words("scene.json -o bad.gif --image-size 0"));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--image-size 0"));
    let out = animate(&dir, &words("scene.json -o bad.png --png"));
    assert!(String::from_utf8_lossy(&out.stderr).contains("is one file"));
}

#[test]
fn animate_cli_writes_lottie() {
    let dir = folder("lottie", &scene(GOOD));
    let out = animate(&dir, &["scene.json", "-o", "anim.json"]);
    ok(&out);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("anim.json")).unwrap()).unwrap();
    // 1 s at 10 fps: frames 0..=10, a shape per path (the curve, the rect).
    assert_eq!(
        (doc["fr"].as_f64(), doc["op"].as_f64()),
        (Some(10.0), Some(10.0))
    );
    let layer = &doc["layers"][0];
    assert_eq!(layer["ty"], 4);
    let groups = layer["shapes"].as_array().unwrap();
    assert_eq!(groups.len(), 2, "{groups:?}");
    // The rect is on top, so first; both are filled black (SVG's default paint).
    for g in groups {
        let items = g["it"].as_array().unwrap();
        assert_eq!(items[0]["ty"], "sh");
        assert_eq!(items[0]["ks"]["a"], 1, "the shapes move");
        assert_eq!(items[1]["ty"], "fl");
        let colour: Vec<f64> = items[1]["c"]["k"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        assert_eq!(colour, [0.0, 0.0, 0.0, 1.0]);
    }
    assert!(
        stderr.contains("path keyframes of 22 (2 paths × 11 frames) within 0.001"),
        "{stderr}"
    );
    // Every frame kept with tolerance 0, and bad tolerances refused.
    let out = animate(&dir, &words("scene.json -o all.json --lottie-tolerance 0"));
    ok(&out);
    assert!(String::from_utf8_lossy(&out.stderr).contains("22 path keyframes of 22"));
    for bad in ["--lottie-tolerance=-1", "--lottie-tolerance=nan"] {
        let out = animate(&dir, &["scene.json", "-o", "bad.json", bad]);
        assert!(!out.status.success());
        assert!(String::from_utf8_lossy(&out.stderr).contains("--lottie-tolerance"));
    }
    let out = animate(&dir, &words("scene.json -o bad.json --png"));
    assert!(String::from_utf8_lossy(&out.stderr).contains("are for SVG output"));
    assert_eq!(
        listing(&dir),
        ["all.json", "anim.json", "drawing.svg", "scene.json"]
    );
}

#[test]
fn animate_cli_writes_an_animated_svg() {
    let dir = folder("svg", &scene(GOOD));
    let out = animate(&dir, &["scene.json", "-o", "out.svg"]);
    ok(&out);
    let text = std::fs::read_to_string(dir.join("out.svg")).unwrap();
    let paths = animated_paths(&text);
    assert_eq!(paths.len(), 2, "the rect became a path");
    assert_eq!(text.matches("<animate ").count(), 2);
    assert_eq!(text.matches("</path>").count(), 2);
    for (path, anim) in paths {
        let values: Vec<&str> = attribute(anim, "values").split(';').collect();
        assert_eq!(values.len(), 11, "0, 0.1, …, 1 s at 10 fps");
        assert_eq!(attribute(anim, "keyTimes").split(';').count(), 11);
        assert_eq!(attribute(anim, "dur"), "1s");
        assert_eq!(attribute(anim, "attributeName"), "d");
        assert_eq!(values[0], attribute(path, "d"));
        let n_c = |d: &str| d.matches('C').count();
        assert!(values.iter().all(|v| n_c(v) == n_c(values[0])));
    }
    // The fps and duration overrides.
    let out = animate(&dir, &words("scene.json -o out.svg --fps 4 --duration 2"));
    ok(&out);
    let text = std::fs::read_to_string(dir.join("out.svg")).unwrap();
    assert!(text.contains(r#"dur="2s""#));
    assert_eq!(text.matches("<animate ").count(), 2);
    let (_, anim) = animated_paths(&text)[0];
    assert_eq!(attribute(anim, "values").split(';').count(), 9);
    assert_eq!(listing(&dir), ["drawing.svg", "out.svg", "scene.json"]);
}

#[test]
fn animate_cli_writes_a_frames_folder() {
    let dir = folder("frames", &scene(GOOD));
    let out = animate(&dir, &words("scene.json -o frames --png --fps 5"));
    ok(&out);
    let want: Vec<String> = (0..6)
        .flat_map(|f| [format!("frame-{f:04}.png"), format!("frame-{f:04}.svg")])
        .collect();
    assert_eq!(listing(&dir.join("frames")), want);
    let png = std::fs::read(dir.join("frames/frame-0003.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    // Again, without PNGs: the earlier frames folder is replaced.
    let out = animate(&dir, &words("scene.json -o frames --fps 2"));
    ok(&out);
    assert_eq!(
        listing(&dir.join("frames")),
        ["frame-0000.svg", "frame-0001.svg", "frame-0002.svg"]
    );
    // A folder holding anything else is not touched.
    std::fs::write(dir.join("frames/notes.txt"), "mine").unwrap();
    let out = animate(&dir, &["scene.json", "-o", "frames"]);
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("holds notes.txt, which is not a frame"),
        "{stderr}"
    );
    assert!(dir.join("frames/notes.txt").exists());
    assert_eq!(listing(&dir), ["drawing.svg", "frames", "scene.json"]);
}

#[test]
fn animate_cli_authors_zooming_animation() {
    let Some(root) = common::external_data::shared_data() else {
        return;
    };
    let scene = root.join(
        "vectorskinning/turtle-seven-stack/zooming animation/after-zoomout/turtles-seven-deformation2.json",
    );
    let dir = folder("authors", "{}");
    let out = animate(
        &dir,
        &[
            scene.to_str().unwrap(),
            "-o",
            "zoom.svg",
            "--duration",
            "4",
            "--fps",
            "2",
        ],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("1200 keyframes, 9 frames at 2 fps over 4 s"),
        "{stderr}"
    );
    let text = std::fs::read_to_string(dir.join("zoom.svg")).unwrap();
    let animates = text.matches("<animate ").count();
    assert!(animates > 100, "{animates}");
    for (_, anim) in animated_paths(&text) {
        assert_eq!(attribute(anim, "values").split(';').count(), 9);
    }
}

#[test]
fn animate_cli_errors_name_scene_and_element_and_write_nothing() {
    let cases = [
        (
            "none",
            scene("null"),
            "scene.json: the scene has no animation",
        ),
        (
            "empty",
            scene(r#"{"keyframes": []}"#),
            "scene.json: animation: no keyframes",
        ),
        (
            "order",
            scene(r#"{"keyframes": [{"time": 0.5, "pose": 0}, {"time": 0.2, "pose": 0}]}"#),
            "scene.json: animation: keyframes[1]: time 0.2 is not after keyframes[0]'s 0.5",
        ),
        (
            "missing",
            scene(r#"{"keyframes": [{"time": 0, "pose": 3}]}"#),
            "scene.json: animation.keyframes[0].pose: pose 3 does not exist",
        ),
        (
            "single",
            scene(r#"{"keyframes": [{"time": 0, "pose": 0}]}"#),
            "scene.json: animation: the animation lasts 0 s",
        ),
        (
            "nan",
            scene(r#"{"keyframes": [{"time": 0, "pose": [[NaN, 0, 0, 1, 0, 0], {}]}]}"#),
            "scene.json: invalid scene JSON",
        ),
    ];
    for (name, text, want) in cases {
        let dir = folder(name, &text);
        for target in ["out.svg", "out.json", "out.png", "out.gif", "frames"] {
            let out = animate(&dir, &["scene.json", "-o", target]);
            let stderr = String::from_utf8_lossy(&out.stderr);
            assert!(!out.status.success(), "{name}");
            assert!(stderr.contains(want), "{name}: {stderr}");
            assert_eq!(listing(&dir), ["drawing.svg", "scene.json"], "{name}");
        }
    }
    // A bad override.
    let dir = folder("fps", &scene(GOOD));
    let out = animate(&dir, &words("scene.json -o out.svg --fps=-3"));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("scene.json: --fps: frame rate -3 is not in (0, 1000]"),
        "{stderr}"
    );
    assert_eq!(listing(&dir), ["drawing.svg", "scene.json"]);
    // A single-file name that is not .svg is refused, not made into a folder of that name.
    for target in ["anim.webp", "anim.JPG"] {
        let out = animate(&dir, &["scene.json", "-o", target]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{target}");
        assert!(
            stderr.contains(&format!(
                "{target}: an animation is written as an animated .svg"
            )),
            "{stderr}"
        );
        assert_eq!(listing(&dir), ["drawing.svg", "scene.json"]);
    }
}

/// Longer than one chunk of frames: every frame is written, in order, and each frame's paths
/// are the animated SVG's value at that frame (both are deformed from the same poses).
#[test]
fn animate_cli_frames_past_one_chunk_match_the_animated_svg() {
    let dir = folder("chunks", &scene(GOOD));
    for args in [
        &["scene.json", "-o", "frames", "--fps", "150"][..],
        &["scene.json", "-o", "all.svg", "--fps", "150"][..],
    ] {
        let out = animate(&dir, args);
        ok(&out);
    }
    let frames = listing(&dir.join("frames"));
    assert_eq!(frames.len(), 151, "0, 1/150, …, 1 s");
    let text = std::fs::read_to_string(dir.join("all.svg")).unwrap();
    let animated = animated_paths(&text);
    for (f, name) in frames.iter().enumerate() {
        assert_eq!(name, &format!("frame-{f:04}.svg"));
        let frame = std::fs::read_to_string(dir.join("frames").join(name)).unwrap();
        let ds: Vec<&str> = frame
            .match_indices("<path ")
            .map(|(i, _)| attribute(&frame[i..i + frame[i..].find('>').unwrap()], "d"))
            .collect();
        for (k, (_, anim)) in animated.iter().enumerate() {
            let value = attribute(anim, "values").split(';').nth(f).unwrap();
            assert_eq!(ds[k], value, "frame {f}, path {k}");
        }
    }
}

/// An animated SVG that would not fit in memory is refused before anything is computed, with
/// the way out in the message, and nothing is written.
#[test]
fn animate_cli_refuses_a_huge_animated_svg() {
    let mut d = String::from("M0 0");
    for k in 1..=3000 {
        d.push_str(&format!(" L{k} {}", k % 7));
    }
    let dir = TestDir::new("splineskin-animate-cli-huge-");
    std::fs::write(
        dir.join("drawing.svg"),
        format!(r#"<svg xmlns="http://www.w3.org/2000/svg"><path d="{d}"/></svg>"#),
    )
    .unwrap();
    std::fs::write(
        dir.join("scene.json"),
        r#"{"splineskin_scene": 1, "svg": "drawing.svg",
  "handles": [{"position": [0, 0]}, {"position": [3000, 0]}],
  "animation": {"fps": 1000, "keyframes": [{"time": 0, "pose": [{}, {}]}, {"time": 60, "pose": [{}, {"rotate": 30}]}]}}"#,
    )
    .unwrap();
    let out = animate(&dir, &["scene.json", "-o", "huge.svg"]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("huge.svg") && err.contains("frames folder"),
        "{err}"
    );
    assert_eq!(listing(&dir), ["drawing.svg", "scene.json"]);
}

/// PNG renders draw text in DejaVu Sans (shipped with splineskin): animate's PNG frames and
/// deform's PNG name the families drawn in it instead, once, and say nothing when the text
/// asks for no family or the drawing has no text.
#[test]
fn png_outputs_name_the_font_families_they_substitute() {
    let with_text = SVG.replace(
        "</svg>",
        r#"<text x="20" y="95" font-family="Arial">label</text><g><text x="60" y="95">two</text></g></svg>"#,
    );
    let dir = folder("text", &scene(GOOD));
    std::fs::write(dir.join("drawing.svg"), &with_text).unwrap();
    let out = animate(&dir, &words("scene.json -o frames --png --fps 2"));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("frame-0000.png: text drawn in DejaVu Sans in place of Arial"),
        "{stderr}"
    );
    assert_eq!(stderr.matches("in place of").count(), 1, "{stderr}");
    let deform = |dir: &Path, extra: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_splineskin"))
            .current_dir(dir)
            .args(["deform", "scene.json"])
            .args(extra)
            .output()
            .unwrap()
    };
    let out = deform(&dir, &["-o", "out.png"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("out.png: text drawn in DejaVu Sans in place of Arial"),
        "{stderr}"
    );
    // As outlines, no text is left to substitute a font for.
    let out = deform(&dir, &["-o", "outlined.png", "--text-outlines"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(!stderr.contains("in place of"), "{stderr}");

    let unnamed = folder("unnamed-font", &scene(GOOD));
    std::fs::write(
        unnamed.join("drawing.svg"),
        SVG.replace("</svg>", r#"<text x="20" y="95">label</text></svg>"#),
    )
    .unwrap();
    let plain = folder("no-text", &scene(GOOD));
    for dir in [&unnamed, &plain] {
        let out = deform(dir, &["-o", "out.png"]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{stderr}");
        assert!(!stderr.contains("in place of"), "{stderr}");
    }
}

/// `--text-outlines`: the text becomes paths of its glyphs that deform with the art, in the
/// animated SVG and in every frame; without it the text is written back as text.
#[test]
fn text_outlines_deform_with_the_art() {
    let with_text = SVG.replace(
        "</svg>",
        r#"<text id="t" x="60" y="55" font-size="12" fill="navy">Hi</text></svg>"#,
    );
    let dir = folder("outlines", &scene(GOOD));
    std::fs::write(dir.join("drawing.svg"), &with_text).unwrap();
    let out = animate(&dir, &words("scene.json -o anim.svg --text-outlines"));
    ok(&out);
    let text = std::fs::read_to_string(dir.join("anim.svg")).unwrap();
    assert!(!text.contains("<text"), "{text}");
    // "Hi": H one outline, i its stem and dot, all animated as one path element.
    let start = text.find("<path id=\"t\"").expect("the text as a path");
    let tag = &text[start..start + text[start..].find('>').unwrap()];
    assert!(tag.contains("fill=\"navy\""), "{tag}");
    assert_eq!(attribute(tag, "d").matches('M').count(), 3, "{tag}");
    let frames = &text[start..];
    let values = attribute(&frames[frames.find("<animate ").unwrap()..], "values");
    let first_and_last: Vec<&str> = values.split(';').collect();
    assert_ne!(first_and_last[0], first_and_last[first_and_last.len() / 2]);

    let out = animate(&dir, &["scene.json", "-o", "kept.svg"]);
    ok(&out);
    let kept = std::fs::read_to_string(dir.join("kept.svg")).unwrap();
    assert!(
        kept.contains(r#"<text id="t""#) && kept.contains(">Hi</text>"),
        "{kept}"
    );
}
