//! What every picture of the library is made of: panels showing one rectangle of drawing space
//! side by side on a raster image ([`PanelGrid`]), their colour maps ([`colour_map`]), line
//! styles ([`strokes`]) and a small pixel font for labels ([`glyphs`]). Used by
//! [`crate::weight_map`] (one panel per handle) and [`crate::compare`] (one panel per method).

pub mod colour_map;
pub mod glyphs;
pub mod grid;
pub mod strokes;

pub use grid::{GridError, PanelGrid};
