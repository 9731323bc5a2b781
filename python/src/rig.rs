//! `SplineRig`: the spline fit of a linear blend skinning deformation (the paper's §3–4),
//! precomputed once for a drawing, handles and weights; each pose is then one product
//! `x = O · vec(T)` written into a numpy array.

use std::sync::Arc;

use kurbo::{Affine, Point};
use numpy::{PyArray2, PyArrayMethods, PyReadonlyArray2, PyReadonlyArray3, PyReadwriteArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use splineskin::drawing::follow::FollowOptions;
use splineskin::drawing::svg_out::{write_svg_with, SvgOptions};
use splineskin::drawing::JointKind;
use splineskin::metrics::{chain_metrics, MetricsOptions};
use splineskin::scene::{
    Compat, Deformer, Engine, JunctionOverride, MeshFamily, PosedDrawing, Scene, WeightSpec,
};

use crate::arrays::{affines_into, matrix, matrix_array, output, points};
use crate::drawing::{view_box_rule, PyDrawing};
use crate::library_error;
use crate::scene::{compat_of, PyScene};

/// The spline fit of a skinning deformation, precomputed (`SplineRig(drawing, handles, …)` or
/// `SplineRig.from_scene(scene)`): `update(transforms)` gives the drawing's control points for
/// one affine map per handle.
#[pyclass(module = "splineskin._splineskin", name = "SplineRig")]
pub struct PySplineRig {
    /// The drawing, weights and engine: the fixed-ratio rig, the flexible solve, or a naive
    /// baseline when the scene's engine is one.
    posed: PosedDrawing,
    drawing: Py<PyDrawing>,
    /// The maps of the last update, reused (a frame allocates nothing on the Rust side).
    pose: Vec<Affine>,
    /// Points of the engines that write `Point`s (flexible, baselines), reused.
    scratch: Vec<Point>,
}

impl PySplineRig {
    /// Sets up `scene` in `compat` and builds its engine as `splineskin deform` does
    /// (flexible when the scene asks for it or `flexible`), the GIL released meanwhile.
    fn build(
        py: Python<'_>,
        scene: &Scene,
        compat: Compat,
        flexible: bool,
    ) -> PyResult<PySplineRig> {
        let posed = py
            .detach(|| PosedDrawing::from_scene(scene, compat, flexible))
            .map_err(library_error)?;
        let drawing = Py::new(
            py,
            PyDrawing {
                drawing: Arc::new(posed.drawing().clone()),
                svg_text: scene.svg_text.as_str().into(),
                name: scene.svg_origin.clone(),
            },
        )?;
        Ok(PySplineRig {
            pose: Vec::with_capacity(posed.n_handles()),
            scratch: if posed.deformer().rig().is_some() && !posed.is_flexible() {
                Vec::new()
            } else {
                vec![Point::ZERO; posed.n_points()]
            },
            posed,
            drawing,
        })
    }
}

/// The weight family named `name` (`exponent` for Shepard's).
fn weight_spec(name: &str, exponent: f64) -> PyResult<WeightSpec> {
    Ok(match name {
        "shepard" => WeightSpec::Shepard { exponent },
        "harmonic" => WeightSpec::Mesh(MeshFamily::Harmonic),
        "biharmonic" => WeightSpec::Mesh(MeshFamily::Biharmonic),
        "bbw" => WeightSpec::Mesh(MeshFamily::Bbw),
        other => {
            return Err(PyValueError::new_err(format!(
                "weights={other:?}: expected \"bbw\", \"shepard\", \"harmonic\" or \"biharmonic\""
            )))
        }
    })
}

/// Junction overrides from `(path, joint, kind)` triples.
fn junction_overrides(junctions: Vec<(usize, usize, String)>) -> PyResult<Vec<JunctionOverride>> {
    junctions
        .into_iter()
        .enumerate()
        .map(|(i, (path, joint, kind))| {
            let parsed: JointKind = serde_json::from_value(serde_json::Value::String(kind.clone()))
                .map_err(|_| {
                    PyValueError::new_err(format!(
                        "junctions[{i}]: kind {kind:?} (expected \"C0\", \"C1\", \"G1\" or \"angle\")"
                    ))
                })?;
            Ok(JunctionOverride {
                path,
                joint,
                kind: parsed,
            })
        })
        .collect()
}

#[pymethods]
impl PySplineRig {
    /// Precomputes the rig of `drawing` with point handles at `handles` (`n × 2`), `weights`
    /// one of `"bbw"` (bounded biharmonic on a triangulation of the drawing's domain, Puppet
    /// Warp's), `"shepard"` (inverse distance `1/d^exponent`), `"harmonic"` or
    /// `"biharmonic"`; `junctions` a list of `(path, joint, kind)` replacing the classified
    /// kinds (`"C0"`, `"C1"`, `"G1"`, `"angle"`); `flexible`: G¹ and fixed-angle junctions
    /// keep their tangents' directions but not their length ratio (an iterative solve per
    /// pose, started from the fixed-ratio fit); `engine` `"ours"` (the fit) or one of the
    /// paper's naive baselines, `"fourcontrols"` (skin every control point),
    /// `"twoendpoints"` (skin the anchors, handles follow) or `"jacobian"` (handles by the
    /// skinning map's Jacobian; inverse-distance weights only); `margin` how far the mesh
    /// families' domain reaches beyond the art, a fraction of the diagonal (default 0.01,
    /// Puppet Warp's "expansion", `splineskin deform --margin`).
    #[new]
    #[pyo3(signature = (drawing, handles, *, weights = "bbw", exponent = 2.0, junctions = None, flexible = false, engine = "ours", margin = None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        drawing: PyRef<'_, PyDrawing>,
        handles: PyReadonlyArray2<'_, f64>,
        weights: &str,
        exponent: f64,
        junctions: Option<Vec<(usize, usize, String)>>,
        flexible: bool,
        engine: &str,
        margin: Option<f64>,
    ) -> PyResult<PySplineRig> {
        let handles: Vec<Point> = points(&handles, "handles", None)?;
        let spec = weight_spec(weights, exponent)?;
        if let Some(m) = margin {
            if !(0.0..=splineskin::domain::MAX_MARGIN).contains(&m) {
                return Err(PyValueError::new_err(format!(
                    "margin={m}: expected a fraction of the drawing's diagonal, 0 to {}",
                    splineskin::domain::MAX_MARGIN
                )));
            }
            if matches!(spec, WeightSpec::Shepard { .. }) {
                return Err(PyValueError::new_err(
                    "margin: the shepard weights have no domain (expected weights \"bbw\", \"harmonic\" or \"biharmonic\" with a margin)",
                ));
            }
        }
        let minimal = serde_json::json!({
            "splineskin_scene": splineskin::scene::ours::SCENE_VERSION,
            "svg_text": &*drawing.svg_text,
        });
        let mut scene =
            Scene::from_json(&minimal.to_string(), &drawing.name, None).map_err(library_error)?;
        scene.svg_origin = drawing.name.clone();
        scene.handles = handles;
        scene.weights = spec;
        if let Some(m) = margin {
            scene.domain = scene.domain.clone().with_margin(m);
        }
        scene.junctions = junction_overrides(junctions.unwrap_or_default())?;
        scene.engine = match engine {
            "ours" => Engine::Ours,
            "fourcontrols" => Engine::FourControls,
            "twoendpoints" => Engine::TwoEndpoints,
            "jacobian" => Engine::Jacobian,
            other => {
                return Err(PyValueError::new_err(format!(
                    "engine={other:?}: expected \"ours\" or a naive baseline: \"fourcontrols\", \"twoendpoints\", \"jacobian\""
                )))
            }
        };
        PySplineRig::build(py, &scene, Compat::None, flexible)
    }

    /// Precomputes the rig of `scene` (a `Scene` or a path to a scene file) as `splineskin
    /// deform` does: its drawing, junction kinds, handles, weights and engine (flexible G¹
    /// when the scene asks for it, as the paper authors' scenes do, or `flexible=True`; a
    /// naive baseline when the scene's engine is one); `compat="vectorskinning"` for the
    /// paper authors' code exactly.
    #[staticmethod]
    #[pyo3(signature = (scene, *, compat = None, flexible = false))]
    fn from_scene(
        py: Python<'_>,
        scene: SceneArg<'_>,
        compat: Option<&str>,
        flexible: bool,
    ) -> PyResult<PySplineRig> {
        let compat = compat_of(compat)?;
        match scene {
            SceneArg::Scene(scene) => PySplineRig::build(py, &scene.scene, compat, flexible),
            SceneArg::Path(path) => {
                let scene = PyScene::load_path(py, &path)?;
                PySplineRig::build(py, &scene.scene, compat, flexible)
            }
        }
    }

    /// The control points for `transforms`, one affine map per handle (`n_handles × 2 × 3`
    /// of `[[a, c, e], [b, d, f]]`, or `× 3 × 3` with last rows `(0, 0, 1)`): `n_points × 2`,
    /// written into `out` if given (a C-order `float64` array of that shape; no copy is made
    /// and `out` is returned), else into a new array. The product `O · vec(T)` runs with the
    /// GIL released.
    #[pyo3(signature = (transforms, out = None))]
    fn update<'py>(
        &mut self,
        py: Python<'py>,
        transforms: PyReadonlyArray3<'py, f64>,
        out: Option<Bound<'py, PyArray2<f64>>>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        affines_into(
            &transforms,
            "transforms",
            self.posed.n_handles(),
            &mut self.pose,
        )?;
        let n = self.posed.n_points();
        let out = output(py, out, n, 2)?;
        {
            let mut writable: PyReadwriteArray2<'py, f64> = out.try_readwrite()?;
            let slice = writable.as_slice_mut()?;
            let (posed, pose, scratch) = (&self.posed, &self.pose, &mut self.scratch);
            py.detach(|| -> Result<(), String> {
                match posed.deformer() {
                    // The fixed-ratio rig writes into the caller's array directly.
                    Deformer::Fixed(rig) => {
                        rig.update_coords(pose, slice).map_err(|e| e.to_string())?;
                        if let Some(k) = slice.iter().position(|v| !v.is_finite()) {
                            return Err(format!(
                                "{}: the deformed point {} is not finite (the pose's maps are too large for the drawing)",
                                posed.origin(),
                                k / 2
                            ));
                        }
                        Ok(())
                    }
                    _ => {
                        posed.update(pose, scratch).map_err(|e| e.to_string())?;
                        for (xy, p) in slice.chunks_exact_mut(2).zip(scratch.iter()) {
                            xy[0] = p.x;
                            xy[1] = p.y;
                        }
                        Ok(())
                    }
                }
            })
            .map_err(library_error)?;
        }
        Ok(out)
    }

    /// How far `points` (`n_points × 2`; default: this rig's `update(transforms)`) are from
    /// the skinned target under `transforms` (the paper's figures, `splineskin compare`'s):
    /// `{"energy": ∫‖R − s‖², "max": largest distance / diagonal, "rms": …, "per_curve":
    /// n_curves × 3 array of the three per input curve, "diagonal": …}`, distances sampled at
    /// the same parameter on both.
    #[pyo3(signature = (transforms, points = None))]
    fn metrics<'py>(
        &mut self,
        py: Python<'py>,
        transforms: PyReadonlyArray3<'py, f64>,
        points: Option<PyReadonlyArray2<'py, f64>>,
    ) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
        let result: Vec<Point> = match &points {
            Some(p) => {
                affines_into(
                    &transforms,
                    "transforms",
                    self.posed.n_handles(),
                    &mut self.pose,
                )?;
                crate::arrays::points(p, "points", Some(self.posed.n_points()))?
            }
            None => {
                let out = self.update(py, transforms, None)?;
                let data = out.readonly();
                crate::arrays::points(&data, "points", None)?
            }
        };
        let (posed, pose) = (&self.posed, &self.pose);
        let m = py
            .detach(|| {
                chain_metrics(
                    posed.drawing(),
                    posed.weights(),
                    pose,
                    &result,
                    &MetricsOptions::default(),
                )
            })
            .map_err(library_error)?;
        let dict = pyo3::types::PyDict::new(py);
        dict.set_item("energy", m.overall.energy)?;
        dict.set_item("max", m.overall.max)?;
        dict.set_item("rms", m.overall.rms)?;
        dict.set_item("diagonal", m.diagonal)?;
        let per: Vec<f64> = m
            .per_curve
            .iter()
            .flat_map(|f| [f.energy, f.max, f.rms])
            .collect();
        dict.set_item("per_curve", matrix_array(py, per, 3))?;
        Ok(dict)
    }

    /// The SVG document deformed by `transforms` (one affine map per handle, as `update`
    /// takes them), as `splineskin deform` writes it: the input document with every element's
    /// control points moved, ids, styles and structure kept, and gradients, patterns,
    /// markers, text and images carried by the deformation's best-fit map over each element
    /// (stroke widths scaled by it with `scale_strokes`). `viewbox`: `"keep"` the input's, or
    /// `"fit"` it to the deformed art.
    #[pyo3(signature = (transforms, *, viewbox = "keep", scale_strokes = false))]
    fn to_svg(
        &self,
        py: Python<'_>,
        transforms: PyReadonlyArray3<'_, f64>,
        viewbox: &str,
        scale_strokes: bool,
    ) -> PyResult<String> {
        let rule = view_box_rule(viewbox)?;
        let mut pose = Vec::with_capacity(self.posed.n_handles());
        affines_into(&transforms, "transforms", self.posed.n_handles(), &mut pose)?;
        let (posed, pose) = (&self.posed, &pose);
        py.detach(|| -> Result<String, String> {
            let mut points = vec![Point::ZERO; posed.n_points()];
            posed.update(pose, &mut points).map_err(|e| e.to_string())?;
            let follow = FollowOptions::default().with_scale_strokes(scale_strokes);
            let maps = posed
                .setup()
                .element_maps(pose, &follow)
                .map_err(|e| e.to_string())?;
            let options = SvgOptions::default()
                .with_view_box(rule)
                .with_follow(maps.as_ref());
            write_svg_with(posed.drawing(), &points, &options).map_err(|e| e.to_string())
        })
        .map_err(library_error)
    }

    /// The weights of every handle at `points` (`m × 2`): `m × n_handles`.
    fn weights_at<'py>(
        &self,
        py: Python<'py>,
        points: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let data = matrix(&points, "points", None, 2)?;
        let weights = self.posed.weights();
        let h = weights.n_handles();
        let values = py.detach(|| {
            let mut values = vec![0.0; data.len() / 2 * h];
            for (p, row) in data.chunks_exact(2).zip(values.chunks_exact_mut(h.max(1))) {
                weights.eval(Point::new(p[0], p[1]), row);
            }
            values
        });
        Ok(matrix_array(py, values, h))
    }

    /// The drawing the rig deforms (with the junction kinds it was built with).
    #[getter]
    fn drawing(&self, py: Python<'_>) -> Py<PyDrawing> {
        self.drawing.clone_ref(py)
    }

    /// Number of handles.
    #[getter]
    fn n_handles(&self) -> usize {
        self.posed.n_handles()
    }

    /// Number of chain points of the drawing (the rows `update` writes).
    #[getter]
    fn n_points(&self) -> usize {
        self.posed.n_points()
    }

    /// Whether G¹ and fixed-angle junctions are flexible (each `update` then solves).
    #[getter]
    fn flexible(&self) -> bool {
        self.posed.is_flexible()
    }

    /// The engine: `ours` (the spline fit, fixed or flexible) or a naive baseline of the
    /// scene (`fourcontrols`, `twoendpoints`, `jacobian`).
    #[getter]
    fn engine(&self) -> &'static str {
        self.posed.engine().name()
    }

    /// The operator `O`: `(2 · n_points) × (6 · n_handles)`, row `2k + d` coordinate `d` of
    /// point `k`, column `6i + c` coefficient `c` of handle `i`'s map `(a, b, c, d, e, f)`
    /// (SVG's order: `x' = a x + c y + e`, `y' = b x + d y + f`). A copy.
    #[getter]
    fn operator<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let rig = self.posed.rig().ok_or_else(|| {
            PyValueError::new_err("a naive baseline has no operator (it is not a linear fit)")
        })?;
        Ok(matrix_array(
            py,
            rig.operator().to_vec(),
            6 * rig.n_handles(),
        ))
    }

    fn __repr__(&self) -> String {
        format!(
            "<splineskin.SplineRig: {} points, {} handles, {}{}>",
            self.posed.n_points(),
            self.posed.n_handles(),
            self.posed.engine().name(),
            if self.posed.is_flexible() {
                ", flexible"
            } else {
                ""
            }
        )
    }
}

/// A scene given as a `Scene` or as a path to its file.
pub enum SceneArg<'py> {
    /// A loaded scene.
    Scene(PyRef<'py, PyScene>),
    /// A path to a scene file.
    Path(std::path::PathBuf),
}

impl<'a, 'py> FromPyObject<'a, 'py> for SceneArg<'py> {
    type Error = PyErr;
    fn extract(object: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        if let Ok(scene) = object.extract::<PyRef<'py, PyScene>>() {
            return Ok(SceneArg::Scene(scene));
        }
        object
            .extract::<std::path::PathBuf>()
            .map(SceneArg::Path)
            .map_err(|_| {
                PyValueError::new_err(
                    "scene: expected a splineskin.Scene or a path to a scene file",
                )
            })
    }
}

impl SceneArg<'_> {
    /// The scene: the one given, or the file read.
    pub fn load(self, py: Python<'_>) -> PyResult<Scene> {
        match self {
            SceneArg::Scene(scene) => Ok(scene.scene.clone()),
            SceneArg::Path(path) => Ok(PyScene::load_path(py, &path)?.scene),
        }
    }
}
