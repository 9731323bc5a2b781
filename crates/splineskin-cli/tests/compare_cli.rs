//! `splineskin compare` through the binary:
//!
//! * on a small scene written here: the picture's size is the library's layout for the same
//!   comparison, `--json` prints one object per method with the documented keys, and its
//!   figures are the library's metrics for the same pose, bit for bit;
//! * on the bundled drawing's poses, ours has the smallest energy among the point baselines;
//! * at the identity pose every method but the refit is exact, so the dashes of the target
//!   near a handle are in the colour of zero error (and at a bent pose, in the same place,
//!   the worst baseline's are not);
//! * a missing scene, a pose the scene does not have and an output that is not `.png` fail
//!   with a message naming the file, a non-zero status, and no file written.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::cli::ok;
use common::test_dir::TestDir;

use kurbo::Affine;
use serde::Deserialize;
use splineskin::compare::{
    compare_methods, posed_markers, CompareInputs, CompareOptions, Comparison, Method,
};
use splineskin::figure::colour_map::error_colour;
use splineskin::figure::comparison::{render_comparison, ComparePicture, PictureOptions};
use splineskin::metrics::MetricsOptions;
use splineskin::scene::{Compat, Scene};
use splineskin::weight_map::RgbaImage;

/// An S-shaped open path and a closed blob; three handles along the S. The pose bends the
/// right end up and turns it.
const SCENE: &str = r#"{"splineskin_scene": 1,
  "svg_text": "<svg xmlns='http://www.w3.org/2000/svg'><path d='M0 0 C30 40 70 40 100 0 S170 -40 200 0'/><path d='M60 60 C80 50 120 50 140 60 C150 80 110 100 90 90 C70 85 50 75 60 60 Z'/></svg>",
  "handles": [{"position": [0, 0]}, {"position": [100, 0]}, {"position": [200, 0]}],
  "weights": {"family": "shepard"},
  "poses": [
    {"name": "identity", "transforms": [{}, {}, {}]},
    {"name": "bend", "transforms": [{}, {"rotate": 10}, {"rotate": 35, "translate": [0, -30]}]}
  ]}"#;

/// The keys every `--json` line has, as documented in the CLI's `compare.rs`.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct JsonRow {
    scene: String,
    pose: usize,
    method: String,
    curves: usize,
    energy: f64,
    max: f64,
    rms: f64,
    distance: String,
    closest_max: f64,
    closest_rms: f64,
    diagonal: f64,
    refit_tolerance: Option<f64>,
    folds: Option<usize>,
}

/// A fresh folder for one test.
fn folder(name: &str) -> TestDir {
    TestDir::new(&format!("splineskin-compare-cli-{name}-"))
}

/// A [`folder`] holding [`SCENE`] as `scene.json`, and that file's path.
fn folder_with_scene(name: &str) -> (TestDir, PathBuf) {
    let dir = folder(name);
    let scene = dir.join("scene.json");
    std::fs::write(&scene, SCENE).unwrap();
    (dir, scene)
}

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_splineskin"))
        .arg("compare")
        .args(args)
        .output()
        .expect("run splineskin")
}

/// The library's picture of `c` with the handles of `scene` moved by `pose`, panels `width`
/// pixels wide, and the PNG the command wrote to `png`.
fn picture_and_png(
    scene: &Scene,
    c: &Comparison,
    pose: &[Affine],
    width: u32,
    png: &Path,
) -> (ComparePicture, RgbaImage) {
    let markers = posed_markers(&scene.handle_set(), pose);
    let options = PictureOptions::default().with_panel_width(width);
    let picture = render_comparison(c, &markers, &options).unwrap();
    let image = RgbaImage::decode_png(&std::fs::read(png).unwrap()).unwrap();
    (picture, image)
}

fn rows(out: &Output) -> Vec<JsonRow> {
    ok(out);
    String::from_utf8(out.stdout.clone())
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{l}: {e}")))
        .collect()
}

/// The library's comparison of `scene_path` at `pose`, set up as the CLI documents it.
fn library(scene_path: &Path, pose: usize) -> (Scene, Comparison, Vec<Affine>) {
    let scene = Scene::load(scene_path).unwrap();
    let setup = scene.setup(Compat::None).unwrap();
    let pose = scene.pose(pose).unwrap().transforms;
    let shepard = scene.point_shepard(Compat::None).unwrap();
    let inputs = CompareInputs {
        drawing: &setup.drawing,
        weights: setup.weights.as_ref(),
        gradient: &shepard,
        fit: setup.options,
        flexible: scene.flexible_options(Compat::None),
        pose: &pose,
    };
    let options =
        CompareOptions::default().with_metrics(MetricsOptions::default().with_fit(setup.options));
    let c = compare_methods(&inputs, &options).unwrap();
    (scene, c, pose)
}

#[test]
fn compare_json_and_picture_match_the_library() {
    let (dir, scene) = folder_with_scene("small");
    let png = dir.join("compare.png");
    let args = [
        scene.to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
        "--pose",
        "1",
        "--json",
        "--width",
        "300",
    ];
    let rows = rows(&run(&args));
    let (scene_value, c, pose) = library(&scene, 1);
    let names: Vec<&str> = rows.iter().map(|r| r.method.as_str()).collect();
    assert_eq!(
        names,
        [
            "ours",
            "fourcontrols",
            "twoendpoints",
            "jacobian",
            "schneider",
            "schneider-same-count"
        ]
    );
    for (row, m) in rows.iter().zip(&c.methods) {
        let o = m.metrics.overall;
        assert_eq!(
            (row.energy, row.max, row.rms),
            (o.energy, o.max, o.rms),
            "{}",
            row.method
        );
        assert_eq!(row.curves, m.result.n_curves());
        assert_eq!(
            (row.closest_max, row.closest_rms),
            (m.closest.overall.max, m.closest.overall.rms)
        );
        // The nearest point is never further than the point at the same parameter (up to
        // the nearest-point search's accuracy, 1e-6 of the diagonal).
        assert!(row.closest_max <= row.max + 1e-6, "{}", row.method);
        assert!(row.closest_rms <= row.rms + 1e-6, "{}", row.method);
        assert_eq!(row.pose, 1);
        assert_eq!(row.diagonal, c.diagonal);
        assert_eq!(row.scene, scene.display().to_string());
        let closest = !m.method.keeps_structure();
        assert_eq!(
            row.distance,
            if closest {
                "closest_point"
            } else {
                "parametric"
            }
        );
        assert_eq!(
            row.refit_tolerance,
            (m.method == Method::Schneider).then_some(c.refit_tolerance)
        );
        assert_eq!(row.folds, m.folds, "{}", row.method);
        assert_eq!(row.folds.is_some(), m.method.keeps_structure());
    }
    // The input has 2 + 3 curves (the blob closes on its start: Z adds none); the refit at
    // least as many, the refit at the input's count no more, path by path.
    assert_eq!(rows[0].curves, 5);
    assert!(rows[4].curves >= rows[0].curves);
    let same = c.get(Method::SchneiderSameCount).unwrap();
    let input = c.get(Method::Ours).unwrap();
    for (a, b) in same.result.paths.iter().zip(&input.result.paths) {
        assert!(a.n_curves() <= b.n_curves());
    }
    let (picture, image) = picture_and_png(&scene_value, &c, &pose, 300, &png);
    assert_eq!(
        (image.width, image.height),
        (picture.grid.width, picture.grid.height)
    );
    // Six panels of 300 px in the grid closest to square.
    assert_eq!(picture.grid.corners.len(), 6);
    assert!(picture.grid.width >= 2 * 300);
    // No temporary file left beside the output.
    let names: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert_eq!(names.len(), 2, "{names:?}");
}

#[test]
fn compare_ours_has_the_least_energy_on_the_bundled_drawing() {
    let dir = folder("demo");
    let scene = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../splineskin/assets/demo-scene.json"
    );
    for pose in ["0", "1", "2"] {
        let png = dir.join(format!("demo-{pose}.png"));
        let rows = rows(&run(&[
            scene,
            "-o",
            png.to_str().unwrap(),
            "--pose",
            pose,
            "--json",
        ]));
        let row = |name: &str| rows.iter().find(|r| r.method == name).unwrap();
        for baseline in ["fourcontrols", "twoendpoints", "jacobian"] {
            for (what, f) in [
                ("energy", (|r: &JsonRow| r.energy) as fn(&JsonRow) -> f64),
                ("max", |r| r.max),
                ("rms", |r| r.rms),
            ] {
                assert!(
                    f(row("ours")) < f(row(baseline)),
                    "pose {pose}: {what}: ours {} vs {baseline} {}",
                    f(row("ours")),
                    f(row(baseline))
                );
            }
        }
        // With at most as many curves as the input, the refit stays further from the target than
        // the fit (by the only measure they share, the nearest point).
        let (ours, refit) = (row("ours"), row("schneider-same-count"));
        assert!(refit.curves <= ours.curves, "pose {pose}");
        assert!(
            ours.closest_max < refit.closest_max && ours.closest_rms < refit.closest_rms,
            "pose {pose}: ours {} {} vs refit {} {}",
            ours.closest_max,
            ours.closest_rms,
            refit.closest_max,
            refit.closest_rms
        );
    }
}

/// The largest per-channel difference.
fn difference(a: [u8; 3], b: [u8; 3]) -> u8 {
    (0..3).map(|k| a[k].abs_diff(b[k])).max().unwrap()
}

/// The normalised error whose colour is nearest `c`, if `c` is within 3 levels of the ramp.
fn on_ramp(c: [u8; 3]) -> Option<f64> {
    (0..=200)
        .map(|k| f64::from(k) / 200.0)
        .map(|e| (difference(c, error_colour(e)), e))
        .filter(|(d, _)| *d <= 3)
        .min_by_key(|(d, _)| *d)
        .map(|(_, e)| e)
}

/// Colours of the pixels under the target samples of the S path's first curve near handle 0
/// (t ≤ 0.3), in panel `panel`.
fn target_pixels(
    c: &Comparison,
    picture_grid: &splineskin::figure::PanelGrid,
    image: &RgbaImage,
    panel: usize,
) -> Vec<[u8; 3]> {
    let s = c.samples_per_curve;
    (0..=(3 * (s - 1)) / 10)
        .map(|k| {
            let p = picture_grid.to_pixel(panel, c.target[k]).unwrap();
            image.colour_at(p).unwrap()
        })
        .collect()
}

#[test]
fn compare_identity_pose_draws_the_target_in_the_zero_colour() {
    let (dir, scene) = folder_with_scene("identity");
    for (pose, exact) in [(0, true), (1, false)] {
        let png = dir.join(format!("pose-{pose}.png"));
        let pose_arg = pose.to_string();
        let out = run(&[
            scene.to_str().unwrap(),
            "-o",
            png.to_str().unwrap(),
            "--pose",
            &pose_arg,
            "--width",
            "400",
        ]);
        ok(&out);
        let (scene_value, c, transforms) = library(&scene, pose);
        let (picture, image) = picture_and_png(&scene_value, &c, &transforms, 400, &png);
        // Panels of the methods that keep the input's curves: ours, fourcontrols,
        // twoendpoints, jacobian.
        for panel in 0..4 {
            let colours = target_pixels(&c, &picture.grid, &image, panel);
            let on: Vec<f64> = colours.iter().filter_map(|&c| on_ramp(c)).collect();
            assert!(on.len() >= 5, "pose {pose} panel {panel}: {colours:?}");
            let worst = on.iter().fold(0.0f64, |a, &e| a.max(e));
            if exact {
                // Every method is exact: every dash is the colour of 0.
                assert!(worst <= 0.01, "panel {panel}: {on:?}");
            } else if panel == 2 {
                // twoendpoints, the worst baseline here, is visibly off near the bent end's
                // neighbour already.
                assert!(worst > 0.05, "panel {panel}: {on:?}");
            }
        }
        if exact {
            for m in &c.methods[..4] {
                assert!(m.metrics.overall.max < 1e-12, "{:?}", m.method);
            }
        }
    }
}

#[test]
fn compare_errors_name_the_file_and_leave_nothing() {
    let (dir, scene) = folder_with_scene("errors");
    let png = dir.join("out.png");
    let cases: [(Vec<String>, &str); 5] = [
        (
            vec![dir.join("missing.json").display().to_string()],
            "missing.json",
        ),
        (
            vec![scene.display().to_string(), "--pose".into(), "7".into()],
            "pose '7' does not exist (poses: 0 'identity', 1 'bend')",
        ),
        (
            vec![
                scene.display().to_string(),
                "-o".into(),
                dir.join("out.svg").display().to_string(),
            ],
            "out.svg: the comparison is a picture (expected a name ending in .png)",
        ),
        (
            vec![
                scene.display().to_string(),
                "--refit-tolerance".into(),
                "1e307".into(),
            ],
            "refit tolerance 1e307 (fraction of the diagonal) is not positive and finite in drawing units",
        ),
        (
            vec![
                scene.display().to_string(),
                "--refit-tolerance=-0.5".into(),
            ],
            "refit tolerance -5e-1",
        ),
    ];
    for (args, expected) in cases {
        let mut all = args.clone();
        if !all.iter().any(|a| a == "-o") {
            all.extend(["-o".to_string(), png.display().to_string()]);
        }
        let refs: Vec<&str> = all.iter().map(String::as_str).collect();
        let out = run(&refs);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
        assert!(stderr.starts_with("error: "), "{stderr}");
        let files: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(files, ["scene.json"], "{args:?}");
    }
}
