//! [`DefOp::fit`]: the constrained least-squares fit of a `(Φ, Ψ)` deformation operator to
//! ground-truth deformations at sampled handle configurations (Poranne & Lipman 2016, §3.2,
//! Eq. (8) and Appendix A; DESIGN.md §4), solved through its Kronecker structure.
//!
//! # The problem
//!
//! Per coordinate `ν ∈ {x, y}` (the two decouple and share every matrix) the unknown is
//! `G` (`|Φ| × |Ψ|`, the paper's `(Cν)ᵀ`), and the operator's vertex values at `Q` are
//! `Dᵀ G ψ(Q)`. With the samples `Q_1 … Q_m`, `Ψ_s = [ψ(Q_1) … ψ(Q_m)]` (`|Ψ| × m`), the ground
//! truths `U` (`n_vertices × m`, column `k` the vertices' ν coordinate at `Q_k`) and `M` the
//! consistent mass matrix:
//!
//! ```text
//! minimise   ‖U − Dᵀ G Ψ_s‖²_M = tr((U − DᵀGΨ_s)ᵀ M (U − DᵀGΨ_s))             (8a)
//! subject to G ψ(P) = c₀                  rest pose: Dᵀc₀ = ν, the coordinate    (8b)
//!            S G = L                      handles interpolated at every Q          (8c′)
//!            G T = 0                      thin-plate splines only: side conditions
//! ```
//!
//! `S = Φ(P)` (`n × |Φ|`) evaluates the spatial functions at the handles, and `L` (`n × |Ψ|`)
//! writes the handles' own coordinates in `Ψ`: `L ψ(Q) = (q_ℓ.ν)_ℓ` for every `Q` (`Ψ` holds the
//! linear functions: `q_ℓ.ν = p_ℓ.ν · ψ_0 + scale · z_{2ℓ+ν}`). The paper imposes (8c)
//! `S G ψ(Q_k) = q_k` at the samples only; its Proposition 2 shows that this implies (8c′)
//! when `Ψ` interpolates uniquely on the samples. (8c′) is imposed here directly: the same
//! condition where the proposition applies, and interpolation at every configuration even
//! when it does not (fewer samples than polynomial functions). `T` (`|Ψ| × (1 + 2n)`) holds the
//! linear polynomials at the thin-plate centres (`Σ_k a_k = 0`, `Σ_k a_k z_k = 0` for every
//! row's kernel coefficients `a`), which makes thin-plate interpolation unique.
//!
//! # The solution
//!
//! Constraints act on `G` from the left (`S`) and from the right (`R = [ψ(P) | T]`, `r`
//! columns), so every feasible `G` is
//!
//! ```text
//! G = G₀ + N_S X N_Rᵀ,     G₀ = Z_S L + (C_R − Z_S L R) W_Rᵀ
//! ```
//!
//! with `N_S` a basis of `null(S)` and `Z_S` a right inverse (`S Z_S = I`), from a QR of `Sᵀ`;
//! `N_R` an orthonormal basis of `null(Rᵀ)` and `W_R = Q₁ R_r⁻ᵀ` (`W_Rᵀ R = I`), from a QR of
//! `R`; `C_R = [c₀ | 0]`. (`S G₀ = L` uses `S C_R = L R`: the rest pose puts the handles at `P`
//! and satisfies the side conditions.) `X` (`(|Φ| − n) × (|Ψ| − r)`) is free. Substituting,
//! with `E₀ = U − Dᵀ G₀ Ψ_s` and `Ψ' = N_Rᵀ Ψ_s`, the normal equations are
//!
//! ```text
//! (N_Sᵀ D M Dᵀ N_S) X (Ψ' Ψ'ᵀ) = N_Sᵀ D M E₀ Ψ'ᵀ       i.e.  (B ⊗ A′) vec X = vec(…)
//! ```
//!
//! the paper's `B ⊗ D A Dᵀ` structure. It is never formed: because `A′ = N_Sᵀ D M Dᵀ N_S` is a
//! fixed symmetric positive definite left factor, the minimiser splits into two one-sided
//! problems,
//!
//! ```text
//! F = A′⁻¹ N_Sᵀ D M E₀          spatial projection (|Φ| − n) × m: a Cholesky of A′
//! X = F Ψ'⁺                     handle-space least squares, row by row: a thin SVD of Ψ'
//! ```
//!
//! (write `A′ = LLᵀ`: the objective is `‖M^{½}(E₀ − Dᵀ N_S F)‖² + ‖Lᵀ(F − X Ψ')‖²`, and the
//! second term is smallest for `X = FΨ'⁺` whatever `L`). The pseudo-inverse drops singular
//! values below [`DefOpOptions::rank_tolerance`] of the largest, so fewer samples than
//! functions give the minimum-norm fit rather than an error, and it never squares `Ψ'`'s
//! condition number as `Ψ'Ψ'ᵀ` would. For the **hats** (`D` = identity) `N_S` selects the free
//! vertices and `E₀` vanishes at the handles (the ground truth meets them), so
//! `F = E₀` restricted to the free vertices: the mass matrix cancels, and the fit is a
//! least-squares fit of each vertex's trajectory. Work: one `|Ψ| × r` QR, one thin SVD of
//! `(|Ψ| − r) × m`, and products of `2(|Φ| − n) × m` by `m × (|Ψ| − r)` matrices.
//!
//! **Interpolation.** With the rest configuration among the samples (its ground truth is the
//! rest mesh) and `Ψ'` of full rank `m − 1`, thin-plate splines reproduce every training sample
//! exactly in `Φ` (the paper's Proposition 1): `F`'s rows are orthogonal to `null(Ψ')`.

use faer::linalg::solvers::Solve;
use faer::linalg::triangular_solve::solve_upper_triangular_in_place;
use faer::{Mat, MatRef, Par, Side};
use kurbo::Point;

use super::error::DefOpError;
use super::handle_basis::{HandleBasis, HandleBasisKind};
use super::handles::{bounding_box_diagonal, HandleSet};
use super::operator::DefOp;
use super::spatial_basis::SpatialBasis;
use splineskin_core::mesh::operators::consistent_mass_csc;
use splineskin_core::mesh::TriMesh;

/// Default [`DefOpOptions::rank_tolerance`]: singular values of the handle-basis sample matrix
/// below `1e-12` of the largest are dropped. That is about four thousand times the rounding
/// unit (2.2e-16): directions weaker than this carry rounding, not data, and dividing by them
/// would amplify it into the coefficients.
pub const DEFAULT_RANK_TOLERANCE: f64 = 1e-12;

/// Ground-truth handles may miss their targets by this fraction of the bounding-box diagonal
/// (solvers set them exactly; a caller's data may carry rounding).
const HANDLE_TOLERANCE: f64 = 1e-9;

/// A reduced spatial basis must reproduce the coordinate functions to this fraction of the
/// bounding-box diagonal (bases built here do to about 1e-13).
const LINEAR_TOLERANCE: f64 = 1e-8;

/// Relative size below which a pivot of the QR of `Sᵀ` or `R` counts as zero: `Φ` cannot
/// interpolate at the handles, or `Ψ`'s constraints are dependent.
const PIVOT_TOLERANCE: f64 = 1e-10;

/// Options of [`DefOp::fit`].
///
/// ```
/// use splineskin_defop::{DefOpOptions, HandleBasisKind};
/// let options = DefOpOptions::default().with_handle_basis(HandleBasisKind::Quadratic);
/// assert_eq!(options.handle_basis, HandleBasisKind::Quadratic);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct DefOpOptions {
    /// The handle basis `Ψ`; a thin-plate spline basis is centred at the samples. Default:
    /// [`HandleBasisKind::ThinPlateSpline`] (the paper's best trade-off).
    pub handle_basis: HandleBasisKind,
    /// The length unit of the handle basis' variable `z = (Q − P) / scale`, drawing units.
    /// Only conditioning depends on it. Default: `None`, the root-mean-square handle
    /// displacement of the samples (the bounding-box diagonal if that is 0).
    pub scale: Option<f64>,
    /// Relative singular-value cut of the handle-space least squares (dimensionless).
    /// Default: [`DEFAULT_RANK_TOLERANCE`].
    pub rank_tolerance: f64,
}

impl Default for DefOpOptions {
    fn default() -> Self {
        DefOpOptions {
            handle_basis: HandleBasisKind::ThinPlateSpline,
            scale: None,
            rank_tolerance: DEFAULT_RANK_TOLERANCE,
        }
    }
}

impl DefOpOptions {
    /// Sets [`DefOpOptions::handle_basis`].
    pub fn with_handle_basis(mut self, kind: HandleBasisKind) -> Self {
        self.handle_basis = kind;
        self
    }
    /// Sets [`DefOpOptions::scale`].
    pub fn with_scale(mut self, scale: f64) -> Self {
        self.scale = Some(scale);
        self
    }
    /// Sets [`DefOpOptions::rank_tolerance`].
    pub fn with_rank_tolerance(mut self, tolerance: f64) -> Self {
        self.rank_tolerance = tolerance;
        self
    }

    fn check(&self) -> Result<(), DefOpError> {
        if !(self.rank_tolerance.is_finite() && (0.0..1.0).contains(&self.rank_tolerance)) {
            return Err(DefOpError::InvalidOption {
                name: "rank_tolerance",
                value: self.rank_tolerance.to_string(),
                expected: "a fraction in [0, 1)",
            });
        }
        Ok(())
    }
}

/// The spatial side of the fit: how `G`'s rows map to vertex values and constraints.
enum SpatialSide {
    /// `D` = identity: `free` lists the free vertices (`N_S` selects them), handle `ℓ`'s row is
    /// `handles[ℓ]` (`Z_S` selects it).
    Hats { free: Vec<usize> },
    /// A reduced basis.
    Reduced(Box<ReducedSide>),
}

/// The matrices of a reduced spatial basis' side of the fit.
struct ReducedSide {
    /// `Dᵀ`, `n_vertices × |Φ|`.
    dt: Mat<f64>,
    /// `Z_S`, `|Φ| × n`.
    z_s: Mat<f64>,
    /// `N_S`, `|Φ| × (|Φ| − n)`.
    n_s: Mat<f64>,
    /// `A′⁻¹ N_Sᵀ D M`, `(|Φ| − n) × n_vertices`.
    projection: Mat<f64>,
    /// `c₀`, `|Φ| × 2`.
    c0: Mat<f64>,
}

impl DefOp {
    /// Fits the operator with spatial basis `spatial` and handle basis `options.handle_basis`
    /// to the ground truths `solutions[k]` (one point per mesh vertex) at the handle
    /// configurations `configurations[k]` (one point per handle, in `handles`' order), as
    /// the module documentation derives. The result reproduces the rest pose at `Q = P` and puts
    /// the handles on `Q` at every configuration; include the rest configuration (with the
    /// rest mesh as its solution) among the samples for thin-plate interpolation of every
    /// sample.
    ///
    /// Errors: an invalid mesh or handle set ([`DefOpError`]'s mesh and handle variants), a
    /// basis built on another mesh, no samples or mismatched counts, a sample with the wrong
    /// size, non-finite values or handles off target, a spatial basis without the linear
    /// functions or unable to interpolate at the handles, too few or degenerate samples for
    /// the thin-plate side conditions (`2n + 1` not on one hyperplane).
    pub fn fit(
        mesh: &TriMesh,
        handles: &[usize],
        spatial: &SpatialBasis,
        configurations: &[Vec<Point>],
        solutions: &[Vec<Point>],
        options: &DefOpOptions,
    ) -> Result<DefOp, DefOpError> {
        options.check()?;
        let handle_set = HandleSet::new(mesh, handles)?;
        let nv = mesh.n_vertices();
        if spatial.n_vertices() != nv {
            return Err(DefOpError::BasisMismatch {
                basis_vertices: spatial.n_vertices(),
                n_vertices: nv,
            });
        }
        let rest: Vec<Point> = handles.iter().map(|&h| mesh.vertices[h]).collect();
        let diagonal = bounding_box_diagonal(mesh);
        check_samples(configurations, solutions, handles, nv, diagonal)?;
        let scale = match options.scale {
            Some(scale) => scale,
            None => rms_displacement(configurations, &rest).unwrap_or(diagonal),
        };
        let handle_basis = match options.handle_basis {
            HandleBasisKind::ThinPlateSpline => {
                HandleBasis::thin_plate_spline(&rest, scale, configurations)?
            }
            HandleBasisKind::Linear => HandleBasis::polynomial(1, &rest, scale)?,
            HandleBasisKind::Quadratic => HandleBasis::polynomial(2, &rest, scale)?,
            HandleBasisKind::Cubic => HandleBasis::polynomial(3, &rest, scale)?,
        };
        let hs = HandleSide::new(&handle_basis, configurations, &rest, options)?;
        let side = spatial_side(mesh, handles, &handle_set, spatial, diagonal)?;
        let nf = spatial.n_functions();
        let n_free = nf - handles.len();
        let m = configurations.len();
        // Per coordinate: G₀ and F, F stacked [F_x; F_y].
        let mut f = Mat::<f64>::zeros(2 * n_free, m);
        let g0 = [0, 1].map(|axis| {
            let samples = AxisSamples {
                mesh,
                handles,
                rest: &rest,
                configurations,
                solutions,
                scale,
                nf,
            };
            let (g0, fa) = samples.terms(axis, &handle_basis, &hs, &side);
            f.get_mut(axis * n_free..(axis + 1) * n_free, ..)
                .copy_from(&fa);
            g0
        });
        let x = &f * &hs.pinv; // 2(|Φ| − n) × (|Ψ| − r)
        let coefficients = coefficients(&x, g0, &hs.n_r, &side, nf, n_free);
        let vertex_values = match side {
            SpatialSide::Hats { .. } => Vec::new(),
            SpatialSide::Reduced(side) => (0..nf)
                .flat_map(|i| (0..nv).map(move |v| (v, i)))
                .map(|(v, i)| side.dt[(v, i)])
                .collect(),
        };
        Ok(DefOp {
            spatial: spatial.clone(),
            handle_basis,
            handles: handles.to_vec(),
            coefficients,
            vertex_values,
        })
    }
}

/// The handle side of the fit, from `Ψ_s` (the basis at every sample, `|Ψ| × m`):
/// `R = [ψ(P) | T]`, its null space `N_R` and `W_Rᵀ = R_r⁻¹ Q₁ᵀ` from its QR factorisation,
/// `W_Rᵀ Ψ_s`, and the pseudo-inverse of `Ψ′ = N_Rᵀ Ψ_s`.
struct HandleSide {
    /// `R`, `|Ψ| × r`.
    r_mat: Mat<f64>,
    /// `N_R`, `|Ψ| × (|Ψ| − r)`.
    n_r: Mat<f64>,
    /// `W_Rᵀ`, `r × |Ψ|`.
    w_rt: Mat<f64>,
    /// `(Ψ′)⁺`, `m × (|Ψ| − r)`.
    pinv: Mat<f64>,
    /// `W_Rᵀ Ψ_s`, `r × m`.
    w_psi: Mat<f64>,
}

impl HandleSide {
    fn new(
        handle_basis: &HandleBasis,
        configurations: &[Vec<Point>],
        rest: &[Point],
        options: &DefOpOptions,
    ) -> Result<HandleSide, DefOpError> {
        let n = rest.len();
        let m = configurations.len();
        let np = handle_basis.n_functions();
        let mut psi_s = Mat::<f64>::zeros(np, m);
        let mut buffer = vec![0.0; np];
        for (k, q) in configurations.iter().enumerate() {
            handle_basis.eval(q, &mut buffer)?;
            psi_s
                .col_mut(k)
                .iter_mut()
                .zip(&buffer)
                .for_each(|(a, &b)| *a = b);
        }
        let n_side = if options.handle_basis == HandleBasisKind::ThinPlateSpline {
            1 + 2 * n
        } else {
            0
        };
        let r = 1 + n_side;
        let mut r_mat = Mat::<f64>::zeros(np, r);
        handle_basis.eval(rest, &mut buffer)?;
        r_mat
            .col_mut(0)
            .iter_mut()
            .zip(&buffer)
            .for_each(|(a, &b)| *a = b);
        for k in 0..handle_basis.n_centres() {
            let row = 1 + 2 * n + k;
            r_mat[(row, 1)] = 1.0;
            for (c, &z) in handle_basis.centre(k).iter().enumerate() {
                r_mat[(row, 2 + c)] = z;
            }
        }
        let qr = r_mat.qr();
        let q_full = qr.compute_Q();
        let r_r = qr.thin_R().to_owned();
        let pivot_max = (0..r).map(|i| r_r[(i, i)].abs()).fold(0.0, f64::max);
        if let Some(i) = (0..r).find(|&i| r_r[(i, i)].abs() <= PIVOT_TOLERANCE * pivot_max) {
            return Err(DefOpError::DegenerateSamples {
                detail: format!(
                    "the thin-plate side conditions are dependent (pivot {i} of {r}): need at least {} samples not all on one hyperplane of the 2n-dimensional handle space, got {m}",
                    2 * n + 1
                ),
            });
        }
        let n_r = q_full.get(.., r..).to_owned();
        // W_Rᵀ = R_r⁻¹ Q₁ᵀ.
        let mut w_rt = q_full.get(.., ..r).transpose().to_owned();
        solve_upper_triangular_in_place(r_r.as_ref(), w_rt.as_mut(), Par::Seq);
        let psi_prime = n_r.transpose() * &psi_s;
        let pinv = pseudo_inverse(psi_prime.as_ref(), options.rank_tolerance)?;
        let w_psi = &w_rt * &psi_s;
        Ok(HandleSide {
            r_mat,
            n_r,
            w_rt,
            pinv,
            w_psi,
        })
    }
}

/// The training data of one coordinate's terms ([`AxisSamples::terms`]).
struct AxisSamples<'a> {
    mesh: &'a TriMesh,
    handles: &'a [usize],
    rest: &'a [Point],
    configurations: &'a [Vec<Point>],
    solutions: &'a [Vec<Point>],
    scale: f64,
    /// `|Φ|`, the spatial basis's functions.
    nf: usize,
}

impl AxisSamples<'_> {
    /// Coordinate `axis`'s `G₀` (`|Φ| × |Ψ|`) and its block of `F` (`(|Φ| − n) × m`): the
    /// solutions' residuals from `G₀ Ψ_s` on the free rows.
    fn terms(
        &self,
        axis: usize,
        handle_basis: &HandleBasis,
        hs: &HandleSide,
        side: &SpatialSide,
    ) -> (Mat<f64>, Mat<f64>) {
        let (mesh, handles, rest) = (self.mesh, self.handles, self.rest);
        let (n, m) = (handles.len(), self.configurations.len());
        let nv = mesh.n_vertices();
        let np = handle_basis.n_functions();
        let coordinate = |p: Point| if axis == 0 { p.x } else { p.y };
        // L: n × |Ψ|, two entries per row.
        let mut l = Mat::<f64>::zeros(n, np);
        for (ell, &p) in rest.iter().enumerate() {
            l[(ell, 0)] = coordinate(p);
            l[(ell, handle_basis.linear_index(ell, axis))] = self.scale;
        }
        // Q_ν: n × m.
        let q_nu = Mat::<f64>::from_fn(n, m, |ell, k| coordinate(self.configurations[k][ell]));
        let (z_l, z_q, c0) = match side {
            SpatialSide::Hats { .. } => {
                let nf = self.nf;
                let mut z_l = Mat::<f64>::zeros(nf, np);
                let mut z_q = Mat::<f64>::zeros(nf, m);
                for (ell, &h) in handles.iter().enumerate() {
                    z_l.row_mut(h).copy_from(l.row(ell));
                    z_q.row_mut(h).copy_from(q_nu.row(ell));
                }
                let c0 = Mat::<f64>::from_fn(nf, 1, |v, _| coordinate(mesh.vertices[v]));
                (z_l, z_q, c0)
            }
            SpatialSide::Reduced(side) => (
                &side.z_s * &l,
                &side.z_s * &q_nu,
                side.c0.get(.., axis..axis + 1).to_owned(),
            ),
        };
        let nf = self.nf;
        // B = C_R − Z_S L R.
        let mut b = -(&z_l * &hs.r_mat);
        for i in 0..nf {
            b[(i, 0)] += c0[(i, 0)];
        }
        let g0 = &z_l + &b * &hs.w_rt;
        let g0_psi = &z_q + &b * &hs.w_psi; // |Φ| × m
        let u = Mat::<f64>::from_fn(nv, m, |v, k| coordinate(self.solutions[k][v]));
        let fa = match side {
            SpatialSide::Hats { free } => Mat::<f64>::from_fn(free.len(), m, |row, k| {
                u[(free[row], k)] - g0_psi[(free[row], k)]
            }),
            SpatialSide::Reduced(side) => {
                let e0 = &u - &side.dt * &g0_psi;
                &side.projection * &e0
            }
        };
        (g0, fa)
    }
}

/// The operator's coefficients `G` (`2 · |Φ| × |Ψ|`, stored column by column of `Ψ`, `x` rows
/// then `y` rows): `G₀ + N_S X N_Rᵀ` per coordinate, `X` the least-squares solution `x`.
fn coefficients(
    x: &Mat<f64>,
    g0: [Mat<f64>; 2],
    n_r: &Mat<f64>,
    side: &SpatialSide,
    nf: usize,
    n_free: usize,
) -> Vec<f64> {
    let np = n_r.nrows();
    let mut coefficients = vec![0.0; 2 * nf * np];
    for (axis, mut g) in g0.into_iter().enumerate() {
        let xn = x.get(axis * n_free..(axis + 1) * n_free, ..) * n_r.transpose();
        match side {
            SpatialSide::Hats { free } => {
                for (row, &v) in free.iter().enumerate() {
                    for j in 0..np {
                        g[(v, j)] += xn[(row, j)];
                    }
                }
            }
            SpatialSide::Reduced(side) => g += &side.n_s * &xn,
        }
        for j in 0..np {
            for i in 0..nf {
                coefficients[j * 2 * nf + axis * nf + i] = g[(i, j)];
            }
        }
    }
    coefficients
}

/// Checks the training data: as many solutions as configurations (at least one), each of the
/// right size and finite, with the handles on their targets.
fn check_samples(
    configurations: &[Vec<Point>],
    solutions: &[Vec<Point>],
    handles: &[usize],
    n_vertices: usize,
    diagonal: f64,
) -> Result<(), DefOpError> {
    if configurations.is_empty() || configurations.len() != solutions.len() {
        return Err(DefOpError::SampleCount {
            configurations: configurations.len(),
            solutions: solutions.len(),
        });
    }
    for (k, (q, u)) in configurations.iter().zip(solutions).enumerate() {
        let bad = |reason: String| Err(DefOpError::BadSample { sample: k, reason });
        if q.len() != handles.len() {
            return bad(format!(
                "{} handle positions for {} handles",
                q.len(),
                handles.len()
            ));
        }
        if u.len() != n_vertices {
            return bad(format!(
                "{} solution points for {n_vertices} vertices",
                u.len()
            ));
        }
        if let Some(l) = q.iter().position(|p| !p.is_finite()) {
            return bad(format!("handle {l} at {:?} is not finite", q[l]));
        }
        if let Some(v) = u.iter().position(|p| !p.is_finite()) {
            return bad(format!("solution vertex {v} at {:?} is not finite", u[v]));
        }
        for (l, (&h, &target)) in handles.iter().zip(q).enumerate() {
            let miss = (u[h] - target).hypot();
            if miss > HANDLE_TOLERANCE * diagonal {
                return bad(format!(
                    "the solution puts handle {l} (vertex {h}) at {:?}, {miss:e} from its target {target:?}",
                    u[h]
                ));
            }
        }
    }
    Ok(())
}

/// Root-mean-square distance of the configurations' handles from the rest positions, `None`
/// if zero.
fn rms_displacement(configurations: &[Vec<Point>], rest: &[Point]) -> Option<f64> {
    let count = (configurations.len() * rest.len()) as f64;
    let sum: f64 = configurations
        .iter()
        .flat_map(|q| q.iter().zip(rest).map(|(q, p)| (*q - *p).hypot2()))
        .sum();
    let rms = (sum / count).sqrt();
    (rms > 0.0).then_some(rms)
}

/// `A⁺` (`ncols × nrows`) from a thin SVD, singular values below `tolerance` of the largest
/// dropped.
fn pseudo_inverse(a: MatRef<'_, f64>, tolerance: f64) -> Result<Mat<f64>, DefOpError> {
    if a.nrows() == 0 || a.ncols() == 0 {
        return Ok(Mat::zeros(a.ncols(), a.nrows()));
    }
    let svd = a.thin_svd().map_err(|e| DefOpError::DegenerateSamples {
        detail: format!("the SVD of the handle-basis sample matrix failed: {e:?}"),
    })?;
    let s = svd.S().column_vector();
    let largest = (0..s.nrows()).map(|i| s[i]).fold(0.0, f64::max);
    let kept: Vec<usize> = (0..s.nrows())
        .filter(|&i| s[i] > tolerance * largest)
        .collect();
    tracing::debug!(
        rank = kept.len(),
        rows = a.nrows(),
        columns = a.ncols(),
        smallest_kept = kept.last().map(|&i| s[i] / largest),
        "handle-basis sample matrix"
    );
    // A⁺ = V S⁺ Uᵀ over the kept singular values.
    let v = Mat::<f64>::from_fn(a.ncols(), kept.len(), |i, j| {
        svd.V()[(i, kept[j])] / s[kept[j]]
    });
    let u = Mat::<f64>::from_fn(a.nrows(), kept.len(), |i, j| svd.U()[(i, kept[j])]);
    Ok(&v * u.transpose())
}

/// The spatial side of the fit (see [`SpatialSide`]).
fn spatial_side(
    mesh: &TriMesh,
    handles: &[usize],
    handle_set: &HandleSet,
    spatial: &SpatialBasis,
    diagonal: f64,
) -> Result<SpatialSide, DefOpError> {
    let nv = mesh.n_vertices();
    let n = handles.len();
    let nf = spatial.n_functions();
    if spatial.is_hats() {
        // Every vertex is referenced (the basis checked), so the free vertices are the rest.
        return Ok(SpatialSide::Hats {
            free: handle_set.free.clone(),
        });
    }
    if nf < n {
        return Err(DefOpError::HandlesNotInterpolable {
            rank: nf,
            n_handles: n,
        });
    }
    let dt = Mat::<f64>::from_fn(nv, nf, |v, i| spatial.value(i, v));
    // Sᵀ = Q R: Z_S = Q₁ R⁻ᵀ, N_S = Q₂.
    let st = Mat::<f64>::from_fn(nf, n, |i, ell| dt[(handles[ell], i)]);
    let qr = st.qr();
    let q = qr.compute_Q();
    let r = qr.thin_R().to_owned();
    let pivot_max = (0..n).map(|i| r[(i, i)].abs()).fold(0.0, f64::max);
    let rank = (0..n)
        .filter(|&i| r[(i, i)].abs() > PIVOT_TOLERANCE * pivot_max)
        .count();
    if rank < n {
        return Err(DefOpError::HandlesNotInterpolable { rank, n_handles: n });
    }
    let mut z_st = q.get(.., ..n).transpose().to_owned();
    solve_upper_triangular_in_place(r.as_ref(), z_st.as_mut(), Par::Seq);
    let z_s = z_st.transpose().to_owned();
    let n_s = q.get(.., n..).to_owned();
    // M Dᵀ with the consistent mass.
    let mass = consistent_mass_csc(mesh);
    let mut mdt = Mat::<f64>::zeros(nv, nf);
    for i in 0..nf {
        for c in 0..nv {
            let x = dt[(c, i)];
            let (rows, values) = mass.column(c);
            for (&row, &value) in rows.iter().zip(values) {
                mdt[(row, i)] += value * x;
            }
        }
    }
    let a_phi = dt.transpose() * &mdt;
    let factor_error = |what: &str| DefOpError::Factorization {
        detail: format!(
            "{what}: the reduced mass matrix is not positive definite (dependent basis functions?)"
        ),
    };
    let a_llt = a_phi.llt(Side::Lower).map_err(|_| factor_error("D M Dᵀ"))?;
    // c₀: the M-projection of x and y onto Φ, which must reproduce them.
    let xy = Mat::<f64>::from_fn(nv, 2, |v, axis| {
        let p = mesh.vertices[v];
        if axis == 0 {
            p.x
        } else {
            p.y
        }
    });
    let c0 = a_llt.solve(mdt.transpose() * &xy);
    let residual = (&dt * &c0 - &xy)
        .col_iter()
        .flat_map(|c| c.iter().copied().collect::<Vec<_>>())
        .fold(0.0f64, |a, b| a.max(b.abs()));
    if residual > LINEAR_TOLERANCE * diagonal {
        return Err(DefOpError::NotLinearlyPrecise { residual });
    }
    let a_prime = n_s.transpose() * &a_phi * &n_s;
    let projection = a_prime
        .llt(Side::Lower)
        .map_err(|_| factor_error("N_Sᵀ D M Dᵀ N_S"))?
        .solve(n_s.transpose() * mdt.transpose());
    Ok(SpatialSide::Reduced(Box::new(ReducedSide {
        dt,
        z_s,
        n_s,
        projection,
        c0,
    })))
}
