//! The deformation-operator convergence study as a plot (Poranne & Lipman 2016, Fig. 8):
//! training samples against held-out error, both logarithmic, one line per handle basis
//! ([`splineskin_defop::study`] computes the rows).

use resvg::tiny_skia::{self, Pixmap};
use splineskin_defop::{DefOpError, HandleBasisKind, Study, StudyRow, STUDY_BASES};

use super::glyphs;
use super::strokes::{paint, stroke, Line};

/// Plot size in pixels.
const PLOT_SIZE: (u32, u32) = (960, 640);
/// Plot margins in pixels: left, right, top, bottom.
const MARGINS: (f64, f64, f64, f64) = (110.0, 40.0, 70.0, 80.0);
/// Label glyph scale (font pixels to image pixels).
const LABEL_SCALE: u32 = 2;
/// Title glyph scale.
const TITLE_SCALE: u32 = 3;
const AXIS: Line = Line {
    rgba: [40, 40, 40, 255],
    width: 1.5,
};
const GRID: Line = Line {
    rgba: [0, 0, 0, 28],
    width: 1.0,
};
const TEXT: [u8; 4] = [70, 70, 70, 255];
const TITLE_TEXT: [u8; 4] = [0, 0, 0, 255];
/// Line colours of the bases, in [`STUDY_BASES`] order (colour-blind-safe Okabe–Ito hues).
const BASIS_COLOURS: [[u8; 4]; 4] = [
    [0, 114, 178, 255],
    [230, 159, 0, 255],
    [0, 158, 115, 255],
    [213, 94, 0, 255],
];

/// Short tick text of a positive value: `0.05`, `0.002`, `1E-4`, `3E-5`.
fn tick_text(v: f64) -> String {
    if v >= 1e-3 {
        let s = format!("{v:.4}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        s.to_string()
    } else {
        let e = v.log10().floor();
        let m = (v / 10f64.powf(e)).round();
        format!("{m}E{e}")
    }
}

/// The study as a PNG plot: training samples against error, both logarithmic, one line per
/// basis with a dot per measurement, ticks at the sample counts and at 1, 2 and 5 times the
/// powers of ten, a legend, and a title naming the error's unit and `title` (e.g. the
/// shape and energy). Labels use the figures' pixel font ([`super::glyphs`]).
///
/// Errors only when a row's error is not positive and finite or the pixmap cannot be
/// allocated or encoded (as [`DefOpError::InvalidOption`] naming the row).
pub fn study_plot_png(study: &Study, title: &str) -> Result<Vec<u8>, DefOpError> {
    let bad = |detail: String| DefOpError::InvalidOption {
        name: "study plot",
        value: detail,
        expected: "positive finite errors",
    };
    if let Some(r) = study
        .rows
        .iter()
        .find(|r| !(r.error.is_finite() && r.error > 0.0))
    {
        return Err(bad(format!(
            "{} at {} samples: error {}",
            r.basis.name(),
            r.samples,
            r.error
        )));
    }
    let (w, h) = PLOT_SIZE;
    let mut image = Pixmap::new(w, h).ok_or_else(|| bad("pixmap".into()))?;
    image.fill(tiny_skia::Color::WHITE);
    let axes = Axes::of(study, w, h);
    draw_grid(&mut image, &axes, study);
    draw_titles(&mut image, &axes, title);
    // One line per basis, in the order they first appear.
    let mut bases: Vec<HandleBasisKind> = Vec::new();
    for r in &study.rows {
        if !bases.contains(&r.basis) {
            bases.push(r.basis);
        }
    }
    for &b in &bases {
        draw_series(&mut image, &axes, study, b);
    }
    draw_legend(&mut image, &axes, &bases);
    image.encode_png().map_err(|e| bad(format!("encode: {e}")))
}

/// The plot's frame in pixels and its logarithmic ranges: sample counts across, errors up.
struct Axes {
    x0: f64,
    x1: f64,
    y0: f64,
    y1: f64,
    /// log10 of the sample counts at `x0` and `x1`.
    lx0: f64,
    lx1: f64,
    /// log10 of the errors at `y1` (bottom) and `y0` (top).
    ly0: f64,
    ly1: f64,
}

impl Axes {
    /// The axes of `study` on a `w × h` image: log ranges padded by a little, the error range
    /// spanning at least a factor of 10.
    fn of(study: &Study, w: u32, h: u32) -> Axes {
        let (ml, mr, mt, mb) = MARGINS;
        let fold = |f: fn(f64, f64) -> f64, init: f64, g: fn(&StudyRow) -> f64| {
            study.rows.iter().map(g).fold(init, f)
        };
        let (s_lo, s_hi) = (
            fold(f64::min, f64::INFINITY, |r| r.samples as f64),
            fold(f64::max, 0.0, |r| r.samples as f64),
        );
        let (e_lo, e_hi) = (
            fold(f64::min, f64::INFINITY, |r| r.error),
            fold(f64::max, 0.0, |r| r.error),
        );
        let (lx0, lx1) = (s_lo.log10() - 0.05, s_hi.max(s_lo * 1.5).log10() + 0.05);
        let (mut ly0, mut ly1) = (e_lo.log10(), e_hi.log10());
        if ly1 - ly0 < 1.0 {
            let mid = 0.5 * (ly0 + ly1);
            (ly0, ly1) = (mid - 0.5, mid + 0.5);
        }
        let pad = 0.05 * (ly1 - ly0);
        Axes {
            x0: ml,
            x1: f64::from(w) - mr,
            y0: mt,
            y1: f64::from(h) - mb,
            lx0,
            lx1,
            ly0: ly0 - pad,
            ly1: ly1 + pad,
        }
    }

    /// The pixel column of `samples`.
    fn px(&self, samples: f64) -> f64 {
        self.x0 + (samples.log10() - self.lx0) / (self.lx1 - self.lx0) * (self.x1 - self.x0)
    }

    /// The pixel row of `error`.
    fn py(&self, error: f64) -> f64 {
        self.y1 - (error.log10() - self.ly0) / (self.ly1 - self.ly0) * (self.y1 - self.y0)
    }
}

/// A straight line from `a` to `b`.
fn draw_line(pixmap: &mut Pixmap, a: (f64, f64), b: (f64, f64), style: Line) {
    let mut pb = tiny_skia::PathBuilder::new();
    pb.move_to(a.0 as f32, a.1 as f32);
    pb.line_to(b.0 as f32, b.1 as f32);
    if let Some(path) = pb.finish() {
        stroke(pixmap, &path, style, 1.0);
    }
}

/// The height of a label's glyphs in pixels.
fn glyph_height() -> f64 {
    f64::from(glyphs::GLYPH_HEIGHT * LABEL_SCALE)
}

/// The grid, the ticks (errors at 1, 2, 5 × 10^k; the study's sample counts) and the axes.
fn draw_grid(image: &mut Pixmap, axes: &Axes, study: &Study) {
    let Axes { x0, x1, y0, y1, .. } = *axes;
    let text_paint = paint(TEXT);
    let s = LABEL_SCALE;
    for k in (axes.ly0.floor() as i32)..=(axes.ly1.ceil() as i32) {
        for m in [1.0, 2.0, 5.0] {
            let v = m * 10f64.powi(k);
            let l = v.log10();
            if l < axes.ly0 || l > axes.ly1 {
                continue;
            }
            let y = axes.py(v).round() + 0.5;
            draw_line(image, (x0, y), (x1, y), GRID);
            draw_line(image, (x0 - 6.0, y), (x0, y), AXIS);
            let text = tick_text(v);
            let tw = f64::from(glyphs::text_width(&text, s));
            glyphs::draw_text(
                image,
                &text,
                x0 - 10.0 - tw,
                y - glyph_height() / 2.0,
                s,
                &text_paint,
            );
        }
    }
    let mut counts: Vec<usize> = study.rows.iter().map(|r| r.samples).collect();
    counts.sort_unstable();
    counts.dedup();
    for &c in &counts {
        let x = axes.px(c as f64).round() + 0.5;
        draw_line(image, (x, y0), (x, y1), GRID);
        draw_line(image, (x, y1), (x, y1 + 6.0), AXIS);
        let text = c.to_string();
        let tw = f64::from(glyphs::text_width(&text, s));
        glyphs::draw_text(image, &text, x - tw / 2.0, y1 + 12.0, s, &text_paint);
    }
    draw_line(image, (x0, y1), (x1, y1), AXIS);
    draw_line(image, (x0, y0), (x0, y1), AXIS);
}

/// The axes' titles and the plot's `title`.
fn draw_titles(image: &mut Pixmap, axes: &Axes, title: &str) {
    let Axes { x0, x1, y0, y1, .. } = *axes;
    let text_paint = paint(TEXT);
    let s = LABEL_SCALE;
    let x_title = "TRAINING SAMPLES";
    let tw = f64::from(glyphs::text_width(x_title, s));
    glyphs::draw_text(
        image,
        x_title,
        0.5 * (x0 + x1) - tw / 2.0,
        y1 + 40.0,
        s,
        &text_paint,
    );
    glyphs::draw_text(
        image,
        "ERROR: RMS DISTANCE / DIAGONAL",
        x0 - 100.0,
        y0 - 22.0,
        s,
        &text_paint,
    );
    glyphs::draw_text(
        image,
        title,
        x0 - 100.0,
        14.0,
        TITLE_SCALE,
        &paint(TITLE_TEXT),
    );
}

/// The colour of basis `b` (black for one the study does not list).
fn basis_colour(b: HandleBasisKind) -> [u8; 4] {
    STUDY_BASES
        .iter()
        .position(|&k| k == b)
        .map_or([0, 0, 0, 255], |i| BASIS_COLOURS[i])
}

/// Basis `b`'s line through its measurements, with a dot at each.
fn draw_series(image: &mut Pixmap, axes: &Axes, study: &Study, b: HandleBasisKind) {
    let style = Line {
        rgba: basis_colour(b),
        width: 2.5,
    };
    let points: Vec<(f64, f64)> = study
        .rows
        .iter()
        .filter(|r| r.basis == b)
        .map(|r| (axes.px(r.samples as f64), axes.py(r.error)))
        .collect();
    let mut pb = tiny_skia::PathBuilder::new();
    for (i, &(x, y)) in points.iter().enumerate() {
        if i == 0 {
            pb.move_to(x as f32, y as f32);
        } else {
            pb.line_to(x as f32, y as f32);
        }
    }
    if let Some(path) = pb.finish() {
        stroke(image, &path, style, 1.0);
    }
    for &(x, y) in &points {
        if let Some(dot) = tiny_skia::PathBuilder::from_circle(x as f32, y as f32, 4.5) {
            image.fill_path(
                &dot,
                &paint(basis_colour(b)),
                tiny_skia::FillRule::Winding,
                tiny_skia::Transform::identity(),
                None,
            );
        }
    }
}

/// The legend, top right inside the axes, on white: a line of each basis's colour and its name.
fn draw_legend(image: &mut Pixmap, axes: &Axes, bases: &[HandleBasisKind]) {
    let glyph_h = glyph_height();
    let entry_h = glyph_h + 10.0;
    let legend_w = 150.0;
    let (lx, ly) = (axes.x1 - legend_w - 10.0, axes.y0 + 10.0);
    if let Some(rect) = tiny_skia::Rect::from_xywh(
        lx as f32,
        ly as f32,
        legend_w as f32,
        (entry_h * bases.len() as f64 + 10.0) as f32,
    ) {
        image.fill_rect(
            rect,
            &paint([255, 255, 255, 235]),
            tiny_skia::Transform::identity(),
            None,
        );
        stroke(image, &tiny_skia::PathBuilder::from_rect(rect), GRID, 1.0);
    }
    for (i, &b) in bases.iter().enumerate() {
        let y = ly + 10.0 + entry_h * i as f64;
        let mid = y + glyph_h / 2.0;
        draw_line(
            image,
            (lx + 10.0, mid),
            (lx + 45.0, mid),
            Line {
                rgba: basis_colour(b),
                width: 3.0,
            },
        );
        let name = match b {
            HandleBasisKind::ThinPlateSpline => "TPS",
            other => other.name(),
        };
        glyphs::draw_text(image, name, lx + 55.0, y, LABEL_SCALE, &paint(TEXT));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use kurbo::Rect;
    use splineskin_core::mesh::TriMesh;
    use splineskin_defop::{study, SampleRegion, SpatialBasis, StudyOptions, TrainOptions};

    #[test]
    fn study_error_falls_with_samples_for_tps_and_plots() {
        let mesh = TriMesh::grid(Rect::new(0., 0., 4., 1.), 12, 3).unwrap();
        let handles = [0, 12, 45, 51];
        let spatial = SpatialBasis::hats(&mesh).unwrap();
        let mut options = StudyOptions::new(
            TrainOptions::default().with_regions(vec![(SampleRegion::Disc { radius: 0.3 }, 1.0)]),
            vec![10, 40],
        );
        options.n_held_out = 6;
        let result = study(&mesh, &handles, &spatial, &options, &|_| {}).unwrap();
        let tps: Vec<f64> = result
            .rows
            .iter()
            .filter(|r| r.basis == HandleBasisKind::ThinPlateSpline)
            .map(|r| r.error)
            .collect();
        assert!(tps[1] < tps[0], "{tps:?}");
        let png = study_plot_png(&result, "TEST").unwrap();
        let pixmap = Pixmap::decode_png(&png).unwrap();
        assert_eq!((pixmap.width(), pixmap.height()), PLOT_SIZE);
    }

    #[test]
    fn study_tick_texts() {
        assert_eq!(tick_text(0.05), "0.05");
        assert_eq!(tick_text(0.001), "0.001");
        assert_eq!(tick_text(2e-4), "2E-4");
    }
}
