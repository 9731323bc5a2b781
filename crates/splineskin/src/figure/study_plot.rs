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
    let (ml, mr, mt, mb) = MARGINS;
    let (x0, x1, y0, y1) = (ml, f64::from(w) - mr, mt, f64::from(h) - mb);
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
    // Log ranges padded by a little; the error range spans at least a factor of 10.
    let (lx0, lx1) = (s_lo.log10() - 0.05, s_hi.max(s_lo * 1.5).log10() + 0.05);
    let (mut ly0, mut ly1) = (e_lo.log10(), e_hi.log10());
    if ly1 - ly0 < 1.0 {
        let mid = 0.5 * (ly0 + ly1);
        (ly0, ly1) = (mid - 0.5, mid + 0.5);
    }
    let pad = 0.05 * (ly1 - ly0);
    (ly0, ly1) = (ly0 - pad, ly1 + pad);
    let px = |s: f64| x0 + (s.log10() - lx0) / (lx1 - lx0) * (x1 - x0);
    let py = |e: f64| y1 - (e.log10() - ly0) / (ly1 - ly0) * (y1 - y0);
    let line = |pixmap: &mut Pixmap, a: (f64, f64), b: (f64, f64), style: Line| {
        let mut pb = tiny_skia::PathBuilder::new();
        pb.move_to(a.0 as f32, a.1 as f32);
        pb.line_to(b.0 as f32, b.1 as f32);
        if let Some(path) = pb.finish() {
            stroke(pixmap, &path, style, 1.0);
        }
    };
    let text_paint = paint(TEXT);
    let s = LABEL_SCALE;
    let glyph_h = f64::from(glyphs::GLYPH_HEIGHT * s);

    // Horizontal grid and y ticks at 1, 2, 5 × 10^k.
    for k in (ly0.floor() as i32)..=(ly1.ceil() as i32) {
        for m in [1.0, 2.0, 5.0] {
            let v = m * 10f64.powi(k);
            let l = v.log10();
            if l < ly0 || l > ly1 {
                continue;
            }
            let y = py(v).round() + 0.5;
            line(&mut image, (x0, y), (x1, y), GRID);
            line(&mut image, (x0 - 6.0, y), (x0, y), AXIS);
            let text = tick_text(v);
            let tw = f64::from(glyphs::text_width(&text, s));
            glyphs::draw_text(
                &mut image,
                &text,
                x0 - 10.0 - tw,
                y - glyph_h / 2.0,
                s,
                &text_paint,
            );
        }
    }
    // Vertical grid and x ticks at the sample counts.
    let mut counts: Vec<usize> = study.rows.iter().map(|r| r.samples).collect();
    counts.sort_unstable();
    counts.dedup();
    for &c in &counts {
        let x = px(c as f64).round() + 0.5;
        line(&mut image, (x, y0), (x, y1), GRID);
        line(&mut image, (x, y1), (x, y1 + 6.0), AXIS);
        let text = c.to_string();
        let tw = f64::from(glyphs::text_width(&text, s));
        glyphs::draw_text(&mut image, &text, x - tw / 2.0, y1 + 12.0, s, &text_paint);
    }
    // Axes.
    line(&mut image, (x0, y1), (x1, y1), AXIS);
    line(&mut image, (x0, y0), (x0, y1), AXIS);
    let x_title = "TRAINING SAMPLES";
    let tw = f64::from(glyphs::text_width(x_title, s));
    glyphs::draw_text(
        &mut image,
        x_title,
        0.5 * (x0 + x1) - tw / 2.0,
        y1 + 40.0,
        s,
        &text_paint,
    );
    glyphs::draw_text(
        &mut image,
        "ERROR: RMS DISTANCE / DIAGONAL",
        x0 - 100.0,
        y0 - 22.0,
        s,
        &text_paint,
    );
    glyphs::draw_text(
        &mut image,
        title,
        x0 - 100.0,
        14.0,
        TITLE_SCALE,
        &paint(TITLE_TEXT),
    );

    // One line per basis, dots at the measurements.
    let mut bases: Vec<HandleBasisKind> = Vec::new();
    for r in &study.rows {
        if !bases.contains(&r.basis) {
            bases.push(r.basis);
        }
    }
    let colour = |b: HandleBasisKind| {
        STUDY_BASES
            .iter()
            .position(|&k| k == b)
            .map_or([0, 0, 0, 255], |i| BASIS_COLOURS[i])
    };
    for &b in &bases {
        let style = Line {
            rgba: colour(b),
            width: 2.5,
        };
        let points: Vec<(f64, f64)> = study
            .rows
            .iter()
            .filter(|r| r.basis == b)
            .map(|r| (px(r.samples as f64), py(r.error)))
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
            stroke(&mut image, &path, style, 1.0);
        }
        for &(x, y) in &points {
            if let Some(dot) = tiny_skia::PathBuilder::from_circle(x as f32, y as f32, 4.5) {
                image.fill_path(
                    &dot,
                    &paint(colour(b)),
                    tiny_skia::FillRule::Winding,
                    tiny_skia::Transform::identity(),
                    None,
                );
            }
        }
    }
    // Legend, top right inside the axes, on white.
    let entry_h = glyph_h + 10.0;
    let legend_w = 150.0;
    let (lx, ly) = (x1 - legend_w - 10.0, y0 + 10.0);
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
        stroke(
            &mut image,
            &tiny_skia::PathBuilder::from_rect(rect),
            GRID,
            1.0,
        );
    }
    for (i, &b) in bases.iter().enumerate() {
        let y = ly + 10.0 + entry_h * i as f64;
        let mid = y + glyph_h / 2.0;
        line(
            &mut image,
            (lx + 10.0, mid),
            (lx + 45.0, mid),
            Line {
                rgba: colour(b),
                width: 3.0,
            },
        );
        let name = match b {
            HandleBasisKind::ThinPlateSpline => "TPS",
            other => other.name(),
        };
        glyphs::draw_text(&mut image, name, lx + 55.0, y, s, &text_paint);
    }
    image.encode_png().map_err(|e| bad(format!("encode: {e}")))
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
