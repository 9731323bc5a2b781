//! Helpers shared by the unit tests of several modules.

use kurbo::Point;

/// The points with the given coordinates.
pub(crate) fn pts(v: &[(f64, f64)]) -> Vec<Point> {
    v.iter().map(|&p| Point::from(p)).collect()
}

/// Two open curves (points 0–3 and 3–6) meeting C¹ at point 3: equal, collinear tangents.
pub(crate) const SMOOTH_C1: [(f64, f64); 7] = [
    (0., 0.),
    (1., 1.),
    (2., 0.),
    (3., 0.),
    (4., 0.),
    (5., 1.),
    (6., 0.),
];

/// Two open curves (points 0–3 and 3–6) meeting G¹ at point 3 with tangent lengths 1 and 2:
/// smooth, but not strictly C¹.
pub(crate) const SMOOTH_RATIO_2: [(f64, f64); 7] = [
    (0., 0.),
    (1., 1.),
    (2., 0.),
    (3., 0.),
    (5., 0.),
    (6., 1.),
    (7., 0.),
];

/// Two open curves whose handles at the junction lie on it (point 2 on 3, point 4 on 3): the
/// junction's directions come from points 1 and 5, which meet it G¹.
pub(crate) const STACKED_HANDLES: [(f64, f64); 7] = [
    (0., 0.),
    (1., 0.),
    (3., 0.),
    (3., 0.),
    (3., 0.),
    (6., 0.),
    (7., 1.),
];

/// A closed chain of two curves (the last point is the first), smooth everywhere: C¹ at
/// both junctions.
pub(crate) const CLOSED_TWO_CURVES: [(f64, f64); 7] = [
    (1., 0.),
    (1., 1.),
    (-1., 1.),
    (-1., 0.),
    (-1., -1.),
    (1., -1.),
    (1., 0.),
];
