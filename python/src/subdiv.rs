//! `Cage` and `SubdivRig`: Catmull–Clark subdivision surfaces (the paper's §6) — a control cage
//! from OBJ, its limit surface evaluated at ptex coordinates, and the rig that fits the cage
//! to a skinned limit surface, one product per pose.

use numpy::{
    PyArray2, PyArray3, PyArrayMethods, PyReadonlyArray2, PyReadonlyArray3, PyUntypedArrayMethods,
};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use splineskin::subdiv::handoff::{FittedAnimation, UpAxis};
use splineskin::subdiv::{
    parse_obj, to_obj_string, Affine3, Cage, LimitOptions, LimitSurface, Point3, SubdivScene,
    SubdivSetup, MAX_LIMIT_MESH_LEVEL,
};

use crate::arrays::{check_finite, matrix, matrix_array, output};
use crate::drawing::{check_exists, read_text};
use crate::library_error;

/// A Catmull–Clark control cage (`Cage.from_obj`): vertex positions and faces of any size.
#[pyclass(module = "splineskin._splineskin", name = "Cage", frozen)]
pub struct PyCage {
    cage: Cage,
    name: String,
}

/// Positions `n × 3` from an array, checked.
fn positions(array: &PyReadonlyArray2<'_, f64>, name: &str, n: usize) -> PyResult<Vec<Point3>> {
    let data = matrix(array, name, Some(n), 3)?;
    Ok(data.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect())
}

/// An `n × 3` array of `points`.
fn points3_array<'py>(py: Python<'py>, points: &[Point3]) -> Bound<'py, PyArray2<f64>> {
    matrix_array(py, points.iter().flatten().copied().collect(), 3)
}

impl PyCage {
    /// The cage with `positions` in place of its own (`None`: its own).
    fn with_positions(&self, positions_given: Option<PyReadonlyArray2<'_, f64>>) -> PyResult<Cage> {
        let mut cage = self.cage.clone();
        if let Some(p) = positions_given {
            let p = positions(&p, "positions", cage.n_vertices())?;
            cage.set_positions(p).map_err(library_error)?;
        }
        Ok(cage)
    }
}

#[pymethods]
impl PyCage {
    /// Reads a cage from OBJ: a path, or the OBJ text itself (a string with a line break).
    /// Faces of any size; OpenSubdiv's crease and corner tags (`t crease`, `t corner`) are
    /// kept.
    #[staticmethod]
    #[pyo3(signature = (source, /))]
    fn from_obj(py: Python<'_>, source: ObjSource) -> PyResult<PyCage> {
        let (text, name) = match source {
            ObjSource::Text(text) => (text, "<obj text>".to_string()),
            ObjSource::Path(path) => (read_text(&path)?, path.display().to_string()),
        };
        let cage = py
            .detach(|| parse_obj(&text, &name))
            .map_err(library_error)?;
        Ok(PyCage { cage, name })
    }

    /// The vertex positions, `n_vertices × 3`.
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        points3_array(py, self.cage.positions())
    }

    /// The faces, each a list of vertex indices (0-based), counter-clockwise seen from outside.
    #[getter]
    fn faces(&self) -> Vec<Vec<u32>> {
        self.cage.faces().map(|f| f.to_vec()).collect()
    }

    /// Number of vertices.
    #[getter]
    fn n_vertices(&self) -> usize {
        self.cage.n_vertices()
    }

    /// Number of faces.
    #[getter]
    fn n_faces(&self) -> usize {
        self.cage.n_faces()
    }

    /// The OBJ text of the cage, with `positions` (`n_vertices × 3`) if given; tags kept.
    #[pyo3(signature = (positions = None))]
    fn to_obj(&self, positions: Option<PyReadonlyArray2<'_, f64>>) -> PyResult<String> {
        Ok(to_obj_string(&self.with_positions(positions)?))
    }

    /// Points of the limit surface: at ptex faces `ptex` (OpenSubdiv's numbering: one per
    /// quad, `n` per `n`-gon) and parameters `uv` (`m × 2`, in `[0, 1]²`), of the cage with
    /// `positions` if given: `m × 3`.
    #[pyo3(signature = (ptex, uv, positions = None))]
    fn limit<'py>(
        &self,
        py: Python<'py>,
        ptex: Vec<u32>,
        uv: PyReadonlyArray2<'py, f64>,
        positions: Option<PyReadonlyArray2<'py, f64>>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let uv = matrix(&uv, "uv", Some(ptex.len()), 2)?;
        let cage = self.with_positions(positions)?;
        let points = py
            .detach(|| -> Result<Vec<Point3>, String> {
                let surface = LimitSurface::new(&cage, &LimitOptions::default())
                    .map_err(|e| e.to_string())?;
                let mut locations = Vec::with_capacity(ptex.len());
                for (k, (&f, st)) in ptex.iter().zip(uv.chunks_exact(2)).enumerate() {
                    locations.push(
                        surface
                            .ptex_location(f, st[0], st[1])
                            .map_err(|e| format!("ptex[{k}], uv[{k}]: {e}"))?,
                    );
                }
                let stencils = surface.stencils(&locations).map_err(|e| e.to_string())?;
                Ok(stencils
                    .iter()
                    .map(|s| s.position(cage.positions()))
                    .collect())
            })
            .map_err(|e| library_error(format!("{}: {e}", self.name)))?;
        Ok(points3_array(py, &points))
    }

    fn __repr__(&self) -> String {
        format!(
            "<splineskin.Cage {:?}: {} vertices, {} faces>",
            self.name,
            self.cage.n_vertices(),
            self.cage.n_faces()
        )
    }
}

/// What `Cage.from_obj` was given.
pub enum ObjSource {
    /// OBJ text.
    Text(String),
    /// A path.
    Path(std::path::PathBuf),
}

impl<'a, 'py> FromPyObject<'a, 'py> for ObjSource {
    type Error = PyErr;
    fn extract(object: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        if let Ok(text) = object.extract::<String>() {
            return Ok(if text.contains('\n') {
                ObjSource::Text(text)
            } else {
                ObjSource::Path(text.into())
            });
        }
        object
            .extract::<std::path::PathBuf>()
            .map(ObjSource::Path)
            .map_err(|_| PyValueError::new_err("expected OBJ text or a path to an OBJ file"))
    }
}

/// Frame times (`n_frames`) and cages (`n_frames × n_vertices × 3`).
type TimesAndCages<'py> = (Bound<'py, numpy::PyArray1<f64>>, Bound<'py, PyArray3<f64>>);

/// The rig of a subdivision scene (`SubdivRig.from_scene`): `update(transforms)` gives the
/// cage whose limit surface is closest to the skinned one.
#[pyclass(module = "splineskin._splineskin", name = "SubdivRig")]
pub struct PySubdivRig {
    scene: SubdivScene,
    setup: SubdivSetup,
    /// The maps of the last update, reused.
    pose: Vec<Affine3>,
}

#[pymethods]
impl PySubdivRig {
    /// Reads a subdivision scene (`splineskin subdiv deform` reads the same) and precomputes
    /// its limit surface, quadrature, weights and rig, the GIL released.
    #[staticmethod]
    #[pyo3(signature = (path, /))]
    fn from_scene(py: Python<'_>, path: std::path::PathBuf) -> PyResult<PySubdivRig> {
        check_exists(&path)?;
        let (scene, setup) = py
            .detach(|| -> Result<_, String> {
                let scene = SubdivScene::load(&path).map_err(|e| e.to_string())?;
                let setup = scene.setup().map_err(|e| e.to_string())?;
                Ok((scene, setup))
            })
            .map_err(library_error)?;
        Ok(PySubdivRig {
            pose: Vec::with_capacity(setup.rig.n_handles()),
            scene,
            setup,
        })
    }

    /// The cage positions (`n_vertices × 3`) for `transforms`, one 3-D affine map per handle
    /// (`n_handles × 3 × 4`, rows `[a b c t]` acting on `(x, y, z, 1)`, or `× 4 × 4` with last
    /// rows `(0, 0, 0, 1)`), written into `out` if given (a C-order `float64` array of that
    /// shape, returned; no copy), else into a new array.
    #[pyo3(signature = (transforms, out = None))]
    fn update<'py>(
        &mut self,
        py: Python<'py>,
        transforms: PyReadonlyArray3<'py, f64>,
        out: Option<Bound<'py, PyArray2<f64>>>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let h = self.setup.rig.n_handles();
        let shape = transforms.shape();
        if shape[0] != h || shape[2] != 4 || !(shape[1] == 3 || shape[1] == 4) {
            return Err(PyValueError::new_err(format!(
                "transforms: an array of shape ({h}, 3, 4) expected, got ({}, {}, {})",
                shape[0], shape[1], shape[2]
            )));
        }
        let data: std::borrow::Cow<'_, [f64]> = if transforms.is_c_contiguous() {
            std::borrow::Cow::Borrowed(transforms.as_slice()?)
        } else {
            std::borrow::Cow::Owned(transforms.as_array().iter().copied().collect())
        };
        let rows = shape[1];
        check_finite(&data, "transforms", rows * 4)?;
        self.pose.clear();
        for (k, m) in data.chunks_exact(rows * 4).enumerate() {
            if rows == 4 && (m[12] != 0.0 || m[13] != 0.0 || m[14] != 0.0 || m[15] != 1.0) {
                return Err(PyValueError::new_err(format!(
                    "transforms[{k}]: the last row of a 4 × 4 affine map must be (0, 0, 0, 1)"
                )));
            }
            self.pose.push([
                [m[0], m[1], m[2], m[3]],
                [m[4], m[5], m[6], m[7]],
                [m[8], m[9], m[10], m[11]],
            ]);
        }
        let n = self.setup.rig.n_vertices();
        let out = output(py, out, n, 3)?;
        {
            let mut writable = out.try_readwrite()?;
            let (points, _) = writable.as_slice_mut()?.as_chunks_mut::<3>();
            let (rig, pose) = (&self.setup.rig, &self.pose);
            py.detach(|| rig.update(pose, points))
                .map_err(library_error)?;
        }
        Ok(out)
    }

    /// Pose `index` of the scene: `n_handles × 3 × 4`.
    #[pyo3(signature = (index = 0))]
    fn pose<'py>(&self, py: Python<'py>, index: usize) -> PyResult<Bound<'py, PyArray3<f64>>> {
        let pose = self.scene.pose(index).map_err(library_error)?;
        let data: Vec<f64> = pose.iter().flatten().flatten().copied().collect();
        let array = numpy::ndarray::Array3::from_shape_vec((pose.len(), 3, 4), data)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(PyArray3::from_owned_array(py, array))
    }

    /// The scene's animation fitted frame by frame (what `splineskin subdiv animate` writes):
    /// `(times, cages)`, the frame times in seconds (`n_frames`) and every frame's cage
    /// (`n_frames × n_vertices × 3`). Raises if the scene has no `animation`.
    fn animation<'py>(&self, py: Python<'py>) -> PyResult<TimesAndCages<'py>> {
        let fitted = self.fitted(py)?;
        let (n_frames, n) = (fitted.cages.len(), self.setup.cage.n_vertices());
        let data: Vec<f64> = fitted.cages.iter().flatten().flatten().copied().collect();
        let cages = numpy::ndarray::Array3::from_shape_vec((n_frames, n, 3), data)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok((
            numpy::PyArray1::from_vec(py, fitted.times),
            PyArray3::from_owned_array(py, cages),
        ))
    }

    /// Writes the scene's animation to `path` as `splineskin subdiv animate` does: `.usda` (the
    /// cage as a Catmull-Clark USD mesh, points sampled per frame) or `.glb` (the limit surface
    /// tessellated at `level`, one morph target per frame); `up` is `"y"` or `"z"`. The file is
    /// written whole or not at all.
    #[pyo3(signature = (path, *, level = 3, up = "y"))]
    fn write_animation(
        &self,
        py: Python<'_>,
        path: std::path::PathBuf,
        level: usize,
        up: &str,
    ) -> PyResult<()> {
        let up = match up {
            "y" | "Y" => UpAxis::Y,
            "z" | "Z" => UpAxis::Z,
            other => {
                return Err(PyValueError::new_err(format!(
                    "up={other:?}; expected \"y\" or \"z\""
                )))
            }
        };
        if !(1..=MAX_LIMIT_MESH_LEVEL).contains(&level) {
            return Err(PyValueError::new_err(format!(
                "level={level}; expected 1 ..= {MAX_LIMIT_MESH_LEVEL}"
            )));
        }
        let extension = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        let fitted = self.fitted(py)?;
        let name = self
            .scene
            .obj
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let setup = &self.setup;
        let bytes = py
            .detach(|| match extension.as_deref() {
                Some("usda") => fitted.usda(setup, &name, up).map(String::into_bytes),
                Some("glb") => fitted.glb(setup, level, &name, up),
                _ => Ok(Vec::new()),
            })
            .map_err(library_error)?;
        if bytes.is_empty() {
            return Err(PyValueError::new_err(format!(
                "{}: expected a name ending in .usda (USD) or .glb (binary glTF)",
                path.display()
            )));
        }
        splineskin::atomic_write::write_atomically(&path, &bytes)
            .map_err(|e| library_error(format!("{}: {e}", path.display())))
    }

    /// Number of poses of the scene.
    #[getter]
    fn n_poses(&self) -> usize {
        self.scene.poses.len().max(1)
    }

    /// The cage at rest.
    #[getter]
    fn cage(&self) -> PyCage {
        PyCage {
            cage: self.setup.cage.clone(),
            name: self.scene.obj.display().to_string(),
        }
    }

    /// Number of handles.
    #[getter]
    fn n_handles(&self) -> usize {
        self.setup.rig.n_handles()
    }

    /// Number of cage vertices (the rows `update` writes).
    #[getter]
    fn n_vertices(&self) -> usize {
        self.setup.rig.n_vertices()
    }

    fn __repr__(&self) -> String {
        format!(
            "<splineskin.SubdivRig {:?}: {} cage vertices, {} handles>",
            self.scene.file,
            self.setup.rig.n_vertices(),
            self.setup.rig.n_handles()
        )
    }
}

impl PySubdivRig {
    /// The scene's animation fitted frame by frame, the GIL released.
    fn fitted(&self, py: Python<'_>) -> PyResult<FittedAnimation> {
        let (scene, setup) = (&self.scene, &self.setup);
        py.detach(|| FittedAnimation::new(scene, setup))
            .map_err(library_error)
    }
}
