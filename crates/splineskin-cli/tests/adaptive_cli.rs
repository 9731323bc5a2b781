//! `deform --tolerance` and `compare --tolerance` (adaptive control points): the JSON output
//! lists the inserted anchors, every input anchor is still there, the comparison has the two
//! adaptive methods; a tolerance that is not a positive number is refused with a message.

mod common;

use common::cli::{failed, json_lines, ok, run};
use common::test_dir::TestDir;

fn scene() -> String {
    concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../splineskin/assets/demo-scene.json"
    )
    .to_string()
}

fn paths(json: &serde_json::Value) -> Vec<Vec<[f64; 2]>> {
    json["paths"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            p["points"]
                .as_array()
                .unwrap()
                .iter()
                .map(|q| [q[0].as_f64().unwrap(), q[1].as_f64().unwrap()])
                .collect()
        })
        .collect()
}

#[test]
fn deform_tolerance_inserts_marked_anchors_and_keeps_the_others() {
    let dir = TestDir::new("splineskin-adaptive-cli-");
    let scene = scene();
    let read = |name: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(dir.join(name)).unwrap()).unwrap()
    };
    // The scene deformed with adaptive control points, written to `output`.
    let refined_args = |output| ["deform", &scene, "--tolerance", "0.001", "-o", output];
    ok(&run(&dir, &["deform", &scene, "-o", "plain.json"]));
    let stderr = common::cli::ok_stderr(&dir, &refined_args("refined.json"));
    assert!(stderr.contains("anchors inserted"), "{stderr}");
    // The summary counts the curves written: more than the input's 58.
    assert!(!stderr.contains(": 58 curves in 16 paths"), "{stderr}");
    let (plain, refined) = (read("plain.json"), read("refined.json"));
    assert!(plain["paths"][0].get("inserted").is_none(), "{plain}");
    let (a, b) = (paths(&plain), paths(&refined));
    let mut inserted_total = 0;
    for (p, (a, b)) in a.iter().zip(&b).enumerate() {
        let inserted: Vec<usize> = refined["paths"][p]["inserted"]
            .as_array()
            .unwrap()
            .iter()
            .map(|k| k.as_u64().unwrap() as usize)
            .collect();
        inserted_total += inserted.len();
        assert_eq!(b.len(), a.len() + 3 * inserted.len(), "path {p}");
        // The anchors not inserted are the input's, in order (deformed by a different fit,
        // so compared by count and order, not position: the ends of open paths too).
        let kept: Vec<usize> = (0..b.len())
            .step_by(3)
            .map(|i| i / 3)
            .filter(|k| !inserted.contains(k))
            .collect();
        assert_eq!(kept.len(), a.len().div_ceil(3), "path {p}");
    }
    assert!(inserted_total > 0);

    // In SVG output the inserted anchors are listed on their elements ("subpath:anchor"), the
    // same ones as in the JSON (the fish's elements are one subpath each, in path order).
    ok(&run(&dir, &refined_args("refined.svg")));
    let svg = std::fs::read_to_string(dir.join("refined.svg")).unwrap();
    let document = roxmltree::Document::parse(&svg).unwrap();
    let marked: Vec<Vec<usize>> = document
        .descendants()
        .filter(|n| n.has_tag_name("path"))
        .map(|n| {
            n.attribute("data-splineskin-inserted")
                .map(|list| {
                    list.split(' ')
                        .map(|e| {
                            let (s, k) = e.split_once(':').unwrap();
                            assert_eq!(s, "0", "{e}");
                            k.parse().unwrap()
                        })
                        .collect()
                })
                .unwrap_or_default()
        })
        .collect();
    let listed: Vec<Vec<usize>> = (0..a.len())
        .map(|p| {
            refined["paths"][p]["inserted"]
                .as_array()
                .unwrap()
                .iter()
                .map(|k| k.as_u64().unwrap() as usize)
                .collect()
        })
        .collect();
    assert_eq!(marked, listed);
    // Without --tolerance there is nothing to mark.
    ok(&run(&dir, &["deform", &scene, "-o", "plain.svg"]));
    let plain_svg = std::fs::read_to_string(dir.join("plain.svg")).unwrap();
    assert!(!plain_svg.contains("data-splineskin-inserted"));
}

#[test]
fn compare_tolerance_adds_the_adaptive_methods() {
    let dir = TestDir::new("splineskin-adaptive-cli-compare-");
    let out = ok(&run(
        &dir,
        &[
            "compare",
            &scene(),
            "--tolerance",
            "0.001",
            "--json",
            "-o",
            "c.png",
        ],
    ));
    let rows: Vec<serde_json::Value> = json_lines(&out);
    let row = |m: &str| {
        rows.iter()
            .find(|r| r["method"] == m)
            .unwrap_or_else(|| panic!("{m}: {out}"))
    };
    let (ours, same) = (row("ours-adaptive"), row("schneider-adaptive-count"));
    assert!(ours["closest_max"].as_f64().unwrap() <= 1e-3, "{ours}");
    assert!(
        ours["closest_max"].as_f64() < same["closest_max"].as_f64(),
        "{ours} {same}"
    );
    assert!(same["curves"].as_u64() <= ours["curves"].as_u64());
    assert_eq!(ours["folds"], 0);
    // Without the flag the table has neither.
    let plain = ok(&run(&dir, &["compare", &scene(), "--json", "-o", "c.png"]));
    assert!(!plain.contains("adaptive"), "{plain}");
}

#[test]
fn tolerance_must_be_a_positive_fraction() {
    let dir = TestDir::new("splineskin-adaptive-cli-bad-");
    for bad in ["0", "-1", "nan"] {
        let flag = format!("--tolerance={bad}");
        let stderr = failed(&run(&dir, &["deform", &scene(), &flag, "-o", "out.json"]));
        assert!(stderr.contains("tolerance"), "{bad}: {stderr}");
        assert!(!dir.join("out.json").exists(), "{bad}: nothing is written");
    }
}

#[test]
fn animate_tolerance_refines_for_every_frame() {
    let dir = TestDir::new("splineskin-adaptive-cli-animate-");
    let plain = common::cli::ok_stderr(&dir, &["animate", &scene(), "-o", "plain.svg"]);
    let refined = common::cli::ok_stderr(
        &dir,
        &[
            "animate",
            &scene(),
            "--tolerance",
            "0.001",
            "-o",
            "refined.svg",
        ],
    );
    assert!(plain.contains(": 58 curves in 16 paths"), "{plain}");
    assert!(refined.contains("anchors inserted"), "{refined}");
    // The summary counts the refined drawing's curves.
    let curves = |s: &str| -> usize {
        let head = s.split(" curves in ").next().unwrap();
        head.rsplit(' ').next().unwrap().parse().unwrap()
    };
    let line = refined.lines().find(|l| l.contains(" curves in ")).unwrap();
    assert!(curves(line) > 58, "{refined}");
    // Each path's animated `d` has as many curves as the refined drawing: more `C` than before.
    let c_count = |name: &str| {
        std::fs::read_to_string(dir.join(name))
            .unwrap()
            .matches('C')
            .count()
    };
    assert!(c_count("refined.svg") > c_count("plain.svg"));
}

#[test]
fn deform_tolerance_with_flexible_junctions() {
    let dir = TestDir::new("splineskin-adaptive-cli-flexible-");
    let stderr = common::cli::ok_stderr(
        &dir,
        &[
            "deform",
            &scene(),
            "--tolerance",
            "0.001",
            "--flexible",
            "-o",
            "flexible.json",
        ],
    );
    assert!(
        stderr.contains("flexible:") && stderr.contains("anchors inserted"),
        "{stderr}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("flexible.json")).unwrap()).unwrap();
    let inserted: usize = json["paths"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["inserted"].as_array().unwrap().len())
        .sum();
    assert!(inserted > 0);
    // Every point is finite (the flexible solve ran on the refined drawing).
    for p in paths(&json).iter().flatten() {
        assert!(p[0].is_finite() && p[1].is_finite());
    }
}
