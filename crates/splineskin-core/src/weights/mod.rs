//! Handle weight functions `w_i : R² → R`.
//!
//! The fit ([`crate::spline_fit`]) only needs to evaluate the weights of all handles at points
//! along the curves, and to know where along a curve a weight function stops being smooth (mesh
//! weights are piecewise linear: the quadrature splits curves at mesh edges). That is the whole
//! [`WeightField`] interface, so new families (harmonic, biharmonic, bounded biharmonic, mean
//! value coordinates) plug in without any change to the fit.
//!
//! | family | module | handles |
//! |---|---|---|
//! | Shepard (inverse distance) | [`shepard`] | points |
//! | Shepard with bones (distance to the segment) | [`segment_shepard`] | points and bones |
//! | harmonic (`k = 1`), biharmonic (`k = 2`) | [`mod@harmonic`] | vertices of a mesh (points, or any Dirichlet data) |
//! | bounded biharmonic (BBW) | [`bbw`] | vertices of a mesh |
//! | linearly precise biharmonic coordinates (Wang et al. 2015) | [`mod@biharmonic_coordinates`] | vertices of a mesh (at least three, not on a line) |
//! | mean value coordinates (closed form, whole plane) | [`mvc`] | vertices of a cage polygon |
//! | harmonic coordinates (`k = 1`, piecewise linear data along the cage) | [`cage`] | vertices of a cage polygon (on a caged [`crate::domain::Domain`]) |
//!
//! The mesh families compute [`VertexWeights`] on a [`crate::mesh::TriMesh`] from
//! [`DirichletData`]; [`crate::domain::MeshWeights`] evaluates them anywhere in the plane.

mod admm_start;
pub mod bbw;
pub mod biharmonic_coordinates;
pub mod cage;
pub mod coarse_to_fine;
mod dirichlet;
mod error;
pub mod harmonic;
mod mesh_field;
pub mod mvc;
mod reduced_cholesky;
pub mod segment_shepard;
pub mod shepard;
mod vertex_weights;

pub use bbw::{bbw_weights, bounded_biharmonic, bounded_biharmonic_from, BbwOptions};
pub use biharmonic_coordinates::biharmonic_coordinates;
pub use cage::{cage_boundary_data, harmonic_coordinates};
pub use dirichlet::DirichletData;
pub use error::WeightsError;
pub use harmonic::{harmonic, harmonic_weights};
pub use mvc::MeanValue;
pub use segment_shepard::SegmentShepard;
pub use shepard::{Shepard, ShepardOptions};
pub use vertex_weights::VertexWeights;

use kurbo::Point;

/// A set of weight functions, one per handle, evaluated together.
///
/// Implementations are immutable once built (all precomputation done in their constructor), so
/// they can be shared between threads and evaluated in parallel.
pub trait WeightField: Send + Sync {
    /// Number of handles `h`.
    fn n_handles(&self) -> usize;

    /// Writes `w_i(p)` for every handle `i` into `out` (length [`WeightField::n_handles`]).
    fn eval(&self, p: Point, out: &mut [f64]);

    /// Appends to `out` the parameters `t ∈ (0, 1)` at which the weights restricted to the cubic
    /// `curve` are not smooth (for example where it crosses mesh edges), in any order.
    /// Quadrature splits the curve there so that every piece integrates a smooth function.
    /// Smooth families (Shepard) append nothing, which is the default; mean value coordinates
    /// report where the curve passes through a cage vertex (they are smooth elsewhere).
    fn kinks(&self, curve: &[Point; 4], out: &mut Vec<f64>) {
        let _ = (curve, out);
    }
}
