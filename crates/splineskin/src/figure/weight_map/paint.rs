//! What is painted on a weight map: each panel's colour fill with its iso-lines, the curves,
//! mesh and handle overlays, the panel labels and borders, and the colour bar. The layout
//! ([`WeightMapLayout`]) says where; [`super::render_weight_map`] says in which order.

use kurbo::Point;
use resvg::tiny_skia::{self, PathBuilder, Pixmap};

use super::layout;
use super::{HandleMarker, Panel, WeightMapLayout, DEFAULT_ISO_STEP};
use crate::drawing::Drawing;
use crate::figure::colour_map;
use crate::figure::glyphs;
use crate::figure::strokes::{self, paint, stroke, Line, COLOUR_BAR_LINE};
use crate::mesh::TriMesh;
use colour_map::{luma, weight_colour, OUT_OF_RANGE_FULL};

/// Opacity of iso-lines drawn dark (over light colours).
pub(super) const ISO_DARK_ALPHA: f64 = 0.55;
/// Opacity of iso-lines drawn light (over dark colours).
pub(super) const ISO_LIGHT_ALPHA: f64 = 0.7;
/// Luma above which a colour counts as light (iso-lines over it are dark).
pub(super) const LIGHT_LUMA: f64 = 0.45;
/// Nominal iso-line width, pixels.
pub(super) const ISO_LINE_WIDTH: f64 = 1.0;

/// Colours the panel pixmap from the samples of panel `s`, with iso-lines every `iso_step`.
pub(super) fn fill_panel(
    panel: &mut Pixmap,
    samples: &[f64],
    s: usize,
    n_shown: usize,
    iso_step: Option<f64>,
    layout: &WeightMapLayout,
) {
    let (pw, ph) = (layout.panel_width as usize, layout.panel_height as usize);
    let value = |x: usize, y: usize| samples[(y * pw + x) * n_shown + s];
    let half_width = 0.5 * ISO_LINE_WIDTH * layout.line_scale;
    let data = panel.data_mut();
    for y in 0..ph {
        for x in 0..pw {
            let w = value(x, y);
            let mut colour = weight_colour(w);
            if let Some(step) = iso_step {
                let derivative = |a: f64, b: f64, spacing: f64| (b - a) / spacing;
                let gx = match (x > 0, x + 1 < pw) {
                    (true, true) => derivative(value(x - 1, y), value(x + 1, y), 2.0),
                    (false, true) => derivative(w, value(x + 1, y), 1.0),
                    (true, false) => derivative(value(x - 1, y), w, 1.0),
                    (false, false) => 0.0,
                };
                let gy = match (y > 0, y + 1 < ph) {
                    (true, true) => derivative(value(x, y - 1), value(x, y + 1), 2.0),
                    (false, true) => derivative(w, value(x, y + 1), 1.0),
                    (true, false) => derivative(value(x, y - 1), w, 1.0),
                    (false, false) => 0.0,
                };
                let coverage = iso_coverage(w, gx.hypot(gy), step, half_width);
                if coverage > 0.0 {
                    let (line, alpha) = if luma(colour) > LIGHT_LUMA {
                        ([0, 0, 0], ISO_DARK_ALPHA)
                    } else {
                        ([255, 255, 255], ISO_LIGHT_ALPHA)
                    };
                    colour = colour_map::mix(colour, line, alpha * coverage);
                }
            }
            let k = 4 * (y * pw + x);
            data[k..k + 4].copy_from_slice(&[colour[0], colour[1], colour[2], 255]);
        }
    }
}

/// How much of a pixel an iso-line covers, in `[0, 1]`: the line of half-width `half_width`
/// pixels at the multiple of `step` nearest `w` (none at 0 and 1), at estimated distance
/// `|w − level| / gradient` pixels, with a one-pixel linear fall-off.
pub(super) fn iso_coverage(w: f64, gradient: f64, step: f64, half_width: f64) -> f64 {
    let level = (w / step).round() * step;
    let at_bound = level.abs() < 1e-6 * step || (level - 1.0).abs() < 1e-6 * step;
    if at_bound || gradient <= 0.0 || !gradient.is_finite() {
        return 0.0;
    }
    let distance = (w - level).abs() / gradient;
    (half_width + 0.5 - distance).clamp(0.0, 1.0)
}

/// The drawing's curves in panel pixel coordinates, `None` if it has none.
pub(super) fn curves_path(drawing: &Drawing, layout: &WeightMapLayout) -> Option<tiny_skia::Path> {
    let mut b = PathBuilder::new();
    let px = |p: Point| {
        let q = layout.panel_pixel(p);
        (q.x as f32, q.y as f32)
    };
    for path in &drawing.paths {
        let (x, y) = px(path.points[0]);
        b.move_to(x, y);
        for j in 0..path.n_curves() {
            let [_, p1, p2, p3] = path.curve_points(j);
            let ((x1, y1), (x2, y2), (x3, y3)) = (px(p1), px(p2), px(p3));
            b.cubic_to(x1, y1, x2, y2, x3, y3);
        }
        if path.closed {
            b.close();
        }
    }
    b.finish()
}

/// Every edge of `mesh` once, and its boundary edges (those of one triangle only), in panel
/// pixel coordinates.
pub(super) fn mesh_paths(
    mesh: &TriMesh,
    layout: &WeightMapLayout,
) -> (Option<tiny_skia::Path>, Option<tiny_skia::Path>) {
    let mut half_edges: Vec<[usize; 2]> = mesh
        .triangles
        .iter()
        .flat_map(|t| [[t[0], t[1]], [t[1], t[2]], [t[2], t[0]]])
        .map(|[a, b]| [a.min(b), a.max(b)])
        .collect();
    half_edges.sort_unstable();
    let (mut all, mut boundary) = (PathBuilder::new(), PathBuilder::new());
    for run in half_edges.chunk_by(|a, b| a == b) {
        let [a, c] = run[0];
        let (p, q) = (
            layout.panel_pixel(mesh.vertices[a]),
            layout.panel_pixel(mesh.vertices[c]),
        );
        let (p, q) = ((p.x as f32, p.y as f32), (q.x as f32, q.y as f32));
        all.move_to(p.0, p.1);
        all.line_to(q.0, q.1);
        if run.len() == 1 {
            boundary.move_to(p.0, p.1);
            boundary.line_to(q.0, q.1);
        }
    }
    (all.finish(), boundary.finish())
}

/// Mesh edges: faint white, thinner than a pixel, so that a dense mesh tints rather than
/// hides the colours.
pub(super) const MESH_EDGE: Line = Line {
    rgba: [255, 255, 255, 90],
    width: 0.6,
};
/// The mesh's boundary, dashed ([`DASH`]): where the weights stop being interpolated.
pub(super) const DOMAIN_BOUNDARY: Line = Line {
    rgba: [255, 255, 255, 200],
    width: 1.0,
};
/// Dash of [`DOMAIN_BOUNDARY`]: on, off, in line widths.
pub(super) const DASH: [f64; 2] = [5.0, 4.0];
/// A light halo under the curves, so that dark curves read over dark colours.
pub(super) const CURVE_HALO: Line = Line {
    rgba: [255, 255, 255, 150],
    width: 3.0,
};
/// The curves: thin, near black.
pub(super) const CURVE: Line = Line {
    rgba: [20, 20, 20, 255],
    width: 1.3,
};
/// The panel's own handle: a black ring over a white one (readable on every colour).
pub(super) const OWN_HANDLE: [Line; 2] = [
    Line {
        rgba: [255, 255, 255, 230],
        width: 3.5,
    },
    Line {
        rgba: [0, 0, 0, 255],
        width: 1.6,
    },
];
/// The other handles: thinner rings.
pub(super) const OTHER_HANDLE: [Line; 2] = [
    Line {
        rgba: [255, 255, 255, 230],
        width: 2.5,
    },
    Line {
        rgba: [0, 0, 0, 255],
        width: 1.0,
    },
];
/// Bones are drawn this many times wider than rings, to read as segments rather than lines of
/// the drawing.
pub(super) const BONE_WIDEN: f64 = 1.5;
/// Frame around each panel (not scaled).
pub(super) const PANEL_BORDER: Line = Line {
    rgba: [120, 120, 120, 255],
    width: 1.0,
};
/// A panel's label.
pub(super) const LABEL_TEXT: [u8; 4] = [0, 0, 0, 255];
/// The colour bar's tick values.
pub(super) const TICK_TEXT: [u8; 4] = [40, 40, 40, 255];

/// Strokes `path` dashed by [`DASH`].
pub(super) fn dashed(pixmap: &mut Pixmap, path: &tiny_skia::Path, line: Line, scale: f64) {
    strokes::dashed(pixmap, path, line, scale, DASH);
}

/// Nominal ring radius of the panel's own handle, pixels.
pub(super) const OWN_RING_RADIUS: f64 = 8.0;
/// Nominal ring radius of the other handles, pixels.
pub(super) const OTHER_RING_RADIUS: f64 = 4.5;

/// A handle, white under black so that it reads on every colour: a ring around a point (the
/// centre stays clear), the segment of a bone. The panel's own handle is drawn larger.
pub(super) fn handle_marker(
    pixmap: &mut Pixmap,
    marker: &HandleMarker,
    own: bool,
    layout: &WeightMapLayout,
) {
    let to_panel = |p: Point| layout.panel_pixel(p);
    draw_handle_marker(pixmap, marker, own, &to_panel, layout.line_scale);
}

/// [`handle_marker`] with drawing points placed by `to_panel` (drawing → panel pixels) and
/// lines scaled by `line_scale`: shared with [`crate::compare`].
pub(crate) fn draw_handle_marker(
    pixmap: &mut Pixmap,
    marker: &HandleMarker,
    own: bool,
    to_panel: &dyn Fn(Point) -> Point,
    line_scale: f64,
) {
    let (radius, lines) = if own {
        (OWN_RING_RADIUS, OWN_HANDLE)
    } else {
        (OTHER_RING_RADIUS, OTHER_HANDLE)
    };
    let path = match *marker {
        HandleMarker::Point(p) => {
            let at = to_panel(p);
            let radius = radius * line_scale;
            PathBuilder::from_circle(at.x as f32, at.y as f32, radius as f32)
        }
        HandleMarker::Segment([a, b]) => {
            let (a, b) = (to_panel(a), to_panel(b));
            let mut builder = PathBuilder::new();
            builder.move_to(a.x as f32, a.y as f32);
            builder.line_to(b.x as f32, b.y as f32);
            builder.finish()
        }
    };
    let Some(path) = path else {
        return;
    };
    let widen = match marker {
        HandleMarker::Point(_) => 1.0,
        HandleMarker::Segment(_) => BONE_WIDEN,
    };
    for line in lines {
        stroke(pixmap, &path, line, widen * line_scale);
    }
}

/// The handle index in the strip above the panel, left-aligned, black.
pub(super) fn panel_label(image: &mut Pixmap, text: &str, panel: &Panel, layout: &WeightMapLayout) {
    let s = layout.glyph_scale + 1;
    let top = f64::from(panel.y) - f64::from(layout.label_height);
    glyphs::draw_text(image, text, f64::from(panel.x), top, s, &paint(LABEL_TEXT));
}

/// A one-pixel grey frame just outside the panel.
pub(super) fn panel_border(image: &mut Pixmap, panel: &Panel, layout: &WeightMapLayout) {
    let size = (layout.panel_width, layout.panel_height);
    strokes::frame(image, (panel.x, panel.y), size, PANEL_BORDER);
}

/// The colour bar: viridis from 0 to 1, the out-of-range ramps at its ends when such values
/// occur (`below`, `above`), ticks at 0, ½ and 1 (and at the ramps' deep ends) with their
/// values, minor ticks at the iso-line step (0.1 without iso-lines).
pub(super) fn colour_bar(
    image: &mut Pixmap,
    layout: &WeightMapLayout,
    below: bool,
    above: bool,
    iso: Option<f64>,
) {
    let bar = layout.colour_bar;
    let ext = layout.bar_extension;
    let x_start = if below { bar.x0 - ext } else { bar.x0 };
    let x_end = if above { bar.x1 + ext } else { bar.x1 };
    let value_at = |x: f64| {
        if x < bar.x0 {
            -OUT_OF_RANGE_FULL * (bar.x0 - x) / ext
        } else if x > bar.x1 {
            1.0 + OUT_OF_RANGE_FULL * (x - bar.x1) / ext
        } else {
            (x - bar.x0) / bar.width()
        }
    };
    strokes::fill_columns(image, (x_start, x_end), (bar.y0, bar.y1), |x| {
        weight_colour(value_at(x))
    });
    let ls = layout.line_scale;
    strokes::outline(image, (x_start, x_end), (bar.y0, bar.y1), COLOUR_BAR_LINE);
    let pixel_of = |w: f64| {
        if w < 0.0 {
            bar.x0 + w / OUT_OF_RANGE_FULL * ext
        } else if w > 1.0 {
            bar.x1 + (w - 1.0) / OUT_OF_RANGE_FULL * ext
        } else {
            bar.x0 + w * bar.width()
        }
    };
    // The middle of the pixel column holding `w`: a 1 px line covers it exactly.
    let tick = |image: &mut Pixmap, w: f64, length: f64| {
        strokes::tick(
            image,
            (pixel_of(w).floor() + 0.5, bar.y1),
            length,
            COLOUR_BAR_LINE,
        );
    };
    let minor = iso.unwrap_or(DEFAULT_ISO_STEP);
    let n_minor = (1.0 / minor).floor() as usize;
    for k in 1..n_minor {
        tick(image, k as f64 * minor, 0.5 * layout::TICK_LENGTH * ls);
    }
    let mut labelled = vec![0.0, 0.5, 1.0];
    if below {
        labelled.push(-OUT_OF_RANGE_FULL);
    }
    if above {
        labelled.push(1.0 + OUT_OF_RANGE_FULL);
    }
    let s = layout.glyph_scale;
    let text_top = bar.y1 + (layout::TICK_LENGTH * ls).round() + f64::from(s) * 2.0;
    for w in labelled {
        tick(image, w, layout::TICK_LENGTH * ls);
        let text = format!("{w}");
        let x = pixel_of(w) - f64::from(glyphs::text_width(&text, s)) / 2.0;
        glyphs::draw_text(image, &text, x.round(), text_top, s, &paint(TICK_TEXT));
    }
}
