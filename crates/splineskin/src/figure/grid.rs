//! Where everything goes in a picture of panels: the rectangle of drawing space every panel
//! shows, the scale, the grid of panels with a label strip above each, the colour bar below
//! them, and the sizes of lines and labels.
//!
//! ```text
//!  gutter
//!  label strip        label strip
//! ┌──────────────┐   ┌──────────────┐    every panel: the same frame of drawing space,
//! │    panel 0   │   │    panel 1   │    panel_width × panel_height pixels
//! └──────────────┘   └──────────────┘
//!        ▕▒▒▒▒▒▒▒▒▒▒▒▒▒▒▒▒▒▏              colour bar, then its tick labels
//! ```

use kurbo::{Point, Rect};

use super::glyphs::GLYPH_HEIGHT;

/// Margin around the frame's content, on every side, as a fraction of the content's larger
/// side: 0.05. Leaves room for handle markers at the edge, and bounds a panel's aspect ratio at
/// 1 : 11 for the thinnest drawings.
pub const FRAME_MARGIN: f64 = 0.05;

/// Largest side of a picture, in pixels: [`crate::render::MAX_RENDER_SIZE`].
pub const MAX_IMAGE_SIDE: u32 = crate::render::MAX_RENDER_SIZE;

/// Largest number of pixels of a picture: 2²⁶ (about 67 million, e.g. 8192 × 8192). Weight
/// maps keep 8 bytes per panel pixel of samples on top of the image's 4.
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
/// Fraction of a panel's width taken by the colour bar's main section.
pub const BAR_MAIN_FRACTION: f64 = 0.6;
/// Nominal length of the colour bar's major ticks, in pixels.
pub const TICK_LENGTH: f64 = 5.0;

/// Why a grid of panels cannot be laid out.
#[derive(Debug, Clone, thiserror::Error, PartialEq)]
#[non_exhaustive]
pub enum GridError {
    /// The panel width is out of range.
    #[error("panel width {width} px is out of range (expected {min} to {max} pixels)")]
    InvalidPanelWidth {
        /// The width asked for.
        width: u32,
        /// [`MIN_PANEL_WIDTH`].
        min: u32,
        /// [`MAX_IMAGE_SIDE`].
        max: u32,
    },
    /// The content has no finite bounds.
    #[error("the content to draw does not have finite bounds")]
    NonFiniteGeometry,
    /// The image would be too large.
    #[error("a {width}×{height} image is too large (at most {max_side} pixels a side and {max_pixels} in all)")]
    TooLarge {
        /// Image width.
        width: u64,
        /// Image height.
        height: u64,
        /// [`MAX_IMAGE_SIDE`].
        max_side: u32,
        /// [`MAX_IMAGE_PIXELS`].
        max_pixels: u64,
    },
}

/// The geometry of a picture of panels.
///
/// Every panel shows the same rectangle [`PanelGrid::frame`] of drawing space (y down, as in
/// SVG) at [`PanelGrid::scale`] pixels per unit: drawing point `p` is at
/// `(p − frame.origin) · scale` from the panel's corner. Pixel `(i, j)` covers
/// `[i, i + 1) × [j, j + 1)`.
#[derive(Clone, Debug, PartialEq)]
pub struct PanelGrid {
    /// The drawing-space rectangle each panel shows: the content with [`FRAME_MARGIN`] on every
    /// side, then grown vertically (centred) to a whole number of pixels.
    pub frame: Rect,
    /// Pixels per drawing unit.
    pub scale: f64,
    /// Width of a panel in pixels.
    pub panel_width: u32,
    /// Height of a panel in pixels: the frame's height times the scale, rounded up, at least 1.
    pub panel_height: u32,
    /// Top-left corner of each panel, in image pixels, row by row.
    pub corners: Vec<(u32, u32)>,
    /// Number of panel columns: the one making the grid closest to square (more columns on a
    /// tie).
    pub columns: usize,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// The colour bar's main section, in image pixels, centred below the grid.
    pub colour_bar: Rect,
    /// Line widths, marker radii and gutters relative to their nominal sizes (at
    /// [`REFERENCE_PANEL_WIDTH`]).
    pub line_scale: f64,
    /// Gutter between panels and around the image, in pixels.
    pub gutter: u32,
    /// Size of a font pixel of the colour bar's tick labels, in pixels (panel labels are one
    /// step larger).
    pub glyph_scale: u32,
    /// Height of one line of a panel's label, in pixels.
    pub label_line_height: u32,
    /// Height of the strip above each panel holding its label lines, in pixels.
    pub label_height: u32,
}

impl PanelGrid {
    /// Lays out `n_panels` (≥ 1) panels of `panel_width` pixels showing `content` (a
    /// drawing-space rectangle; a point gets a frame of one unit), each with `label_lines`
    /// lines of label above it, and a colour bar below.
    ///
    /// Errors: [`GridError::InvalidPanelWidth`], [`GridError::NonFiniteGeometry`],
    /// [`GridError::TooLarge`].
    ///
    /// ```
    /// use kurbo::{Point, Rect};
    /// use splineskin::figure::PanelGrid;
    /// // 100 × 30 of content, 5 % margins: a 110 × 40 frame, 2 px per unit at 220 px.
    /// let grid = PanelGrid::new(Rect::new(0.0, 0.0, 100.0, 30.0), 3, 220, 1)?;
    /// assert_eq!((grid.scale, grid.panel_height), (2.0, 80));
    /// assert_eq!(grid.corners.len(), 3);
    /// assert_eq!(grid.to_pixel(0, Point::new(-5.0, -5.0)), Some(Point::new(6.0, 24.0)));
    /// # Ok::<(), splineskin::figure::GridError>(())
    /// ```
    pub fn new(
        content: Rect,
        n_panels: usize,
        panel_width: u32,
        label_lines: u32,
    ) -> Result<PanelGrid, GridError> {
        let pw = panel_width;
        if !(MIN_PANEL_WIDTH..=MAX_IMAGE_SIDE).contains(&pw) {
            return Err(GridError::InvalidPanelWidth {
                width: pw,
                min: MIN_PANEL_WIDTH,
                max: MAX_IMAGE_SIDE,
            });
        }
        let finite = [content.x0, content.y0, content.x1, content.y1]
            .iter()
            .all(|v| v.is_finite());
        if !finite {
            return Err(GridError::NonFiniteGeometry);
        }
        let side = content.width().max(content.height());
        // A lone point: a frame of one drawing unit around it.
        let side = if side > 0.0 { side } else { 1.0 };
        let margin = FRAME_MARGIN * side;
        let frame = content.inflate(margin, margin);
        let scale = f64::from(pw) / frame.width();
        let ph_exact = frame.height() * scale;
        if !(scale.is_finite() && ph_exact.is_finite() && scale > 0.0) {
            return Err(GridError::NonFiniteGeometry);
        }
        // Bounded by the aspect ratio (at most 1 : 11) times the panel width. Rounded up (the
        // slack absorbs the rounding of `scale`), so that the frame only ever grows.
        let ph = ((ph_exact - PIXEL_SLACK).ceil() as u32).max(1);
        let centre_y = 0.5 * (frame.y0 + frame.y1);
        let half = 0.5 * f64::from(ph) / scale;
        let frame = Rect::new(frame.x0, centre_y - half, frame.x1, centre_y + half);

        let n = n_panels.max(1);
        let columns = best_columns(n, f64::from(pw), f64::from(ph));
        let rows = n.div_ceil(columns);

        let line_scale =
            (f64::from(pw) / REFERENCE_PANEL_WIDTH).clamp(LINE_SCALE_RANGE.0, LINE_SCALE_RANGE.1);
        let gutter = ((GUTTER * line_scale).round() as u32).max(4);
        let glyph_scale = ((2.0 * line_scale).round() as u32).max(MIN_GLYPH_SCALE);
        let bar_height = (BAR_HEIGHT * line_scale).round();
        let tick_label_height = f64::from(GLYPH_HEIGHT * glyph_scale);
        // A label line: glyphs one step larger, over a gap of one of their pixels.
        let label_line_height = (GLYPH_HEIGHT + 1) * (glyph_scale + 1);
        let label_height = label_line_height * label_lines;

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
            return Err(GridError::TooLarge {
                width,
                height,
                max_side: MAX_IMAGE_SIDE,
                max_pixels: MAX_IMAGE_PIXELS,
            });
        }
        let (width, height) = (width as u32, height as u32);
        let corners = (0..n_panels)
            .map(|k| {
                (
                    gutter + (k % columns) as u32 * (pw + gutter),
                    gutter + label_height + (k / columns) as u32 * (label_height + ph + gutter),
                )
            })
            .collect();
        let main = (BAR_MAIN_FRACTION * f64::from(pw)).round();
        let bar_x0 = ((f64::from(width) - main) / 2.0).round();
        let colour_bar = Rect::new(bar_x0, bar_top, bar_x0 + main, bar_top + bar_height);
        Ok(PanelGrid {
            frame,
            scale,
            panel_width: pw,
            panel_height: ph,
            corners,
            columns,
            width,
            height,
            colour_bar,
            line_scale,
            gutter,
            glyph_scale,
            label_line_height,
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
    /// [`PanelGrid::corners`]): pixel coordinates, `floor` of which is the pixel holding it.
    /// `None` if there is no such panel.
    pub fn to_pixel(&self, panel: usize, p: Point) -> Option<Point> {
        let &(x, y) = self.corners.get(panel)?;
        let q = self.panel_pixel(p);
        Some(Point::new(q.x + f64::from(x), q.y + f64::from(y)))
    }

    /// The drawing point at the centre of a panel's pixel `(x, y)`.
    pub fn pixel_centre(&self, x: u32, y: u32) -> Point {
        Point::new(
            self.frame.x0 + (f64::from(x) + 0.5) / self.scale,
            self.frame.y0 + (f64::from(y) + 0.5) / self.scale,
        )
    }
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
    fn grid_best_columns_square_panels() {
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

    #[test]
    fn grid_label_lines_add_strips() {
        let content = Rect::new(0.0, 0.0, 100.0, 30.0);
        let one = PanelGrid::new(content, 2, 220, 1).unwrap();
        let two = PanelGrid::new(content, 2, 220, 2).unwrap();
        assert_eq!(two.label_height, 2 * one.label_height);
        assert_eq!(one.label_height, one.label_line_height);
        // Two stacked panels: each gains one line.
        assert_eq!(two.height, one.height + 2 * one.label_line_height);
        assert_eq!(two.corners[0].1, one.corners[0].1 + one.label_line_height);
    }
}
