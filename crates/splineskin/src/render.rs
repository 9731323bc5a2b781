//! PNG rendering with resvg (stub: being written).
