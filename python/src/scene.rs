//! `Scene`: a scene file (ours or the paper authors'), read as `splineskin deform` reads it:
//! its drawing, handles, weight family and poses.

use numpy::{PyArray2, PyArray3};
use pyo3::exceptions::{PyIndexError, PyValueError};
use pyo3::prelude::*;
use splineskin::scene::{Compat, Scene, WeightSpec};

use crate::arrays::points_array;
use crate::drawing::{check_exists, PyDrawing};
use crate::library_error;

/// A scene: a drawing, its handles, weights and poses (`Scene.load`, `Scene.from_json`).
#[pyclass(module = "splineskin._splineskin", name = "Scene", frozen)]
pub struct PyScene {
    /// The scene.
    pub scene: Scene,
}

/// The compatibility mode named `compat`: `None` (ours) or `"vectorskinning"` (the paper
/// authors' code exactly, as `--compat vectorskinning`).
pub fn compat_of(compat: Option<&str>) -> PyResult<Compat> {
    match compat {
        None => Ok(Compat::None),
        Some("vectorskinning") => Ok(Compat::VectorSkinning),
        Some(other) => Err(PyValueError::new_err(format!(
            "compat={other:?}: expected None or \"vectorskinning\""
        ))),
    }
}

/// `transforms` (one per handle) as a `k × 2 × 3` array of `[[a, c, e], [b, d, f]]`.
pub fn affines_array<'py>(
    py: Python<'py>,
    transforms: &[kurbo::Affine],
) -> PyResult<Bound<'py, PyArray3<f64>>> {
    let data: Vec<f64> = transforms
        .iter()
        .flat_map(|t| {
            let [a, b, c, d, e, f] = t.as_coeffs();
            [a, c, e, b, d, f]
        })
        .collect();
    let array = numpy::ndarray::Array3::from_shape_vec((transforms.len(), 2, 3), data)
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(PyArray3::from_owned_array(py, array))
}

impl PyScene {
    /// Reads the scene file at `path` (a missing file is `FileNotFoundError`).
    pub fn load_path(py: Python<'_>, path: &std::path::Path) -> PyResult<PyScene> {
        check_exists(path)?;
        let scene = py.detach(|| Scene::load(path)).map_err(library_error)?;
        Ok(PyScene { scene })
    }
}

#[pymethods]
impl PyScene {
    /// Reads a scene file (ours or the paper authors'). A scene of ours may name its SVG
    /// file relative to the scene's folder.
    #[staticmethod]
    #[pyo3(signature = (path, /))]
    fn load(py: Python<'_>, path: std::path::PathBuf) -> PyResult<PyScene> {
        PyScene::load_path(py, &path)
    }

    /// Parses a scene from its JSON text (its SVG inline; `name` names it in messages).
    #[staticmethod]
    #[pyo3(signature = (text, /, name = "<scene>"))]
    fn from_json(text: &str, name: &str) -> PyResult<PyScene> {
        let scene = Scene::from_json(text, name, None).map_err(library_error)?;
        Ok(PyScene { scene })
    }

    /// The file the scene came from, or its given name.
    #[getter]
    fn name(&self) -> &str {
        &self.scene.origin
    }

    /// The point handles' rest positions: `float64` array `n_handles × 2`.
    #[getter]
    fn handles<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        points_array(py, &self.scene.handles)
    }

    /// Number of handles of the rig (points, bones and cage vertices).
    #[getter]
    fn n_handles(&self) -> usize {
        self.scene.n_handles()
    }

    /// The weight family: `shepard`, `harmonic`, `biharmonic`, `bbw` or `mvc`.
    #[getter]
    fn weights(&self) -> String {
        match &self.scene.weights {
            WeightSpec::Shepard { .. } => "shepard".into(),
            WeightSpec::Mesh(family) => family.name().into(),
            WeightSpec::MeanValue => "mvc".into(),
            WeightSpec::NotImplemented(name) => name.clone(),
        }
    }

    /// Whether the scene asks for flexible G¹ junctions.
    #[getter]
    fn flexible(&self) -> bool {
        self.scene.flexible
    }

    /// Number of poses (a scene without poses has one: the identity).
    #[getter]
    fn n_poses(&self) -> usize {
        self.scene.poses.len().max(1)
    }

    /// The poses' names (`None` for unnamed ones).
    #[getter]
    fn pose_names(&self) -> Vec<Option<String>> {
        if self.scene.poses.is_empty() {
            return vec![None];
        }
        self.scene.poses.iter().map(|p| p.name.clone()).collect()
    }

    /// Pose `index` (or named `index`): one affine map per handle, `float64` array
    /// `n_handles × 2 × 3` of `[[a, c, e], [b, d, f]]`.
    #[pyo3(signature = (index = PoseKey::Index(0)))]
    fn pose<'py>(&self, py: Python<'py>, index: PoseKey) -> PyResult<Bound<'py, PyArray3<f64>>> {
        let pose = match index {
            PoseKey::Index(i) => self.scene.pose(i).ok_or_else(|| {
                PyIndexError::new_err(format!(
                    "{}: pose {i} does not exist ({} poses)",
                    self.scene.origin,
                    self.scene.poses.len().max(1)
                ))
            })?,
            PoseKey::Name(name) => {
                self.scene
                    .pose_by_key(&name)
                    .map_err(|e| PyIndexError::new_err(format!("{}: {e}", self.scene.origin)))?
                    .1
            }
        };
        affines_array(py, &pose.transforms)
    }

    /// The scene's drawing, read as ours (`compat=None`) or as the paper authors' code reads
    /// it (`compat="vectorskinning"`).
    #[pyo3(signature = (*, compat = None))]
    fn drawing(&self, py: Python<'_>, compat: Option<&str>) -> PyResult<PyDrawing> {
        let compat = compat_of(compat)?;
        let scene = &self.scene;
        let drawing = py.detach(|| scene.drawing(compat)).map_err(library_error)?;
        Ok(PyDrawing {
            drawing: std::sync::Arc::new(drawing),
            svg_text: scene.svg_text.as_str().into(),
            name: scene.svg_origin.clone(),
        })
    }

    fn __repr__(&self) -> String {
        format!(
            "<splineskin.Scene {:?}: {} handles, {} weights, {} poses>",
            self.scene.origin,
            self.scene.n_handles(),
            self.weights(),
            self.n_poses()
        )
    }
}

/// A pose asked for by index or by name.
pub enum PoseKey {
    /// Its index in the scene's poses.
    Index(usize),
    /// Its name.
    Name(String),
}

impl<'a, 'py> FromPyObject<'a, 'py> for PoseKey {
    type Error = PyErr;
    fn extract(object: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        if let Ok(i) = object.extract::<usize>() {
            return Ok(PoseKey::Index(i));
        }
        object
            .extract::<String>()
            .map(PoseKey::Name)
            .map_err(|_| PyValueError::new_err("a pose is asked for by index (int) or name (str)"))
    }
}
