//! [`DefOpError`]: why a ground-truth deformation could not be set up or solved.

use splineskin_core::linalg::LinalgError;
use splineskin_core::mesh::MeshError;

/// Why a point-handle deformation ([`super::Arap`], [`super::SymmetricArap`]) could not be set
/// up or solved. Every variant names the handle, vertex or triangle at fault.
#[derive(Debug, thiserror::Error, PartialEq)]
#[non_exhaustive]
pub enum DefOpError {
    /// The mesh is not valid ([`splineskin_core::mesh::TriMesh::check`]).
    #[error("invalid mesh: {0}")]
    Mesh(#[from] MeshError),
    /// No handle was given.
    #[error("no handles: at least one handle vertex is needed")]
    NoHandles,
    /// A handle is not a vertex of the mesh.
    #[error(
        "handle {handle}: vertex index {vertex} out of range (the mesh has {n_vertices} vertices)"
    )]
    HandleOutOfRange {
        /// Position of the handle in the list given.
        handle: usize,
        /// The index given.
        vertex: usize,
        /// Number of vertices of the mesh.
        n_vertices: usize,
    },
    /// Two handles name the same vertex.
    #[error("handles {first} and {second}: both at vertex {vertex} (expected distinct vertices)")]
    DuplicateHandle {
        /// The shared vertex.
        vertex: usize,
        /// The first handle at it.
        first: usize,
        /// The second handle at it.
        second: usize,
    },
    /// A connected part of the mesh holds no handle, so nothing fixes its position and the
    /// energy has no unique minimiser.
    #[error("vertex {vertex}: its connected part of the mesh holds no handle (expected at least one handle per part)")]
    PartWithoutHandle {
        /// The smallest vertex of the part.
        vertex: usize,
    },
    /// The number of targets is not the number of handles.
    #[error("{given} targets for {n_handles} handles (expected one target per handle)")]
    TargetCount {
        /// Number of targets given.
        given: usize,
        /// Number of handles.
        n_handles: usize,
    },
    /// A target is NaN or infinite.
    #[error("handle {handle}: target ({x}, {y}) is not finite")]
    NonFiniteTarget {
        /// The handle.
        handle: usize,
        /// Its x.
        x: f64,
        /// Its y.
        y: f64,
    },
    /// The positions buffer (initial guess in, result out) does not have one point per
    /// vertex.
    #[error("{given} positions for a mesh of {n_vertices} vertices (expected one per vertex)")]
    PositionCount {
        /// Number of positions given.
        given: usize,
        /// Number of vertices of the mesh.
        n_vertices: usize,
    },
    /// The training was stopped by its [`crate::StopSignal`] before it ended.
    #[error("stopped before the training ended")]
    Stopped,
    /// An output or scratch buffer does not have the length the call needs.
    #[error("buffer of length {given} (expected {expected})")]
    BufferLength {
        /// Its length.
        given: usize,
        /// The length needed.
        expected: usize,
    },
    /// An initial position is NaN or infinite.
    #[error("vertex {vertex}: initial position ({x}, {y}) is not finite")]
    NonFinitePosition {
        /// The vertex.
        vertex: usize,
        /// Its x.
        x: f64,
        /// Its y.
        y: f64,
    },
    /// The initial guess of a flip-preventing solve has a triangle that is flipped or
    /// degenerate (signed area ≤ 0), where the energy is infinite.
    #[error("triangle {triangle}: the initial guess gives it signed area {area:e} (expected a flip-free start, every area positive)")]
    FlippedStart {
        /// The triangle.
        triangle: usize,
        /// Its signed area in the initial guess.
        area: f64,
    },
    /// Thin-plate splines need the rest configuration and `2n` more samples (their side
    /// conditions: the `1 + 2n` linear functions of `n` handles); fewer were asked for.
    #[error(
        "{handles} handles need at least {needed} training samples for thin-plate splines (their side conditions take the rest configuration and 2n more); {given} asked"
    )]
    TooFewSamples {
        /// Handles.
        handles: usize,
        /// Samples needed besides the rest configuration (`2n`).
        needed: usize,
        /// Samples asked for.
        given: usize,
    },
    /// An option has a value outside its range.
    #[error("option {name} = {value}: expected {expected}")]
    InvalidOption {
        /// The option's field name.
        name: &'static str,
        /// The value given.
        value: String,
        /// What is allowed.
        expected: &'static str,
    },
    /// A vertex belongs to no triangle: a spatial basis has no value to give it.
    #[error("vertex {vertex} belongs to no triangle (a spatial basis needs every vertex in a triangle; remove it from the mesh)")]
    UnreferencedVertex {
        /// The vertex.
        vertex: usize,
    },
    /// The linearly precise biharmonic coordinates of a spatial basis could not be computed.
    #[error("biharmonic coordinates: {0}")]
    Weights(#[from] splineskin_core::weights::WeightsError),
    /// The Krylov–Schur eigensolver of a Laplacian eigenfunction basis did not converge (or
    /// could not get its workspace).
    #[error("Laplacian eigenfunctions: {detail}")]
    Eigensolver {
        /// What failed.
        detail: String,
    },
    /// A spatial basis was built on a mesh with another number of vertices.
    #[error("the spatial basis has {basis_vertices} vertices, the mesh {n_vertices} (expected the basis of this mesh)")]
    BasisMismatch {
        /// Vertices of the basis.
        basis_vertices: usize,
        /// Vertices of the mesh.
        n_vertices: usize,
    },
    /// No training samples, or not one solution per configuration.
    #[error("{configurations} configurations and {solutions} solutions (expected at least one sample, one solution per configuration)")]
    SampleCount {
        /// Configurations given.
        configurations: usize,
        /// Solutions given.
        solutions: usize,
    },
    /// A training sample is unusable.
    #[error("sample {sample}: {reason}")]
    BadSample {
        /// Index of the sample.
        sample: usize,
        /// What is wrong.
        reason: String,
    },
    /// The samples are too few or too degenerate for the handle basis.
    #[error("degenerate samples: {detail}")]
    DegenerateSamples {
        /// What is degenerate.
        detail: String,
    },
    /// The spatial basis cannot take arbitrary values at the handles (`Φ(P)` has rank below
    /// the number of handles), so handle interpolation (the paper's Proposition 2) is out of
    /// reach: use more functions, or control vertices at the handles.
    #[error("the spatial basis can interpolate {rank} independent values at the {n_handles} handles (expected all: add functions, or put control vertices at the handles)")]
    HandlesNotInterpolable {
        /// Rank of `Φ(P)`.
        rank: usize,
        /// Number of handles.
        n_handles: usize,
    },
    /// The spatial basis does not hold the coordinate functions `x` and `y`, so the rest pose
    /// cannot be reproduced.
    #[error("the spatial basis reproduces x and y only to {residual:e} (expected the linear functions in the basis)")]
    NotLinearlyPrecise {
        /// Largest error of the best approximation of `x` or `y`, drawing units.
        residual: f64,
    },
    /// The drawing could not be fitted (a malformed chain, a non-finite control point, a path
    /// system that failed to solve): the spline fit's own error.
    #[error("spline fit: {0}")]
    Fit(#[from] splineskin_core::spline_fit::FitError),
    /// The drawing's domain could not be triangulated, or the mesh could not locate points.
    #[error("domain: {0}")]
    Domain(#[from] splineskin_core::domain::DomainError),
    /// A point of the drawing (a quadrature node of a curve) lies farther outside the
    /// operator's mesh than the tolerance: the operator says nothing there (nearer points
    /// outside take the weights of the nearest boundary point).
    #[error("path {path}: point ({x}, {y}) lies {distance} outside the mesh (tolerance {tolerance}, drawing units; expected the drawing inside the operator's mesh)")]
    DrawingOutsideMesh {
        /// The path.
        path: usize,
        /// The point's x.
        x: f64,
        /// The point's y.
        y: f64,
        /// Distance of the point to the mesh, drawing units.
        distance: f64,
        /// The largest distance accepted, drawing units.
        tolerance: f64,
    },
    /// The handle vertices of a domain are not the operator's handles.
    #[error("the domain's handle vertices {domain:?} are not the operator's {op:?} (expected the domain the operator was trained on)")]
    HandleMismatch {
        /// The domain's handle vertices.
        domain: Vec<usize>,
        /// The operator's.
        op: Vec<usize>,
    },
    /// The sparse Cholesky factorisation failed. The systems factored are positive definite
    /// by construction (every part of the mesh holds a handle, Hessians are projected and
    /// regularised), so this is a bug or a mesh so degenerate that rounding dominates.
    #[error("sparse Cholesky factorisation failed ({detail}); the matrix should be positive definite by construction: a bug, or a degenerate mesh")]
    Factorization {
        /// Stage and faer's error.
        detail: String,
    },
}

impl From<LinalgError> for DefOpError {
    fn from(e: LinalgError) -> Self {
        DefOpError::Factorization {
            detail: e.to_string(),
        }
    }
}

/// Checks a count option (iterations, samples, …): [`DefOpError::InvalidOption`] naming
/// `name` when `value` is 0, expecting "at least 1".
pub(crate) fn check_count_option(name: &'static str, value: usize) -> Result<(), DefOpError> {
    if value == 0 {
        return Err(DefOpError::InvalidOption {
            name,
            value: "0".into(),
            expected: "at least 1",
        });
    }
    Ok(())
}
