//! SVG import (stub: being written).

/// What is kept of the source document to write deformed geometry back into it.
#[derive(Clone, Debug, Default)]
pub struct SvgSource {}
