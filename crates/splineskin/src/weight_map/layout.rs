//! Where everything goes in a weight map: the frame of drawing space every panel shows, the
//! scale, the grid of panels, the colour bar, and the sizes of lines and labels.

use kurbo::{ParamCurveExtrema, Point, Rect};

use super::{HandleMarker, WeightMapError, WeightMapOptions};
use crate::drawing::Drawing;
use crate::mesh::TriMesh;

/// Margin around the frame's content (curves, handles, mesh), on every side, as a fraction of
/// the content's larger side: 0.05. Leaves room for handle markers at the edge, and bounds a
/// panel's aspect ratio at 1 : 11 for the thinnest drawings.
pub const FRAME_MARGIN: f64 = 0.05;

/// Largest side of a weight map, in pixels: [`crate::render::MAX_RENDER_SIZE`].
pub const MAX_IMAGE_SIDE: u32 = crate::render::MAX_RENDER_SIZE;

/// Largest number of pixels of a weight map: 2²⁶ (about 67 million, e.g. 8192 × 8192). The
/// samples take 8 bytes per panel pixel on top of the image's 4.
pub const MAX_IMAGE_PIXELS: u64 = 1 << 26;

/// Smallest panel width, in pixels: 32 (a panel must hold its label and a handle marker).
pub const MIN_PANEL_WIDTH: u32 = 32;

/// Panel width at which line widths, marker radii, gutters and labels have their nominal
/// sizes: 512 px. They scale with the panel width, within [`LINE_SCALE_RANGE`].
pub const REFERENCE_PANEL_WIDTH: f64 = 512.0;

/// Range of the line scale (panel width / [`REFERENCE_PANEL_WIDTH`]): lines stay at least
/// half and at most four times their nominal width.
pub const LINE_SCALE_RANGE: (f64, f64) = (0.5, 4.0);

/// Rounding slack when making the panel height a whole number of pixels: 1e-6 px.
const PIXEL_SLACK: f64 = 1e-6;

/// Smallest size of a font pixel, in pixels: 2 (digits 6 × 10 px, legible at any panel
/// width).
const MIN_GLYPH_SCALE: u32 = 2;

/// Nominal gutter between panels and around the image, in pixels.
const GUTTER: f64 = 12.0;
/// Nominal height of the colour bar, in pixels.
const BAR_HEIGHT: f64 = 14.0;
/// Fraction of a panel's width taken by the colour bar's `[0, 1]` section; the out-of-range
/// extensions take [`BAR_EXTENSION_FRACTION`] each on either side.
const BAR_MAIN_FRACTION: f64 = 0.6;
/// Fraction of a panel's width taken by each out-of-range extension of the colour bar.
const BAR_EXTENSION_FRACTION: f64 = 0.15;
/// Nominal length of the colour bar's major ticks, in pixels.
pub(crate) const TICK_LENGTH: f64 = 5.0;

/// One panel: the weights of `handle`, with its top-left corner at pixel `(x, y)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Panel {
    /// The handle whose weight the panel shows.
    pub handle: usize,
    /// Left edge, pixels from the image's left.
    pub x: u32,
    /// Top edge, pixels from the image's top.
    pub y: u32,
}

/// The geometry of a weight map image.
///
/// Every panel shows the same rectangle [`WeightMapLayout::frame`] of drawing space (the SVG
/// root's user units, y down as in SVG) at [`WeightMapLayout::scale`] pixels per unit: drawing
/// point `p` is at `(p − frame.origin) · scale` from the panel's corner. Pixel `(i, j)` covers
/// `[i, i + 1) × [j, j + 1)` and is coloured by the weight at its centre.
#[derive(Clone, Debug, PartialEq)]
pub struct WeightMapLayout {
    /// The drawing-space rectangle each panel shows: the bounds of the curves, the handles
    /// and the mesh (when given), with [`FRAME_MARGIN`] on every side, then grown vertically
    /// (centred) to a whole number of pixels.
    pub frame: Rect,
    /// Pixels per drawing unit.
    pub scale: f64,
    /// Width of a panel in pixels ([`WeightMapOptions::panel_width`]).
    pub panel_width: u32,
    /// Height of a panel in pixels: the frame's height times the scale, rounded up, at least 1.
    pub panel_height: u32,
    /// The panels, in handle order (one, with [`WeightMapOptions::handle`]).
    pub panels: Vec<Panel>,
    /// Number of panel columns: the one making the grid of panels closest to square (more
    /// columns on a tie).
    pub columns: usize,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// The colour bar's `[0, 1]` section, in image pixels (`x0` is 0, `x1` is 1).
    pub colour_bar: Rect,
    /// Width of each out-of-range extension of the colour bar, in pixels (drawn only when
    /// values out of `[0, 1]` occur).
    pub bar_extension: f64,
    /// Line widths, marker radii and gutters relative to their nominal sizes (at
    /// [`REFERENCE_PANEL_WIDTH`]).
    pub line_scale: f64,
    /// Gutter between panels and around the image, in pixels.
    pub gutter: u32,
    /// Size of a font pixel of the colour bar's tick labels, in pixels (panel labels are one
    /// step larger).
    pub glyph_scale: u32,
    /// Height of the strip above each panel holding its handle's index, in pixels.
    pub label_height: u32,
}

impl WeightMapLayout {
    /// The layout for the curves of `drawing`, the handles `handles` and, when given, the
    /// `mesh` the weights were solved on (it is always inside the frame, so that drawing its
    /// edges or not gives the same layout).
    ///
    /// Errors: [`WeightMapError::NoHandles`], [`WeightMapError::NonFiniteHandle`],
    /// [`WeightMapError::UnknownHandle`], [`WeightMapError::InvalidPanelWidth`],
    /// [`WeightMapError::NonFiniteGeometry`], [`WeightMapError::TooLarge`].
    pub fn new(
        drawing: &Drawing,
        handles: &[HandleMarker],
        mesh: Option<&TriMesh>,
        options: &WeightMapOptions,
    ) -> Result<WeightMapLayout, WeightMapError> {
        if handles.is_empty() {
            return Err(WeightMapError::NoHandles);
        }
        if let Some(i) = handles.iter().position(|h| !h.is_finite()) {
            return Err(WeightMapError::NonFiniteHandle { handle: i });
        }
        if let Some(i) = options.handle.filter(|&i| i >= handles.len()) {
            return Err(WeightMapError::UnknownHandle {
                handle: i,
                n_handles: handles.len(),
            });
        }
        let pw = options.panel_width;
        if !(MIN_PANEL_WIDTH..=MAX_IMAGE_SIDE).contains(&pw) {
            return Err(WeightMapError::InvalidPanelWidth {
                width: pw,
                min: MIN_PANEL_WIDTH,
                max: MAX_IMAGE_SIDE,
            });
        }

        let content = content_bounds(drawing, handles, mesh);
        let finite = [content.x0, content.y0, content.x1, content.y1]
            .iter()
            .all(|v| v.is_finite());
        if !finite {
            return Err(WeightMapError::NonFiniteGeometry);
        }
        let side = content.width().max(content.height());
        // A lone handle and no curves: a frame of one drawing unit around it.
        let side = if side > 0.0 { side } else { 1.0 };
        let margin = FRAME_MARGIN * side;
        let frame = content.inflate(margin, margin);
        let scale = f64::from(pw) / frame.width();
        let ph_exact = frame.height() * scale;
        if !(scale.is_finite() && ph_exact.is_finite() && scale > 0.0) {
            return Err(WeightMapError::NonFiniteGeometry);
        }
        // Bounded by the aspect ratio (at most 1 : 11) times the panel width. Rounded up (the
        // slack absorbs the rounding of `scale`), so that the frame only ever grows.
        let ph = ((ph_exact - PIXEL_SLACK).ceil() as u32).max(1);
        let centre_y = 0.5 * (frame.y0 + frame.y1);
        let half = 0.5 * f64::from(ph) / scale;
        let frame = Rect::new(frame.x0, centre_y - half, frame.x1, centre_y + half);

        let shown: Vec<usize> = match options.handle {
            Some(i) => vec![i],
            None => (0..handles.len()).collect(),
        };
        let n = shown.len();
        let columns = best_columns(n, f64::from(pw), f64::from(ph));
        let rows = n.div_ceil(columns);

        let line_scale =
            (f64::from(pw) / REFERENCE_PANEL_WIDTH).clamp(LINE_SCALE_RANGE.0, LINE_SCALE_RANGE.1);
        let gutter = ((GUTTER * line_scale).round() as u32).max(4);
        let glyph_scale = ((2.0 * line_scale).round() as u32).max(MIN_GLYPH_SCALE);
        let bar_height = (BAR_HEIGHT * line_scale).round();
        let tick_label_height = f64::from(super::glyphs::GLYPH_HEIGHT * glyph_scale);
        // The panel label: glyphs one step larger, over a gap of one of their pixels.
        let label_height = (super::glyphs::GLYPH_HEIGHT + 1) * (glyph_scale + 1);

        let size = |count: usize, panel: u32| -> u64 {
            u64::from(gutter) + count as u64 * (u64::from(panel) + u64::from(gutter))
        };
        let width = size(columns, pw);
        let grid_height = size(rows, label_height + ph);
        let bar_top = grid_height as f64;
        let height = grid_height as f64
            + bar_height
            + (TICK_LENGTH * line_scale).round()
            + f64::from(glyph_scale) * 2.0
            + tick_label_height
            + f64::from(gutter);
        let height = height as u64;
        if width > u64::from(MAX_IMAGE_SIDE)
            || height > u64::from(MAX_IMAGE_SIDE)
            || width * height > MAX_IMAGE_PIXELS
        {
            return Err(WeightMapError::TooLarge {
                width,
                height,
                max_side: MAX_IMAGE_SIDE,
                max_pixels: MAX_IMAGE_PIXELS,
            });
        }
        let (width, height) = (width as u32, height as u32);

        let panels = shown
            .iter()
            .enumerate()
            .map(|(k, &handle)| Panel {
                handle,
                x: gutter + (k % columns) as u32 * (pw + gutter),
                y: gutter + label_height + (k / columns) as u32 * (label_height + ph + gutter),
            })
            .collect();
        let main = (BAR_MAIN_FRACTION * f64::from(pw)).round();
        let bar_x0 = ((f64::from(width) - main) / 2.0).round();
        let colour_bar = Rect::new(bar_x0, bar_top, bar_x0 + main, bar_top + bar_height);
        Ok(WeightMapLayout {
            frame,
            scale,
            panel_width: pw,
            panel_height: ph,
            panels,
            columns,
            width,
            height,
            colour_bar,
            bar_extension: (BAR_EXTENSION_FRACTION * f64::from(pw)).round(),
            line_scale,
            gutter,
            glyph_scale,
            label_height,
        })
    }

    /// Where drawing point `p` is in a panel's own pixel coordinates (from its top-left corner).
    pub fn panel_pixel(&self, p: Point) -> Point {
        Point::new(
            (p.x - self.frame.x0) * self.scale,
            (p.y - self.frame.y0) * self.scale,
        )
    }

    /// Where drawing point `p` is in the image, in panel `panel` (an index into
    /// [`WeightMapLayout::panels`]): pixel coordinates, `floor` of which is the pixel holding
    /// it. `None` if there is no such panel.
    pub fn to_pixel(&self, panel: usize, p: Point) -> Option<Point> {
        let corner = self.panels.get(panel)?;
        let q = self.panel_pixel(p);
        Some(Point::new(
            q.x + f64::from(corner.x),
            q.y + f64::from(corner.y),
        ))
    }

    /// The drawing point at the centre of a panel's pixel `(x, y)`.
    pub fn pixel_centre(&self, x: u32, y: u32) -> Point {
        Point::new(
            self.frame.x0 + (f64::from(x) + 0.5) / self.scale,
            self.frame.y0 + (f64::from(y) + 0.5) / self.scale,
        )
    }
}

/// Bounds of the curves (tight, not of the control points), the handles and the mesh
/// vertices. `handles` is not empty.
fn content_bounds(drawing: &Drawing, handles: &[HandleMarker], mesh: Option<&TriMesh>) -> Rect {
    let first = handles[0].points()[0];
    let mut bounds = Rect::from_points(first, first);
    for h in handles {
        for &p in h.points() {
            bounds = bounds.union_pt(p);
        }
    }
    for path in &drawing.paths {
        for j in 0..path.n_curves() {
            bounds = bounds.union(path.curve(j).bounding_box());
        }
    }
    if let Some(mesh) = mesh {
        for &v in &mesh.vertices {
            bounds = bounds.union_pt(v);
        }
    }
    bounds
}

/// The number of columns, among `1..=n`, whose grid of `n` panels of `pw × ph` is closest to
/// square (smallest `|ln(width / height)|`); more columns on a tie.
fn best_columns(n: usize, pw: f64, ph: f64) -> usize {
    let mut best = (f64::INFINITY, 1);
    for columns in (1..=n).rev() {
        let rows = n.div_ceil(columns);
        let cost = ((columns as f64 * pw) / (rows as f64 * ph)).ln().abs();
        if cost < best.0 - 1e-12 {
            best = (cost, columns);
        }
    }
    best.1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_best_columns_square_panels() {
        assert_eq!(best_columns(1, 1.0, 1.0), 1);
        assert_eq!(best_columns(2, 1.0, 1.0), 2); // tie 2:1 vs 1:2 → more columns
        assert_eq!(best_columns(4, 1.0, 1.0), 2);
        assert_eq!(best_columns(5, 1.0, 1.0), 3);
        assert_eq!(best_columns(9, 1.0, 1.0), 3);
        // Wide panels stack: 2 panels of 2:1 → one column, square grid.
        assert_eq!(best_columns(2, 2.0, 1.0), 1);
        // Tall panels line up: 3 panels of 1:3 → one row.
        assert_eq!(best_columns(3, 1.0, 3.0), 3);
    }
}
