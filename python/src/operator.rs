//! `Operator` and `OperatorRig`: deformation operators (Poranne & Lipman 2016) — closed-form
//! approximations of ARAP or symmetric ARAP deformations of a triangle mesh driven by point
//! handles, trained on ground-truth solves — and their join with a drawing, so that the
//! drawing's control points are one product per configuration (`G_spline · ψ(Q)`).

use std::sync::Mutex;

use kurbo::Point;
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use splineskin::defop::{
    train, DefOpRig, Energy, OperatorFile, Progress, StopSignal, TrainingMetadata,
};
use splineskin::scene::{Compat, DefOpSettings};
use splineskin::spline_fit::FitOptions;

use crate::arrays::{matrix_array, output, points, points_array, points_into};
use crate::drawing::{check_exists, PyDrawing};
use crate::library_error;
use crate::rig::SceneArg;
use crate::weights::{handle_vertices, mesh_of};

/// A trained deformation operator on a triangle mesh (`Operator.train`, `Operator.from_scene`,
/// `Operator.load`): `evaluate(Q)` deforms the mesh for handle positions `Q`.
#[pyclass(module = "splineskin._splineskin", name = "Operator", frozen)]
pub struct PyOperator {
    file: OperatorFile,
}

/// The energy named `name`: `"sarap"` (symmetric ARAP, never folds a triangle) or `"arap"`.
fn energy_of(name: &str) -> PyResult<Energy> {
    match name {
        "sarap" => Ok(Energy::SymmetricArap),
        "arap" => Ok(Energy::Arap),
        other => Err(PyValueError::new_err(format!(
            "energy={other:?}: expected \"sarap\" (symmetric ARAP) or \"arap\""
        ))),
    }
}

/// Trains on `mesh` with handles at vertices `handles` as `settings` ask, reporting each
/// ground-truth solve to `progress` (a Python callable `(solved, to_solve, stage, n_stages)`,
/// called with the GIL taken back). The training runs on a thread of its own while this one
/// waits with the GIL released, looking at Python's signals every [`SIGNAL_POLL`]: an
/// exception from the callback, or a `KeyboardInterrupt` (Ctrl-C, a notebook's interrupt),
/// stops the training at its next solve ([`StopSignal`]) and is raised.
fn train_file(
    py: Python<'_>,
    mesh: splineskin::mesh::TriMesh,
    handles: Vec<usize>,
    settings: &DefOpSettings,
    cover: Vec<Vec<Point>>,
    progress: Option<Py<PyAny>>,
    source: String,
) -> PyResult<OperatorFile> {
    let failed: Mutex<Option<PyErr>> = Mutex::new(None);
    let stop = StopSignal::new();
    // Keeps the first exception and stops the training.
    let fail = |e: PyErr| {
        if let Ok(mut slot) = failed.lock() {
            slot.get_or_insert(e);
        }
        stop.raise();
    };
    let work = || -> Result<OperatorFile, String> {
        let spatial = settings
            .spatial_basis
            .build(&mesh, &handles)
            .map_err(|e| format!("{source}: spatial basis: {e}"))?;
        let options = settings
            .train_options(&mesh)
            .with_cover(cover)
            .with_stop(stop.clone());
        let report = |p: Progress| {
            let Some(callback) = &progress else { return };
            // Checked and raised with the GIL held, so once the callback has raised, no
            // other thread calls it again.
            Python::attach(|py| {
                if stop.is_raised() {
                    return;
                }
                if let Err(e) = callback.call1(py, (p.solved, p.to_solve, p.stage, p.n_stages)) {
                    fail(e);
                }
            });
        };
        let started = std::time::Instant::now();
        let training = train(&mesh, &handles, &spatial, &options, &report)
            .map_err(|e| format!("{source}: training: {e}"))?;
        let mut metadata = TrainingMetadata::default();
        metadata.energy = Some(splineskin::scene::energy_name(settings.energy).into());
        metadata.n_samples = Some(settings.samples);
        metadata.sample_region = Some(settings.region.describe());
        metadata.seed = Some(settings.seed);
        metadata.training_seconds = Some(started.elapsed().as_secs_f64());
        metadata.source = Some(source.clone());
        metadata.spatial_basis = Some(settings.spatial_basis.name());
        OperatorFile::new(mesh, training.op, metadata).map_err(|e| e.to_string())
    };
    let caller = std::thread::current();
    let result = std::thread::scope(|scope| {
        let worker = scope.spawn(|| {
            let result = work();
            caller.unpark();
            result
        });
        // Wakes when the training ends (or at the latest after SIGNAL_POLL, which also covers
        // a worker that panicked before unparking).
        while !worker.is_finished() {
            py.detach(|| std::thread::park_timeout(SIGNAL_POLL));
            if let Err(e) = py.check_signals() {
                fail(e);
            }
        }
        worker.join()
    });
    if let Some(e) = failed.into_inner().ok().flatten() {
        return Err(e);
    }
    match result {
        Ok(result) => result.map_err(library_error),
        Err(_) => Err(library_error(format!(
            "{source}: the training thread panicked"
        ))),
    }
}

/// How often a training waiting in [`train_file`] looks at Python's signals: 0.1 s.
const SIGNAL_POLL: std::time::Duration = std::time::Duration::from_millis(100);

/// The settings of a training: `base` with what the caller gave.
fn settings_with(
    mut base: DefOpSettings,
    energy: Option<&str>,
    samples: Option<usize>,
    seed: Option<u64>,
) -> PyResult<DefOpSettings> {
    if let Some(e) = energy {
        base.energy = energy_of(e)?;
    }
    if let Some(n) = samples {
        if n == 0 {
            return Err(PyValueError::new_err(
                "samples=0: expected at least 1 training sample",
            ));
        }
        base.samples = n;
    }
    if let Some(s) = seed {
        base.seed = s;
    }
    Ok(base)
}

#[pymethods]
impl PyOperator {
    /// Trains an operator on the mesh `(V, F)` (libigl's conventions) driven by handles at
    /// vertices `b`: `samples` ground-truth deformations (`energy` `"sarap"` or `"arap"`) of
    /// handle configurations drawn in discs about the rest (seeded by `seed`), fitted in
    /// bootstrapping stages. `progress(solved, to_solve, stage, n_stages)` is called after each
    /// solve. Runs on all cores with the GIL released. An exception raised by `progress`, or
    /// Ctrl-C (`KeyboardInterrupt`), stops the training at its next solve and is raised.
    #[staticmethod]
    #[pyo3(signature = (V, F, b, *, energy = "sarap", samples = 100, seed = 1, progress = None))]
    #[allow(non_snake_case, clippy::too_many_arguments)]
    fn train(
        py: Python<'_>,
        V: numpy::PyArrayLike2<'_, f64, numpy::AllowTypeChange>,
        F: numpy::PyArrayLike2<'_, i64, numpy::AllowTypeChange>,
        b: Bound<'_, PyAny>,
        energy: &str,
        samples: usize,
        seed: u64,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<PyOperator> {
        let mesh = mesh_of(&V, &F)?;
        let handles = handle_vertices(&b, &mesh)?;
        let settings = settings_with(
            DefOpSettings::default(),
            Some(energy),
            Some(samples),
            Some(seed),
        )?;
        let file = train_file(
            py,
            mesh,
            handles,
            &settings,
            Vec::new(),
            progress,
            "mesh".into(),
        )?;
        Ok(PyOperator { file })
    }

    /// Trains the operator of `scene` (a `Scene` or a path) as `splineskin defop train` does:
    /// on the drawing's domain (or the scene's mesh), with the scene's `defop` settings, any of
    /// which `energy`, `samples`, `seed` replace; `cover` `"poses"` or `"animation"` adds
    /// samples along the way to the scene's poses or frames.
    #[staticmethod]
    #[pyo3(signature = (scene, *, energy = None, samples = None, seed = None, cover = None, progress = None))]
    fn from_scene(
        py: Python<'_>,
        scene: SceneArg<'_>,
        energy: Option<&str>,
        samples: Option<usize>,
        seed: Option<u64>,
        cover: Option<&str>,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<PyOperator> {
        let scene = scene.load(py)?;
        let mut settings = settings_with(
            scene.defop.clone().unwrap_or_default(),
            energy,
            samples,
            seed,
        )?;
        if let Some(name) = cover {
            settings.cover = splineskin::scene::Cover::parse(name).ok_or_else(|| {
                PyValueError::new_err(format!(
                    "cover={name:?}: expected \"poses\" or \"animation\""
                ))
            })?;
        }
        let shape = py
            .detach(|| scene.defop_shape(&settings))
            .map_err(library_error)?;
        let rest: Vec<Point> = shape
            .handles
            .iter()
            .map(|&h| shape.mesh.vertices[h])
            .collect();
        let configurations = scene
            .cover_configurations(settings.cover, &rest)
            .map_err(library_error)?;
        let file = train_file(
            py,
            shape.mesh,
            shape.handles,
            &settings,
            configurations,
            progress,
            scene.origin.clone(),
        )?;
        Ok(PyOperator { file })
    }

    /// Reads an operator file (`splineskin defop train -o FILE`, or `Operator.save`).
    #[staticmethod]
    #[pyo3(signature = (path, /))]
    fn load(py: Python<'_>, path: std::path::PathBuf) -> PyResult<PyOperator> {
        check_exists(&path)?;
        let file = py
            .detach(|| OperatorFile::load(&path))
            .map_err(library_error)?;
        Ok(PyOperator { file })
    }

    /// Writes the operator file (read back by `Operator.load` and `splineskin defop deform
    /// --operator`).
    #[pyo3(signature = (path, /))]
    fn save(&self, py: Python<'_>, path: std::path::PathBuf) -> PyResult<()> {
        let file = &self.file;
        py.detach(|| file.save(&path)).map_err(library_error)
    }

    /// The mesh deformed for handle positions `Q` (`n_handles × 2`): `n_vertices × 2`.
    #[allow(non_snake_case)]
    fn evaluate<'py>(
        &self,
        py: Python<'py>,
        Q: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let q = points(&Q, "Q", Some(self.file.op.n_handles()))?;
        let op = &self.file.op;
        let positions = py.detach(|| op.eval(&q)).map_err(library_error)?;
        Ok(points_array(py, &positions))
    }

    /// Joins `drawing` (a `Drawing`, or a `Scene` whose drawing and junction kinds are used
    /// as `splineskin defop deform` uses them) with the operator: an `OperatorRig`.
    fn join(&self, py: Python<'_>, drawing: JoinArg<'_>) -> PyResult<PyOperatorRig> {
        let (drawing, options) = match drawing {
            JoinArg::Drawing(d) => (
                (*d.drawing).clone(),
                FitOptions::default().with_parallel(true),
            ),
            JoinArg::Scene(scene) => {
                let (drawing, _) = scene
                    .scene
                    .drawing_with_junctions(Compat::None)
                    .map_err(library_error)?;
                (
                    drawing,
                    scene.scene.fit_options(Compat::None).with_parallel(true),
                )
            }
        };
        let file = &self.file;
        let rig = py
            .detach(|| DefOpRig::precompute(&drawing, &file.mesh, &file.op, &options))
            .map_err(library_error)?;
        Ok(PyOperatorRig {
            psi: vec![0.0; rig.handle_basis().n_functions()],
            q: Vec::with_capacity(rig.n_handles()),
            rig,
        })
    }

    /// The mesh's vertices at rest, `n_vertices × 2`.
    #[getter]
    #[allow(non_snake_case)]
    fn V<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        points_array(py, &self.file.mesh.vertices)
    }

    /// The mesh's triangles, `int64` `m × 3`.
    #[getter]
    #[allow(non_snake_case)]
    fn F<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        let data: Vec<i64> = self
            .file
            .mesh
            .triangles
            .iter()
            .flat_map(|t| t.map(|i| i as i64))
            .collect();
        let array =
            numpy::ndarray::Array2::from_shape_vec((self.file.mesh.triangles.len(), 3), data)
                .map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(PyArray2::from_owned_array(py, array))
    }

    /// The handles' vertices, `int64`.
    #[getter]
    fn b<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        let b: Vec<i64> = self.file.op.handles().iter().map(|&i| i as i64).collect();
        PyArray1::from_vec(py, b)
    }

    /// The handles' rest positions, `n_handles × 2`.
    #[getter]
    fn rest_handles<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        points_array(py, &self.file.rest_handles())
    }

    /// Number of handles.
    #[getter]
    fn n_handles(&self) -> usize {
        self.file.op.n_handles()
    }

    /// How it was trained, as a dict (the operator file's metadata): `energy`, `n_samples`,
    /// `sample_region`, `seed`, `training_seconds`, `source`, `spatial_basis`; `None` where
    /// the file does not say.
    #[getter]
    fn metadata<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let text = serde_json::to_string(&self.file.metadata)
            .map_err(|e| PyValueError::new_err(format!("metadata: {e}")))?;
        py.import("json")?.call_method1("loads", (text,))
    }

    fn __repr__(&self) -> String {
        format!(
            "<splineskin.Operator: {} vertices, {} handles>",
            self.file.mesh.n_vertices(),
            self.file.op.n_handles()
        )
    }
}

/// A drawing joined to an operator (`Operator.join`): `update(Q)` gives its control points for
/// handle positions `Q`.
#[pyclass(module = "splineskin._splineskin", name = "OperatorRig")]
pub struct PyOperatorRig {
    rig: DefOpRig,
    /// `ψ(Q)` of the last update, reused (a frame allocates nothing on the Rust side).
    psi: Vec<f64>,
    /// The handle positions of the last update, reused.
    q: Vec<Point>,
}

#[pymethods]
impl PyOperatorRig {
    /// The drawing's control points (`n_points × 2`) for handle positions `Q`
    /// (`n_handles × 2`), written into `out` if given (a C-order `float64` array of that shape,
    /// returned), else into a new array.
    #[pyo3(signature = (Q, out = None))]
    #[allow(non_snake_case)]
    fn update<'py>(
        &mut self,
        py: Python<'py>,
        Q: PyReadonlyArray2<'py, f64>,
        out: Option<Bound<'py, PyArray2<f64>>>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        points_into(&Q, "Q", Some(self.rig.n_handles()), &mut self.q)?;
        let out = output(py, out, self.rig.n_points(), 2)?;
        {
            let mut writable = out.try_readwrite()?;
            let slice = writable.as_slice_mut()?;
            let (rig, q, psi) = (&self.rig, &self.q, &mut self.psi);
            py.detach(|| rig.write_coords(q, psi, slice))
                .map_err(library_error)?;
        }
        Ok(out)
    }

    /// `G_spline`, `(2 · n_points) × |Ψ|`: the drawing's coordinates are `G_spline · ψ(Q)`.
    #[getter]
    fn operator<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        // Stored column-major: transpose into rows.
        let rows = 2 * self.rig.n_points();
        let cols = self.rig.handle_basis().n_functions();
        let c = self.rig.coefficients();
        let mut data = vec![0.0; rows * cols];
        for j in 0..cols {
            for i in 0..rows {
                data[i * cols + j] = c[j * rows + i];
            }
        }
        matrix_array(py, data, cols)
    }

    /// Number of handles.
    #[getter]
    fn n_handles(&self) -> usize {
        self.rig.n_handles()
    }

    /// Number of chain points written.
    #[getter]
    fn n_points(&self) -> usize {
        self.rig.n_points()
    }

    fn __repr__(&self) -> String {
        format!(
            "<splineskin.OperatorRig: {} points, {} handles>",
            self.rig.n_points(),
            self.rig.n_handles()
        )
    }
}

/// What `Operator.join` takes: a drawing, or a scene.
pub enum JoinArg<'py> {
    /// A drawing with its classified junction kinds.
    Drawing(PyRef<'py, PyDrawing>),
    /// A scene: its drawing with its junction kinds and fit options.
    Scene(PyRef<'py, crate::scene::PyScene>),
}

impl<'a, 'py> FromPyObject<'a, 'py> for JoinArg<'py> {
    type Error = PyErr;
    fn extract(object: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        if let Ok(d) = object.extract::<PyRef<'py, PyDrawing>>() {
            return Ok(JoinArg::Drawing(d));
        }
        object
            .extract::<PyRef<'py, crate::scene::PyScene>>()
            .map(JoinArg::Scene)
            .map_err(|_| {
                PyValueError::new_err("join: expected a splineskin.Drawing or a splineskin.Scene")
            })
    }
}
