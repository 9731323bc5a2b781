//! The fourth baseline: sample the skinned path densely and refit it with Schneider's
//! algorithm (Graphics Gems, 1990), which changes the number of curves ([`schneider_refit`]),
//! or refit to the input's curve count ([`schneider_refit_same_count`]).

use kurbo::{Affine, CubicBez, ParamCurve, Point, Vec2};

use super::{check_pose_len, skin_point};
use crate::bezier;
use crate::drawing::{Drawing, JointKind, Path};
use crate::spline_fit::PoseError;
use crate::weights::WeightField;

/// Default samples per input curve of [`schneider_refit`]: 64. Dense enough that the refit
/// follows the target between samples too: with the default tolerance, the target's largest
/// distance from the refit (101 samples per curve, `metrics::refit_metrics`) is below
/// 0.1 % of the diagonal on the bundled drawing and the authors' clam and turtles
/// (`tests/naive_baselines.rs`).
pub const DEFAULT_REFIT_SAMPLES: usize = 64;

/// Default error tolerance of [`schneider_refit`]: 0.5 drawing units (half a pixel at 1:1).
pub const DEFAULT_REFIT_TOLERANCE: f64 = 0.5;

/// Default Newton reparametrisation rounds per fit in [`schneider_refit`]: 4, as in
/// Schneider's published code.
pub const DEFAULT_REPARAMETRISATION_ROUNDS: usize = 4;

/// Largest recursion depth of the split in [`fit_cubics`]: 64. Both halves of a split have
/// fewer samples than the whole, so the depth is bounded by the sample count anyway; the cap
/// only bounds the stack on pathological input (a run past it ends with the heuristic cubic).
pub const MAX_SPLIT_DEPTH: usize = 64;

/// Options of [`schneider_refit`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct RefitOptions {
    /// Largest distance between a sample and the fitted curve (at the sample's parameter),
    /// in drawing units. Default: [`DEFAULT_REFIT_TOLERANCE`].
    pub tolerance: f64,
    /// Samples per input curve (uniform in its parameter). Default: [`DEFAULT_REFIT_SAMPLES`].
    pub samples_per_curve: usize,
    /// Newton reparametrisation rounds before splitting. Default:
    /// [`DEFAULT_REPARAMETRISATION_ROUNDS`].
    pub reparametrisation_rounds: usize,
}

impl Default for RefitOptions {
    fn default() -> Self {
        RefitOptions {
            tolerance: DEFAULT_REFIT_TOLERANCE,
            samples_per_curve: DEFAULT_REFIT_SAMPLES,
            reparametrisation_rounds: DEFAULT_REPARAMETRISATION_ROUNDS,
        }
    }
}

impl RefitOptions {
    /// Sets [`RefitOptions::tolerance`].
    pub fn with_tolerance(mut self, tolerance: f64) -> Self {
        self.tolerance = tolerance;
        self
    }
    /// Sets [`RefitOptions::samples_per_curve`].
    pub fn with_samples_per_curve(mut self, samples: usize) -> Self {
        self.samples_per_curve = samples;
        self
    }
    /// Sets [`RefitOptions::reparametrisation_rounds`].
    pub fn with_reparametrisation_rounds(mut self, rounds: usize) -> Self {
        self.reparametrisation_rounds = rounds;
        self
    }
}

/// The result of [`schneider_refit`]: one chain per input path, with its own number of curves.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Refit {
    /// The refitted paths, in the input's order.
    pub paths: Vec<RefitPath>,
}

/// One refitted path: a chain of `3n + 1` points (closed: the last equals the first), as
/// [`Path::points`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RefitPath {
    /// The chain points.
    pub points: Vec<Point>,
    /// Whether the path is closed.
    pub closed: bool,
}

impl RefitPath {
    /// Number of cubic curves.
    pub fn n_curves(&self) -> usize {
        self.points.len().saturating_sub(1) / 3
    }

    /// Curve `j` as a kurbo cubic.
    pub fn curve(&self, j: usize) -> CubicBez {
        let p = &self.points[3 * j..3 * j + 4];
        CubicBez::new(p[0], p[1], p[2], p[3])
    }
}

impl Refit {
    /// Total number of curves.
    pub fn n_curves(&self) -> usize {
        self.paths.iter().map(RefitPath::n_curves).sum()
    }

    /// Wraps chain points in the layout of [`crate::spline_fit::SplineRig::update`] (any
    /// result of the same structure as `drawing`), e.g. to measure them by closest point with
    /// `metrics::refit_metrics`. `None` on a length mismatch.
    pub fn from_chains(drawing: &Drawing, points: &[Point]) -> Option<Refit> {
        if points.len() != drawing.n_points() {
            return None;
        }
        let paths = drawing
            .paths
            .iter()
            .zip(drawing.path_ranges())
            .map(|(p, range)| RefitPath {
                points: points[range].to_vec(),
                closed: p.closed,
            })
            .collect();
        Some(Refit { paths })
    }
}

/// An error of [`schneider_refit`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum RefitError {
    /// The pose does not have one map per handle.
    #[error(transparent)]
    Pose(#[from] PoseError),
    /// The tolerance is not a positive finite number of drawing units.
    #[error("refit tolerance {0} is not positive and finite")]
    Tolerance(f64),
    /// Fewer than 2 samples per curve were asked for.
    #[error("{0} samples per curve asked for: at least 2 are needed")]
    Samples(usize),
    /// A deformed sample is not finite (a non-finite transform or weight).
    #[error("path {path}: a deformed sample is not finite")]
    NotFinite {
        /// The input path.
        path: usize,
    },
    /// A list of curve budgets does not have one entry per path.
    #[error("{got} curve budgets for a drawing of {expected} paths")]
    Budgets {
        /// Budgets given.
        got: usize,
        /// Paths in the drawing.
        expected: usize,
    },
}

/// Sample-and-refit baseline (paper §5 and Fig. 3): each path is sampled densely
/// (`samples_per_curve` uniform parameters per curve), the samples are mapped by the skinning
/// map `f`, and the resulting polyline is refitted with Schneider's algorithm ([`fit_cubics`]),
/// which changes the number of curves.
///
/// The path is cut at its corners (joints of kind [`JointKind::C0`] and
/// [`JointKind::FixedAngle`], and open ends), where the fit keeps a corner; each smooth run
/// between corners is fitted as one digitised curve (a closed path without corners as one loop,
/// with a common tangent at its seam; a closed path with corners starts at its first corner).
/// End tangents are estimated from the samples as in Schneider's method. Errors: a pose of the
/// wrong length, a tolerance that is not positive and finite, fewer than 2 samples per curve,
/// non-finite deformed samples.
///
/// ```
/// use kurbo::{Affine, Point};
/// use splineskin::drawing::{Drawing, JunctionOptions, Path};
/// use splineskin::naive::{schneider_refit, RefitOptions};
/// use splineskin::weights::{Shepard, ShepardOptions};
/// let pts = [(0.0, 0.0), (1.0, 1.0), (2.0, 1.0), (3.0, 0.0)].map(Point::from).to_vec();
/// let drawing = Drawing {
///     paths: vec![Path::new(pts, false, &JunctionOptions::default()).unwrap()],
///     ..Default::default()
/// };
/// let field = Shepard::new(&[Point::new(0.0, 0.0), Point::new(3.0, 0.0)], ShepardOptions::default());
/// let pose = [Affine::IDENTITY, Affine::rotate_about(0.5, Point::new(3.0, 0.0))];
/// let refit = schneider_refit(&drawing, &field, &pose, &RefitOptions::default().with_tolerance(1e-3)).unwrap();
/// assert_eq!(refit.paths.len(), 1);
/// assert!(refit.n_curves() >= 1);
/// ```
pub fn schneider_refit(
    drawing: &Drawing,
    field: &dyn WeightField,
    pose: &[Affine],
    options: &RefitOptions,
) -> Result<Refit, RefitError> {
    check_refit_inputs(field, pose, options)?;
    let mut w = vec![0.0; pose.len()];
    let mut paths = Vec::with_capacity(drawing.paths.len());
    for (index, path) in drawing.paths.iter().enumerate() {
        let samples = deformed_samples(path, field, pose, options.samples_per_curve, &mut w);
        if samples.iter().any(|p| !p.is_finite()) {
            return Err(RefitError::NotFinite { path: index });
        }
        paths.push(refit_path(path, &samples, options));
    }
    Ok(Refit { paths })
}

/// The argument checks of [`schneider_refit`].
fn check_refit_inputs(
    field: &dyn WeightField,
    pose: &[Affine],
    options: &RefitOptions,
) -> Result<(), RefitError> {
    check_pose_len(pose, field.n_handles())?;
    if !(options.tolerance.is_finite() && options.tolerance > 0.0) {
        return Err(RefitError::Tolerance(options.tolerance));
    }
    if options.samples_per_curve < 2 {
        return Err(RefitError::Samples(options.samples_per_curve));
    }
    Ok(())
}

/// Bisection rounds on the tolerance of [`schneider_refit_same_count`]: 40 (in log scale from
/// 1e-9 to 10 times the path's sample extent, the tolerance is then found to 1 %).
pub const SAME_COUNT_ROUNDS: usize = 40;

/// The sample-and-refit baseline at the input's curve budget: each path refitted (as in
/// [`schneider_refit`], from the same samples) with the smallest tolerance, found by bisection
/// in log scale, at which it has at most as many curves as the input path. This is the fair
/// comparison for methods that keep the input's curves: the same number of curves, each placed
/// where the refit likes. Returns the refit and each path's tolerance (drawing units).
///
/// `options.tolerance` is not used (it must still be positive and finite); the other options
/// are. Errors as [`schneider_refit`].
///
/// ```
/// use kurbo::{Affine, Point};
/// use splineskin::drawing::{Drawing, JunctionOptions, Path};
/// use splineskin::naive::{schneider_refit_same_count, RefitOptions};
/// use splineskin::weights::{Shepard, ShepardOptions};
/// let pts = [(0., 0.), (1., 1.), (2., 1.), (3., 0.), (4., -1.), (5., -1.), (6., 0.)];
/// let path = Path::new(pts.map(Point::from).to_vec(), false, &JunctionOptions::default()).unwrap();
/// let drawing = Drawing { paths: vec![path], ..Default::default() };
/// let field = Shepard::new(&[Point::new(0.0, 0.0), Point::new(6.0, 0.0)], ShepardOptions::default());
/// let pose = [Affine::IDENTITY, Affine::rotate_about(0.8, Point::new(6.0, 0.0))];
/// let (refit, tolerances) = schneider_refit_same_count(&drawing, &field, &pose, &RefitOptions::default()).unwrap();
/// assert!(refit.paths[0].n_curves() <= 2);
/// assert!(tolerances[0] > 0.0);
/// ```
pub fn schneider_refit_same_count(
    drawing: &Drawing,
    field: &dyn WeightField,
    pose: &[Affine],
    options: &RefitOptions,
) -> Result<(Refit, Vec<f64>), RefitError> {
    let budgets: Vec<usize> = drawing.paths.iter().map(Path::n_curves).collect();
    schneider_refit_within(drawing, field, pose, options, &budgets)
}

/// [`schneider_refit_same_count`] with a curve budget per path (`budgets[p]` curves for path
/// `p`, e.g. the counts another method ended with): per path, the refit with the smallest
/// tolerance that needs at most its budget.
///
/// Errors as [`schneider_refit`]; a budget list of the wrong length is
/// [`RefitError::Budgets`].
///
/// ```
/// use kurbo::{Affine, Point};
/// use splineskin::drawing::{Drawing, JunctionOptions, Path};
/// use splineskin::naive::{schneider_refit_within, RefitOptions};
/// use splineskin::weights::{Shepard, ShepardOptions};
/// let pts = [(0., 0.), (1., 1.), (2., 1.), (3., 0.), (4., -1.), (5., -1.), (6., 0.)];
/// let path = Path::new(pts.map(Point::from).to_vec(), false, &JunctionOptions::default()).unwrap();
/// let drawing = Drawing { paths: vec![path], ..Default::default() };
/// let field = Shepard::new(&[Point::new(0.0, 0.0), Point::new(6.0, 0.0)], ShepardOptions::default());
/// let pose = [Affine::IDENTITY, Affine::rotate_about(0.8, Point::new(6.0, 0.0))];
/// let (refit, _) = schneider_refit_within(&drawing, &field, &pose, &RefitOptions::default(), &[5]).unwrap();
/// assert!(refit.paths[0].n_curves() <= 5);
/// ```
pub fn schneider_refit_within(
    drawing: &Drawing,
    field: &dyn WeightField,
    pose: &[Affine],
    options: &RefitOptions,
    budgets: &[usize],
) -> Result<(Refit, Vec<f64>), RefitError> {
    check_refit_inputs(field, pose, options)?;
    if budgets.len() != drawing.paths.len() {
        return Err(RefitError::Budgets {
            got: budgets.len(),
            expected: drawing.paths.len(),
        });
    }
    let mut w = vec![0.0; pose.len()];
    let mut paths = Vec::with_capacity(drawing.paths.len());
    let mut tolerances = Vec::with_capacity(drawing.paths.len());
    for (index, path) in drawing.paths.iter().enumerate() {
        let samples = deformed_samples(path, field, pose, options.samples_per_curve, &mut w);
        if samples.iter().any(|p| !p.is_finite()) {
            return Err(RefitError::NotFinite { path: index });
        }
        let extent = kurbo::Rect::from_points(samples[0], samples[0]);
        let extent = samples
            .iter()
            .fold(extent, |r, p| r.union_pt(*p))
            .size()
            .to_vec2()
            .hypot()
            .max(f64::MIN_POSITIVE);
        let budget = budgets[index];
        let fit = |tolerance: f64| refit_path(path, &samples, &options.with_tolerance(tolerance));
        let (mut lo, mut hi) = ((1e-9 * extent).ln(), (10.0 * extent).ln());
        let mut best = fit(hi.exp());
        if best.n_curves() > budget {
            // Not even one curve per smooth run at this tolerance: no limit at all.
            best = fit(f64::MAX);
            paths.push(best);
            tolerances.push(f64::INFINITY);
            continue;
        }
        let mut best_tolerance = hi.exp();
        let low = fit(lo.exp());
        if low.n_curves() <= budget {
            (best, best_tolerance) = (low, lo.exp());
        } else {
            for _ in 0..SAME_COUNT_ROUNDS {
                let mid = 0.5 * (lo + hi);
                let r = fit(mid.exp());
                if r.n_curves() <= budget {
                    hi = mid;
                    (best, best_tolerance) = (r, mid.exp());
                } else {
                    lo = mid;
                }
            }
        }
        paths.push(best);
        tolerances.push(best_tolerance);
    }
    Ok((Refit { paths }, tolerances))
}

/// `f(B_j(t))` at `t = k / m`, `k = 0..m−1`, for every curve `j`, and the path's last point:
/// `n·m + 1` samples; sample `j·m` is on-curve point `j`.
fn deformed_samples(
    path: &Path,
    field: &dyn WeightField,
    pose: &[Affine],
    m: usize,
    w: &mut [f64],
) -> Vec<Point> {
    let n = path.n_curves();
    let mut out = Vec::with_capacity(n * m + 1);
    for j in 0..n {
        let c = path.curve_points(j);
        for k in 0..m {
            out.push(skin_point(
                field,
                pose,
                bezier::eval(&c, k as f64 / m as f64),
                w,
            ));
        }
    }
    out.push(skin_point(
        field,
        pose,
        path.points[path.points.len() - 1],
        w,
    ));
    out
}

/// Whether the path keeps a corner at joint `k`.
fn is_corner(kind: JointKind) -> bool {
    matches!(kind, JointKind::C0 | JointKind::FixedAngle | JointKind::End)
}

/// Refits one path from its deformed samples (`n·m + 1`, on-curve point `j` at `j·m`).
fn refit_path(path: &Path, samples: &[Point], options: &RefitOptions) -> RefitPath {
    let m = options.samples_per_curve;
    let n = path.n_curves();
    let mut chain = Vec::new();
    if path.closed {
        let corners: Vec<usize> = (0..n).filter(|&k| is_corner(path.joints[k])).collect();
        // The loop's samples without the repeated last one, starting at `start`.
        let ring = &samples[..n * m];
        let rotated = |start: usize| -> Vec<Point> {
            let mut v: Vec<Point> = ring[start..]
                .iter()
                .chain(&ring[..start])
                .copied()
                .collect();
            v.push(ring[start]);
            v
        };
        match corners.first() {
            None => {
                // One smooth loop: both ends share the centre tangent at the seam.
                let d = rotated(0);
                let last = d.len() - 1;
                let centre = centre_tangent(d[last - 1], d[1]);
                let (t1, t2) = match centre {
                    Some(c) => (-c, c),
                    None => (
                        left_tangent(&d, 0, last).unwrap_or(Vec2::ZERO),
                        right_tangent(&d, 0, last).unwrap_or(Vec2::ZERO),
                    ),
                };
                chain.push(d[0]);
                fit_cubics(&d, t1, t2, options, &mut chain);
            }
            Some(&first) => {
                let d = rotated(first * m);
                chain.push(d[0]);
                let mut bounds: Vec<usize> =
                    corners.iter().map(|&k| (k + n - first) % n * m).collect();
                bounds.push(n * m);
                for run in bounds.windows(2) {
                    fit_run(&d[run[0]..=run[1]], options, &mut chain);
                }
            }
        }
    } else {
        let mut bounds: Vec<usize> = (0..=n)
            .filter(|&k| is_corner(path.joints[k]))
            .map(|k| k * m)
            .collect();
        if bounds.last() != Some(&(n * m)) {
            bounds.push(n * m);
        }
        chain.push(samples[0]);
        for run in bounds.windows(2) {
            fit_run(&samples[run[0]..=run[1]], options, &mut chain);
        }
    }
    RefitPath {
        points: chain,
        closed: path.closed,
    }
}

/// Fits an open run of samples with tangents estimated at its ends.
fn fit_run(d: &[Point], options: &RefitOptions, chain: &mut Vec<Point>) {
    let last = d.len() - 1;
    let t1 = left_tangent(d, 0, last).unwrap_or(Vec2::ZERO);
    let t2 = right_tangent(d, 0, last).unwrap_or(Vec2::ZERO);
    fit_cubics(d, t1, t2, options, chain);
}

/// Unit vector from `d[first]` towards the first later sample distinct from it (Schneider's
/// `ComputeLeftTangent`, skipping repeated samples).
fn left_tangent(d: &[Point], first: usize, last: usize) -> Option<Vec2> {
    d[first + 1..=last]
        .iter()
        .map(|p| *p - d[first])
        .find(|v| v.hypot2() > 0.0)
        .map(Vec2::normalize)
}

/// Unit vector from `d[last]` towards the first earlier sample distinct from it
/// (`ComputeRightTangent`).
fn right_tangent(d: &[Point], first: usize, last: usize) -> Option<Vec2> {
    d[first..last]
        .iter()
        .rev()
        .map(|p| *p - d[last])
        .find(|v| v.hypot2() > 0.0)
        .map(Vec2::normalize)
}

/// Unit tangent at a split sample from its neighbours `before` and `after`, pointing backwards
/// (`ComputeCenterTangent`: `(d[i−1] − d[i+1])` normalised).
fn centre_tangent(before: Point, after: Point) -> Option<Vec2> {
    let v = before - after;
    (v.hypot2() > 0.0).then(|| v.normalize())
}

/// Schneider's algorithm (*An algorithm for automatically fitting digitized curves*, Graphics
/// Gems, 1990): fits the samples `d` (at least 2) with a G¹ chain of cubics whose samples lie
/// within `options.tolerance` of it, and appends the chain's points after `d[0]` to `chain`
/// (the caller pushed `d[0]`). `t1` is the unit tangent leaving `d[0]`, `t2` the unit tangent
/// leaving `d[last]` backwards (zero if unknown: the heuristic control points are used).
///
/// ```text
/// FitCubic(d, t̂1, t̂2):
///   u ← chord-length parameters of d
///   Q ← least-squares cubic with Q(0) = d_0, Q(1) = d_last, Q₁ = d_0 + α₁t̂1, Q₂ = d_last + α₂t̂2
///   if max_i ‖Q(u_i) − d_i‖ < ε: done
///   if it is < 2ε: up to `rounds` times u_i ← u_i − (Q(u_i) − d_i)·Q'(u_i) /
///                  (Q'(u_i)·Q'(u_i) + (Q(u_i) − d_i)·Q''(u_i)),  refit, done if < ε
///   split at the sample of largest error, t̂c from its neighbours:
///   FitCubic(d[..=split], t̂1, t̂c);  FitCubic(d[split..], −t̂c, t̂2)
/// ```
///
/// The least-squares step solves Schneider's 2×2 normal equations for `α₁, α₂`; when they are
/// singular or give `α < 1e-6 · ‖d_last − d_0‖`, the Wu–Barsky heuristic
/// `α₁ = α₂ = ‖d_last − d_0‖ / 3` is used (as in the published code).
///
/// ```
/// use kurbo::{Point, Vec2};
/// use splineskin::naive::{fit_cubics, RefitOptions};
/// // Samples of a quarter circle of radius 10: within 0.01 with a few cubics.
/// let d: Vec<Point> = (0..=50)
///     .map(|k| {
///         let a = std::f64::consts::FRAC_PI_2 * k as f64 / 50.0;
///         Point::new(10.0 * a.cos(), 10.0 * a.sin())
///     })
///     .collect();
/// let mut chain = vec![d[0]];
/// let opts = RefitOptions::default().with_tolerance(0.01);
/// fit_cubics(&d, Vec2::new(0.0, 1.0), Vec2::new(1.0, 0.0), &opts, &mut chain);
/// assert_eq!((chain.len() - 1) % 3, 0);
/// assert_eq!(*chain.last().unwrap(), d[50]);
/// ```
pub fn fit_cubics(d: &[Point], t1: Vec2, t2: Vec2, options: &RefitOptions, chain: &mut Vec<Point>) {
    fit_cubic(d, t1, t2, options, chain, 0);
}

fn fit_cubic(
    d: &[Point],
    t1: Vec2,
    t2: Vec2,
    options: &RefitOptions,
    chain: &mut Vec<Point>,
    depth: usize,
) {
    let last = d.len() - 1;
    let tol2 = options.tolerance * options.tolerance;
    if last == 1 || depth >= MAX_SPLIT_DEPTH {
        let dist = (d[last] - d[0]).hypot() / 3.0;
        chain.extend([d[0] + t1 * dist, d[last] + t2 * dist, d[last]]);
        return;
    }
    let mut u = chord_length_parameters(d);
    let mut bez = generate_bezier(d, &u, t1, t2);
    let (mut max_err, mut split) = max_error(d, &bez, &u);
    if max_err < tol2 {
        chain.extend([bez[1], bez[2], bez[3]]);
        return;
    }
    // Schneider's iterationError: ε² · 4 (twice the distance tolerance).
    if max_err < 4.0 * tol2 {
        for _ in 0..options.reparametrisation_rounds {
            reparametrise(d, &bez, &mut u);
            bez = generate_bezier(d, &u, t1, t2);
            (max_err, split) = max_error(d, &bez, &u);
            if max_err < tol2 {
                chain.extend([bez[1], bez[2], bez[3]]);
                return;
            }
        }
    }
    let tc = centre_tangent(d[split - 1], d[split + 1])
        .or_else(|| left_tangent(d, split, last).map(|v| -v))
        .unwrap_or(Vec2::ZERO);
    fit_cubic(&d[..=split], t1, tc, options, chain, depth + 1);
    fit_cubic(&d[split..], -tc, t2, options, chain, depth + 1);
}

/// Parameters `u_i ∈ [0, 1]` proportional to the polyline length up to `d_i`; uniform when the
/// polyline has zero length.
fn chord_length_parameters(d: &[Point]) -> Vec<f64> {
    let mut u = Vec::with_capacity(d.len());
    u.push(0.0);
    for w in d.windows(2) {
        let prev = u[u.len() - 1];
        u.push(prev + (w[1] - w[0]).hypot());
    }
    let total = u[u.len() - 1];
    let n = (d.len() - 1) as f64;
    for (i, v) in u.iter_mut().enumerate() {
        *v = if total > 0.0 {
            *v / total
        } else {
            i as f64 / n
        };
    }
    u
}

/// Least-squares cubic through `d[0]` and `d[last]` with inner control points along `t1`, `t2`
/// (Schneider's `GenerateBezier`).
fn generate_bezier(d: &[Point], u: &[f64], t1: Vec2, t2: Vec2) -> [Point; 4] {
    let (p0, p3) = (d[0], d[d.len() - 1]);
    let mut c = [[0.0; 2]; 2];
    let mut x = [0.0; 2];
    for (p, &t) in d.iter().zip(u) {
        let b = bezier::bernstein(t);
        let a1 = t1 * b[1];
        let a2 = t2 * b[2];
        c[0][0] += a1.dot(a1);
        c[0][1] += a1.dot(a2);
        c[1][1] += a2.dot(a2);
        // The part of d_i not explained by the fixed end points.
        let tmp = *p - (p0.to_vec2() * (b[0] + b[1]) + p3.to_vec2() * (b[2] + b[3])).to_point();
        x[0] += a1.dot(tmp);
        x[1] += a2.dot(tmp);
    }
    c[1][0] = c[0][1];
    let det = c[0][0] * c[1][1] - c[1][0] * c[0][1];
    let (mut alpha1, mut alpha2) = (0.0, 0.0);
    if det != 0.0 {
        alpha1 = (x[0] * c[1][1] - x[1] * c[0][1]) / det;
        alpha2 = (c[0][0] * x[1] - c[1][0] * x[0]) / det;
    }
    let seg = (p3 - p0).hypot();
    let eps = 1e-6 * seg;
    if det == 0.0 || !(alpha1 >= eps && alpha2 >= eps) {
        alpha1 = seg / 3.0;
        alpha2 = alpha1;
    }
    [p0, p0 + t1 * alpha1, p3 + t2 * alpha2, p3]
}

/// Largest squared distance `‖Q(u_i) − d_i‖²` over the inner samples, and where (Schneider's
/// `ComputeMaxError`; the split sample is inner, `1 ≤ split ≤ last − 1`).
fn max_error(d: &[Point], bez: &[Point; 4], u: &[f64]) -> (f64, usize) {
    let last = d.len() - 1;
    let mut worst = (0.0, last / 2);
    for i in 1..last {
        let e = (bezier::eval(bez, u[i]) - d[i]).hypot2();
        if e >= worst.0 {
            worst = (e, i);
        }
    }
    worst
}

/// One Newton step per sample on `(Q(u) − d)·Q'(u) = 0` (Schneider's `Reparameterize`), kept in
/// `[0, 1]`.
fn reparametrise(d: &[Point], bez: &[Point; 4], u: &mut [f64]) {
    let curve = CubicBez::new(bez[0], bez[1], bez[2], bez[3]);
    for (p, t) in d.iter().zip(u.iter_mut()) {
        let q = curve.eval(*t) - *p;
        let q1 = bezier::derivative(bez, *t);
        let q2 = second_derivative(bez, *t);
        let den = q1.dot(q1) + q.dot(q2);
        if den != 0.0 && den.is_finite() {
            *t = (*t - q.dot(q1) / den).clamp(0.0, 1.0);
        }
    }
}

/// `B''(t) = 6[(1−t)(c2 − 2c1 + c0) + t(c3 − 2c2 + c1)]`.
pub(super) fn second_derivative(c: &[Point; 4], t: f64) -> Vec2 {
    let a = c[2].to_vec2() - c[1].to_vec2() * 2.0 + c[0].to_vec2();
    let b = c[3].to_vec2() - c[2].to_vec2() * 2.0 + c[1].to_vec2();
    (a * (1.0 - t) + b * t) * 6.0
}
