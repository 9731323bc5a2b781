//! `splineskin deform` on scenes whose engine is a naive baseline (`fourcontrols`,
//! `twoendpoints`, `jacobian`): every such case of the paper authors' solver outputs
//! (../shared/data/vectorskinning/authors-solver-outputs), deformed through the binary in
//! compatibility mode to JSON, agrees with their output to 1e-6 of the bounding-box diagonal
//! (the library measures 3.9e-16: tests/naive_baselines.rs). Skipped, with a message, without
//! ../shared/data.

mod common;

use std::path::Path;

use common::cli::{ok, splineskin, stderr};
use common::test_dir::TestDir;
use serde::Deserialize;

/// Agreement required, as a fraction of the diagonal.
const TOLERANCE: f64 = 1e-6;

#[derive(Deserialize)]
struct InputPath {
    cubic_bezier_chain: Vec<[f64; 2]>,
}

#[derive(Deserialize)]
struct Case {
    case: String,
    source_json: String,
    engine_type: String,
    input_paths: Vec<InputPath>,
    deformed_paths: Vec<Vec<[f64; 2]>>,
}

#[derive(Deserialize)]
struct Output {
    paths: Vec<OutputPath>,
}

#[derive(Deserialize)]
struct OutputPath {
    points: Vec<[f64; 2]>,
}

fn naive_cases(root: &Path) -> Vec<Case> {
    common::external_data::read_authors_solver_outputs::<Case>(root)
        .into_iter()
        .filter(|c| ["fourcontrols", "twoendpoints", "jacobian"].contains(&c.engine_type.as_str()))
        .collect()
}

#[test]
fn deform_naive_engines_reproduce_the_authors_solver() {
    let Some(root) = common::external_data::shared_data() else {
        return;
    };
    let cases = naive_cases(&root);
    let dir = TestDir::new("splineskin-deform-naive-");
    let engines: std::collections::BTreeSet<&str> =
        cases.iter().map(|c| c.engine_type.as_str()).collect();
    assert_eq!(
        engines.len(),
        3,
        "every naive engine has cases: {engines:?}"
    );
    for case in &cases {
        let source = case
            .source_json
            .strip_prefix("tests-and-results/")
            .expect("source under tests-and-results/");
        let scene = root.join("vectorskinning").join(source);
        let out = dir.join(format!("{}.json", case.case));
        let args = [&scene, &out].map(|p| p.to_str().unwrap());
        let run = splineskin(&[
            "deform",
            args[0],
            "--compat",
            "vectorskinning",
            "-o",
            args[1],
        ]);
        assert!(run.status.success(), "{}: {}", case.case, stderr(&run));
        let text = std::fs::read_to_string(&out).expect("output");
        let ours: Output = serde_json::from_str(&text).expect("output JSON");
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in case.input_paths.iter().flat_map(|p| &p.cubic_bezier_chain) {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let diagonal = (hi[0] - lo[0]).hypot(hi[1] - lo[1]);
        assert_eq!(ours.paths.len(), case.deformed_paths.len(), "{}", case.case);
        let mut worst: f64 = 0.0;
        for (a, b) in ours.paths.iter().zip(&case.deformed_paths) {
            assert_eq!(a.points.len(), b.len(), "{}", case.case);
            for (p, q) in a.points.iter().zip(b) {
                worst = worst.max((p[0] - q[0]).hypot(p[1] - q[1]));
            }
        }
        let relative = worst / diagonal;
        eprintln!(
            "{} ({}): {relative:.2e} of the diagonal",
            case.case, case.engine_type
        );
        assert!(relative <= TOLERANCE, "{}: {relative:e}", case.case);
    }
}

/// `animate` applies a naive engine too (through the same `Deformer` as `deform`; it used to
/// refuse them): the last frame of a `fourcontrols` animation is that baseline's deformation
/// of the last keyframe (every control point skinned), computed here by the library, and it
/// differs from the spline fit's.
#[test]
fn animate_naive_engine() {
    use kurbo::{Affine, Point};
    use splineskin::scene::{Compat, Deformer, Scene};
    let dir = TestDir::new("splineskin-animate-naive-");
    let text = r#"{"splineskin_scene": 1, "engine": "fourcontrols",
            "svg_text": "<svg xmlns='http://www.w3.org/2000/svg'><path d='M0 0 C10 10 20 10 30 0'/></svg>",
            "handles": [{"position": [0, 0]}, {"position": [30, 0]}],
            "animation": {"fps": 4, "keyframes": [
                {"time": 0, "pose": [{}, {}]},
                {"time": 1, "pose": [{}, {"rotate": 40}]}]}}"#;
    let scene_path = dir.join("scene.json");
    std::fs::write(&scene_path, text).expect("scene");
    let frames = dir.join("frames");
    let args = [&scene_path, &frames].map(|p| p.to_str().unwrap());
    ok(&splineskin(&["animate", args[0], "-o", args[1]]));
    // 1 s at 4 fps: frames 0..=4; the last is the last keyframe.
    let last = std::fs::read_to_string(frames.join("frame-0004.svg")).expect("last frame");
    // The path's d attribute (quoted as in the input, ' or ").
    let at = last.find(" d=").expect("a path") + 3;
    let quote = last[at..].chars().next().expect("quote");
    let d = last[at + 1..].split(quote).next().expect("d");
    let numbers: Vec<f64> = d
        .split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-' || c == 'e'))
        .filter_map(|t| t.parse().ok())
        .collect();
    assert_eq!(numbers.len(), 8, "{last}");
    let scene = Scene::from_json(text, "scene.json", None).expect("scene");
    let setup = scene.setup(Compat::None).expect("setup");
    let pose = [
        Affine::IDENTITY,
        Affine::rotate_about(40f64.to_radians(), (30.0, 0.0)),
    ];
    let mut naive = vec![Point::ZERO; 4];
    Deformer::new(&scene, &setup, Compat::None, false)
        .expect("deformer")
        .deform(&setup, &pose, &mut naive)
        .expect("naive");
    for (k, p) in naive.iter().enumerate() {
        assert!(
            (numbers[2 * k] - p.x).abs() < 1e-6 && (numbers[2 * k + 1] - p.y).abs() < 1e-6,
            "point {k}: {last}"
        );
    }
    let mut ours_scene = scene.clone();
    ours_scene.engine = splineskin::scene::Engine::Ours;
    let mut ours = vec![Point::ZERO; 4];
    Deformer::new(&ours_scene, &setup, Compat::None, false)
        .expect("rig")
        .deform(&setup, &pose, &mut ours)
        .expect("ours");
    let gap = naive
        .iter()
        .zip(&ours)
        .map(|(a, b)| (*a - *b).hypot())
        .fold(0.0, f64::max);
    assert!(gap > 1e-3, "the baseline differs from the fit here: {gap}");
}
