//! [`DirichletData`]: prescribed values at a set of mesh vertices — the boundary conditions of
//! the harmonic and bounded biharmonic solves.
//!
//! Point handles prescribe the identity (`w_i = 1` at handle `i`'s vertex, 0 at the other
//! handles'; [`DirichletData::handles`]); a cage prescribes piecewise linear values along its
//! edges (harmonic coordinates); any other data fits the same shape.

use super::WeightsError;

/// Values prescribed at `n_fixed` distinct vertices for `n_columns` weight functions.
///
/// ```
/// use splineskin_core::weights::DirichletData;
/// let handles = DirichletData::handles(&[4, 9])?;
/// assert_eq!(handles.n_columns(), 2);
/// assert_eq!(handles.values_at(1), &[0.0, 1.0]); // at vertex 9
///
/// // Two vertices, one column: w = 0 at vertex 0 and w = 2 at vertex 3.
/// let data = DirichletData::new(vec![0, 3], vec![0.0, 2.0], 1)?;
/// assert_eq!(data.vertices(), &[0, 3]);
/// # Ok::<(), splineskin_core::weights::WeightsError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct DirichletData {
    vertices: Vec<usize>,
    values: Vec<f64>,
    n_columns: usize,
}

impl DirichletData {
    /// `values` (`vertices.len() × n_columns`, row-major: row `r` holds the values at
    /// `vertices[r]`). Errors if there is no vertex or no column, the vertices repeat, the
    /// shape is wrong, or a value is not finite. Whether the vertices exist is checked
    /// against the mesh by the solvers.
    pub fn new(
        vertices: Vec<usize>,
        values: Vec<f64>,
        n_columns: usize,
    ) -> Result<DirichletData, WeightsError> {
        if vertices.is_empty() || n_columns == 0 {
            return Err(WeightsError::NoHandles);
        }
        let n_fixed = vertices.len();
        if n_fixed.checked_mul(n_columns) != Some(values.len()) {
            return Err(WeightsError::DirichletShape {
                len: values.len(),
                n_fixed,
                n_columns,
            });
        }
        let mut order: Vec<usize> = (0..n_fixed).collect();
        order.sort_by_key(|&r| (vertices[r], r));
        for pair in order.windows(2) {
            if vertices[pair[0]] == vertices[pair[1]] {
                return Err(WeightsError::DuplicateHandle {
                    vertex: vertices[pair[0]],
                    first: pair[0],
                    second: pair[1],
                });
            }
        }
        if let Some(k) = values.iter().position(|v| !v.is_finite()) {
            return Err(WeightsError::NonFiniteValue {
                row: k / n_columns,
                vertex: vertices[k / n_columns],
                column: k % n_columns,
                value: values[k],
            });
        }
        Ok(DirichletData {
            vertices,
            values,
            n_columns,
        })
    }

    /// Point handles at `handles` (vertex indices): column `i` is 1 at `handles[i]` and 0 at
    /// the other handles (libigl's `bc = eye(#handles)`).
    pub fn handles(handles: &[usize]) -> Result<DirichletData, WeightsError> {
        let h = handles.len();
        let mut values = vec![0.0; h * h];
        for i in 0..h {
            values[i * h + i] = 1.0;
        }
        DirichletData::new(handles.to_vec(), values, h)
    }

    /// The fixed vertices.
    pub fn vertices(&self) -> &[usize] {
        &self.vertices
    }

    /// Number of columns (weight functions).
    pub fn n_columns(&self) -> usize {
        self.n_columns
    }

    /// The values at the `row`-th fixed vertex, one per column.
    pub fn values_at(&self, row: usize) -> &[f64] {
        &self.values[row * self.n_columns..(row + 1) * self.n_columns]
    }

    /// The same fixed vertices with only the columns `columns` (in that order): the data of a
    /// subset of the weight functions, for solving columns apart (the bounded biharmonic
    /// columns are independent programs). Errors if `columns` is empty or names a column that
    /// does not exist.
    ///
    /// ```
    /// use splineskin_core::weights::DirichletData;
    /// let data = DirichletData::handles(&[4, 9, 11])?;
    /// let part = data.select_columns(&[2, 0])?;
    /// assert_eq!(part.vertices(), &[4, 9, 11]);
    /// assert_eq!(part.values_at(2), &[1.0, 0.0]); // vertex 11: column 2, then column 0
    /// assert!(data.select_columns(&[3]).is_err());
    /// # Ok::<(), splineskin_core::weights::WeightsError>(())
    /// ```
    pub fn select_columns(&self, columns: &[usize]) -> Result<DirichletData, WeightsError> {
        if let Some(&column) = columns.iter().find(|&&c| c >= self.n_columns) {
            return Err(WeightsError::ColumnOutOfRange {
                column,
                n_columns: self.n_columns,
            });
        }
        let values = (0..self.vertices.len())
            .flat_map(|row| columns.iter().map(move |&c| self.values_at(row)[c]))
            .collect();
        DirichletData::new(self.vertices.clone(), values, columns.len())
    }

    /// Checks the vertices against a mesh of `n_vertices` vertices.
    pub(crate) fn check_range(&self, n_vertices: usize) -> Result<(), WeightsError> {
        match self.vertices.iter().position(|&v| v >= n_vertices) {
            Some(handle) => Err(WeightsError::HandleOutOfRange {
                handle,
                vertex: self.vertices[handle],
                n_vertices,
            }),
            None => Ok(()),
        }
    }
}
