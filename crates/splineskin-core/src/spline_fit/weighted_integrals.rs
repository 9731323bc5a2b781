//! The weighted integrals `Ŵ_ij` of the fit (Liu et al. 2014 §4, eq. of the fit of one curve;
//! DESIGN.md §1 "Fit of one curve"): for handle `i` and curve `j` with homogeneous control
//! matrix `C̄_j` (3×4, rows `x`, `y`, `1`) and Bernstein basis `b(t)`,
//!
//! ```text
//! Ŵ_ij = C̄_j M_ij,    M_ij = ∫ w_i(B_j(t)) b(t) b(t)ᵀ dμ_j  ≈  Σ_q ω_q w_i(B_j(t_q)) b(t_q) b(t_q)ᵀ
//! ```
//!
//! (3×4), so that the fit of curve `j` solves `C'_j Â_j = Σ_i T_i Ŵ_ij` with
//! `Â_j = ∫ b bᵀ dμ_j`. `M_ij` ([`CurveNodes::weighted_grams`]) uses the nodes `t_q` and node
//! weights `ω_q` of [`super::quadrature`], the same rule as `Â_j`
//! ([`CurveNodes::gram`]): when `Σ_i w_i ≡ 1`, `Σ_i M_ij = Â_j` and `Σ_i Ŵ_ij = C̄_j Â_j` to
//! rounding, so identity transforms reproduce the curve (DESIGN.md §1, "Consistency").
//! [`weighted_integral`] multiplies by `C̄_j`; the fit's system (`system.rs`) puts
//! `Σ_i T_i Ŵ_ij` into its right-hand sides column by column.

use kurbo::Point;

use super::quadrature::CurveNodes;
use crate::bezier;

impl CurveNodes<'_> {
    /// `M_i = Σ_q ω_q w_i(q) b(t_q) b(t_q)ᵀ` for every handle `i`, written to `out`
    /// (one 4×4 matrix per handle): the weighted Gram matrices, `Ŵ_i = C̄ M_i`
    /// ([`weighted_integral`]).
    pub fn weighted_grams(&self, out: &mut Vec<[[f64; 4]; 4]>) {
        let n_handles = self.n_handles;
        out.clear();
        out.resize(n_handles, [[0.0; 4]; 4]);
        // The matrices are symmetric: accumulate the upper triangle (10 of 16 entries), then
        // mirror it.
        for (q, (&t, &w)) in self.t.iter().zip(self.omega).enumerate() {
            let b = bezier::bernstein(t);
            let mut bb = [0.0; 10];
            let mut e = 0;
            for k in 0..4 {
                for l in k..4 {
                    bb[e] = w * b[k] * b[l];
                    e += 1;
                }
            }
            for (i, m) in out.iter_mut().enumerate() {
                let wi = self.weights[q * n_handles + i];
                if wi == 0.0 {
                    continue;
                }
                let mut e = 0;
                for k in 0..4 {
                    for l in k..4 {
                        m[k][l] += wi * bb[e];
                        e += 1;
                    }
                }
            }
        }
        for m in out.iter_mut() {
            for k in 0..4 {
                for l in 0..k {
                    m[k][l] = m[l][k];
                }
            }
        }
    }
}

/// `Ŵ = C̄ M` for one curve and one handle: `C̄` the homogeneous control matrix of the curve
/// with control points `c` (rows `(x_k)`, `(y_k)`, `(1)`), `M` its weighted Gram matrix
/// ([`CurveNodes::weighted_grams`]):
///
/// ```text
/// Ŵ[s][l] = Σ_k C̄[s][k] M[k][l],   C̄[0][k] = x_k,  C̄[1][k] = y_k,  C̄[2][k] = 1
/// ```
///
/// ```
/// use kurbo::Point;
/// use splineskin_core::spline_fit::weighted_integrals::weighted_integral;
/// let c = [(0.0, 0.0), (1.0, 2.0), (3.0, 2.0), (4.0, 0.0)].map(Point::from);
/// // M = ½ I gives Ŵ = ½ C̄.
/// let m = std::array::from_fn(|k| std::array::from_fn(|l| if k == l { 0.5 } else { 0.0 }));
/// let w = weighted_integral(&c, &m);
/// assert_eq!(w[0], [0.0, 0.5, 1.5, 2.0]);
/// assert_eq!(w[1], [0.0, 1.0, 1.0, 0.0]);
/// assert_eq!(w[2], [0.5; 4]);
/// ```
pub fn weighted_integral(c: &[Point; 4], m: &[[f64; 4]; 4]) -> [[f64; 4]; 3] {
    let mut w = [[0.0; 4]; 3];
    for l in 0..4 {
        for (k, ck) in c.iter().enumerate() {
            w[0][l] += ck.x * m[k][l];
            w[1][l] += ck.y * m[k][l];
            w[2][l] += m[k][l];
        }
    }
    w
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two handles with weights `w_0 = 0.2 + 0.6 t`, `w_1 = 0.8 − 0.6 t` at five nodes (a
    /// partition of unity): `Σ_i Ŵ_i = C̄ Â` (the consistency the fit relies on).
    #[test]
    fn weighted_integrals_sum_to_control_matrix_times_gram() {
        let t = [0.05, 0.25, 0.5, 0.75, 0.95];
        let omega = [0.1, 0.25, 0.3, 0.25, 0.1];
        let weights: Vec<f64> = t
            .iter()
            .flat_map(|&t| [0.2 + 0.6 * t, 0.8 - 0.6 * t])
            .collect();
        let nodes = CurveNodes {
            t: &t,
            omega: &omega,
            weights: &weights,
            n_handles: 2,
        };
        let c = [(0.0, 0.0), (1.0, 2.0), (3.0, 2.5), (4.0, -1.0)].map(Point::from);
        let a = nodes.gram();
        let mut m = Vec::new();
        nodes.weighted_grams(&mut m);
        let w: Vec<_> = m.iter().map(|m| weighted_integral(&c, m)).collect();
        let expected = weighted_integral(&c, &a);
        for s in 0..3 {
            for l in 0..4 {
                let sum = w[0][s][l] + w[1][s][l];
                let scale = expected[s][l].abs().max(a[0][0]);
                assert!(
                    (sum - expected[s][l]).abs() <= 1e-14 * scale,
                    "{s} {l}: {sum}"
                );
            }
        }
        // The row of ones is the column sums of M: Ŵ[2][l] = Σ_k M[k][l].
        for l in 0..4 {
            let column: f64 = (0..4).map(|k| m[1][k][l]).sum();
            assert_eq!(w[1][2][l], column);
        }
    }
}
