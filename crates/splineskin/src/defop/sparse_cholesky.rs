//! A sparse Cholesky factorisation split into its symbolic analysis (once per sparsity
//! pattern: fill-reducing ordering and elimination structure) and its numeric factorisation
//! (per set of values), with solves that allocate nothing (the caller owns the workspace).
//!
//! This is faer's low-level API (`factorize_symbolic_cholesky` with its AMD ordering,
//! `factorize_numeric_llt`, `LltRef::solve_in_place_with_conj`), sequential as STACK.md asks.
//! The ARAP global step factors once and solves every iteration; the SARAP Newton step
//! refactors numerically each iteration on the pattern analysed once.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky,
    SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

use super::DefOpError;

/// The symbolic analysis of a symmetric `n × n` pattern given by its upper triangle in
/// compressed sparse columns with sorted rows.
#[derive(Debug)]
pub(crate) struct CholeskyAnalysis {
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
    ) -> Result<CholeskyAnalysis, DefOpError> {
        let pattern = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
        let symbolic = factorize_symbolic_cholesky(
            pattern,
            Side::Upper,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams::default(),
        )
        .map_err(|e| factorization_error("symbolic analysis", e))?;
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

    /// A workspace for [`CholeskyAnalysis::factor`] and for solves with up to `n_rhs`
    /// right-hand sides.
    pub fn workspace(&self, n_rhs: usize) -> Result<MemBuffer, DefOpError> {
        let request = self
            .symbolic
            .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default())
            .or(self.symbolic.solve_in_place_scratch::<f64>(n_rhs, Par::Seq));
        MemBuffer::try_new(request).map_err(|e| factorization_error("workspace", e))
    }

    /// Factors the matrix with upper-triangle `values` (in this pattern's order) into
    /// `factor` (length [`CholeskyAnalysis::factor_len`]). Errors when a pivot is not
    /// positive: the matrix is not numerically positive definite.
    pub fn factor(
        &self,
        values: &[f64],
        factor: &mut [f64],
        workspace: &mut MemBuffer,
    ) -> Result<(), DefOpError> {
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
            .map_err(|e| factorization_error("numeric factorisation", e))
    }

    /// Overwrites `rhs` (`n × n_rhs`, column-major) with `A⁻¹ rhs` for the matrix factored
    /// into `factor`.
    pub fn solve(&self, factor: &[f64], rhs: &mut [f64], workspace: &mut MemBuffer) {
        let n_rhs = rhs.len() / self.n.max(1);
        if self.n == 0 {
            return;
        }
        LltRef::new(&self.symbolic, factor).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, self.n, n_rhs),
            Par::Seq,
            MemStack::new(workspace),
        );
    }
}

fn factorization_error(stage: &str, e: impl std::fmt::Debug) -> DefOpError {
    DefOpError::Factorization {
        detail: format!("{stage}: {e:?}"),
    }
}
