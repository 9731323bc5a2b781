//! Catmull–Clark subdivision surfaces and their closed-form rig (`splineskin-subdiv`), with
//! the comparison picture of [`crate::figure`] at the path it always had.

pub use crate::figure::subdiv_comparison::{
    render_comparison_png, ComparisonPictureOptions, DEFAULT_PANEL_WIDTH,
};
pub use crate::figure::surface_raster::{Camera, Raster};
pub use splineskin_subdiv::*;
