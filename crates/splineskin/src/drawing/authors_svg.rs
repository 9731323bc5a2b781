//! The paper authors' SVG reading, for compatibility mode (stub: being written).
