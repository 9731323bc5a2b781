//! Errors of refinement and limit evaluation ([`SubdivError`]), and of handles and their
//! weights on a surface ([`SurfaceWeightsError`], which wraps the first): one module below
//! both the handles and the surface weights that report them.

/// Why a cage cannot be refined, or a limit value cannot be given. Elements are named by their
/// 0-based index in the cage.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SubdivError {
    /// `opensubdiv-rs` refused the topology.
    #[error("cannot build the subdivision topology: {what}")]
    Topology {
        /// Its message.
        what: String,
    },
    /// A refinement level out of the supported range.
    #[error("refinement level {level}; expected 1..={max}")]
    BadLevel {
        /// The level asked for.
        level: usize,
        /// The deepest supported level.
        max: usize,
    },
    /// A surface location names a face or sub-face that does not exist, or `(u, v)` outside
    /// `[0, 1]²`.
    #[error("location face {face}, sub-face {subface}, (u, v) = ({u}, {v}): {what}")]
    BadLocation {
        /// The face.
        face: u32,
        /// The sub-face.
        subface: u32,
        /// The u parameter.
        u: f64,
        /// The v parameter.
        v: f64,
        /// What is wrong and what was expected.
        what: String,
    },
    /// A ptex face index out of range.
    #[error("ptex face {ptex}; expected one < {n_ptex}")]
    BadPtex {
        /// The index given.
        ptex: u32,
        /// Number of ptex faces.
        n_ptex: u32,
    },
    /// A cage vertex index out of range.
    #[error("vertex {vertex}; expected one < {n_vertices}")]
    BadVertex {
        /// The index given.
        vertex: u32,
        /// Number of cage vertices.
        n_vertices: usize,
    },
    /// The location is on a hole face, which has no limit surface.
    #[error("face {face} is a hole: it has no limit surface")]
    InHole {
        /// The face.
        face: u32,
    },
    /// A vertex used by no face has no limit point.
    #[error("vertex {vertex} belongs to no face: it has no limit point")]
    NoSurface {
        /// The vertex.
        vertex: u32,
    },
    /// The location lies in a face of the isolation level where neither a regular patch nor
    /// the corner approximation is available (a corner whose limit mask is undefined there, or
    /// a face the sparse refinement did not refine: a bug if it ever happens at the default
    /// isolation).
    #[error("location face {face}, sub-face {subface}, (u, v) = ({u}, {v}) lies next to an irregular feature that isolation level {isolation} does not resolve")]
    Unresolved {
        /// The face.
        face: u32,
        /// The sub-face.
        subface: u32,
        /// The u parameter.
        u: f64,
        /// The v parameter.
        v: f64,
        /// The isolation level used.
        isolation: usize,
    },
    /// Quadrature options out of range.
    #[error("quadrature: {what}")]
    BadQuadrature {
        /// What is wrong and what was expected.
        what: String,
    },
    /// The inputs of a subdivision rig do not fit together, or its Gram matrix cannot be
    /// factored.
    #[error("subdivision rig: {what}")]
    BadRig {
        /// What is wrong and what was expected.
        what: String,
    },
    /// A per-frame buffer or list of the wrong length.
    #[error("{found} {what}; expected {expected}")]
    SizeMismatch {
        /// What was passed.
        what: &'static str,
        /// The length expected.
        expected: usize,
        /// The length passed.
        found: usize,
    },
    /// The limit mask of a vertex is not reached by the chosen isolation level (a semi-sharp
    /// feature at it that has not decayed).
    #[error("vertex {vertex}: its limit mask is not reached at isolation level {isolation}")]
    UnresolvedVertex {
        /// The vertex.
        vertex: u32,
        /// The isolation level used.
        isolation: usize,
    },
    /// A refinement step produced something inconsistent: a bug in splineskin or in
    /// `opensubdiv-rs`.
    #[error("internal error (a bug, please report it): {what}")]
    Internal {
        /// What went wrong.
        what: String,
    },
}

/// Why handles, or weights of handles on a subdivision surface, are not valid or could not be
/// computed. Files are named as given, lines are 1-based, handles and vertices 0-based.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SurfaceWeightsError {
    /// No handle was given.
    #[error("no handles; expected at least one point or bone")]
    NoHandles,
    /// A handle is not finite, or a bone has coinciding ends.
    #[error("handle {handle}: {what}")]
    BadHandle {
        /// The handle (points first, then bones).
        handle: usize,
        /// What is wrong.
        what: String,
    },
    /// An option is out of range.
    #[error("{what}")]
    BadOption {
        /// What is wrong and what was expected.
        what: String,
    },
    /// A weight file could not be read.
    #[error("{file}: cannot read the weight file: {source}")]
    Read {
        /// The file.
        file: String,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// A line of a weight file is not a row of weights.
    #[error("{file}:{line}: {what}")]
    Table {
        /// The file.
        file: String,
        /// The 1-based line.
        line: usize,
        /// What is wrong and what was expected.
        what: String,
    },
    /// A weight file has the wrong number of rows.
    #[error("{file}: {found} rows of weights; expected one per cage vertex, {expected}")]
    TableRows {
        /// The file.
        file: String,
        /// Rows found.
        found: usize,
        /// Cage vertices.
        expected: usize,
    },
    /// The weights at a point do not sum to a positive number, or are not finite, so they
    /// cannot be normalised.
    #[error("{at}: weights {weights:?} cannot be normalised; expected finite weights with a positive sum")]
    NotNormalisable {
        /// Where (a quadrature node, a mesh vertex, a cage vertex).
        at: String,
        /// The weights.
        weights: Vec<f64>,
    },
    /// A weight asked for at a cage vertex that has no surface around it.
    #[error("cage vertex {vertex} lies in no face with a surface (only in holes, or in none); it has no weights")]
    NoSurface {
        /// The vertex.
        vertex: u32,
    },
    /// The heat-diffusion system could not be solved.
    #[error("bone heat: {what}")]
    Solve {
        /// What failed.
        what: String,
    },
    /// Refinement or limit evaluation failed.
    #[error(transparent)]
    Subdiv(#[from] SubdivError),
}
