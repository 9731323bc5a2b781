//! `--viewbox keep|fit` of `splineskin deform` and `splineskin animate` through the command
//! line, on a drawing whose handles all translate together (every weight family then moves
//! the drawing by exactly that translation, so the art's bounds are known in closed form):
//!
//! * `keep` writes the input's viewBox and warns naming the paths (and for an animation the
//!   frames) that leave it, with how far;
//! * `fit` writes the union of the input's viewBox and the art, and for an animation one
//!   viewBox for every frame, the union over all of them, in the animated SVG and in each file
//!   of a frames folder alike.
//!
//! `defop deform --viewbox` is tested in `defop_cli.rs` (it needs a trained operator).

mod common;

use std::path::Path;

use common::cli::{ok_stderr, words};
use common::test_dir::TestDir;

/// Art at rest: path `a` spans x 10 … 90 (its end points; its control points lie between)
/// and y 30 … 50, rect `b` spans x 20 … 50, y 60 … 80; the viewBox is 0 0 100 100.
const SVG: &str = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100">
  <path id="a" d="M10 50 C20 30 40 50 50 50 C70 50 80 30 90 50"/>
  <rect id="b" x="20" y="60" width="30" height="20"/>
</svg>"#;

/// Both handles translate by +30 in x at 0.5 s and by −25 at 1 s (10 frames a second): the
/// translation at frame f is 6f for f ≤ 5 and 30 − 11(f − 5) after, so path `a` leaves the
/// viewBox on the right in frames 2 … 6 (by 20 at frame 5) and on the left in frames 9 and 10
/// (by 15 at frame 10), rect `b` on the left in frame 10 only (by 5). Pose `right` is the
/// +30 translation alone.
const SCENE: &str = r#"{"splineskin_scene": 1, "svg": "drawing.svg",
  "handles": [{"position": [10, 50]}, {"position": [90, 50]}],
  "poses": [{"name": "right", "transforms": [{"translate": [30, 0]}, {"translate": [30, 0]}]}],
  "animation": {"fps": 10, "keyframes": [
    {"time": 0, "pose": [{}, {}]},
    {"time": 0.5, "pose": "right"},
    {"time": 1, "pose": [{"translate": [-25, 0]}, {"translate": [-25, 0]}]}]}}"#;

/// The union over all frames: x from −15 (frame 10) to 120 (frame 5), y the input's 0 … 100.
const FITTED: [f64; 4] = [-15.0, 0.0, 135.0, 100.0];

/// A deformation by one translation on every handle is that translation to rounding: 1e-9 of
/// the viewBox's size is far above rounding and far below any misplaced bound.
const TOLERANCE: f64 = 1e-9 * 100.0;

fn folder(name: &str) -> TestDir {
    let dir = TestDir::new(&format!("splineskin-viewbox-cli-{name}-"));
    std::fs::write(dir.join("drawing.svg"), SVG).unwrap();
    std::fs::write(dir.join("scene.json"), SCENE).unwrap();
    dir
}

/// The value of attribute `name` on the root `<svg>` start tag of `text`, if any.
fn root_attribute<'t>(text: &'t str, name: &str) -> Option<&'t str> {
    let start = text.find("<svg").unwrap();
    let tag = &text[start..start + text[start..].find('>').unwrap()];
    let at = tag.find(&format!(" {name}=\""))? + name.len() + 3;
    Some(&tag[at..at + tag[at..].find('"').unwrap()])
}

/// The root viewBox of the SVG file `path`, as four numbers.
fn view_box(path: &Path) -> [f64; 4] {
    let text = std::fs::read_to_string(path).unwrap();
    let values: Vec<f64> = root_attribute(&text, "viewBox")
        .unwrap_or_else(|| panic!("{}: no viewBox", path.display()))
        .split([' ', ','])
        .filter(|s| !s.is_empty())
        .map(|s| s.parse().unwrap())
        .collect();
    values.try_into().unwrap()
}

fn assert_close(found: [f64; 4], expected: [f64; 4], what: &str) {
    for k in 0..4 {
        assert!(
            (found[k] - expected[k]).abs() <= TOLERANCE,
            "{what}: viewBox {found:?}, expected {expected:?}"
        );
    }
}

#[test]
fn viewbox_cli_deform_keep_warns_and_fit_grows() {
    let dir = folder("deform");
    let stderr = ok_stderr(&dir, &words("deform scene.json --pose right -o keep.svg"));
    assert_eq!(view_box(&dir.join("keep.svg")), [0.0, 0.0, 100.0, 100.0]);
    assert!(
        stderr.contains("leaves the viewBox (cropped): path#a (line 2) by 20.000 (user units)"),
        "{stderr}"
    );
    let stderr = ok_stderr(
        &dir,
        &words("deform scene.json --pose right -o fit.svg --viewbox fit"),
    );
    assert!(stderr.contains("grows to include 1 path(s)"), "{stderr}");
    // x from the input's 0 to 90 + 30.
    assert_close(
        view_box(&dir.join("fit.svg")),
        [0.0, 0.0, 120.0, 100.0],
        "deform fit",
    );
}

#[test]
fn viewbox_cli_animate_keep_names_frames_and_paths() {
    let dir = folder("keep");
    let stderr = ok_stderr(&dir, &words("animate scene.json -o out.svg"));
    assert_eq!(view_box(&dir.join("out.svg")), [0.0, 0.0, 100.0, 100.0]);
    for expected in [
        "out.svg: the deformed art leaves the viewBox (cropped) in 7 of 11 frames (frames 2–10): ",
        "path#a (line 2) by 20.000 at frame 5 (outside in 7 frames), ",
        "rect#b (line 3) by 5.000 at frame 10 (outside in 1 frame) (user units)",
        "--viewbox fit",
    ] {
        assert!(stderr.contains(expected), "{expected:?} in {stderr}");
    }
    // A frames folder says the same and keeps the viewBox in every frame.
    let stderr = ok_stderr(&dir, &words("animate scene.json -o frames"));
    assert!(
        stderr.contains("in 7 of 11 frames (frames 2–10): path#a (line 2) by 20.000 at frame 5"),
        "{stderr}"
    );
    for f in 0..11 {
        let frame = dir.join(format!("frames/frame-{f:04}.svg"));
        assert_eq!(view_box(&frame), [0.0, 0.0, 100.0, 100.0], "frame {f}");
    }
    // Nothing leaves: nothing said.
    let still = SCENE.replace("-25", "0").replace("30, 0", "0, 0");
    std::fs::write(dir.join("still.json"), still).unwrap();
    let stderr = ok_stderr(&dir, &words("animate still.json -o still.svg"));
    assert!(!stderr.contains("viewBox"), "{stderr}");
}

#[test]
fn viewbox_cli_animate_fit_is_one_view_box_for_every_frame() {
    let dir = folder("fit");
    let stderr = ok_stderr(&dir, &words("animate scene.json -o out.svg --viewbox fit"));
    assert!(
        stderr.contains("out.svg: the viewBox grows to hold every frame (2 path(s)"),
        "{stderr}"
    );
    let text = std::fs::read_to_string(dir.join("out.svg")).unwrap();
    assert_close(view_box(&dir.join("out.svg")), FITTED, "animated SVG");
    // No width/height in the input: written as the viewBox size, grown in proportion.
    let width: f64 = root_attribute(&text, "width").unwrap().parse().unwrap();
    let height: f64 = root_attribute(&text, "height").unwrap().parse().unwrap();
    assert!((width - 135.0).abs() <= TOLERANCE && (height - 100.0).abs() <= TOLERANCE);
    assert_eq!(text.matches("<animate ").count(), 2, "still animated");

    // A frames folder: the same viewBox, to the byte, in every frame, and the frames' geometry
    // is that of a run keeping the viewBox.
    ok_stderr(&dir, &words("animate scene.json -o fit --viewbox fit"));
    ok_stderr(&dir, &words("animate scene.json -o keep"));
    let first = std::fs::read_to_string(dir.join("fit/frame-0000.svg")).unwrap();
    let first = root_attribute(&first, "viewBox").unwrap().to_string();
    for f in 0..11 {
        let name = format!("frame-{f:04}.svg");
        let fit = std::fs::read_to_string(dir.join("fit").join(&name)).unwrap();
        let keep = std::fs::read_to_string(dir.join("keep").join(&name)).unwrap();
        assert_eq!(root_attribute(&fit, "viewBox").unwrap(), first, "frame {f}");
        assert_close(view_box(&dir.join("fit").join(&name)), FITTED, &name);
        let body = |t: &str| t[t.find("<path").unwrap()..].to_string();
        assert_eq!(body(&fit), body(&keep), "frame {f}: the same paths");
    }
}
