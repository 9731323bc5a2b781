//! The naive baselines ([`splineskin::naive`]) and the metrics ([`splineskin::metrics`]) on
//! real drawings:
//!
//! * the authors' `fourcontrols`, `twoendpoints` and `jacobian` cases of
//!   `../shared/data/vectorskinning/authors-solver-outputs` (their solver's output with those
//!   engines) agree in compatibility mode (`Compat::VectorSkinning`: their drawing reader and
//!   Shepard snap) point by point to 1e-6 of the bounding-box diagonal;
//! * on the bundled drawing, the identity pose reproduces the input and one affine map on every
//!   handle gives that map, for the three point baselines; the metrics of that exact target are
//!   zero (for the fit too);
//! * Schneider's refit keeps every deformed sample within its tolerance;
//! * the spline fit's energy is below every point baseline's on the bundled drawing's poses and
//!   the authors' clam and turtles Shepard scenes (the table is printed).
//!
//! Tests that read `../shared/data` print a message and pass when it is missing.

#[path = "common/external_data.rs"]
mod external_data;

use std::path::Path as FsPath;

use kurbo::{Affine, ParamCurveNearest, Point};
use serde::Deserialize;
use splineskin::drawing::Drawing;
use splineskin::metrics::{chain_metrics, refit_metrics, ErrorFigures, MetricsOptions};
use splineskin::naive::{
    schneider_refit, schneider_refit_same_count, skin_control_points, skin_on_curve_points,
    skin_point, skin_with_jacobian, FiniteDifferences, Refit, RefitOptions,
};
use splineskin::scene::{Compat, Engine, Scene, AUTHORS_SHEPARD_SNAP};
use splineskin::spline_fit::SplineRig;
use splineskin::weights::{Shepard, ShepardOptions, WeightField};

/// Agreement with the authors' naive engines in compatibility mode, as a fraction of the
/// bounding-box diagonal (their output is `float64` from the same formulas).
const COMPAT_TOLERANCE: f64 = 1e-6;

/// Identity and common-affine exactness, as a fraction of the diagonal: rounding of
/// `Σ_i w_i T_i` (weights sum to one to ~1e-16) on coordinates of order 1e3.
const EXACT: f64 = 1e-12;

/// The fields of an `authors-solver-outputs` case used here.
#[derive(Deserialize)]
struct AuthorsCase {
    case: String,
    source_json: String,
    engine_type: String,
    weight_function: String,
    handle_positions: Vec<[f64; 2]>,
    handle_transforms_2x3: Vec<[[f64; 3]; 2]>,
    deformed_paths: Vec<Vec<[f64; 2]>>,
}

impl AuthorsCase {
    fn pose(&self) -> Vec<Affine> {
        self.handle_transforms_2x3
            .iter()
            .map(|m| Affine::new([m[0][0], m[1][0], m[0][1], m[1][1], m[0][2], m[1][2]]))
            .collect()
    }
}

fn cases(root: &FsPath) -> Vec<AuthorsCase> {
    external_data::read_authors_solver_outputs(root)
}

fn scene_of(root: &FsPath, source_json: &str) -> Scene {
    let relative = source_json
        .strip_prefix("tests-and-results/")
        .expect("source_json under tests-and-results/");
    let file = root.join("vectorskinning").join(relative);
    Scene::load(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()))
}

/// The three point baselines, by the authors' engine names.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Method {
    FourControls,
    TwoEndpoints,
    Jacobian,
}

const METHODS: [Method; 3] = [Method::FourControls, Method::TwoEndpoints, Method::Jacobian];

impl Method {
    fn name(self) -> &'static str {
        match self {
            Method::FourControls => "fourcontrols",
            Method::TwoEndpoints => "twoendpoints",
            Method::Jacobian => "jacobian",
        }
    }

    /// Runs the baseline; the Jacobian uses `shepard`'s analytic gradient when given, else
    /// central differences of `field`.
    fn run(
        self,
        drawing: &Drawing,
        field: &dyn WeightField,
        shepard: Option<&Shepard>,
        pose: &[Affine],
    ) -> Vec<Point> {
        let mut out = vec![Point::ZERO; drawing.n_points()];
        match self {
            Method::FourControls => skin_control_points(drawing, field, pose, &mut out),
            Method::TwoEndpoints => skin_on_curve_points(drawing, field, pose, &mut out),
            Method::Jacobian => match shepard {
                Some(s) => skin_with_jacobian(drawing, s, pose, &mut out),
                None => {
                    let fd = FiniteDifferences::for_drawing(field, drawing);
                    skin_with_jacobian(drawing, &fd, pose, &mut out)
                }
            },
        }
        .expect("sizes");
        out
    }
}

/// The authors' Shepard weights as compatibility mode builds them (their `1e-8` snap).
fn authors_shepard(scene: &Scene) -> Shepard {
    Shepard::new(
        &scene.handles,
        ShepardOptions::default().with_snap_distance_squared(AUTHORS_SHEPARD_SNAP),
    )
}

#[test]
fn authors_naive_engines_agree_in_compatibility_mode() {
    let Some(root) = external_data::shared_data() else {
        return;
    };
    let mut checked = Vec::new();
    for case in cases(&root) {
        let method = match case.engine_type.as_str() {
            "fourcontrols" => Method::FourControls,
            "twoendpoints" => Method::TwoEndpoints,
            "jacobian" => Method::Jacobian,
            _ => continue,
        };
        assert_eq!(case.weight_function, "shepard", "{}", case.case);
        let mut scene = scene_of(&root, &case.source_json);
        // The scene layer runs only the paper's engine for now; the drawing and weights of
        // compatibility mode do not depend on the engine.
        scene.engine = Engine::Ours;
        let pose = scene.pose(0).expect("pose 0").transforms;
        assert_eq!(pose, case.pose(), "{}: pose", case.case);
        let handles: Vec<Point> = case
            .handle_positions
            .iter()
            .map(|p| Point::new(p[0], p[1]))
            .collect();
        assert_eq!(scene.handles, handles, "{}: handles", case.case);
        let setup = scene.setup(Compat::VectorSkinning).expect("setup");
        let drawing = &setup.drawing;
        // The analytic gradient needs the concrete Shepard field: the same as the setup's.
        let shepard = authors_shepard(&scene);
        let mut a = vec![0.0; shepard.positions().len()];
        let mut b = a.clone();
        for p in drawing.flat_points() {
            shepard.eval(p, &mut a);
            setup.weights.eval(p, &mut b);
            assert_eq!(a, b, "{}: weights at {p:?}", case.case);
        }
        let diag = drawing.diagonal();
        assert_eq!(
            drawing.paths.len(),
            case.deformed_paths.len(),
            "{}",
            case.case
        );
        let theirs: Vec<Point> = case
            .deformed_paths
            .iter()
            .flatten()
            .map(|q| Point::new(q[0], q[1]))
            .collect();
        for (path, chain) in drawing.paths.iter().zip(&case.deformed_paths) {
            assert_eq!(path.points.len(), chain.len(), "{}", case.case);
        }
        let distance = |out: &[Point]| {
            out.iter()
                .zip(&theirs)
                .map(|(p, q)| (*p - *q).hypot() / diag)
                .fold(0.0, f64::max)
        };
        let worst = distance(&method.run(drawing, setup.weights.as_ref(), Some(&shepard), &pose));
        // The other two baselines are far from this case: the comparison tells them apart.
        let others = METHODS
            .iter()
            .filter(|m| **m != method)
            .map(|m| distance(&m.run(drawing, setup.weights.as_ref(), Some(&shepard), &pose)))
            .fold(f64::INFINITY, f64::min);
        assert!(others > 1e3 * COMPAT_TOLERANCE, "{}: {others:e}", case.case);
        eprintln!(
            "{} ({}): max {:.2e} of the diagonal over {} points (the other baselines: {:.2e})",
            case.case,
            method.name(),
            worst,
            drawing.n_points(),
            others
        );
        assert!(worst <= COMPAT_TOLERANCE, "{}: {worst:e}", case.case);
        checked.push(case.case);
    }
    assert_eq!(checked.len(), 7, "expected the 7 naive cases: {checked:?}");
}

/// The bundled scene's drawing and weights (our default mode).
fn demo() -> (Scene, Drawing, std::sync::Arc<dyn WeightField>) {
    let scene = splineskin::examples::demo_scene();
    let setup = scene.setup(Compat::None).expect("demo setup");
    (scene, setup.drawing, setup.weights)
}

#[test]
fn identity_and_common_affine_map_are_exact_on_the_demo() {
    let (scene, drawing, weights) = demo();
    let shepard = Shepard::new(&scene.handles, ShepardOptions::default());
    let input = drawing.flat_points();
    let diag = drawing.diagonal();
    let h = scene.handles.len();
    let t = Affine::new([1.1, 0.25, -0.3, 0.85, 40.0, -17.0]);
    let rig = SplineRig::precompute(&drawing, weights.as_ref(), &Default::default()).unwrap();
    for (map, label) in [(Affine::IDENTITY, "identity"), (t, "common affine")] {
        let pose = vec![map; h];
        for method in METHODS {
            for analytic in [Some(&shepard), None] {
                if analytic.is_none() && method != Method::Jacobian {
                    continue;
                }
                let out = method.run(&drawing, weights.as_ref(), analytic, &pose);
                let worst = input
                    .iter()
                    .zip(&out)
                    .map(|(p, q)| (map * *p - *q).hypot() / diag)
                    .fold(0.0, f64::max);
                assert!(worst <= EXACT, "{label}, {}: {worst:e}", method.name());
                // The exact target is a cubic: every figure vanishes.
                let m = chain_metrics(&drawing, weights.as_ref(), &pose, &out, &Default::default())
                    .unwrap();
                assert!(m.overall.max <= EXACT && m.overall.rms <= EXACT, "{m:?}");
                assert!(m.overall.energy <= (EXACT * diag).powi(2) * 1e3, "{m:?}");
            }
        }
    }
    // The fit reproduces a common map only where its junction constraints allow: a general
    // affine map breaks the fixed angles of the demo's right-angle corner (the fit then
    // differs by 0.3 % of the diagonal there), a similarity keeps them. The demo's smooth
    // junctions are G¹ within the classification tolerance, not exactly, and the constraint
    // makes them exact: 4e-8 of the diagonal.
    let similarity = Affine::rotate(0.4)
        .then_scale(1.3)
        .then_translate((40.0, -17.0).into());
    for map in [Affine::IDENTITY, similarity] {
        let pose = vec![map; h];
        let mut ours = vec![Point::ZERO; rig.n_points()];
        rig.update(&pose, &mut ours).unwrap();
        let m = chain_metrics(
            &drawing,
            weights.as_ref(),
            &pose,
            &ours,
            &Default::default(),
        )
        .unwrap();
        assert!(m.overall.max <= 1e-7, "{map:?}, ours: {:?}", m.overall);
    }
}

#[test]
fn schneider_refit_stays_within_its_tolerance() {
    let (scene, drawing, weights) = demo();
    let diag = drawing.diagonal();
    for pose in &scene.poses {
        for tolerance in [0.05, 0.5, 2.0] {
            let options = RefitOptions::default().with_tolerance(tolerance);
            let refit = schneider_refit(&drawing, weights.as_ref(), &pose.transforms, &options)
                .expect("refit");
            // Every deformed sample (the refit's input) is within the tolerance of the result.
            let mut w = vec![0.0; weights.n_handles()];
            let m = options.samples_per_curve;
            let mut worst: f64 = 0.0;
            for (path, result) in drawing.paths.iter().zip(&refit.paths) {
                assert_eq!(path.closed, result.closed);
                for j in 0..path.n_curves() {
                    let c = path.curve_points(j);
                    for k in 0..=m {
                        let x = splineskin::bezier::eval(&c, k as f64 / m as f64);
                        let s = skin_point(weights.as_ref(), &pose.transforms, x, &mut w);
                        let d = (0..result.n_curves())
                            .map(|r| result.curve(r).nearest(s, 1e-9 * diag).distance_sq)
                            .fold(f64::INFINITY, f64::min)
                            .sqrt();
                        worst = worst.max(d);
                    }
                }
            }
            eprintln!(
                "demo '{}', tolerance {tolerance}: {} curves (input {}), farthest sample {worst:.3e}",
                pose.name.as_deref().unwrap_or("?"),
                refit.n_curves(),
                drawing.n_curves()
            );
            assert!(worst <= tolerance, "{worst} > {tolerance}");
        }
    }
}

/// One row of the comparison table.
struct Row {
    method: String,
    n_curves: usize,
    figures: ErrorFigures,
}

/// Every method on `drawing` under `pose`: ours (the rig), the three point baselines and a
/// Schneider refit (closest-point figures); prints the table and returns it (ours first).
fn compare(
    label: &str,
    drawing: &Drawing,
    weights: &dyn WeightField,
    shepard: &Shepard,
    rig: &SplineRig,
    pose: &[Affine],
) -> Vec<Row> {
    let options = MetricsOptions::default();
    let mut rows = Vec::new();
    let mut ours = vec![Point::ZERO; rig.n_points()];
    rig.update(pose, &mut ours).unwrap();
    let figures = chain_metrics(drawing, weights, pose, &ours, &options).unwrap();
    rows.push(Row {
        method: "ours".into(),
        n_curves: drawing.n_curves(),
        figures: figures.overall,
    });
    for method in METHODS {
        let out = method.run(drawing, weights, Some(shepard), pose);
        let figures = chain_metrics(drawing, weights, pose, &out, &options).unwrap();
        rows.push(Row {
            method: method.name().into(),
            n_curves: drawing.n_curves(),
            figures: figures.overall,
        });
    }
    let refit_options = RefitOptions::default();
    let refit = schneider_refit(drawing, weights, pose, &refit_options).unwrap();
    let figures = refit_metrics(drawing, weights, pose, &refit, &options).unwrap();
    rows.push(Row {
        method: format!("schneider {}*", refit_options.tolerance),
        n_curves: refit.n_curves(),
        figures: figures.overall,
    });
    // Ours by closest point too, for comparison with the refit's figures.
    let closest = refit_metrics(
        drawing,
        weights,
        pose,
        &Refit::from_chains(drawing, &ours).unwrap(),
        &options,
    )
    .unwrap();
    rows.push(Row {
        method: "ours*".into(),
        n_curves: drawing.n_curves(),
        figures: closest.overall,
    });
    eprintln!("\n{label} ({} curves)", drawing.n_curves());
    eprintln!(
        "  {:<15} {:>7} {:>12} {:>10} {:>10}",
        "method", "curves", "energy", "max", "rms"
    );
    for r in &rows {
        eprintln!(
            "  {:<15} {:>7} {:>12.4e} {:>9.4}% {:>9.4}%",
            r.method,
            r.n_curves,
            r.figures.energy,
            100.0 * r.figures.max,
            100.0 * r.figures.rms
        );
    }
    rows
}

/// Ours must have the lowest energy, max and RMS among the methods of the input's structure.
fn assert_ours_best(label: &str, rows: &[Row]) {
    let ours = &rows[0].figures;
    for r in &rows[1..=3] {
        assert!(
            ours.energy <= r.figures.energy,
            "{label}: ours {} > {} {}",
            ours.energy,
            r.method,
            r.figures.energy
        );
        assert!(ours.rms <= r.figures.rms, "{label}: RMS vs {}", r.method);
        assert!(ours.max <= r.figures.max, "{label}: max vs {}", r.method);
    }
}

#[test]
fn ours_beats_the_baselines_on_the_demo() {
    let (scene, drawing, weights) = demo();
    let shepard = Shepard::new(&scene.handles, ShepardOptions::default());
    let rig = SplineRig::precompute(&drawing, weights.as_ref(), &Default::default()).unwrap();
    for pose in &scene.poses {
        let label = format!("demo '{}'", pose.name.as_deref().unwrap_or("?"));
        let rows = compare(
            &label,
            &drawing,
            weights.as_ref(),
            &shepard,
            &rig,
            &pose.transforms,
        );
        assert_ours_best(&label, &rows);
    }
}

#[test]
fn ours_beats_the_baselines_on_the_authors_clam_and_turtles() {
    let Some(root) = external_data::shared_data() else {
        return;
    };
    let scenes = [
        "tests-and-results/clam-songrun/clam-Our-shepard/clam-songrun-deformation.json",
        "tests-and-results/clam-songrun/clam-Ours2-Shepard/clam-songrun-deformation.json",
        "tests-and-results/turtle-seven-stack/comparison/shepard ours/turtles-seven-deformation.json",
    ];
    for source in scenes {
        let scene = scene_of(&root, source);
        let setup = scene.setup(Compat::None).expect("setup");
        let shepard = Shepard::new(&scene.handles, ShepardOptions::default());
        let rig = SplineRig::precompute(&setup.drawing, setup.weights.as_ref(), &setup.options)
            .expect("precompute");
        let pose = scene.pose(0).expect("pose 0").transforms;
        let label = source
            .strip_prefix("tests-and-results/")
            .unwrap_or(source)
            .trim_end_matches("-deformation.json");
        let rows = compare(
            label,
            &setup.drawing,
            setup.weights.as_ref(),
            &shepard,
            &rig,
            &pose,
        );
        assert_ours_best(label, &rows);
    }
}

#[test]
fn schneider_refit_same_count_uses_the_smallest_tolerance_within_the_budget() {
    let (scene, drawing, weights) = demo();
    let options = RefitOptions::default();
    for pose in &scene.poses {
        let (refit, tolerances) =
            schneider_refit_same_count(&drawing, weights.as_ref(), &pose.transforms, &options)
                .expect("refit");
        for (p, ((path, result), &tol)) in drawing
            .paths
            .iter()
            .zip(&refit.paths)
            .zip(&tolerances)
            .enumerate()
        {
            assert!(result.n_curves() <= path.n_curves(), "path {p}");
            assert!(tol.is_finite() && tol > 0.0, "path {p}: {tol}");
            // The path's refit at that tolerance is the result; 2 % tighter it needs more
            // curves than the input (unless the search's floor was already within budget).
            let at = |t: f64| {
                schneider_refit(
                    &drawing,
                    weights.as_ref(),
                    &pose.transforms,
                    &options.with_tolerance(t),
                )
                .unwrap()
                .paths[p]
                    .clone()
            };
            assert_eq!(&at(tol), result, "path {p}");
            let floor = 1e-8 * drawing.diagonal();
            if tol > floor {
                assert!(
                    at(0.98 * tol).n_curves() > path.n_curves(),
                    "path {p}: tolerance {tol} is not the smallest within the budget"
                );
            }
        }
    }
}
