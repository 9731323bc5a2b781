//! Every picture of the library, on shared drawing primitives.
//!
//! Primitives: panels showing one rectangle of drawing space side by side on a raster image
//! ([`PanelGrid`]), their colour maps ([`colour_map`]), line styles ([`strokes`]), a small
//! pixel font for labels ([`glyphs`]) and a z-buffered triangle rasteriser for surfaces
//! ([`surface_raster`]).
//!
//! Pictures: weight maps ([`weight_map`], one panel per handle), method comparisons
//! ([`comparison`] of [`crate::compare`], one panel per method), the subdivision comparison
//! ([`subdiv_comparison`], Liu et al. 2014 Fig. 8) and the deformation-operator study plot
//! ([`study_plot`], Poranne & Lipman 2016 Fig. 8).

pub mod colour_map;
pub mod comparison;
pub mod glyphs;
pub mod grid;
pub mod pixmap;
pub mod strokes;
pub mod study_plot;
pub mod subdiv_comparison;
pub mod surface_raster;
pub mod weight_map;

pub use grid::{GridError, PanelGrid};
pub use pixmap::PixmapError;
pub use study_plot::study_plot_png;
pub use subdiv_comparison::{render_comparison_png, ComparisonPictureOptions, DEFAULT_PANEL_WIDTH};
pub use surface_raster::{Camera, Raster};
