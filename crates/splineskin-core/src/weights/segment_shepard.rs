//! Shepard weights of point handles **and bones**: the distance to a bone is the distance to
//! its segment (DESIGN.md §2, "bones: distance to segment").
//!
//! ```text
//! w_i(x) = d_i(x)^(−a) / Σ_k d_k(x)^(−a),   d_i = ‖x − p_i‖ (point),  min_{s∈[0,1]} ‖x − (p₀ + s(p₁ − p₀))‖ (bone)
//! ```
//!
//! evaluated as [`crate::weights::Shepard`] does, `w_i = (d_min/d_i)^a / Σ_k (d_min/d_k)^a`;
//! on a handle (`d_i = 0`, anywhere along a bone) the limit is used: weight 1 there, 0 for the
//! others. Scenes without bones use [`crate::weights::Shepard`] itself.

use kurbo::Point;

use super::shepard::weights_from_squared_distances;
use super::{ShepardOptions, WeightField};
use crate::domain::polygon::segment_distance;

/// Shepard weights of point handles followed by bones (segments), in that order.
///
/// ```
/// use kurbo::Point;
/// use splineskin_core::weights::SegmentShepard;
/// use splineskin_core::weights::{ShepardOptions, WeightField};
/// let bone = [Point::new(0.0, 0.0), Point::new(4.0, 0.0)];
/// let w = SegmentShepard::new(&[Point::new(2.0, 2.0)], &[bone], ShepardOptions::default());
/// let mut out = [0.0; 2];
/// w.eval(Point::new(3.0, 0.0), &mut out); // on the bone
/// assert_eq!(out, [0.0, 1.0]);
/// w.eval(Point::new(2.0, 1.0), &mut out); // 1 from both
/// assert_eq!(out, [0.5, 0.5]);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct SegmentShepard {
    points: Vec<Point>,
    segments: Vec<[Point; 2]>,
    options: ShepardOptions,
}

impl SegmentShepard {
    /// Weights of point handles at `points` and bones `segments` (the caller validates that
    /// everything is finite and the exponent positive; see the `splineskin` crate's `scene` module).
    pub fn new(points: &[Point], segments: &[[Point; 2]], options: ShepardOptions) -> Self {
        SegmentShepard {
            points: points.to_vec(),
            segments: segments.to_vec(),
            options,
        }
    }
}

impl WeightField for SegmentShepard {
    fn n_handles(&self) -> usize {
        self.points.len() + self.segments.len()
    }

    fn eval(&self, p: Point, out: &mut [f64]) {
        debug_assert_eq!(out.len(), self.n_handles());
        let distances2 =
            self.points
                .iter()
                .map(|h| (p - *h).hypot2())
                .chain(self.segments.iter().map(|s| {
                    let d = segment_distance(p, s[0], s[1]).0;
                    d * d
                }));
        for (d2, o) in distances2.zip(out.iter_mut()) {
            *o = d2;
        }
        weights_from_squared_distances(out, &self.options);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::weights::Shepard;

    #[test]
    fn segment_shepard_matches_shepard_on_points() {
        let pts = [
            Point::new(0.0, 0.0),
            Point::new(3.0, 1.0),
            Point::new(-2.0, 5.0),
        ];
        let a = Shepard::new(&pts, ShepardOptions::default().with_exponent(3.0));
        let b = SegmentShepard::new(&pts, &[], ShepardOptions::default().with_exponent(3.0));
        let (mut wa, mut wb) = ([0.0; 3], [0.0; 3]);
        for q in [Point::new(1.0, 1.0), Point::new(-7.0, 0.5), pts[1]] {
            a.eval(q, &mut wa);
            b.eval(q, &mut wb);
            assert_eq!(wa, wb);
        }
    }

    #[test]
    fn segment_shepard_uses_distance_to_the_segment() {
        // A point handle at (0, 3); a bone from (−1, 0) to (1, 0). At (5, 0) the bone is 4
        // away (its end (1, 0)), the point √34: w ∝ (1/16, 1/34).
        let w = SegmentShepard::new(
            &[Point::new(0.0, 3.0)],
            &[[Point::new(-1.0, 0.0), Point::new(1.0, 0.0)]],
            ShepardOptions::default(),
        );
        let mut out = [0.0; 2];
        w.eval(Point::new(5.0, 0.0), &mut out);
        let (a, b) = (1.0 / 34.0, 1.0 / 16.0);
        assert!((out[0] - a / (a + b)).abs() < 1e-15, "{out:?}");
        assert!((out[1] - b / (a + b)).abs() < 1e-15, "{out:?}");
        // Above the bone's middle at height 1: the bone is 1 away, the point 2.
        w.eval(Point::new(0.0, 1.0), &mut out);
        assert!((out[1] - 0.8).abs() < 1e-15, "{out:?}");
    }
}
