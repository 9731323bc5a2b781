//! The naive baselines the paper compares its fit with (Liu, Jacobson & Gingold 2014, §5;
//! DESIGN.md §1 "Naive baselines").
//!
//! All of them start from the skinning map
//!
//! ```text
//! f(x) = Σ_i w_i(x) T_i x̄ = A(x) x̄,   A(x) = Σ_i w_i(x) T_i   (the blended transform)
//! ```
//!
//! and apply it to something other than the whole curve:
//!
//! | function | the authors' `engineType` | what is skinned |
//! |---|---|---|
//! | [`skin_control_points`] | `fourcontrols` | every control point: `c_k' = f(c_k)` |
//! | [`skin_on_curve_points`] | `twoendpoints` | on-curve points `f(q)`; an off-curve point `c` next to the on-curve point `q` takes `q`'s blended transform: `c' = A(q) c̄` |
//! | [`skin_with_jacobian`] | `jacobian` | on-curve points `f(q)`; off-curve points `c' = f(q) + J(q) (c − q)`, `J` the Jacobian of `f` |
//! | [`schneider_refit`] | — | dense samples of each path, mapped by `f` and refitted with Schneider's algorithm (the curve count changes) |
//!
//! Off-curve point `P_3j+1` belongs to on-curve point `P_3j`, `P_3j+2` to `P_3j+3` (the paper:
//! "treating each off-curve point as a vector whose origin is the adjacent interpolated
//! point"). The first three write the same layout as [`SplineRig::update`]: the chain points
//! of every path concatenated, [`Drawing::n_points`] of them (a closed path's repeated last
//! point equals its first). Since `Σ_i w_i ≡ 1` for every family here, one affine map `T` on
//! every handle gives `A ≡ T` and `J ≡` its linear part, so all three reproduce `T` exactly,
//! and the identity pose reproduces the input.
//!
//! The Jacobian of `f` at `x` is
//!
//! ```text
//! J(x) = L(A(x)) + Σ_i (T_i x̄ − f(x)) ∇w_i(x)ᵀ
//! ```
//!
//! (`L` the linear part; the `f(x)` term adds `f(x) Σ_i ∇w_iᵀ = 0` and makes a common `T`
//! exact). The gradients come from a [`WeightGradient`]: analytic for [`Shepard`]
//! ([`Shepard::eval_with_gradient`]), central differences of any [`WeightField`] with
//! [`FiniteDifferences`] (mesh weights are piecewise linear: at a mesh edge the difference
//! averages the gradients of the triangles on either side).
//!
//! [`SplineRig::update`]: crate::spline_fit::SplineRig::update

use kurbo::{Affine, Point, Vec2};

use crate::drawing::Drawing;
use crate::spline_fit::PoseError;
use crate::weights::{Shepard, WeightField};

mod schneider;
pub use schneider::{
    fit_cubics, schneider_refit, schneider_refit_same_count, schneider_refit_within, Refit,
    RefitError, RefitOptions, RefitPath, DEFAULT_REFIT_SAMPLES, DEFAULT_REFIT_TOLERANCE,
    DEFAULT_REPARAMETRISATION_ROUNDS, MAX_SPLIT_DEPTH, SAME_COUNT_ROUNDS,
};

/// The blended transform `A(p) = Σ_i w_i(p) T_i`, with `w` (length `pose.len()`) as scratch
/// for the weights (left holding `w_i(p)`).
///
/// ```
/// use kurbo::{Affine, Point};
/// use splineskin::naive::blended_transform;
/// use splineskin::weights::{Shepard, ShepardOptions};
/// let field = Shepard::new(&[Point::new(0.0, 0.0), Point::new(2.0, 0.0)], ShepardOptions::default());
/// let pose = [Affine::IDENTITY, Affine::translate((4.0, 0.0))];
/// let a = blended_transform(&field, &pose, Point::new(1.0, 0.0), &mut [0.0; 2]);
/// assert_eq!(a, Affine::translate((2.0, 0.0)));
/// ```
pub fn blended_transform(
    field: &dyn WeightField,
    pose: &[Affine],
    p: Point,
    w: &mut [f64],
) -> Affine {
    field.eval(p, w);
    blend(pose, w)
}

/// The skinning map `f(p) = Σ_i w_i(p) T_i p̄`, with `w` as scratch as in
/// [`blended_transform`].
///
/// ```
/// use kurbo::{Affine, Point};
/// use splineskin::naive::skin_point;
/// use splineskin::weights::{Shepard, ShepardOptions};
/// let field = Shepard::new(&[Point::new(0.0, 0.0), Point::new(2.0, 0.0)], ShepardOptions::default());
/// let pose = [Affine::IDENTITY, Affine::translate((4.0, 0.0))];
/// assert_eq!(skin_point(&field, &pose, Point::new(2.0, 0.0), &mut [0.0; 2]), Point::new(6.0, 0.0));
/// ```
pub fn skin_point(field: &dyn WeightField, pose: &[Affine], p: Point, w: &mut [f64]) -> Point {
    blended_transform(field, pose, p, w) * p
}

/// The skinning map's derivatives in the pose, for [`crate::drawing::carry::CarryOperator`]:
/// `f(p) = Σ_i w_i(p) T_i p̄` is linear in the pose's coefficients, with
/// `∂f/∂(a_i, b_i, c_i, d_i, e_i, f_i) = w_i(p) ((x, 0), (0, x), (y, 0), (0, y), (1, 0), (0, 1))`
/// (`T_i = [a b c d e f]` in `Affine`'s order, `p = (x, y)`). Writes them into `d[6i + k]`,
/// and `d[6h] = 0` (`f` at the zero pose); `d` has `6h + 1` entries, `w` `h` (scratch).
///
/// ```
/// use kurbo::{Affine, Point, Vec2};
/// use splineskin::naive::{skin_point, skin_point_derivatives};
/// use splineskin::weights::{Shepard, ShepardOptions};
/// let field = Shepard::new(&[Point::new(0.0, 0.0), Point::new(2.0, 0.0)], ShepardOptions::default());
/// let p = Point::new(0.5, 1.0);
/// let mut d = [Vec2::ZERO; 13];
/// skin_point_derivatives(&field, p, &mut d, &mut [0.0; 2]);
/// // Linear in the pose: Σ_j x_j d_j is the skinning map at the pose x.
/// let pose = [Affine::rotate(0.3), Affine::translate((1.0, 2.0))];
/// let x: Vec<f64> = pose.iter().flat_map(|t| t.as_coeffs()).collect();
/// let f = x.iter().zip(&d).fold(d[12], |s, (xj, dj)| s + *xj * *dj);
/// assert!((f.to_point() - skin_point(&field, &pose, p, &mut [0.0; 2])).hypot() < 1e-12);
/// ```
pub fn skin_point_derivatives(field: &dyn WeightField, p: Point, d: &mut [Vec2], w: &mut [f64]) {
    field.eval(p, w);
    for (i, &wi) in w.iter().enumerate() {
        let [x, y] = [p.x * wi, p.y * wi];
        d[6 * i..6 * i + 6].copy_from_slice(&[
            Vec2::new(x, 0.0),
            Vec2::new(0.0, x),
            Vec2::new(y, 0.0),
            Vec2::new(0.0, y),
            Vec2::new(wi, 0.0),
            Vec2::new(0.0, wi),
        ]);
    }
    d[6 * w.len()] = Vec2::ZERO;
}

/// `Σ_i w_i T_i` (coefficient-wise: affine maps form a vector space).
pub(crate) fn blend(pose: &[Affine], w: &[f64]) -> Affine {
    let mut c = [0.0; 6];
    for (t, &wi) in pose.iter().zip(w) {
        if wi == 0.0 {
            continue;
        }
        for (ck, tk) in c.iter_mut().zip(t.as_coeffs()) {
            *ck += wi * tk;
        }
    }
    Affine::new(c)
}

/// Checks that `pose` has one map per handle ([`PoseError::Transforms`] if not).
pub(crate) fn check_pose_len(pose: &[Affine], n_handles: usize) -> Result<(), PoseError> {
    if pose.len() != n_handles {
        return Err(PoseError::Transforms {
            got: pose.len(),
            expected: n_handles,
        });
    }
    Ok(())
}

/// Checks the pose length against the field and the output length against the drawing.
fn check_sizes(
    drawing: &Drawing,
    n_handles: usize,
    pose: &[Affine],
    out: &[Point],
) -> Result<(), PoseError> {
    check_pose_len(pose, n_handles)?;
    if out.len() != drawing.n_points() {
        return Err(PoseError::Output {
            got: out.len(),
            expected: drawing.n_points(),
        });
    }
    Ok(())
}

/// The authors' `fourcontrols` baseline: every control point skinned as a point,
/// `c_k' = Σ_i w_i(c_k) T_i c̄_k` (paper §5, "we apply the deformation directly to all control
/// points"; its Fig. 1).
///
/// Writes into `out` (length [`Drawing::n_points`], the layout of
/// [`crate::spline_fit::SplineRig::update`]). Errors if `pose` does not have one map per handle
/// of `field` or `out` has the wrong length.
///
/// ```
/// use kurbo::{Affine, Point};
/// use splineskin::drawing::{Drawing, JunctionOptions, Path};
/// use splineskin::naive::skin_control_points;
/// use splineskin::weights::{Shepard, ShepardOptions};
/// let pts = [(0.0, 0.0), (1.0, 1.0), (2.0, 1.0), (3.0, 0.0)].map(Point::from).to_vec();
/// let drawing = Drawing {
///     paths: vec![Path::new(pts.clone(), false, &JunctionOptions::default()).unwrap()],
///     ..Default::default()
/// };
/// let field = Shepard::new(&[Point::new(0.0, 0.0), Point::new(3.0, 0.0)], ShepardOptions::default());
/// let t = Affine::rotate(0.3).then_translate((1.0, 2.0).into());
/// let mut out = vec![Point::ZERO; drawing.n_points()];
/// skin_control_points(&drawing, &field, &[t, t], &mut out).unwrap();
/// for (p, q) in pts.iter().zip(&out) {
///     assert!((t * *p - *q).hypot() < 1e-12);
/// }
/// ```
pub fn skin_control_points(
    drawing: &Drawing,
    field: &dyn WeightField,
    pose: &[Affine],
    out: &mut [Point],
) -> Result<(), PoseError> {
    check_sizes(drawing, field.n_handles(), pose, out)?;
    let mut w = vec![0.0; pose.len()];
    for (p, o) in drawing.paths.iter().flat_map(|p| &p.points).zip(out) {
        *o = skin_point(field, pose, *p, &mut w);
    }
    Ok(())
}

/// The on-curve point an off-curve chain point belongs to: `P_3j+1 → P_3j`, `P_3j+2 → P_3j+3`
/// (an on-curve point to itself).
#[inline]
fn owner(k: usize) -> usize {
    match k % 3 {
        0 => k,
        1 => k - 1,
        _ => k + 1,
    }
}

/// The authors' `twoendpoints` baseline: on-curve points skinned, `q' = A(q) q̄`; each off-curve
/// point `c` carried by the blended transform of its on-curve neighbour `q`, `c' = A(q) c̄`
/// (paper §5: "we apply the interpolated point's transformation", treating the off-curve point
/// as a vector from `q`: `A(q) c̄ = q' + L(A(q)) (c − q)`).
///
/// Both tangents at a junction are mapped by the same linear map, so a G¹ junction stays G¹
/// with its tangent-length ratio (a fixed-angle one does not, unless `L(A(q))` is a
/// similarity). Output and errors as [`skin_control_points`].
///
/// ```
/// use kurbo::{Affine, Point};
/// use splineskin::drawing::{Drawing, JunctionOptions, Path};
/// use splineskin::naive::skin_on_curve_points;
/// use splineskin::weights::{Shepard, ShepardOptions};
/// let pts = [(0.0, 0.0), (1.0, 1.0), (2.0, 1.0), (3.0, 0.0)].map(Point::from).to_vec();
/// let drawing = Drawing {
///     paths: vec![Path::new(pts, false, &JunctionOptions::default()).unwrap()],
///     ..Default::default()
/// };
/// // Handles on the two ends: each end, and its off-curve neighbour, follows its handle.
/// let field = Shepard::new(&[Point::new(0.0, 0.0), Point::new(3.0, 0.0)], ShepardOptions::default());
/// let pose = [Affine::IDENTITY, Affine::translate((0.0, 5.0))];
/// let mut out = vec![Point::ZERO; 4];
/// skin_on_curve_points(&drawing, &field, &pose, &mut out).unwrap();
/// assert_eq!(out, [(0.0, 0.0), (1.0, 1.0), (2.0, 6.0), (3.0, 5.0)].map(Point::from));
/// ```
pub fn skin_on_curve_points(
    drawing: &Drawing,
    field: &dyn WeightField,
    pose: &[Affine],
    out: &mut [Point],
) -> Result<(), PoseError> {
    check_sizes(drawing, field.n_handles(), pose, out)?;
    let mut w = vec![0.0; pose.len()];
    carry_by_on_curve_points(drawing, out, |q| {
        let a = blended_transform(field, pose, q, &mut w);
        move |c| a * c
    });
    Ok(())
}

/// Writes every chain point of `drawing` into `out` (the layout of
/// [`crate::spline_fit::SplineRig::update`], length checked by the caller) by the map that its
/// on-curve point `q` gives: `map_at(q)` is called once per on-curve point and applied to `q`
/// and to the off-curve points it owns (`P_3j±1`, see [`owner`]).
fn carry_by_on_curve_points<F: Fn(Point) -> Point>(
    drawing: &Drawing,
    out: &mut [Point],
    mut map_at: impl FnMut(Point) -> F,
) {
    for (path, range) in drawing.paths.iter().zip(drawing.path_ranges()) {
        let n = path.points.len();
        let chunk = &mut out[range];
        for q in (0..n).step_by(3) {
            let map = map_at(path.points[q]);
            for k in q.saturating_sub(1)..(q + 2).min(n) {
                if owner(k) == q {
                    chunk[k] = map(path.points[k]);
                }
            }
        }
    }
}

/// Weight functions with gradients: what [`skin_with_jacobian`] needs.
pub trait WeightGradient: Send + Sync {
    /// Number of handles `h`.
    fn n_handles(&self) -> usize;

    /// Writes `w_i(p)` into `w` and `∇w_i(p)` into `grad` for every handle `i` (both of
    /// length [`WeightGradient::n_handles`]).
    fn eval_with_gradient(&self, p: Point, w: &mut [f64], grad: &mut [Vec2]);
}

impl WeightGradient for Shepard {
    fn n_handles(&self) -> usize {
        WeightField::n_handles(self)
    }

    /// Analytic: [`Shepard::eval_with_gradient`].
    fn eval_with_gradient(&self, p: Point, w: &mut [f64], grad: &mut [Vec2]) {
        Shepard::eval_with_gradient(self, p, w, grad);
    }
}

/// Default step of [`FiniteDifferences`], as a fraction of the drawing's bounding-box diagonal:
/// 1e-5. Central differences err by `O(step²)` from curvature and `O(ε / step)` from rounding
/// (`ε` ≈ 1e-16 relative); this step balances them near 1e-10 relative for smooth weights.
pub const DEFAULT_RELATIVE_STEP: f64 = 1e-5;

/// Gradients of any [`WeightField`] by central differences,
/// `∂w_i/∂x ≈ (w_i(x + h e_x) − w_i(x − h e_x)) / 2h` (and likewise in `y`), for families
/// without an analytic gradient (mesh weights: harmonic, biharmonic, BBW).
///
/// `step` `h` is in drawing units (see [`DEFAULT_RELATIVE_STEP`]). For piecewise linear mesh
/// weights the difference is exact inside a triangle farther than `h` from its edges, and the
/// average of the neighbouring triangles' gradients across an edge.
///
/// ```
/// use kurbo::{Point, Vec2};
/// use splineskin::naive::{FiniteDifferences, WeightGradient};
/// use splineskin::weights::{Shepard, ShepardOptions};
/// let shepard = Shepard::new(&[Point::new(0.0, 0.0), Point::new(2.0, 0.0)], ShepardOptions::default());
/// let fd = FiniteDifferences::new(&shepard, 1e-5);
/// let (mut w, mut g) = ([0.0; 2], [Vec2::ZERO; 2]);
/// fd.eval_with_gradient(Point::new(1.0, 0.0), &mut w, &mut g);
/// // Along the axis w_0(x) = (2 − x)² / (x² + (2 − x)²), so w_0'(1) = −1.
/// assert!((g[0] - Vec2::new(-1.0, 0.0)).hypot() < 1e-9);
/// ```
#[derive(Clone, Copy)]
pub struct FiniteDifferences<'a> {
    field: &'a dyn WeightField,
    step: f64,
}

impl<'a> FiniteDifferences<'a> {
    /// Central differences of `field` with step `step` (drawing units, positive).
    pub fn new(field: &'a dyn WeightField, step: f64) -> Self {
        FiniteDifferences { field, step }
    }

    /// Central differences with the step [`DEFAULT_RELATIVE_STEP`] times `drawing`'s diagonal.
    pub fn for_drawing(field: &'a dyn WeightField, drawing: &Drawing) -> Self {
        Self::new(field, DEFAULT_RELATIVE_STEP * drawing.diagonal().max(1.0))
    }
}

impl WeightGradient for FiniteDifferences<'_> {
    fn n_handles(&self) -> usize {
        self.field.n_handles()
    }

    fn eval_with_gradient(&self, p: Point, w: &mut [f64], grad: &mut [Vec2]) {
        let h = self.field.n_handles();
        self.field.eval(p, w);
        let mut plus = vec![0.0; h];
        let mut minus = vec![0.0; h];
        grad.fill(Vec2::ZERO);
        for e in [Vec2::new(self.step, 0.0), Vec2::new(0.0, self.step)] {
            self.field.eval(p + e, &mut plus);
            self.field.eval(p - e, &mut minus);
            let unit = e / self.step;
            for ((g, a), b) in grad.iter_mut().zip(&plus).zip(&minus) {
                *g += unit * ((a - b) / (2.0 * self.step));
            }
        }
    }
}

/// The image `f(q)` and the Jacobian `J(q)` (as the linear part of an [`Affine`] with no
/// translation) of the skinning map at `q`. Formula in the module doc.
///
/// ```
/// use kurbo::{Affine, Point};
/// use splineskin::naive::skinning_jacobian;
/// use splineskin::weights::{Shepard, ShepardOptions};
/// let field = Shepard::new(&[Point::new(0.0, 0.0), Point::new(2.0, 0.0)], ShepardOptions::default());
/// // Handle 1 moves right by 4: along the axis f(x) = x + 4 w_1(x), and w_1'(1) = 1
/// // (w_1(x) = x² / (x² + (2 − x)²)), so f'(1) = 5.
/// let pose = [Affine::IDENTITY, Affine::translate((4.0, 0.0))];
/// let (fq, j) = skinning_jacobian(&field, &pose, Point::new(1.0, 0.0));
/// assert_eq!(fq, Point::new(3.0, 0.0));
/// assert!((j.as_coeffs()[0] - 5.0).abs() < 1e-12);
/// ```
pub fn skinning_jacobian(field: &dyn WeightGradient, pose: &[Affine], q: Point) -> (Point, Affine) {
    let mut w = vec![0.0; pose.len()];
    let mut g = vec![Vec2::ZERO; pose.len()];
    jacobian_at(field, pose, q, &mut w, &mut g)
}

fn jacobian_at(
    field: &dyn WeightGradient,
    pose: &[Affine],
    q: Point,
    w: &mut [f64],
    g: &mut [Vec2],
) -> (Point, Affine) {
    field.eval_with_gradient(q, w, g);
    let a = blend(pose, w);
    let fq = a * q;
    let c = a.as_coeffs();
    // Columns of J: [[j0, j2], [j1, j3]] in Affine's (a, b, c, d) order.
    let mut j = [c[0], c[1], c[2], c[3]];
    for (t, gi) in pose.iter().zip(g.iter()) {
        let d = *t * q - fq;
        j[0] += d.x * gi.x;
        j[1] += d.y * gi.x;
        j[2] += d.x * gi.y;
        j[3] += d.y * gi.y;
    }
    (fq, Affine::new([j[0], j[1], j[2], j[3], 0.0, 0.0]))
}

/// The authors' `jacobian` baseline ("Interpolated Jacobian", paper §5 and Fig. 7): on-curve
/// points skinned, `q' = f(q)`; each off-curve point `c` moved as a vector from its on-curve
/// neighbour `q` by the Jacobian of the skinning map there, `c' = f(q) + J(q) (c − q)`.
///
/// `J(q)` is shared by both tangents at a junction, so G¹ junctions stay G¹ with their ratio.
/// Output and errors as [`skin_control_points`].
///
/// ```
/// use kurbo::{Affine, Point};
/// use splineskin::drawing::{Drawing, JunctionOptions, Path};
/// use splineskin::naive::skin_with_jacobian;
/// use splineskin::weights::{Shepard, ShepardOptions};
/// let pts = [(0.0, 0.0), (1.0, 1.0), (2.0, 1.0), (3.0, 0.0)].map(Point::from).to_vec();
/// let drawing = Drawing {
///     paths: vec![Path::new(pts.clone(), false, &JunctionOptions::default()).unwrap()],
///     ..Default::default()
/// };
/// let field = Shepard::new(&[Point::new(0.0, 0.0), Point::new(3.0, 0.0)], ShepardOptions::default());
/// let mut out = vec![Point::ZERO; 4];
/// skin_with_jacobian(&drawing, &field, &[Affine::IDENTITY; 2], &mut out).unwrap();
/// assert_eq!(out, pts);
/// ```
pub fn skin_with_jacobian(
    drawing: &Drawing,
    field: &dyn WeightGradient,
    pose: &[Affine],
    out: &mut [Point],
) -> Result<(), PoseError> {
    check_sizes(drawing, field.n_handles(), pose, out)?;
    let mut w = vec![0.0; pose.len()];
    let mut g = vec![Vec2::ZERO; pose.len()];
    carry_by_on_curve_points(drawing, out, |on| {
        let (fq, j) = jacobian_at(field, pose, on, &mut w, &mut g);
        move |c: Point| fq + (j * (c - on).to_point()).to_vec2()
    });
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::schneider::second_derivative;
    use super::*;
    use crate::bezier;
    use crate::drawing::JunctionOptions;
    use crate::drawing::Path;
    use crate::weights::ShepardOptions;
    use kurbo::CubicBez;
    use kurbo::ParamCurveNearest;

    fn drop_drawing() -> Drawing {
        // A closed drop (C⁰ tip, smooth elsewhere) and an open S curve.
        let drop = [
            (0.0, 0.0),
            (20.0, 10.0),
            (30.0, 30.0),
            (20.0, 40.0),
            (15.0, 45.0),
            (-15.0, 45.0),
            (-20.0, 40.0),
            (-30.0, 30.0),
            (-20.0, 10.0),
            (0.0, 0.0),
        ]
        .map(Point::from)
        .to_vec();
        let s = [(50.0, 0.0), (60.0, 20.0), (70.0, -20.0), (80.0, 0.0)]
            .map(Point::from)
            .to_vec();
        let o = JunctionOptions::default();
        Drawing {
            paths: vec![
                Path::new(drop, true, &o).unwrap(),
                Path::new(s, false, &o).unwrap(),
            ],
            ..Default::default()
        }
    }

    /// A pose of [`field`]'s three handles that bends the drawing: a turn, a shift, the identity.
    fn bend() -> [Affine; 3] {
        [
            Affine::rotate(0.4),
            Affine::translate((5.0, -3.0)),
            Affine::IDENTITY,
        ]
    }

    fn field() -> Shepard {
        Shepard::new(
            &[
                Point::new(0.0, 10.0),
                Point::new(0.0, 45.0),
                Point::new(75.0, 0.0),
            ],
            ShepardOptions::default(),
        )
    }

    #[test]
    fn second_derivative_matches_differences() {
        let c = [(0.0, 0.0), (1.0, 3.0), (4.0, -1.0), (5.0, 2.0)].map(Point::from);
        let h = 1e-5;
        for t in [0.1, 0.5, 0.9] {
            let fd = (bezier::derivative(&c, t + h) - bezier::derivative(&c, t - h)) / (2.0 * h);
            assert!((fd - second_derivative(&c, t)).hypot() < 1e-6);
        }
    }

    #[test]
    fn jacobian_matches_differences_of_the_skinning_map() {
        let f = field();
        let pose = [
            Affine::rotate(0.3),
            Affine::translate((5.0, -3.0)),
            Affine::scale_non_uniform(1.2, 0.8),
        ];
        let q = Point::new(12.0, 20.0);
        let (fq, j) = skinning_jacobian(&f, &pose, q);
        let h = 1e-5;
        let mut w = [0.0; 3];
        for (axis, e) in [Vec2::new(h, 0.0), Vec2::new(0.0, h)]
            .into_iter()
            .enumerate()
        {
            let col = (skin_point(&f, &pose, q + e, &mut w) - skin_point(&f, &pose, q - e, &mut w))
                / (2.0 * h);
            let c = j.as_coeffs();
            let want = if axis == 0 {
                Vec2::new(c[0], c[1])
            } else {
                Vec2::new(c[2], c[3])
            };
            assert!((col - want).hypot() < 1e-7, "{col:?} vs {want:?}");
        }
        assert_eq!(fq, skin_point(&f, &pose, q, &mut w));
        // Finite differences of the weights give the same Jacobian.
        let fd = FiniteDifferences::new(&f, 1e-5);
        let (_, j2) = skinning_jacobian(&fd, &pose, q);
        for (a, b) in j.as_coeffs().iter().zip(j2.as_coeffs()) {
            assert!((a - b).abs() < 1e-7);
        }
    }

    #[test]
    fn baselines_reproduce_identity_and_a_common_affine_map() {
        let d = drop_drawing();
        let f = field();
        let input = d.flat_points();
        let t = Affine::new([1.1, 0.2, -0.3, 0.9, 4.0, -7.0]);
        for (pose, map) in [([Affine::IDENTITY; 3], Affine::IDENTITY), ([t; 3], t)] {
            let mut out = vec![Point::ZERO; d.n_points()];
            for method in 0..3 {
                match method {
                    0 => skin_control_points(&d, &f, &pose, &mut out).unwrap(),
                    1 => skin_on_curve_points(&d, &f, &pose, &mut out).unwrap(),
                    _ => skin_with_jacobian(&d, &f, &pose, &mut out).unwrap(),
                }
                for (p, q) in input.iter().zip(&out) {
                    // Rounding of Σ w_i T_i with coordinates of order 100.
                    assert!(
                        (map * *p - *q).hypot() < 1e-12,
                        "method {method}: {p:?} -> {q:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn twoendpoints_and_jacobian_keep_g1_ratios() {
        let d = drop_drawing();
        let f = field();
        let pose = bend();
        let mut out = vec![Point::ZERO; d.n_points()];
        for method in 0..2 {
            if method == 0 {
                skin_on_curve_points(&d, &f, &pose, &mut out).unwrap();
            } else {
                skin_with_jacobian(&d, &f, &pose, &mut out).unwrap();
            }
            // Joint 1 of the drop (point 3) is smooth: in (2 → 3) and out (3 → 4) stay parallel.
            let a = out[3] - out[2];
            let b = out[4] - out[3];
            assert!(a.cross(b).abs() < 1e-9 * a.hypot() * b.hypot());
        }
    }

    #[test]
    fn sizes_are_checked() {
        let d = drop_drawing();
        let f = field();
        let mut out = vec![Point::ZERO; d.n_points()];
        assert_eq!(
            skin_control_points(&d, &f, &[Affine::IDENTITY; 2], &mut out),
            Err(PoseError::Transforms {
                got: 2,
                expected: 3
            })
        );
        assert_eq!(
            skin_with_jacobian(&d, &f, &[Affine::IDENTITY; 3], &mut out[1..]),
            Err(PoseError::Output {
                got: d.n_points() - 1,
                expected: d.n_points()
            })
        );
        assert!(matches!(
            schneider_refit(
                &d,
                &f,
                &[Affine::IDENTITY; 3],
                &RefitOptions::default().with_tolerance(0.0)
            ),
            Err(RefitError::Tolerance(_))
        ));
    }

    #[test]
    fn schneider_fits_within_tolerance_and_lines_with_one_curve() {
        // Collinear samples: one curve, on the line.
        let line: Vec<Point> = (0..=20)
            .map(|k| Point::new(k as f64, 2.0 * k as f64))
            .collect();
        let mut chain = vec![line[0]];
        let t = Vec2::new(1.0, 2.0).normalize();
        fit_cubics(
            &line,
            t,
            -t,
            &RefitOptions::default().with_tolerance(1e-6),
            &mut chain,
        );
        assert_eq!(chain.len(), 4, "{chain:?}");
        assert!(chain.iter().all(|p| (p.y - 2.0 * p.x).abs() < 1e-12));
        // Samples of a cubic (uniform in t, not in arc length): every sample within the
        // tolerance of the fit, more curves for a tighter tolerance.
        let c = [(0.0, 0.0), (10.0, 20.0), (30.0, 20.0), (40.0, 0.0)].map(Point::from);
        let d: Vec<Point> = (0..=40)
            .map(|k| bezier::eval(&c, k as f64 / 40.0))
            .collect();
        let t1 = (c[1] - c[0]).normalize();
        let t2 = (c[2] - c[3]).normalize();
        let mut counts = Vec::new();
        for tolerance in [1e-3, 1e-1, 1.0] {
            let mut chain = vec![d[0]];
            fit_cubics(
                &d,
                t1,
                t2,
                &RefitOptions::default().with_tolerance(tolerance),
                &mut chain,
            );
            let n = (chain.len() - 1) / 3;
            for p in &d {
                let dist = (0..n)
                    .map(|j| {
                        CubicBez::new(
                            chain[3 * j],
                            chain[3 * j + 1],
                            chain[3 * j + 2],
                            chain[3 * j + 3],
                        )
                        .nearest(*p, 1e-12)
                        .distance_sq
                    })
                    .fold(f64::INFINITY, f64::min);
                assert!(dist.sqrt() <= tolerance, "{tolerance}: {}", dist.sqrt());
            }
            counts.push(n);
        }
        assert!(counts[0] > counts[2], "{counts:?}");
        assert_eq!(counts[2], 1, "{counts:?}");
    }

    #[test]
    fn schneider_refit_keeps_corners_and_closes_loops() {
        let d = drop_drawing();
        let f = field();
        let pose = bend();
        let refit =
            schneider_refit(&d, &f, &pose, &RefitOptions::default().with_tolerance(0.05)).unwrap();
        let mut w = [0.0; 3];
        let tip = skin_point(&f, &pose, Point::ZERO, &mut w);
        let drop = &refit.paths[0];
        assert!(drop.closed);
        assert_eq!(drop.points[0], tip);
        assert_eq!(drop.points[drop.points.len() - 1], tip);
        let s = &refit.paths[1];
        assert_eq!(
            s.points[0],
            skin_point(&f, &pose, Point::new(50.0, 0.0), &mut w)
        );
    }
}
