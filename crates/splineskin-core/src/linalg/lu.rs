//! An LU factorisation with partial pivoting, for a system factored once and solved for many
//! right-hand sides: the fit's KKT system `[H Cᵀ; C 0]` (`spline_fit::system`), solved for the
//! `6h` columns of the handles' maps.
//!
//! ```text
//! P A Q = L U   (n ≤ DENSE_MAX: faer's dense LU, Q = I; larger: faer's sparse LU, Q = COLAMD)
//! X ← A⁻¹ X     (in place, every column of X)
//! ```
//!
//! The matrix arrives as `(row, column, value)` entries, duplicates summed. Most paths of a
//! drawing give small systems (a path of 25 control points: 50 unknowns and its junction
//! rows), for which the sparse machinery (column ordering, symbolic analysis, compressed
//! storage) costs more than the dense elimination itself: on a drawing of 100 000 curves in
//! 28 000 paths of 4–25 points the fit's precompute took 0.87 s with the sparse LU everywhere.

use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, MatMut};

use super::LinalgError;

/// Largest order solved densely: 96 (a dense LU of order 96 is about 0.6 Mflop, and its
/// storage 74 KB).
pub const DENSE_MAX: usize = 96;

/// Overwrites every column of `rhs` with `A⁻¹` times it, `A` the square `n × n` matrix with
/// `entries` (duplicates summed; every index below `n`), by one LU factorisation: dense when
/// `n ≤ DENSE_MAX`, else faer's sparse `sp_lu`. Errors when an entry is out of range or the
/// sparse factorisation fails; a singular `A` that factors leaves non-finite values in `rhs`,
/// which the caller checks.
///
/// ```
/// use faer::{mat, sparse::Triplet};
/// use splineskin_core::linalg::lu_solve_in_place;
/// // [2 1; 1 3] x = [3; 4]  →  x = (1, 1)
/// let a = [Triplet::new(0, 0, 2.0), Triplet::new(0, 1, 1.0), Triplet::new(1, 0, 1.0),
///          Triplet::new(1, 1, 3.0)];
/// let mut x = mat![[3.0], [4.0]];
/// lu_solve_in_place(2, &a, x.as_mut())?;
/// assert!((x[(0, 0)] - 1.0).abs() < 1e-15 && (x[(1, 0)] - 1.0).abs() < 1e-15);
/// # Ok::<(), splineskin_core::linalg::LinalgError>(())
/// ```
pub fn lu_solve_in_place(
    n: usize,
    entries: &[Triplet<usize, usize, f64>],
    rhs: MatMut<'_, f64>,
) -> Result<(), LinalgError> {
    if n <= DENSE_MAX {
        dense(n, entries)?.partial_piv_lu().solve_in_place(rhs);
        return Ok(());
    }
    let a = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, entries)
        .map_err(|e| LinalgError::new("assembling the matrix", e))?;
    let lu = a
        .sp_lu()
        .map_err(|e| LinalgError::new("LU factorisation", e))?;
    lu.solve_in_place(rhs);
    Ok(())
}

/// The dense `n × n` matrix with `entries` (duplicates summed).
pub fn dense(n: usize, entries: &[Triplet<usize, usize, f64>]) -> Result<Mat<f64>, LinalgError> {
    let mut a = Mat::<f64>::zeros(n, n);
    for e in entries {
        if e.row >= n || e.col >= n {
            return Err(LinalgError {
                stage: "assembling the matrix",
                detail: format!("entry ({}, {}) outside {n} × {n}", e.row, e.col),
            });
        }
        a[(e.row, e.col)] += e.val;
    }
    Ok(a)
}

#[cfg(test)]
mod tests {
    use super::*;

    type Entry = Triplet<usize, usize, f64>;

    /// A nonsymmetric KKT-like `n × n` matrix `[H Cᵀ; C 0]` (pivoting needed): `H` of order
    /// `n − n/4`, 4 on the diagonal, −1 above and −0.5 below it; `C` with `n/4` rows
    /// `e_{3k} − e_{3k+1}`; and its product with two known columns.
    fn kkt_like(n: usize) -> (Vec<Entry>, [Vec<f64>; 2], Mat<f64>) {
        let r = n / 4;
        let m = n - r;
        let mut entries = Vec::new();
        for i in 0..m {
            entries.push(Triplet::new(i, i, 4.0));
            if i + 1 < m {
                entries.push(Triplet::new(i, i + 1, -1.0));
                entries.push(Triplet::new(i + 1, i, -0.5));
            }
        }
        for k in 0..r {
            for (col, v) in [(3 * k, 1.0), (3 * k + 1, -1.0)] {
                entries.push(Triplet::new(m + k, col, v));
                entries.push(Triplet::new(col, m + k, v));
            }
        }
        let x = [
            (0..n).map(|i| 1.0 + i as f64).collect::<Vec<_>>(),
            (0..n).map(|i| ((i * 7) % 5) as f64 - 2.0).collect(),
        ];
        let mut b = Mat::<f64>::zeros(n, 2);
        for (c, xc) in x.iter().enumerate() {
            for e in &entries {
                b[(e.row, c)] += e.val * xc[e.col];
            }
        }
        (entries, x, b)
    }

    #[test]
    fn lu_solves_dense_and_sparse_sizes() {
        // Below, at and above DENSE_MAX: both factorisations.
        for n in [3, DENSE_MAX, DENSE_MAX + 1, 400] {
            let (entries, x, mut b) = kkt_like(n);
            lu_solve_in_place(n, &entries, b.as_mut()).unwrap();
            // The solutions reach n in size.
            let scale = n as f64;
            for (c, xc) in x.iter().enumerate() {
                for (i, &want) in xc.iter().enumerate() {
                    let got = b[(i, c)];
                    assert!(
                        (got - want).abs() <= 1e-13 * scale,
                        "n {n}, column {c}, row {i}: {got}"
                    );
                }
            }
        }
    }

    #[test]
    fn lu_rejects_entries_outside_the_matrix() {
        for n in [2, DENSE_MAX + 1] {
            let entries = [Triplet::new(0, 0, 1.0), Triplet::new(n, 0, 1.0)];
            let mut b = Mat::<f64>::zeros(n, 1);
            let e = lu_solve_in_place(n, &entries, b.as_mut()).unwrap_err();
            assert_eq!(e.stage, "assembling the matrix", "n {n}: {e}");
        }
    }
}
