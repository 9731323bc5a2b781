//! PNG rendering of SVG text with resvg and tiny-skia: how the CLI makes pictures and how tests
//! look at results.
//!
//! The document is scaled uniformly so that the longer side of its viewport is `max_size`
//! pixels, drawn over a white background, and encoded as 8-bit RGBA PNG. Text is drawn in
//! DejaVu Sans whatever family it names ([`crate::fonts`]: the font ships in the binary, no
//! system font is looked up, so a picture is the same on every machine), and images are drawn
//! only when embedded as data URLs: nothing is read from the file system.

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
/// use splineskin_svg::render::render_png;
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
    render_pixmap(svg_text, max_size)?
        .encode_png()
        .map_err(|e| RenderError::Encode {
            message: e.to_string(),
        })
}

/// An image as 8-bit RGBA rows, top to bottom (premultiplication undone; opaque here, since
/// the background is white).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RgbaImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `4 · width · height` bytes: red, green, blue, alpha per pixel.
    pub data: Vec<u8>,
}

/// [`render_png`] without the encoding: the pixels.
///
/// ```
/// use splineskin_svg::render::render_rgba;
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 20 10">
///   <rect width="10" height="10" fill="red"/></svg>"#;
/// let image = render_rgba(svg, 20).unwrap();
/// assert_eq!((image.width, image.height, image.data.len()), (20, 10, 800));
/// assert_eq!(image.data[..4], [255, 0, 0, 255]);
/// assert_eq!(image.data[4 * 15..4 * 16], [255, 255, 255, 255]);
/// ```
pub fn render_rgba(svg_text: &str, max_size: u32) -> Result<RgbaImage, RenderError> {
    let pixmap = render_pixmap(svg_text, max_size)?;
    let data = pixmap
        .pixels()
        .iter()
        .flat_map(|p| {
            let c = p.demultiply();
            [c.red(), c.green(), c.blue(), c.alpha()]
        })
        .collect();
    Ok(RgbaImage {
        width: pixmap.width(),
        height: pixmap.height(),
        data,
    })
}

fn render_pixmap(svg_text: &str, max_size: u32) -> Result<tiny_skia::Pixmap, RenderError> {
    if max_size == 0 || max_size > MAX_RENDER_SIZE {
        return Err(RenderError::InvalidSize {
            size: max_size,
            max: MAX_RENDER_SIZE,
        });
    }
    let options = crate::fonts::usvg_options(true);
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
    Ok(pixmap)
}

/// The font families that text of the SVG document `svg_text` asks for but is drawn without
/// (empty when it does not parse or every text gets what it asks for): what a caller says next
/// to a picture from [`render_png`], which draws all text in DejaVu Sans ([`crate::fonts`]).
///
/// Each text span's `font-family` list is read in order: `DejaVu Sans` or `sans-serif` met
/// first means the text gets what it asks for; otherwise the list's first family is reported
/// (a named family not shipped, or a generic one other than `sans-serif`, which is drawn in
/// DejaVu Sans too). Text without `font-family` gets DejaVu Sans and is not reported. Each
/// family is listed once, in document order.
///
/// ```
/// use splineskin_svg::render::substituted_families;
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg"><text x="1" y="9">plain</text>
///   <text font-family="Arial, sans-serif">fallback given</text>
///   <text font-family="Helvetica, Arial">a</text><text font-family="monospace">b</text>
///   <text font-family="Helvetica">c</text></svg>"#;
/// assert_eq!(substituted_families(svg), ["Helvetica", "monospace"]);
/// ```
pub fn substituted_families(svg_text: &str) -> Vec<String> {
    use usvg::FontFamily;
    fn visit(group: &usvg::Group, out: &mut Vec<String>) {
        for node in group.children() {
            match node {
                usvg::Node::Group(g) => visit(g, out),
                usvg::Node::Text(text) => {
                    let spans = text.chunks().iter().flat_map(|c| c.spans());
                    for families in spans.map(|s| s.font().families()) {
                        let satisfied = families.iter().find_map(|f| match f {
                            FontFamily::SansSerif => Some(true),
                            FontFamily::Named(n) if n == crate::fonts::FAMILY => Some(true),
                            FontFamily::Named(_) => None,
                            _ => Some(false),
                        });
                        if satisfied != Some(true) {
                            if let Some(first) = families.first() {
                                let name = match first {
                                    FontFamily::Named(n) => n.clone(),
                                    generic => generic.to_string(),
                                };
                                if !out.contains(&name) {
                                    out.push(name);
                                }
                            }
                        }
                    }
                }
                _ => {}
            }
            node.subroots(|g| visit(g, out));
        }
    }
    let Ok(tree) = usvg::Tree::from_str(svg_text, &crate::fonts::usvg_options(false)) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    visit(tree.root(), &mut out);
    out
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
