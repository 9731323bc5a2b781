//! Where everything goes in a weight map: the frame of drawing space every panel shows, the
//! scale, the grid of panels, the colour bar, and the sizes of lines and labels.

use kurbo::{ParamCurveExtrema, Point, Rect};

use super::{HandleMarker, WeightMapError, WeightMapOptions};
use crate::drawing::Drawing;
use crate::figure::grid::{GridError, PanelGrid};
use crate::mesh::TriMesh;

pub use crate::figure::grid::{
    FRAME_MARGIN, LINE_SCALE_RANGE, MAX_IMAGE_PIXELS, MAX_IMAGE_SIDE, MIN_PANEL_WIDTH,
    REFERENCE_PANEL_WIDTH, TICK_LENGTH,
};

/// Fraction of a panel's width taken by each out-of-range extension of the colour bar.
const BAR_EXTENSION_FRACTION: f64 = 0.15;

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
        let shown: Vec<usize> = match options.handle {
            Some(i) => vec![i],
            None => (0..handles.len()).collect(),
        };
        let content = content_bounds(drawing, handles, mesh);
        let grid =
            PanelGrid::new(content, shown.len(), options.panel_width, 1).map_err(|e| match e {
                GridError::InvalidPanelWidth { width, min, max } => {
                    WeightMapError::InvalidPanelWidth { width, min, max }
                }
                GridError::TooLarge {
                    width,
                    height,
                    max_side,
                    max_pixels,
                } => WeightMapError::TooLarge {
                    width,
                    height,
                    max_side,
                    max_pixels,
                },
                _ => WeightMapError::NonFiniteGeometry,
            })?;
        let panels = shown
            .iter()
            .zip(&grid.corners)
            .map(|(&handle, &(x, y))| Panel { handle, x, y })
            .collect();
        Ok(WeightMapLayout {
            frame: grid.frame,
            scale: grid.scale,
            panel_width: grid.panel_width,
            panel_height: grid.panel_height,
            panels,
            columns: grid.columns,
            width: grid.width,
            height: grid.height,
            colour_bar: grid.colour_bar,
            bar_extension: (BAR_EXTENSION_FRACTION * f64::from(grid.panel_width)).round(),
            line_scale: grid.line_scale,
            gutter: grid.gutter,
            glyph_scale: grid.glyph_scale,
            label_height: grid.label_height,
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
