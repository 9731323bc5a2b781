//! PNG rendering of SVG text with resvg and tiny-skia: how the CLI makes pictures and how tests
//! look at results.
//!
//! The document is scaled uniformly so that the longer side of its viewport is `max_size`
//! pixels, drawn over a white background, and encoded as 8-bit RGBA PNG. Text is not rendered
//! (usvg's `text` feature is off), and images are drawn only when embedded as data URLs:
//! nothing is read from the file system.

use resvg::tiny_skia;

/// Largest accepted `max_size`, in pixels: 16384 (a 16384² RGBA pixmap is 1 GiB).
pub const MAX_RENDER_SIZE: u32 = 16384;

/// Errors of [`render_png`].
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RenderError {
    /// `max_size` is 0 or above [`MAX_RENDER_SIZE`].
    #[error("cannot render at {size} px: expected a size in 1..={max} pixels")]
    InvalidSize {
        /// The size asked for.
        size: u32,
        /// [`MAX_RENDER_SIZE`].
        max: u32,
    },
    /// usvg cannot read the SVG text.
    #[error("cannot render the SVG: {message}")]
    Parse {
        /// usvg's description.
        message: String,
    },
    /// The pixmap cannot be allocated.
    #[error("cannot render: cannot allocate a {width}×{height} pixmap")]
    Pixmap {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
    },
    /// PNG encoding failed.
    #[error("cannot encode the PNG: {message}")]
    Encode {
        /// The encoder's description.
        message: String,
    },
}

/// Renders `svg_text` to PNG bytes, scaled so that the longer side of the document's viewport
/// is `max_size` pixels (the other side is rounded, at least 1 px), on a white background.
///
/// Errors: [`RenderError::InvalidSize`] for `max_size` outside `1..=`[`MAX_RENDER_SIZE`],
/// [`RenderError::Parse`] when usvg cannot read the text.
///
/// ```
/// use splineskin::render::render_png;
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 20 10">
///   <rect width="10" height="10"/></svg>"#;
/// let png = render_png(svg, 64).unwrap();
/// let pixmap = resvg::tiny_skia::Pixmap::decode_png(&png).unwrap();
/// assert_eq!((pixmap.width(), pixmap.height()), (64, 32));
/// let black = pixmap.pixel(10, 10).unwrap();
/// let white = pixmap.pixel(50, 10).unwrap();
/// assert_eq!((black.red(), white.red()), (0, 255));
/// ```
pub fn render_png(svg_text: &str, max_size: u32) -> Result<Vec<u8>, RenderError> {
    if max_size == 0 || max_size > MAX_RENDER_SIZE {
        return Err(RenderError::InvalidSize {
            size: max_size,
            max: MAX_RENDER_SIZE,
        });
    }
    let options = usvg::Options {
        resources_dir: None,
        image_href_resolver: usvg::ImageHrefResolver {
            resolve_data: usvg::ImageHrefResolver::default_data_resolver(),
            resolve_string: Box::new(|_, _| None),
        },
        ..usvg::Options::default()
    };
    let tree = usvg::Tree::from_str(svg_text, &options).map_err(|e| RenderError::Parse {
        message: e.to_string(),
    })?;
    let size = tree.size();
    let (w, h) = (f64::from(size.width()), f64::from(size.height()));
    let scale = f64::from(max_size) / w.max(h);
    let pixels = |side: f64| ((side * scale).round() as u32).clamp(1, max_size);
    let (width, height) = (pixels(w), pixels(h));
    let mut pixmap =
        tiny_skia::Pixmap::new(width, height).ok_or(RenderError::Pixmap { width, height })?;
    pixmap.fill(tiny_skia::Color::WHITE);
    let transform = tiny_skia::Transform::from_scale(scale as f32, scale as f32);
    resvg::render(&tree, transform, &mut pixmap.as_mut());
    pixmap.encode_png().map_err(|e| RenderError::Encode {
        message: e.to_string(),
    })
}

/// Number of `<text>` elements in the SVG document `svg_text` (0 when it does not parse):
/// what [`render_png`] leaves out, so that callers can say so instead of showing a picture
/// with its labels silently missing.
///
/// ```
/// use splineskin::render::text_elements;
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg"><text x="1" y="2">hi</text>
///   <g><text>there</text></g><path d="M0 0 L1 1"/></svg>"#;
/// assert_eq!(text_elements(svg), 2);
/// ```
pub fn text_elements(svg_text: &str) -> usize {
    const SVG_NS: &str = "http://www.w3.org/2000/svg";
    roxmltree::Document::parse_with_options(
        svg_text,
        roxmltree::ParsingOptions {
            allow_dtd: true,
            ..roxmltree::ParsingOptions::default()
        },
    )
    .map(|doc| {
        doc.descendants()
            .filter(|n| n.tag_name().name() == "text" && n.tag_name().namespace() == Some(SVG_NS))
            .count()
    })
    .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SQUARE: &str = r#"<svg xmlns="http://www.w3.org/2000/svg" width="40" height="80">
        <rect x="0" y="0" width="20" height="20" fill="black"/></svg>"#;

    #[test]
    fn render_longer_side_is_max_size() {
        let png = render_png(SQUARE, 100).unwrap();
        let pixmap = tiny_skia::Pixmap::decode_png(&png).unwrap();
        assert_eq!((pixmap.width(), pixmap.height()), (50, 100));
    }

    #[test]
    fn render_black_shape_on_white() {
        let png = render_png(SQUARE, 80).unwrap();
        let pixmap = tiny_skia::Pixmap::decode_png(&png).unwrap();
        let inside = pixmap.pixel(5, 5).unwrap();
        assert_eq!((inside.red(), inside.green(), inside.blue()), (0, 0, 0));
        let outside = pixmap.pixel(30, 60).unwrap();
        assert_eq!(
            (
                outside.red(),
                outside.green(),
                outside.blue(),
                outside.alpha()
            ),
            (255, 255, 255, 255)
        );
    }

    #[test]
    fn render_rejects_bad_size_and_bad_text() {
        assert!(matches!(
            render_png(SQUARE, 0),
            Err(RenderError::InvalidSize { size: 0, .. })
        ));
        assert!(matches!(
            render_png(SQUARE, MAX_RENDER_SIZE + 1),
            Err(RenderError::InvalidSize { .. })
        ));
        assert!(matches!(
            render_png("<svg", 10),
            Err(RenderError::Parse { .. })
        ));
    }
}
