//! Invariants of the fit on the bundled drawing (`examples::DEMO_SVG` read with `read_svg`, the
//! demo scene's five handles, default options), under both measures, and on a tiling of it to
//! about a thousand curves:
//!
//! * the identity pose reproduces the input to 1e-9 of the bounding-box diagonal;
//! * one map on every handle gives that map of the input (1e-9): similarities on the drawing as
//!   imported; general affine maps once the joints whose constraint is not affine-invariant
//!   (fixed angles, and G¹ joints keeping a non-zero input angle) are relaxed to C⁰;
//! * after each of the scene's poses and after random per-handle affine poses, every junction
//!   satisfies its kind (module `junction` of the library: tangents through the next distinct
//!   control point): closed paths stay closed, C¹ tangents are equal (where the input is C¹;
//!   elsewhere they keep the input's angle and ratio), G¹ tangents keep their input angle and
//!   length ratio, fixed-angle junctions keep angle and ratio, control points lying on a junction
//!   point stay on it (1e-9);
//! * the deformed drawing written by `svg_out::write_svg` reads back to the same paths and points;
//! * junction kinds overridden through a scene (`junctions: [{path, joint, kind}]`) change the
//!   fit: the imposed relation holds after every pose and did not without the override, a smooth
//!   joint made C⁰ is free; overrides of missing paths or joints, or of open ends, are errors
//!   naming `junctions[i]`.
//!
//! The paper authors' discretisation (`Compat::VectorSkinning`) does not reproduce the input at
//! its G¹ joints (its rows force parallel tangents, and the bundled drawing's smooth joints are
//! parallel only to the three decimals it was written with), so there the checks are its own
//! constraint rows after every pose, the equivariance of the fit (one map on every handle gives
//! that map of the identity pose's result), and the identity pose on the paths whose input
//! satisfies those rows.
//!
//! Every test prints the worst error it saw per invariant (`cargo test -- --nocapture`).

mod common;

use common::measure::joint_count as count;
use common::Rng;
use kurbo::{Affine, Point, Vec2};
use splineskin::drawing::svg_out::write_svg;
use splineskin::drawing::{read_svg, Drawing, ImportOptions, JointKind, JunctionOptions, Path};
use splineskin::examples::{demo_scene, tile, DEMO_SCENE, DEMO_SVG};
use splineskin::scene::{Compat, Scene, SceneError};
use splineskin::spline_fit::{FitOptions, Measure, SplineRig};
use splineskin::weights::{Shepard, ShepardOptions, WeightField};

/// Required accuracy of every invariant: relative to the drawing's bounding-box diagonal for
/// positions, radians for angles, relative for length ratios. The errors measured are below
/// 3e-14 of the diagonal for positions and 3e-12 for angles and ratios; a wrong input is off by
/// far more (`rig_invariants_checks_detect_errors`).
const INVARIANT_TOLERANCE: f64 = 1e-9;

/// Largest input angle (radians) of a G¹ joint that still counts as exactly parallel for the
/// general affine check: 1e-12. A G¹ joint keeps its input angle θ, which a general affine map
/// changes by about θ, moving the fit by about θ times a tangent length: below 1e-12 rad that
/// is far under [`INVARIANT_TOLERANCE`].
const PARALLEL_ANGLE: f64 = 1e-12;

/// Curves of the tiled drawing: about a thousand (the demo's 58 curves tile to a 5 × 4 grid).
const TILED_CURVES: usize = 1000;

/// Random poses per rig.
const RANDOM_POSES: usize = 4;

/// Largest errors seen, per invariant.
#[derive(Default, Debug)]
struct Worst {
    /// Identity pose, relative to the diagonal.
    identity: f64,
    /// One map on every handle, relative to the diagonal.
    affine: f64,
    /// Closed paths: last point vs first, relative to the diagonal.
    closed: f64,
    /// C¹: difference of the tangents, relative to the diagonal.
    c1: f64,
    /// G¹: angle error (radians) and ratio error (relative).
    g1_angle: f64,
    g1_ratio: f64,
    /// Fixed angle: angle error (radians) and ratio error (relative).
    angle_angle: f64,
    angle_ratio: f64,
    /// Control points on a junction point, relative to the diagonal.
    pinned: f64,
    /// Authors' rows: residual relative to the diagonal.
    authors_rows: f64,
    /// SVG round trip, relative to the diagonal.
    svg: f64,
    /// Junctions checked, per kind C1, G1, fixed angle.
    counts: [usize; 3],
}

impl Worst {
    fn assert_within(&self, what: &str) {
        eprintln!("{what}: {self:?}");
        for (name, v) in [
            ("identity", self.identity),
            ("affine", self.affine),
            ("closed", self.closed),
            ("C1", self.c1),
            ("G1 angle", self.g1_angle),
            ("G1 ratio", self.g1_ratio),
            ("fixed angle", self.angle_angle),
            ("fixed-angle ratio", self.angle_ratio),
            ("pinned", self.pinned),
            ("authors' rows", self.authors_rows),
            ("svg round trip", self.svg),
        ] {
            assert!(v <= INVARIANT_TOLERANCE, "{what}: {name} error {v:e}");
        }
    }
}

impl Rng {
    /// A general affine map per handle: linear part within ±0.4 of the identity (so orientation
    /// is kept), translation within ±40 units, about the handle's position.
    fn pose(&mut self, handles: &[Point]) -> Vec<Affine> {
        handles
            .iter()
            .map(|h| {
                let m = [
                    1.0 + self.range(-0.4, 0.4),
                    self.range(-0.4, 0.4),
                    self.range(-0.4, 0.4),
                    1.0 + self.range(-0.4, 0.4),
                    self.range(-40.0, 40.0),
                    self.range(-40.0, 40.0),
                ];
                Affine::translate(h.to_vec2()) * Affine::new(m) * Affine::translate(-h.to_vec2())
            })
            .collect()
    }
}

fn rotate(v: Vec2, angle: f64) -> Vec2 {
    let (s, c) = angle.sin_cos();
    Vec2::new(c * v.x - s * v.y, s * v.x + c * v.y)
}

/// Signed angle from `u` to `v`, in `(−π, π]`.
fn signed_angle(u: Vec2, v: Vec2) -> f64 {
    u.cross(v).atan2(u.dot(v))
}

/// `a − b` wrapped into `(−π, π]`, absolute.
fn angle_difference(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(std::f64::consts::TAU);
    d.min(std::f64::consts::TAU - d)
}

/// The first point of the chain, going backwards (`step = −1`) or forwards (`+1`) from
/// on-curve point `p` within the neighbouring curve, farther than `eps` from it: the library's
/// definition of a junction's tangent (module `drawing::junction`). Chain index `3n` of a
/// closed chain is its point 0.
fn next_distinct(
    points: &[Point],
    closed: bool,
    p: usize,
    backwards: bool,
    eps: f64,
) -> Option<usize> {
    let m = points.len() - 1;
    if backwards {
        if p == 0 && !closed {
            return None;
        }
        let base = if p == 0 { m } else { p };
        (1..=3)
            .map(|k| base - k)
            .find(|&i| (points[i] - points[p]).hypot() > eps)
    } else {
        if p == m && !closed {
            return None;
        }
        let base = if p == m { 0 } else { p };
        (1..=3)
            .map(|k| base + k)
            .find(|&i| (points[i] - points[p]).hypot() > eps)
    }
}

/// The library's coincidence distance of a chain: the relative tolerance times the diagonal of
/// its control points' bounding box.
fn coincidence(points: &[Point], relative: f64) -> f64 {
    let (mut lo, mut hi) = (points[0], points[0]);
    for p in points {
        lo = Point::new(lo.x.min(p.x), lo.y.min(p.y));
        hi = Point::new(hi.x.max(p.x), hi.y.max(p.y));
    }
    ((hi - lo).hypot() * relative).max(f64::MIN_POSITIVE)
}

/// The relation a deformed junction must satisfy in our form, measured: for tangents `u`, `v`
/// of the input and `u'`, `v'` of the output (next distinct points on each side), the angle
/// error `|∠(u', v') − θ|` and the ratio error `|(|v'|/|u'|) / r − 1|`, where `θ`, `r` are what
/// the kind keeps (C¹ on a C¹ input: 0 and 1; otherwise the input's angle and ratio, so that
/// the rest pose is the drawing; C¹ and G¹ on a corner of the input keep only its position). `None` when one side has
/// no distinct point (the joint then only keeps its position).
#[derive(Debug)]
struct Relation {
    angle_error: f64,
    ratio_error: f64,
    /// `|v' − u'|` (only meaningful for strict C¹).
    difference: f64,
    /// Whether the relation is strict C¹ (a C¹ joint whose input is C¹).
    strict_c1: bool,
    /// Largest distance of a control point lying on the junction point in the input from the
    /// junction point in the output.
    pinned: f64,
}

fn relation(
    input: &[Point],
    output: &[Point],
    closed: bool,
    joint: usize,
    kind: JointKind,
    options: &JunctionOptions,
) -> Option<Relation> {
    let m = input.len() - 1;
    let p = 3 * joint;
    let eps = coincidence(input, options.coincidence);
    let a = next_distinct(input, closed, p, true, eps)?;
    let b = next_distinct(input, closed, p, false, eps)?;
    let (u, v) = (input[p] - input[a], input[b] - input[p]);
    let (u2, v2) = (output[p] - output[a], output[b] - output[p]);
    let input_angle = signed_angle(u, v);
    // Strict C¹ only where the input is C¹; everywhere else the input's own angle and ratio,
    // whatever kind was saved (the rest pose is the drawing).
    let input_is_c1 = input_angle.abs() <= options.c1_ratio
        && (u.hypot() / v.hypot() - 1.0).abs() <= options.c1_ratio;
    let (theta, ratio) = match kind {
        JointKind::C1 if input_is_c1 => (0.0, 1.0),
        // A corner saved smooth keeps only its position.
        JointKind::C1 | JointKind::G1 if input_angle.abs() > options.smooth_angle => return None,
        JointKind::C1 | JointKind::G1 | JointKind::FixedAngle => {
            (input_angle, v.hypot() / u.hypot())
        }
        JointKind::End | JointKind::C0 => return None,
    };
    // Points strictly between a and p, and p and b, in chain order (wrapping at a closed end).
    let end = if p == 0 { m } else { p };
    let pinned = (1..end - a)
        .map(|d| (end - d) % m)
        .chain((1..b - p).map(|d| p + d))
        .map(|q| (output[q] - output[p]).hypot())
        .fold(0.0, f64::max);
    Some(Relation {
        angle_error: angle_difference(signed_angle(u2, v2), theta),
        ratio_error: ((v2.hypot() / u2.hypot()) / ratio - 1.0).abs(),
        difference: (v2 - u2).hypot(),
        strict_c1: kind == JointKind::C1 && input_is_c1,
        pinned,
    })
}

impl Relation {
    /// The error of a C¹ joint: `|v' − u'|` relative to `diag` where strict, else the angle
    /// and ratio errors of the input's relation.
    fn c1_error(&self, diag: f64) -> f64 {
        if self.strict_c1 {
            self.difference / diag
        } else {
            self.angle_error.max(self.ratio_error)
        }
    }
}

/// Checks every junction of the deformed `output` (layout of `Drawing::flat_points`) in our
/// form, recording the errors in `worst`.
fn check_junctions(
    drawing: &Drawing,
    output: &[Point],
    options: &JunctionOptions,
    worst: &mut Worst,
) {
    let diag = drawing.diagonal();
    for (path, range) in drawing.paths.iter().zip(drawing.path_ranges()) {
        let n = path.points.len();
        let o = &output[range];
        if path.closed {
            worst.closed = worst.closed.max((o[0] - o[n - 1]).hypot() / diag);
        }
        for (k, &kind) in path.joints.iter().enumerate() {
            let Some(r) = relation(&path.points, o, path.closed, k, kind, options) else {
                continue;
            };
            worst.pinned = worst.pinned.max(r.pinned / diag);
            match kind {
                JointKind::C1 => {
                    worst.c1 = worst.c1.max(r.c1_error(diag));
                    worst.counts[0] += 1;
                }
                JointKind::G1 => {
                    worst.g1_angle = worst.g1_angle.max(r.angle_error);
                    worst.g1_ratio = worst.g1_ratio.max(r.ratio_error);
                    worst.counts[1] += 1;
                }
                JointKind::FixedAngle => {
                    worst.angle_angle = worst.angle_angle.max(r.angle_error);
                    worst.angle_ratio = worst.angle_ratio.max(r.ratio_error);
                    worst.counts[2] += 1;
                }
                JointKind::End | JointKind::C0 => unreachable!("no relation for {kind:?}"),
            }
        }
    }
}

/// Largest residual of the paper authors' rows (`ConstraintForm::Authors`) on path `path` of
/// `drawing` deformed to `o` (its chain points), relative to `diag`: immediate neighbours
/// `a = p − 1`, `b = p + 1`, `lu·v' − lv·R(θ)·u' = 0` with the input lengths normalised by the
/// larger, `θ` the input angle at fixed-angle joints and 0 at C¹ and G¹ ones.
fn authors_residual(path: &Path, o: &[Point], diag: f64) -> f64 {
    let m = path.points.len() - 1;
    let mut worst: f64 = 0.0;
    for (k, &kind) in path.joints.iter().enumerate() {
        if matches!(kind, JointKind::End | JointKind::C0) {
            continue;
        }
        let p = 3 * k;
        let a = if p == 0 { m - 1 } else { p - 1 };
        let b = p + 1;
        let (u, v) = (
            path.points[p] - path.points[a],
            path.points[b] - path.points[p],
        );
        let scale = u.hypot().max(v.hypot());
        if scale == 0.0 {
            continue;
        }
        let theta = if kind == JointKind::FixedAngle && u.hypot() > 0.0 && v.hypot() > 0.0 {
            signed_angle(u, v)
        } else {
            0.0
        };
        let (lu, lv) = (u.hypot() / scale, v.hypot() / scale);
        let (u2, v2) = (o[p] - o[a], o[b] - o[p]);
        worst = worst.max((v2 * lu - rotate(u2, theta) * lv).hypot() / diag);
    }
    worst
}

/// The chain points of each path of `drawing` within `flat` (layout of `Drawing::flat_points`).
fn per_path<'a>(
    drawing: &'a Drawing,
    flat: &'a [Point],
) -> impl Iterator<Item = (&'a Path, &'a [Point])> {
    drawing
        .paths
        .iter()
        .zip(drawing.path_ranges())
        .map(move |(path, range)| (path, &flat[range]))
}

/// Largest distance between `want` and `got`, relative to `diag`.
fn max_distance(want: impl IntoIterator<Item = Point>, got: &[Point], diag: f64) -> f64 {
    want.into_iter()
        .zip(got)
        .map(|(p, q)| (p - *q).hypot() / diag)
        .fold(0.0, f64::max)
}

/// A copy of `drawing` whose joints that a general affine map does not keep are C⁰: fixed
/// angles, and G¹ joints whose input angle exceeds [`PARALLEL_ANGLE`] (with `options`, the
/// tolerances the fit writes its constraints with).
fn affine_invariant_copy(drawing: &Drawing, options: &JunctionOptions) -> Drawing {
    let mut copy = drawing.clone();
    for path in &mut copy.paths {
        let eps = coincidence(&path.points, options.coincidence);
        for k in 0..path.joints.len() {
            let kind = path.joints[k];
            let relax = match kind {
                JointKind::FixedAngle => true,
                JointKind::G1 => {
                    let p = 3 * k;
                    let a = next_distinct(&path.points, path.closed, p, true, eps);
                    let b = next_distinct(&path.points, path.closed, p, false, eps);
                    match (a, b) {
                        (Some(a), Some(b)) => {
                            let u = path.points[p] - path.points[a];
                            let v = path.points[b] - path.points[p];
                            signed_angle(u, v).abs() > PARALLEL_ANGLE
                        }
                        _ => false,
                    }
                }
                _ => false,
            };
            if relax {
                path.joints[k] = JointKind::C0;
            }
        }
    }
    copy
}

/// The bundled drawing (our importer) and the demo scene's handles.
fn demo() -> (Drawing, Vec<Point>, Vec<Vec<Affine>>) {
    let drawing = read_svg(DEMO_SVG, &ImportOptions::default()).unwrap();
    let scene = demo_scene();
    let poses = scene.poses.iter().map(|p| p.transforms.clone()).collect();
    (drawing, scene.handles, poses)
}

fn shepard(handles: &[Point]) -> Shepard {
    Shepard::new(handles, ShepardOptions::default())
}

/// A similarity and a general affine map (shear and unequal scales), both orientation
/// preserving, moving the drawing well away from where it was.
fn test_maps() -> (Affine, Affine) {
    let similarity = Affine::translate((37.0, -21.0)) * Affine::rotate(0.7) * Affine::scale(1.6);
    let general = Affine::new([1.3, 0.4, -0.7, 0.9, 12.0, -5.0]);
    (similarity, general)
}

/// Identity and one-map invariants of `drawing` under `options`, recorded in `worst`. Returns
/// the rig of `drawing` with Shepard weights of `handles` (the one checked under the identity
/// and the similarity).
fn check_identity_and_maps(
    drawing: &Drawing,
    handles: &[Point],
    options: &FitOptions,
    worst: &mut Worst,
) -> SplineRig {
    let weights = shepard(handles);
    let diag = drawing.diagonal();
    let input = drawing.flat_points();
    let rig = SplineRig::precompute(drawing, &weights, options).unwrap();
    let mut out = vec![Point::ZERO; rig.n_points()];
    rig.update(&vec![Affine::IDENTITY; handles.len()], &mut out)
        .unwrap();
    worst.identity = worst
        .identity
        .max(max_distance(input.iter().copied(), &out, diag));

    let (similarity, general) = test_maps();
    rig.update(&vec![similarity; handles.len()], &mut out)
        .unwrap();
    worst.affine = worst.affine.max(max_distance(
        input.iter().map(|&p| similarity * p),
        &out,
        diag,
    ));

    let relaxed = affine_invariant_copy(drawing, &options.junctions);
    let relaxed_rig = SplineRig::precompute(&relaxed, &weights, options).unwrap();
    relaxed_rig
        .update(&vec![general; handles.len()], &mut out)
        .unwrap();
    worst.affine = worst
        .affine
        .max(max_distance(input.iter().map(|&p| general * p), &out, diag));
    rig
}

/// [`check_identity_and_maps`] under `measure`: the invariants recorded, the options, the rig
/// and a buffer for its points.
fn checked_rig(
    drawing: &Drawing,
    handles: &[Point],
    measure: Measure,
) -> (Worst, FitOptions, SplineRig, Vec<Point>) {
    let mut worst = Worst::default();
    let options = FitOptions::default().with_measure(measure);
    let rig = check_identity_and_maps(drawing, handles, &options, &mut worst);
    let out = vec![Point::ZERO; rig.n_points()];
    (worst, options, rig, out)
}

#[test]
fn rig_invariants_demo_identity_and_maps() {
    let (drawing, handles, _) = demo();
    // The general map is checked with the right angle and the four G¹ joints that keep a
    // non-zero input angle relaxed; eleven G¹ and all C¹ joints stay.
    let relaxed = affine_invariant_copy(&drawing, &JunctionOptions::default());
    assert_eq!(count(&relaxed, JointKind::FixedAngle), 0);
    assert_eq!(
        count(&relaxed, JointKind::G1),
        count(&drawing, JointKind::G1) - 4
    );
    assert_eq!(
        count(&relaxed, JointKind::C1),
        count(&drawing, JointKind::C1)
    );
    for measure in [Measure::LengthWeighted, Measure::ArcLength] {
        let mut worst = Worst::default();
        let options = FitOptions::default().with_measure(measure);
        let _ = check_identity_and_maps(&drawing, &handles, &options, &mut worst);
        worst.assert_within(&format!("demo, {measure:?}"));
    }
}

#[test]
fn rig_invariants_demo_junctions_after_poses() {
    let (drawing, handles, poses) = demo();
    let weights = shepard(&handles);
    let mut rng = Rng(0x5eed_0001);
    for measure in [Measure::LengthWeighted, Measure::ArcLength] {
        let mut worst = Worst::default();
        let options = FitOptions::default().with_measure(measure);
        let rig = SplineRig::precompute(&drawing, &weights, &options).unwrap();
        let mut out = vec![Point::ZERO; rig.n_points()];
        let random: Vec<_> = (0..RANDOM_POSES).map(|_| rng.pose(&handles)).collect();
        for pose in poses.iter().chain(&random) {
            rig.update(pose, &mut out).unwrap();
            check_junctions(&drawing, &out, &options.junctions, &mut worst);
        }
        // Every constrained kind of the drawing was checked, after every pose.
        let n_poses = poses.len() + RANDOM_POSES;
        assert_eq!(worst.counts[0], n_poses * count(&drawing, JointKind::C1));
        assert_eq!(worst.counts[1], n_poses * count(&drawing, JointKind::G1));
        assert_eq!(
            worst.counts[2],
            n_poses * count(&drawing, JointKind::FixedAngle)
        );
        assert!(worst.counts.iter().all(|&c| c > 0), "{:?}", worst.counts);
        worst.assert_within(&format!("demo poses, {measure:?}"));
    }
}

/// Two open paths added to the bundled drawing, each with both handles of its middle junction
/// lying on the junction point, so that the tangents come from the next distinct points: a G¹
/// junction (ratio 2) and a right-angle one. In compatibility mode, a polyline whose lines have
/// their control points on their ends.
const DEGENERATE_PATHS: &str = r#"<path id="degenerate-g1" fill="none" stroke="black" d="M 100 380 C 120 360 160 380 160 380 C 160 380 240 420 260 380"/>
<path id="degenerate-angle" fill="none" stroke="black" d="M 300 380 C 320 370 340 380 340 380 C 340 380 330 400 360 420"/>
<path id="polyline" fill="none" stroke="black" d="M 400 380 L 440 360 L 480 380 L 520 400"/>
</svg>"#;

fn demo_with_degenerate_handles() -> String {
    DEMO_SVG.replace("</svg>", DEGENERATE_PATHS)
}

#[test]
fn rig_invariants_degenerate_handles_use_next_distinct_points() {
    let svg = demo_with_degenerate_handles();
    let drawing = read_svg(&svg, &ImportOptions::default()).unwrap();
    let (_, handles, poses) = demo();
    let n = drawing.paths.len();
    let (g1, angle) = (&drawing.paths[n - 3], &drawing.paths[n - 2]);
    assert_eq!(g1.joints, [JointKind::End, JointKind::G1, JointKind::End]);
    assert_eq!(angle.joints[1], JointKind::FixedAngle);
    assert_eq!(g1.points[2], g1.points[3]);
    let mut rng = Rng(0x5eed_0002);
    for measure in [Measure::LengthWeighted, Measure::ArcLength] {
        let (mut worst, options, rig, mut out) = checked_rig(&drawing, &handles, measure);
        for pose in poses
            .iter()
            .cloned()
            .chain((0..RANDOM_POSES).map(|_| rng.pose(&handles)))
        {
            rig.update(&pose, &mut out).unwrap();
            check_junctions(&drawing, &out, &options.junctions, &mut worst);
            // The degenerate handles stayed degenerate and the curve next to them moved.
            let (_, o) = per_path(&drawing, &out).nth(n - 3).unwrap();
            assert!((o[2] - o[3]).hypot() <= INVARIANT_TOLERANCE * drawing.diagonal());
            assert!((o[3] - g1.points[3]).hypot() > 1.0, "{:?}", o[3]);
        }
        worst.assert_within(&format!("demo with degenerate handles, {measure:?}"));
    }
}

#[test]
fn rig_invariants_tiled_demo() {
    let (drawing, handles, _) = demo();
    let (tiled, tiled_handles) = tile(&drawing, &handles, TILED_CURVES);
    assert!((TILED_CURVES..2 * TILED_CURVES).contains(&tiled.n_curves()));
    let mut rng = Rng(0x5eed_0003);
    for measure in [Measure::LengthWeighted, Measure::ArcLength] {
        let (mut worst, options, rig, mut out) = checked_rig(&tiled, &tiled_handles, measure);
        rig.update(&rng.pose(&tiled_handles), &mut out).unwrap();
        check_junctions(&tiled, &out, &options.junctions, &mut worst);
        worst.assert_within(&format!(
            "tiled demo ({} curves), {measure:?}",
            tiled.n_curves()
        ));
    }
}

#[test]
fn rig_invariants_deformed_svg_reads_back() {
    let (drawing, handles, poses) = demo();
    let weights = shepard(&handles);
    let rig = SplineRig::precompute(&drawing, &weights, &FitOptions::default()).unwrap();
    let diag = drawing.diagonal();
    let mut out = vec![Point::ZERO; rig.n_points()];
    let mut worst = Worst::default();
    let identity = vec![Affine::IDENTITY; handles.len()];
    for pose in std::iter::once(&identity).chain(&poses) {
        rig.update(pose, &mut out).unwrap();
        let svg = write_svg(&drawing, &out).unwrap();
        let back = read_svg(&svg, &ImportOptions::default()).unwrap();
        assert_eq!(back.paths.len(), drawing.paths.len());
        for (a, b) in drawing.paths.iter().zip(&back.paths) {
            assert_eq!((a.points.len(), a.closed), (b.points.len(), b.closed));
        }
        worst.svg = worst.svg.max(max_distance(back.flat_points(), &out, diag));
    }
    worst.assert_within("deformed SVG read back");
}

/// The demo scene's setup in the authors' compatibility mode, with drawing `svg` and `measure`.
fn compat_setup(svg: &str, measure: Measure) -> splineskin::scene::Setup {
    let mut scene = demo_scene();
    scene.svg_text = svg.to_string();
    scene.measure = measure;
    scene.setup(Compat::VectorSkinning).unwrap()
}

#[test]
fn rig_invariants_compat_vectorskinning() {
    let mut rng = Rng(0x5eed_0004);
    let with_lines = demo_with_degenerate_handles();
    for (svg, measure) in [
        (DEMO_SVG, Measure::LengthWeighted),
        (DEMO_SVG, Measure::ArcLength),
        (with_lines.as_str(), Measure::LengthWeighted),
    ] {
        let setup = compat_setup(svg, measure);
        let (drawing, weights, options) = (&setup.drawing, setup.weights.as_ref(), &setup.options);
        let handles = demo_scene().handles;
        let diag = drawing.diagonal();
        let input = drawing.flat_points();
        let mut worst = Worst::default();
        let rig = SplineRig::precompute(drawing, weights, options).unwrap();
        assert!(rig.rank_deficient_paths().is_empty());
        let mut rest = vec![Point::ZERO; rig.n_points()];
        rig.update(&vec![Affine::IDENTITY; handles.len()], &mut rest)
            .unwrap();

        // The identity pose reproduces exactly the paths whose input satisfies the rows.
        let (mut exact, mut moved) = (0, 0);
        for ((path, r), (_, i)) in per_path(drawing, &rest).zip(per_path(drawing, &input)) {
            if authors_residual(path, &path.points, diag) <= f64::EPSILON {
                worst.identity = worst.identity.max(max_distance(i.iter().copied(), r, diag));
                exact += 1;
            } else {
                moved += 1;
            }
        }
        eprintln!("identity: {exact} paths satisfy the authors' rows, {moved} do not");
        assert!(exact >= 6 && moved >= 1, "{exact} exact, {moved} moved");

        // One map on every handle maps the rest result.
        let (similarity, general) = test_maps();
        let mut out = vec![Point::ZERO; rig.n_points()];
        rig.update(&vec![similarity; handles.len()], &mut out)
            .unwrap();
        worst.affine = max_distance(rest.iter().map(|&p| similarity * p), &out, diag);
        let relaxed = affine_invariant_copy(drawing, &options.junctions);
        let relaxed_rig = SplineRig::precompute(&relaxed, weights, options).unwrap();
        relaxed_rig
            .update(&vec![Affine::IDENTITY; handles.len()], &mut rest)
            .unwrap();
        relaxed_rig
            .update(&vec![general; handles.len()], &mut out)
            .unwrap();
        worst.affine =
            worst
                .affine
                .max(max_distance(rest.iter().map(|&p| general * p), &out, diag));

        // The authors' rows hold after every pose.
        for pose in demo_scene()
            .poses
            .iter()
            .map(|p| p.transforms.clone())
            .chain((0..RANDOM_POSES).map(|_| rng.pose(&handles)))
        {
            rig.update(&pose, &mut out).unwrap();
            for (path, o) in per_path(drawing, &out) {
                worst.authors_rows = worst.authors_rows.max(authors_residual(path, o, diag));
                if path.closed {
                    worst.closed = worst.closed.max((o[0] - o[o.len() - 1]).hypot() / diag);
                }
            }
        }
        worst.assert_within(&format!(
            "compat vectorskinning, {} paths, {measure:?}",
            drawing.paths.len()
        ));
    }
}

/// Each check above reports errors it is meant to catch: control points skinned one by one
/// (the paper's first naive baseline) break C¹, G¹ and fixed angles and the authors' rows, a
/// map off by a ten-millionth of a radian is seen by the map checks, and moving a closing or a
/// pinned point by 1e-7 of the diagonal is seen by the closure and pin checks.
#[test]
fn rig_invariants_checks_detect_errors() {
    let svg = demo_with_degenerate_handles();
    let drawing = read_svg(&svg, &ImportOptions::default()).unwrap();
    let (_, handles, poses) = demo();
    let weights = shepard(&handles);
    let diag = drawing.diagonal();
    let input = drawing.flat_points();
    let options = JunctionOptions::default();
    let above = |v: f64, what: &str| assert!(v > 10.0 * INVARIANT_TOLERANCE, "{what}: {v:e}");

    // Naive skinning of every control point.
    let naive = |drawing: &Drawing, pose: &[Affine]| -> Vec<Point> {
        let mut w = vec![0.0; handles.len()];
        drawing
            .flat_points()
            .iter()
            .map(|&p| {
                weights.eval(p, &mut w);
                let sum = w
                    .iter()
                    .zip(pose)
                    .fold(Vec2::ZERO, |s, (wi, t)| s + (*t * p).to_vec2() * *wi);
                sum.to_point()
            })
            .collect()
    };
    let flap = &poses[2];
    let mut worst = Worst::default();
    check_junctions(&drawing, &naive(&drawing, flap), &options, &mut worst);
    above(worst.c1, "C1");
    above(worst.g1_angle.max(worst.g1_ratio), "G1");
    above(worst.angle_angle.max(worst.angle_ratio), "fixed angle");
    let compat = compat_setup(&svg, Measure::LengthWeighted).drawing;
    let naive_compat = naive(&compat, flap);
    let authors = per_path(&compat, &naive_compat)
        .map(|(path, o)| authors_residual(path, o, compat.diagonal()))
        .fold(0.0, f64::max);
    above(authors, "authors' rows");

    // A slightly wrong map.
    let (similarity, _) = test_maps();
    let rig = SplineRig::precompute(&drawing, &weights, &FitOptions::default()).unwrap();
    let mut out = vec![Point::ZERO; rig.n_points()];
    rig.update(&vec![similarity; handles.len()], &mut out)
        .unwrap();
    let off = similarity * Affine::rotate(1e-7);
    above(
        max_distance(input.iter().map(|&p| off * p), &out, diag),
        "map",
    );

    // A closed path opened, a pinned point moved.
    let nudge = Vec2::new(0.0, 1e-7 * diag);
    let closed = drawing.paths.iter().position(|p| p.closed).unwrap();
    let degenerate = drawing.paths.len() - 3;
    for (path_index, point) in [
        (closed, drawing.paths[closed].points.len() - 1),
        (degenerate, 2),
    ] {
        let mut moved = input.clone();
        let first: usize = drawing.paths[..path_index]
            .iter()
            .map(|p| p.points.len())
            .sum();
        moved[first + point] += nudge;
        let mut worst = Worst::default();
        check_junctions(&drawing, &moved, &options, &mut worst);
        above(worst.closed.max(worst.pinned), "closure or pin");
    }
}

/// The demo scene (drawing inline) with `junctions` (JSON array, our format) added.
fn scene_with_junctions(junctions: &str) -> Result<Scene, SceneError> {
    let mut json: serde_json::Value = serde_json::from_str(DEMO_SCENE).unwrap();
    let object = json.as_object_mut().unwrap();
    object.remove("svg");
    object.insert("svg_text".into(), DEMO_SVG.into());
    object.insert("junctions".into(), serde_json::from_str(junctions).unwrap());
    Scene::from_json(&json.to_string(), "junctions.json", None)
}

/// The scene's drawing deformed by each of its poses and by random ones, in `compat` mode.
fn deform_scene(scene: &Scene, compat: Compat) -> (Drawing, Vec<Vec<Point>>) {
    let setup = scene.setup(compat).unwrap();
    let rig =
        SplineRig::precompute(&setup.drawing, setup.weights.as_ref(), &setup.options).unwrap();
    let mut rng = Rng(0x5eed_0005);
    let random: Vec<_> = (0..RANDOM_POSES)
        .map(|_| rng.pose(&scene.handles))
        .collect();
    let outputs = scene
        .poses
        .iter()
        .map(|p| &p.transforms)
        .chain(&random)
        .map(|pose| {
            let mut out = vec![Point::ZERO; rig.n_points()];
            rig.update(pose, &mut out).unwrap();
            out
        })
        .collect();
    (setup.drawing, outputs)
}

/// Overrides on the fish's body (path 3, closed, joints C0 G1 G1 G1 G1 C1 C0), tail (path 0)
/// and gill (path 8, open, End G1 End), as (path, joint, kind as imported, kind imposed).
const OVERRIDES: [(usize, usize, JointKind, JointKind); 5] = [
    (3, 1, JointKind::G1, JointKind::C0),
    (3, 6, JointKind::C0, JointKind::G1),
    (3, 0, JointKind::C0, JointKind::C1),
    (0, 2, JointKind::C0, JointKind::FixedAngle),
    (8, 1, JointKind::G1, JointKind::C1),
];

fn overrides_json() -> String {
    let items: Vec<String> = OVERRIDES
        .iter()
        .map(|(path, joint, _, kind)| {
            format!(
                r#"{{"path": {path}, "joint": {joint}, "kind": "{}"}}"#,
                kind.name()
            )
        })
        .collect();
    format!("[{}]", items.join(", "))
}

/// Overriding a joint changes the fit: the imposed relation (C¹ on a C¹ input: equal tangents;
/// C¹ and G¹ elsewhere, and angle: the input's angle and ratio, so that the rest pose is the
/// drawing) holds after every pose with
/// the override and fails without it; a smooth joint made C⁰ is free (its G¹ relation, which
/// held before, no longer does). Every other junction keeps its kind.
#[test]
fn scene_junction_overrides_change_the_fit() {
    let options = JunctionOptions::default();
    let (plain, plain_outputs) = deform_scene(&scene_with_junctions("[]").unwrap(), Compat::None);
    let scene = scene_with_junctions(&overrides_json()).unwrap();
    let (drawing, outputs) = deform_scene(&scene, Compat::None);
    let diag = drawing.diagonal();
    let mut worst = Worst::default();
    for out in &outputs {
        check_junctions(&drawing, out, &options, &mut worst);
    }
    worst.assert_within("demo with junction overrides");

    // The error of relation `kind` at the joint (angle and ratio, or the tangents' difference
    // for C¹), largest over the poses.
    let error = |drawing: &Drawing, outputs: &[Vec<Point>], path: usize, joint: usize, kind| {
        outputs
            .iter()
            .map(|out| {
                let (p, o) = per_path(drawing, out).nth(path).unwrap();
                let r = relation(&p.points, o, p.closed, joint, kind, &options).unwrap();
                match kind {
                    JointKind::C1 => r.c1_error(diag),
                    _ => r.angle_error.max(r.ratio_error),
                }
            })
            .fold(0.0, f64::max)
    };
    for (path, joint, imported, imposed) in OVERRIDES {
        assert_eq!(plain.paths[path].joints[joint], imported);
        assert_eq!(drawing.paths[path].joints[joint], imposed);
        let p = &drawing.paths[path];
        if imposed != JointKind::C0
            && relation(&p.points, &p.points, p.closed, joint, imposed, &options).is_none()
        {
            // A corner of the input saved C¹ or G¹: it keeps only its position (the rest
            // pose is the drawing, checked above with the identity pose).
            assert!(matches!(imposed, JointKind::C1 | JointKind::G1));
            eprintln!("path {path} joint {joint} {imported:?} → {imposed:?}: a corner, kept C0");
            continue;
        }
        let (checked, before, after) = if imposed == JointKind::C0 {
            // Free now: the G¹ relation held and no longer does.
            let before = error(&plain, &plain_outputs, path, joint, imported);
            let after = error(&drawing, &outputs, path, joint, imported);
            assert!(before <= INVARIANT_TOLERANCE, "{path}/{joint}: {before:e}");
            (imported, before, after)
        } else {
            let before = error(&plain, &plain_outputs, path, joint, imposed);
            let after = error(&drawing, &outputs, path, joint, imposed);
            assert!(after <= INVARIANT_TOLERANCE, "{path}/{joint}: {after:e}");
            (imposed, before, after)
        };
        eprintln!("path {path} joint {joint} {imported:?} → {imposed:?}: {checked:?} relation error {before:e} before, {after:e} after");
        if (imported, imposed) == (JointKind::G1, JointKind::C1) {
            // The input is not C¹ there: C¹ keeps the input's angle and ratio (the rest pose
            // is the drawing), which is what G¹ kept already.
            assert!(before <= INVARIANT_TOLERANCE, "{path}/{joint}: {before:e}");
            continue;
        }
        let changed = if imposed == JointKind::C0 {
            after
        } else {
            before
        };
        assert!(changed > 1e-4, "{path}/{joint}: {changed:e}");
    }
}

/// The same in compatibility mode, where the authors' rows are written: the body's corner made
/// G¹ satisfies their parallel-tangent row after every pose, and did not without the override.
#[test]
fn scene_junction_override_in_compat_mode() {
    let json = r#"[{"path": 3, "joint": 6, "kind": "G1"}]"#;
    let (plain, plain_outputs) =
        deform_scene(&scene_with_junctions("[]").unwrap(), Compat::VectorSkinning);
    let (drawing, outputs) =
        deform_scene(&scene_with_junctions(json).unwrap(), Compat::VectorSkinning);
    assert_eq!(plain.paths[3].joints[6], JointKind::C0);
    assert_eq!(drawing.paths[3].joints[6], JointKind::G1);
    let diag = drawing.diagonal();
    let body = &drawing.paths[3];
    let residual = |outputs: &[Vec<Point>]| {
        outputs
            .iter()
            .map(|out| authors_residual(body, per_path(&drawing, out).nth(3).unwrap().1, diag))
            .fold(0.0, f64::max)
    };
    let (before, after) = (residual(&plain_outputs), residual(&outputs));
    eprintln!(
        "compat: body corner made G1, authors' rows residual {before:e} before, {after:e} after"
    );
    assert!(after <= INVARIANT_TOLERANCE, "{after:e}");
    assert!(before > 1e-4, "{before:e}");
}

/// Overrides naming a path or joint the drawing does not have, or an open end, are errors that
/// name the entry (`junctions[i]`) and say what is wrong; so is the kind `end`.
#[test]
fn scene_junction_override_errors_name_the_entry() {
    let setup_error = |junctions: &str, compat: Compat| -> String {
        let scene = scene_with_junctions(junctions).unwrap();
        match scene.setup(compat) {
            Ok(_) => panic!("{junctions}: accepted"),
            Err(e) => e.to_string(),
        }
    };
    let valid = r#"{"path": 3, "joint": 1, "kind": "C0"}"#;
    for (junctions, compat, expected) in [
        (
            format!(r#"[{valid}, {{"path": 99, "joint": 0, "kind": "C1"}}]"#),
            Compat::None,
            [
                "junctions[1]",
                "path 99 does not exist (the drawing has 16)",
            ],
        ),
        (
            r#"[{"path": 3, "joint": 7, "kind": "G1"}]"#.to_string(),
            Compat::None,
            ["junctions[0]", "joint 7 does not exist (path 3 has 7)"],
        ),
        (
            format!(r#"[{valid}, {valid}, {{"path": 8, "joint": 0, "kind": "G1"}}]"#),
            Compat::None,
            ["junctions[2]", "joint 0 of path 8 is an open end"],
        ),
        (
            r#"[{"path": 8, "joint": 2, "kind": "angle"}]"#.to_string(),
            Compat::None,
            ["junctions[0]", "joint 2 of path 8 is an open end"],
        ),
        // The circles and the rectangle are not read in compatibility mode: 11 paths.
        (
            r#"[{"path": 12, "joint": 0, "kind": "C1"}]"#.to_string(),
            Compat::VectorSkinning,
            [
                "junctions[0]",
                "path 12 does not exist (the drawing has 11)",
            ],
        ),
    ] {
        let message = setup_error(&junctions, compat);
        for needle in expected {
            assert!(message.contains(needle), "{junctions}: {message}");
        }
        assert!(message.contains("junctions.json"), "{message}");
    }
    // Path 12 (the pupil, an ellipse) exists in our mode.
    let scene = scene_with_junctions(r#"[{"path": 12, "joint": 0, "kind": "C0"}]"#).unwrap();
    assert_eq!(
        scene.setup(Compat::None).ok().unwrap().drawing.paths[12].joints[0],
        JointKind::C0
    );

    let message = scene_with_junctions(r#"[{"path": 3, "joint": 1, "kind": "end"}]"#)
        .err()
        .unwrap()
        .to_string();
    assert!(message.contains("junctions[0].kind"), "{message}");
    let message = scene_with_junctions(r#"[{"path": 3, "joint": 1, "kind": "C2"}]"#)
        .err()
        .unwrap()
        .to_string();
    assert!(message.contains("C2"), "{message}");
}
