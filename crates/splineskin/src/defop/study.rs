//! [`study()`]: the convergence experiment of Poranne & Lipman 2016, Fig. 8 (DESIGN.md §4):
//! for each handle basis, the error of the fitted operator against the ground truth on
//! held-out handle configurations as the number of training samples grows.
//!
//! ```text
//! 1. train once with the largest sample count m_max (train(): bootstrapped ground truths)
//! 2. draw n_held_out configurations from the same regions with another seed, and solve
//!    their ground truth from the rest pose (ground_truths_from_rest)
//! 3. for each basis Ψ and each count m: fit DefOp on the rest configuration and the first m
//!    training samples, and measure
//!        error(Ψ, m) = mean_k  l2_distance(D(·, Q_k), U_k) / diagonal
//!    (RMS distance over the shape, as a fraction of the rest mesh's bounding-box diagonal)
//! ```
//!
//! Prefixes of one sample set make the counts nested, as in the paper; every basis and count is
//! measured against the same held-out truth. That truth is solved from the rest pose, not from
//! an operator's prediction: both energies have several local minima for large displacements,
//! and a truth started from the operator under test would depend on that operator.

use std::time::Instant;

use kurbo::Point;

use super::handles::bounding_box_diagonal;
use super::{
    ground_truths_from_rest, l2_distance, train, DefOp, DefOpError, HandleBasisKind, Progress,
    SampleRegion, Sampler, SpatialBasis, TrainOptions, Training, DEFAULT_DISC_FRACTION,
};
use crate::figure::glyphs;
use crate::figure::strokes::{paint, stroke, Line};
use crate::mesh::TriMesh;
use resvg::tiny_skia::{self, Pixmap};

/// Default [`StudyOptions::n_held_out`]: 20 held-out configurations.
pub const DEFAULT_HELD_OUT: usize = 20;

/// Default [`StudyOptions::held_out_seed`] (any seed other than the training's).
pub const DEFAULT_HELD_OUT_SEED: u64 = 424_242;

/// The four handle bases of the paper's Fig. 8, in the order the study reports them.
pub const STUDY_BASES: [HandleBasisKind; 4] = [
    HandleBasisKind::Linear,
    HandleBasisKind::Quadratic,
    HandleBasisKind::Cubic,
    HandleBasisKind::ThinPlateSpline,
];

/// Options of [`study()`].
///
/// ```
/// use splineskin::defop::{StudyOptions, TrainOptions};
/// let options = StudyOptions::new(TrainOptions::default(), vec![20, 40, 80]);
/// assert_eq!(options.n_held_out, 20);
/// ```
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct StudyOptions {
    /// Energy, sampling regions, seed, solvers and parallelism of the training and of the
    /// held-out solves; its `n_samples` and handle basis are replaced (the largest count, and
    /// thin-plate splines for bootstrapping).
    pub train: TrainOptions,
    /// The sample counts (each ≥ 1), increasing.
    pub sample_counts: Vec<usize>,
    /// Held-out configurations. Default: [`DEFAULT_HELD_OUT`].
    pub n_held_out: usize,
    /// Seed of the held-out sampler. Default: [`DEFAULT_HELD_OUT_SEED`].
    pub held_out_seed: u64,
    /// Handle bases measured. Default: [`STUDY_BASES`].
    pub bases: Vec<HandleBasisKind>,
}

impl StudyOptions {
    /// The study of `sample_counts` with the training options `train` and the defaults.
    pub fn new(train: TrainOptions, sample_counts: Vec<usize>) -> StudyOptions {
        StudyOptions {
            train,
            sample_counts,
            n_held_out: DEFAULT_HELD_OUT,
            held_out_seed: DEFAULT_HELD_OUT_SEED,
            bases: STUDY_BASES.to_vec(),
        }
    }
}

/// `count` sample counts from `first` to `last` in a geometric sequence (rounded, distinct,
/// increasing; `first` and `last` included).
///
/// ```
/// use splineskin::defop::geometric_sample_counts;
/// assert_eq!(geometric_sample_counts(25, 800, 6), vec![25, 50, 100, 200, 400, 800]);
/// ```
pub fn geometric_sample_counts(first: usize, last: usize, count: usize) -> Vec<usize> {
    let (first, last) = (first.max(1), last.max(first.max(1)));
    let ratio = (last as f64 / first as f64).powf(1.0 / (count.max(2) - 1) as f64);
    let mut counts: Vec<usize> = (0..count.max(2))
        .map(|k| (first as f64 * ratio.powi(k as i32)).round() as usize)
        .collect();
    counts.dedup();
    counts
}

/// Where a study is: training (as [`train`] reports it), then the held-out solves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StudyProgress {
    /// A training solve finished.
    Training(Progress),
    /// `done` of `total` held-out ground truths solved.
    HeldOut {
        /// Solved so far.
        done: usize,
        /// To solve.
        total: usize,
    },
}

/// One measurement of a [`Study`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StudyRow {
    /// The handle basis.
    pub basis: HandleBasisKind,
    /// Training samples besides the rest configuration.
    pub samples: usize,
    /// Mean over the held-out configurations of the RMS distance over the shape
    /// ([`l2_distance`]) to the ground truth, as a fraction of the bounding-box diagonal.
    pub error: f64,
    /// The largest of those distances, same unit.
    pub max_error: f64,
    /// Seconds of the fit.
    pub fit_seconds: f64,
}

/// The result of [`study()`].
#[derive(Clone, Debug)]
pub struct Study {
    /// One row per basis and count, bases in [`StudyOptions::bases`] order; thin-plate
    /// splines skip counts below `2n` (their side conditions need the rest configuration and
    /// `2n` more samples).
    pub rows: Vec<StudyRow>,
    /// The rest mesh's bounding-box diagonal (drawing units): the errors' unit.
    pub diagonal: f64,
    /// Held-out configurations measured.
    pub n_held_out: usize,
    /// The training (its largest count).
    pub training: Training,
    /// Seconds of the training.
    pub training_seconds: f64,
    /// Seconds of the held-out solves.
    pub held_out_seconds: f64,
}

/// Runs the convergence study (module documentation) on `mesh` with handles at `handles` and
/// spatial basis `spatial`. Errors as [`train`] and [`DefOp::fit`], or on empty or zero
/// sample counts or no held-out configuration.
///
/// ```
/// use kurbo::Rect;
/// use splineskin::defop::{study, SpatialBasis, StudyOptions, TrainOptions};
/// use splineskin::mesh::TriMesh;
/// let mesh = TriMesh::grid(Rect::new(0., 0., 4., 1.), 8, 2)?;
/// let spatial = SpatialBasis::hats(&mesh)?;
/// let mut options = StudyOptions::new(TrainOptions::default(), vec![5, 10]);
/// options.n_held_out = 3;
/// let result = study(&mesh, &[9, 17], &spatial, &options, &|_| {})?;
/// assert_eq!(result.rows.len(), 4 * 2);
/// assert!(result.rows.iter().all(|r| r.error.is_finite()));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn study(
    mesh: &TriMesh,
    handles: &[usize],
    spatial: &SpatialBasis,
    options: &StudyOptions,
    progress: &(dyn Fn(StudyProgress) + Sync),
) -> Result<Study, DefOpError> {
    let counts = &options.sample_counts;
    let largest = counts.iter().copied().max().unwrap_or(0);
    if counts.is_empty() || counts.contains(&0) {
        return Err(DefOpError::InvalidOption {
            name: "sample_counts",
            value: format!("{counts:?}"),
            expected: "at least one count, each at least 1",
        });
    }
    if options.n_held_out == 0 {
        return Err(DefOpError::InvalidOption {
            name: "n_held_out",
            value: "0".into(),
            expected: "at least 1",
        });
    }
    let train_options = options
        .train
        .clone()
        .with_n_samples(largest)
        .with_handle_basis(HandleBasisKind::ThinPlateSpline);
    let clock = Instant::now();
    let training = train(mesh, handles, spatial, &train_options, &|p| {
        progress(StudyProgress::Training(p));
    })?;
    let training_seconds = clock.elapsed().as_secs_f64();

    let diagonal = bounding_box_diagonal(mesh);
    let regions = if options.train.regions.is_empty() {
        vec![(
            SampleRegion::Disc {
                radius: DEFAULT_DISC_FRACTION * diagonal,
            },
            1.0,
        )]
    } else {
        options.train.regions.clone()
    };
    let rest: Vec<Point> = handles.iter().map(|&h| mesh.vertices[h]).collect();
    let held_out =
        Sampler::new(&rest, &regions, options.held_out_seed)?.configurations(options.n_held_out);
    let clock = Instant::now();
    let total = held_out.len();
    let truths = ground_truths_from_rest(mesh, handles, &options.train, &held_out, &|done| {
        progress(StudyProgress::HeldOut { done, total });
    })?;
    let held_out_seconds = clock.elapsed().as_secs_f64();

    let mut rows = Vec::with_capacity(options.bases.len() * counts.len());
    for &basis in &options.bases {
        for &m in counts {
            // Thin-plate interpolation needs the rest and 2n samples not on one hyperplane.
            if basis == HandleBasisKind::ThinPlateSpline && m < 2 * handles.len() {
                continue;
            }
            let clock = Instant::now();
            let op = DefOp::fit(
                mesh,
                handles,
                spatial,
                &training.configurations[..=m],
                &training.solutions[..=m],
                &train_options.fit.with_handle_basis(basis),
            )?;
            let fit_seconds = clock.elapsed().as_secs_f64();
            let mut evaluator = op.evaluator();
            let mut positions = vec![Point::ZERO; mesh.n_vertices()];
            let mut sum = 0.0;
            let mut max: f64 = 0.0;
            for (q, truth) in held_out.iter().zip(&truths) {
                evaluator.eval(q, &mut positions)?;
                let d = l2_distance(mesh, &positions, truth)? / diagonal;
                sum += d;
                max = max.max(d);
            }
            rows.push(StudyRow {
                basis,
                samples: m,
                error: sum / total as f64,
                max_error: max,
                fit_seconds,
            });
        }
    }
    Ok(Study {
        rows,
        diagonal,
        n_held_out: total,
        training,
        training_seconds,
        held_out_seconds,
    })
}

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

impl Study {
    /// The study as a PNG plot: training samples against error, both logarithmic, one line per
    /// basis with a dot per measurement, ticks at the sample counts and at 1, 2 and 5 times the
    /// powers of ten, a legend, and a title naming the error's unit and `title` (e.g. the
    /// shape and energy). Labels use the figures' pixel font ([`crate::figure::glyphs`]).
    ///
    /// Errors only when a row's error is not positive and finite or the pixmap cannot be
    /// allocated or encoded (as [`DefOpError::InvalidOption`] naming the row).
    pub fn plot_png(&self, title: &str) -> Result<Vec<u8>, DefOpError> {
        let bad = |detail: String| DefOpError::InvalidOption {
            name: "study plot",
            value: detail,
            expected: "positive finite errors",
        };
        if let Some(r) = self
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
            self.rows.iter().map(g).fold(init, f)
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
        let mut counts: Vec<usize> = self.rows.iter().map(|r| r.samples).collect();
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
        for r in &self.rows {
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
            let points: Vec<(f64, f64)> = self
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
}

#[cfg(test)]
mod tests {
    use super::*;
    use kurbo::Rect;

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
        let png = result.plot_png("TEST").unwrap();
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
