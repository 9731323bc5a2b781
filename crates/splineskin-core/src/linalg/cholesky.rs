//! A sparse Cholesky factorisation `A = L Lᵀ` of a symmetric positive definite matrix, split
//! into its symbolic analysis (once per sparsity pattern: elimination order and structure) and
//! its numeric factorisation (per set of values), with solves that allocate nothing (the caller
//! owns the workspace). Shared by the weight solvers (`weights`), the ground-truth deformations
//! (`defop`), the spatial bases of the deformation operators and the subdivision rig and its
//! bone-heat weights ([`solve_spd_in_place`], one system solved once, given as the upper
//! triangle in a [`Csc`]).
//!
//! ```text
//! once per pattern:   CholeskyAnalysis::new(n, col_ptr, row_idx, ordering)   (upper triangle, sorted rows)
//! per set of values:  analysis.factor(&values, &mut factor, &mut workspace)
//! per right-hand side: analysis.solve(&factor, &mut rhs, &mut workspace)     (rhs ← A⁻¹ rhs)
//! ```
//!
//! This is faer's low-level API (`factorize_symbolic_cholesky`, `factorize_numeric_llt`,
//! `LltRef::solve_in_place_with_conj`), sequential as STACK.md asks. [`Ordering::Amd`] lets faer
//! order the pattern; [`Ordering::Identity`] keeps the caller's order, for callers that ordered
//! a larger matrix once and factor principal submatrices of it in the induced order.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky,
    SymmetricOrdering,
};
use faer::sparse::linalg::{amd, SupernodalThreshold};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

use super::{Csc, LinalgError};

/// When faer factors supernodally (dense blocks) rather than column by column: when the
/// factorisation's flops per entry of the factor exceed 10, a quarter of faer's default 40.
/// Our systems are cotangent Laplacians and their squares on 2-D meshes; on them the blocked
/// kernel is already faster at that density. Measured (sequential, 2-core x86-64): harmonic
/// weights of the 19 727-vertex turtles domain 47 → 37 ms, bounded biharmonic weights (one
/// factorisation per active-set step) of libigl's 575- and 1 091-vertex test shapes 22 → 18 ms
/// and 77 → 67 ms. Small or very sparse systems stay simplicial.
const SUPERNODAL_THRESHOLD: SupernodalThreshold = SupernodalThreshold(0.25);

/// The elimination order of a [`CholeskyAnalysis`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ordering {
    /// Approximate minimum degree, computed by faer from the pattern.
    Amd,
    /// The pattern's own order (the caller has already ordered it).
    Identity,
}

/// The symbolic analysis of a symmetric `n × n` pattern given by its upper triangle in
/// compressed sparse columns with sorted rows.
#[derive(Debug)]
pub struct CholeskyAnalysis {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    symbolic: SymbolicCholesky<usize>,
}

impl CholeskyAnalysis {
    /// Analyses the pattern (upper triangle, sorted rows, diagonal present in every column).
    pub fn new(
        n: usize,
        col_ptr: Vec<usize>,
        row_idx: Vec<usize>,
        ordering: Ordering,
    ) -> Result<CholeskyAnalysis, LinalgError> {
        let pattern = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
        let ordering = match ordering {
            Ordering::Amd => SymmetricOrdering::Amd,
            Ordering::Identity => SymmetricOrdering::Identity,
        };
        let symbolic = factorize_symbolic_cholesky(
            pattern,
            Side::Upper,
            ordering,
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: SUPERNODAL_THRESHOLD,
                ..Default::default()
            },
        )
        .map_err(|e| LinalgError::new("symbolic analysis", e))?;
        Ok(CholeskyAnalysis {
            n,
            col_ptr,
            row_idx,
            symbolic,
        })
    }

    /// Order of the matrix.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Number of stored (upper-triangle) entries: the length of a values array.
    pub fn n_entries(&self) -> usize {
        self.row_idx.len()
    }

    /// Number of values of the factor.
    pub fn factor_len(&self) -> usize {
        self.symbolic.len_val()
    }

    /// Position in the values array of entry `(row, col)`, `row ≤ col`, if stored.
    pub fn entry(&self, row: usize, col: usize) -> Option<usize> {
        let range = self.col_ptr[col]..self.col_ptr[col + 1];
        self.row_idx[range.clone()]
            .binary_search(&row)
            .ok()
            .map(|k| range.start + k)
    }

    /// The workspace [`CholeskyAnalysis::factor`] and solves with up to `n_rhs` right-hand
    /// sides need.
    pub fn workspace_request(&self, n_rhs: usize) -> StackReq {
        self.symbolic
            .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default())
            .or(self.symbolic.solve_in_place_scratch::<f64>(n_rhs, Par::Seq))
    }

    /// A workspace for [`CholeskyAnalysis::factor`] and for solves with up to `n_rhs`
    /// right-hand sides.
    pub fn workspace(&self, n_rhs: usize) -> Result<MemBuffer, LinalgError> {
        MemBuffer::try_new(self.workspace_request(n_rhs))
            .map_err(|e| LinalgError::new("workspace", e))
    }

    /// Factors the matrix with upper-triangle `values` (in this pattern's order) into
    /// `factor` (length [`CholeskyAnalysis::factor_len`]). Errors when a pivot is not
    /// positive: the matrix is not numerically positive definite.
    pub fn factor(
        &self,
        values: &[f64],
        factor: &mut [f64],
        workspace: &mut MemBuffer,
    ) -> Result<(), LinalgError> {
        let pattern = SymbolicSparseColMatRef::new_checked(
            self.n,
            self.n,
            &self.col_ptr,
            None,
            &self.row_idx,
        );
        self.symbolic
            .factorize_numeric_llt(
                factor,
                SparseColMatRef::new(pattern, values),
                Side::Upper,
                LltRegularization::default(),
                Par::Seq,
                MemStack::new(workspace),
                Default::default(),
            )
            .map(|_| ())
            .map_err(|e| LinalgError::new("numeric factorisation", e))
    }

    /// Factors the matrix with upper-triangle `values` into a new factor, with a new workspace
    /// for solves with up to `n_rhs` right-hand sides: [`CholeskyAnalysis::factor`] for a
    /// system factored once.
    pub fn factored(
        &self,
        values: &[f64],
        n_rhs: usize,
    ) -> Result<(Vec<f64>, MemBuffer), LinalgError> {
        let mut factor = vec![0.0; self.factor_len()];
        let mut workspace = self.workspace(n_rhs)?;
        self.factor(values, &mut factor, &mut workspace)?;
        Ok((factor, workspace))
    }

    /// Overwrites `rhs` (`n × n_rhs`, column-major) with `A⁻¹ rhs` for the matrix factored
    /// into `factor`. The workspace must have been sized for at least `n_rhs` columns.
    pub fn solve(&self, factor: &[f64], rhs: &mut [f64], workspace: &mut MemBuffer) {
        self.solve_in_stack(factor, rhs, MemStack::new(workspace));
    }

    /// [`CholeskyAnalysis::solve`] with a borrowed stack (of at least
    /// [`CholeskyAnalysis::workspace_request`]).
    pub fn solve_in_stack(&self, factor: &[f64], rhs: &mut [f64], stack: &mut MemStack) {
        if self.n == 0 {
            return;
        }
        let n_rhs = rhs.len() / self.n;
        LltRef::new(&self.symbolic, factor).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, self.n, n_rhs),
            Par::Seq,
            stack,
        );
    }
}

/// Number of right-hand sides [`solve_spd_in_place`] solves together.
const SOLVE_BLOCK: usize = 64;

/// Solves `A X = R` in place for the columns of `rhs` (column-major, `n` rows each) with one
/// factorisation of the symmetric positive definite `A` given by its upper triangle ([`Ordering::Amd`];
/// the columns in blocks of 64). For one system solved once (the subdivision rig's Gram
/// matrix, bone-heat weights); a pattern factored many times keeps its [`CholeskyAnalysis`].
pub fn solve_spd_in_place(a: &Csc, rhs: &mut [f64]) -> Result<(), LinalgError> {
    if a.n == 0 {
        return Ok(());
    }
    let analysis = CholeskyAnalysis::new(a.n, a.col_ptr.clone(), a.row_idx.clone(), Ordering::Amd)?;
    let (factor, mut workspace) = analysis.factored(&a.values, SOLVE_BLOCK)?;
    for block in rhs.chunks_mut(a.n * SOLVE_BLOCK) {
        analysis.solve(&factor, block, &mut workspace);
    }
    Ok(())
}

/// The approximate minimum degree order of the symmetric pattern `pattern` (full storage,
/// sorted rows; faer's AMD with default parameters): `(order, inverse)` with `order[k]` the
/// index eliminated `k`-th and `inverse[order[k]] = k`. For callers that order a matrix once
/// and factor principal submatrices of it in the induced order ([`Ordering::Identity`]).
pub fn amd_order(pattern: &Csc) -> Result<(Vec<usize>, Vec<usize>), LinalgError> {
    let n = pattern.n;
    let mut order = vec![0usize; n];
    let mut inverse = vec![0usize; n];
    let mut memory = MemBuffer::try_new(amd::order_scratch::<usize>(n, pattern.row_idx.len()))
        .map_err(|e| LinalgError::new("AMD workspace", e))?;
    let symbolic =
        SymbolicSparseColMatRef::new_checked(n, n, &pattern.col_ptr, None, &pattern.row_idx);
    amd::order(
        &mut order,
        &mut inverse,
        symbolic,
        amd::Control::default(),
        MemStack::new(&mut memory),
    )
    .map_err(|e| LinalgError::new("AMD ordering", e))?;
    Ok((order, inverse))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tridiagonal `[-1 2 -1]` matrix of order `n` (upper triangle), a 1-D Laplacian with
    /// both ends fixed: symmetric positive definite.
    fn tridiagonal(n: usize) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
        let (mut col_ptr, mut row_idx, mut values) = (vec![0], Vec::new(), Vec::new());
        for j in 0..n {
            if j > 0 {
                row_idx.push(j - 1);
                values.push(-1.0);
            }
            row_idx.push(j);
            values.push(2.0);
            col_ptr.push(row_idx.len());
        }
        (col_ptr, row_idx, values)
    }

    #[test]
    fn sparse_cholesky_solves_both_orderings() {
        let n = 7;
        let (col_ptr, row_idx, values) = tridiagonal(n);
        // A x = b for x = (1, 2, …, n): b_i = 2x_i − x_{i−1} − x_{i+1}.
        let x: Vec<f64> = (1..=n).map(|i| i as f64).collect();
        let b: Vec<f64> = (0..n)
            .map(|i| 2.0 * x[i] - if i > 0 { x[i - 1] } else { 0.0 } - x.get(i + 1).unwrap_or(&0.0))
            .collect();
        for ordering in [Ordering::Amd, Ordering::Identity] {
            let analysis =
                CholeskyAnalysis::new(n, col_ptr.clone(), row_idx.clone(), ordering).unwrap();
            assert_eq!(analysis.n_entries(), values.len());
            assert_eq!(analysis.entry(2, 3), Some(5));
            assert_eq!(analysis.entry(1, 3), None);
            let mut factor = vec![0.0; analysis.factor_len()];
            let mut workspace = analysis.workspace(2).unwrap();
            analysis
                .factor(&values, &mut factor, &mut workspace)
                .unwrap();
            let mut rhs = [b.clone(), b.clone()].concat();
            analysis.solve(&factor, &mut rhs, &mut workspace);
            for (got, want) in rhs.iter().zip(x.iter().chain(&x)) {
                assert!((got - want).abs() < 1e-12, "{ordering:?}: {got} vs {want}");
            }
        }
    }

    #[test]
    fn sparse_cholesky_rejects_indefinite_matrix() {
        let (col_ptr, row_idx, mut values) = tridiagonal(4);
        values.iter_mut().for_each(|v| *v = -*v);
        let analysis = CholeskyAnalysis::new(4, col_ptr, row_idx, Ordering::Amd).unwrap();
        let mut factor = vec![0.0; analysis.factor_len()];
        let mut workspace = analysis.workspace(1).unwrap();
        let e = analysis
            .factor(&values, &mut factor, &mut workspace)
            .unwrap_err();
        assert_eq!(e.stage, "numeric factorisation");
    }
}
