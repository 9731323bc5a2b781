//! One sparse Cholesky factorisation, many right-hand sides: the linear algebra of the rig
//! (`Â`, [`super::SubdivRig`]) and of bone-heat weights (`−L + M H`,
//! [`super::surface_weights::BoneHeat`]).
//!
//! faer's supernodal or simplicial `LLᵀ` (as faer chooses), AMD ordering, sequential
//! (STACK.md: on 2 cores the parallel path is slower at these sizes).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

/// Number of right-hand sides solved together.
const SOLVE_BLOCK: usize = 64;

/// The upper triangle of a symmetric `n × n` matrix in compressed columns (row indices sorted
/// within each column).
#[derive(Clone, Debug, Default)]
pub(crate) struct UpperCsc {
    pub n: usize,
    pub col_ptr: Vec<usize>,
    pub row_idx: Vec<usize>,
    pub values: Vec<f64>,
}

impl UpperCsc {
    /// The upper triangle of `m` (a full symmetric faer matrix), with `shift[j]` added to each
    /// diagonal entry `j` (a diagonal missing from `m` is created).
    pub fn from_symmetric(m: &faer::sparse::SparseColMat<usize, f64>, shift: &[f64]) -> Self {
        let n = m.nrows();
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        let mut values = Vec::new();
        col_ptr.push(0);
        for j in 0..n {
            let range = m.col_range(j);
            let mut column: Vec<(usize, f64)> = m.symbolic().row_idx()[range.clone()]
                .iter()
                .zip(&m.val()[range])
                .filter(|(&i, _)| i <= j)
                .map(|(&i, &x)| (i, x))
                .collect();
            column.sort_unstable_by_key(|&(i, _)| i);
            match column.last_mut() {
                Some((i, x)) if *i == j => *x += shift[j],
                _ => column.push((j, shift[j])),
            }
            row_idx.extend(column.iter().map(|&(i, _)| i));
            values.extend(column.iter().map(|&(_, x)| x));
            col_ptr.push(row_idx.len());
        }
        UpperCsc {
            n,
            col_ptr,
            row_idx,
            values,
        }
    }
}

impl UpperCsc {
    /// The symmetric matrix with upper-triangle entries `entries` (`(row, column, value)`,
    /// `row ≤ column`, repeated entries summed, in any order) plus `diagonal` on the diagonal
    /// (`n` long).
    pub fn from_entries(n: usize, mut entries: Vec<(usize, usize, f64)>, diagonal: &[f64]) -> Self {
        entries.extend(diagonal.iter().enumerate().map(|(i, &d)| (i, i, d)));
        entries.sort_unstable_by_key(|&(i, j, _)| (j, i));
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::with_capacity(entries.len());
        let mut values = Vec::with_capacity(entries.len());
        col_ptr.push(0);
        let mut k = 0;
        for j in 0..n {
            while k < entries.len() && entries[k].1 == j {
                let (i, _, mut x) = entries[k];
                k += 1;
                while k < entries.len() && entries[k].0 == i && entries[k].1 == j {
                    x += entries[k].2;
                    k += 1;
                }
                row_idx.push(i);
                values.push(x);
            }
            col_ptr.push(row_idx.len());
        }
        UpperCsc {
            n,
            col_ptr,
            row_idx,
            values,
        }
    }
}

/// Solves `A X = R` in place for the columns of `rhs` (column-major, `n` rows each) with one
/// factorisation of the symmetric positive definite `A` given by its upper triangle. The error
/// is faer's, with the stage that failed.
pub(crate) fn solve_spd_in_place(a: &UpperCsc, rhs: &mut [f64]) -> Result<(), String> {
    let n = a.n;
    if n == 0 {
        return Ok(());
    }
    let upper = SymbolicSparseColMatRef::new_checked(n, n, &a.col_ptr, None, &a.row_idx);
    let failed = |stage: &str, e: &dyn std::fmt::Debug| format!("{stage} failed ({e:?})");
    let symbolic = factorize_symbolic_cholesky(
        upper,
        Side::Upper,
        SymmetricOrdering::Amd,
        CholeskySymbolicParams::default(),
    )
    .map_err(|e| failed("symbolic analysis", &e))?;
    let mut l_values = vec![0.0; symbolic.len_val()];
    let scratch = symbolic
        .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default())
        .or(symbolic.solve_in_place_scratch::<f64>(SOLVE_BLOCK, Par::Seq));
    let mut memory = MemBuffer::try_new(scratch).map_err(|e| failed("workspace", &e))?;
    symbolic
        .factorize_numeric_llt(
            &mut l_values,
            SparseColMatRef::new(upper, &a.values),
            Side::Upper,
            LltRegularization::default(),
            Par::Seq,
            MemStack::new(&mut memory),
            Default::default(),
        )
        .map_err(|e| failed("numeric factorisation", &e))?;
    let llt = LltRef::new(&symbolic, &l_values);
    for block in rhs.chunks_mut(n * SOLVE_BLOCK) {
        let k = block.len() / n;
        llt.solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(block, n, k),
            Par::Seq,
            MemStack::new(&mut memory),
        );
    }
    Ok(())
}
