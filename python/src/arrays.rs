//! numpy arrays in and out: shapes, order and finiteness checked with messages that name the
//! argument, in the layouts the library uses (points `n × 2`, affine maps `k × 2 × 3`).

use std::borrow::Cow;

use kurbo::{Affine, Point};
use numpy::{PyArray2, PyReadonlyArray2, PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// The `float64` data of `array` (`name` for messages) in row-major order, checked to be
/// `rows × cols` (`rows` `None`: any number of rows): the array's own memory when it is in C
/// order, else a row-major copy (a Fortran-order or strided view is read as numpy shows it).
pub fn matrix<'a>(
    array: &'a PyReadonlyArray2<'_, f64>,
    name: &str,
    rows: Option<usize>,
    cols: usize,
) -> PyResult<Cow<'a, [f64]>> {
    let shape = array.shape();
    if shape[1] != cols || rows.is_some_and(|r| r != shape[0]) {
        let expected = match rows {
            Some(r) => format!("({r}, {cols})"),
            None => format!("(n, {cols})"),
        };
        return Err(PyValueError::new_err(format!(
            "{name}: an array of shape {expected} expected, got ({}, {})",
            shape[0], shape[1]
        )));
    }
    let data = if array.is_c_contiguous() {
        Cow::Borrowed(array.as_slice()?)
    } else {
        Cow::Owned(array.as_array().iter().copied().collect())
    };
    check_finite(&data, name, cols)?;
    Ok(data)
}

/// Errors naming the first entry of `data` (rows of `cols`) that is not finite.
pub fn check_finite(data: &[f64], name: &str, cols: usize) -> PyResult<()> {
    match data.iter().position(|v| !v.is_finite()) {
        Some(i) => Err(PyValueError::new_err(format!(
            "{name}[{}, {}] is {}: every value must be finite",
            i / cols,
            i % cols,
            data[i]
        ))),
        None => Ok(()),
    }
}

/// Points from an `n × 2` array, checked to have `rows` rows when given.
pub fn points(
    array: &PyReadonlyArray2<'_, f64>,
    name: &str,
    rows: Option<usize>,
) -> PyResult<Vec<Point>> {
    let mut out = Vec::new();
    points_into(array, name, rows, &mut out)?;
    Ok(out)
}

/// [`points`] into `out` (cleared first; allocates nothing once `out` has the capacity), for
/// the arrays a frame reads.
pub fn points_into(
    array: &PyReadonlyArray2<'_, f64>,
    name: &str,
    rows: Option<usize>,
    out: &mut Vec<Point>,
) -> PyResult<()> {
    let data = matrix(array, name, rows, 2)?;
    out.clear();
    out.extend(data.chunks_exact(2).map(|p| Point::new(p[0], p[1])));
    Ok(())
}

/// Writes affine maps from a `k × 2 × 3` array (`[[a, c, e], [b, d, f]]` each, the matrix
/// acting on column vectors `(x, y, 1)`) or a `k × 3 × 3` one whose last rows are `(0, 0, 1)`
/// into `out` (cleared first; sized once by the caller, so a frame allocates nothing).
pub fn affines_into(
    array: &PyReadonlyArray3<'_, f64>,
    name: &str,
    expected: usize,
    out: &mut Vec<Affine>,
) -> PyResult<()> {
    let shape = array.shape();
    if shape[0] != expected || shape[2] != 3 || !(shape[1] == 2 || shape[1] == 3) {
        return Err(PyValueError::new_err(format!(
            "{name}: an array of shape ({expected}, 2, 3) expected (one affine map [[a, c, e], \
             [b, d, f]] per handle), got ({}, {}, {})",
            shape[0], shape[1], shape[2]
        )));
    }
    let data: Cow<'_, [f64]> = if array.is_c_contiguous() {
        Cow::Borrowed(array.as_slice()?)
    } else {
        Cow::Owned(array.as_array().iter().copied().collect())
    };
    let rows = shape[1];
    check_finite(&data, name, rows * 3)?;
    out.clear();
    for (k, m) in data.chunks_exact(rows * 3).enumerate() {
        if rows == 3 && (m[6] != 0.0 || m[7] != 0.0 || m[8] != 1.0) {
            return Err(PyValueError::new_err(format!(
                "{name}[{k}]: the last row of a 3 × 3 affine map must be (0, 0, 1), got ({}, {}, {})",
                m[6], m[7], m[8]
            )));
        }
        out.push(Affine::new([m[0], m[3], m[1], m[4], m[2], m[5]]));
    }
    Ok(())
}

/// A new `n × 2` array of `points`.
pub fn points_array<'py>(py: Python<'py>, points: &[Point]) -> Bound<'py, PyArray2<f64>> {
    let flat: Vec<f64> = points.iter().flat_map(|p| [p.x, p.y]).collect();
    matrix_array(py, flat, 2)
}

/// A new `(data.len() / cols) × cols` array owning `data` (row-major).
pub fn matrix_array(py: Python<'_>, data: Vec<f64>, cols: usize) -> Bound<'_, PyArray2<f64>> {
    let rows = data.len() / cols.max(1);
    let array = numpy::ndarray::Array2::from_shape_vec((rows, cols), data)
        .expect("rows × cols values by construction");
    PyArray2::from_owned_array(py, array)
}

/// The array an update writes into: `out` if given, checked to be a C-order `float64` array
/// of shape `rows × cols`, else a new one of that shape.
pub fn output<'py>(
    py: Python<'py>,
    out: Option<Bound<'py, PyArray2<f64>>>,
    rows: usize,
    cols: usize,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let Some(out) = out else {
        return Ok(PyArray2::zeros(py, [rows, cols], false));
    };
    let shape = out.shape().to_vec();
    if shape != [rows, cols] || !out.is_c_contiguous() {
        return Err(PyValueError::new_err(format!(
            "out: a C-order float64 array of shape ({rows}, {cols}) expected, got shape {shape:?}{}",
            if out.is_c_contiguous() { "" } else { " not in C order" }
        )));
    }
    Ok(out)
}

/// A new `n_vertices × n_handles` array of `weights`.
pub fn weights_array<'py>(
    py: Python<'py>,
    weights: &splineskin::weights::VertexWeights,
) -> Bound<'py, PyArray2<f64>> {
    matrix_array(py, weights.as_slice().to_vec(), weights.n_handles())
}
