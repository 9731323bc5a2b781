//! [`SurfaceWeightsError`]: why handle weights on a subdivision surface could not be built.

use super::super::error::SubdivError;

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
