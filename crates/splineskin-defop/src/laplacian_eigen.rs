//! The smoothest eigenfunctions of a Laplacian-type operator on a triangle mesh: the pairs
//! `(λ, φ)` of the generalised symmetric eigenproblem
//!
//! ```text
//! K φ = λ M φ,   φᵀ M φ = 1,   smallest λ first
//! ```
//!
//! with `M` the Voronoi lumped mass ([`splineskin_core::mesh::operators::lumped_mass`]) and `K` one of
//! [`EigenOperator`]: the cotangent Laplacian `−L` (Dirichlet energy, natural boundary
//! conditions) or the linearly precise squared Laplacian of Wang et al. 2015
//! (`mesh/crouzeix_raviart.rs`), whose null space is the linear functions.
//!
//! **Method: shift-invert subspace iteration.** With `M` diagonal the problem is the standard
//! symmetric one `M^{-1/2} K M^{-1/2} y = λ y`, `y = M^{1/2} φ`. Its smallest eigenvalues are
//! the largest of the shift-inverted operator
//!
//! ```text
//! T = M^{1/2} (K + σ M)⁻¹ M^{1/2},      T y = y / (λ + σ)
//! ```
//!
//! applied with one sparse Cholesky factorisation of `K + σM` (AMD ordering) and two
//! triangular solves per vector. A block of `b = n_pairs + max(n_pairs / 2, 8)` orthonormal
//! vectors `Y` is iterated (Rutishauser's subspace iteration with Rayleigh–Ritz; Saad 2011,
//! *Numerical Methods for Large Eigenvalue Problems*, §5.2):
//!
//! ```text
//! Z = T Y;   H = Yᵀ Z = W Θ Wᵀ (dense, b × b, faer);   residuals ‖Z w_j − θ_j Y w_j‖;   Y ← orth(Z W)
//! ```
//!
//! until the `n_pairs` largest Ritz values `θ_j` have residuals below [`RELATIVE_TOLERANCE`]
//! `· θ_j`. Eigenvalue `j` converges like `(θ_{b+1} / θ_j)^iterations`, about `(2/3)^iterations`
//! for the Laplacian's roughly linear spectrum. faer's Krylov–Schur
//! (`matrix_free::eigen::partial_self_adjoint_eigen`) needs fewer operator applications but was
//! tried first and set aside: on the octopus (an eightfold, nearly symmetric shape, so nearly
//! double eigenvalues) it did not return within a minute for 50 cotangent-Laplacian eigenpairs
//! with the deflation below, nor for 10 linearly precise ones without it.
//!
//! The shift `σ > 0` makes `K + σM` positive definite although `K` is only semidefinite; it is
//! [`SHIFT_FRACTION`] of the operator's own scale `max_i K_ii / M_ii` (about its largest
//! eigenvalue).
//!
//! **Known null space, deflated.** `K`'s null space is known exactly: the constants on each
//! connected part for the Laplacian, and `1, x, y` on each part for the linearly precise
//! operator. It is an invariant subspace of `T` with the repeated eigenvalue `1/σ`, by far the
//! largest; the iteration runs on `P T P`, `P` the orthogonal projector onto the complement of
//! `M^{1/2}·(null space)`, and the null space is returned first, M-orthonormalised, with
//! `λ = 0`.
//!
//! **Measured** on the benchmark octopus (1 991 vertices, release build, one core): 10, 20,
//! 50, 100 functions in 0.05, 0.13, 0.32, 0.88 s (linearly precise operator) and 0.05, 0.12,
//! 0.67, 1.37 s (cotangent Laplacian). A dense solver of the same problem (faer's
//! `self_adjoint_eigen` of the `n_vertices²` matrix) took 1.56 s there and grows as
//! `n_vertices³` (about 25 s at 5 000 vertices), with `n_vertices²` memory; the sparse method
//! grows with the factor's size and the number of functions.

use faer::dyn_stack::MemBuffer;
use faer::{Mat, MatRef};

use super::error::DefOpError;
use splineskin_core::linalg::Csc;
use splineskin_core::linalg::{CholeskyAnalysis, Ordering};
use splineskin_core::mesh::cotangent::laplacian_csc;
use splineskin_core::mesh::crouzeix_raviart::linearly_precise_energy_csc;
use splineskin_core::mesh::operators::{lumped_mass, MassKind};
use splineskin_core::mesh::TriMesh;

/// The shift `σ` as a fraction of `max_i K_ii / M_ii` (the operator's largest diagonal
/// Rayleigh quotient, about its highest eigenvalue). It only has to make `K + σM` factor: the
/// null space, where `σ` matters, is deflated. It must stay below the smallest nonzero
/// eigenvalues, or they cluster at `1/σ` in the shift-inverted spectrum and the iteration
/// crawls: the linearly precise operator spans nine orders of magnitude on a 1 200-vertex
/// octopus (lowest nonzero eigenvalue 1.5, highest 2.2e9), where a fraction of `1e-4`
/// (σ = 1.8e5) left a Krylov–Schur solve running for minutes. At `1e-10` (σ ≈ 0.2 there) the factorisation's
/// condition number is about `1e10`; its rounding falls mostly on the near-null directions,
/// which the deflation removes.
pub const SHIFT_FRACTION: f64 = 1e-10;

/// Convergence tolerance of the subspace iteration: each wanted Ritz pair's residual
/// `‖T y − θ y‖` below this fraction of its `θ` (dimensionless). Eigenvalues are then exact to
/// about its square relative to the spectral gap, eigenvectors to about itself.
pub const RELATIVE_TOLERANCE: f64 = 1e-10;

/// Iteration cap of the subspace iteration: far above what the rate `(2/3)^iterations` needs
/// (about 60 iterations); it only stops a solve that stagnates.
const MAX_ITERATIONS: usize = 2000;

/// Extra vectors in the block beyond those wanted, at least: they speed convergence up
/// (the rate is `θ_{b+1} / θ_j`) and keep near-double eigenvalues at the block's end apart.
const MIN_GUARD_VECTORS: usize = 8;

/// Which Laplacian-type operator `K` the eigenfunctions are taken of.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum EigenOperator {
    /// The cotangent Laplacian `−L` ([`splineskin_core::mesh::operators::cotangent_laplacian`]): the
    /// classic manifold harmonics (Neumann boundary conditions; the constant is the first
    /// eigenfunction, the linear functions are not eigenfunctions).
    Cotangent,
    /// The linearly precise squared Laplacian of Wang et al. 2015 (Crouzeix–Raviart variant,
    /// as [`splineskin_core::weights::biharmonic_coordinates()`]): its three zero eigenvalues hold the
    /// linear functions, and its next eigenfunctions are biharmonic-smooth. The operator
    /// Poranne & Lipman 2016 (§3.1) name for their reduced basis.
    LinearlyPrecise,
}

/// Eigenpairs: `values[j]` with the vertex values `vectors[j·n_vertices ..][..n_vertices]`.
#[derive(Clone, Debug)]
pub(crate) struct Eigenpairs {
    pub values: Vec<f64>,
    /// Column-major `n_vertices × values.len()`, M-orthonormal columns.
    pub vectors: Vec<f64>,
}

/// `P T P`, `T = M^{1/2} (K + σM)⁻¹ M^{1/2}`.
struct ShiftInverted<'a> {
    analysis: &'a CholeskyAnalysis,
    factor: &'a [f64],
    sqrt_mass: &'a [f64],
    /// Orthonormal columns (`n` values each, contiguous) spanning `M^{1/2}·(null space)`.
    deflated: &'a [f64],
}

impl ShiftInverted<'_> {
    /// `v ← P v`.
    fn project(&self, v: &mut [f64]) {
        for y in self.deflated.chunks(v.len().max(1)) {
            let dot: f64 = y.iter().zip(v.iter()).map(|(a, b)| a * b).sum();
            v.iter_mut().zip(y).for_each(|(a, b)| *a -= dot * b);
        }
    }

    /// `block ← P T P block` for a column-major block of columns of length `n`.
    fn apply(&self, block: &mut [f64], workspace: &mut MemBuffer) {
        let n = self.sqrt_mass.len();
        for column in block.chunks_mut(n) {
            self.project(column);
            column
                .iter_mut()
                .zip(self.sqrt_mass)
                .for_each(|(a, s)| *a *= s);
        }
        self.analysis.solve(self.factor, block, workspace);
        for column in block.chunks_mut(n) {
            column
                .iter_mut()
                .zip(self.sqrt_mass)
                .for_each(|(a, s)| *a *= s);
            self.project(column);
        }
    }
}

/// The operator `K` of `operator` on `mesh` (full symmetric storage).
pub(crate) fn operator_csc(mesh: &TriMesh, operator: EigenOperator) -> Csc {
    match operator {
        EigenOperator::Cotangent => {
            let mut l = laplacian_csc(mesh);
            l.values.iter_mut().for_each(|v| *v = -*v);
            l
        }
        EigenOperator::LinearlyPrecise => linearly_precise_energy_csc(mesh),
    }
}

/// The functions spanning the null space of `operator` on `mesh`: per connected part, its
/// indicator (and, for the linearly precise operator, `x` and `y` on it).
fn null_space(mesh: &TriMesh, operator: EigenOperator) -> Vec<Vec<f64>> {
    let components = mesh.components();
    let n_components = components.iter().max().map_or(0, |&c| c + 1);
    let mut functions = Vec::new();
    for c in 0..n_components {
        let on = |f: &dyn Fn(kurbo::Point) -> f64| -> Vec<f64> {
            mesh.vertices
                .iter()
                .zip(&components)
                .map(|(&p, &k)| if k == c { f(p) } else { 0.0 })
                .collect()
        };
        functions.push(on(&|_| 1.0));
        if operator == EigenOperator::LinearlyPrecise {
            functions.push(on(&|p| p.x));
            functions.push(on(&|p| p.y));
        }
    }
    functions
}

/// The `n_pairs` smallest eigenpairs of `K φ = λ M φ` on `mesh` (valid, every vertex in a
/// triangle), M-orthonormal, eigenvalues increasing: the null space first (`λ = 0`), then the
/// eigenpairs of the deflated operator by subspace iteration.
pub(crate) fn smallest_eigenpairs(
    mesh: &TriMesh,
    operator: EigenOperator,
    n_pairs: usize,
) -> Result<Eigenpairs, DefOpError> {
    let n = mesh.n_vertices();
    let k = operator_csc(mesh, operator);
    let mass = lumped_mass(mesh, MassKind::Voronoi);
    if let Some(vertex) = mass.iter().position(|&m| m.is_nan() || m <= 0.0) {
        return Err(DefOpError::UnreferencedVertex { vertex });
    }
    let scale = (0..n)
        .map(|v| {
            let (rows, vals) = k.column(v);
            rows.binary_search(&v).map_or(0.0, |i| vals[i]) / mass[v]
        })
        .fold(0.0, f64::max);
    let sigma = SHIFT_FRACTION * scale;
    // Upper triangle of K + σM.
    let mut triplets = Vec::with_capacity(k.values.len() / 2 + 2 * n);
    for col in 0..n {
        let (rows, vals) = k.column(col);
        for (&row, &x) in rows.iter().zip(vals) {
            if row <= col {
                triplets.push((row, col, x));
            }
        }
        triplets.push((col, col, sigma * mass[col]));
    }
    let shifted = Csc::from_triplets(n, triplets);
    let analysis = CholeskyAnalysis::new(n, shifted.col_ptr, shifted.row_idx, Ordering::Amd)?;
    let (factor, _) = analysis.factored(&shifted.values, 1)?;
    let sqrt_mass: Vec<f64> = mass.iter().map(|m| m.sqrt()).collect();
    // The null space in y = M^{1/2} φ coordinates, orthonormalised (Gram–Schmidt twice).
    let mut deflated: Vec<f64> = Vec::new();
    for f in null_space(mesh, operator) {
        let mut y: Vec<f64> = f.iter().zip(&sqrt_mass).map(|(a, s)| a * s).collect();
        for _ in 0..2 {
            for q in deflated.chunks(n) {
                let dot: f64 = q.iter().zip(&y).map(|(a, b)| a * b).sum();
                y.iter_mut().zip(q).for_each(|(a, b)| *a -= dot * b);
            }
        }
        let norm = y.iter().map(|a| a * a).sum::<f64>().sqrt();
        deflated.extend(y.iter().map(|a| a / norm));
    }
    let n_null = deflated.len() / n.max(1);
    let op = ShiftInverted {
        analysis: &analysis,
        factor: &factor,
        sqrt_mass: &sqrt_mass,
        deflated: &deflated,
    };
    let mut values = vec![0.0; n_null.min(n_pairs)];
    let mut out: Vec<f64> = deflated[..values.len() * n]
        .chunks(n)
        .flat_map(|y| y.iter().zip(&sqrt_mass).map(|(a, s)| a / s))
        .collect();
    let n_pairs = (n_pairs.min(n) - values.len()).min(n - n_null);
    if n_pairs == 0 {
        return Ok(Eigenpairs {
            values,
            vectors: out,
        });
    }
    let b = (n_pairs + (n_pairs / 2).max(MIN_GUARD_VECTORS)).min(n - n_null);
    let mut workspace = analysis.workspace(b)?;
    // A fixed, generic start (no symmetry of the mesh can make it orthogonal to a mode).
    let mut block: Vec<f64> = (0..n * b)
        .map(|i| ((i as f64 + 1.0) * 0.618_033_988_749_895).fract() - 0.5)
        .collect();
    for column in block.chunks_mut(n) {
        op.project(column);
    }
    let mut y = orthonormal_columns(&block, n, b);
    let mut converged = false;
    let mut worst = f64::INFINITY;
    let mut ritz = (Vec::new(), Mat::<f64>::zeros(0, 0));
    for iteration in 0..MAX_ITERATIONS {
        block.copy_from_slice(&y);
        op.apply(&mut block, &mut workspace);
        let ym = MatRef::from_column_major_slice(&y, n, b);
        let zm = MatRef::from_column_major_slice(&block, n, b);
        let h = ym.transpose() * zm;
        let h = Mat::<f64>::from_fn(b, b, |i, j| 0.5 * (h[(i, j)] + h[(j, i)]));
        let evd = h
            .self_adjoint_eigen(faer::Side::Lower)
            .map_err(|e| DefOpError::Eigensolver {
                detail: format!("Rayleigh–Ritz: {e:?}"),
            })?;
        // Descending θ.
        let theta: Vec<f64> = (0..b).rev().map(|j| evd.S().column_vector()[j]).collect();
        let w = Mat::<f64>::from_fn(b, b, |i, j| evd.U()[(i, b - 1 - j)]);
        let yw = ym * &w;
        let zw = zm * &w;
        worst = (0..n_pairs)
            .map(|j| {
                let r: f64 = (0..n)
                    .map(|i| (zw[(i, j)] - theta[j] * yw[(i, j)]).powi(2))
                    .sum::<f64>()
                    .sqrt();
                r / theta[j]
            })
            .fold(0.0, f64::max);
        if worst <= RELATIVE_TOLERANCE {
            tracing::debug!(iteration, worst, b, "subspace iteration converged");
            converged = true;
            ritz = (theta, yw);
            break;
        }
        let next: Vec<f64> = (0..b)
            .flat_map(|j| (0..n).map(move |i| (i, j)))
            .map(|(i, j)| zw[(i, j)])
            .collect();
        y = orthonormal_columns(&next, n, b);
    }
    if !converged {
        return Err(DefOpError::Eigensolver {
            detail: format!(
                "subspace iteration: relative residual {worst:e} after {MAX_ITERATIONS} iterations (tolerance {RELATIVE_TOLERANCE:e})"
            ),
        });
    }
    let (theta, vectors) = ritz;
    for j in 0..n_pairs {
        values.push(1.0 / theta[j] - sigma);
        out.extend((0..n).map(|i| vectors[(i, j)] / sqrt_mass[i]));
    }
    Ok(Eigenpairs {
        values,
        vectors: out,
    })
}

/// An orthonormal basis of the span of the `b` columns (column-major, length `n` each) of
/// `block`, as a column-major `n × b` array: the thin Q of a Householder QR.
fn orthonormal_columns(block: &[f64], n: usize, b: usize) -> Vec<f64> {
    let q = MatRef::from_column_major_slice(block, n, b)
        .qr()
        .compute_thin_Q();
    (0..b)
        .flat_map(|j| (0..n).map(move |i| (i, j)))
        .map(|(i, j)| q[(i, j)])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use kurbo::{Point, Rect};

    /// A jittered grid: no symmetry, so the eigenvalues are simple.
    fn mesh() -> TriMesh {
        let mut mesh = TriMesh::grid(Rect::new(0., 0., 2., 1.), 14, 7).unwrap();
        for (i, p) in mesh.vertices.iter_mut().enumerate() {
            if p.x > 0.0 && p.x < 2.0 && p.y > 0.0 && p.y < 1.0 {
                *p += kurbo::Vec2::new(
                    0.02 * ((i * 37 % 11) as f64 / 11.0 - 0.5),
                    0.02 * ((i * 53 % 7) as f64 / 7.0 - 0.5),
                );
            }
        }
        mesh.check().unwrap();
        mesh
    }

    /// The same problem solved densely.
    fn dense_eigenvalues(mesh: &TriMesh, operator: EigenOperator) -> Vec<f64> {
        let n = mesh.n_vertices();
        let k = operator_csc(mesh, operator).into_faer().to_dense();
        let mass = lumped_mass(mesh, MassKind::Voronoi);
        let a = Mat::<f64>::from_fn(n, n, |i, j| k[(i, j)] / (mass[i] * mass[j]).sqrt());
        a.self_adjoint_eigenvalues(faer::Side::Lower).unwrap()
    }

    #[test]
    fn laplacian_eigen_matches_dense_solver() {
        let mesh = mesh();
        let n = mesh.n_vertices();
        let mass = lumped_mass(&mesh, MassKind::Voronoi);
        for operator in [EigenOperator::Cotangent, EigenOperator::LinearlyPrecise] {
            let pairs = smallest_eigenpairs(&mesh, operator, 12).unwrap();
            let dense = dense_eigenvalues(&mesh, operator);
            let k = operator_csc(&mesh, operator).into_faer().to_dense();
            let top = dense[11];
            for (j, (&got, &want)) in pairs.values.iter().zip(&dense).enumerate() {
                assert!(
                    (got - want).abs() <= 1e-9 * top,
                    "{operator:?} λ_{j}: {got} vs {want}"
                );
                // Residual ‖Kφ − λMφ‖ and M-normalisation.
                let phi = &pairs.vectors[j * n..(j + 1) * n];
                let norm: f64 = phi.iter().zip(&mass).map(|(p, m)| p * p * m).sum();
                assert!(
                    (norm - 1.0).abs() < 1e-10,
                    "{operator:?} φ_{j}: norm {norm}"
                );
                let residual = (0..n)
                    .map(|i| {
                        let kphi: f64 = (0..n).map(|c| k[(i, c)] * phi[c]).sum();
                        (kphi - got * mass[i] * phi[i]).abs() / mass[i].sqrt()
                    })
                    .fold(0.0, f64::max);
                assert!(
                    residual < 1e-7 * top,
                    "{operator:?} φ_{j}: residual {residual:e}"
                );
            }
            if operator == EigenOperator::LinearlyPrecise {
                // The three zero eigenvalues: the linear functions.
                assert!(pairs.values[2].abs() < 1e-9 * top && pairs.values[3] > 1e-3 * top);
            } else {
                assert!(pairs.values[0].abs() < 1e-9 * top && pairs.values[1] > 1e-3 * top);
            }
        }
        let _ = Point::ZERO;
    }
}
