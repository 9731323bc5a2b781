//! Running the paper authors' saved scenes and comparing deformed drawings with their solver's
//! output curve against curve (used where control points are not comparable).
#![allow(dead_code, missing_docs)]

use kurbo::{CubicBez, ParamCurve, ParamCurveNearest, Point};
use splineskin::drawing::{Drawing, Path};
use splineskin::scene::{Compat, Scene};
use splineskin::spline_fit::quadrature::SampledCurves;
use splineskin::spline_fit::{FlexibleOptions, FlexibleReport, FlexibleSolver, SplineRig};

use super::authors_outputs::AuthorsCase;

/// Samples per curve for the curve-to-curve distance.
pub const SAMPLES_PER_CURVE: usize = 24;

/// Accuracy of the nearest-point search, as a fraction of the diagonal.
pub const NEAREST_ACCURACY: f64 = 1e-9;

/// Tolerance for recognising the same on-curve point in both readings (their coordinates are
/// `float32`, ours `f64`), as a fraction of the diagonal.
pub const SAME_POINT: f64 = 1e-6;

pub fn scene_of(root: &std::path::Path, case: &AuthorsCase) -> Scene {
    let relative = case
        .source_json
        .strip_prefix("tests-and-results/")
        .expect("source_json under tests-and-results/");
    let file = root.join("vectorskinning").join(relative);
    Scene::load(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()))
}

pub fn deform(scene: &Scene, compat: Compat) -> (Drawing, Vec<Point>, Vec<usize>) {
    deform_with(scene, compat, |_| {})
}

/// [`deform`] after `edit` has changed the drawing read from the scene.
pub fn deform_with(
    scene: &Scene,
    compat: Compat,
    edit: impl FnOnce(&mut Drawing),
) -> (Drawing, Vec<Point>, Vec<usize>) {
    let mut setup = scene.setup(compat).expect("setup");
    edit(&mut setup.drawing);
    let rig = SplineRig::precompute(&setup.drawing, setup.weights.as_ref(), &setup.options)
        .expect("precompute");
    let mut out = vec![Point::ZERO; rig.n_points()];
    rig.update(&scene.pose(0).expect("pose 0").transforms, &mut out)
        .expect("update");
    (setup.drawing, out, rig.rank_deficient_paths().to_vec())
}

/// [`deform`] with flexible G¹ and angle joints: the scene's flexible options for `compat`
/// (ours, or the authors' rule in compatibility mode), or `options` if given. Also returns the
/// solve's report.
pub fn deform_flexible(
    scene: &Scene,
    compat: Compat,
    options: Option<FlexibleOptions>,
) -> (Drawing, Vec<Point>, Vec<usize>, FlexibleReport) {
    let setup = scene.setup(compat).expect("setup");
    let fit = setup.options;
    let samples = SampledCurves::sample(&setup.drawing, setup.weights.as_ref(), &fit);
    let options = options
        .or_else(|| scene.flexible_options(compat))
        .expect("a flexible scene");
    let solver = FlexibleSolver::new(&setup.drawing, &samples, &fit.with_parallel(true), options)
        .expect("precompute");
    let mut out = vec![Point::ZERO; solver.rig().n_points()];
    let report = solver
        .solve(&scene.pose(0).expect("pose 0").transforms, None, &mut out)
        .expect("flexible solve");
    let singular = solver.rig().rank_deficient_paths().to_vec();
    (setup.drawing, out, singular, report)
}

pub fn curve(points: &[Point], path: &Path, k: usize) -> CubicBez {
    let p = |i: usize| {
        if path.closed && i == path.points.len() - 1 {
            points[0]
        } else {
            points[i]
        }
    };
    CubicBez::new(p(3 * k), p(3 * k + 1), p(3 * k + 2), p(3 * k + 3))
}

/// Largest distance from samples of `a` to the curve `b`.
pub fn one_sided(a: CubicBez, b: CubicBez, accuracy: f64) -> f64 {
    (0..=SAMPLES_PER_CURVE)
        .map(|s| {
            let q = a.eval(s as f64 / SAMPLES_PER_CURVE as f64);
            b.nearest(q, accuracy).distance_sq.sqrt()
        })
        .fold(0.0, f64::max)
}

/// Largest curve-to-curve distance, over the authors' paths not in `excluded`, between their
/// deformed curves and ours (`ours` with `points`), relative to `diag`.
pub fn default_mode_distance(
    case: &AuthorsCase,
    theirs: &Drawing,
    ours: &Drawing,
    points: &[Point],
    excluded: &[usize],
    diag: f64,
) -> f64 {
    let matched = match_paths(theirs, ours, SAME_POINT * diag);
    let our_offsets = offsets(ours);
    let accuracy = NEAREST_ACCURACY * diag;
    let mut worst: f64 = 0.0;
    for (i, &j) in matched.iter().enumerate() {
        if excluded.contains(&i) {
            continue;
        }
        let (a, b) = (&theirs.paths[i], &ours.paths[j]);
        let deformed: Vec<Point> = case.deformed_paths[i]
            .iter()
            .map(|q| Point::new(q[0], q[1]))
            .collect();
        let mine = &points[our_offsets[j]..our_offsets[j] + b.points.len()];
        for k in 0..a.n_curves() {
            let (ca, cb) = (curve(&deformed, a, k), curve(mine, b, k));
            let d = one_sided(ca, cb, accuracy).max(one_sided(cb, ca, accuracy));
            worst = worst.max(d / diag);
        }
    }
    worst
}

/// For each of the authors' paths, the index of our path with the same on-curve points (our
/// import also reads shapes they ignore, such as `<polygon>`, so ours may have more paths).
pub fn match_paths(theirs: &Drawing, ours: &Drawing, tolerance: f64) -> Vec<usize> {
    let same = |a: &Path, b: &Path| {
        a.n_curves() == b.n_curves()
            && (0..=a.n_curves()).all(|k| (a.points[3 * k] - b.points[3 * k]).hypot() <= tolerance)
    };
    let mut next = 0;
    theirs
        .paths
        .iter()
        .enumerate()
        .map(|(i, a)| {
            let j = (next..ours.paths.len())
                .find(|&j| same(a, &ours.paths[j]))
                .unwrap_or_else(|| panic!("their path {i} has no counterpart in ours"));
            next = j + 1;
            j
        })
        .collect()
}

pub fn offsets(drawing: &Drawing) -> Vec<usize> {
    drawing
        .paths
        .iter()
        .scan(0, |o, p| {
            let start = *o;
            *o += p.points.len();
            Some(start)
        })
        .collect()
}
