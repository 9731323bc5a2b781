//! A sparse LU factorisation with partial pivoting, for a system factored once and solved for
//! many right-hand sides: the fit's KKT system `[H Cᵀ; C 0]` (`spline_fit::system`), solved
//! for the `6h` columns of the handles' maps.
//!
//! ```text
//! P A Q = L U   (faer's supernodal or simplicial sparse LU, column order COLAMD)
//! X ← A⁻¹ X     (in place, every column of X)
//! ```

use faer::linalg::solvers::Solve;
use faer::sparse::SparseColMat;
use faer::MatMut;

use super::LinalgError;

/// Overwrites every column of `rhs` with `A⁻¹` times it, `A` square and invertible, by one
/// sparse LU factorisation (faer's `sp_lu`). Errors when the factorisation fails; a singular
/// `A` that factors leaves non-finite values in `rhs`, which the caller checks.
///
/// ```text
/// [ 2 1 ] x = [ 3 ]   →   x = (1, 1)
/// [ 1 3 ]     [ 4 ]
/// ```
pub fn lu_solve_in_place(
    a: &SparseColMat<usize, f64>,
    rhs: MatMut<'_, f64>,
) -> Result<(), LinalgError> {
    let lu = a
        .sp_lu()
        .map_err(|e| LinalgError::new("LU factorisation", e))?;
    lu.solve_in_place(rhs);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::sparse::Triplet;
    use faer::Mat;

    #[test]
    fn lu_solves_a_nonsymmetric_system_for_two_columns() {
        // A = [[2, 1, 0], [0, 3, 1], [1, 0, 4]], x₁ = (1, 2, 3), x₂ = (−1, 0, 2).
        let entries = [
            (0, 0, 2.0),
            (0, 1, 1.0),
            (1, 1, 3.0),
            (1, 2, 1.0),
            (2, 0, 1.0),
            (2, 2, 4.0),
        ];
        let triplets: Vec<_> = entries
            .iter()
            .map(|&(i, j, v)| Triplet::new(i, j, v))
            .collect();
        let a = SparseColMat::<usize, f64>::try_new_from_triplets(3, 3, &triplets).unwrap();
        let x = [[1.0, 2.0, 3.0], [-1.0, 0.0, 2.0]];
        let mut b = Mat::<f64>::zeros(3, 2);
        for (c, xc) in x.iter().enumerate() {
            for &(i, j, v) in &entries {
                b[(i, c)] += v * xc[j];
            }
        }
        lu_solve_in_place(&a, b.as_mut()).unwrap();
        for (c, xc) in x.iter().enumerate() {
            for (i, &want) in xc.iter().enumerate() {
                assert!((b[(i, c)] - want).abs() <= 1e-14, "{c} {i}: {}", b[(i, c)]);
            }
        }
    }
}
