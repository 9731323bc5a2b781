//! The comparison as a PNG: one panel per method, all showing the same frame of drawing space.
//!
//! ```text
//!  OURS                          FOURCONTROLS                  label: method,
//!  MAX 0.12%  RMS 0.03%  38 C    MAX 1.9%  RMS 0.6%  38 C       max, RMS, curves
//! ┌───────────────────────┐    ┌───────────────────────┐
//! │  ─ ─ ─ target s(t), dashed, coloured by distance     │    result: solid grey,
//! │  ─── result, • its curve ends, ○ posed handles       │    on-curve points as dots
//! └───────────────────────┘    └───────────────────────┘
//!   DISTANCE TO TARGET (% OF DIAGONAL)  ▕▒▒▒▒▒▒▒▒▒▒▒▒▏      0 … the largest over all panels
//! ```
//!
//! Each dash of the target is coloured ([`error_colour`]) by the distance from the target to
//! the result at the dash's middle ([`crate::compare::MethodResult::distances`], interpolated between
//! samples), divided by the largest distance over **all** panels (the paper's figure
//! convention: the same colour is the same error in every panel), or by [`ERROR_FLOOR`] times
//! the diagonal if that is larger (rounding is not an error). The colour bar's ticks give the
//! distances as a percentage of the diagonal.

use kurbo::{ParamCurveExtrema, Point, Rect};
use resvg::tiny_skia::{
    self, LineCap, LineJoin, PathBuilder, Pixmap, PixmapPaint, Stroke, Transform,
};

use super::colour_map::error_colour;
use super::glyphs;
use super::grid::GridError;
use super::grid::{PanelGrid, TICK_LENGTH};
use super::pixmap::{encode_png, new_pixmap, PixmapError};
use super::strokes::{self, paint, stroke, Line, COLOUR_BAR_LINE};
use super::weight_map::{draw_handle_marker, HandleMarker};
use crate::compare::methods::{Comparison, Method, MethodResult};
use crate::naive::Refit;

/// Default panel width: 420 pixels (six panels fit a 1300-pixel-wide picture in three columns).
pub const DEFAULT_COMPARE_PANEL_WIDTH: u32 = 420;

/// Distances below this fraction of the diagonal are drawn in the colour of 0 even when they
/// are the largest: 1e-9 (rounding of `Σ_i w_i T_i x` on drawing coordinates is ~1e-13 of the
/// diagonal; an error worth seeing is many orders above).
pub const ERROR_FLOOR: f64 = 1e-9;

/// Why a comparison cannot be drawn.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ComparePictureError {
    /// The picture cannot be laid out.
    #[error("picture: {0}")]
    Grid(#[from] GridError),
    /// The pixmap cannot be allocated or encoded.
    #[error("picture: {0}")]
    Pixmap(#[from] PixmapError),
}

/// Options of [`render_comparison`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct PictureOptions {
    /// Width of each panel in pixels. Default: [`DEFAULT_COMPARE_PANEL_WIDTH`].
    pub panel_width: u32,
}

impl Default for PictureOptions {
    fn default() -> Self {
        PictureOptions {
            panel_width: DEFAULT_COMPARE_PANEL_WIDTH,
        }
    }
}

impl PictureOptions {
    /// Sets [`PictureOptions::panel_width`].
    pub fn with_panel_width(mut self, pixels: u32) -> Self {
        self.panel_width = pixels;
        self
    }

    /// Checks the options before any work (the panel width's range, as
    /// [`render_comparison`] would), so that a command can refuse them before computing the
    /// comparison. `n_methods` panels of a square drawing are laid out.
    ///
    /// ```
    /// use splineskin::figure::comparison::PictureOptions;
    /// assert!(PictureOptions::default().check(6).is_ok());
    /// assert!(PictureOptions::default().with_panel_width(0).check(6).is_err());
    /// ```
    pub fn check(&self, n_methods: usize) -> Result<(), ComparePictureError> {
        PanelGrid::new(
            Rect::new(0.0, 0.0, 1.0, 1.0),
            n_methods.max(1),
            self.panel_width,
            LABEL_LINES,
        )?;
        Ok(())
    }
}

/// A rendered comparison.
#[derive(Clone, Debug)]
pub struct ComparePicture {
    /// The image, 8-bit RGBA PNG.
    pub png: Vec<u8>,
    /// Where everything is: panel `k` shows [`Comparison::methods`]`[k]`.
    pub grid: PanelGrid,
    /// The distance drawn in the colour of 1 (drawing units): the largest over all panels, at
    /// least [`ERROR_FLOOR`] times the diagonal.
    pub error_scale: f64,
}

/// The result's curves: solid, mid-dark grey, under the target.
const RESULT: Line = Line {
    rgba: [85, 85, 85, 255],
    width: 1.6,
};
/// The result's on-curve points (its curves' ends): small grey dots, nominal radius in pixels.
const KNOT_RADIUS: f64 = 2.2;
/// Colour of the on-curve dots.
const KNOT: [u8; 4] = [60, 60, 60, 255];
/// Nominal width of the target's dashes, pixels.
const TARGET_WIDTH: f64 = 2.8;
/// The target's dash: on, off, in dash widths.
const TARGET_DASH: [f64; 2] = [2.4, 1.4];
/// Frame around each panel (not scaled).
const PANEL_BORDER: Line = Line {
    rgba: [150, 150, 150, 255],
    width: 1.0,
};
/// Method names.
const TITLE_TEXT: [u8; 4] = [0, 0, 0, 255];
/// Figures under the method name, and the colour bar's text.
const FIGURE_TEXT: [u8; 4] = [70, 70, 70, 255];

/// Draws `comparison` as a PNG: one panel per method (same frame, laid out by
/// [`PanelGrid::new`] with two label lines), each showing the result (grey, with dots at its
/// on-curve points), the target dashed and coloured by the distance to the result (module doc)
/// and `handles` (the posed handles, drawn as rings and segments); the method's name, max and
/// RMS distance (% of the diagonal) and curve count above it; the colour bar below.
///
/// Errors: the grid's ([`ComparePictureError::Grid`]), allocation or encoding failures
/// ([`ComparePictureError::Pixmap`]).
///
/// ```
/// use kurbo::{Affine, Point};
/// use splineskin::compare::{compare_methods, CompareInputs, CompareOptions};
/// use splineskin::figure::comparison::{render_comparison, PictureOptions};
/// use splineskin::drawing::{read_svg, ImportOptions};
/// use splineskin::weight_map::{HandleMarker, RgbaImage};
/// use splineskin::weights::{Shepard, ShepardOptions};
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg"><path d="M0 0 C30 40 70 40 100 0"/></svg>"#;
/// let drawing = read_svg(svg, &ImportOptions::default())?;
/// let handles = [Point::new(0.0, 0.0), Point::new(100.0, 0.0)];
/// let weights = Shepard::new(&handles, ShepardOptions::default());
/// let pose = [Affine::IDENTITY, Affine::translate((0.0, 20.0))];
/// let inputs = CompareInputs {
///     drawing: &drawing, weights: &weights, gradient: &weights,
///     fit: Default::default(), flexible: None, pose: &pose,
/// };
/// let c = compare_methods(&inputs, &CompareOptions::default())?;
/// let markers: Vec<HandleMarker> = handles.iter().zip(&pose).map(|(&p, t)| HandleMarker::Point(*t * p)).collect();
/// let picture = render_comparison(&c, &markers, &PictureOptions::default().with_panel_width(200))?;
/// let image = RgbaImage::decode_png(&picture.png)?;
/// assert_eq!((image.width, image.height), (picture.grid.width, picture.grid.height));
/// assert_eq!(picture.grid.corners.len(), c.methods.len());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn render_comparison(
    comparison: &Comparison,
    handles: &[HandleMarker],
    options: &PictureOptions,
) -> Result<ComparePicture, ComparePictureError> {
    let content = content_bounds(comparison, handles);
    let grid = PanelGrid::new(
        content,
        comparison.methods.len(),
        options.panel_width,
        LABEL_LINES,
    )?;
    let error_scale = comparison
        .largest_distance()
        .max(ERROR_FLOOR * comparison.diagonal)
        .max(f64::MIN_POSITIVE);
    let (pw, ph) = (grid.panel_width, grid.panel_height);
    let mut image = new_pixmap(grid.width, grid.height)?;
    image.fill(tiny_skia::Color::WHITE);
    let mut panel = new_pixmap(pw, ph)?;
    let to_panel = |p: Point| grid.panel_pixel(p);
    let text_scale = label_scale(comparison, &grid);
    for (m, &(x, y)) in comparison.methods.iter().zip(&grid.corners) {
        panel.fill(tiny_skia::Color::WHITE);
        if let Some(path) = chains_path(&m.result, &to_panel) {
            stroke(&mut panel, &path, RESULT, grid.line_scale);
        }
        draw_target(&mut panel, comparison, m, error_scale, &grid);
        draw_knots(&mut panel, &m.result, &grid);
        for h in handles {
            draw_handle_marker(&mut panel, h, true, &to_panel, grid.line_scale);
        }
        image.draw_pixmap(
            x as i32,
            y as i32,
            panel.as_ref(),
            &PixmapPaint::default(),
            Transform::identity(),
            None,
        );
        strokes::frame(&mut image, (x, y), (pw, ph), PANEL_BORDER);
        draw_label(
            &mut image,
            &label_lines(comparison, m),
            (x, y),
            text_scale,
            &grid,
        );
    }
    colour_bar(
        &mut image,
        &grid,
        error_scale / comparison.diagonal.max(f64::MIN_POSITIVE),
    );
    let png = encode_png(&image)?;
    Ok(ComparePicture {
        png,
        grid,
        error_scale,
    })
}

/// Lines of label above each panel: the method, then its figures.
const LABEL_LINES: u32 = 2;

/// Bounds of every result's curves, the target samples and the handles.
fn content_bounds(comparison: &Comparison, handles: &[HandleMarker]) -> Rect {
    let mut bounds: Option<Rect> = None;
    let mut add = |r: Rect| {
        bounds = Some(bounds.map_or(r, |b| b.union(r)));
    };
    for m in &comparison.methods {
        for path in &m.result.paths {
            for j in 0..path.n_curves() {
                add(path.curve(j).bounding_box());
            }
        }
    }
    for &p in &comparison.target {
        add(Rect::from_points(p, p));
    }
    for h in handles {
        for &p in h.points() {
            add(Rect::from_points(p, p));
        }
    }
    bounds.unwrap_or(Rect::ZERO)
}

/// The chains as one tiny-skia path in panel pixels; `None` if empty.
fn chains_path(result: &Refit, to_panel: &dyn Fn(Point) -> Point) -> Option<tiny_skia::Path> {
    let mut b = PathBuilder::new();
    let px = |p: Point| {
        let q = to_panel(p);
        (q.x as f32, q.y as f32)
    };
    for path in &result.paths {
        let Some(&first) = path.points.first() else {
            continue;
        };
        let (x, y) = px(first);
        b.move_to(x, y);
        for c in path.points[1..].chunks_exact(3) {
            let ((x1, y1), (x2, y2), (x3, y3)) = (px(c[0]), px(c[1]), px(c[2]));
            b.cubic_to(x1, y1, x2, y2, x3, y3);
        }
        if path.closed {
            b.close();
        }
    }
    b.finish()
}

/// Dots at the result's on-curve points (one per curve end).
fn draw_knots(panel: &mut Pixmap, result: &Refit, grid: &PanelGrid) {
    let radius = (KNOT_RADIUS * grid.line_scale) as f32;
    let mut b = PathBuilder::new();
    for path in &result.paths {
        for p in path.points.iter().step_by(3) {
            let q = grid.panel_pixel(*p);
            b.push_circle(q.x as f32, q.y as f32, radius);
        }
    }
    if let Some(path) = b.finish() {
        panel.fill_path(
            &path,
            &paint(KNOT),
            tiny_skia::FillRule::Winding,
            Transform::identity(),
            None,
        );
    }
}

/// The target, path by path, as a dashed polyline through its samples (the dash pattern runs
/// on across curves), each dash coloured by the normalised distance at its middle.
fn draw_target(
    panel: &mut Pixmap,
    comparison: &Comparison,
    m: &MethodResult,
    error_scale: f64,
    grid: &PanelGrid,
) {
    let width = TARGET_WIDTH * grid.line_scale;
    let (on, off) = (TARGET_DASH[0] * width, TARGET_DASH[1] * width);
    let s = comparison.samples_per_curve;
    let style = Stroke {
        width: width as f32,
        line_cap: LineCap::Butt,
        line_join: LineJoin::Round,
        ..Stroke::default()
    };
    let mut first = 0;
    for &n_curves in &comparison.path_curves {
        // The path's samples, without the repeated end of one curve and start of the next.
        let mut points: Vec<(Point, f64)> = Vec::with_capacity(n_curves * (s - 1) + 1);
        for j in 0..n_curves {
            let range = (first + j) * s..(first + j + 1) * s;
            let skip = usize::from(j > 0);
            for k in range.skip(skip) {
                points.push((grid.panel_pixel(comparison.target[k]), m.distances[k]));
            }
        }
        first += n_curves;
        for (dash, errors) in dashes(&points, on, off) {
            if dash.len() < 2 {
                continue;
            }
            let e = errors[errors.len() / 2] / error_scale;
            let [r, g, b] = error_colour(e);
            let mut pb = PathBuilder::new();
            pb.move_to(dash[0].x as f32, dash[0].y as f32);
            for p in &dash[1..] {
                pb.line_to(p.x as f32, p.y as f32);
            }
            if let Some(path) = pb.finish() {
                panel.stroke_path(
                    &path,
                    &paint([r, g, b, 255]),
                    &style,
                    Transform::identity(),
                    None,
                );
            }
        }
    }
}

/// The dashes of the polyline `points` (each with the error at it) for a pattern of `on`
/// drawn and `off` skipped (arc length, starting with a dash): each dash as its polyline and
/// the errors interpolated along it. Every pass of the walk reaches either the end of a
/// segment or the next boundary of the pattern, with the state changes made explicitly, so
/// rounding (a position far from the origin plus a remainder below its ulp) cannot stall it.
fn dashes(points: &[(Point, f64)], on: f64, off: f64) -> Vec<(Vec<Point>, Vec<f64>)> {
    let mut out = Vec::new();
    if !(on > 0.0 && off >= 0.0) {
        return out;
    }
    // `phase`: the arc length into the current on + off period.
    let mut phase = 0.0;
    let mut dash: Vec<Point> = Vec::new();
    let mut errors: Vec<f64> = Vec::new();
    for pair in points.windows(2) {
        let ((a, ea), (b, eb)) = (pair[0], pair[1]);
        let length = (b - a).hypot();
        let at = |u: f64| {
            let f = if length > 0.0 { u / length } else { 0.0 };
            (a.lerp(b, f), ea + f * (eb - ea))
        };
        let mut u = 0.0;
        while u < length {
            let in_dash = phase < on;
            let to_boundary = if in_dash { on } else { on + off } - phase;
            let rest = length - u;
            let end = if to_boundary >= rest {
                length
            } else {
                u + to_boundary
            };
            if in_dash {
                if dash.is_empty() {
                    let (p, e) = at(u);
                    dash.push(p);
                    errors.push(e);
                }
                let (p, e) = at(end);
                dash.push(p);
                errors.push(e);
            }
            if to_boundary > rest {
                phase += rest;
            } else if in_dash {
                phase = on;
                out.push((std::mem::take(&mut dash), std::mem::take(&mut errors)));
            } else {
                phase = 0.0;
            }
            u = end;
        }
    }
    if dash.len() >= 2 {
        out.push((dash, errors));
    }
    out
}

/// The two label lines of a panel: the method's name, then its figures.
fn label_lines(comparison: &Comparison, m: &MethodResult) -> [String; 2] {
    let title = match m.method {
        Method::Ours => "ours (fixed ratio)".to_string(),
        Method::OursFlexible => "ours (flexible)".to_string(),
        Method::Schneider => format!(
            "schneider refit (tol {}%)",
            percent(comparison.refit_tolerance / comparison.diagonal.max(f64::MIN_POSITIVE))
        ),
        Method::SchneiderSameCount => "schneider refit (input curve count)".to_string(),
        other => other.name().to_string(),
    };
    let o = m.metrics.overall;
    let figures = format!(
        "max {}%  rms {}%  {} curves",
        percent(o.max),
        percent(o.rms),
        m.result.n_curves()
    );
    [title, figures]
}

/// The labels' font pixel: one step larger than the colour bar's, smaller if some panel's
/// label line would not fit the panel's width (the same in every panel).
fn label_scale(comparison: &Comparison, grid: &PanelGrid) -> u32 {
    let longest = comparison
        .methods
        .iter()
        .flat_map(|m| label_lines(comparison, m))
        .map(|t| glyphs::text_width(&t, 1))
        .max()
        .unwrap_or(0)
        .max(1);
    (grid.glyph_scale + 1)
        .min(grid.panel_width / longest)
        .max(1)
}

/// The method's name, and its figures, in the strip above its panel, font pixel `s`.
fn draw_label(
    image: &mut Pixmap,
    lines: &[String; 2],
    (x, y): (u32, u32),
    s: u32,
    grid: &PanelGrid,
) {
    let top = f64::from(y) - f64::from(grid.label_height);
    glyphs::draw_text(image, &lines[0], f64::from(x), top, s, &paint(TITLE_TEXT));
    let line = f64::from(grid.label_line_height);
    glyphs::draw_text(
        image,
        &lines[1],
        f64::from(x),
        top + line,
        s,
        &paint(FIGURE_TEXT),
    );
}

/// `fraction` as a percentage with 2 significant digits (at least one decimal), e.g. `1.2`,
/// `0.034`, `12`; `0` for 0.
fn percent(fraction: f64) -> String {
    let p = 100.0 * fraction;
    if p == 0.0 || !p.is_finite() {
        return "0".into();
    }
    let decimals = (1 - p.abs().log10().floor() as i32).clamp(0, 12) as usize;
    format!("{p:.decimals$}")
}

/// The colour bar: the error ramp from 0 to 1, ticks at 0, ½ and 1 labelled with the distance
/// as a percentage of the diagonal (`top` is the fraction of the diagonal at 1), and its title
/// to the left.
fn colour_bar(image: &mut Pixmap, grid: &PanelGrid, top: f64) {
    let bar = grid.colour_bar;
    strokes::fill_columns(image, (bar.x0, bar.x1), (bar.y0, bar.y1), |x| {
        error_colour((x - bar.x0) / bar.width())
    });
    strokes::outline(image, (bar.x0, bar.x1), (bar.y0, bar.y1), COLOUR_BAR_LINE);
    let ls = grid.line_scale;
    let s = grid.glyph_scale;
    let text_top = bar.y1 + (TICK_LENGTH * ls).round() + f64::from(s) * 2.0;
    for v in [0.0, 0.5, 1.0] {
        let x = (bar.x0 + v * bar.width()).floor().min(bar.x1 - 1.0) + 0.5;
        strokes::tick(image, (x, bar.y1), TICK_LENGTH * ls, COLOUR_BAR_LINE);
        let text = format!("{}%", percent(v * top));
        let tx = x - f64::from(glyphs::text_width(&text, s)) / 2.0;
        glyphs::draw_text(image, &text, tx.round(), text_top, s, &paint(FIGURE_TEXT));
    }
    let title = "distance to target s(t)";
    let tx = bar.x0 - f64::from(grid.gutter) - f64::from(glyphs::text_width(title, s));
    let ty = bar.y0 + (bar.height() - f64::from(glyphs::GLYPH_HEIGHT * s)) / 2.0;
    glyphs::draw_text(
        image,
        title,
        tx.round().max(0.0),
        ty.round(),
        s,
        &paint(FIGURE_TEXT),
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Total arc length of polylines.
    fn drawn(dashes: &[(Vec<Point>, Vec<f64>)]) -> f64 {
        dashes
            .iter()
            .flat_map(|(d, _)| d.windows(2).map(|w| (w[1] - w[0]).hypot()))
            .sum()
    }

    #[test]
    fn dashes_follow_the_pattern_exactly() {
        // A straight line of length 100 in 7 uneven segments, pattern 4 on, 2 off: dashes
        // [0,4], [6,10], …, [96,100]; the errors interpolate linearly (error = x here).
        let xs = [0.0, 3.0, 4.0, 10.0, 33.3, 50.0, 77.7, 100.0];
        let points: Vec<(Point, f64)> = xs.iter().map(|&x| (Point::new(x, 0.0), x)).collect();
        let d = dashes(&points, 4.0, 2.0);
        assert_eq!(d.len(), 17);
        for (k, (dash, errors)) in d.iter().enumerate() {
            let (x0, x1) = (6.0 * k as f64, (6.0 * k as f64 + 4.0).min(100.0));
            assert!(
                (dash[0].x - x0).abs() < 1e-12,
                "dash {k} starts at {}",
                dash[0].x
            );
            assert!((dash.last().unwrap().x - x1).abs() < 1e-12, "dash {k}");
            for (p, e) in dash.iter().zip(errors) {
                assert!((p.x - e).abs() < 1e-12);
            }
        }
        assert!((drawn(&d) - (16.0 * 4.0 + 4.0)).abs() < 1e-9);
    }

    #[test]
    fn dashes_terminate_far_from_the_origin() {
        // Thousands of short segments at coordinates around 1e6, where a remainder of the
        // pattern can be below the ulp of the position (the walk used to stall there).
        let points: Vec<(Point, f64)> = (0..20_000)
            .map(|k| {
                let t = k as f64 * 0.013_7;
                (Point::new(1e6 + t, 1e6 - 0.3 * t), 0.0)
            })
            .collect();
        let total: f64 = points.windows(2).map(|w| (w[1].0 - w[0].0).hypot()).sum();
        let d = dashes(&points, 1.1, 0.7);
        // About on / (on + off) of the length is drawn.
        let share = drawn(&d) / total;
        assert!((share - 1.1 / 1.8).abs() < 0.01, "{share}");
        // Degenerate patterns draw nothing rather than loop.
        assert!(dashes(&points, 0.0, 1.0).is_empty());
        assert!(dashes(&points, f64::NAN, 1.0).is_empty());
    }

    #[test]
    fn percent_has_two_significant_digits() {
        assert_eq!(percent(0.0123), "1.2");
        assert_eq!(percent(0.000346), "0.035");
        assert_eq!(percent(0.123), "12");
        assert_eq!(percent(0.0), "0");
        assert_eq!(percent(1e-11), "0.0000000010");
    }
}
