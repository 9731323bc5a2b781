//! Weights on a given triangle mesh in libigl's conventions: `V` (`n × 2`, or `n × 3` with
//! every `z` equal), `F` (`m × 3` vertex indices), `b` (the constrained vertices, or the
//! handles' positions, each matched to the vertex there) and `bc`
//! (their values, `len(b) × k`; default the identity, one column per handle: `w_i = 1` at
//! `b[i]`, 0 at the others). The same solvers the library uses on a drawing's domain.

use kurbo::Point;
use numpy::{AllowTypeChange, PyArray2, PyArrayLike1, PyArrayLike2, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use splineskin::mesh::TriMesh;
use splineskin::weights::bbw::{bounded_biharmonic, BbwOptions};
use splineskin::weights::harmonic::harmonic as polyharmonic;
use splineskin::weights::DirichletData;

use crate::arrays::{check_finite, matrix_array, weights_array};
use crate::library_error;

/// The mesh of `v` and `f`, 2-D: `v` may be `n × 3` if its `z` are all equal (a planar mesh
/// as libigl holds it); triangles all clockwise are turned counter-clockwise (the weights do
/// not depend on it); a mix of both is refused by the mesh check.
pub fn mesh_of(
    v: &PyArrayLike2<'_, f64, AllowTypeChange>,
    f: &PyArrayLike2<'_, i64, AllowTypeChange>,
) -> PyResult<TriMesh> {
    let (vs, fs) = (v.shape(), f.shape());
    if !(vs[1] == 2 || vs[1] == 3) {
        return Err(PyValueError::new_err(format!(
            "V: an array of shape (n, 2) or (n, 3) expected, got ({}, {})",
            vs[0], vs[1]
        )));
    }
    if fs[1] != 3 {
        return Err(PyValueError::new_err(format!(
            "F: an array of shape (m, 3) expected (triangles), got ({}, {})",
            fs[0], fs[1]
        )));
    }
    let va = v.as_array();
    let fa = f.as_array();
    let mut vertices = Vec::with_capacity(vs[0]);
    for r in 0..vs[0] {
        vertices.push(Point::new(va[(r, 0)], va[(r, 1)]));
        if vs[1] == 3 && va[(r, 2)] != va[(0, 2)] {
            return Err(PyValueError::new_err(format!(
                "V[{r}, 2] = {} but V[0, 2] = {}: the mesh must be planar (weights are computed \
                 in the plane)",
                va[(r, 2)],
                va[(0, 2)]
            )));
        }
    }
    let flat: Vec<f64> = vertices.iter().flat_map(|p| [p.x, p.y]).collect();
    check_finite(&flat, "V", 2)?;
    let mut triangles = Vec::with_capacity(fs[0]);
    for r in 0..fs[0] {
        let mut t = [0usize; 3];
        for c in 0..3 {
            let i = fa[(r, c)];
            if i < 0 || i as usize >= vertices.len() {
                return Err(PyValueError::new_err(format!(
                    "F[{r}, {c}] = {i}: not a vertex index (V has {} rows)",
                    vertices.len()
                )));
            }
            t[c] = i as usize;
        }
        triangles.push(t);
    }
    let area = |t: &[usize; 3]| {
        let (a, b, c) = (vertices[t[0]], vertices[t[1]], vertices[t[2]]);
        (b - a).cross(c - a)
    };
    if !triangles.is_empty() && triangles.iter().all(|t| area(t) < 0.0) {
        for t in &mut triangles {
            t.swap(1, 2);
        }
    }
    TriMesh::new(vertices, triangles).map_err(library_error)
}

/// Where a vertex must be to stand for a handle given by position: within this fraction of
/// the mesh's bounding-box diagonal (the positions a mesh file or a triangulator wrote back).
pub const HANDLE_POSITION_TOLERANCE: f64 = 1e-9;

/// The handle vertices `b` names: vertex indices (a 1-D array of integers), or positions
/// (`k × 2`), each matched to the mesh's vertex there (within [`HANDLE_POSITION_TOLERANCE`]
/// of the diagonal).
pub fn handle_vertices(b: &Bound<'_, PyAny>, mesh: &TriMesh) -> PyResult<Vec<usize>> {
    let n = mesh.n_vertices();
    if let Ok(positions) = b.extract::<PyArrayLike2<'_, f64, AllowTypeChange>>() {
        let shape = positions.shape();
        if shape[1] != 2 {
            return Err(PyValueError::new_err(format!(
                "b: vertex indices (k,) or handle positions (k, 2) expected, got ({}, {})",
                shape[0], shape[1]
            )));
        }
        let tolerance = HANDLE_POSITION_TOLERANCE * mesh.bounding_box_diagonal();
        let a = positions.as_array();
        return (0..shape[0])
            .map(|k| {
                let p = Point::new(a[(k, 0)], a[(k, 1)]);
                let (best, distance) = mesh
                    .vertices
                    .iter()
                    .enumerate()
                    .map(|(i, v)| (i, (*v - p).hypot()))
                    .fold((0, f64::INFINITY), |m, c| if c.1 < m.1 { c } else { m });
                if distance <= tolerance {
                    Ok(best)
                } else {
                    Err(PyValueError::new_err(format!(
                        "b[{k}] = ({}, {}): no vertex there (the nearest, {best}, is {distance:e} away)",
                        p.x, p.y
                    )))
                }
            })
            .collect();
    }
    let indices = b
        .extract::<PyArrayLike1<'_, i64, AllowTypeChange>>()
        .map_err(|_| {
            PyValueError::new_err("b: vertex indices (k,) or handle positions (k, 2) expected")
        })?;
    indices
        .as_array()
        .iter()
        .enumerate()
        .map(|(k, &i)| {
            usize::try_from(i).ok().filter(|&i| i < n).ok_or_else(|| {
                PyValueError::new_err(format!("b[{k}] = {i}: not a vertex index (V has {n} rows)"))
            })
        })
        .collect()
}

/// The boundary data of the handle vertices `b` and `bc` (identity without `bc`).
fn dirichlet(
    b: Vec<usize>,
    bc: Option<&PyArrayLike2<'_, f64, AllowTypeChange>>,
) -> PyResult<DirichletData> {
    match bc {
        None => DirichletData::handles(&b).map_err(library_error),
        Some(bc) => {
            let shape = bc.shape();
            if shape[0] != b.len() {
                return Err(PyValueError::new_err(format!(
                    "bc: {} rows for {} constrained vertices (b)",
                    shape[0],
                    b.len()
                )));
            }
            let values: Vec<f64> = bc.as_array().iter().copied().collect();
            check_finite(&values, "bc", shape[1].max(1))?;
            DirichletData::new(b, values, shape[1]).map_err(library_error)
        }
    }
}

/// Order-`k` polyharmonic weights on the mesh `(V, F)` (`k = 1` harmonic, `k = 2`
/// biharmonic): `Δᵏ w = 0` with `w = bc` at the vertices `b` (libigl's `harmonic(V, F, b,
/// bc, k)`, cotangent Laplacian and Voronoi mass matrix). Returns `n × columns of bc`.
#[pyfunction]
#[pyo3(signature = (V, F, b, bc = None, k = 1))]
#[allow(non_snake_case)]
pub fn harmonic<'py>(
    py: Python<'py>,
    V: PyArrayLike2<'py, f64, AllowTypeChange>,
    F: PyArrayLike2<'py, i64, AllowTypeChange>,
    b: Bound<'py, PyAny>,
    bc: Option<PyArrayLike2<'py, f64, AllowTypeChange>>,
    k: usize,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let mesh = mesh_of(&V, &F)?;
    let data = dirichlet(handle_vertices(&b, &mesh)?, bc.as_ref())?;
    let weights = py
        .detach(|| polyharmonic(&mesh, &data, k))
        .map_err(library_error)?;
    Ok(weights_array(py, &weights))
}

/// Bounded biharmonic weights on the mesh `(V, F)` (Jacobson et al. 2011; libigl's `bbw`):
/// the biharmonic energy minimised with `0 ≤ w ≤ 1` and `w = bc` at the vertices `b`, by the
/// library's active-set solver. Not normalised, as libigl's (`partition_unity=True` divides
/// each row by its sum). Returns `n × columns of bc`. Each column is its own program: with
/// `parallel` (the default, as `splineskin weights` does) they are solved on all cores, with
/// the same result to the last bit as one after the other.
#[pyfunction]
#[pyo3(signature = (V, F, b, bc = None, *, partition_unity = false, parallel = true))]
#[allow(non_snake_case)]
pub fn bbw<'py>(
    py: Python<'py>,
    V: PyArrayLike2<'py, f64, AllowTypeChange>,
    F: PyArrayLike2<'py, i64, AllowTypeChange>,
    b: Bound<'py, PyAny>,
    bc: Option<PyArrayLike2<'py, f64, AllowTypeChange>>,
    partition_unity: bool,
    parallel: bool,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let mesh = mesh_of(&V, &F)?;
    let data = dirichlet(handle_vertices(&b, &mesh)?, bc.as_ref())?;
    let options = BbwOptions::default().with_parallel(parallel);
    let weights = py
        .detach(|| -> Result<_, String> {
            let mut w = bounded_biharmonic(&mesh, &data, &options).map_err(|e| e.to_string())?;
            if partition_unity {
                w.normalize_rows().map_err(|e| e.to_string())?;
            }
            Ok(w)
        })
        .map_err(library_error)?;
    Ok(weights_array(py, &weights))
}

/// Mean value coordinates (Floater 2003; Hormann & Floater 2006) of `points` (`m × 2`) with
/// respect to the polygon `cage` (`n × 2`, counter-clockwise, simple): `m × n`, each row
/// reproducing its point (`Σ w_i c_i = p`) and summing to 1, defined in the whole plane.
#[pyfunction]
pub fn mvc<'py>(
    py: Python<'py>,
    cage: numpy::PyReadonlyArray2<'py, f64>,
    points: numpy::PyReadonlyArray2<'py, f64>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let cage = crate::arrays::points(&cage, "cage", None)?;
    let points = crate::arrays::points(&points, "points", None)?;
    let n = cage.len();
    let field = splineskin::weights::MeanValue::new(&cage).map_err(library_error)?;
    let values = py.detach(|| {
        use splineskin::weights::WeightField;
        let mut values = vec![0.0; points.len() * n];
        for (p, row) in points.iter().zip(values.chunks_exact_mut(n.max(1))) {
            field.eval(*p, row);
        }
        values
    });
    Ok(matrix_array(py, values, n))
}
