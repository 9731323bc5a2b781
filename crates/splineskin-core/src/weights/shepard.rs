//! Shepard (inverse-distance) weights.
//!
//! ```text
//! w_i(x) = ‖x − p_i‖^(−a) / Σ_k ‖x − p_k‖^(−a)
//! ```
//!
//! with `p_i` the handle positions and `a` the exponent (2 in the paper, §5, and in the
//! authors' code). At a handle the limit is used: weight 1 for that handle, 0 for the others.
//! Evaluated as `w_i = (d_min/d_i)^a / Σ_k (d_min/d_k)^a`, which neither overflows near a
//! handle nor underflows far away.
//!
//! The gradient ([`Shepard::eval_with_gradient`], for the Jacobian baseline of
//! `splineskin::naive`) follows from `u_i = d_i^(−a)`, `∇u_i = u_i g_i` with
//! `g_i = −a (x − p_i) / d_i²`:
//!
//! ```text
//! ∇w_i(x) = w_i (g_i − Σ_k w_k g_k)
//! ```
//!
//! which, like the weights, involves only ratios and needs no `d^(−a)` itself.

use kurbo::{Point, Vec2};

use super::WeightField;

/// Default Shepard exponent `a`: 2 (`1/d²`), as in the paper.
pub const DEFAULT_EXPONENT: f64 = 2.0;

/// Options of [`Shepard`] weights.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct ShepardOptions {
    /// The exponent `a` of `‖x − p_i‖^(−a)`; must be positive and finite.
    /// Default: [`DEFAULT_EXPONENT`].
    pub exponent: f64,
    /// A point whose squared distance to a handle is below this value takes weight 1 at the
    /// nearest such handle (and 0 elsewhere), in squared drawing units. Default: 0 (only an exact
    /// hit). The paper authors' code uses `1e-8`; compatibility mode sets that.
    pub snap_distance_squared: f64,
}

impl Default for ShepardOptions {
    fn default() -> Self {
        ShepardOptions {
            exponent: DEFAULT_EXPONENT,
            snap_distance_squared: 0.0,
        }
    }
}

impl ShepardOptions {
    /// Sets [`ShepardOptions::exponent`].
    pub fn with_exponent(mut self, exponent: f64) -> Self {
        self.exponent = exponent;
        self
    }
    /// Sets [`ShepardOptions::snap_distance_squared`].
    pub fn with_snap_distance_squared(mut self, d2: f64) -> Self {
        self.snap_distance_squared = d2;
        self
    }
}

/// Shepard weights of a set of point handles.
///
/// ```
/// use kurbo::Point;
/// use splineskin_core::weights::{Shepard, ShepardOptions, WeightField};
/// let w = Shepard::new(&[Point::new(0.0, 0.0), Point::new(2.0, 0.0)], ShepardOptions::default());
/// let mut out = [0.0; 2];
/// w.eval(Point::new(1.0, 0.0), &mut out);
/// assert_eq!(out, [0.5, 0.5]);
/// w.eval(Point::new(2.0, 0.0), &mut out);
/// assert_eq!(out, [0.0, 1.0]);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Shepard {
    positions: Vec<Point>,
    options: ShepardOptions,
}

impl Shepard {
    /// Shepard weights for handles at `positions` (the caller validates that they are finite and
    /// that the exponent is positive; see `splineskin::scene`).
    pub fn new(positions: &[Point], options: ShepardOptions) -> Shepard {
        Shepard {
            positions: positions.to_vec(),
            options,
        }
    }

    /// The handle positions.
    pub fn positions(&self) -> &[Point] {
        &self.positions
    }

    /// Writes `w_i(p)` into `w` and the gradient `∇w_i(p)` into `grad` for every handle `i`
    /// (both of length [`WeightField::n_handles`]); the weights are those of
    /// [`WeightField::eval`], bit for bit.
    ///
    /// Formula in the module doc. Where the weights snap to a handle (an exact hit, or within
    /// [`ShepardOptions::snap_distance_squared`]) the gradient is written as zero: the limit at
    /// the handle for exponents `a > 1` (there `w_i = 1 − O(d^a)`); for `a ≤ 1` Shepard
    /// weights have no gradient at a handle and zero is a convention.
    ///
    /// ```
    /// use kurbo::{Point, Vec2};
    /// use splineskin_core::weights::{Shepard, ShepardOptions};
    /// let w = Shepard::new(&[Point::new(0.0, 0.0), Point::new(2.0, 0.0)], ShepardOptions::default());
    /// let (mut v, mut g) = ([0.0; 2], [Vec2::ZERO; 2]);
    /// w.eval_with_gradient(Point::new(1.0, 0.0), &mut v, &mut g);
    /// // Along the axis w_0(x) = (2 − x)² / (x² + (2 − x)²): w_0(1) = 1/2, w_0'(1) = −1.
    /// assert_eq!(v, [0.5, 0.5]);
    /// assert!((g[0] - Vec2::new(-1.0, 0.0)).hypot() < 1e-15);
    /// assert!((g[0] + g[1]).hypot() < 1e-15);
    /// ```
    pub fn eval_with_gradient(&self, p: Point, w: &mut [f64], grad: &mut [Vec2]) {
        debug_assert_eq!(grad.len(), self.positions.len());
        self.eval(p, w);
        let snapped = self
            .positions
            .iter()
            .map(|h| (p - *h).hypot2())
            .fold(f64::INFINITY, f64::min);
        if snapped <= self.options.snap_distance_squared || snapped == 0.0 {
            grad.fill(Vec2::ZERO);
            return;
        }
        let a = self.options.exponent;
        let mut mean = Vec2::ZERO;
        for ((h, g), &wi) in self.positions.iter().zip(grad.iter_mut()).zip(w.iter()) {
            let d = p - *h;
            *g = d * (-a / d.hypot2());
            mean += *g * wi;
        }
        for (g, &wi) in grad.iter_mut().zip(w.iter()) {
            *g = (*g - mean) * wi;
        }
    }
}

impl WeightField for Shepard {
    fn n_handles(&self) -> usize {
        self.positions.len()
    }

    fn eval(&self, p: Point, out: &mut [f64]) {
        debug_assert_eq!(out.len(), self.positions.len());
        for (h, o) in self.positions.iter().zip(out.iter_mut()) {
            *o = (p - *h).hypot2();
        }
        weights_from_squared_distances(out, &self.options);
    }
}

/// Turns the squared distances `d_i²` in `out` into the normalised Shepard weights
/// `w_i = (d_min/d_i)^a / Σ_k (d_min/d_k)^a` (the module's formula, scaled by the smallest
/// distance so no power overflows), or, when the smallest `d²` is zero or within
/// [`ShepardOptions::snap_distance_squared`], into 1 for the nearest handle and 0 for the
/// others. Shared by [`Shepard`] and [`super::SegmentShepard`], which differ only in the
/// distance.
pub fn weights_from_squared_distances(out: &mut [f64], options: &ShepardOptions) {
    let mut nearest = 0;
    let mut d2_min = f64::INFINITY;
    for (i, &d2) in out.iter().enumerate() {
        if d2 < d2_min {
            d2_min = d2;
            nearest = i;
        }
    }
    if d2_min <= options.snap_distance_squared || d2_min == 0.0 {
        out.fill(0.0);
        if let Some(o) = out.get_mut(nearest) {
            *o = 1.0;
        }
        return;
    }
    let half_a = 0.5 * options.exponent;
    let mut sum = 0.0;
    for o in out.iter_mut() {
        let r = d2_min / *o;
        *o = if half_a == 1.0 { r } else { r.powf(half_a) };
        sum += *o;
    }
    for o in out.iter_mut() {
        *o /= sum;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three handles in general position.
    const THREE_HANDLES: [Point; 3] = [
        Point::new(0.0, 0.0),
        Point::new(3.0, 1.0),
        Point::new(-1.0, 4.0),
    ];

    #[test]
    fn shepard_sums_to_one_and_matches_closed_form() {
        let hs = THREE_HANDLES;
        let w = Shepard::new(&hs, ShepardOptions::default().with_exponent(3.0));
        let x = Point::new(0.7, 0.2);
        let mut out = [0.0; 3];
        w.eval(x, &mut out);
        let raw: Vec<f64> = hs.iter().map(|h| (x - *h).hypot().powf(-3.0)).collect();
        let s: f64 = raw.iter().sum();
        for i in 0..3 {
            assert!((out[i] - raw[i] / s).abs() < 1e-15);
        }
        assert!((out.iter().sum::<f64>() - 1.0).abs() < 1e-15);
    }

    #[test]
    fn shepard_snaps_within_distance() {
        let hs = [Point::new(0.0, 0.0), Point::new(1.0, 0.0)];
        let w = Shepard::new(
            &hs,
            ShepardOptions::default().with_snap_distance_squared(1e-8),
        );
        let mut out = [0.0; 2];
        w.eval(Point::new(1.0 + 5e-5, 0.0), &mut out);
        assert_eq!(out, [0.0, 1.0]);
        let w = Shepard::new(&hs, ShepardOptions::default());
        w.eval(Point::new(1.0 + 5e-5, 0.0), &mut out);
        assert!(out[0] > 0.0 && out[0] < 1e-8);
    }

    #[test]
    fn shepard_gradient_matches_central_differences() {
        let hs = THREE_HANDLES;
        // Central differences with step 1e-5 are accurate to about 1e-9 here (third
        // derivatives of order 1, rounding 1e-16 / 1e-5).
        const STEP: f64 = 1e-5;
        const AGREEMENT: f64 = 1e-8;
        for a in [1.0, 2.0, 3.5] {
            let w = Shepard::new(&hs, ShepardOptions::default().with_exponent(a));
            let x = Point::new(0.7, 0.2);
            let (mut v, mut g) = ([0.0; 3], [Vec2::ZERO; 3]);
            w.eval_with_gradient(x, &mut v, &mut g);
            let mut plain = [0.0; 3];
            w.eval(x, &mut plain);
            assert_eq!(v, plain);
            let (mut wp, mut wm) = ([0.0; 3], [0.0; 3]);
            for (axis, e) in [Vec2::new(STEP, 0.0), Vec2::new(0.0, STEP)]
                .iter()
                .enumerate()
            {
                w.eval(x + *e, &mut wp);
                w.eval(x - *e, &mut wm);
                for i in 0..3 {
                    let fd = (wp[i] - wm[i]) / (2.0 * STEP);
                    let an = if axis == 0 { g[i].x } else { g[i].y };
                    assert!((fd - an).abs() < AGREEMENT, "a={a} i={i}: {fd} vs {an}");
                }
            }
        }
    }

    #[test]
    fn shepard_gradient_is_zero_at_a_handle() {
        let hs = [Point::new(0.0, 0.0), Point::new(3.0, 1.0)];
        let w = Shepard::new(&hs, ShepardOptions::default());
        let (mut v, mut g) = ([0.0; 2], [Vec2::new(1.0, 1.0); 2]);
        w.eval_with_gradient(hs[1], &mut v, &mut g);
        assert_eq!(v, [0.0, 1.0]);
        assert_eq!(g, [Vec2::ZERO; 2]);
    }

    #[test]
    fn shepard_far_away_does_not_underflow() {
        let hs = [Point::new(0.0, 0.0), Point::new(1.0, 0.0)];
        let w = Shepard::new(&hs, ShepardOptions::default().with_exponent(40.0));
        let mut out = [0.0; 2];
        w.eval(Point::new(1e12, 0.0), &mut out);
        assert!(out.iter().all(|v| v.is_finite()));
        assert!((out.iter().sum::<f64>() - 1.0).abs() < 1e-15);
    }
}
