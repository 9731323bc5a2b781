//! The symmetric ARAP (SARAP) energy, with its gradient and a positive semidefinite
//! approximation of its Hessian per triangle (for Newton's method).
//!
//! ```text
//! E_SARAP(u) = Σ_t A_t ψ(J_t),   ψ = (Σ − 1)² + (1/σ − 1)²   (σ > 0),   ψ = +∞ (σ ≤ 0)
//! ```
//!
//! with `Σ ≥ σ` the singular values of the deformation gradient `J_t` (Poranne & Lipman 2016,
//! Eq. (11); DESIGN.md §4). Stretching the larger singular value by `k` costs what shrinking
//! the smaller by `1/k` does, and a triangle that collapses (`σ → 0`) costs `+∞`, so the
//! energy is a barrier against flips.
//!
//! **Derivatives.** In the split `Q = ‖(E, H)‖`, `R = ‖(F, G)‖` of
//! [`super::deformation_gradient`] (`Σ = Q + R`, `σ = Q − R`), with `h(s) = (1/s − 1)²`,
//! `h'(s) = 2s⁻² − 2s⁻³`, `h''(s) = 6s⁻⁴ − 4s⁻³`:
//!
//! ```text
//! ψ_Q = 2(Σ − 1) + h'(σ),   ψ_R = 2(Σ − 1) − h'(σ)
//! ∇_(E,H) ψ = ψ_Q (E, H)/Q,   ∇_(F,G) ψ = ψ_R (F, G)/R
//! ```
//!
//! The Hessian in `(E, H, F, G)` has four eigenpairs (the planar case of Smith, Goes & Kim
//! 2019, *Analytic eigensystems for isotropic distortion energies*): `4` along
//! `(n_Q + n_R)/√2` (stretching `Σ`), `2h''(σ)` along `(n_Q − n_R)/√2` (stretching `σ`), the
//! twist `ψ_Q/Q` along `t_Q` and the flip `ψ_R/R` along `t_R`, where `n_Q = (E, H, 0, 0)/Q`,
//! `t_Q = (−H, E, 0, 0)/Q`, `n_R = (0, 0, F, G)/R`, `t_R = (0, 0, −G, F)/R`. Clamping the
//! negative eigenvalues to zero gives the projected Hessian Newton's method needs (Teran et al.
//! 2005). `J_t` is linear in the triangle's six coordinates, so the vertex gradient and
//! Hessian are `A_t Wᵀ ∇ψ` and `A_t Wᵀ (∇²ψ)₊ W` with `W = ∂(E, H, F, G)/∂u`.
//!
//! **Not smooth where `Σ = σ ≠ 1`.** ψ is not a symmetric function of the singular values, so
//! it has a convex crease along the conformal maps `J = sR` with `s ≠ 1` (`R = 0`): there
//! `ψ_R → 2(s − 1)(1 − s⁻³) ≥ 0` while `R → 0`, the flip eigenvalue `ψ_R/R` grows without
//! bound and the gradient has no limit. At the rest pose (`s = 1`) it is smooth. Newton steps
//! stay valid descent directions (the projected Hessian is positive semidefinite wherever it
//! is evaluated); the solver's stopping test is therefore on the step, not on the gradient.
//! At exactly `R = 0` the flip direction is taken as `(0, 0, 0, 1)` with curvature `ψ_RR`
//! (exact when `s = 1`) and `∇_(F,G) ψ = 0` (the least-norm subgradient).

use kurbo::{Point, Vec2};

use super::deformation_gradient::{ConformalSplit, TriangleGradients};
use super::error::DefOpError;
use super::handles::check_position_count;
use super::orientation::double_area;
use splineskin_core::mesh::TriMesh;

/// `E_SARAP` of `mesh` deformed to `positions` (one per vertex; the rest pose is
/// `mesh.vertices`): `+∞` when a triangle is flipped or collapsed. In squared drawing units.
///
/// ```
/// use kurbo::Point;
/// use splineskin_defop::{arap_energy, sarap_energy};
/// use splineskin_core::mesh::TriMesh;
/// let v = vec![Point::new(0., 0.), Point::new(1., 0.), Point::new(0., 1.)];
/// let mesh = TriMesh::new(v.clone(), vec![[0, 1, 2]])?;
/// // Stretch x by 2 (Σ = 2, σ = 1) or shrink y by ½ (Σ = 1, σ = ½): the same SARAP cost,
/// // A (2 − 1)² = ½, where ARAP charges the shrink only a quarter of that.
/// let stretched: Vec<Point> = v.iter().map(|&p| Point::new(2. * p.x, p.y)).collect();
/// let shrunk: Vec<Point> = v.iter().map(|&p| Point::new(p.x, 0.5 * p.y)).collect();
/// assert!((sarap_energy(&mesh, &stretched)? - 0.5).abs() < 1e-15);
/// assert!((sarap_energy(&mesh, &shrunk)? - 0.5).abs() < 1e-15);
/// assert!((arap_energy(&mesh, &shrunk)? - 0.125).abs() < 1e-15);
/// // Flipped: infinite.
/// let flipped: Vec<Point> = v.iter().map(|&p| Point::new(p.x, -p.y)).collect();
/// assert_eq!(sarap_energy(&mesh, &flipped)?, f64::INFINITY);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn sarap_energy(mesh: &TriMesh, positions: &[Point]) -> Result<f64, DefOpError> {
    mesh.check()?;
    check_position_count(positions, mesh.n_vertices())?;
    Ok(sarap_energy_of(&TriangleGradients::new(mesh), positions))
}

/// `E_SARAP` from precomputed rest data (`+∞` on a flip).
pub(crate) fn sarap_energy_of(rest: &TriangleGradients, u: &[Point]) -> f64 {
    let mut energy = 0.0;
    for t in 0..rest.n_triangles() {
        // The signed area decides orientation exactly as the line search's root finder does;
        // σ > 0 follows from it up to rounding, which `density` checks as well.
        let double = double_area(rest.triangles[t], u);
        if double.is_nan() || double <= 0.0 {
            return f64::INFINITY;
        }
        energy += rest.area[t] * density(&rest.jacobian(t, u).split());
    }
    energy
}

/// ψ of one triangle (`+∞` when `σ ≤ 0`).
fn density(s: &ConformalSplit) -> f64 {
    let sigma = s.q - s.r;
    if sigma.is_nan() || sigma <= 0.0 {
        return f64::INFINITY;
    }
    (s.q + s.r - 1.0).powi(2) + (1.0 / sigma - 1.0).powi(2)
}

/// One triangle's gradient and Hessian of `A_t ψ` over its six coordinates
/// `(u_0x, u_0y, u_1x, u_1y, u_2x, u_2y)`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct TriangleDerivatives {
    pub gradient: [f64; 6],
    /// The projected Hessian (negative eigenvalues clamped to 0): symmetric positive
    /// semidefinite.
    pub hessian: [[f64; 6]; 6],
    /// The Hessian itself (every eigenvalue kept; at `R = 0` the convention of the module
    /// documentation).
    pub exact_hessian: [[f64; 6]; 6],
}

/// [`TriangleDerivatives`] of triangle `t` at `u`, or `None` when it is flipped or collapsed.
pub(crate) fn triangle_derivatives(
    rest: &TriangleGradients,
    t: usize,
    u: &[Point],
) -> Option<TriangleDerivatives> {
    let s = rest.jacobian(t, u).split();
    let (sigma_max, sigma) = (s.q + s.r, s.q - s.r);
    if sigma.is_nan() || sigma <= 0.0 {
        return None;
    }
    let area = rest.area[t];
    let h1 = 2.0 / (sigma * sigma) - 2.0 / (sigma * sigma * sigma);
    let h2 = 6.0 / sigma.powi(4) - 4.0 / sigma.powi(3);
    let psi_q = 2.0 * (sigma_max - 1.0) + h1;
    let psi_r = 2.0 * (sigma_max - 1.0) - h1;
    // Unit directions in (E, H) and (F, G); σ > 0 implies Q > R ≥ 0.
    let n_q = [s.e / s.q, s.h / s.q];
    let t_q = [-n_q[1], n_q[0]];
    let (n_r, t_r, flip) = if s.r > 0.0 {
        let n = [s.f / s.r, s.g / s.r];
        ([n[0], n[1]], [-n[1], n[0]], psi_r / s.r)
    } else {
        ([1.0, 0.0], [0.0, 1.0], 2.0 + h2)
    };
    let grad_r = if s.r > 0.0 { psi_r } else { 0.0 };
    // ∇ψ in (E, H, F, G).
    let grad_ehfg = [
        psi_q * n_q[0],
        psi_q * n_q[1],
        grad_r * n_r[0],
        grad_r * n_r[1],
    ];
    let half_sqrt2 = std::f64::consts::FRAC_1_SQRT_2;
    let modes: [(f64, [f64; 4]); 4] = [
        (
            4.0,
            [
                half_sqrt2 * n_q[0],
                half_sqrt2 * n_q[1],
                half_sqrt2 * n_r[0],
                half_sqrt2 * n_r[1],
            ],
        ),
        (
            2.0 * h2,
            [
                half_sqrt2 * n_q[0],
                half_sqrt2 * n_q[1],
                -half_sqrt2 * n_r[0],
                -half_sqrt2 * n_r[1],
            ],
        ),
        (psi_q / s.q, [t_q[0], t_q[1], 0.0, 0.0]),
        (flip, [0.0, 0.0, t_r[0], t_r[1]]),
    ];
    let w = ehfg_rows(&rest.gradient[t]);
    let mut gradient = [0.0; 6];
    for (m, row) in w.iter().enumerate() {
        for k in 0..6 {
            gradient[k] += area * grad_ehfg[m] * row[k];
        }
    }
    let mut hessian = [[0.0; 6]; 6];
    let mut exact_hessian = [[0.0; 6]; 6];
    for (lambda, v) in modes {
        // Wᵀ v: the mode as a motion of the six coordinates.
        let mut wv = [0.0; 6];
        for (m, row) in w.iter().enumerate() {
            for k in 0..6 {
                wv[k] += v[m] * row[k];
            }
        }
        let scale = area * lambda;
        for i in 0..6 {
            for j in 0..6 {
                // wv[i]·wv[j] first, so the result is exactly symmetric.
                let term = scale * (wv[i] * wv[j]);
                exact_hessian[i][j] += term;
                if lambda > 0.0 {
                    hessian[i][j] += term;
                }
            }
        }
    }
    Some(TriangleDerivatives {
        gradient,
        hessian,
        exact_hessian,
    })
}

/// `W = ∂(E, H, F, G)/∂(u_0x, u_0y, u_1x, u_1y, u_2x, u_2y)` for the hat gradients `g` of a
/// triangle: `J = Σ_k u_k g_kᵀ` and `E = (a + d)/2`, `H = (c − b)/2`, `F = (a − d)/2`,
/// `G = (c + b)/2`.
fn ehfg_rows(g: &[Vec2; 3]) -> [[f64; 6]; 4] {
    let mut w = [[0.0; 6]; 4];
    for k in 0..3 {
        let (x, y) = (2 * k, 2 * k + 1);
        let (gx, gy) = (0.5 * g[k].x, 0.5 * g[k].y);
        w[0][x] = gx;
        w[0][y] = gy;
        w[1][x] = -gy;
        w[1][y] = gx;
        w[2][x] = gx;
        w[2][y] = -gy;
        w[3][x] = gy;
        w[3][y] = gx;
    }
    w
}

#[cfg(test)]
mod tests {
    use super::*;

    fn one_triangle() -> (TriangleGradients, Vec<Point>) {
        let v = vec![
            Point::new(0.1, 0.0),
            Point::new(1.3, 0.2),
            Point::new(0.4, 0.9),
        ];
        let mesh = TriMesh::new(v.clone(), vec![[0, 1, 2]]).unwrap();
        (TriangleGradients::new(&mesh), v)
    }

    /// The corners with flat coordinates `x` (`u_0x, u_0y, u_1x, …`).
    fn corners(x: &[f64; 6]) -> Vec<Point> {
        (0..3).map(|k| Point::new(x[2 * k], x[2 * k + 1])).collect()
    }

    fn energy_at(rest: &TriangleGradients, x: &[f64; 6]) -> f64 {
        sarap_energy_of(rest, &corners(x))
    }

    /// The derivatives of the one triangle of `rest` at `x` (not flipped).
    fn derivatives_at(rest: &TriangleGradients, x: &[f64; 6]) -> TriangleDerivatives {
        triangle_derivatives(rest, 0, &corners(x)).unwrap()
    }

    /// The corners `v` under the linear map `(x, y) ↦ (a x + b y, c x + d y)`, flat.
    fn linear_image(v: &[Point], [a, b, c, d]: [f64; 4]) -> [f64; 6] {
        std::array::from_fn(|i| {
            let p = v[i / 2];
            if i % 2 == 0 {
                a * p.x + b * p.y
            } else {
                c * p.x + d * p.y
            }
        })
    }

    /// Asserts that `hessian` is the derivative of the gradient at `x`: each column `k` within
    /// 1e-6 of the central difference of the gradient along coordinate `k` (step 1e-6).
    fn assert_hessian_matches_differences(
        rest: &TriangleGradients,
        x: &[f64; 6],
        hessian: &[[f64; 6]; 6],
    ) {
        let h = 1e-6;
        for k in 0..6 {
            let (mut plus, mut minus) = (*x, *x);
            plus[k] += h;
            minus[k] -= h;
            let (gp, gm) = (
                derivatives_at(rest, &plus).gradient,
                derivatives_at(rest, &minus).gradient,
            );
            for i in 0..6 {
                let fd = (gp[i] - gm[i]) / (2.0 * h);
                let exact = hessian[i][k];
                assert!((fd - exact).abs() < 1e-6, "H[{i}][{k}]: {fd} vs {exact}");
            }
        }
    }

    /// A deformed configuration away from the crease (Σ ≠ σ) where ψ is smooth and its
    /// Hessian positive definite except for the translations.
    fn deformed(v: &[Point]) -> [f64; 6] {
        let mut x = [0.0; 6];
        for k in 0..3 {
            let p = v[k];
            x[2 * k] = 1.1 * p.x + 0.3 * p.y + 0.05 * k as f64;
            x[2 * k + 1] = -0.2 * p.x + 0.8 * p.y;
        }
        x
    }

    #[test]
    fn sarap_gradient_matches_finite_differences() {
        let (rest, v) = one_triangle();
        let x = deformed(&v);
        let d = derivatives_at(&rest, &x);
        // Central differences: error O(h²) ≈ 1e-10 at h = 1e-5, plus rounding 1e-16/h.
        let h = 1e-5;
        for k in 0..6 {
            let (mut plus, mut minus) = (x, x);
            plus[k] += h;
            minus[k] -= h;
            let fd = (energy_at(&rest, &plus) - energy_at(&rest, &minus)) / (2.0 * h);
            assert!(
                (fd - d.gradient[k]).abs() < 1e-8,
                "{k}: {fd} vs {}",
                d.gradient[k]
            );
        }
    }

    #[test]
    fn sarap_hessian_matches_finite_differences_where_convex() {
        // A slight expansion (Q > 1, so the twist ψ_Q/Q > 0, and σ < 1.5, so h''(σ) > 0):
        // no eigenvalue is clamped and the projected Hessian is the true one.
        let (rest, v) = one_triangle();
        let x = linear_image(&v, [1.05, 0.01, 0.03, 1.02]);
        let d = derivatives_at(&rest, &x);
        assert_hessian_matches_differences(&rest, &x, &d.hessian);
        assert_eq!(d.hessian, d.exact_hessian);
    }

    #[test]
    fn sarap_exact_hessian_matches_finite_differences_where_clamped() {
        // Compressed (Q < 1: negative twist) and stretched past σ = 1.5 (negative h''): the
        // exact Hessian is indefinite, and must still be the derivative of the gradient.
        let (rest, v) = one_triangle();
        for map in [[0.7, 0.1, -0.05, 0.8], [2.4, 0.2, 0.1, 1.9]] {
            let x = linear_image(&v, map);
            let derivatives = derivatives_at(&rest, &x);
            assert_ne!(
                derivatives.hessian, derivatives.exact_hessian,
                "nothing clamped"
            );
            assert_hessian_matches_differences(&rest, &x, &derivatives.exact_hessian);
        }
    }

    #[test]
    fn sarap_projected_hessian_is_positive_semidefinite() {
        // Large stretch: h''(σ) < 0 for σ > 1.5 and the twist ψ_Q/Q can be negative, so
        // clamping is exercised; xᵀHx ≥ 0 on random vectors.
        let (rest, v) = one_triangle();
        let u: Vec<Point> = v
            .iter()
            .map(|p| Point::new(3.0 * p.x + 0.4 * p.y, 0.1 * p.x + 1.8 * p.y))
            .collect();
        let d = triangle_derivatives(&rest, 0, &u).unwrap();
        let mut seed = 1u64;
        for _ in 0..200 {
            let z: [f64; 6] = std::array::from_fn(|_| {
                seed = seed
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
            });
            let mut quad = 0.0;
            for i in 0..6 {
                for j in 0..6 {
                    quad += z[i] * d.hessian[i][j] * z[j];
                    assert_eq!(d.hessian[i][j], d.hessian[j][i]);
                }
            }
            assert!(quad >= -1e-14, "{quad}");
        }
    }

    #[test]
    fn sarap_is_zero_at_rigid_motions_and_infinite_on_flips() {
        let (rest, v) = one_triangle();
        let (c, s) = (0.6f64.cos(), 0.6f64.sin());
        let u: Vec<Point> = v
            .iter()
            .map(|p| Point::new(c * p.x - s * p.y + 3.0, s * p.x + c * p.y - 1.0))
            .collect();
        let d = triangle_derivatives(&rest, 0, &u).unwrap();
        assert!(sarap_energy_of(&rest, &u) < 1e-28);
        assert!(
            d.gradient.iter().all(|g| g.abs() < 1e-14),
            "{:?}",
            d.gradient
        );
        let mirrored: Vec<Point> = v.iter().map(|p| Point::new(-p.x, p.y)).collect();
        assert!(triangle_derivatives(&rest, 0, &mirrored).is_none());
        assert_eq!(sarap_energy_of(&rest, &mirrored), f64::INFINITY);
    }
}
