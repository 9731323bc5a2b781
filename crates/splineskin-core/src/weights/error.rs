//! [`WeightsError`]: why a weight family could not be computed.

use crate::domain::DomainError;
use crate::mesh::MeshError;

/// Why weights could not be computed: on a mesh ([`mod@super::harmonic`], [`mod@super::bbw`],
/// [`mod@super::cage`]) or of a cage ([`super::MeanValue`]).
#[derive(Debug, thiserror::Error, PartialEq)]
#[non_exhaustive]
pub enum WeightsError {
    /// The mesh is not valid ([`crate::mesh::TriMesh::check`]).
    #[error("invalid mesh: {0}")]
    Mesh(#[from] MeshError),
    /// No handle (no Dirichlet vertex) was given.
    #[error("no handles: at least one vertex with prescribed weights is needed")]
    NoHandles,
    /// A handle (a Dirichlet vertex) is not a vertex of the mesh.
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
    /// Two handles (Dirichlet entries) name the same vertex.
    #[error("handles {first} and {second}: both at vertex {vertex} (expected distinct vertices)")]
    DuplicateHandle {
        /// The shared vertex.
        vertex: usize,
        /// The first handle at it.
        first: usize,
        /// The second handle at it.
        second: usize,
    },
    /// Dirichlet values do not have the shape `n_fixed × n_columns`.
    #[error("Dirichlet data: {len} values for {n_fixed} vertices × {n_columns} columns")]
    DirichletShape {
        /// Number of values given.
        len: usize,
        /// Number of fixed vertices.
        n_fixed: usize,
        /// Number of columns (weight functions).
        n_columns: usize,
    },
    /// A column was asked for that the data does not have
    /// ([`super::DirichletData::select_columns`]).
    #[error("column {column} does not exist (the data has {n_columns} columns)")]
    ColumnOutOfRange {
        /// The column asked for.
        column: usize,
        /// Number of columns of the data.
        n_columns: usize,
    },
    /// Weights do not have the shape `n_vertices × n_handles`.
    #[error("{len} weights for {n_vertices} vertices × {n_handles} handles")]
    WeightsShape {
        /// Number of values given.
        len: usize,
        /// Number of vertices.
        n_vertices: usize,
        /// Number of handles.
        n_handles: usize,
    },
    /// A Dirichlet value is NaN or infinite.
    #[error("Dirichlet data: value {value} at fixed vertex {row} (vertex {vertex}), column {column} is not finite")]
    NonFiniteValue {
        /// Row of the value (position in the fixed-vertex list).
        row: usize,
        /// The vertex.
        vertex: usize,
        /// Column.
        column: usize,
        /// The value.
        value: f64,
    },
    /// A Dirichlet value lies outside the bounds of a bounded solve (BBW: `[0, 1]`), so the
    /// problem has no feasible point.
    #[error("Dirichlet data: value {value} at vertex {vertex}, column {column} lies outside the bounds [{lower}, {upper}]")]
    ValueOutOfBounds {
        /// The vertex.
        vertex: usize,
        /// Column.
        column: usize,
        /// The value.
        value: f64,
        /// Lower bound.
        lower: f64,
        /// Upper bound.
        upper: f64,
    },
    /// A vertex belongs to no triangle: no energy involves it, so its weight is undetermined.
    #[error("vertex {vertex} belongs to no triangle (its weight is undetermined; remove it from the mesh)")]
    UnreferencedVertex {
        /// The vertex.
        vertex: usize,
    },
    /// A connected part of the mesh holds no handle: the energy does not determine the weights
    /// there (any constant is a minimiser).
    #[error("vertex {vertex}: its connected part of the mesh holds no handle, so its weights are undetermined")]
    UnconstrainedComponent {
        /// The smallest vertex of that part.
        vertex: usize,
    },
    /// A connected part of the mesh holds fewer than three handles not on one line: an energy
    /// that is zero on every linear function (the linearly precise biharmonic coordinates)
    /// does not determine the weights there (a linear function vanishing at the handles can
    /// be added to any minimiser).
    #[error("vertex {vertex}: its connected part of the mesh holds {n_handles} handle(s), all on one line (expected at least three handles not on a line)")]
    CollinearHandles {
        /// The smallest vertex of that part.
        vertex: usize,
        /// Number of handles in that part.
        n_handles: usize,
    },
    /// The requested polyharmonic order is not supported.
    #[error("harmonic order {order} is not supported (expected 1 ..= {max})")]
    UnsupportedOrder {
        /// The order asked for.
        order: usize,
        /// The largest supported order.
        max: usize,
    },
    /// Options out of their domain (a tolerance that is not positive, bounds in the wrong
    /// order, no iterations allowed).
    #[error("invalid option {name} = {value}: {expected}")]
    InvalidOption {
        /// The option.
        name: &'static str,
        /// Its value, printed.
        value: String,
        /// What was expected.
        expected: &'static str,
    },
    /// A row of weights sums to zero (or a negative or non-finite number), so it cannot be
    /// normalised.
    #[error("vertex {vertex}: its weights sum to {sum}, which cannot be normalised to 1")]
    ZeroRowSum {
        /// The vertex.
        vertex: usize,
        /// The sum.
        sum: f64,
    },
    /// The bounded solve was stopped by its [`crate::stop::StopSignal`]
    /// ([`super::bbw::BbwOptions::stop`]) before it settled.
    #[error(
        "stopped before the bounded biharmonic weights settled (their result was no longer wanted)"
    )]
    Stopped,
    /// The bounded solve did not find its active set within the iteration limit.
    #[error("bounded biharmonic weight of column {column}: the active set did not settle within {iterations} iterations ({n_changes} constraints still changing)")]
    NotConverged {
        /// The column (handle).
        column: usize,
        /// Iterations done.
        iterations: usize,
        /// Number of bound constraints that changed in the last iteration.
        n_changes: usize,
    },
    /// The sparse factorisation failed. The energies are positive definite once every part of
    /// the mesh holds a handle, so this means an extremely ill-conditioned mesh (near-degenerate
    /// triangles) — or a bug.
    #[error("sparse Cholesky factorisation failed ({detail}); the mesh may have near-degenerate triangles")]
    Factorization {
        /// What faer reported.
        detail: String,
    },
    /// A cage is not a simple counter-clockwise polygon of at least 3 finite vertices without
    /// zero-length edges: the same [`DomainError`] (one of its `Cage*` variants) that
    /// [`crate::domain::Domain::build`] gives for it.
    #[error("invalid cage: {0}")]
    Cage(DomainError),
    /// A cage weight family was asked for on a domain built without a cage.
    #[error("the domain has no cage (build it with DomainOptions::with_cage)")]
    NoCage,
    /// The outer boundary of a caged domain does not run along its cage: a corner missing or
    /// out of order, or a boundary vertex off the cage edge between its corners. A domain
    /// from [`crate::domain::Domain::build`] never does this (a bug), a modified one may.
    #[error("domain vertex {vertex}: {reason}; the domain's outer boundary does not follow its cage (a bug, or a modified Domain)")]
    CageBoundary {
        /// The mesh vertex.
        vertex: usize,
        /// What is wrong there.
        reason: &'static str,
    },
}
