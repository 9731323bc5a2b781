//! `splineskin deform` says where a deformation folds an outline over itself: a square whose
//! corner pin is dragged across the opposite side warns with the path, the two curves and a
//! position on the crossing, and its JSON output lists them; the same square bent gently, and
//! the bundled fish under a small move, do not. `compare --json` counts each method's folds.

mod common;

use common::cli::ok_stderr;
use common::test_dir::TestDir;

/// A square outline, its corners pinned in the tests.
const SQUARE: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="-20 -20 60 60">
  <path id="square" d="M0 0 L20 0 L20 20 L0 20 Z" fill="#c84"/>
</svg>"##;

/// The numbers of `(x, y)` in a fold warning line.
fn position(line: &str) -> (f64, f64) {
    let inner = line.split(" cross at (").nth(1).expect("a position");
    let inner = inner.split(')').next().expect("closed");
    let mut numbers = inner
        .split(", ")
        .map(|v| v.parse::<f64>().expect("a number"));
    (numbers.next().unwrap(), numbers.next().unwrap())
}

#[test]
fn deform_warns_where_a_dragged_corner_folds_the_outline() {
    let dir = TestDir::new("splineskin-folds-cli-");
    std::fs::write(dir.join("square.svg"), SQUARE).unwrap();
    let pins = [
        "--pin", "0,0", "--pin", "20,0", "--pin", "20,20", "--pin", "0,20",
    ];
    // Deforms the square with its corners pinned by `moves`, written to `output`: the stderr.
    let deform_to = |moves: &[&str], output: &str| {
        let mut args = vec!["deform", "square.svg", "--weights", "bbw"];
        args.extend_from_slice(&pins);
        args.extend_from_slice(moves);
        args.extend_from_slice(&["-o", output]);
        ok_stderr(&dir, &args)
    };
    let run = |moves: &[&str]| deform_to(moves, "out.svg");
    // The JSON output of `moves`, written to `output`.
    let json_of = |moves: &[&str], output: &str| -> serde_json::Value {
        deform_to(moves, output);
        serde_json::from_str(&std::fs::read_to_string(dir.join(output)).unwrap()).unwrap()
    };
    // Corner (20, 20) dragged to (−10, 10): across the left side.
    let folded = run(&["--move", "2:-30,-10"]);
    let lines: Vec<&str> = folded
        .lines()
        .filter(|l| l.contains("folds over itself"))
        .collect();
    assert!(!lines.is_empty(), "{folded}");
    for line in &lines {
        assert!(
            line.contains("path 0 folds over itself: its curves"),
            "{line}"
        );
        // On the crossing: the dragged sides run between the pinned corners and (−10, 10), so
        // the crossing lies within their box.
        let (x, y) = position(line);
        assert!(
            (-10.0..=20.0).contains(&x) && (0.0..=20.0).contains(&y),
            "{line}"
        );
    }
    // The JSON output lists the same crossings, with the curves and positions.
    let json = json_of(&["--move", "2:-30,-10"], "out.json");
    let folds = json["folds"].as_array().expect("a folds list");
    assert_eq!(folds.len(), lines.len(), "{json}");
    for (fold, line) in folds.iter().zip(&lines) {
        let (x, y) = position(line);
        assert_eq!(fold["path"], 0);
        let at = fold["at"].as_array().unwrap();
        // The warning prints the same position (rounded).
        assert!(
            (at[0].as_f64().unwrap() - x).abs() < 1e-6
                && (at[1].as_f64().unwrap() - y).abs() < 1e-6,
            "{fold} vs {line}"
        );
    }
    // Gently: corner (20, 20) moved by (3, −2). No fold (with inverse-distance weights the
    // fit draws a spike at that corner, whose two sides overlap: a fold it reports).
    let gentle = run(&["--move", "2:3,-2"]);
    assert!(!gentle.contains("folds over itself"), "{gentle}");
    let json = json_of(&["--move", "2:3,-2"], "gentle.json");
    assert_eq!(json["folds"], serde_json::json!([]), "{json}");
}

#[test]
fn deform_bundled_fish_small_move_reports_no_fold() {
    let dir = TestDir::new("splineskin-folds-cli-fish-");
    let fish = concat!(env!("CARGO_MANIFEST_DIR"), "/../splineskin/assets/demo.svg");
    let stderr = ok_stderr(
        &dir,
        &["deform", fish, "--move", "0:0,-10", "-o", "out.svg"],
    );
    assert!(!stderr.contains("folds over itself"), "{stderr}");
}

#[test]
fn compare_json_counts_each_methods_folds() {
    let dir = TestDir::new("splineskin-folds-cli-compare-");
    // The square's corner dragged across (as above), as a scene with Shepard weights.
    let scene = serde_json::json!({
        "splineskin_scene": 1,
        "svg_text": SQUARE,
        "handles": [{"position": [0, 0]}, {"position": [20, 0]}, {"position": [20, 20]}, {"position": [0, 20]}],
        "weights": {"family": "bbw"},
        "poses": [
            {"name": "across", "transforms": [{}, {}, {"translate": [-30, -10]}, {}]},
            {"name": "gentle", "transforms": [{}, {}, {"translate": [3, -2]}, {}]}
        ]
    });
    std::fs::write(dir.join("square.json"), scene.to_string()).unwrap();
    let rows = |pose: &str| -> Vec<serde_json::Value> {
        let out = common::cli::ok(&common::cli::run(
            &dir,
            &[
                "compare",
                "square.json",
                "--pose",
                pose,
                "--json",
                "-o",
                "c.png",
            ],
        ));
        out.lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect()
    };
    let across = rows("across");
    let folds = |rows: &[serde_json::Value], method: &str| {
        rows.iter().find(|r| r["method"] == method).unwrap()["folds"].clone()
    };
    assert!(folds(&across, "ours").as_u64().unwrap() > 0, "{across:?}");
    assert_eq!(folds(&across, "schneider"), serde_json::Value::Null);
    let gentle = rows("gentle");
    for method in ["ours", "fourcontrols", "jacobian"] {
        assert_eq!(folds(&gentle, method), 0, "{method}: {gentle:?}");
    }
}
