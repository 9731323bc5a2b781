//! [`Csc`]: the square sparse matrix in compressed columns that the mesh operators build and
//! the factorisations take.

use faer::sparse::{SparseColMat, SymbolicSparseColMat};

/// Wraps sorted CSC arrays into faer's matrix (the arrays are built valid by [`Csc`]'s constructors).
fn csc(
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    values: Vec<f64>,
) -> SparseColMat<usize, f64> {
    let symbolic = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
    SparseColMat::new(symbolic, values)
}

/// A square sparse matrix in compressed sparse column form with sorted row indices: the
/// working form of the mesh operators and the weight solvers (faer's matrices are built from
/// and converted to it), and of the factorisations of [`super::cholesky`], which take the upper
/// triangle of a symmetric matrix in this form.
#[derive(Clone, Debug, PartialEq)]
pub struct Csc {
    /// The order `n`.
    pub n: usize,
    /// Where each column starts in `row_idx` and `values` (`n + 1` entries).
    pub col_ptr: Vec<usize>,
    /// The row of each stored entry, sorted within each column.
    pub row_idx: Vec<usize>,
    /// The value of each stored entry.
    pub values: Vec<f64>,
}

impl Csc {
    /// The square matrix of order `n` whose column `j` holds the entries `(row, value)` that
    /// `fill(j, column)` writes into `column` (cleared before each call), sorted by row;
    /// `capacity` is the expected number of entries.
    pub fn from_columns(
        n: usize,
        capacity: usize,
        mut fill: impl FnMut(usize, &mut Vec<(usize, f64)>),
    ) -> Csc {
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::with_capacity(capacity);
        let mut values = Vec::with_capacity(capacity);
        let mut column = Vec::new();
        col_ptr.push(0);
        for j in 0..n {
            column.clear();
            fill(j, &mut column);
            row_idx.extend(column.iter().map(|&(i, _)| i));
            values.extend(column.iter().map(|&(_, x)| x));
            col_ptr.push(row_idx.len());
        }
        Csc {
            n,
            col_ptr,
            row_idx,
            values,
        }
    }

    /// Column `j` of the faer matrix `m`, `(row, value)` sorted by row, into `column`.
    fn sorted_column_of(m: &SparseColMat<usize, f64>, j: usize, column: &mut Vec<(usize, f64)>) {
        let range = m.col_range(j);
        column.extend(
            m.symbolic().row_idx()[range.clone()]
                .iter()
                .copied()
                .zip(m.val()[range].iter().copied()),
        );
        column.sort_unstable_by_key(|&(i, _)| i);
    }

    /// Copies a faer matrix (square; rows sorted here).
    #[cfg(test)]
    pub fn from_faer(m: &SparseColMat<usize, f64>) -> Csc {
        Csc::from_columns(m.ncols(), m.compute_nnz(), |j, column| {
            Csc::sorted_column_of(m, j, column)
        })
    }

    /// The square matrix of order `n` whose entry `(row, col)` is the sum of the triplets
    /// `(row, col, value)` given for it (sorted rows, explicit zeros kept).
    pub fn from_triplets(n: usize, mut triplets: Vec<(usize, usize, f64)>) -> Csc {
        triplets.sort_unstable_by_key(|&(row, col, _)| (col, row));
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx: Vec<usize> = Vec::new();
        let mut values: Vec<f64> = Vec::new();
        col_ptr.push(0);
        let mut next = 0;
        for col in 0..n {
            let start = row_idx.len();
            while next < triplets.len() && triplets[next].1 == col {
                let (row, _, value) = triplets[next];
                if row_idx.len() > start && row_idx.last() == Some(&row) {
                    if let Some(last) = values.last_mut() {
                        *last += value;
                    }
                } else {
                    row_idx.push(row);
                    values.push(value);
                }
                next += 1;
            }
            col_ptr.push(row_idx.len());
        }
        Csc {
            n,
            col_ptr,
            row_idx,
            values,
        }
    }

    /// The upper triangle of the symmetric matrix with upper-triangle entries `entries`
    /// (`(row, column, value)`, `row ≤ column`, repeated entries summed, in any order) plus
    /// `diagonal` on the diagonal (`n` long): [`Csc::from_triplets`] of both.
    pub fn upper_from_entries(
        n: usize,
        mut entries: Vec<(usize, usize, f64)>,
        diagonal: &[f64],
    ) -> Csc {
        entries.extend(diagonal.iter().enumerate().map(|(i, &d)| (i, i, d)));
        Csc::from_triplets(n, entries)
    }

    /// The upper triangle of `m` (a full symmetric faer matrix), with `shift[j]` added to each
    /// diagonal entry `j` (a diagonal missing from `m` is created).
    pub fn upper_from_symmetric(m: &SparseColMat<usize, f64>, shift: &[f64]) -> Csc {
        Csc::from_columns(m.nrows(), 0, |j, column| {
            Csc::sorted_column_of(m, j, column);
            column.retain(|&(i, _)| i <= j);
            match column.last_mut() {
                Some((i, x)) if *i == j => *x += shift[j],
                _ => column.push((j, shift[j])),
            }
        })
    }

    /// The matrix as faer's.
    pub fn into_faer(self) -> SparseColMat<usize, f64> {
        csc(self.n, self.col_ptr, self.row_idx, self.values)
    }

    /// `s · self`.
    pub fn scaled(mut self, s: f64) -> Csc {
        self.values.iter_mut().for_each(|v| *v *= s);
        self
    }

    /// Rows `col_ptr[j]..col_ptr[j+1]` of column `j` and their values.
    pub fn column(&self, j: usize) -> (&[usize], &[f64]) {
        let r = self.col_ptr[j]..self.col_ptr[j + 1];
        (&self.row_idx[r.clone()], &self.values[r])
    }

    /// `self · diag(d) · rhs` by Gustavson's column-by-column product: column `j` of the
    /// result is `Σ_k self[:, k] d_k rhs[k, j]`.
    pub fn times_diagonal_times(&self, d: &[f64], rhs: &Csc) -> Csc {
        let n = self.n;
        let mut accumulator = vec![0.0; n];
        let mut marker = vec![usize::MAX; n];
        let mut pattern = Vec::new();
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        let mut values = Vec::new();
        col_ptr.push(0);
        for j in 0..n {
            pattern.clear();
            let (ks, bs) = rhs.column(j);
            for (&k, &b) in ks.iter().zip(bs) {
                let scale = d[k] * b;
                let (is, avs) = self.column(k);
                for (&i, &a) in is.iter().zip(avs) {
                    if marker[i] != j {
                        marker[i] = j;
                        accumulator[i] = 0.0;
                        pattern.push(i);
                    }
                    accumulator[i] += a * scale;
                }
            }
            pattern.sort_unstable();
            for &i in &pattern {
                row_idx.push(i);
                values.push(accumulator[i]);
            }
            col_ptr.push(row_idx.len());
        }
        Csc {
            n,
            col_ptr,
            row_idx,
            values,
        }
    }
}
