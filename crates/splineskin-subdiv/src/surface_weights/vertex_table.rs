//! User-supplied weights: one row per cage vertex, one column per handle, read from a CSV file.
//!
//! # Format
//!
//! ```text
//! # weights of the car: handles front, back (points), then the axle (a bone)
//! 1, 0, 0
//! 0.5, 0.25, 0.25
//! …
//! ```
//!
//! * one row per cage vertex, in the order of the OBJ's `v` lines (vertex 0 first);
//! * one column per handle, in handle order (point handles, then bones), separated by commas
//!   (spaces around numbers are ignored);
//! * every value a finite number ≥ 0, every row with a positive sum; rows are normalised to
//!   sum to one (so rows need not be normalised in the file);
//! * blank lines and lines starting with `#` are skipped.
//!
//! Anything else is a [`SurfaceWeightsError`] naming the file, the line and the column.
//!
//! # On the surface
//!
//! The weights are carried to the limit surface **by the limit stencils**:
//! `w_i(p) = Σ_v m_p,v W_v,i`, `m_p` the limit stencil of the point. That is the weight
//! treated as one more coordinate of the cage and subdivided with it — the surface and its
//! weights share one parameterisation, the result is as smooth as the surface (C² away from
//! extraordinary vertices, exact at every quadrature node), and since limit stencils have
//! non-negative weights summing to one, the weights stay in `[0, 1]` and keep their partition
//! of unity. (Interpolating over a refined mesh instead would be only C⁰ and would depend on
//! a chosen level.) The naive method skins each cage vertex with its own row.

use std::path::Path;

use super::super::cage::Point3;
use super::super::error::SurfaceWeightsError;
use super::{SurfaceSample, SurfaceWeights};

/// The largest weight file read, in bytes (256 MiB, as for OBJ files).
pub const MAX_WEIGHT_FILE_BYTES: u64 = 256 << 20;

/// Weights given per cage vertex (module documentation).
///
/// ```
/// use splineskin_subdiv::parse_weight_csv;
/// let w = parse_weight_csv("# two vertices, two handles\n1, 0\n1, 3\n", "w.csv", 2, 2)?;
/// assert_eq!(w.row(1), &[0.25, 0.75]);
/// # Ok::<(), splineskin_subdiv::SurfaceWeightsError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct CageVertexWeights {
    n_handles: usize,
    /// Vertex-major, normalised rows.
    values: Vec<f64>,
}

impl CageVertexWeights {
    /// Weights from normalised or unnormalised rows, vertex-major (`n_vertices · n_handles`):
    /// checked and normalised as a file's rows are (`file` names the source in errors; the
    /// line is the row's 1-based index).
    pub fn new(
        values: Vec<f64>,
        n_handles: usize,
        file: &str,
    ) -> Result<Self, SurfaceWeightsError> {
        if n_handles == 0 {
            return Err(SurfaceWeightsError::NoHandles);
        }
        let mut values = values;
        for (r, row) in values.chunks_mut(n_handles).enumerate() {
            check_row(row, n_handles, file, r + 1)?;
        }
        Ok(CageVertexWeights { n_handles, values })
    }

    /// Number of cage vertices.
    pub fn n_vertices(&self) -> usize {
        self.values.len() / self.n_handles
    }

    /// The normalised weights of cage vertex `v`.
    ///
    /// # Panics
    /// If `v >= n_vertices()`.
    pub fn row(&self, v: usize) -> &[f64] {
        &self.values[v * self.n_handles..][..self.n_handles]
    }
}

/// Reads a weight file (module documentation) for a cage of `n_vertices` vertices and
/// `n_handles` handles.
pub fn read_weight_csv(
    path: &Path,
    n_vertices: usize,
    n_handles: usize,
) -> Result<CageVertexWeights, SurfaceWeightsError> {
    let file = path.display().to_string();
    let read = |source| SurfaceWeightsError::Read {
        file: file.clone(),
        source,
    };
    let size = std::fs::metadata(path).map_err(read)?.len();
    if size > MAX_WEIGHT_FILE_BYTES {
        return Err(SurfaceWeightsError::Table {
            file,
            line: 1,
            what: format!("the file has {size} bytes; expected at most {MAX_WEIGHT_FILE_BYTES}"),
        });
    }
    let bytes = std::fs::read(path).map_err(read)?;
    let text = String::from_utf8(bytes).map_err(|_| SurfaceWeightsError::Table {
        file: file.clone(),
        line: 1,
        what: "not UTF-8 text; expected a CSV file of weights".into(),
    })?;
    parse_weight_csv(&text, &file, n_vertices, n_handles)
}

/// Parses the text of a weight file (`file` names it in errors).
pub fn parse_weight_csv(
    text: &str,
    file: &str,
    n_vertices: usize,
    n_handles: usize,
) -> Result<CageVertexWeights, SurfaceWeightsError> {
    if n_handles == 0 {
        return Err(SurfaceWeightsError::NoHandles);
    }
    let mut values = Vec::with_capacity(n_vertices * n_handles);
    let mut rows = 0;
    for (index, line) in text.lines().enumerate() {
        let line_no = index + 1;
        let trimmed = line.trim();
        if trimmed.is_empty() || trimmed.starts_with('#') {
            continue;
        }
        rows += 1;
        if rows > n_vertices {
            return Err(SurfaceWeightsError::TableRows {
                file: file.to_owned(),
                found: rows + text.lines().skip(index + 1).filter(|l| is_row(l)).count(),
                expected: n_vertices,
            });
        }
        let start = values.len();
        for (column, field) in trimmed.split(',').enumerate() {
            let field = field.trim();
            let value: f64 = field.parse().map_err(|_| SurfaceWeightsError::Table {
                file: file.to_owned(),
                line: line_no,
                what: format!("column {}: '{field}' is not a number", column + 1),
            })?;
            values.push(value);
        }
        check_row(&mut values[start..], n_handles, file, line_no)?;
    }
    if rows != n_vertices {
        return Err(SurfaceWeightsError::TableRows {
            file: file.to_owned(),
            found: rows,
            expected: n_vertices,
        });
    }
    Ok(CageVertexWeights { n_handles, values })
}

fn is_row(line: &str) -> bool {
    let t = line.trim();
    !t.is_empty() && !t.starts_with('#')
}

/// Checks one row (finite, ≥ 0, positive sum, `n_handles` long) and normalises it.
fn check_row(
    row: &mut [f64],
    n_handles: usize,
    file: &str,
    line: usize,
) -> Result<(), SurfaceWeightsError> {
    let bad = |what: String| SurfaceWeightsError::Table {
        file: file.to_owned(),
        line,
        what,
    };
    if row.len() != n_handles {
        return Err(bad(format!(
            "{} columns; expected one per handle, {n_handles}",
            row.len()
        )));
    }
    for (column, &w) in row.iter().enumerate() {
        if !(w.is_finite() && w >= 0.0) {
            return Err(bad(format!(
                "column {}: weight {w}; expected a finite number ≥ 0",
                column + 1
            )));
        }
    }
    let sum: f64 = row.iter().sum();
    if sum <= 0.0 {
        return Err(bad(
            "all weights are 0; expected a row with a positive sum".into()
        ));
    }
    for w in row.iter_mut() {
        *w /= sum;
    }
    Ok(())
}

impl SurfaceWeights for CageVertexWeights {
    fn n_handles(&self) -> usize {
        self.n_handles
    }

    fn eval(&self, at: &SurfaceSample<'_>, out: &mut [f64]) -> Result<(), SurfaceWeightsError> {
        out.fill(0.0);
        for (&v, &m) in at.indices.iter().zip(at.weights) {
            let v = v as usize;
            if v >= self.n_vertices() {
                return Err(SurfaceWeightsError::BadOption {
                    what: format!(
                        "a limit stencil uses cage vertex {v}, but the weights are for {} vertices",
                        self.n_vertices()
                    ),
                });
            }
            for (o, w) in out.iter_mut().zip(self.row(v)) {
                *o += m * w;
            }
        }
        Ok(())
    }

    fn eval_cage_vertex(
        &self,
        vertex: u32,
        _position: Point3,
        out: &mut [f64],
    ) -> Result<(), SurfaceWeightsError> {
        let v = vertex as usize;
        if v >= self.n_vertices() {
            return Err(SurfaceWeightsError::NoSurface { vertex });
        }
        out.copy_from_slice(self.row(v));
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn message(text: &str, n_vertices: usize, n_handles: usize) -> String {
        parse_weight_csv(text, "w.csv", n_vertices, n_handles)
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn weight_csv_errors_name_file_line_and_column() {
        assert_eq!(
            message("1, 0\n0.5, nan\n", 2, 2),
            "w.csv:2: column 2: weight NaN; expected a finite number ≥ 0"
        );
        assert_eq!(
            message("# header\n1, 0\n0.5, 0.2, 0.3\n", 2, 2),
            "w.csv:3: 3 columns; expected one per handle, 2"
        );
        assert_eq!(
            message("1, 0\n1, x\n", 2, 2),
            "w.csv:2: column 2: 'x' is not a number"
        );
        assert_eq!(
            message("1, 0\n", 2, 2),
            "w.csv: 1 rows of weights; expected one per cage vertex, 2"
        );
        assert_eq!(
            message("1, 0\n0, 1\n1, 1\n\n1, 1\n", 2, 2),
            "w.csv: 4 rows of weights; expected one per cage vertex, 2"
        );
        assert_eq!(
            message("0, 0\n", 1, 2),
            "w.csv:1: all weights are 0; expected a row with a positive sum"
        );
        assert_eq!(
            message("-1, 2\n", 1, 2),
            "w.csv:1: column 1: weight -1; expected a finite number ≥ 0"
        );
        let missing = read_weight_csv(Path::new("/nonexistent/w.csv"), 1, 1).unwrap_err();
        assert!(
            missing
                .to_string()
                .starts_with("/nonexistent/w.csv: cannot read"),
            "{missing}"
        );
    }

    #[test]
    fn weight_csv_rows_carried_by_stencils() {
        let w = parse_weight_csv("2, 2\n0, 1\n1, 0\n", "w.csv", 3, 2).unwrap();
        assert_eq!(w.row(0), &[0.5, 0.5]);
        let mut out = [0.0; 2];
        let at = SurfaceSample {
            location: crate::SurfaceLocation {
                face: 0,
                subface: 0,
                u: 0.5,
                v: 0.5,
            },
            position: [0.0; 3],
            indices: &[0, 1, 2],
            weights: &[0.5, 0.25, 0.25],
        };
        w.eval(&at, &mut out).unwrap();
        assert_eq!(out, [0.5, 0.5]);
        w.eval_cage_vertex(1, [0.0; 3], &mut out).unwrap();
        assert_eq!(out, [0.0, 1.0]);
    }
}
