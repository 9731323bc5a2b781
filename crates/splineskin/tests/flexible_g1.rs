//! Flexible G¹ and flexible fixed-angle joints (`spline_fit::flexible`):
//!
//! * on the bundled drawing (its scene's five Shepard handles, default options) under the
//!   scene's poses and random affine poses: the fit energy never increases from step to step,
//!   ends at or below the fixed-ratio rig's, every G¹ junction keeps parallel tangents (its
//!   input's angle, to 1e-9 rad) and every fixed-angle junction its angle, closed paths stay
//!   closed; the default tolerance is within 1e-4 of the diagonal of a converged (1e-9) solve;
//!   a warm start from a nearby pose's solution ends at the cold result (same tolerance);
//! * the identity pose gives back the input (its energy is 0, nothing can lower it);
//! * on the authors' Shepard scenes with G¹ joints, default mode: the same energy properties;
//!   compatibility mode (their schedule and stopping rule) agrees with their solver's output,
//!   flexible iterations included, to 0.3 % of the diagonal (report per case).
//!
//! Figures are printed (`cargo test --test flexible_g1 -- --nocapture`).

mod common;

use common::scene_compare::{deform_flexible, scene_of};
use common::{authors_outputs, Rng};
use kurbo::{Affine, Point, Vec2};
use splineskin::drawing::{Drawing, JointKind};
use splineskin::examples::demo_scene;
use splineskin::scene::{Compat, Scene};
use splineskin::spline_fit::quadrature::SampledCurves;
use splineskin::spline_fit::{FlexibleOptions, FlexibleReport, FlexibleRule, FlexibleSolver};

/// Accuracy of continuity after a flexible solve: radians for angles, fraction of the diagonal
/// for positions.
const CONTINUITY: f64 = 1e-9;

/// Energies may only go down, up to rounding: relative slack 1e-12.
const ENERGY_SLACK: f64 = 1e-12;

/// Distance allowed between the default tolerance's result, or a warm-started one, and a
/// converged solve, as a fraction of the diagonal: 1e-4.
const CONVERGED: f64 = 1e-4;

/// Random poses on the bundled drawing.
const RANDOM_POSES: usize = 6;

impl Rng {
    /// A rotation by up to ±40°, a scale in [0.7, 1.3] and a translation within ±60 units per
    /// handle, about the handle.
    fn pose(&mut self, handles: &[Point]) -> Vec<Affine> {
        handles
            .iter()
            .map(|h| {
                let about = Affine::translate(h.to_vec2());
                Affine::translate((self.range(-60.0, 60.0), self.range(-60.0, 60.0)))
                    * about
                    * Affine::rotate(self.range(-0.7, 0.7))
                    * Affine::scale(self.range(0.7, 1.3))
                    * about.inverse()
            })
            .collect()
    }
}

/// A scene's solver in `compat` with `options`.
fn solver(scene: &Scene, compat: Compat, options: FlexibleOptions) -> (Drawing, FlexibleSolver) {
    let setup = scene.setup(compat).expect("setup");
    let samples = SampledCurves::sample(&setup.drawing, setup.weights.as_ref(), &setup.options);
    let fit = setup.options.with_parallel(true);
    let solver = FlexibleSolver::new(&setup.drawing, &samples, &fit, options).expect("solver");
    (setup.drawing, solver)
}

/// Checks that the report's energies never increase and end at or below the fixed-ratio one,
/// and that `solver.energy` of `points` is the last; returns the relative gain over the rig.
fn check_energies(
    what: &str,
    solver: &FlexibleSolver,
    pose: &[Affine],
    points: &[Point],
    report: &FlexibleReport,
) -> f64 {
    for pair in report.energies.windows(2) {
        assert!(
            pair[1] <= pair[0] * (1.0 + ENERGY_SLACK),
            "{what}: energy went up: {:?}",
            report.energies
        );
    }
    let e = solver.energy(pose, points).expect("energy");
    // The solver iterates about each path's centre and reports those energies; recomputed
    // from the points it wrote they agree to rounding, which matters only for energies at
    // the level of rounding itself: the energy of a 1e-10-of-the-diagonal distance along the
    // whole drawing (the solver's noise floor, NOISE_DISTANCE) is allowed on top.
    let flat = points;
    let (lo, hi) = flat.iter().fold((flat[0], flat[0]), |(lo, hi), p| {
        (
            Point::new(lo.x.min(p.x), lo.y.min(p.y)),
            Point::new(hi.x.max(p.x), hi.y.max(p.y)),
        )
    });
    let diag = (hi - lo).hypot();
    let noise = (splineskin::spline_fit::flexible::NOISE_DISTANCE * diag).powi(2) * diag;
    assert!(
        (e - report.energy()).abs() <= 1e-9 * report.fixed_ratio_energy.max(1e-300) + noise,
        "{what}: energy {e} vs reported {}",
        report.energy()
    );
    assert!(
        e <= report.fixed_ratio_energy * (1.0 + ENERGY_SLACK),
        "{what}: flexible {e} > fixed ratio {}",
        report.fixed_ratio_energy
    );
    if report.fixed_ratio_energy > 0.0 {
        1.0 - e / report.fixed_ratio_energy
    } else {
        0.0
    }
}

/// The first chain point farther than `eps` from on-curve point `p`, backwards or forwards
/// within the neighbouring curve (the library's tangent rule); chain index `3n` of a closed
/// chain is its point 0.
fn next_distinct(points: &[Point], closed: bool, p: usize, back: bool, eps: f64) -> Option<usize> {
    let m = points.len() - 1;
    let (base, step): (usize, isize) = match (back, p) {
        (true, 0) if !closed => return None,
        (true, 0) => (m, -1),
        (true, _) => (p, -1),
        (false, _) if p == m && !closed => return None,
        (false, _) if p == m => (0, 1),
        (false, _) => (p, 1),
    };
    (1..=3)
        .map(|k| (base as isize + step * k) as usize)
        .find(|&i| (points[i] - points[p]).hypot() > eps)
}

/// Largest continuity errors of `out` (layout of `Drawing::flat_points`): G¹ angle error (from
/// the input's angle; G¹ on a corner of the input is C⁰), fixed-angle error (radians),
/// closure (fraction of the diagonal). Also fails on a reversed tangent.
fn continuity(drawing: &Drawing, out: &[Point]) -> (f64, f64, f64) {
    let diag = drawing.diagonal();
    let (mut g1, mut angle, mut closed) = (0.0f64, 0.0f64, 0.0f64);
    let mut offset = 0;
    for path in &drawing.paths {
        let n = path.points.len();
        let o = &out[offset..offset + n];
        offset += n;
        if path.closed {
            closed = closed.max((o[0] - o[n - 1]).hypot() / diag);
        }
        let eps = 1e-9 * diag;
        for (k, &kind) in path.joints.iter().enumerate() {
            if !matches!(kind, JointKind::G1 | JointKind::FixedAngle) {
                continue;
            }
            let p = 3 * k;
            let (Some(a), Some(b)) = (
                next_distinct(&path.points, path.closed, p, true, eps),
                next_distinct(&path.points, path.closed, p, false, eps),
            ) else {
                continue;
            };
            let signed = |u: Vec2, v: Vec2| u.cross(v).atan2(u.dot(v));
            let theta = signed(
                path.points[p] - path.points[a],
                path.points[b] - path.points[p],
            );
            // G¹ tangents farther apart than the smooth angle are a corner in the input, kept
            // C⁰ (no relation); every other G¹ and fixed-angle junction keeps its input angle.
            let smooth = splineskin::drawing::JunctionOptions::default().smooth_angle;
            if kind == JointKind::G1 && theta.abs() > smooth {
                continue;
            }
            let kept = theta;
            let now = signed(o[p] - o[a], o[b] - o[p]);
            let error = (now - kept).abs();
            assert!(error < 1.0, "joint {k}: tangent reversed ({now} vs {kept})");
            match kind {
                JointKind::G1 => g1 = g1.max(error),
                _ => angle = angle.max(error),
            }
        }
    }
    (g1, angle, closed)
}

/// Largest distance between two point sets, relative to the diagonal.
fn distance(a: &[Point], b: &[Point], diag: f64) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (*p - *q).hypot() / diag)
        .fold(0.0, f64::max)
}

#[test]
fn flexible_bundled_drawing_energy_and_continuity() {
    bundled_drawing(FlexibleRule::Newton);
}

#[test]
fn flexible_bundled_drawing_alternating_energy_and_continuity() {
    bundled_drawing(FlexibleRule::Alternating);
}

/// The bundled drawing's checks (module doc) with `rule`.
fn bundled_drawing(rule: FlexibleRule) {
    let scene = demo_scene();
    let options = FlexibleOptions::default().with_rule(rule);
    let (drawing, solver) = solver(&scene, Compat::None, options);
    let (_, converged) = self::solver(
        &scene,
        Compat::None,
        options.with_tolerance(1e-9).with_max_steps(400),
    );
    assert!(solver.n_flexible_junctions() > 0);
    let diag = drawing.diagonal();
    let mut rng = Rng(5);
    let mut poses: Vec<Vec<Affine>> = scene.poses.iter().map(|p| p.transforms.clone()).collect();
    poses.extend((0..RANDOM_POSES).map(|_| rng.pose(&scene.handles)));
    let n = solver.rig().n_points();
    let (mut out, mut reference, mut warm_out) = (
        vec![Point::ZERO; n],
        vec![Point::ZERO; n],
        vec![Point::ZERO; n],
    );
    let mut previous: Option<(Vec<Affine>, Vec<Point>)> = None;
    for (i, pose) in poses.iter().enumerate() {
        let report = solver.solve(pose, None, &mut out).expect("solve");
        let gain = check_energies(&format!("pose {i}"), &solver, pose, &out, &report);
        let (g1, angle, closed) = continuity(&drawing, &out);
        assert!(
            g1 <= CONTINUITY && angle <= CONTINUITY && closed <= CONTINUITY,
            "pose {i}: {g1:e} {angle:e} {closed:e}"
        );
        converged
            .solve(pose, None, &mut reference)
            .expect("converged");
        let to_converged = distance(&out, &reference, diag);
        assert!(
            to_converged <= CONVERGED,
            "pose {i}: {to_converged:e} from converged"
        );
        // Warm start from the solution of a pose 1 % of the way back to the previous one.
        let mut warm_note = String::new();
        if let Some((prev_pose, _)) = &previous {
            let near: Vec<Affine> = prev_pose
                .iter()
                .zip(pose)
                .map(|(a, b)| {
                    Affine::new(std::array::from_fn(|c| {
                        0.99 * b.as_coeffs()[c] + 0.01 * a.as_coeffs()[c]
                    }))
                })
                .collect();
            let mut start = vec![Point::ZERO; n];
            solver.solve(&near, None, &mut start).expect("near");
            let warm = solver
                .solve(pose, Some(&start), &mut warm_out)
                .expect("warm");
            check_energies(&format!("pose {i}, warm"), &solver, pose, &warm_out, &warm);
            if rule == FlexibleRule::Alternating {
                // The ratio step with the nearby solution's ratios beats the rig's start.
                assert!(
                    warm.warm_started_paths > 0,
                    "pose {i}: no path started from the nearby solution"
                );
            }
            let d = distance(&warm_out, &reference, diag);
            assert!(d <= CONVERGED, "pose {i}: warm start {d:e} from converged");
            if rule == FlexibleRule::Newton {
                // Newton starts from a previous solution only where it beats the fixed-ratio
                // fit: the same pose's own result is taken on every path (counted as a step)
                // and confirmed by at most one Newton step.
                let mut again = vec![Point::ZERO; n];
                let same = solver.solve(pose, Some(&out), &mut again).expect("same");
                assert_eq!(same.warm_started_paths, same.paths, "pose {i}");
                assert!(same.steps <= 2, "pose {i}: {:?}", same.path_steps);
                let d = distance(&again, &reference, diag);
                assert!(d <= CONVERGED, "pose {i}: re-solve {d:e} from converged");
            }
            warm_note = format!(
                "; warm start from a pose 1 % nearer the previous: {} steps (cold {}), {} paths warm, {d:.1e} from converged",
                warm.steps, report.steps, warm.warm_started_paths
            );
        }
        eprintln!(
            "pose {i}: energy {:.4e} -> {:.4e} ({:.1} % lower), {} steps (max over {} paths), {} shortened; G1 {g1:.1e} rad, angle {angle:.1e} rad, closed {closed:.1e}; {to_converged:.1e} from converged{warm_note}",
            report.fixed_ratio_energy,
            report.energy(),
            100.0 * gain,
            report.steps,
            report.paths,
            report.shortened_steps
        );
        previous = Some((pose.clone(), out.clone()));
    }
}

#[test]
fn flexible_identity_pose_gives_the_input() {
    let scene = demo_scene();
    let (drawing, solver) = solver(&scene, Compat::None, FlexibleOptions::default());
    let pose = vec![Affine::IDENTITY; solver.rig().n_handles()];
    let mut out = vec![Point::ZERO; solver.rig().n_points()];
    let report = solver.solve(&pose, None, &mut out).expect("solve");
    let d = distance(&out, &drawing.flat_points(), drawing.diagonal());
    eprintln!(
        "identity: {d:.1e} of the diagonal from the input, energy {:.1e} (fixed ratio {:.1e}), {} steps",
        report.energy(),
        report.fixed_ratio_energy,
        report.steps
    );
    assert!(d <= CONTINUITY, "{d:e}");
    // The energy is zero up to rounding (relative to the drawing's squared size times length).
    assert!(
        report.energy() <= 1e-20 * diag_scale(&drawing),
        "{}",
        report.energy()
    );
}

/// `diag³`: the scale of an energy (squared distance times length) on the drawing.
fn diag_scale(drawing: &Drawing) -> f64 {
    drawing.diagonal().powi(3)
}

#[test]
fn flexible_authors_shepard_cases_default_mode_energy() {
    let Some(root) = common::data_root() else {
        return;
    };
    for case in authors_outputs::shepard_flexible_cases(&root) {
        let scene = scene_of(&root, &case);
        let (drawing, solver) = solver(&scene, Compat::None, FlexibleOptions::default());
        let pose = scene.pose(0).expect("pose 0").transforms;
        let mut out = vec![Point::ZERO; solver.rig().n_points()];
        let report = solver.solve(&pose, None, &mut out).expect("solve");
        let gain = check_energies(&case.case, &solver, &pose, &out, &report);
        let (g1, angle, closed) = continuity(&drawing, &out);
        eprintln!(
            "{}: default mode, energy {:.4e} -> {:.4e} ({:.1} % lower), {} steps (max over {} paths); G1 {g1:.1e}, angle {angle:.1e}, closed {closed:.1e}",
            case.case,
            report.fixed_ratio_energy,
            report.energy(),
            100.0 * gain,
            report.steps,
            report.paths
        );
        assert!(
            g1 <= CONTINUITY && angle <= CONTINUITY && closed <= CONTINUITY,
            "{}",
            case.case
        );
    }
}

/// Agreement required with the authors' solver (their flexible iterations included) in
/// compatibility mode, as a fraction of the bounding-box diagonal: 0.3 % (their stopping test
/// is 1 px per coordinate, so their result is not an exact minimiser).
const AUTHORS_TOLERANCE: f64 = 3e-3;

#[test]
fn flexible_authors_shepard_cases_conform() {
    let Some(root) = common::data_root() else {
        return;
    };
    let cases = authors_outputs::shepard_flexible_cases(&root);
    for case in &cases {
        let scene = scene_of(&root, case);
        let (theirs, points, singular, report) =
            deform_flexible(&scene, Compat::VectorSkinning, None);
        let diag = theirs.diagonal();
        let errors = authors_outputs::per_path_errors(&theirs, &points, &case.deformed_paths, diag);
        let worst = authors_outputs::worst_except(&errors, &singular);
        eprintln!(
            "{}: {worst:.2e} of the diagonal; {} paths iterated, steps {} (max); singular {:?}",
            case.case, report.paths, report.steps, singular
        );
        for &(p, steps) in &report.path_steps {
            if errors[p] > 1e-9 {
                eprintln!("  path {p}: {:.2e}, {steps} steps", errors[p]);
            }
        }
        assert!(worst <= AUTHORS_TOLERANCE, "{}: {worst:e}", case.case);
    }
}
