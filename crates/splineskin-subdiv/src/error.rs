//! Errors of refinement and limit evaluation.

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
