//! `splineskin demo`, the README's first command: it writes the bundled drawing at rest and in
//! each of its poses as SVG and PNG; the posed SVGs read back with the same paths, the label's
//! text carries a transform (it follows the plate), and every path's exact bounds lie inside
//! the written viewBox (it grows where the art leaves the input's; nothing is cropped).

mod common;

use common::test_dir::TestDir;
use splineskin::drawing::svg_out::art_bounds;
use splineskin::drawing::{read_svg, ImportOptions};

/// The root viewBox of SVG text, as (x, y, width, height).
fn view_box(text: &str) -> [f64; 4] {
    let start = text.find("<svg").unwrap();
    let tag = &text[start..start + text[start..].find('>').unwrap()];
    let at = tag.find(" viewBox=\"").expect("a viewBox") + 10;
    let values: Vec<f64> = tag[at..at + tag[at..].find('"').unwrap()]
        .split([' ', ','])
        .filter(|s| !s.is_empty())
        .map(|s| s.parse().unwrap())
        .collect();
    values.try_into().unwrap()
}

#[test]
fn demo_writes_every_pose_uncropped_with_its_label_following() {
    let dir = TestDir::new("splineskin-demo-cli-");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_splineskin"))
        .args(["demo", "-o"])
        .arg(dir.join("out"))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let rest_text = std::fs::read_to_string(dir.join("out/rest.svg")).unwrap();
    let rest = read_svg(&rest_text, &ImportOptions::default()).unwrap();
    assert_eq!(view_box(&rest_text), [0.0, 0.0, 600.0, 400.0]);
    let poses = ["swish", "nose-up", "flap"];
    let mut grown = 0;
    for pose in poses {
        for ext in ["svg", "png"] {
            let file = dir.join(format!("out/{pose}.{ext}"));
            assert!(file.is_file(), "{}: not written ({stdout})", file.display());
        }
        let text = std::fs::read_to_string(dir.join(format!("out/{pose}.svg"))).unwrap();
        let posed = read_svg(&text, &ImportOptions::default()).unwrap();
        assert_eq!(posed.paths.len(), rest.paths.len(), "{pose}");
        assert_eq!(posed.n_curves(), rest.n_curves(), "{pose}");
        let label = &text[text.find("<text").expect("the label")..];
        let label = &label[..label.find('>').unwrap()];
        assert!(label.contains("transform=\"matrix("), "{pose}: {label}");
        let [x, y, w, h] = view_box(&text);
        if [x, y, w, h] != [0.0, 0.0, 600.0, 400.0] {
            grown += 1;
        }
        let art = art_bounds(&posed, &posed.flat_points()).unwrap().unwrap();
        // The viewBox is written in the shortest decimal that reads back; 1e-9 of its size.
        let slack = 1e-9 * w.max(h);
        assert!(
            art.x0 >= x - slack
                && art.y0 >= y - slack
                && art.x1 <= x + w + slack
                && art.y1 <= y + h + slack,
            "{pose}: art {art:?} outside viewBox {x} {y} {w} {h}"
        );
    }
    // The label plate leaves the input's viewBox in at least one pose: the check above is
    // not vacuous.
    assert!(grown > 0, "no pose grew the viewBox");
}
