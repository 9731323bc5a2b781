//! Mean value coordinates of a cage polygon (DESIGN.md §2): Floater 2003, "Mean value
//! coordinates" (CAGD 20(1)), for convex polygons; Hormann & Floater 2006, "Mean value
//! coordinates for arbitrary planar polygons" (ACM TOG 25(4)), for any simple polygon and any
//! point of the plane, inside or outside.
//!
//! For the cage vertices `v_0 … v_{n−1}` (indices mod `n`) and a point `x`,
//!
//! ```text
//! s_i = v_i − x,   r_i = ‖s_i‖,   A_i = s_i × s_{i+1},   D_i = s_i · s_{i+1}
//! t_i = tan(α_i / 2)   (α_i the signed angle at x from s_i to s_{i+1}, of the sign of A_i)
//!     = (r_i r_{i+1} − D_i) / A_i  =  A_i / (r_i r_{i+1} + D_i)
//! w̃_i = (t_{i−1} + t_i) / r_i,      w_i = w̃_i / Σ_k w̃_k
//! ```
//!
//! Hormann & Floater use `A_i` for half the cross product (a triangle's area); here it is the
//! whole cross product, and `t_i` has no factor 2. The two forms of `t_i` are equal; each edge
//! uses the one without cancellation: the first when `D_i < 0` (`α_i` beyond ±90°, where
//! `r_i r_{i+1} + D_i` cancels — near the edge itself), the second when `D_i ≥ 0` (small angles,
//! where `r_i r_{i+1} − D_i` cancels — far from the edge; it also gives `t_i = 0` on the edge's
//! line beyond its ends without a special case). With signed angles the sum `Σ_k w̃_k` does not
//! vanish off the polygon (Hormann & Floater 2006 show the coordinates are well defined for
//! any simple polygon), so the weights are defined in the whole plane, outside the cage
//! included.
//!
//! Properties (tested in `tests/weights_cage.rs`): partition of unity `Σ w_i = 1`, linear
//! precision `Σ w_i v_i = x`, Lagrange `w_i(v_k) = δ_ik` at the vertices, linear along the edges
//! (`1 − s`, `s` at the point `v_i + s (v_{i+1} − v_i)`), positive inside a convex cage.
//!
//! **Smoothness.** The weights are smooth (C^∞) everywhere except at the cage's vertices, where
//! they are only C⁰ — across the edges too: near edge `i` only `t_i` is singular, and
//! multiplying `w̃_j` and `Σ_k w̃_k` by `A_i` turns both into smooth functions
//! (`A_i t_i = r_i r_{i+1} − D_i`) with a denominator `(r_i r_{i+1} − D_i)(1/r_i + 1/r_{i+1}) > 0`
//! on the edge. So [`WeightField::kinks`] reports where a curve passes through a cage vertex,
//! not where it crosses an edge. A curve passing *near* a vertex (but not within
//! [`COINCIDENT_RELATIVE`] of the scale) sees weights that vary on the scale of its distance to
//! the vertex; that is not reported, and quadrature integrates it to the accuracy of its rule.
//!
//! Special cases, by the formula's limits: at a vertex (`r_i ≤` [`VERTEX_SNAP_RELATIVE`] × the
//! cage's diameter) the Lagrange value; on an edge (`D_i < 0` and `|A_i| ≤`
//! [`EDGE_SNAP_SINE`] `· r_i r_{i+1}`, within about `1e-16` edge lengths of it) the linear
//! interpolation `w_i = r_{i+1} / (r_i + r_{i+1})`, `w_{i+1} = r_i / (r_i + r_{i+1})`.
//!
//! Accuracy: to rounding inside and near the cage (measured: partition of unity and linear
//! precision to 4e-15 at points up to a cage size outside it); far outside, `Σ_k w̃_k` is a
//! difference of terms that nearly cancel (the signed angles sum to zero), and the relative
//! error grows like the distance `d` over the cage's size (measured about `3e-16 d`). `A_i` is
//! computed as `s_i × e_i` (`e_i = v_{i+1} − v_i`), equal to `s_i × s_{i+1}` but without that
//! product's cancellation far away, which would make the error grow like `d²`.

use kurbo::{Point, Rect, Vec2};

use super::{WeightField, WeightsError};
use crate::domain::crossings::cubic_segment_crossings;
use crate::domain::locate::merge_kinks;
use crate::domain::polygon::check_cage;
use crate::domain::{DomainError, COINCIDENT_RELATIVE};

/// A point closer to a cage vertex than this fraction of the cage's diameter takes the vertex's
/// Lagrange weights: `f64::EPSILON` (≈ 2.2e-16). The exact weights differ from those by a
/// relative `O(r_i / diameter)`, below rounding; the snap keeps `1 / r_i` from overflowing.
pub const VERTEX_SNAP_RELATIVE: f64 = f64::EPSILON;

/// A point whose view of an edge subtends an angle with `|sin α_i| ≤` this value and
/// `cos α_i < 0` lies on the edge (its distance to the edge is at most a quarter of this value
/// times the edge's length) and takes the edge's linear interpolation: `f64::EPSILON`. Below
/// it `t_i` is no longer resolved in double precision (`A_i` is rounding noise).
pub const EDGE_SNAP_SINE: f64 = f64::EPSILON;

/// Mean value coordinates of a cage: one handle per cage vertex, `w_i(x)` for every point `x`
/// of the plane (see the module documentation for the formula and its sources).
///
/// ```
/// use kurbo::Point;
/// use splineskin_core::weights::{MeanValue, WeightField};
/// let square = [(0., 0.), (2., 0.), (2., 2.), (0., 2.)].map(Point::from);
/// let mvc = MeanValue::new(&square)?;
/// assert_eq!(mvc.n_handles(), 4);
/// let mut w = [0.0; 4];
/// // At the centre all four weights are equal.
/// mvc.eval(Point::new(1.0, 1.0), &mut w);
/// assert!(w.iter().all(|&wi| (wi - 0.25).abs() < 1e-15));
/// // On the bottom edge: linear between its two vertices.
/// mvc.eval(Point::new(0.5, 0.0), &mut w);
/// assert_eq!(w, [0.75, 0.25, 0.0, 0.0]);
/// // Outside, linear precision still holds: Σ w_i v_i = x.
/// let x = Point::new(3.0, -1.0);
/// mvc.eval(x, &mut w);
/// let sum = square.iter().zip(&w).fold(Point::ZERO, |acc, (v, wi)| acc + v.to_vec2() * *wi);
/// assert!((sum - x).hypot() < 1e-14);
/// // Not smooth only at the vertices: the line y = x through vertex (0, 0) at t = ½ has a
/// // kink there; the line y = 1 crosses two edges and has none.
/// let mut kinks = Vec::new();
/// mvc.kinks(&[-1., -1. / 3., 1. / 3., 1.].map(|x| Point::new(x, x)), &mut kinks);
/// assert_eq!(kinks.len(), 1);
/// assert!((kinks[0] - 0.5).abs() < 1e-14);
/// kinks.clear();
/// mvc.kinks(&[-1., 0., 2., 3.].map(|x| Point::new(x, 1.0)), &mut kinks);
/// assert!(kinks.is_empty());
/// # Ok::<(), splineskin_core::weights::WeightsError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct MeanValue {
    vertices: Vec<Point>,
    /// `e_i = v_{i+1} − v_i`.
    edges: Vec<Vec2>,
    /// Diagonal of the cage's bounding box (drawing units).
    diameter: f64,
    /// Vertex snap distance: [`VERTEX_SNAP_RELATIVE`] × `diameter`.
    snap: f64,
}

impl MeanValue {
    /// Mean value coordinates of the cage `cage`: a simple counter-clockwise polygon of at
    /// least 3 vertices, closed implicitly (a last vertex repeating the first is dropped, as
    /// [`crate::domain::DomainOptions::cage`] does, so handle `i` is the same cage vertex in
    /// both).
    ///
    /// Errors with [`WeightsError::Cage`] holding the same [`DomainError`] variant that
    /// [`crate::domain::Domain::build`] gives for that cage: a non-finite vertex
    /// ([`DomainError::CageNonFinite`]), fewer than 3 vertices
    /// ([`DomainError::CageTooFewVertices`]), a zero-length edge (shorter than
    /// [`COINCIDENT_RELATIVE`] × the cage's bounding-box diagonal;
    /// [`DomainError::CageDegenerateEdge`]), edges that cross or touch
    /// ([`DomainError::CageSelfIntersecting`]), or a clockwise order
    /// ([`DomainError::CageClockwise`]).
    ///
    /// ```
    /// use kurbo::Point;
    /// use splineskin_core::domain::DomainError;
    /// use splineskin_core::weights::{MeanValue, WeightsError};
    /// let clockwise = [(0., 0.), (0., 1.), (1., 1.), (1., 0.)].map(Point::from);
    /// assert!(matches!(
    ///     MeanValue::new(&clockwise),
    ///     Err(WeightsError::Cage(DomainError::CageClockwise { .. }))
    /// ));
    /// ```
    pub fn new(cage: &[Point]) -> Result<MeanValue, WeightsError> {
        let vertices = checked_cage(cage).map_err(WeightsError::Cage)?;
        let diameter = bounding_diagonal(&vertices);
        let n = vertices.len();
        let edges = (0..n)
            .map(|i| vertices[(i + 1) % n] - vertices[i])
            .collect();
        Ok(MeanValue {
            snap: VERTEX_SNAP_RELATIVE * diameter,
            diameter,
            vertices,
            edges,
        })
    }

    /// The cage's vertices (without a repeated closing vertex): handle `i` is `vertices()[i]`.
    pub fn vertices(&self) -> &[Point] {
        &self.vertices
    }
}

/// The cage without a repeated closing vertex, checked by the rules of
/// [`crate::domain::DomainOptions::cage`].
fn checked_cage(cage: &[Point]) -> Result<Vec<Point>, DomainError> {
    let mut c = cage.to_vec();
    if c.len() > 1 && c.first() == c.last() {
        c.pop();
    }
    if let Some(vertex) = c.iter().position(|p| !(p.x.is_finite() && p.y.is_finite())) {
        return Err(DomainError::CageNonFinite { vertex });
    }
    if c.len() < 3 {
        return Err(DomainError::CageTooFewVertices {
            n_vertices: c.len(),
        });
    }
    check_cage(&c, COINCIDENT_RELATIVE * bounding_diagonal(&c))?;
    Ok(c)
}

/// The bounding box of `points` (not empty).
fn bounds(points: &[Point]) -> Rect {
    points
        .iter()
        .fold(Rect::from_points(points[0], points[0]), |r, &p| {
            r.union_pt(p)
        })
}

/// Diagonal of the bounding box of `points` (not empty).
pub(super) fn bounding_diagonal(points: &[Point]) -> f64 {
    let r = bounds(points);
    r.width().hypot(r.height())
}

/// `t_i = tan(α_i / 2)` from `A_i`, `D_i` and `r_i r_{i+1}` by the form without cancellation
/// (module documentation). Requires `r_i r_{i+1} > 0` and, when `D_i < 0`, `A_i ≠ 0`.
#[inline]
fn half_angle_tan(cross: f64, dot: f64, rr: f64) -> f64 {
    if dot >= 0.0 {
        cross / (rr + dot)
    } else {
        (rr - dot) / cross
    }
}

impl WeightField for MeanValue {
    fn n_handles(&self) -> usize {
        self.vertices.len()
    }

    /// The mean value coordinates at `p` (NaN if `p` is not finite). Allocates nothing:
    /// `out` holds the distances `r_i` until they are replaced by the weights.
    fn eval(&self, p: Point, out: &mut [f64]) {
        let v = &self.vertices;
        let n = v.len();
        debug_assert_eq!(out.len(), n);
        // Pass 1: distances, and the Lagrange case at a vertex.
        for (o, &vi) in out.iter_mut().zip(v) {
            *o = (vi - p).hypot();
        }
        if let Some(k) = out.iter().position(|&r| r <= self.snap) {
            out.fill(0.0);
            out[k] = 1.0;
            return;
        }
        // Edge i runs from v_i to v_{i+1}; `t_of(i, r_i, r_{i+1})` is its t_i, or `None` when
        // p lies on it.
        let t_of = |i: usize, ri: f64, rj: f64| -> Option<f64> {
            let (si, sj) = (v[i] - p, v[(i + 1) % n] - p);
            // A_i = s_i × s_{i+1} = s_i × e_i: without the cancellation of two long, nearly
            // parallel vectors far from the cage.
            let cross = si.cross(self.edges[i]);
            let (dot, rr) = (si.dot(sj), ri * rj);
            if dot < 0.0 && cross.abs() <= EDGE_SNAP_SINE * rr {
                None
            } else {
                Some(half_angle_tan(cross, dot, rr))
            }
        };
        let on_edge = |out: &mut [f64], i: usize, ri: f64, rj: f64| {
            out.fill(0.0);
            out[i] = rj / (ri + rj);
            out[(i + 1) % n] = ri / (ri + rj);
        };
        // Pass 2: w̃_i = (t_{i−1} + t_i) / r_i in place; r_0 is kept for the last edge.
        let (r0, r_last) = (out[0], out[n - 1]);
        let Some(t_last) = t_of(n - 1, r_last, r0) else {
            return on_edge(out, n - 1, r_last, r0);
        };
        let mut t_prev = t_last;
        let mut sum = 0.0;
        for i in 0..n {
            let ri = out[i];
            let ti = if i + 1 < n {
                let rj = out[i + 1];
                match t_of(i, ri, rj) {
                    Some(t) => t,
                    None => return on_edge(out, i, ri, rj),
                }
            } else {
                t_last
            };
            let w = (t_prev + ti) / ri;
            out[i] = w;
            sum += w;
            t_prev = ti;
        }
        for o in out.iter_mut() {
            *o /= sum;
        }
    }

    /// The parameters where the cubic passes through a cage vertex (the only places where mean
    /// value coordinates are not smooth; module documentation), ascending. Candidates are the
    /// cubic's crossings of the two edges meeting at the vertex, found exactly on the cubic
    /// ([`crate::domain::crossings`]); a crossing counts when the curve point lies within
    /// [`COINCIDENT_RELATIVE`] × the larger of the cage's and the curve's control box
    /// diagonals of the vertex. Crossings closer than
    /// [`KINK_MERGE`](crate::domain::locate::KINK_MERGE) are one kink (a curve
    /// through a vertex crosses both of its edges there).
    fn kinks(&self, curve: &[Point; 4], out: &mut Vec<f64>) {
        let start = out.len();
        let hull = bounds(curve);
        let tolerance = COINCIDENT_RELATIVE * self.diameter.max(hull.width().hypot(hull.height()));
        if !tolerance.is_finite() {
            return;
        }
        let hull = hull.inflate(tolerance, tolerance);
        let n = self.vertices.len();
        for i in 0..n {
            let (a, b) = (self.vertices[i], self.vertices[(i + 1) % n]);
            // The curve lies in its control points' hull: only vertices in it can be hit.
            if !(hull.contains(a) || hull.contains(b)) {
                continue;
            }
            // This edge's crossings, appended, then filtered in place.
            let mark = out.len();
            cubic_segment_crossings(curve, a, b, out);
            let mut keep = mark;
            for k in mark..out.len() {
                let p = crate::bezier::eval(curve, out[k]);
                if (p - a).hypot() <= tolerance || (p - b).hypot() <= tolerance {
                    out[keep] = out[k];
                    keep += 1;
                }
            }
            out.truncate(keep);
        }
        merge_kinks(out, start);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::test_support::pts;

    /// Floater's formula as written, with the angles from `atan2` (an independent route to the
    /// same weights, valid off the polygon).
    fn by_angles(cage: &[Point], x: Point) -> Vec<f64> {
        let n = cage.len();
        let s: Vec<_> = cage.iter().map(|&v| v - x).collect();
        let alpha: Vec<f64> = (0..n)
            .map(|i| {
                let (a, b) = (s[i], s[(i + 1) % n]);
                a.cross(b).atan2(a.dot(b))
            })
            .collect();
        let raw: Vec<f64> = (0..n)
            .map(|i| ((alpha[(i + n - 1) % n] / 2.0).tan() + (alpha[i] / 2.0).tan()) / s[i].hypot())
            .collect();
        let sum: f64 = raw.iter().sum();
        raw.iter().map(|w| w / sum).collect()
    }

    #[test]
    fn mvc_matches_floaters_angle_formula() {
        // A non-convex hexagon; points inside, outside and on an edge's line beyond its ends.
        let cage = pts(&[(0., 0.), (4., 0.), (4., 2.), (2., 2.), (2., 4.), (0., 4.)]);
        let mvc = MeanValue::new(&cage).unwrap();
        let mut w = [0.0; 6];
        for x in [
            (1.0, 1.0),
            (3.0, 3.0),
            (-1.0, 5.0),
            (3.5, 1.9),
            (6.0, 0.0),
            (2.0, 7.0),
        ] {
            let x = Point::from(x);
            mvc.eval(x, &mut w);
            let reference = by_angles(&cage, x);
            for i in 0..6 {
                // Both are rounding-accurate at these points, well away from the cage edges.
                assert!(
                    (w[i] - reference[i]).abs() < 1e-13,
                    "{x:?} {i}: {w:?} {reference:?}"
                );
            }
        }
    }

    #[test]
    fn mvc_half_angle_tan_forms_agree() {
        for deg in [
            -179.0, -120.0, -90.0, -30.0, -1e-6, 1e-6, 45.0, 90.0, 150.0, 179.9,
        ] {
            let a: f64 = f64::to_radians(deg);
            let (r, rj) = (1.3, 0.7);
            let (cross, dot) = (r * rj * a.sin(), r * rj * a.cos());
            let t = half_angle_tan(cross, dot, r * rj);
            assert!(
                (t - (a / 2.0).tan()).abs() <= 1e-13 * (a / 2.0).tan().abs().max(1.0),
                "{deg}"
            );
        }
    }

    #[test]
    fn mvc_snaps_next_to_vertices_and_edges() {
        let cage = pts(&[(0., 0.), (1., 0.), (1., 1.), (0., 1.)]);
        let mvc = MeanValue::new(&cage).unwrap();
        let mut w = [0.0; 4];
        // 1e-300 from a vertex: 1/r_i would overflow without the snap.
        mvc.eval(Point::new(1.0, 1e-300), &mut w);
        assert_eq!(w, [0.0, 1.0, 0.0, 0.0]);
        // 1e-300 inside the left edge: A_i is subnormal, t_i would overflow.
        mvc.eval(Point::new(1e-300, 0.25), &mut w);
        assert_eq!(w, [0.75, 0.0, 0.0, 0.25]);
        // Just beyond the snap: the formula, already the edge's interpolation to rounding.
        mvc.eval(Point::new(1e-12, 0.25), &mut w);
        let expected = [0.75, 0.0, 0.0, 0.25];
        for i in 0..4 {
            assert!((w[i] - expected[i]).abs() < 1e-11, "{w:?}");
        }
        assert!(
            w[1] > 0.0 && w[2] > 0.0,
            "off the edge, all weights positive: {w:?}"
        );
    }

    #[test]
    fn mvc_drops_a_repeated_closing_vertex() {
        let open = pts(&[(0., 0.), (1., 0.), (0., 1.)]);
        let mut closed = open.clone();
        closed.push(open[0]);
        let mvc = MeanValue::new(&closed).unwrap();
        assert_eq!(mvc.vertices(), &open[..]);
        assert_eq!(mvc.n_handles(), 3);
    }
}
