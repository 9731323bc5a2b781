//! Pictures of handle weights: each handle's weight function `w_i` as a colour map over the
//! drawing, one panel per handle, as a PNG image.
//!
//! ```text
//!  0                1                  the handle's index above its panel
//! ┌──────────────┐ ┌──────────────┐
//! │              │ │              │   panel i: w_i sampled at every pixel centre, in viridis
//! │   ◎      ○   │ │   ○      ◎   │   ◎ handle i, ○ the other handles
//! │  ~~curves~~  │ │  ~~curves~~  │   the drawing's curves as thin dark strokes on top
//! └──────────────┘ └──────────────┘   optional: mesh edges, iso-lines every 0.1
//!    ▕▒▒▒▒▒▒▒▒▒▒▒▒▒▒▒▒▒▒▏             colour bar 0 … 1 (with out-of-range ends when needed)
//!     0       0.5       1
//! ```
//!
//! The weight field is evaluated through [`WeightField::eval`] at the centre of every pixel:
//! every family is defined on the whole plane (mesh families outside their domain take the
//! weights of the nearest boundary point, [`crate::domain::MeshWeights`]), so the whole panel is
//! the field itself, not an extrapolation made here. Values in `[0, 1]` are drawn in viridis;
//! values outside (negative lobes and overshoots of unbounded families such as biharmonic
//! weights) in two ramps of hues viridis does not use ([`colour_map`]), so they are never read
//! as in-range values. The frame, scale and grid are in [`WeightMapLayout`].
//!
//! Iso-lines are drawn where `w_i` crosses a multiple of the step (0 and 1 excepted: bounded
//! families are exactly 0 or 1 on whole regions), anti-aliased from the distance to the level
//! estimated as `|w − level| / |∇w|` with `∇w` by central differences of the pixel samples.

pub mod layout;
mod paint;

/// The colour maps, shared with the other pictures ([`crate::figure::colour_map`]).
pub use crate::figure::colour_map;

/// The handle markers drawn on the panels, at the path they always had
/// ([`crate::scene::handles::HandleMarker`]).
pub use crate::scene::handles::HandleMarker;
pub use layout::{Panel, WeightMapLayout};

pub(crate) use paint::draw_handle_marker;
use paint::{
    colour_bar, curves_path, dashed, fill_panel, handle_marker, mesh_paths, panel_border,
    panel_label, CURVE, CURVE_HALO, DOMAIN_BOUNDARY, MESH_EDGE,
};

use kurbo::Point;
use resvg::tiny_skia::{self, Pixmap, PixmapPaint, Transform};

use crate::drawing::Drawing;
use crate::figure::pixmap::{encode_png, new_pixmap, PixmapError};
use crate::figure::strokes::stroke;
use crate::mesh::TriMesh;
use crate::weights::WeightField;
use colour_map::{range_of, Range};

/// Default panel width: 512 pixels.
pub const DEFAULT_PANEL_WIDTH: u32 = 512;

/// Default iso-line step: 0.1 weight units (nine lines between 0 and 1).
pub const DEFAULT_ISO_STEP: f64 = 0.1;

/// Smallest iso-line step: 0.001 weight units (finer lines fill the picture).
pub const MIN_ISO_STEP: f64 = 1e-3;

/// Options of [`render_weight_map`].
///
/// ```
/// use splineskin::weight_map::{WeightMapOptions, DEFAULT_PANEL_WIDTH};
/// let options = WeightMapOptions::default().with_handle(Some(2)).with_iso_step(Some(0.1));
/// assert_eq!(options.panel_width, DEFAULT_PANEL_WIDTH);
/// assert!(!options.mesh_lines);
/// ```
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct WeightMapOptions {
    /// Width of each panel in pixels, in `MIN_PANEL_WIDTH..=MAX_IMAGE_SIDE` (its height
    /// follows the frame's aspect ratio). Default: [`DEFAULT_PANEL_WIDTH`].
    pub panel_width: u32,
    /// Draw only this handle's panel. Default: none (one panel per handle).
    pub handle: Option<usize>,
    /// Draw the mesh's edges (when a mesh is given). Default: false.
    pub mesh_lines: bool,
    /// Draw iso-lines at multiples of this step (in `[MIN_ISO_STEP, 1]`). Default: none.
    pub iso_step: Option<f64>,
    /// Sample the weights on several threads (rayon's global pool). Default: false.
    pub parallel: bool,
}

impl Default for WeightMapOptions {
    fn default() -> Self {
        WeightMapOptions {
            panel_width: DEFAULT_PANEL_WIDTH,
            handle: None,
            mesh_lines: false,
            iso_step: None,
            parallel: false,
        }
    }
}

impl WeightMapOptions {
    /// Sets [`WeightMapOptions::panel_width`].
    pub fn with_panel_width(mut self, pixels: u32) -> Self {
        self.panel_width = pixels;
        self
    }
    /// Sets [`WeightMapOptions::handle`].
    pub fn with_handle(mut self, handle: Option<usize>) -> Self {
        self.handle = handle;
        self
    }
    /// Sets [`WeightMapOptions::mesh_lines`].
    pub fn with_mesh_lines(mut self, on: bool) -> Self {
        self.mesh_lines = on;
        self
    }
    /// Sets [`WeightMapOptions::iso_step`].
    pub fn with_iso_step(mut self, step: Option<f64>) -> Self {
        self.iso_step = step;
        self
    }
    /// Sets [`WeightMapOptions::parallel`].
    pub fn with_parallel(mut self, parallel: bool) -> Self {
        self.parallel = parallel;
        self
    }
}

/// Why a weight map cannot be drawn.
#[derive(Debug, thiserror::Error, PartialEq)]
#[non_exhaustive]
pub enum WeightMapError {
    /// No handles.
    #[error("no handles: nothing to draw")]
    NoHandles,
    /// The handle markers and the weight field disagree on the number of handles.
    #[error("{n_markers} handle markers for a weight field of {n_handles} handles")]
    HandleCount {
        /// Markers given.
        n_markers: usize,
        /// [`WeightField::n_handles`].
        n_handles: usize,
    },
    /// A handle position is NaN or infinite.
    #[error("handle {handle}: position is not finite")]
    NonFiniteHandle {
        /// The handle.
        handle: usize,
    },
    /// [`WeightMapOptions::handle`] names no handle.
    #[error("handle {handle} does not exist (there are {n_handles} handles, 0 to {})", n_handles - 1)]
    UnknownHandle {
        /// The index asked for.
        handle: usize,
        /// Number of handles (at least 1).
        n_handles: usize,
    },
    /// [`WeightMapOptions::panel_width`] out of range.
    #[error("panel width {width} px is out of range (expected {min} to {max} pixels)")]
    InvalidPanelWidth {
        /// The width asked for.
        width: u32,
        /// [`layout::MIN_PANEL_WIDTH`].
        min: u32,
        /// [`layout::MAX_IMAGE_SIDE`].
        max: u32,
    },
    /// [`WeightMapOptions::iso_step`] out of range.
    #[error("iso-line step {step} is out of range (expected {min} to 1)")]
    InvalidIsoStep {
        /// The step asked for.
        step: f64,
        /// [`MIN_ISO_STEP`].
        min: f64,
    },
    /// The drawing or the mesh has coordinates that give no finite frame.
    #[error("the drawing, handles and mesh do not have finite bounds")]
    NonFiniteGeometry,
    /// The image would be too large.
    #[error("a {width}×{height} image is too large (at most {max_side} pixels a side and {max_pixels} in all): ask for narrower panels or one handle")]
    TooLarge {
        /// Image width.
        width: u64,
        /// Image height.
        height: u64,
        /// [`layout::MAX_IMAGE_SIDE`].
        max_side: u32,
        /// [`layout::MAX_IMAGE_PIXELS`].
        max_pixels: u64,
    },
    /// The weight field returned NaN or an infinity.
    #[error("weight of handle {handle} is not finite at ({x}, {y})")]
    NonFiniteWeight {
        /// The handle.
        handle: usize,
        /// Where (drawing units).
        x: f64,
        /// Where (drawing units).
        y: f64,
    },
    /// The pixmap cannot be allocated or encoded.
    #[error(transparent)]
    Pixmap(#[from] PixmapError),
    /// [`RgbaImage::decode_png`] cannot read the bytes.
    #[error("cannot decode the PNG: {message}")]
    Decode {
        /// The decoder's description.
        message: String,
    },
}

/// An 8-bit RGBA image (straight alpha) read back from PNG bytes: for tests and tools that look
/// at weight maps without a PNG decoder of their own.
///
/// ```
/// use splineskin::weight_map::RgbaImage;
/// let png = splineskin::render::render_png(
///     r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 2 1"><rect width="1" height="1"/></svg>"#,
///     20,
/// )?;
/// let image = RgbaImage::decode_png(&png)?;
/// assert_eq!((image.width, image.height), (20, 10));
/// assert_eq!(image.pixel(2, 2), Some([0, 0, 0, 255]));
/// assert_eq!(image.pixel(15, 2), Some([255, 255, 255, 255]));
/// assert_eq!(image.pixel(20, 0), None);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RgbaImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width × height` pixels, row by row from the top left.
    pub pixels: Vec<[u8; 4]>,
}

impl RgbaImage {
    /// Decodes PNG bytes (any colour type the PNG decoder accepts).
    pub fn decode_png(png: &[u8]) -> Result<RgbaImage, WeightMapError> {
        let pixmap = Pixmap::decode_png(png).map_err(|e| WeightMapError::Decode {
            message: e.to_string(),
        })?;
        let (width, height) = (pixmap.width(), pixmap.height());
        let pixels = pixmap
            .take_demultiplied()
            .chunks_exact(4)
            .map(|c| [c[0], c[1], c[2], c[3]])
            .collect();
        Ok(RgbaImage {
            width,
            height,
            pixels,
        })
    }

    /// The pixel at column `x`, row `y`; `None` outside the image.
    pub fn pixel(&self, x: u32, y: u32) -> Option<[u8; 4]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        Some(self.pixels[y as usize * self.width as usize + x as usize])
    }

    /// The colour (without alpha) of the pixel holding image point `p` (pixel coordinates, as
    /// [`WeightMapLayout::to_pixel`] gives); `None` outside the image.
    pub fn colour_at(&self, p: Point) -> Option<[u8; 3]> {
        if !(p.x >= 0.0 && p.y >= 0.0) {
            return None;
        }
        let [r, g, b, _] = self.pixel(p.x.floor() as u32, p.y.floor() as u32)?;
        Some([r, g, b])
    }
}

/// The range of one handle's weight over the pixel centres of its panel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WeightRange {
    /// The handle.
    pub handle: usize,
    /// Smallest sampled weight.
    pub min: f64,
    /// Largest sampled weight.
    pub max: f64,
}

impl WeightRange {
    /// Whether every sample is in `[0, 1]` up to [`colour_map::OUT_OF_RANGE_TOLERANCE`] (no
    /// pixel is drawn in an out-of-range colour).
    pub fn is_within_unit(&self) -> bool {
        range_of(self.min) == Range::Within && range_of(self.max) == Range::Within
    }
}

/// A rendered weight map.
#[derive(Clone, Debug)]
pub struct WeightMap {
    /// The image, 8-bit RGBA PNG.
    pub png: Vec<u8>,
    /// Where everything is in it.
    pub layout: WeightMapLayout,
    /// Per panel, in [`WeightMapLayout::panels`] order, the range of the sampled weights.
    pub ranges: Vec<WeightRange>,
}

/// Renders the weights of `weights` (one function per handle, handle `i` drawn as
/// `handles[i]`) over the curves of `drawing` as a PNG: one panel per handle (or only
/// [`WeightMapOptions::handle`]'s), laid out as [`WeightMapLayout::new`] says, with a colour
/// bar below. `mesh` is the mesh a mesh family was solved on: it is kept inside the frame,
/// and its edges are drawn with [`WeightMapOptions::mesh_lines`].
///
/// Each panel shows, bottom to top: `w_i` at every pixel centre ([`colour_map::weight_colour`]),
/// iso-lines (dark over light colours, light over dark ones), mesh edges (thin, translucent
/// white), the mesh's boundary (dashed white, whenever a mesh is given: outside it the weights
/// are those of the nearest boundary point), the curves (dark, over a light halo so that they
/// read on dark colours too), every handle (a ring for a point, large for handle `i` and small for the others, the pixel at its
/// centre keeping its weight colour; a segment for a bone, thick for handle `i`) and the
/// handle's index above the panel.
///
/// Errors: those of [`WeightMapLayout::new`], [`WeightMapError::HandleCount`],
/// [`WeightMapError::InvalidIsoStep`], [`WeightMapError::NonFiniteWeight`], and allocation or
/// encoding failures.
///
/// ```
/// use kurbo::Point;
/// use splineskin::drawing::{read_svg, ImportOptions};
/// use splineskin::weight_map::colour_map::viridis;
/// use splineskin::weight_map::{render_weight_map, HandleMarker, RgbaImage, WeightMapOptions};
/// use splineskin::weights::{Shepard, ShepardOptions};
///
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg"><path d="M0 0 C30 40 70 40 100 0"/></svg>"#;
/// let drawing = read_svg(svg, &ImportOptions::default())?;
/// let handles = [Point::new(10.0, 10.0), Point::new(90.0, 10.0)];
/// let weights = Shepard::new(&handles, ShepardOptions::default());
/// let markers = handles.map(HandleMarker::Point);
/// let options = WeightMapOptions::default().with_panel_width(200);
/// let map = render_weight_map(&drawing, &markers, &weights, None, &options)?;
/// let image = RgbaImage::decode_png(&map.png)?;
/// assert_eq!((image.width, image.height), (map.layout.width, map.layout.height));
/// // Panel 1, at handle 1: weight 1, the top colour of viridis; at handle 0 about 0.
/// let at = map.layout.to_pixel(1, handles[1]).unwrap();
/// assert_eq!(image.colour_at(at), Some(viridis(1.0)));
/// let at = map.layout.to_pixel(1, handles[0]).unwrap();
/// assert_eq!(image.colour_at(at), Some(viridis(0.0)));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn render_weight_map(
    drawing: &Drawing,
    handles: &[HandleMarker],
    weights: &dyn WeightField,
    mesh: Option<&TriMesh>,
    options: &WeightMapOptions,
) -> Result<WeightMap, WeightMapError> {
    if handles.len() != weights.n_handles() {
        return Err(WeightMapError::HandleCount {
            n_markers: handles.len(),
            n_handles: weights.n_handles(),
        });
    }
    if let Some(step) = options.iso_step {
        if !(MIN_ISO_STEP..=1.0).contains(&step) {
            return Err(WeightMapError::InvalidIsoStep {
                step,
                min: MIN_ISO_STEP,
            });
        }
    }
    let layout = WeightMapLayout::new(drawing, handles, mesh, options)?;
    let shown: Vec<usize> = layout.panels.iter().map(|p| p.handle).collect();
    let samples = sample(weights, &layout, &shown, options.parallel)?;
    let ranges = ranges_of(&samples, &shown);

    let (pw, ph) = (layout.panel_width, layout.panel_height);
    let mut image = new_pixmap(layout.width, layout.height)?;
    image.fill(tiny_skia::Color::WHITE);
    let mut panel = new_pixmap(pw, ph)?;
    let curves = curves_path(drawing, &layout);
    let (edges, boundary) = match mesh {
        Some(mesh) => mesh_paths(mesh, &layout),
        None => (None, None),
    };
    let edges = edges.filter(|_| options.mesh_lines);
    for (s, placement) in layout.panels.iter().enumerate() {
        fill_panel(
            &mut panel,
            &samples,
            s,
            shown.len(),
            options.iso_step,
            &layout,
        );
        let ls = layout.line_scale;
        if let Some(edges) = &edges {
            stroke(&mut panel, edges, MESH_EDGE, ls);
        }
        if let Some(boundary) = &boundary {
            dashed(&mut panel, boundary, DOMAIN_BOUNDARY, ls);
        }
        if let Some(curves) = &curves {
            stroke(&mut panel, curves, CURVE_HALO, ls);
            stroke(&mut panel, curves, CURVE, ls);
        }
        for (i, h) in handles.iter().enumerate() {
            let own = i == placement.handle;
            handle_marker(&mut panel, h, own, &layout);
        }
        image.draw_pixmap(
            placement.x as i32,
            placement.y as i32,
            panel.as_ref(),
            &PixmapPaint::default(),
            Transform::identity(),
            None,
        );
        panel_border(&mut image, placement, &layout);
        panel_label(
            &mut image,
            &placement.handle.to_string(),
            placement,
            &layout,
        );
    }
    let below = ranges.iter().any(|r| range_of(r.min) == Range::Below);
    let above = ranges.iter().any(|r| range_of(r.max) == Range::Above);
    colour_bar(&mut image, &layout, below, above, options.iso_step);
    let png = encode_png(&image)?;
    Ok(WeightMap {
        png,
        layout,
        ranges,
    })
}

/// The weights of the `shown` handles at every pixel centre of a panel: entry
/// `(y · panel_width + x) · shown.len() + s` is `w_{shown[s]}` at pixel `(x, y)`.
fn sample(
    weights: &dyn WeightField,
    layout: &WeightMapLayout,
    shown: &[usize],
    parallel: bool,
) -> Result<Vec<f64>, WeightMapError> {
    let (pw, ph) = (layout.panel_width as usize, layout.panel_height as usize);
    let n_shown = shown.len();
    let row_len = pw * n_shown;
    let mut samples = vec![0.0; row_len * ph];
    let fill_row = |y: usize, row: &mut [f64], all: &mut Vec<f64>| {
        all.resize(weights.n_handles(), 0.0);
        for x in 0..pw {
            weights.eval(layout.pixel_centre(x as u32, y as u32), all);
            for (s, &i) in shown.iter().enumerate() {
                row[x * n_shown + s] = all[i];
            }
        }
    };
    if parallel {
        use rayon::prelude::*;
        samples
            .par_chunks_mut(row_len)
            .enumerate()
            .for_each_init(Vec::new, |all, (y, row)| fill_row(y, row, all));
    } else {
        let mut all = Vec::new();
        for (y, row) in samples.chunks_mut(row_len).enumerate() {
            fill_row(y, row, &mut all);
        }
    }
    if let Some(k) = samples.iter().position(|w| !w.is_finite()) {
        let pixel = k / n_shown;
        let p = layout.pixel_centre((pixel % pw) as u32, (pixel / pw) as u32);
        return Err(WeightMapError::NonFiniteWeight {
            handle: shown[k % n_shown],
            x: p.x,
            y: p.y,
        });
    }
    Ok(samples)
}

/// Per shown handle, the smallest and largest sample.
fn ranges_of(samples: &[f64], shown: &[usize]) -> Vec<WeightRange> {
    let n = shown.len();
    shown
        .iter()
        .enumerate()
        .map(|(s, &handle)| {
            let (min, max) = samples
                .iter()
                .skip(s)
                .step_by(n)
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &w| {
                    (lo.min(w), hi.max(w))
                });
            WeightRange { handle, min, max }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::colour_map::{viridis, BELOW_DEEP, BELOW_LIGHT};
    use super::*;
    use crate::domain::MeshWeights;
    use crate::drawing::{read_svg, ImportOptions};
    use crate::weights::{Shepard, ShepardOptions};
    use kurbo::Rect;

    /// An arc from (0, 0) to (100, 0) bulging to y = 30, with handles below it at (25, 0)
    /// and (75, 0), about 24 units from the curve.
    fn arc_scene() -> (Drawing, [Point; 2]) {
        let svg =
            r#"<svg xmlns="http://www.w3.org/2000/svg"><path d="M0 0 C30 40 70 40 100 0"/></svg>"#;
        let drawing = read_svg(svg, &ImportOptions::default()).unwrap();
        (drawing, [Point::new(25.0, 0.0), Point::new(75.0, 0.0)])
    }

    fn markers(points: &[Point]) -> Vec<HandleMarker> {
        points.iter().map(|&p| HandleMarker::Point(p)).collect()
    }

    /// The largest per-channel difference.
    fn difference(a: [u8; 3], b: [u8; 3]) -> u8 {
        (0..3).map(|k| a[k].abs_diff(b[k])).max().unwrap()
    }

    /// Weights linear in x on the square [0, 10]² (a 5 × 5 grid mesh): handle 0 has
    /// `a + b·x`, handle 1 the rest of 1. Linear interpolation reproduces them exactly inside;
    /// outside, the nearest boundary point's value, i.e. x clamped to [0, 10].
    fn linear_field(a: f64, b: f64) -> (TriMesh, MeshWeights) {
        let mesh = TriMesh::grid(Rect::new(0.0, 0.0, 10.0, 10.0), 5, 5).unwrap();
        let values = mesh
            .vertices
            .iter()
            .flat_map(|v| [a + b * v.x, 1.0 - a - b * v.x])
            .collect();
        let weights = MeshWeights::new(&mesh, values, 2).unwrap();
        (mesh, weights)
    }

    fn render(
        drawing: &Drawing,
        handles: &[Point],
        weights: &dyn WeightField,
        mesh: Option<&TriMesh>,
        options: &WeightMapOptions,
    ) -> (WeightMap, RgbaImage) {
        let map = render_weight_map(drawing, &markers(handles), weights, mesh, options).unwrap();
        let image = RgbaImage::decode_png(&map.png).unwrap();
        (map, image)
    }

    /// [`render`] of [`linear_field`]`(a, b)` with its mesh and no drawing, the two handles at
    /// the middles of the square's left and right sides.
    fn render_linear_field(a: f64, b: f64, options: &WeightMapOptions) -> (WeightMap, RgbaImage) {
        let (mesh, weights) = linear_field(a, b);
        let handles = [Point::new(0.0, 5.0), Point::new(10.0, 5.0)];
        render(
            &Drawing::default(),
            &handles,
            &weights,
            Some(&mesh),
            options,
        )
    }

    #[test]
    fn weight_map_layout_by_hand() {
        // Content: the arc (x 0..100, y 0..30) and the handles (y = 0): 100 × 30; margin
        // 5 % of 100 → frame (−5, −5)–(105, 35), 110 × 40. At 220 px: scale 2, panels
        // 220 × 80; line scale 0.5 (clamped), gutter 6, glyphs 2 px (the least), panel
        // labels 3 px in a strip of 6 · 3 = 18 px. Two wide panels stack (1 column: 220 × 160
        // is nearer square than 440 × 80). Width 6 + 220 + 6 = 232; height
        // 6 + 2·(18 + 80 + 6) = 214, + bar 7 + tick 3 + 4 + tick labels 10 + gutter 6 = 244.
        let (drawing, handles) = arc_scene();
        let options = WeightMapOptions::default().with_panel_width(220);
        let layout = WeightMapLayout::new(&drawing, &markers(&handles), None, &options).unwrap();
        assert_eq!(layout.frame, Rect::new(-5.0, -5.0, 105.0, 35.0));
        assert_eq!(layout.scale, 2.0);
        assert_eq!((layout.panel_width, layout.panel_height), (220, 80));
        assert_eq!(layout.columns, 1);
        assert_eq!(
            layout.panels,
            vec![
                Panel {
                    handle: 0,
                    x: 6,
                    y: 24
                },
                Panel {
                    handle: 1,
                    x: 6,
                    y: 128
                }
            ]
        );
        assert_eq!((layout.width, layout.height), (232, 244));
        assert_eq!(
            layout.to_pixel(1, handles[1]),
            Some(Point::new(6.0 + 160.0, 128.0 + 10.0))
        );
        assert_eq!(layout.to_pixel(2, handles[1]), None);
        // One handle: one panel.
        let one = WeightMapLayout::new(
            &drawing,
            &markers(&handles),
            None,
            &options.clone().with_handle(Some(1)),
        )
        .unwrap();
        assert_eq!(
            one.panels,
            vec![Panel {
                handle: 1,
                x: 6,
                y: 24
            }]
        );
        assert_eq!((one.width, one.height), (232, 244 - 104));
    }

    #[test]
    fn weight_map_shepard_handles_are_top_and_bottom_of_the_map() {
        let (drawing, handles) = arc_scene();
        let weights = Shepard::new(&handles, ShepardOptions::default());
        let options = WeightMapOptions::default().with_panel_width(220);
        let (map, image) = render(&drawing, &handles, &weights, None, &options);
        assert_eq!(
            (image.width, image.height),
            (map.layout.width, map.layout.height)
        );
        for panel in 0..2 {
            for (i, &h) in handles.iter().enumerate() {
                let at = map.layout.to_pixel(panel, h).unwrap();
                // Shepard at the pixel centre, 0.35 units from the handle and 50 from the
                // other: 1 − 5e-5 or 5e-5, which viridis rounds to its ends.
                let want = if i == panel {
                    viridis(1.0)
                } else {
                    viridis(0.0)
                };
                assert_eq!(image.colour_at(at), Some(want), "panel {panel}, handle {i}");
            }
        }
        // Each panel's index is written above it: "0" and "1" (3 px font pixels, 9 × 15 px).
        for (k, panel) in map.layout.panels.iter().enumerate() {
            let inked = |dx: u32, dy: u32| {
                let y = panel.y - map.layout.label_height + dy;
                image.pixel(panel.x + dx, y).unwrap()[..3] == [0, 0, 0]
            };
            // Both glyphs have their middle column set on the top row; only "0" has its right
            // column set on the second row ("0" is .X. / X.X, "1" is .X. / XX.).
            assert!(inked(4, 1), "panel {k}");
            assert_eq!(inked(7, 4), k == 0, "panel {k}");
            assert!(!inked(4, 16), "panel {k}: the gap under the label");
        }
        // Shepard weights are in [0, 1]: no out-of-range tint, the bar has no extensions.
        assert!(map.ranges.iter().all(|r| r.is_within_unit()));
        assert!(map.ranges[0].max > 0.999 && map.ranges[0].min < 0.01);
        let bar = map.layout.colour_bar;
        let left_of_bar = Point::new(bar.x0 - 5.0, bar.y0 + 2.0);
        assert_eq!(image.colour_at(left_of_bar), Some([255, 255, 255]));
        let bar_start = Point::new(bar.x0 + 0.5, bar.y0 + 2.0);
        let first = viridis(0.5 / bar.width());
        assert_eq!(image.colour_at(bar_start), Some(first));
    }

    #[test]
    fn weight_map_curves_land_on_their_user_units() {
        // A viewBox not at the origin and a group transform: the line is y = 80 from x = 120
        // to 220 in root user units, and must be drawn there.
        let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="100 50 200 100" width="400" height="200">
            <g transform="translate(120 60)"><path d="M0 20 L100 20" stroke="black"/></g></svg>"#;
        let drawing = read_svg(svg, &ImportOptions::default()).unwrap();
        let handles = [Point::new(150.0, 100.0), Point::new(200.0, 100.0)];
        let weights = Shepard::new(&handles, ShepardOptions::default());
        let options = WeightMapOptions::default().with_panel_width(1024);
        let (map, image) = render(&drawing, &handles, &weights, None, &options);
        let dark = |p: Point| {
            let c = image.colour_at(map.layout.to_pixel(0, p).unwrap()).unwrap();
            c.iter().all(|&v| v <= 40)
        };
        for x in [130.0, 170.0, 210.0] {
            assert!(
                dark(Point::new(x, 80.0)),
                "x = {x}: the line is not drawn at y = 80"
            );
            // 1 unit is 9.3 px: one unit off the line is the weight colour.
            assert!(!dark(Point::new(x, 81.0)) && !dark(Point::new(x, 79.0)));
        }
        assert!(!dark(Point::new(223.0, 80.0)), "the line ends at x = 220");
    }

    #[test]
    fn weight_map_linear_field_is_viridis_of_x_everywhere() {
        let options = WeightMapOptions::default().with_panel_width(110);
        let (map, image) = render_linear_field(0.0, 0.1, &options);
        let layout = &map.layout;
        // frame (−0.5, −0.5)–(10.5, 10.5), 10 px per unit
        assert_eq!(layout.frame, Rect::new(-0.5, -0.5, 10.5, 10.5));
        assert_eq!(layout.scale, 10.0);
        for (panel, placement) in layout.panels.iter().enumerate() {
            let mut checked = 0;
            for row in [30, 80] {
                for col in 0..110u32 {
                    // Skip the dashed boundary (x = 0 and 10, pixels 5 and 105).
                    if col.abs_diff(5) <= 2 || col.abs_diff(105) <= 2 {
                        continue;
                    }
                    let p = layout.pixel_centre(col, row);
                    let w0 = (p.x / 10.0).clamp(0.0, 1.0);
                    let w = if panel == 0 { w0 } else { 1.0 - w0 };
                    let at = Point::new(
                        f64::from(placement.x + col) + 0.5,
                        f64::from(placement.y + row) + 0.5,
                    );
                    let got = image.colour_at(at).unwrap();
                    assert!(
                        difference(got, viridis(w)) <= 1,
                        "panel {panel} pixel ({col}, {row}): {got:?} for w = {w}"
                    );
                    checked += 1;
                }
            }
            assert!(checked > 190);
        }
        let r = map.ranges[0];
        assert!(r.min.abs() < 1e-12 && (r.max - 1.0).abs() < 1e-12, "{r:?}");
    }

    #[test]
    fn weight_map_iso_lines_and_mesh_lines_where_expected() {
        let base = WeightMapOptions::default()
            .with_panel_width(110)
            .with_handle(Some(0));
        let (map, plain) = render_linear_field(0.0, 0.1, &base);
        let iso = base.clone().with_iso_step(Some(0.1));
        let (_, with_iso) = render_linear_field(0.0, 0.1, &iso);
        let lines = base.clone().with_mesh_lines(true);
        let (_, with_mesh) = render_linear_field(0.0, 0.1, &lines);
        let corner = map.layout.panels[0];
        let at = |col: u32, row: u32| {
            Point::new(
                f64::from(corner.x + col) + 0.5,
                f64::from(corner.y + row) + 0.5,
            )
        };
        let row = 33; // y = 2.85: off the grid lines y = 2 and 4
                      // Level 0.5 is at x = 5, the boundary between pixels 54 and 55: both half a pixel
                      // from it; pixel 50 is 5 px away.
        for col in [54, 55] {
            let (a, b) = (
                plain.colour_at(at(col, row)).unwrap(),
                with_iso.colour_at(at(col, row)).unwrap(),
            );
            assert!(difference(a, b) >= 10, "pixel {col}: {a:?} vs {b:?}");
        }
        for col in [50, 60, 42] {
            assert_eq!(
                plain.colour_at(at(col, row)),
                with_iso.colour_at(at(col, row))
            );
        }
        // Mesh edges: vertical lines at x = 0, 2, …, 10 (pixels 5, 25, …), diagonals inside
        // each square. Pixel 25 (x = 2) is on an edge; row 33 at x = 3.2 (pixel 37) is on no
        // edge (the diagonal of the square [2, 4]² there passes at y = 2.8 or 3.2 ± 0.35 px).
        let on_edge = at(25, row);
        assert!(
            difference(
                plain.colour_at(on_edge).unwrap(),
                with_mesh.colour_at(on_edge).unwrap()
            ) >= 10
        );
        assert_eq!(plain.colour_at(at(31, 70)), with_mesh.colour_at(at(31, 70)));
        // The boundary (x = 0) is drawn, dashed, with or without mesh lines: pixel 5 is not
        // the field on most rows.
        let n_drawn = (20..60)
            .filter(|&row| difference(plain.colour_at(at(5, row)).unwrap(), viridis(0.0)) >= 10)
            .count();
        assert!(n_drawn >= 20, "{n_drawn} of 40 rows");
    }

    #[test]
    fn weight_map_out_of_range_values_take_the_out_of_range_ramps() {
        // w0 = x/5 − 1/2: −0.5 at x = 0, 1.5 at x = 10 (biharmonic-like lobes, exaggerated).
        let options = WeightMapOptions::default().with_panel_width(110);
        let (map, image) = render_linear_field(-0.5, 0.2, &options);
        let r = map.ranges[0];
        assert!(
            (r.min + 0.5).abs() < 1e-12 && (r.max - 1.5).abs() < 1e-12,
            "{r:?}"
        );
        assert!(!r.is_within_unit());
        let corner = map.layout.panels[0];
        let colour = |x: f64, y: f64| {
            let p = map.layout.to_pixel(0, Point::new(x, y)).unwrap();
            let _ = corner;
            image.colour_at(p).unwrap()
        };
        // x = 1.05 (pixel centre): w = −0.29, 58 % of the way down the below ramp.
        let got = colour(1.0, 3.0);
        let want = colour_map::mix(BELOW_LIGHT, BELOW_DEEP, 0.29 / 0.5);
        assert!(difference(got, want) <= 1, "{got:?} vs {want:?}");
        // x = 5.05: w = 0.51, in range.
        assert!(difference(colour(5.0, 3.0), viridis(0.51)) <= 1);
        // The colour bar has its extensions, each end at its deepest colour.
        let bar = map.layout.colour_bar;
        let ext = map.layout.bar_extension;
        let y = bar.y0 + 2.0;
        let left = image.colour_at(Point::new(bar.x0 - ext + 0.5, y)).unwrap();
        assert!(difference(left, BELOW_DEEP) <= 12, "{left:?}");
        let right = image.colour_at(Point::new(bar.x1 + ext - 0.5, y)).unwrap();
        assert!(difference(right, colour_map::ABOVE_DEEP) <= 12, "{right:?}");
    }

    #[test]
    fn weight_map_parallel_is_sequential() {
        let (drawing, handles) = arc_scene();
        let weights = Shepard::new(&handles, ShepardOptions::default());
        let options = WeightMapOptions::default()
            .with_panel_width(96)
            .with_iso_step(Some(0.1));
        let (a, _) = render(&drawing, &handles, &weights, None, &options);
        let (b, _) = render(
            &drawing,
            &handles,
            &weights,
            None,
            &options.with_parallel(true),
        );
        assert_eq!(a.png, b.png);
    }

    /// A field that is NaN right of x = 50.
    struct Broken;
    impl WeightField for Broken {
        fn n_handles(&self) -> usize {
            2
        }
        fn eval(&self, p: Point, out: &mut [f64]) {
            out[0] = if p.x > 50.0 { f64::NAN } else { 0.5 };
            out[1] = 0.5;
        }
    }

    #[test]
    fn weight_map_errors_name_the_problem() {
        let (drawing, handles) = arc_scene();
        let marks = markers(&handles);
        let weights = Shepard::new(&handles, ShepardOptions::default());
        let ok = WeightMapOptions::default().with_panel_width(64);
        let run = |handles: &[HandleMarker], weights: &dyn WeightField, o: &WeightMapOptions| {
            render_weight_map(&drawing, handles, weights, None, o).unwrap_err()
        };
        assert_eq!(
            run(&marks[..1], &weights, &ok),
            WeightMapError::HandleCount {
                n_markers: 1,
                n_handles: 2
            }
        );
        let unknown = run(&marks, &weights, &ok.clone().with_handle(Some(2)));
        assert_eq!(
            unknown,
            WeightMapError::UnknownHandle {
                handle: 2,
                n_handles: 2
            }
        );
        assert!(unknown.to_string().contains("0 to 1"), "{unknown}");
        for width in [0, 31, MAX_IMAGE_SIDE_FOR_TESTS + 1] {
            assert!(matches!(
                run(&marks, &weights, &ok.clone().with_panel_width(width)),
                WeightMapError::InvalidPanelWidth { .. }
            ));
        }
        for step in [0.0, -0.1, 1e-4, 1.5, f64::NAN] {
            assert!(matches!(
                run(&marks, &weights, &ok.clone().with_iso_step(Some(step))),
                WeightMapError::InvalidIsoStep { .. }
            ));
        }
        // 16384 px panels, two of them stacked: too tall.
        assert!(matches!(
            run(&marks, &weights, &ok.clone().with_panel_width(16384)),
            WeightMapError::TooLarge { .. }
        ));
        let mut bad = marks.clone();
        bad[1] = HandleMarker::Point(Point::new(f64::INFINITY, 0.0));
        assert_eq!(
            run(&bad, &weights, &ok),
            WeightMapError::NonFiniteHandle { handle: 1 }
        );
        match run(&marks, &Broken, &ok) {
            WeightMapError::NonFiniteWeight { handle: 0, x, .. } => assert!(x > 50.0),
            e => panic!("{e:?}"),
        }
        assert!(matches!(
            RgbaImage::decode_png(b"not a png"),
            Err(WeightMapError::Decode { .. })
        ));
    }

    const MAX_IMAGE_SIDE_FOR_TESTS: u32 = layout::MAX_IMAGE_SIDE;

    #[test]
    fn weight_map_bone_marker_widens_the_frame() {
        let (drawing, handles) = arc_scene();
        let mut marks = markers(&handles);
        marks.push(HandleMarker::Segment([
            Point::new(40.0, 50.0),
            Point::new(60.0, 70.0),
        ]));
        let layout =
            WeightMapLayout::new(&drawing, &marks, None, &WeightMapOptions::default()).unwrap();
        // content y 0..70, x 0..100 → margin 5, frame y −5..75 (grown to whole pixels).
        assert!(layout.frame.y1 >= 75.0 - 1e-9 && layout.frame.y0 <= -5.0 + 1e-9);
        assert_eq!(layout.panels.len(), 3);
    }
}
