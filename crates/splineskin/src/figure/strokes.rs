//! Line styles and the tiny-skia calls that draw them: strokes and dashes in pixel coordinates,
//! widths given at the nominal panel size and scaled by [`crate::figure::PanelGrid::line_scale`].

use resvg::tiny_skia::{self, LineCap, Paint, Pixmap, Stroke, Transform};

/// A line style: 8-bit sRGB colour with alpha, and width in pixels at the nominal size
/// ([`crate::figure::grid::REFERENCE_PANEL_WIDTH`]), multiplied by a scale when drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Line {
    /// Colour and opacity.
    pub rgba: [u8; 4],
    /// Nominal width in pixels.
    pub width: f64,
}

/// A paint of 8-bit RGBA, anti-aliased.
pub fn paint(rgba: [u8; 4]) -> Paint<'static> {
    let mut paint = Paint::default();
    paint.set_color_rgba8(rgba[0], rgba[1], rgba[2], rgba[3]);
    paint.anti_alias = true;
    paint
}

/// Strokes `path` (pixel coordinates) in `line`, its width times `scale`, with round caps and
/// joins.
pub fn stroke(pixmap: &mut Pixmap, path: &tiny_skia::Path, line: Line, scale: f64) {
    let stroke = Stroke {
        width: (line.width * scale) as f32,
        line_cap: LineCap::Round,
        line_join: tiny_skia::LineJoin::Round,
        ..Stroke::default()
    };
    pixmap.stroke_path(
        path,
        &paint(line.rgba),
        &stroke,
        Transform::identity(),
        None,
    );
}

/// Strokes `path` dashed: `dash` is (on, off) in line widths, butt caps.
pub fn dashed(pixmap: &mut Pixmap, path: &tiny_skia::Path, line: Line, scale: f64, dash: [f64; 2]) {
    let width = line.width * scale;
    let stroke = Stroke {
        width: width as f32,
        dash: tiny_skia::StrokeDash::new(dash.map(|d| (d * width) as f32).to_vec(), 0.0),
        ..Stroke::default()
    };
    pixmap.stroke_path(
        path,
        &paint(line.rgba),
        &stroke,
        Transform::identity(),
        None,
    );
}

/// A `width`-pixel frame just outside the `w × h` rectangle with top-left corner `(x, y)`.
pub fn frame(pixmap: &mut Pixmap, (x, y): (u32, u32), (w, h): (u32, u32), line: Line) {
    let rect = tiny_skia::Rect::from_xywh(
        x as f32 - 0.5,
        y as f32 - 0.5,
        w as f32 + 1.0,
        h as f32 + 1.0,
    );
    if let Some(rect) = rect {
        stroke(pixmap, &tiny_skia::PathBuilder::from_rect(rect), line, 1.0);
    }
}
