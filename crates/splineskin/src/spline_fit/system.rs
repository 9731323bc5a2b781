//! The fit system of one path: assembly of the KKT matrix and right-hand sides, one sparse LU
//! factorisation, and the solve for all `6h` right-hand sides.
//!
//! The energy of path `P` (Liu et al. 2014 §4; DESIGN.md §1) over its unknown chain points `x`
//! (two coordinates each, interleaved) is
//!
//! ```text
//! E(x) = Σ_j Σ_d  x_jdᵀ Â_j x_jd − 2 x_jdᵀ (Σ_i T_i Ŵ_ij)_d + const
//! Â_j  = ∫ b bᵀ dμ_j                       (4×4, curve j)
//! Ŵ_ij = C̄_j ∫ w_i(B_j(t)) b bᵀ dμ_j       (3×4, C̄_j the homogeneous input controls)
//! ```
//!
//! with `x_jd` the four coordinates `d` of curve `j`. Minimising it subject to the junction rows
//! `C x = 0` ([`super::constraints`]) gives the KKT system
//!
//! ```text
//! [ H  Cᵀ ] [x]   [ B vec(T) ]
//! [ C  0  ] [λ] = [    0     ]      H = blocks of Â_j (per coordinate), B = 2m × 6h
//! ```
//!
//! `x = O vec(T)` with `O` the first `2m` rows of `K⁻¹ [B; 0]`: one factorisation, `6h` solves.
//! Column `6i + c` of `B` belongs to coefficient `c` of handle `i`'s affine map in SVG order
//! `(a, b, c, d, e, f)`, i.e. `T_i = [[a, c, e], [b, d, f]]`: entry `T[r][s]` is coefficient
//! `2s + r`.

use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::Mat;

use super::constraints::junction_rows;
use super::quadrature::SampledCurves;
use super::{FitError, FitOptions};
use crate::drawing::Path;

/// Relative size of the smallest singular value below which a path's system counts as rank
/// deficient (compatibility mode's check): 1e-12.
pub const RANK_TOLERANCE: f64 = 1e-12;

/// Largest KKT size for the dense rank check (the check is `O(N³)`): 4000.
pub const MAX_RANK_CHECK_SIZE: usize = 4000;

/// Which coefficients of the handles' maps the right-hand sides cover.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum HandleMaps {
    /// Affine maps: `6h` columns, column `6i + c` coefficient `c` of handle `i` (SVG order).
    Affine,
    /// Translations only (the maps `[0 0 e; 0 0 f]`, the DefOp join): `2h` columns, column
    /// `2i + d` coordinate `d` of handle `i`'s translation (the affine columns `6i + 4 + d`).
    Translation,
}

/// The solved operator of one path.
pub(crate) struct PathOperator {
    /// `2m × 6h` (or `2m × 2h` for [`HandleMaps::Translation`]), column-major: rows are the
    /// unknowns (point `k`, coordinate `d` at `2k + d`).
    pub operator: Mat<f64>,
    /// Number of constraint rows used.
    pub n_constraints: usize,
    /// Whether the system was found rank deficient (only checked when asked).
    pub rank_deficient: bool,
}

/// Assembles and solves the system of `path` (index `path_index`, for messages), whose first
/// curve is curve `first_curve` of `samples`, for the right-hand sides of `maps`.
pub(crate) fn solve_path(
    path_index: usize,
    path: &Path,
    samples: &SampledCurves,
    first_curve: usize,
    options: &FitOptions,
    maps: HandleMaps,
) -> Result<PathOperator, FitError> {
    let h = samples.n_handles();
    let n_curves = path.n_curves();
    let m = path.n_unknown_points();
    let n_x = 2 * m;
    let unknown = |chain_index: usize| {
        if chain_index >= m {
            chain_index - m
        } else {
            chain_index
        }
    };

    let rows = junction_rows(
        &path.points,
        path.closed,
        &path.joints,
        options.constraint_form,
        &options.junctions,
    );
    let n = n_x + rows.n_rows;

    let mut triplets: Vec<Triplet<usize, usize, f64>> =
        Vec::with_capacity(n_curves * 32 + 2 * rows.entries.len());
    // Homogeneous rows of C̄ kept (x, y, 1 or only 1) and the columns per handle.
    let (first_row, per_handle) = match maps {
        HandleMaps::Affine => (0, 6),
        HandleMaps::Translation => (2, 2),
    };
    let mut rhs = Mat::<f64>::zeros(n, per_handle * h);
    let mut weighted = Vec::with_capacity(h);
    for j in 0..n_curves {
        let c = path.curve_points(j);
        let nodes = samples.curve(first_curve + j);
        let a = nodes.gram();
        nodes.weighted_grams(&mut weighted);
        let idx = [0, 1, 2, 3].map(|k| unknown(3 * j + k));
        for (k, &pk) in idx.iter().enumerate() {
            for (l, &pl) in idx.iter().enumerate() {
                for d in 0..2 {
                    triplets.push(Triplet::new(2 * pk + d, 2 * pl + d, a[k][l]));
                }
            }
        }
        // Ŵ_ij[s][l] = Σ_k C̄[s][k] M_ij[k][l], C̄ rows = (x, y, 1).
        for (i, mij) in weighted.iter().enumerate() {
            for (l, &pl) in idx.iter().enumerate() {
                let mut w = [0.0; 3];
                for (k, ck) in c.iter().enumerate() {
                    w[0] += ck.x * mij[k][l];
                    w[1] += ck.y * mij[k][l];
                    w[2] += mij[k][l];
                }
                for (s, ws) in w.iter().enumerate().skip(first_row) {
                    for d in 0..2 {
                        rhs[(2 * pl + d, per_handle * i + 2 * (s - first_row) + d)] += ws;
                    }
                }
            }
        }
    }
    for &(r, col, v) in &rows.entries {
        triplets.push(Triplet::new(n_x + r, col, v));
        triplets.push(Triplet::new(col, n_x + r, v));
    }
    let kkt = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &triplets).map_err(|e| {
        FitError::Solver {
            path: path_index,
            detail: format!("assembling the system: {e:?}"),
        }
    })?;

    let rank_deficient = options.check_rank && is_rank_deficient(&kkt);
    let lu = kkt.sp_lu().map_err(|e| FitError::Solver {
        path: path_index,
        detail: format!("LU factorisation: {e:?}"),
    })?;
    lu.solve_in_place(rhs.as_mut());

    let operator = rhs.subrows(0, n_x).to_owned();
    if !rank_deficient
        && operator
            .col_iter()
            .any(|c| c.iter().any(|v| !v.is_finite()))
    {
        return Err(FitError::Singular { path: path_index });
    }
    Ok(PathOperator {
        operator,
        n_constraints: rows.n_rows,
        rank_deficient,
    })
}

/// Whether the (small) sparse matrix `k` is numerically singular: smallest singular value below
/// [`RANK_TOLERANCE`] times the largest. Matrices larger than [`MAX_RANK_CHECK_SIZE`] are not
/// checked (reported as full rank).
fn is_rank_deficient(k: &SparseColMat<usize, f64>) -> bool {
    let n = k.nrows();
    if n > MAX_RANK_CHECK_SIZE {
        tracing::warn!("rank check skipped for a system of size {n}");
        return false;
    }
    let dense = k.to_dense();
    match dense.singular_values() {
        Ok(s) => {
            let max = s.iter().cloned().fold(0.0, f64::max);
            let min = s.iter().cloned().fold(f64::INFINITY, f64::min);
            min <= RANK_TOLERANCE * max
        }
        Err(_) => true,
    }
}
