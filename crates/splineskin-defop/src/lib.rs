//! Deformation operators (Poranne & Lipman 2016, *Simple Approximations of Planar Deformation
//! Operators*; DESIGN.md §4): closed-form approximations of variational point-handle
//! deformations,
//!
//! ```text
//! D(x, Q) = Σ_i Σ_j C_ij φ_i(x) ψ_j(Q)        spatial basis Φ, handle basis Ψ, Q = handle configuration
//! ```
//!
//! | part | what | items |
//! |---|---|---|
//! | ground truth | the variational deformations (below) | [`Arap`], [`SymmetricArap`] |
//! | spatial bases `Φ` | hats, Laplacian eigenfunctions, linearly precise biharmonic coordinates | [`SpatialBasis`], [`EigenOperator`] |
//! | handle bases `Ψ` | linear, quadratic, cubic polynomials, thin-plate splines | [`HandleBasis`], [`HandleBasisKind`] |
//! | samples | configurations in discs, circles, Gaussians, Voronoi cells | [`Sampler`], [`SampleRegion`] |
//! | fit | constrained least squares through its Kronecker structure | [`DefOp::fit`], [`DefOpOptions`] |
//! | evaluation | `positions = Dᵀ G ψ(Q)`, allocation-free | [`DefOp`], [`DefOpEvaluator`] |
//! | the map at any point | `D(x, Q) = Σ_v λ_v(x) u_v(Q)`, linear in each triangle | [`MeshMap`] |
//! | training | sampling, ground truth (parallel), bootstrapping, fit | [`train`], [`TrainOptions`] |
//! | error measure | root-mean-square distance over the shape | [`l2_distance`] |
//! | the join with splines | a drawing's control points `G_spline ψ(Q)`, constraints kept | [`DefOpRig`], [`DrawingDefOp`] |
//!
//! **Ground truth**: the variational deformations themselves, on a triangle mesh with point
//! handles at vertices and hard positional constraints.
//!
//! | energy | formula (per triangle, times its rest area `A_t`) | solver | module |
//! |---|---|---|---|
//! | ARAP, Eq. (10) | `(Σ_t − 1)² + (σ_t − 1)² = ‖J_t − R_t‖²_F` | local–global, one Cholesky factor for all iterations and targets | [`arap_energy`](fn@arap_energy), [`Arap`] |
//! | symmetric ARAP, Eq. (11) | `(Σ_t − 1)² + (1/σ_t − 1)²`, `+∞` on a flip | Newton, projected Hessian, flip-free line search | [`sarap_energy`](fn@sarap_energy), [`SymmetricArap`] |
//!
//! `J_t` is the deformation gradient on triangle `t`, `Σ_t ≥ σ_t` its singular values
//! (`σ_t < 0` on a flip), `R_t` its closest rotation. Both solvers follow one recipe:
//!
//! ```text
//! once per mesh and handle set:   Arap::new / SymmetricArap::new     (factor or analyse)
//! per target configuration q:     solver.solve(&q, &mut positions)   (positions: initial guess in, result out)
//! ```
//!
//! ```
//! use kurbo::{Point, Rect};
//! use splineskin_defop::{Arap, ArapOptions, SarapOptions, SymmetricArap, flipped_triangles};
//! use splineskin_core::mesh::TriMesh;
//! let mesh = TriMesh::grid(Rect::new(0., 0., 4., 1.), 16, 4)?;
//! let handles = [34, 50]; // (0, 0.5) and (4, 0.5)
//! let targets = [Point::new(0., 0.5), Point::new(3.2, 1.8)];
//! // ARAP from the rest pose, then SARAP from the ARAP solution when it flips nothing.
//! let mut arap_result = mesh.vertices.clone();
//! Arap::new(&mesh, &handles, ArapOptions::default())?.solve(&targets, &mut arap_result)?;
//! let mut sarap_result = if flipped_triangles(&mesh, &arap_result)?.is_empty() {
//!     arap_result.clone()
//! } else {
//!     mesh.vertices.clone()
//! };
//! let report = SymmetricArap::new(&mesh, &handles, SarapOptions::default())?
//!     .solve(&targets, &mut sarap_result)?;
//! assert!(report.converged() && flipped_triangles(&mesh, &sarap_result)?.is_empty());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Conformance: `tests/defop_ground_truth.rs` checks [`Arap`] against libigl 2.6.3's
//! converged solutions in `../shared/data/reference-igl` and both solvers' invariants.

mod arap;
mod arap_energy;
mod deformation_gradient;
mod distance;
mod drawing_defop;
mod error;
mod file;
mod fit;
mod handle_basis;
mod handles;
mod laplacian_eigen;
mod mesh_map;
mod operator;
mod orientation;
mod pin_holding;
mod sample;
mod sarap;
mod sarap_energy;
mod spatial_basis;
mod spline_join;
mod study;
mod train;

pub use arap::{
    Arap, ArapOptions, ArapReport, DEFAULT_ARAP_MAX_ITERATIONS, DEFAULT_ARAP_STEP_TOLERANCE,
    TRAINING_ANDERSON_DEPTH,
};
pub use arap_energy::arap_energy;
pub use distance::l2_distance;
pub use drawing_defop::{
    training_domain_options, DrawingDefOp, TRAINING_MAX_AREA_FRACTION,
    TRAINING_SAMPLES_PER_DIAGONAL,
};
pub use error::DefOpError;
pub use file::{
    OperatorFile, OperatorFileError, TrainingMetadata, OPERATOR_FORMAT_VERSION, OPERATOR_MAGIC,
};
pub use fit::{DefOpOptions, DEFAULT_RANK_TOLERANCE};
pub use handle_basis::{HandleBasis, HandleBasisKind};
pub use laplacian_eigen::{EigenOperator, SHIFT_FRACTION};
pub use mesh_map::{FunctionMaps, MeshMap};
pub use operator::{DefOp, DefOpEvaluator};
pub use orientation::flipped_triangles;
pub use pin_holding::PIN_SNAP_FRACTION;
pub use sample::{SampleRegion, Sampler};
pub use sarap::{
    SarapOptions, SarapReport, SarapStop, SymmetricArap, DEFAULT_SARAP_MAX_ITERATIONS,
    DEFAULT_SARAP_STEP_TOLERANCE,
};
pub use sarap_energy::sarap_energy;
pub use spatial_basis::{SpatialBasis, SpatialBasisKind};
pub use spline_join::{DefOpRig, DefOpRigEvaluator, SplineJoin, OUTSIDE_TOLERANCE_FRACTION};
pub use study::{
    geometric_sample_counts, study, Study, StudyOptions, StudyProgress, StudyRow, DEFAULT_HELD_OUT,
    DEFAULT_HELD_OUT_SEED, STUDY_BASES,
};
pub use train::{
    extend, ground_truths_from_rest, train, trained_distance, Energy, ExtendReport, Progress,
    StageReport, StopSignal, TrainOptions, Training, WarmStart, DEFAULT_COVER_SHARE,
    DEFAULT_DISC_FRACTION, DEFAULT_GROWTH, DEFAULT_TRAINING_SAMPLES,
};
