//! # splineskin-svg
//!
//! SVG in and out for splineskin drawings: [`svg_in`] reads a document (through usvg) into a
//! [`Drawing`] that keeps the record of its source ([`SvgSource`]); [`svg_out`] writes deformed
//! geometry back into the same text, so that every style, id and element the deformation does
//! not touch survives; [`follow`] carries text, images, gradients, patterns and markers with the
//! deformation by least-squares affine maps; [`svg_animate`] and [`smil`] write animated SVG;
//! [`text_outlines`] turns text into glyph-outline paths; [`authors_svg`] reads SVG the way the
//! paper authors' editor does (compatibility mode); [`render`] rasterises documents with resvg
//! in the bundled DejaVu Sans ([`fonts`]).
//!
//! Arrows: this crate uses `splineskin-core`'s drawing model and nothing above it.
//!
//! The record answers where each path came from:
//!
//! ```
//! use splineskin_svg::{read_svg, ImportOptions};
//! use splineskin_core::drawing::PathRole;
//! let svg = "<svg xmlns='http://www.w3.org/2000/svg' viewBox='0 0 10 10'>\n\
//!            <path id='leaf' d='M0 0 L5 5'/><rect width='5' height='5'/>\n\
//!            <path d='M0 0 L1 1 M2 2 L3 3'/><g display='none'><path d='M0 9 L9 0'/></g></svg>";
//! let drawing = read_svg(svg, &ImportOptions::default()).unwrap();
//! let source = drawing.source.as_ref().unwrap();
//! assert_eq!(source.element_label(0), "path#leaf (line 2)");
//! // the authors' numbering: subpath 1 of the document's second <path> element
//! assert_eq!(source.path_tag_position(1), None); // the rect
//! assert_eq!(source.path_tag_position(3), Some((1, 1)));
//! assert_eq!(drawing.path_role(0), PathRole::Visible);
//! assert_eq!(drawing.path_role(4), PathRole::Hidden);
//! ```
#![warn(clippy::print_stdout, clippy::print_stderr)]

pub mod animated_image;
pub mod authors_svg;
pub mod carry;
pub mod document;
pub mod follow;
pub mod fonts;
pub mod lottie;
pub mod render;
mod rewrite;
pub mod smil;
pub mod svg_animate;
pub mod svg_in;
pub mod svg_out;
pub mod text_outlines;

pub use splineskin_core::drawing::{Drawing, SvgSource};
pub use svg_in::{read_svg, read_svg_file, read_svg_named, ImportOptions, SvgError, TextMode};
