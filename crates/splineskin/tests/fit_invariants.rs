//! Invariants of the fit on generated drawings (random chains with exactly smooth, C¹, corner
//! and right-angle junctions, open and closed, some with degenerate handles):
//!
//! * the identity pose reproduces the input to 1e-9 of the bounding-box diagonal;
//! * one affine map on every handle gives exactly that map of the input (1e-9): any affine map
//!   when the drawing has C⁰, C¹ and G¹ joints, similarities when it also has fixed angles
//!   (an angle is not an affine invariant);
//! * after any pose, C⁰ junctions are closed, C¹ tangents are equal, G¹ tangents keep the
//!   input's angle (parallel) and length ratio, fixed-angle junctions keep angle and ratio
//!   (1e-9).

use kurbo::{Affine, Point, Vec2};
use proptest::prelude::*;
use splineskin::drawing::{Drawing, JointKind, JunctionOptions, Path};
use splineskin::spline_fit::{FitOptions, Measure, SplineRig};
use splineskin::weights::{Shepard, ShepardOptions};

/// Required accuracy of every invariant, relative to the drawing's diagonal (or radians).
const INVARIANT_TOLERANCE: f64 = 1e-9;

#[derive(Clone, Copy, Debug)]
enum Join {
    Smooth(f64),
    C1,
    Corner(f64),
    Right,
}

fn join_strategy() -> impl Strategy<Value = Join> {
    prop_oneof![
        (0.3f64..3.0).prop_map(Join::Smooth),
        Just(Join::C1),
        (0.5f64..2.5).prop_map(Join::Corner),
        Just(Join::Right),
    ]
}

/// A chain of `joins.len() + 1` curves starting at the origin; each join decides the first
/// handle of the next curve from the last handle of the previous one.
fn chain(lengths: &[(f64, f64, f64)], joins: &[Join], degenerate_first: bool) -> Vec<Point> {
    let mut pts = vec![Point::ZERO];
    let mut dir = Vec2::new(1.0, 0.0);
    for (j, &(len, bend, h)) in lengths.iter().enumerate() {
        let p0 = *pts.last().unwrap();
        let p1 = if j == 0 {
            if degenerate_first {
                p0
            } else {
                p0 + dir * (h * len)
            }
        } else {
            let c2 = pts[pts.len() - 2];
            let u = p0 - c2;
            let u = if u.hypot() == 0.0 { dir * len * 0.3 } else { u };
            match joins[j - 1] {
                Join::Smooth(r) => p0 + u * r,
                Join::C1 => p0 + u,
                Join::Corner(a) => p0 + rotate(u, a) * 0.8,
                Join::Right => p0 + rotate(u, std::f64::consts::FRAC_PI_2),
            }
        };
        dir = (p1 - p0).normalize();
        if !dir.is_finite() {
            dir = Vec2::new(1.0, 0.0);
        }
        let end_dir = rotate(dir, bend);
        let p3 = p1 + end_dir * len;
        let p2 = p3 - rotate(end_dir, bend) * (h * len);
        pts.extend([p1, p2, p3]);
        dir = (p3 - p2).normalize();
    }
    pts
}

fn rotate(v: Vec2, angle: f64) -> Vec2 {
    let (s, c) = angle.sin_cos();
    Vec2::new(c * v.x - s * v.y, s * v.x + c * v.y)
}

fn check_invariants(drawing: &Drawing, handles: &[Point], pose: &[Affine], measure: Measure) {
    let field = Shepard::new(handles, ShepardOptions::default());
    let options = FitOptions::default().with_measure(measure);
    let rig = SplineRig::precompute(drawing, &field, &options).unwrap();
    let input = drawing.flat_points();
    let diag = drawing.diagonal();
    let tol = INVARIANT_TOLERANCE * diag;
    let mut out = vec![Point::ZERO; rig.n_points()];

    rig.update(&vec![Affine::IDENTITY; handles.len()], &mut out)
        .unwrap();
    for (p, q) in input.iter().zip(&out) {
        assert!((*p - *q).hypot() <= tol, "identity: {p:?} -> {q:?}");
    }
    // A general affine map preserves C0, C1 and G1 with a fixed ratio (ratios of parallel
    // vectors are affine invariants) but not angles: with fixed-angle joints only similarities
    // reproduce exactly.
    let general = Affine::new([1.3, 0.4, -0.7, 0.9, 12.0, -5.0]);
    let similarity = Affine::translate((12.0, -5.0)) * Affine::rotate(0.7) * Affine::scale(1.6);
    let has_angles = drawing
        .paths
        .iter()
        .flat_map(|p| &p.joints)
        .any(|k| *k == JointKind::FixedAngle);
    for a in [similarity, general] {
        if has_angles && a == general {
            continue;
        }
        rig.update(&vec![a; handles.len()], &mut out).unwrap();
        for (p, q) in input.iter().zip(&out) {
            assert!(
                (a * *p - *q).hypot() <= 2.0 * tol,
                "affine: {:?} -> {q:?}",
                a * *p
            );
        }
    }

    rig.update(pose, &mut out).unwrap();
    let mut offset = 0;
    for path in &drawing.paths {
        let n_pts = path.points.len();
        let o = &out[offset..offset + n_pts];
        let m = n_pts - 1;
        if path.closed {
            assert_eq!(o[0], o[m], "closed path stays closed");
        }
        for (k, &kind) in path.joints.iter().enumerate() {
            let p = 3 * k;
            if matches!(kind, JointKind::End | JointKind::C0) {
                continue;
            }
            let a = if p == 0 { m - 1 } else { p - 1 };
            let b = p + 1;
            let (u, v) = (
                path.points[p] - path.points[a],
                path.points[b] - path.points[p],
            );
            let (u2, v2) = (o[p] - o[a], o[b] - o[p]);
            let scale = u2.hypot().max(v2.hypot()).max(1e-300);
            match kind {
                JointKind::C1 => assert!((u2 - v2).hypot() <= tol, "C1: {u2:?} vs {v2:?}"),
                _ => {
                    // Angle and ratio kept: v2 = (|v|/|u|) R(angle(u, v)) u2.
                    let angle = u.cross(v).atan2(u.dot(v));
                    let want = rotate(u2, angle) * (v.hypot() / u.hypot());
                    assert!(
                        (want - v2).hypot() <= INVARIANT_TOLERANCE * scale,
                        "{kind:?}: {want:?} vs {v2:?}"
                    );
                    if kind == JointKind::G1 {
                        assert!(u2.cross(v2).abs() <= INVARIANT_TOLERANCE * scale * scale);
                    }
                }
            }
        }
        offset += n_pts;
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn fit_invariants_hold_on_generated_chains(
        segs in prop::collection::vec((1.0f64..40.0, -1.2f64..1.2, 0.1f64..0.5), 1..7),
        joins in prop::collection::vec(join_strategy(), 6),
        degenerate_first in any::<bool>(),
        handles in prop::collection::vec((-60.0f64..120.0, -60.0f64..120.0), 1..5),
        pose in prop::collection::vec((-0.6f64..0.6, 0.6f64..1.5, -30.0f64..30.0, -30.0f64..30.0), 5),
        arc_length in any::<bool>(),
    ) {
        let pts = chain(&segs, &joins, degenerate_first);
        let path = Path::new(pts, false, &JunctionOptions::default()).unwrap();
        let drawing = Drawing { paths: vec![path], ..Default::default() };
        let handles: Vec<Point> = handles.into_iter().map(Point::from).collect();
        let pose: Vec<Affine> = pose
            .iter()
            .take(handles.len())
            .map(|&(r, s, x, y)| Affine::translate((x, y)) * Affine::rotate(r) * Affine::scale(s))
            .collect();
        let measure = if arc_length { Measure::ArcLength } else { Measure::LengthWeighted };
        check_invariants(&drawing, &handles, &pose, measure);
    }
}

#[test]
fn fit_invariants_closed_smooth_path() {
    // A closed chain of four curves through the unit circle's quadrant points, smooth everywhere
    // (tangent handles of length k = 0.5523), plus a square with right-angle corners.
    let k = 0.552_284_749_830_793_4 * 50.0;
    let r = 50.0;
    let circle: Vec<Point> = [
        (r, 0.0),
        (r, k),
        (k, r),
        (0.0, r),
        (-k, r),
        (-r, k),
        (-r, 0.0),
        (-r, -k),
        (-k, -r),
        (0.0, -r),
        (k, -r),
        (r, -k),
        (r, 0.0),
    ]
    .map(Point::from)
    .to_vec();
    let square: Vec<Point> = [
        (100.0, 0.0),
        (120.0, 0.0),
        (140.0, 0.0),
        (160.0, 0.0),
        (160.0, 20.0),
        (160.0, 40.0),
        (160.0, 60.0),
        (140.0, 60.0),
        (120.0, 60.0),
        (100.0, 60.0),
        (100.0, 40.0),
        (100.0, 20.0),
        (100.0, 0.0),
    ]
    .map(Point::from)
    .to_vec();
    let o = JunctionOptions::default();
    let drawing = Drawing {
        paths: vec![
            Path::new(circle, true, &o).unwrap(),
            Path::new(square, true, &o).unwrap(),
        ],
        ..Default::default()
    };
    assert!(drawing.paths[0].joints.iter().all(|k| *k == JointKind::C1));
    assert!(drawing.paths[1]
        .joints
        .iter()
        .all(|k| *k == JointKind::FixedAngle));
    let handles = [
        Point::new(-40.0, 0.0),
        Point::new(130.0, 30.0),
        Point::new(40.0, 60.0),
    ];
    let pose = [
        Affine::rotate(0.3),
        Affine::translate((20.0, -10.0)) * Affine::scale(1.4),
        Affine::IDENTITY,
    ];
    for measure in [Measure::LengthWeighted, Measure::ArcLength] {
        check_invariants(&drawing, &handles, &pose, measure);
    }
}
