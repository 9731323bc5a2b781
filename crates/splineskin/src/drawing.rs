//! Drawings and SVG: the model of `splineskin-core` ([`Drawing`], [`Path`], [`JointKind`],
//! [`SvgSource`]) and the document code of `splineskin-svg` ([`svg_in`], [`svg_out`],
//! [`follow`], [`carry`], [`svg_animate`], [`lottie`], [`smil`], [`text_outlines`], [`authors_svg`]), at one path.
//!
//! ```
//! use splineskin::drawing::{read_svg, ImportOptions};
//! let svg = r#"<svg xmlns="http://www.w3.org/2000/svg"><path d="M0 0 C1 1 2 1 3 0"/></svg>"#;
//! let drawing = read_svg(svg, &ImportOptions::default()).unwrap();
//! assert_eq!(drawing.n_curves(), 1);
//! ```

pub use splineskin_core::drawing::*;
pub use splineskin_svg::svg_in::{
    import_warnings, read_svg, read_svg_file, read_svg_named, ImportOptions, SvgError, TextMode,
};
pub use splineskin_svg::{
    animated_image, authors_svg, carry, follow, lottie, smil, svg_animate, svg_in, svg_out,
    text_outlines,
};
