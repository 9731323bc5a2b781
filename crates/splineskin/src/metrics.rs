//! How far a deformed drawing is from the skinned target (paper §5 and its figures; DESIGN.md
//! §1 "Naive baselines").
//!
//! The target of input curve `j` (control points `B_j`) is the skinned curve
//!
//! ```text
//! s_j(t) = Σ_i w_i(B_j(t)) T_i B̄_j(t),   t ∈ [0, 1]
//! ```
//!
//! which is in general not a cubic. For a result `R` (chains of cubics) three figures are given,
//! per input curve and over the drawing:
//!
//! * **energy** — the fit's objective `E = Σ_j ∫ ‖R_j(t) − s_j(t)‖² dμ_j`, with the measure
//!   and quadrature of [`MetricsOptions::fit`]: by default the fit's own default,
//!   `dμ_j = ℓ_j dt` (`ℓ_j` the undeformed arc length of curve `j`) integrated by composite
//!   Gauss–Legendre ([`crate::spline_fit::quadrature`]). On that measure the spline fit
//!   ([`crate::spline_fit::SplineRig`]) is the constrained minimiser, so a result of the same
//!   structure satisfying its junction constraints cannot score lower. Units: squared drawing
//!   units times length. The overall value is the sum over curves.
//! * **max** and **RMS distance**, as fractions of the input drawing's bounding-box diagonal
//!   ([`Drawing::diagonal`], the control points' box): the distance is sampled at
//!   [`MetricsOptions::samples_per_curve`] uniform parameters `t_k = k / (S − 1)`,
//!   `k = 0 … S − 1` (ends included), of every curve. RMS is `sqrt(mean d_k²)` over the curve's
//!   samples; the overall RMS pools all samples of all curves (every curve counts equally,
//!   whatever its length) and the overall max is the largest.
//!
//! Two ways to pair a result with the target:
//!
//! * [`chain_metrics`], for results with the input's structure (the spline fit and the naive
//!   baselines): **parametric**, `d = ‖R_j(t) − s_j(t)‖` at equal `t`;
//! * [`refit_metrics`], for any chains (Schneider refits, whose curves and parametrisation
//!   differ): **closest point**, `d = min_{u, c} ‖R_c(u) − s_j(t)‖` over all curves `c` of the
//!   result path refitting input path of curve `j` — the one-sided distance from the target to
//!   the result. The energy is then `Σ_j ∫ d(t)² dμ_j` with that `d`, a lower bound on any
//!   parametric energy of the same curves. The nearest point is found to
//!   [`MetricsOptions::nearest_accuracy`].

use kurbo::{Affine, CubicBez, ParamCurveNearest, Point, Rect};

use crate::bezier;
use crate::drawing::Drawing;
use crate::naive::{check_pose_len, Refit, RefitPath};
use crate::spline_fit::quadrature::SampledCurves;
use crate::spline_fit::{FitOptions, PoseError};
use crate::weights::WeightField;

/// Default distance samples per curve: 101 (`t = 0, 0.01, …, 1`).
pub const DEFAULT_DISTANCE_SAMPLES: usize = 101;

/// Default accuracy of the closest-point search of [`refit_metrics`], as a fraction of the
/// diagonal: 1e-9 (far below any figure reported).
pub const DEFAULT_NEAREST_ACCURACY: f64 = 1e-9;

/// Options of [`chain_metrics`] and [`refit_metrics`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct MetricsOptions {
    /// Quadrature and measure of the energy (the other fields are not used). Default: the
    /// fit's default ([`FitOptions::default`]: length-weighted, composite Gauss).
    pub fit: FitOptions,
    /// Uniform distance samples per curve, ends included (≥ 2). Default:
    /// [`DEFAULT_DISTANCE_SAMPLES`].
    pub samples_per_curve: usize,
    /// Accuracy of closest points, as a fraction of the diagonal. Default:
    /// [`DEFAULT_NEAREST_ACCURACY`].
    pub nearest_accuracy: f64,
}

impl Default for MetricsOptions {
    fn default() -> Self {
        MetricsOptions {
            fit: FitOptions::default(),
            samples_per_curve: DEFAULT_DISTANCE_SAMPLES,
            nearest_accuracy: DEFAULT_NEAREST_ACCURACY,
        }
    }
}

impl MetricsOptions {
    /// Sets [`MetricsOptions::fit`].
    pub fn with_fit(mut self, fit: FitOptions) -> Self {
        self.fit = fit;
        self
    }
    /// Sets [`MetricsOptions::samples_per_curve`].
    pub fn with_samples_per_curve(mut self, samples: usize) -> Self {
        self.samples_per_curve = samples;
        self
    }
}

/// The three figures of one curve, or of the whole drawing.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ErrorFigures {
    /// `∫ ‖R − s‖² dμ` (drawing units² · length).
    pub energy: f64,
    /// Largest sampled distance / diagonal.
    pub max: f64,
    /// Root mean square of the sampled distances / diagonal.
    pub rms: f64,
}

/// Figures of a result against the target: per input curve (all paths, in order) and overall.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Metrics {
    /// One entry per input curve.
    pub per_curve: Vec<ErrorFigures>,
    /// Energy summed, max of maxima, RMS over all samples.
    pub overall: ErrorFigures,
    /// The diagonal the distances are divided by (drawing units).
    pub diagonal: f64,
    /// Every sampled distance, in drawing units (not divided by the diagonal): entry
    /// `j · S + k` is at `t_k = k / (S − 1)` of input curve `j` (all paths in order), the
    /// target point there being entry `j · S + k` of [`target_samples`].
    pub distances: Vec<f64>,
}

/// An error of the metrics.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MetricsError {
    /// The pose or the result has the wrong size.
    #[error(transparent)]
    Pose(#[from] PoseError),
    /// The refit has a different number of paths than the drawing.
    #[error("the result has {got} paths, the drawing {expected}")]
    Paths {
        /// Paths of the result.
        got: usize,
        /// Paths of the drawing.
        expected: usize,
    },
    /// Fewer than 2 distance samples per curve were asked for.
    #[error("{0} distance samples per curve asked for: at least 2 are needed")]
    Samples(usize),
}

/// Parametric figures of `points` (layout of [`crate::spline_fit::SplineRig::update`]: the
/// chain points of every path of `drawing`, concatenated) against the target of `drawing`
/// under `field` and `pose`. See the module doc for the definitions.
///
/// ```
/// use kurbo::{Affine, Point, Vec2};
/// use splineskin::drawing::{Drawing, JunctionOptions, Path};
/// use splineskin::metrics::{chain_metrics, MetricsOptions};
/// use splineskin::weights::{Shepard, ShepardOptions};
/// let pts = [(0.0, 0.0), (0.0, 0.0), (3.0, 4.0), (3.0, 4.0)].map(Point::from).to_vec();
/// let drawing = Drawing {
///     paths: vec![Path::new(pts.clone(), false, &JunctionOptions::default()).unwrap()],
///     ..Default::default()
/// };
/// // One handle: the target is the input. Shift the result by v = (0, 0.5).
/// let field = Shepard::new(&[Point::ZERO], ShepardOptions::default());
/// let shifted: Vec<Point> = pts.iter().map(|p| *p + Vec2::new(0.0, 0.5)).collect();
/// let m = chain_metrics(&drawing, &field, &[Affine::IDENTITY], &shifted, &MetricsOptions::default()).unwrap();
/// // E = ℓ ‖v‖² = 5 · 0.25; distances ‖v‖ / diagonal = 0.5 / 5 everywhere.
/// assert!((m.overall.energy - 1.25).abs() < 1e-12);
/// assert!((m.overall.max - 0.1).abs() < 1e-12 && (m.overall.rms - 0.1).abs() < 1e-12);
/// ```
pub fn chain_metrics(
    drawing: &Drawing,
    field: &dyn WeightField,
    pose: &[Affine],
    points: &[Point],
    options: &MetricsOptions,
) -> Result<Metrics, MetricsError> {
    check(field, pose, options)?;
    if points.len() != drawing.n_points() {
        return Err(PoseError::Output {
            got: points.len(),
            expected: drawing.n_points(),
        }
        .into());
    }
    let result_curve = |path_offset: usize, j: usize| -> [Point; 4] {
        let p = &points[path_offset + 3 * j..path_offset + 3 * j + 4];
        [p[0], p[1], p[2], p[3]]
    };
    measure(drawing, field, pose, options, |_, offset, j, target| {
        let c = result_curve(offset, j);
        (bezier::eval(&c, target.0) - target.1).hypot()
    })
}

/// Closest-point figures of `refit` (one chain per path of `drawing`, any number of curves)
/// against the target of `drawing` under `field` and `pose`. See the module doc: the distance
/// of a target point is to the nearest point of the corresponding result path, and the energy
/// integrates its square.
///
/// ```
/// use kurbo::{Affine, Point};
/// use splineskin::drawing::{Drawing, JunctionOptions, Path};
/// use splineskin::metrics::{refit_metrics, MetricsOptions};
/// use splineskin::naive::Refit;
/// use splineskin::weights::{Shepard, ShepardOptions};
/// let pts = [(0.0, 0.0), (1.0, 2.0), (2.0, 2.0), (3.0, 0.0)].map(Point::from).to_vec();
/// let drawing = Drawing {
///     paths: vec![Path::new(pts.clone(), false, &JunctionOptions::default()).unwrap()],
///     ..Default::default()
/// };
/// let field = Shepard::new(&[Point::ZERO], ShepardOptions::default());
/// // The input itself, split in two halves: a different parametrisation of the target.
/// use kurbo::ParamCurve;
/// let halves = kurbo::CubicBez::new(pts[0], pts[1], pts[2], pts[3]).subdivide();
/// let chain = [halves.0.p0, halves.0.p1, halves.0.p2, halves.0.p3, halves.1.p1, halves.1.p2, halves.1.p3];
/// let refit = Refit { paths: vec![splineskin::naive::RefitPath { points: chain.to_vec(), closed: false }] };
/// let m = refit_metrics(&drawing, &field, &[Affine::IDENTITY], &refit, &MetricsOptions::default()).unwrap();
/// assert!(m.overall.max < 1e-8);
/// ```
pub fn refit_metrics(
    drawing: &Drawing,
    field: &dyn WeightField,
    pose: &[Affine],
    refit: &Refit,
    options: &MetricsOptions,
) -> Result<Metrics, MetricsError> {
    check(field, pose, options)?;
    if refit.paths.len() != drawing.paths.len() {
        return Err(MetricsError::Paths {
            got: refit.paths.len(),
            expected: drawing.paths.len(),
        });
    }
    let accuracy = options.nearest_accuracy * drawing.diagonal().max(f64::MIN_POSITIVE);
    let candidates: Vec<Vec<(CubicBez, Rect)>> = refit.paths.iter().map(hulls).collect();
    measure(drawing, field, pose, options, |path, _, _, target| {
        nearest_distance(&candidates[path], target.1, accuracy)
    })
}

/// The result path's curves with their control-point boxes (each contains its curve).
fn hulls(path: &RefitPath) -> Vec<(CubicBez, Rect)> {
    (0..path.n_curves())
        .map(|j| {
            let c = path.curve(j);
            let r = Rect::from_points(c.p0, c.p1).union_pt(c.p2).union_pt(c.p3);
            (c, r)
        })
        .collect()
}

/// Distance from `p` to the nearest of `curves`, skipping curves whose box is farther than the
/// best so far.
fn nearest_distance(curves: &[(CubicBez, Rect)], p: Point, accuracy: f64) -> f64 {
    let box_distance = |r: &Rect| {
        let dx = (r.x0 - p.x).max(p.x - r.x1).max(0.0);
        let dy = (r.y0 - p.y).max(p.y - r.y1).max(0.0);
        dx.hypot(dy)
    };
    let mut order: Vec<(f64, usize)> = curves
        .iter()
        .enumerate()
        .map(|(k, (_, r))| (box_distance(r), k))
        .collect();
    order.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut best = f64::INFINITY;
    for (lower, k) in order {
        if lower >= best {
            break;
        }
        best = best.min(curves[k].0.nearest(p, accuracy).distance_sq.sqrt());
    }
    best
}

fn check(
    field: &dyn WeightField,
    pose: &[Affine],
    options: &MetricsOptions,
) -> Result<(), MetricsError> {
    check_pose_len(pose, field.n_handles())?;
    if options.samples_per_curve < 2 {
        return Err(MetricsError::Samples(options.samples_per_curve));
    }
    Ok(())
}

/// Runs both measurements with `distance(path, path_offset, j, (t, s_j(t)))` giving the
/// distance of the result from the target point `s_j(t)` of curve `j` of `path` (`j` counted
/// within the path, `path_offset` the index of the path's first chain point).
fn measure(
    drawing: &Drawing,
    field: &dyn WeightField,
    pose: &[Affine],
    options: &MetricsOptions,
    distance: impl Fn(usize, usize, usize, (f64, Point)) -> f64,
) -> Result<Metrics, MetricsError> {
    let diagonal = drawing.diagonal();
    let scale = if diagonal > 0.0 { 1.0 / diagonal } else { 0.0 };
    let nodes = SampledCurves::sample(drawing, field, &options.fit);
    let h = nodes.n_handles();
    let s = options.samples_per_curve;
    let mut w = vec![0.0; h];
    let mut per_curve = Vec::with_capacity(drawing.n_curves());
    let mut distances = Vec::with_capacity(drawing.n_curves() * s);
    let mut overall = ErrorFigures::default();
    let mut sum_sq = 0.0;
    let mut n_samples = 0usize;
    let mut curve_index = 0;
    for (p, (path, range)) in drawing.paths.iter().zip(drawing.path_ranges()).enumerate() {
        let offset = range.start;
        for j in 0..path.n_curves() {
            let c = path.curve_points(j);
            // Energy at the fit's quadrature nodes, with the weights sampled there.
            let q = nodes.curve(curve_index);
            let mut energy = 0.0;
            for (k, (&t, &omega)) in q.t.iter().zip(q.omega).enumerate() {
                let x = bezier::eval(&c, t);
                let target = crate::naive::blend(pose, &q.weights[k * h..(k + 1) * h]) * x;
                let d = distance(p, offset, j, (t, target));
                energy += omega * d * d;
            }
            // Distances at uniform samples.
            let (mut max, mut sq) = (0.0f64, 0.0);
            for k in 0..s {
                let t = k as f64 / (s - 1) as f64;
                let x = bezier::eval(&c, t);
                let target = crate::naive::skin_point(field, pose, x, &mut w);
                let d = distance(p, offset, j, (t, target));
                max = max.max(d);
                sq += d * d;
                distances.push(d);
            }
            per_curve.push(ErrorFigures {
                energy,
                max: max * scale,
                rms: (sq / s as f64).sqrt() * scale,
            });
            overall.energy += energy;
            overall.max = overall.max.max(max * scale);
            sum_sq += sq;
            n_samples += s;
            curve_index += 1;
        }
    }
    if n_samples > 0 {
        overall.rms = (sum_sq / n_samples as f64).sqrt() * scale;
    }
    Ok(Metrics {
        per_curve,
        overall,
        diagonal,
        distances,
    })
}

/// The target where the distances are sampled: `s_j(k / (S − 1))` for every input curve `j`
/// (all paths in order) and `k = 0 … S − 1`, at entry `j · S + k` (`S = samples_per_curve`,
/// at least 2).
///
/// ```
/// use kurbo::{Affine, Point};
/// use splineskin::drawing::{Drawing, JunctionOptions, Path};
/// use splineskin::metrics::target_samples;
/// use splineskin::weights::{Shepard, ShepardOptions};
/// let pts = [(0.0, 0.0), (1.0, 1.0), (2.0, 1.0), (3.0, 0.0)].map(Point::from).to_vec();
/// let drawing = Drawing {
///     paths: vec![Path::new(pts, false, &JunctionOptions::default()).unwrap()],
///     ..Default::default()
/// };
/// let field = Shepard::new(&[Point::ZERO], ShepardOptions::default());
/// let s = target_samples(&drawing, &field, &[Affine::translate((0.0, 1.0))], 3);
/// assert_eq!(s, [Point::new(0.0, 1.0), Point::new(1.5, 1.75), Point::new(3.0, 1.0)]);
/// ```
pub fn target_samples(
    drawing: &Drawing,
    field: &dyn WeightField,
    pose: &[Affine],
    samples_per_curve: usize,
) -> Vec<Point> {
    let s = samples_per_curve.max(2);
    let mut w = vec![0.0; pose.len()];
    let mut out = Vec::with_capacity(drawing.n_curves() * s);
    for path in &drawing.paths {
        for j in 0..path.n_curves() {
            let c = path.curve_points(j);
            for k in 0..s {
                let x = bezier::eval(&c, k as f64 / (s - 1) as f64);
                out.push(crate::naive::skin_point(field, pose, x, &mut w));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::{JunctionOptions, Path};
    use crate::weights::{Shepard, ShepardOptions};
    use kurbo::Vec2;

    fn one_curve(pts: [(f64, f64); 4]) -> Drawing {
        Drawing {
            paths: vec![Path::new(
                pts.map(Point::from).to_vec(),
                false,
                &JunctionOptions::default(),
            )
            .unwrap()],
            ..Default::default()
        }
    }

    #[test]
    fn metrics_of_the_exact_target_are_zero() {
        // One affine map on every handle: the target is that map of the cubic, a cubic.
        let d = one_curve([(0.0, 0.0), (1.0, 3.0), (4.0, -1.0), (5.0, 2.0)]);
        let f = Shepard::new(
            &[Point::ZERO, Point::new(5.0, 0.0)],
            ShepardOptions::default(),
        );
        let t = Affine::new([0.8, 0.3, -0.2, 1.1, 3.0, 1.0]);
        let exact: Vec<Point> = d.flat_points().iter().map(|p| t * *p).collect();
        let opts = MetricsOptions::default();
        let m = chain_metrics(&d, &f, &[t, t], &exact, &opts).unwrap();
        // Rounding of Σ w_i T_i x with coordinates of order 10.
        assert!(m.overall.energy < 1e-26, "{m:?}");
        assert!(m.overall.max < 1e-14);
        let r = refit_metrics(
            &d,
            &f,
            &[t, t],
            &Refit::from_chains(&d, &exact).unwrap(),
            &opts,
        )
        .unwrap();
        assert!(r.overall.max < 1e-8, "{r:?}");
    }

    #[test]
    fn metrics_of_one_moved_control_point_match_closed_forms() {
        // One handle, identity: target = input. Moving c1 by v gives R − s = v b₁(t):
        // E = ℓ ‖v‖² ∫ b₁² dt = ℓ ‖v‖² · 3/35; max = ‖v‖ · max b₁ = ‖v‖ · 4/9 at t = 1/3
        // (sampled at t = k/100: 0.33 gives b₁ within 4e-5 of it).
        let d = one_curve([(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (3.0, 0.0)]);
        let f = Shepard::new(&[Point::new(1.0, 1.0)], ShepardOptions::default());
        let v = Vec2::new(0.0, 0.6);
        let mut moved = d.flat_points();
        moved[1] += v;
        let opts = MetricsOptions::default();
        let m = chain_metrics(&d, &f, &[Affine::IDENTITY], &moved, &opts).unwrap();
        let len = 3.0;
        let diag = d.diagonal();
        assert_eq!(diag, 3.0);
        assert!((m.overall.energy - len * v.hypot2() * 3.0 / 35.0).abs() < 1e-12);
        let max_b1 = 4.0 / 9.0;
        assert!((m.overall.max - v.hypot() * max_b1 / diag).abs() < 1e-4);
        // RMS over 101 uniform samples ≈ sqrt(∫ b₁²) = sqrt(3/35) (trapezoid-like, b₁(0) =
        // b₁(1) = 0, so the mean is ∫ · 100/101 up to O(1e-4)).
        let rms = v.hypot() * (3.0f64 / 35.0 * 100.0 / 101.0).sqrt() / diag;
        assert!(
            (m.overall.rms - rms).abs() < 1e-4 * rms,
            "{} vs {rms}",
            m.overall.rms
        );
        assert_eq!(m.per_curve.len(), 1);
        assert_eq!(m.per_curve[0], m.overall);
    }

    #[test]
    fn sizes_are_checked() {
        let d = one_curve([(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (3.0, 0.0)]);
        let f = Shepard::new(&[Point::new(1.0, 1.0)], ShepardOptions::default());
        let pts = d.flat_points();
        let opts = MetricsOptions::default();
        assert!(chain_metrics(&d, &f, &[], &pts, &opts).is_err());
        assert!(matches!(
            chain_metrics(&d, &f, &[Affine::IDENTITY], &pts[1..], &opts),
            Err(MetricsError::Pose(PoseError::Output { .. }))
        ));
        assert!(matches!(
            refit_metrics(&d, &f, &[Affine::IDENTITY], &Refit::default(), &opts),
            Err(MetricsError::Paths {
                got: 0,
                expected: 1
            })
        ));
    }
}
