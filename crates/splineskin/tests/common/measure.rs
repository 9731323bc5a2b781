//! Distances and sizes the tests measure their tolerances with (both crates' tests read this
//! file: `#[path]` modules where the rest of `common` is not needed).
#![allow(dead_code)]

use kurbo::{Point, Rect};
use splineskin::drawing::{Drawing, JointKind};

/// The largest distance between corresponding points of `a` and `b`, which must have the same
/// length.
pub fn max_distance(a: &[Point], b: &[Point]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(p, q)| (*p - *q).hypot())
        .fold(0.0, f64::max)
}

/// The diagonal of the bounding box of `points` (at least one).
pub fn diagonal(points: &[Point]) -> f64 {
    let r = points
        .iter()
        .fold(Rect::from_points(points[0], points[0]), |r, &p| {
            r.union_pt(p)
        });
    r.width().hypot(r.height())
}

/// How many joints of `drawing`, over all its paths, are of `kind`.
pub fn joint_count(drawing: &Drawing, kind: JointKind) -> usize {
    drawing
        .paths
        .iter()
        .flat_map(|p| &p.joints)
        .filter(|&&k| k == kind)
        .count()
}

/// Checks the two exact reproductions of a rig whose weights sum to one everywhere
/// (DESIGN.md §1): the identity on every one of its `n_handles` handles gives `drawing` back,
/// and one affine map `a` on every handle gives `drawing` mapped by `a`, both within 1e-9 of
/// the drawing's diagonal. Prints the identity's error, relative to the diagonal, under `what`.
pub fn assert_affine_reproduction(
    rig: &splineskin::spline_fit::SplineRig,
    drawing: &Drawing,
    n_handles: usize,
    a: kurbo::Affine,
    what: &str,
) {
    let diag = drawing.diagonal();
    let input = drawing.flat_points();
    let mut out = vec![Point::ZERO; rig.n_points()];
    rig.update(&vec![kurbo::Affine::IDENTITY; n_handles], &mut out)
        .unwrap();
    let worst = max_distance(&out, &input);
    eprintln!(
        "{what}: identity pose reproduced to {:e} of the diagonal",
        worst / diag
    );
    assert!(worst < 1e-9 * diag, "{worst}");
    rig.update(&vec![a; n_handles], &mut out).unwrap();
    let mapped: Vec<Point> = input.iter().map(|&q| a * q).collect();
    let worst = max_distance(&out, &mapped);
    assert!(worst < 1e-9 * diag, "{worst}");
}
