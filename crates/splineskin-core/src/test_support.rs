//! Helpers shared by the unit tests of several modules.

use kurbo::Point;

/// The points with the given coordinates.
pub(crate) fn pts(v: &[(f64, f64)]) -> Vec<Point> {
    v.iter().map(|&p| Point::from(p)).collect()
}
