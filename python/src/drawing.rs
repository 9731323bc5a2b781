//! `Drawing`: a drawing read from an SVG document (every shape as cubic Bézier paths in the
//! root's user units), its control points as arrays, and the document written back with other
//! control points (`to_svg`), its styles, ids, text and everything else kept.

use std::path::PathBuf;
use std::sync::Arc;

use numpy::{PyArray1, PyArray2, PyReadonlyArray2};
use pyo3::exceptions::{PyFileNotFoundError, PyValueError};
use pyo3::prelude::*;
use splineskin::domain::{Domain, DomainOptions, DomainShape};
use splineskin::drawing::svg_out::{write_svg_view_box, ViewBoxRule};
use splineskin::drawing::{read_svg_named, Drawing, ImportOptions};

use crate::arrays::{matrix, points_array};
use crate::library_error;

/// A drawing of cubic Bézier paths read from an SVG document (`Drawing.from_svg`).
///
/// Control points are "chain points": a path of `n` cubics has `3n + 1` of them, anchors at
/// `0, 3, 6, …`, the handles between them (a closed path's last point is its first again);
/// `points` concatenates every path's, in document order.
#[pyclass(module = "splineskin._splineskin", name = "Drawing", frozen)]
pub struct PyDrawing {
    /// The drawing.
    pub drawing: Arc<Drawing>,
    /// The SVG document's text (scenes and rigs are built from it, as the command line does).
    pub svg_text: Arc<str>,
    /// The file it came from, or `<svg text>`.
    pub name: String,
}

impl PyDrawing {
    /// Reads `text` as an SVG document named `name`.
    pub fn read(py: Python<'_>, text: String, name: String) -> PyResult<PyDrawing> {
        let drawing = py
            .detach(|| read_svg_named(&text, &ImportOptions::default(), &name))
            .map_err(library_error)?;
        Ok(PyDrawing {
            drawing: Arc::new(drawing),
            svg_text: text.into(),
            name,
        })
    }
}

/// What `from_svg` was given: a document's text or a file's path.
pub enum Source {
    /// The SVG text itself.
    Text(String),
    /// A path to read.
    Path(PathBuf),
}

impl<'a, 'py> FromPyObject<'a, 'py> for Source {
    type Error = PyErr;
    fn extract(object: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        if let Ok(text) = object.extract::<String>() {
            return Ok(if text.trim_start().starts_with('<') {
                Source::Text(text)
            } else {
                Source::Path(PathBuf::from(text))
            });
        }
        object.extract::<PathBuf>().map(Source::Path).map_err(|_| {
            PyValueError::new_err(
                "expected an SVG document's text (starting with '<') or a path to one (str or \
                 os.PathLike)",
            )
        })
    }
}

/// `FileNotFoundError` naming `path` if there is nothing there.
pub fn check_exists(path: &std::path::Path) -> PyResult<()> {
    if path.exists() {
        Ok(())
    } else {
        Err(PyFileNotFoundError::new_err(format!(
            "{}: no such file",
            path.display()
        )))
    }
}

/// Reads `path` as text, with the errors a Python user expects.
pub fn read_text(path: &std::path::Path) -> PyResult<String> {
    let name = path.display();
    check_exists(path)?;
    std::fs::read_to_string(path).map_err(|e| match e.kind() {
        std::io::ErrorKind::InvalidData => {
            library_error(format!("{name}: not UTF-8 text; expected an SVG document"))
        }
        _ => library_error(format!("{name}: cannot read: {e}")),
    })
}

#[pymethods]
impl PyDrawing {
    /// Reads an SVG document: its text (a string starting with `<`) or a path to it.
    #[staticmethod]
    #[pyo3(signature = (source, /))]
    fn from_svg(py: Python<'_>, source: Source) -> PyResult<PyDrawing> {
        match source {
            Source::Text(text) => PyDrawing::read(py, text, "<svg text>".into()),
            Source::Path(path) => {
                let text = read_text(&path)?;
                PyDrawing::read(py, text, path.display().to_string())
            }
        }
    }

    /// The file the drawing came from, or `<svg text>`.
    #[getter]
    fn name(&self) -> &str {
        &self.name
    }

    /// Number of paths (subpaths in document order).
    #[getter]
    fn n_paths(&self) -> usize {
        self.drawing.paths.len()
    }

    /// Number of cubic curves.
    #[getter]
    fn n_curves(&self) -> usize {
        self.drawing.n_curves()
    }

    /// Number of chain points of all paths (the rows of `points`).
    #[getter]
    fn n_points(&self) -> usize {
        self.drawing.n_points()
    }

    /// The rest control points of every path, concatenated: `float64` array `n_points × 2`.
    #[getter]
    fn points<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        points_array(py, &self.drawing.flat_points())
    }

    /// Where each path's rows start in `points`, and where the last ends (`n_paths + 1`
    /// numbers).
    #[getter]
    fn offsets(&self) -> Vec<usize> {
        let mut offsets = vec![0];
        for path in &self.drawing.paths {
            offsets.push(offsets.last().copied().unwrap_or(0) + path.points.len());
        }
        offsets
    }

    /// Whether each path is closed.
    #[getter]
    fn closed(&self) -> Vec<bool> {
        self.drawing.paths.iter().map(|p| p.closed).collect()
    }

    /// Each path's junction kinds as classified from the geometry, joint `k` starting curve
    /// `k`: `"end"` (an open path's ends), `"C0"`, `"C1"`, `"G1"` or `"angle"`.
    #[getter]
    fn joints(&self) -> Vec<Vec<&'static str>> {
        self.drawing
            .paths
            .iter()
            .map(|p| p.joints.iter().map(|k| k.name()).collect())
            .collect()
    }

    /// The length of the diagonal of the control points' bounding box (tolerances and
    /// distances are fractions of it).
    #[getter]
    fn diagonal(&self) -> f64 {
        self.drawing.diagonal()
    }

    /// The SVG document with the control points `points` (`n_points × 2`, as `points`) in
    /// place of the drawing's: every style, id, text and other element kept. `viewbox`:
    /// `"keep"` the document's viewBox (art outside is cropped by viewers) or `"fit"` (grown
    /// to hold the art).
    #[pyo3(signature = (points, *, viewbox = "keep"))]
    fn to_svg(
        &self,
        py: Python<'_>,
        points: PyReadonlyArray2<'_, f64>,
        viewbox: &str,
    ) -> PyResult<String> {
        let rule = view_box_rule(viewbox)?;
        let data = matrix(&points, "points", Some(self.drawing.n_points()), 2)?;
        let points: Vec<kurbo::Point> = data
            .chunks_exact(2)
            .map(|p| kurbo::Point::new(p[0], p[1]))
            .collect();
        let drawing = self.drawing.clone();
        py.detach(move || write_svg_view_box(&drawing, &points, rule))
            .map_err(library_error)
    }

    /// The triangulated domain the mesh weight families are solved on (with its curves'
    /// samples, refined to `min_angle` degrees and triangles of at most `max_area_fraction` of
    /// its area, up to `max_vertices`), with a vertex at each of `handles` (`n × 2`):
    /// `(V, F, b)` in libigl's conventions, `V` `float64` `n × 2`, `F` `int64` `m × 3`
    /// (counter-clockwise), `b` `int64` the handles' vertices. `shape="enclosing"` (the
    /// default, the paper's): the drawing's largest closed curve around everything, else its
    /// padded bounding box; `shape="art"` (what scenes and `SplineRig` use): the region the
    /// drawing paints grown by `margin` (a fraction of the diagonal, default 0.01), one piece
    /// per group of touching shapes, pieces without a handle left out.
    #[pyo3(signature = (handles, *, max_area_fraction = None, max_vertices = None, min_angle = None, holes = false, shape = "enclosing", margin = None))]
    // One argument per Python keyword (PyO3 maps them one to one).
    #[allow(clippy::type_complexity, clippy::too_many_arguments)]
    fn domain<'py>(
        &self,
        py: Python<'py>,
        handles: PyReadonlyArray2<'py, f64>,
        max_area_fraction: Option<f64>,
        max_vertices: Option<usize>,
        min_angle: Option<f64>,
        holes: bool,
        shape: &str,
        margin: Option<f64>,
    ) -> PyResult<(
        Bound<'py, PyArray2<f64>>,
        Bound<'py, PyArray2<i64>>,
        Bound<'py, PyArray1<i64>>,
    )> {
        let handles = crate::arrays::points(&handles, "handles", None)?;
        let shape = DomainShape::from_name(shape).ok_or_else(|| {
            PyValueError::new_err(format!(
                "shape={shape:?}: expected \"enclosing\" or \"art\""
            ))
        })?;
        let mut options = DomainOptions::default().with_holes(holes).with_shape(shape);
        if let Some(m) = margin {
            options = options.with_margin(m);
        }
        if let Some(f) = max_area_fraction {
            options = options.with_max_area_fraction(f);
        }
        if let Some(n) = max_vertices {
            options = options.with_max_vertices(n);
        }
        if let Some(a) = min_angle {
            options = options.with_min_angle(a);
        }
        let drawing = &self.drawing;
        let domain = py
            .detach(|| Domain::build(drawing, &handles, &[], &options))
            .map_err(|e| library_error(format!("{}: domain: {e}", self.name)))?;
        let mesh = &domain.mesh;
        let v = points_array(py, &mesh.vertices);
        let f: Vec<i64> = mesh
            .triangles
            .iter()
            .flat_map(|t| t.map(|i| i as i64))
            .collect();
        let f = PyArray2::from_owned_array(
            py,
            numpy::ndarray::Array2::from_shape_vec((mesh.triangles.len(), 3), f)
                .map_err(|e| PyValueError::new_err(e.to_string()))?,
        );
        let b: Vec<i64> = domain.handle_vertices.iter().map(|&i| i as i64).collect();
        Ok((v, f, PyArray1::from_vec(py, b)))
    }

    fn __repr__(&self) -> String {
        format!(
            "<splineskin.Drawing {:?}: {} curves in {} paths>",
            self.name,
            self.drawing.n_curves(),
            self.drawing.paths.len()
        )
    }
}

/// The viewBox rule a `viewbox=` argument names: `"keep"` or `"fit"`.
pub(crate) fn view_box_rule(viewbox: &str) -> PyResult<ViewBoxRule> {
    match viewbox {
        "keep" => Ok(ViewBoxRule::Keep),
        "fit" => Ok(ViewBoxRule::Fit),
        other => Err(PyValueError::new_err(format!(
            "viewbox={other:?}: expected \"keep\" or \"fit\""
        ))),
    }
}
