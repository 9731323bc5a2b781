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

/// Outline and ticks of a colour bar: dark grey, 1 pixel (not scaled).
pub const COLOUR_BAR_LINE: Line = Line {
    rgba: [60, 60, 60, 255],
    width: 1.0,
};

/// A paint of 8-bit RGBA, anti-aliased.
pub fn paint(rgba: [u8; 4]) -> Paint<'static> {
    let mut paint = Paint::default();
    paint.set_color_rgba8(rgba[0], rgba[1], rgba[2], rgba[3]);
    paint.anti_alias = true;
    paint
}

/// Strokes `path` (pixel coordinates, no transform) with `stroke` in the colour `rgba`.
fn stroke_in(pixmap: &mut Pixmap, path: &tiny_skia::Path, rgba: [u8; 4], stroke: &Stroke) {
    pixmap.stroke_path(path, &paint(rgba), stroke, Transform::identity(), None);
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
    stroke_in(pixmap, path, line.rgba, &stroke);
}

/// Strokes `path` dashed: `dash` is (on, off) in line widths, butt caps.
pub fn dashed(pixmap: &mut Pixmap, path: &tiny_skia::Path, line: Line, scale: f64, dash: [f64; 2]) {
    let width = line.width * scale;
    let stroke = Stroke {
        width: width as f32,
        dash: tiny_skia::StrokeDash::new(dash.map(|d| (d * width) as f32).to_vec(), 0.0),
        ..Stroke::default()
    };
    stroke_in(pixmap, path, line.rgba, &stroke);
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

/// Fills the pixel columns `x0 .. x1` between rows `y0 .. y1` (clipped to the pixmap), each
/// column in the opaque colour `colour(x + ½)`: a colour bar's ramp.
pub fn fill_columns(
    pixmap: &mut Pixmap,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
    colour: impl Fn(f64) -> [u8; 3],
) {
    let (w, h) = (pixmap.width(), pixmap.height());
    let clamp = |v: f64, max: u32| (v.max(0.0) as u32).min(max);
    let (x0, x1, y0, y1) = (clamp(x0, w), clamp(x1, w), clamp(y0, h), clamp(y1, h));
    let width = w as usize;
    let data = pixmap.data_mut();
    for x in x0..x1 {
        let c = colour(f64::from(x) + 0.5);
        for y in y0..y1 {
            let k = 4 * (y as usize * width + x as usize);
            data[k..k + 4].copy_from_slice(&[c[0], c[1], c[2], 255]);
        }
    }
}

/// The 1-pixel outline just outside the pixel box `x0 .. x1 × y0 .. y1` in `line`.
pub fn outline(pixmap: &mut Pixmap, (x0, x1): (f64, f64), (y0, y1): (f64, f64), line: Line) {
    if let Some(rect) = tiny_skia::Rect::from_ltrb(
        x0 as f32 - 0.5,
        y0 as f32 - 0.5,
        x1 as f32 + 0.5,
        y1 as f32 + 0.5,
    ) {
        stroke(pixmap, &tiny_skia::PathBuilder::from_rect(rect), line, 1.0);
    }
}

/// A vertical tick of `length` pixels down from `(x, y)`, butt-capped, in `line` (its
/// nominal width, unscaled): put `x` at a pixel column's middle for a crisp 1-pixel line.
pub fn tick(pixmap: &mut Pixmap, (x, y): (f64, f64), length: f64, line: Line) {
    let mut b = tiny_skia::PathBuilder::new();
    b.move_to(x as f32, y as f32);
    b.line_to(x as f32, (y + length) as f32);
    if let Some(path) = b.finish() {
        let stroke = Stroke {
            width: line.width as f32,
            ..Stroke::default()
        };
        stroke_in(pixmap, &path, line.rgba, &stroke);
    }
}
