//! The comparison picture (Liu et al. 2014, Fig. 8): the limit surface of our fitted cage and
//! that of the naive skinned cage side by side, seen by one camera, each coloured by its
//! distance to the skinned surface on one common scale ([`error_colour`]: plasma from 0 to the
//! larger of the two maxima), with `max` and `rms` written above and a colour bar below.
//! Rendered by [`super::surface_raster`]: no GPU, no dependency beyond the PNG encoder.

use resvg::tiny_skia::{IntSize, Pixmap};

use super::surface_raster::{Camera, Raster};
use crate::figure::colour_map::error_colour;
use crate::figure::glyphs::{draw_text, GLYPH_HEIGHT};
use crate::figure::strokes::paint;
use splineskin_subdiv::{ComparisonSamples, SubdivCompareError, SubdivComparison};

/// Width of each panel by default, in pixels.
pub const DEFAULT_PANEL_WIDTH: u32 = 480;

/// Options of [`render_comparison_png`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct ComparisonPictureOptions {
    /// Width of each panel, pixels (64 ..= 4096). Default: [`DEFAULT_PANEL_WIDTH`].
    pub panel_width: u32,
    /// The axis drawn upwards: `Some(0 | 1 | 2)` for x, y, z, or `None` for the axis along
    /// which the rest cage is thinnest (models mostly lie on their widest side). Default:
    /// `None`.
    pub up: Option<usize>,
    /// Camera azimuth about the up axis, degrees (0 looks along the axis after it,
    /// cyclically: −z for y up). Default: 35.
    pub azimuth_degrees: f64,
    /// Camera elevation above the x–z plane, degrees. Default: 25.
    pub elevation_degrees: f64,
    /// Samples per pixel along each axis (anti-aliasing, 1 ..= 4). Default: 2.
    pub supersample: u32,
}

impl Default for ComparisonPictureOptions {
    fn default() -> Self {
        ComparisonPictureOptions {
            panel_width: DEFAULT_PANEL_WIDTH,
            up: None,
            azimuth_degrees: 35.0,
            elevation_degrees: 25.0,
            supersample: 2,
        }
    }
}

impl ComparisonPictureOptions {
    /// Sets [`ComparisonPictureOptions::panel_width`].
    pub fn with_panel_width(mut self, px: u32) -> Self {
        self.panel_width = px;
        self
    }

    /// Sets [`ComparisonPictureOptions::up`].
    pub fn with_up(mut self, up: Option<usize>) -> Self {
        self.up = up;
        self
    }

    /// Sets the camera direction (degrees).
    pub fn with_view(mut self, azimuth_degrees: f64, elevation_degrees: f64) -> Self {
        self.azimuth_degrees = azimuth_degrees;
        self.elevation_degrees = elevation_degrees;
        self
    }
}

/// Height of the label band above the panels, pixels.
const HEADER: u32 = 34;
/// Height of the colour-bar band below the panels, pixels.
const FOOTER: u32 = 44;
/// Scale of the 3 × 5 font.
const TEXT_SCALE: u32 = 3;
/// Height over width of a panel, clamped to this range whatever the shape's proportions.
const ASPECT_RANGE: (f64, f64) = (0.4, 1.25);
/// Background, 0..1 RGB.
const BACKGROUND: [f64; 3] = [1.0, 1.0, 1.0];

/// Renders `comparison` (made on `samples`) as a PNG (module documentation).
pub fn render_comparison_png(
    samples: &ComparisonSamples,
    comparison: &SubdivComparison,
    options: &ComparisonPictureOptions,
) -> Result<Vec<u8>, SubdivCompareError> {
    let bad = |what: String| SubdivCompareError::Picture { what };
    if !(64..=4096).contains(&options.panel_width) {
        return Err(bad(format!(
            "panel width {} px; expected 64 ..= 4096",
            options.panel_width
        )));
    }
    if !(1..=4).contains(&options.supersample) {
        return Err(bad(format!(
            "supersampling {}; expected 1 ..= 4",
            options.supersample
        )));
    }
    if !(options.azimuth_degrees.is_finite() && options.elevation_degrees.is_finite()) {
        return Err(bad("the view angles must be finite".into()));
    }
    let (az, el) = (
        options.azimuth_degrees.to_radians(),
        options.elevation_degrees.to_radians(),
    );
    let all: Vec<_> = comparison
        .target
        .iter()
        .chain(&comparison.ours.samples)
        .chain(&comparison.naive.samples)
        .copied()
        .collect();
    if all.iter().flatten().any(|c| !c.is_finite()) {
        return Err(bad("a deformed sample is not finite".into()));
    }
    if options.up.is_some_and(|k| k > 2) {
        return Err(bad("the up axis must be 0, 1 or 2 (x, y, z)".into()));
    }
    let up = options.up.unwrap_or_else(|| thinnest_axis(samples.rest()));
    let w = options.panel_width;
    let aspect = Camera::aspect(&all, up, az, el).clamp(ASPECT_RANGE.0, ASPECT_RANGE.1);
    let h = (f64::from(w) * aspect).round() as u32;
    let ss = options.supersample;
    let camera = Camera::fit(&all, up, az, el, w * ss, h * ss);
    let scale = comparison
        .ours
        .summary
        .max
        .max(comparison.naive.summary.max);
    let scale = if scale > 0.0 { scale } else { 1.0 };
    let mesh = samples.mesh();
    let (width, height) = (2 * w, HEADER + h + FOOTER);
    let size = IntSize::from_wh(width, height).ok_or_else(|| bad("empty picture".into()))?;
    let mut rgba = vec![255u8; width as usize * height as usize * 4];
    for (panel, result) in [&comparison.ours, &comparison.naive].iter().enumerate() {
        let triangles = mesh.triangles(&result.samples);
        let colours: Vec<[f64; 3]> = result
            .errors
            .iter()
            .map(|e| error_colour(e / scale).map(|c| f64::from(c) / 255.0))
            .collect();
        let mut raster = Raster::new(w * ss, h * ss, BACKGROUND);
        raster.draw(&camera, &result.samples, &triangles, &colours);
        let (pw, ph, pixels) = raster.to_rgba(ss);
        for y in 0..ph as usize {
            let src = &pixels[y * pw as usize * 4..][..pw as usize * 4];
            let row = (HEADER as usize + y) * width as usize + panel * w as usize;
            rgba[row * 4..][..src.len()].copy_from_slice(src);
        }
    }
    let mut pixmap =
        Pixmap::from_vec(rgba, size).ok_or_else(|| bad("cannot make the pixmap".into()))?;
    let ink = paint([30, 30, 30, 255]);
    let percent = |x: f64| format_percent(100.0 * x);
    for (panel, (name, result)) in [("OURS", &comparison.ours), ("NAIVE", &comparison.naive)]
        .iter()
        .enumerate()
    {
        let text = format!(
            "{name}  MAX {}  RMS {}",
            percent(result.summary.max),
            percent(result.summary.rms)
        );
        let x = f64::from(panel as u32 * w) + 12.0;
        draw_text(&mut pixmap, &text, x, 10.0, TEXT_SCALE, &ink);
    }
    // The colour bar: the plasma ramp from 0 to the scale.
    let (bar_x0, bar_x1) = (12u32, width.saturating_sub(12));
    let bar_y = HEADER + h + 6;
    let bar_h = 12u32;
    for x in bar_x0..bar_x1 {
        let t = f64::from(x - bar_x0) / f64::from((bar_x1 - bar_x0).max(1));
        let [r, g, b] = error_colour(t);
        let p = paint([r, g, b, 255]);
        if let Some(rect) =
            resvg::tiny_skia::Rect::from_xywh(x as f32, bar_y as f32, 1.0, bar_h as f32)
        {
            pixmap.fill_rect(rect, &p, resvg::tiny_skia::Transform::identity(), None);
        }
    }
    let label_y = f64::from(bar_y + bar_h + 4);
    draw_text(
        &mut pixmap,
        "0",
        f64::from(bar_x0),
        label_y,
        TEXT_SCALE,
        &ink,
    );
    let top = format!("{} OF THE DIAGONAL", percent(scale));
    let tw = crate::figure::glyphs::text_width(&top, TEXT_SCALE);
    draw_text(
        &mut pixmap,
        &top,
        f64::from(bar_x1.saturating_sub(tw)),
        label_y,
        TEXT_SCALE,
        &ink,
    );
    debug_assert!(label_y as u32 + GLYPH_HEIGHT * TEXT_SCALE <= height);
    pixmap
        .encode_png()
        .map_err(|e| bad(format!("PNG encoding failed: {e}")))
}

/// The axis along which `points` extend least.
fn thinnest_axis(points: &[splineskin_subdiv::Point3]) -> usize {
    let extent = |k: usize| {
        let (lo, hi) = points
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p[k]), hi.max(p[k]))
            });
        hi - lo
    };
    (0..3)
        .min_by(|&a, &b| extent(a).total_cmp(&extent(b)))
        .unwrap_or(1)
}

/// A percentage with three significant digits (`0.0123%`, `1.23%`, `12.3%`), or `0%`.
fn format_percent(p: f64) -> String {
    if p == 0.0 {
        return "0%".into();
    }
    let digits = (2 - p.abs().log10().floor() as i32).clamp(0, 12) as usize;
    format!("{p:.digits$}%")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comparison_picture_percentages() {
        assert_eq!(format_percent(0.0), "0%");
        assert_eq!(format_percent(1.2345), "1.23%");
        assert_eq!(format_percent(12.345), "12.3%");
        assert_eq!(format_percent(0.012345), "0.0123%");
        assert_eq!(format_percent(123.4), "123%");
    }
}
