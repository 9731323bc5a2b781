//! Adaptive control points: where the spline fit cannot follow the skinned target closely
//! enough, the input curve is split at rest and the drawing re-rigged, until every curve is
//! within a tolerance over the poses that matter (the future work named by Liu et al. 2014 §7:
//! "insert control points").
//!
//! Splitting curve `B` at `t = ½` (de Casteljau) gives two cubics that trace exactly the same
//! curve, so the rest pose, and every anchor of the drawing, is unchanged; the new anchor joins
//! the halves with parallel tangents of equal length, and is imposed G¹ with that ratio. Only
//! the fit gains freedom: two cubics can follow a target that bends where one cannot.
//!
//! ```text
//! round:  rig the current drawing ──► deform by every pose ──► per-curve max distance d_j
//!         every curve with d_j > tolerance (worst first, within the curve budget) ──► split at ½
//! until:  all d_j ≤ tolerance (met), the budget is spent, or MAX rounds
//! ```
//!
//! `d_j` is the parametric distance of the fit from the target of curve `j`
//! ([`metrics::chain_metrics`], uniform samples), as a fraction of the input drawing's diagonal:
//! at least the closest-point distance, so a drawing refined to `d_j ≤ tol` is within `tol` by
//! closest point too. A curve that several paths run along (a fill and its outline) is split
//! in every one of them, so that they stay one curve and no gap opens. The anchors inserted are
//! listed per path ([`Refined::inserted`]) so that an editor or a file can tell them from the
//! artist's.

use std::collections::HashMap;

use kurbo::{Affine, CubicBez, ParamCurve, Point};

use crate::drawing::{Drawing, JointKind, Path};
use crate::metrics::{self, MetricsError, MetricsOptions};
use crate::spline_fit::quadrature::SampledCurves;
use crate::spline_fit::{
    FitError, FitOptions, FlexibleOptions, FlexibleSolver, PoseError, SplineRig,
};
use crate::weights::WeightField;

/// Default tolerance: 1e-3 of the drawing's diagonal (half a pixel when it is drawn 500 px
/// across).
pub const DEFAULT_TOLERANCE: f64 = 1e-3;

/// Default curve budget, as a multiple of the input's curve count: 4 (and at least
/// [`MIN_BUDGET`] curves).
pub const DEFAULT_BUDGET_FACTOR: usize = 4;

/// Smallest default curve budget: 64 curves (a drawing of a few curves may need many pieces).
pub const MIN_BUDGET: usize = 64;

/// Most refinement rounds: 12 (each round at most doubles a curve's pieces, so a curve can be
/// cut into up to 4 096).
pub const MAX_ROUNDS: usize = 12;

/// Options of [`refine`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct AdaptiveOptions {
    /// Largest distance from the target, as a fraction of the input drawing's diagonal.
    /// Default: [`DEFAULT_TOLERANCE`].
    pub tolerance: f64,
    /// Most curves the refined drawing may have. Default: `None`, [`DEFAULT_BUDGET_FACTOR`]
    /// times the input's, at least [`MIN_BUDGET`].
    pub max_curves: Option<usize>,
    /// The distance samples ([`MetricsOptions::samples_per_curve`]).
    pub metrics: MetricsOptions,
}

impl Default for AdaptiveOptions {
    fn default() -> Self {
        AdaptiveOptions {
            tolerance: DEFAULT_TOLERANCE,
            max_curves: None,
            metrics: MetricsOptions::default(),
        }
    }
}

impl AdaptiveOptions {
    /// Sets [`AdaptiveOptions::tolerance`].
    pub fn with_tolerance(mut self, fraction: f64) -> Self {
        self.tolerance = fraction;
        self
    }
    /// Sets [`AdaptiveOptions::max_curves`].
    pub fn with_max_curves(mut self, curves: usize) -> Self {
        self.max_curves = Some(curves);
        self
    }
}

/// A drawing refined by [`refine`], rigged.
#[derive(Clone)]
pub struct Refined {
    /// The input drawing with curves split at rest (the same paths, in the same order, each
    /// with at least its input's curves).
    pub drawing: Drawing,
    /// Per path, per joint of [`Refined::drawing`] (the layout of [`Path::joints`]): whether
    /// the anchor was inserted by the refinement (`false`: the artist's).
    pub inserted: Vec<Vec<bool>>,
    /// The rig of the refined drawing.
    pub rig: SplineRig,
    /// The largest distance of the fit from the target over the poses, fraction of the input's
    /// diagonal.
    pub worst: f64,
    /// Rounds of splitting done.
    pub rounds: usize,
    /// Whether every curve is within the tolerance (else the budget or the rounds ran out).
    pub met: bool,
}

impl Refined {
    /// Number of anchors inserted.
    pub fn n_inserted(&self) -> usize {
        self.inserted.iter().flatten().filter(|&&b| b).count()
    }

    /// The flexible G¹ solver of the refined drawing, from its rig (the same `weights` and
    /// `fit` it was refined with), for a refined drawing whose fit is flexible.
    pub fn flexible_solver(
        &self,
        weights: &dyn WeightField,
        fit: &FitOptions,
        options: FlexibleOptions,
    ) -> Result<FlexibleSolver, FitError> {
        let samples = SampledCurves::sample(&self.drawing, weights, fit);
        FlexibleSolver::from_rig(self.rig.clone(), &self.drawing, &samples, fit, options)
    }
}

/// Why a drawing could not be refined.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum AdaptiveError {
    /// The rig could not be built.
    #[error(transparent)]
    Fit(#[from] FitError),
    /// A pose does not fit the weights.
    #[error("pose {pose}: {source}")]
    Pose {
        /// Index of the pose.
        pose: usize,
        /// The rig's message.
        source: PoseError,
    },
    /// The distances could not be measured.
    #[error("pose {pose}: {source}")]
    Metrics {
        /// Index of the pose.
        pose: usize,
        /// The metrics' message.
        source: MetricsError,
    },
    /// The tolerance is not a positive finite fraction.
    #[error("tolerance {0:e} (fraction of the diagonal) is not positive and finite")]
    Tolerance(f64),
    /// No pose was given.
    #[error("no poses to refine for (expected at least one)")]
    NoPoses,
}

/// Splits curves of `drawing` at rest until the fit of `weights` follows the skinned target
/// within `options.tolerance` under every pose of `poses` (module doc), or the curve budget is
/// spent. The identity pose needs no split: pass the poses that matter (a scene's poses, its
/// animation's frames, the poses seen while dragging).
///
/// ```
/// use kurbo::{Affine, Point};
/// use splineskin::adaptive::{refine, AdaptiveOptions};
/// use splineskin::drawing::{read_svg, ImportOptions};
/// use splineskin::spline_fit::FitOptions;
/// use splineskin::weights::{Shepard, ShepardOptions};
/// // One long curve, its ends turned opposite ways: one cubic cannot follow the S it becomes.
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg"><path d="M0 0 C30 0 70 0 100 0"/></svg>"#;
/// let drawing = read_svg(svg, &ImportOptions::default())?;
/// let handles = [Point::new(0.0, 0.0), Point::new(50.0, 0.0), Point::new(100.0, 0.0)];
/// let weights = Shepard::new(&handles, ShepardOptions::default());
/// let pose = vec![
///     Affine::translate((0.0, 20.0)),
///     Affine::IDENTITY,
///     Affine::translate((0.0, 20.0)),
/// ];
/// let refined = refine(&drawing, &weights, &FitOptions::default(), &[pose], &AdaptiveOptions::default())?;
/// assert!(refined.met && refined.worst <= 1e-3, "{} curves, worst {:e}", refined.drawing.n_curves(), refined.worst);
/// assert!(refined.drawing.n_curves() > 1);
/// // The artist's anchors are kept, the new ones marked.
/// assert_eq!(refined.drawing.paths[0].points[0], Point::new(0.0, 0.0));
/// assert!(!refined.inserted[0][0] && refined.n_inserted() == refined.drawing.n_curves() - 1);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn refine(
    drawing: &Drawing,
    weights: &dyn WeightField,
    fit: &FitOptions,
    poses: &[Vec<Affine>],
    options: &AdaptiveOptions,
) -> Result<Refined, AdaptiveError> {
    if !(options.tolerance > 0.0 && options.tolerance.is_finite()) {
        return Err(AdaptiveError::Tolerance(options.tolerance));
    }
    if poses.is_empty() {
        return Err(AdaptiveError::NoPoses);
    }
    let diagonal = drawing.diagonal();
    let budget = options
        .max_curves
        .unwrap_or((DEFAULT_BUDGET_FACTOR * drawing.n_curves()).max(MIN_BUDGET))
        .max(drawing.n_curves());
    let mut current = drawing.clone();
    let mut inserted: Vec<Vec<bool>> = drawing
        .paths
        .iter()
        .map(|p| vec![false; p.joints.len()])
        .collect();
    let mut rounds = 0;
    loop {
        let rig = SplineRig::precompute(&current, weights, fit)?;
        let errors = curve_errors(&current, weights, &rig, poses, &options.metrics, diagonal)?;
        let worst = errors.iter().copied().fold(0.0, f64::max);
        let mut over: Vec<usize> = (0..errors.len())
            .filter(|&j| errors[j] > options.tolerance)
            .collect();
        // Worst first, as many as the budget allows (a shared curve costs one per copy).
        over.sort_by(|&a, &b| errors[b].total_cmp(&errors[a]));
        let room = budget.saturating_sub(current.n_curves());
        let split = if rounds == MAX_ROUNDS {
            None
        } else {
            curves_to_split(&current, &over, room)
        };
        let Some(split) = split else {
            return Ok(Refined {
                drawing: current,
                inserted,
                rig,
                worst,
                rounds,
                met: over.is_empty(),
            });
        };
        for (p, path) in current.paths.iter_mut().enumerate() {
            let (refined, flags) = split_path(path, &split[p], &inserted[p]);
            *path = refined;
            inserted[p] = flags;
        }
        rounds += 1;
    }
}

/// Which curves of `drawing` to split (per path, per curve): those of `over` (curve indices
/// over all paths, worst first), each with every copy of it in other paths, as long as the
/// total stays within `room`. `None` when nothing is to be split or nothing fits.
fn curves_to_split(drawing: &Drawing, over: &[usize], room: usize) -> Option<Vec<Vec<bool>>> {
    let copies = shared_copies(drawing);
    let locate = curve_locations(drawing);
    let mut split: Vec<Vec<bool>> = drawing
        .paths
        .iter()
        .map(|p| vec![false; p.n_curves()])
        .collect();
    let mut added = 0;
    for &j in over {
        let (p, c) = locate[j];
        if split[p][c] {
            continue;
        }
        let group = copies.get(&(p, c)).cloned().unwrap_or_else(|| vec![(p, c)]);
        let fresh: Vec<(usize, usize)> = group.into_iter().filter(|&(q, d)| !split[q][d]).collect();
        if added + fresh.len() > room {
            break;
        }
        added += fresh.len();
        for (q, d) in fresh {
            split[q][d] = true;
        }
    }
    (added > 0).then_some(split)
}

/// The largest parametric distance of the fit from the target of each curve of `drawing`
/// (all paths in order) over `poses`, as a fraction of `diagonal`.
fn curve_errors(
    drawing: &Drawing,
    weights: &dyn WeightField,
    rig: &SplineRig,
    poses: &[Vec<Affine>],
    options: &MetricsOptions,
    diagonal: f64,
) -> Result<Vec<f64>, AdaptiveError> {
    let mut points = vec![Point::ZERO; rig.n_points()];
    let mut errors = vec![0.0f64; drawing.n_curves()];
    // The metrics divide by the current drawing's diagonal; the tolerance is the input's.
    let rescale = if diagonal > 0.0 {
        drawing.diagonal() / diagonal
    } else {
        1.0
    };
    for (i, pose) in poses.iter().enumerate() {
        rig.update(pose, &mut points)
            .map_err(|source| AdaptiveError::Pose { pose: i, source })?;
        let m = metrics::chain_metrics(drawing, weights, pose, &points, options)
            .map_err(|source| AdaptiveError::Metrics { pose: i, source })?;
        for (e, c) in errors.iter_mut().zip(&m.per_curve) {
            *e = e.max(c.max * rescale);
        }
    }
    Ok(errors)
}

/// `(path, curve within the path)` of every curve of `drawing`, in order.
fn curve_locations(drawing: &Drawing) -> Vec<(usize, usize)> {
    drawing
        .paths
        .iter()
        .enumerate()
        .flat_map(|(p, path)| (0..path.n_curves()).map(move |c| (p, c)))
        .collect()
}

/// For every curve whose control points another curve of the drawing repeats exactly (either
/// direction: a fill and its outline), the list of all of them.
fn shared_copies(drawing: &Drawing) -> HashMap<(usize, usize), Vec<(usize, usize)>> {
    let key = |c: [Point; 4]| {
        let forward = c.map(|p| (p.x.to_bits(), p.y.to_bits()));
        let mut backward = forward;
        backward.reverse();
        forward.min(backward)
    };
    let mut by_key: HashMap<_, Vec<(usize, usize)>> = HashMap::new();
    for (p, path) in drawing.paths.iter().enumerate() {
        for c in 0..path.n_curves() {
            by_key
                .entry(key(path.curve_points(c)))
                .or_default()
                .push((p, c));
        }
    }
    let mut out = HashMap::new();
    for group in by_key.into_values().filter(|g| g.len() > 1) {
        for &member in &group {
            out.insert(member, group.clone());
        }
    }
    out
}

/// `path` with every curve `c` for which `split[c]` cut at `t = ½`, and its inserted-anchor
/// flags (`flags`, one per joint) carried over with the new anchors marked. The new joints are
/// G¹ (their tangents are parallel, of equal length); the others keep their kinds.
fn split_path(path: &Path, split: &[bool], flags: &[bool]) -> (Path, Vec<bool>) {
    let n = path.n_curves();
    let mut points = vec![path.points[0]];
    let mut joints = Vec::with_capacity(path.joints.len() + n);
    let mut marks = Vec::with_capacity(joints.capacity());
    for c in 0..n {
        // Joint c starts curve c.
        joints.push(path.joints[c]);
        marks.push(flags[c]);
        let [p0, p1, p2, p3] = path.curve_points(c);
        if split[c] {
            let (a, b) = CubicBez::new(p0, p1, p2, p3).subdivide();
            points.extend([a.p1, a.p2, a.p3, b.p1, b.p2]);
            joints.push(JointKind::G1);
            marks.push(true);
        } else {
            points.extend([p1, p2]);
        }
        points.push(p3);
    }
    if !path.closed {
        joints.push(path.joints[n]);
        marks.push(flags[n]);
    } else {
        // Keep the closing point identical to the first.
        let last = points.len() - 1;
        points[last] = points[0];
    }
    (
        Path {
            points,
            closed: path.closed,
            joints,
        },
        marks,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::JunctionOptions;

    #[test]
    fn adaptive_split_keeps_the_curve_and_its_anchors() {
        let pts = [
            (0., 0.),
            (1., 2.),
            (3., 2.),
            (4., 0.),
            (5., -1.),
            (6., 1.),
            (4., 3.),
        ]
        .map(Point::from)
        .to_vec();
        let path = Path::new(pts.clone(), false, &JunctionOptions::default()).unwrap();
        let (split, flags) = split_path(&path, &[true, false], &[false, false, false]);
        assert_eq!(split.n_curves(), 3);
        assert_eq!(flags, vec![false, true, false, false]);
        assert_eq!(split.joints[1], JointKind::G1);
        // Every original anchor is still there.
        assert_eq!(split.points[0], pts[0]);
        assert_eq!(split.points[6], pts[3]);
        assert_eq!(split.points[9], pts[6]);
        // The halves trace the original curve.
        let original = CubicBez::new(pts[0], pts[1], pts[2], pts[3]);
        let first = split.curve(0);
        for k in 0..=10 {
            let t = k as f64 / 10.0;
            assert!((first.eval(t) - original.eval(t / 2.0)).hypot() < 1e-14);
        }
    }

    #[test]
    fn adaptive_split_closed_path_stays_closed() {
        let pts = [
            (1., 0.),
            (1., 1.),
            (-1., 1.),
            (-1., 0.),
            (-1., -1.),
            (1., -1.),
            (1., 0.),
        ]
        .map(Point::from)
        .to_vec();
        let path = Path::new(pts, true, &JunctionOptions::default()).unwrap();
        let (split, flags) = split_path(&path, &[false, true], &[false, false]);
        assert_eq!(split.n_curves(), 3);
        assert_eq!(flags, vec![false, false, true]);
        assert_eq!(split.points[0], split.points[split.points.len() - 1]);
        assert_eq!(split.joints.len(), 3);
    }
}
