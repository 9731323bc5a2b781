//! [`VertexWeights`]: one weight per handle at every mesh vertex, the output of the mesh
//! weight families.

use super::WeightsError;

/// Weights at the vertices of a mesh: `n_vertices × n_handles`, row-major (entry
/// `v · n_handles + i` is `w_i` at vertex `v`), the layout [`crate::domain::MeshWeights::new`]
/// takes.
///
/// ```
/// use splineskin_core::weights::VertexWeights;
/// let mut w = VertexWeights::from_row_major(2, 2, vec![1.0, 0.0, 0.5, 1.5])?;
/// assert_eq!(w.row(1), &[0.5, 1.5]);
/// assert_eq!(w.get(1, 0), 0.5);
/// w.normalize_rows()?;
/// assert_eq!(w.row(1), &[0.25, 0.75]);
/// # Ok::<(), splineskin_core::weights::WeightsError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct VertexWeights {
    n_vertices: usize,
    n_handles: usize,
    values: Vec<f64>,
}

impl VertexWeights {
    /// Wraps `values` (`n_vertices × n_handles`, row-major). Errors with
    /// [`WeightsError::WeightsShape`] if the length is not `n_vertices · n_handles`.
    pub fn from_row_major(
        n_vertices: usize,
        n_handles: usize,
        values: Vec<f64>,
    ) -> Result<VertexWeights, WeightsError> {
        if n_vertices.checked_mul(n_handles) != Some(values.len()) {
            return Err(WeightsError::WeightsShape {
                len: values.len(),
                n_vertices,
                n_handles,
            });
        }
        Ok(VertexWeights {
            n_vertices,
            n_handles,
            values,
        })
    }

    /// Number of vertices (rows).
    pub fn n_vertices(&self) -> usize {
        self.n_vertices
    }

    /// Number of handles (columns).
    pub fn n_handles(&self) -> usize {
        self.n_handles
    }

    /// The weights of every handle at vertex `v` (panics if `v ≥ n_vertices`, like slice
    /// indexing).
    pub fn row(&self, v: usize) -> &[f64] {
        &self.values[v * self.n_handles..(v + 1) * self.n_handles]
    }

    /// `w_i` at vertex `v`.
    pub fn get(&self, v: usize, i: usize) -> f64 {
        self.values[v * self.n_handles + i]
    }

    /// Handle `i`'s weight at every vertex (a copy: the storage is row-major).
    pub fn column(&self, i: usize) -> Vec<f64> {
        self.values
            .iter()
            .skip(i)
            .step_by(self.n_handles.max(1))
            .copied()
            .collect()
    }

    /// All values, row-major.
    pub fn as_slice(&self) -> &[f64] {
        &self.values
    }

    /// All values, row-major, by value.
    pub fn into_values(self) -> Vec<f64> {
        self.values
    }

    /// Divides each row by its sum, so that the weights at every vertex sum to 1 (libigl's
    /// `normalize_row_sums`; how BBW weights are used, Jacobson et al. 2011 §3). Errors if a
    /// row sums to zero, a negative or a non-finite number (then nothing is changed).
    pub fn normalize_rows(&mut self) -> Result<(), WeightsError> {
        let h = self.n_handles;
        if h == 0 {
            return Ok(());
        }
        let sums: Vec<f64> = self
            .values
            .chunks_exact(h)
            .map(|r| r.iter().sum())
            .collect();
        if let Some((vertex, &sum)) = sums
            .iter()
            .enumerate()
            .find(|(_, s)| !(s.is_finite() && **s > 0.0))
        {
            return Err(WeightsError::ZeroRowSum { vertex, sum });
        }
        for (row, sum) in self.values.chunks_exact_mut(h).zip(sums) {
            row.iter_mut().for_each(|w| *w /= sum);
        }
        Ok(())
    }

    /// Weights from `n_handles` contiguous columns of `n_vertices` values each.
    pub(crate) fn from_columns(
        n_vertices: usize,
        n_handles: usize,
        columns: &[f64],
    ) -> VertexWeights {
        debug_assert_eq!(columns.len(), n_vertices * n_handles);
        let mut values = vec![0.0; n_vertices * n_handles];
        for (i, column) in columns.chunks_exact(n_vertices.max(1)).enumerate() {
            for (v, &w) in column.iter().enumerate() {
                values[v * n_handles + i] = w;
            }
        }
        VertexWeights {
            n_vertices,
            n_handles,
            values,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vertex_weights_check_shape_and_refuse_zero_rows() {
        assert_eq!(
            VertexWeights::from_row_major(3, 2, vec![0.0; 5]),
            Err(WeightsError::WeightsShape {
                len: 5,
                n_vertices: 3,
                n_handles: 2
            })
        );
        let mut w =
            VertexWeights::from_row_major(3, 2, vec![1.0, 3.0, 0.0, 0.0, 2.0, 2.0]).unwrap();
        let before = w.clone();
        assert_eq!(
            w.normalize_rows(),
            Err(WeightsError::ZeroRowSum {
                vertex: 1,
                sum: 0.0
            })
        );
        assert_eq!(w, before, "nothing changed on error");
        assert_eq!(w.column(1), vec![3.0, 0.0, 2.0]);
        let mut ok = VertexWeights::from_row_major(2, 2, vec![1.0, 3.0, 2.0, 2.0]).unwrap();
        ok.normalize_rows().unwrap();
        assert_eq!(ok.into_values(), vec![0.25, 0.75, 0.5, 0.5]);
    }
}
