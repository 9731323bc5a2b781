//! The cubic Bernstein basis, its Gram matrix, and Gauss–Legendre quadrature.
//!
//! A cubic Bézier curve with control points `c0..c3` is
//!
//! ```text
//! B(t) = Σ_k c_k b_k(t),   b(t) = [(1-t)³, 3t(1-t)², 3t²(1-t), t³],   t ∈ [0, 1]
//! ```
//!
//! (Liu, Jacobson & Gingold 2014, §3, where it is written `M t̄`). This module knows nothing of
//! weights, drawings or SVG.

use kurbo::{CubicBez, Point, Vec2};

/// The four cubic Bernstein basis functions at `t`: `[(1-t)³, 3t(1-t)², 3t²(1-t), t³]`.
///
/// ```
/// let b = splineskin_core::bezier::bernstein(0.5);
/// assert_eq!(b, [0.125, 0.375, 0.375, 0.125]);
/// ```
#[inline]
pub fn bernstein(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    [s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t]
}

/// The derivatives `b'(t)` of the cubic Bernstein basis functions.
///
/// ```
/// let d = splineskin_core::bezier::bernstein_derivative(0.0);
/// assert_eq!(d, [-3.0, 3.0, 0.0, 0.0]);
/// ```
#[inline]
pub fn bernstein_derivative(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    [
        -3.0 * s * s,
        3.0 * s * s - 6.0 * t * s,
        6.0 * t * s - 3.0 * t * t,
        3.0 * t * t,
    ]
}

/// The exact Gram matrix `Â = ∫₀¹ b(t) b(t)ᵀ dt` of the cubic Bernstein basis.
///
/// `Â_kl = binom(3,k)·binom(3,l) / (7·binom(6,k+l))` (DESIGN.md §1). The fit itself integrates
/// `Â` with the same quadrature as the weighted matrices (see [`crate::spline_fit`]); this
/// closed form is what that quadrature must reproduce when it is exact for degree 6.
///
/// ```
/// let a = splineskin_core::bezier::bernstein_gram();
/// assert!((a[0][0] - 1.0 / 7.0).abs() < 1e-15);
/// assert!((a[0][3] - 1.0 / 140.0).abs() < 1e-15);
/// ```
pub fn bernstein_gram() -> [[f64; 4]; 4] {
    const BINOM3: [f64; 4] = [1.0, 3.0, 3.0, 1.0];
    const BINOM6: [f64; 7] = [1.0, 6.0, 15.0, 20.0, 15.0, 6.0, 1.0];
    let mut a = [[0.0; 4]; 4];
    for (k, row) in a.iter_mut().enumerate() {
        for (l, v) in row.iter_mut().enumerate() {
            *v = BINOM3[k] * BINOM3[l] / (7.0 * BINOM6[k + l]);
        }
    }
    a
}

/// Evaluates the curve with control points `c` at `t` (de Casteljau-free Bernstein sum).
#[inline]
pub fn eval(c: &[Point; 4], t: f64) -> Point {
    combine(&bernstein(t), c).to_point()
}

/// The derivative `B'(t)` of the curve with control points `c`.
#[inline]
pub fn derivative(c: &[Point; 4], t: f64) -> Vec2 {
    combine(&bernstein_derivative(t), c)
}

/// `Σ_k b_k c_k`: the control points combined with the coefficients `b` (a basis at some
/// `t`), summed left to right.
#[inline]
fn combine(b: &[f64; 4], c: &[Point; 4]) -> Vec2 {
    Vec2::new(
        b[0] * c[0].x + b[1] * c[1].x + b[2] * c[2].x + b[3] * c[3].x,
        b[0] * c[0].y + b[1] * c[1].y + b[2] * c[2].y + b[3] * c[3].y,
    )
}

/// The control points of a kurbo cubic as an array.
#[inline]
pub fn control_points(c: &CubicBez) -> [Point; 4] {
    [c.p0, c.p1, c.p2, c.p3]
}

/// Nodes and weights of the `n`-point Gauss–Legendre rule on `[0, 1]`.
///
/// Exact for polynomials of degree `2n − 1`; four nodes integrate `b bᵀ` (degree 6) exactly.
/// Nodes are the roots of the Legendre polynomial `P_n`, found by Newton's method from the
/// Tricomi initial guess (Abramowitz & Stegun 25.4.29); they are returned in increasing order.
///
/// ```
/// let (t, w) = splineskin_core::bezier::gauss_legendre(3);
/// // ∫₀¹ t⁵ dt = 1/6, exact for 3 nodes.
/// let i: f64 = t.iter().zip(&w).map(|(t, w)| w * t.powi(5)).sum();
/// assert!((i - 1.0 / 6.0).abs() < 1e-15);
/// ```
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    assert!(n >= 1, "a Gauss–Legendre rule needs at least one node");
    let mut nodes = vec![0.0; n];
    let mut weights = vec![0.0; n];
    let nf = n as f64;
    for i in 0..n.div_ceil(2) {
        // Initial guess for the i-th root of P_n on [-1, 1] (descending order).
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (nf + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            // Legendre recurrence: (k+1) P_{k+1} = (2k+1) x P_k − k P_{k−1}.
            let (mut p0, mut p1) = (1.0, x);
            for k in 1..n {
                let kf = k as f64;
                let p2 = ((2.0 * kf + 1.0) * x * p1 - kf * p0) / (kf + 1.0);
                p0 = p1;
                p1 = p2;
            }
            let pn = if n == 1 { x } else { p1 };
            let pn1 = if n == 1 { 1.0 } else { p0 };
            dp = nf * (x * pn - pn1) / (x * x - 1.0);
            if n == 1 {
                dp = 1.0;
            }
            let dx = pn / dp;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        let w = 2.0 / ((1.0 - x * x) * dp * dp);
        // Map from [-1, 1] to [0, 1].
        nodes[n - 1 - i] = 0.5 * (1.0 + x);
        nodes[i] = 0.5 * (1.0 - x);
        weights[n - 1 - i] = 0.5 * w;
        weights[i] = 0.5 * w;
    }
    (nodes, weights)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Inverse of `Â` in closed form (DESIGN.md §1).
    const GRAM_INVERSE: [[f64; 4]; 4] = [
        [16.0, -24.0, 16.0, -4.0],
        [-24.0, 208.0 / 3.0, -172.0 / 3.0, 16.0],
        [16.0, -172.0 / 3.0, 208.0 / 3.0, -24.0],
        [-4.0, 16.0, -24.0, 16.0],
    ];

    #[test]
    fn bernstein_partition_of_unity() {
        for i in 0..=20 {
            let t = i as f64 / 20.0;
            let s: f64 = bernstein(t).iter().sum();
            assert!((s - 1.0).abs() < 1e-15);
            let d: f64 = bernstein_derivative(t).iter().sum();
            assert!(d.abs() < 1e-14);
        }
    }

    #[test]
    fn bernstein_gram_times_inverse_is_identity() {
        let a = bernstein_gram();
        for i in 0..4 {
            for j in 0..4 {
                let v: f64 = (0..4).map(|k| a[i][k] * GRAM_INVERSE[k][j]).sum();
                let want = if i == j { 1.0 } else { 0.0 };
                assert!((v - want).abs() < 1e-13, "({i},{j}) = {v}");
            }
        }
    }

    #[test]
    fn gauss_legendre_four_nodes_reproduce_gram() {
        let (t, w) = gauss_legendre(4);
        let exact = bernstein_gram();
        for k in 0..4 {
            for l in 0..4 {
                let v: f64 = t
                    .iter()
                    .zip(&w)
                    .map(|(&t, &w)| w * bernstein(t)[k] * bernstein(t)[l])
                    .sum();
                assert!((v - exact[k][l]).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn gauss_legendre_exact_to_degree_2n_minus_1() {
        for n in 1..=24 {
            let (t, w) = gauss_legendre(n);
            assert!(t.windows(2).all(|p| p[0] < p[1]));
            for deg in 0..(2 * n) {
                let v: f64 = t.iter().zip(&w).map(|(t, w)| w * t.powi(deg as i32)).sum();
                let want = 1.0 / (deg as f64 + 1.0);
                assert!((v - want).abs() < 1e-14, "n={n} deg={deg}: {v} vs {want}");
            }
        }
    }

    #[test]
    fn eval_and_derivative_match_kurbo() {
        use kurbo::ParamCurve;
        use kurbo::ParamCurveDeriv;
        let c = CubicBez::new((0.0, 0.0), (1.0, 3.0), (4.0, -1.0), (5.0, 2.0));
        let cp = control_points(&c);
        for i in 0..=10 {
            let t = i as f64 / 10.0;
            assert!((eval(&cp, t) - c.eval(t)).hypot() < 1e-13);
            assert!((derivative(&cp, t) - c.deriv().eval(t).to_vec2()).hypot() < 1e-12);
        }
    }
}
