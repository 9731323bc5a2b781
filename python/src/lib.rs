//! `splineskin._splineskin`: the library behind the `splineskin` Python package
//! (`python/splineskin/`, which documents the API and adds conveniences in Python).
//!
//! Arrays cross as numpy arrays of `float64` in C order, `n × 2` for points; nothing is copied
//! where the library can read or write the caller's memory (`SplineRig.update(…, out=…)`
//! writes into the caller's array). Errors of the library come back as
//! [`SplineSkinError`] with the library's message (naming the file and the element); arrays of
//! the wrong shape, dtype or order as `ValueError`; a missing file as `FileNotFoundError`.
//! Long calls (reading a drawing, weights, precomputation, the per-frame product) release the
//! GIL, so other Python threads run meanwhile.
//!
//! | Python | Rust |
//! |---|---|
//! | `Drawing` | [`drawing::PyDrawing`]: a drawing read from SVG, its control points, `to_svg` |
//! | `Scene` | [`scene::PyScene`]: a scene file (ours or the paper authors'), its handles and poses |
//! | `SplineRig` | [`rig::PySplineRig`]: the spline fit of a skinning deformation, `update` |
//! | `harmonic`, `bbw`, `mvc` | [`weights`]: weights on a triangle mesh in libigl's conventions; mean value coordinates of a polygon |
//! | `Cage`, `SubdivRig` | [`subdiv`]: Catmull–Clark cages, their limit surface, the subdivision rig |
//! | `Operator`, `OperatorRig` | [`operator`]: deformation operators, trained or read, and their join with a drawing |

use pyo3::prelude::*;

pub mod arrays;
pub mod drawing;
pub mod operator;
pub mod rig;
pub mod scene;
pub mod subdiv;
pub mod weights;

pyo3::create_exception!(
    splineskin._splineskin,
    SplineSkinError,
    pyo3::exceptions::PyException,
    "An error of the splineskin library: bad input (a malformed drawing or scene, a degenerate \
     curve, weights that cannot be computed), with the library's message naming the file and \
     the element."
);

/// The library's error `e` as a [`SplineSkinError`] carrying its message (with its causes).
pub fn library_error(e: impl std::fmt::Display) -> PyErr {
    SplineSkinError::new_err(format!("{e:#}"))
}

/// The extension module.
#[pymodule]
fn _splineskin(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("SplineSkinError", m.py().get_type::<SplineSkinError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<drawing::PyDrawing>()?;
    m.add_class::<scene::PyScene>()?;
    m.add_class::<rig::PySplineRig>()?;
    m.add_class::<operator::PyOperator>()?;
    m.add_class::<subdiv::PyCage>()?;
    m.add_class::<subdiv::PySubdivRig>()?;
    m.add_class::<operator::PyOperatorRig>()?;
    m.add_function(wrap_pyfunction!(weights::harmonic, m)?)?;
    m.add_function(wrap_pyfunction!(weights::bbw, m)?)?;
    m.add_function(wrap_pyfunction!(weights::mvc, m)?)?;
    Ok(())
}
