//! `splineskin bench --json` through the binary: one JSON object per scene with the counts of
//! the scene (checked against the library's own reading of it) and finite, positive medians;
//! mesh families also report the size of their domain (checked against `Scene::setup`), and
//! drawings with G¹ junctions the flexible solve's medians.

mod common;

use std::path::{Path, PathBuf};

use common::cli::{ok, splineskin, words};
use common::test_dir::TestDir;
use serde::Deserialize;
use splineskin::scene::{Compat, Scene};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Row {
    scene: String,
    curves: usize,
    paths: usize,
    handles: usize,
    constraints: usize,
    domain_vertices: Option<usize>,
    setup_s: f64,
    weights_s: f64,
    precompute_s: f64,
    update_s: f64,
    folds_s: f64,
    flexible_s: Option<f64>,
    flexible_warm_s: Option<f64>,
    update_bytes: usize,
    update_bytes_per_s: f64,
    read_bytes_per_s: f64,
    bandwidth_ratio: f64,
    update_threads: usize,
    update_f32_s: f64,
    f32_error: f64,
}

/// A two-curve drawing with three point handles and the weight family `family`; the mesh
/// families get a coarse domain so the test stays quick; written as `scene-FAMILY.json` in `dir`.
fn scene_file(dir: &Path, family: &str) -> PathBuf {
    let domain = if family == "shepard" {
        ""
    } else {
        r#", "domain": {"max_area_fraction": 0.01, "samples_per_diagonal": 40}"#
    };
    let text = format!(
        r#"{{"splineskin_scene": 1,
            "svg_text": "<svg xmlns='http://www.w3.org/2000/svg'><path d='M0 0 C30 40 70 40 100 0 C160 -80 170 -40 200 0'/></svg>",
            "handles": [{{"position": [0, 0]}}, {{"position": [100, 10]}}, {{"position": [200, 0]}}],
            "weights": {{"family": "{family}"}}{domain},
            "pose": [{{"rotate": 10}}, {{}}, {{"translate": [5, 5]}}]}}"#
    );
    let path = dir.join(format!("scene-{family}.json"));
    std::fs::write(&path, text).expect("write the scene");
    path
}

fn bench_json(scene: &Path) -> Row {
    let mut args = words("bench --json --updates 200");
    args.push(scene.to_str().unwrap());
    let stdout = ok(&splineskin(&args));
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(lines.len(), 1, "one line per scene: {stdout}");
    serde_json::from_str(lines[0]).expect("one JSON object with the documented keys")
}

#[test]
fn bench_json_reports_counts_and_medians() {
    let dir = TestDir::new("splineskin-bench-cli-");
    for family in ["shepard", "harmonic", "bbw"] {
        let path = scene_file(&dir, family);
        let row = bench_json(&path);
        let scene = Scene::load(&path).expect("scene");
        let setup = scene.setup(Compat::None).expect("setup");
        assert_eq!(row.scene, path.display().to_string());
        assert_eq!(row.curves, setup.drawing.n_curves(), "{family}");
        assert_eq!(row.paths, setup.drawing.paths.len(), "{family}");
        assert_eq!(row.handles, 3, "{family}");
        assert!(row.constraints > 0, "{family}: the S-curve has a G1 joint");
        assert_eq!(
            row.domain_vertices,
            setup.domain.as_ref().map(|d| d.mesh.n_vertices()),
            "{family}"
        );
        assert_eq!(row.domain_vertices.is_some(), family != "shepard");
        // The S-curve's middle joint is G¹ (outgoing tangent twice the incoming): the flexible
        // solve is timed, cold and warm.
        let flexible = row
            .flexible_s
            .expect("flexible_s for a drawing with a G1 joint");
        let warm = row.flexible_warm_s.expect("flexible_warm_s");
        for (name, t) in [
            ("flexible_s", flexible),
            ("flexible_warm_s", warm),
            ("setup_s", row.setup_s),
            ("weights_s", row.weights_s),
            ("precompute_s", row.precompute_s),
            ("update_s", row.update_s),
            ("folds_s", row.folds_s),
            ("update_bytes_per_s", row.update_bytes_per_s),
            ("read_bytes_per_s", row.read_bytes_per_s),
        ] {
            assert!(t.is_finite() && t > 0.0, "{family}: {name} = {t}");
        }
        // The update reads its operator once: 2 coordinates × 6 coefficients × 3 handles per
        // chain point, in f64; the rates are that over the medians.
        let n_points = setup.drawing.n_points();
        assert_eq!(row.update_bytes, n_points * 2 * 6 * 3 * 8, "{family}");
        let rate = row.update_bytes as f64 / row.update_s;
        assert!(
            (row.update_bytes_per_s - rate).abs() <= 1e-12 * rate,
            "{family}"
        );
        // A small drawing: one thread; rounding the entries to f32 moves the points by a few
        // units in the eighth digit of the coordinates (under 1e-6 of the diagonal here).
        assert_eq!(row.update_threads, 1, "{family}");
        assert!(
            row.update_f32_s.is_finite() && row.update_f32_s > 0.0,
            "{family}"
        );
        assert!(
            row.f32_error > 0.0 && row.f32_error < 1e-6,
            "{family}: {}",
            row.f32_error
        );
        let ratio = row.update_bytes_per_s / row.read_bytes_per_s;
        assert!(
            (row.bandwidth_ratio - ratio).abs() <= 1e-12 * ratio,
            "{family}"
        );
    }
}
