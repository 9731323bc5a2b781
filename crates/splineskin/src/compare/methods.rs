//! Every method deformed by the same pose and measured against the same target
//! ([`super`] tells which and how); the pictures of the result are
//! [`crate::figure::comparison`]'s.

use kurbo::{Affine, Point};

use crate::adaptive::{AdaptiveError, AdaptiveOptions};
use crate::drawing::Drawing;
use crate::metrics::{self, Metrics, MetricsError, MetricsOptions};
use crate::naive::{self, check_pose_len, Refit, RefitError, RefitOptions, WeightGradient};
use crate::scene::handles::HandleMarker;
use crate::scene::{HandleSet, PosedDrawing};
use crate::spline_fit::quadrature::SampledCurves;
use crate::spline_fit::{
    FitError, FitOptions, FlexibleError, FlexibleOptions, FlexibleSolver, PoseError, SplineRig,
};
use crate::weights::WeightField;

/// Default tolerance of the Schneider refit, as a fraction of the drawing's bounding-box
/// diagonal: 1e-3 (half a pixel when the drawing is drawn about 500 px across). At this
/// tolerance the refit follows the target closely, at the price of several times the input's
/// curve count, which is what it is compared on.
pub const DEFAULT_REFIT_TOLERANCE_FRACTION: f64 = 1e-3;

/// One of the compared methods.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// The spline fit with the input's tangent-length ratios (the paper's fixed-ratio G¹).
    Ours,
    /// The spline fit with flexible G¹ and fixed-angle junctions.
    OursFlexible,
    /// Every control point skinned (the authors' `fourcontrols`).
    FourControls,
    /// On-curve points skinned, off-curve points carried by their neighbour's transform (the
    /// authors' `twoendpoints`).
    TwoEndpoints,
    /// On-curve points skinned, off-curve points carried by the Jacobian (the authors'
    /// `jacobian`).
    Jacobian,
    /// Dense samples skinned and refitted by Schneider's algorithm.
    Schneider,
    /// The same refit with, per path, the smallest tolerance that needs no more curves than
    /// the input: the refit at the budget of the methods that keep the curves.
    SchneiderSameCount,
    /// The spline fit of the drawing refined by adaptive control points
    /// ([`crate::adaptive::refine`] for the compared pose): input curves split at rest where
    /// the fit falls short; every input anchor kept.
    OursAdaptive,
    /// The Schneider refit given, per path, as many curves as `ours-adaptive` ended with.
    SchneiderAdaptiveCount,
}

impl Method {
    /// The method's name in tables and JSON: `ours`, `ours-flexible`, `fourcontrols`,
    /// `twoendpoints`, `jacobian`, `schneider`, `schneider-same-count`, `ours-adaptive`,
    /// `schneider-adaptive-count`.
    pub fn name(self) -> &'static str {
        match self {
            Method::Ours => "ours",
            Method::OursFlexible => "ours-flexible",
            Method::FourControls => "fourcontrols",
            Method::TwoEndpoints => "twoendpoints",
            Method::Jacobian => "jacobian",
            Method::Schneider => "schneider",
            Method::SchneiderSameCount => "schneider-same-count",
            Method::OursAdaptive => "ours-adaptive",
            Method::SchneiderAdaptiveCount => "schneider-adaptive-count",
        }
    }

    /// Whether the result keeps the input's curves (measured parametrically), rather than
    /// refitting them (measured by closest point).
    pub fn keeps_structure(self) -> bool {
        !matches!(
            self,
            Method::Schneider
                | Method::SchneiderSameCount
                | Method::OursAdaptive
                | Method::SchneiderAdaptiveCount
        )
    }

    /// Whether the result keeps every anchor of the input (the refits do not: they place
    /// their own).
    pub fn keeps_anchors(self) -> bool {
        !matches!(
            self,
            Method::Schneider | Method::SchneiderSameCount | Method::SchneiderAdaptiveCount
        )
    }
}

/// What is compared: a drawing, its weights, a pose and how the fit is set up.
#[derive(Clone, Copy)]
pub struct CompareInputs<'a> {
    /// The input drawing (junction kinds as the fit should keep them).
    pub drawing: &'a Drawing,
    /// One weight function per handle.
    pub weights: &'a dyn WeightField,
    /// The same weights with gradients, for the Jacobian baseline (e.g. the analytic
    /// [`crate::weights::Shepard`], or [`naive::FiniteDifferences`] of `weights`).
    pub gradient: &'a dyn WeightGradient,
    /// The fit's options (also the energy's measure and quadrature, as in the metrics).
    pub fit: FitOptions,
    /// Also compare the flexible fit, with these options.
    pub flexible: Option<FlexibleOptions>,
    /// One map per handle.
    pub pose: &'a [Affine],
}

/// Options of [`compare_methods`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct CompareOptions {
    /// Tolerance of the Schneider refit, as a fraction of the drawing's diagonal. Default:
    /// [`DEFAULT_REFIT_TOLERANCE_FRACTION`].
    pub refit_tolerance: f64,
    /// The metrics' options. Default: [`MetricsOptions::default`] (the energy on the fit's
    /// default measure: pass [`MetricsOptions::with_fit`] to match another fit).
    pub metrics: MetricsOptions,
    /// Also compare `ours-adaptive` (refined for the compared pose with these options) and
    /// `schneider-adaptive-count`. Default: `None`.
    pub adaptive: Option<AdaptiveOptions>,
}

impl Default for CompareOptions {
    fn default() -> Self {
        CompareOptions {
            refit_tolerance: DEFAULT_REFIT_TOLERANCE_FRACTION,
            metrics: MetricsOptions::default(),
            adaptive: None,
        }
    }
}

impl CompareOptions {
    /// Sets [`CompareOptions::refit_tolerance`].
    pub fn with_refit_tolerance(mut self, fraction: f64) -> Self {
        self.refit_tolerance = fraction;
        self
    }
    /// Sets [`CompareOptions::metrics`].
    pub fn with_metrics(mut self, metrics: MetricsOptions) -> Self {
        self.metrics = metrics;
        self
    }
    /// Sets [`CompareOptions::adaptive`].
    pub fn with_adaptive(mut self, adaptive: AdaptiveOptions) -> Self {
        self.adaptive = Some(adaptive);
        self
    }
}

/// One method's result and figures.
#[derive(Clone, Debug)]
pub struct MethodResult {
    /// Which method.
    pub method: Method,
    /// The result: one chain per input path.
    pub result: Refit,
    /// Its figures against the target ([`metrics::chain_metrics`] for methods that keep the
    /// input's structure, [`metrics::refit_metrics`] for the refit).
    pub metrics: Metrics,
    /// Its figures by closest point for every method ([`metrics::refit_metrics`]; for a refit
    /// the same as [`MethodResult::metrics`]): the one measure all methods share, since the
    /// refit has no parametric correspondence with the input.
    pub closest: Metrics,
    /// Distance from the target to the result at the target samples
    /// ([`Comparison::target`]'s layout), drawing units.
    pub distances: Vec<f64>,
    /// Where the result folds a closed outline over itself: the number of crossings between
    /// curves that do not cross at rest ([`crate::folds::new_self_crossings`]). `None` for the
    /// refits, whose curves are not the input's.
    pub folds: Option<usize>,
}

/// Every method's result on one drawing and pose.
#[derive(Clone, Debug)]
pub struct Comparison {
    /// The methods, in the order of [`Method`] (the flexible fit only when asked for).
    pub methods: Vec<MethodResult>,
    /// The target at `samples_per_curve` uniform parameters of every input curve (all paths in
    /// order): entry `j · S + k` is `s_j(k / (S − 1))`.
    pub target: Vec<Point>,
    /// Samples per input curve `S`.
    pub samples_per_curve: usize,
    /// Number of input curves per path.
    pub path_curves: Vec<usize>,
    /// The input drawing's bounding-box diagonal (drawing units).
    pub diagonal: f64,
    /// The Schneider refit's tolerance, in drawing units.
    pub refit_tolerance: f64,
}

impl Comparison {
    /// The largest distance from the target over every method and sample (drawing units).
    pub fn largest_distance(&self) -> f64 {
        self.methods
            .iter()
            .flat_map(|m| m.distances.iter().copied())
            .fold(0.0, f64::max)
    }

    /// The result of `method`, if compared.
    pub fn get(&self, method: Method) -> Option<&MethodResult> {
        self.methods.iter().find(|m| m.method == method)
    }
}

/// Why a comparison cannot be made (why it cannot be drawn:
/// [`crate::figure::comparison::ComparePictureError`]).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CompareError {
    /// The pose does not fit the weights.
    #[error(transparent)]
    Pose(#[from] PoseError),
    /// The spline fit cannot be built.
    #[error("ours: {0}")]
    Fit(#[from] FitError),
    /// The flexible fit failed.
    #[error("ours-flexible: {0}")]
    Flexible(#[from] FlexibleError),
    /// The refit failed.
    #[error("schneider: {0}")]
    Refit(#[from] RefitError),
    /// The adaptive refinement failed.
    #[error("ours-adaptive: {0}")]
    Adaptive(#[from] AdaptiveError),
    /// The refit tolerance is not a positive fraction of the diagonal that is finite in
    /// drawing units.
    #[error(
        "refit tolerance {0:e} (fraction of the diagonal) is not positive and finite in drawing units"
    )]
    RefitTolerance(f64),
    /// The metrics cannot be computed.
    #[error("{method}: metrics: {source}")]
    Metrics {
        /// The method.
        method: &'static str,
        /// The metrics' error.
        source: MetricsError,
    },
    /// A result has a point that is not finite.
    #[error("{method}: path {path}: the result has a point that is not finite")]
    NotFinite {
        /// The method.
        method: &'static str,
        /// The input path.
        path: usize,
    },
}

impl CompareError {
    /// Wraps an error of measuring `method`'s result as [`CompareError::Metrics`].
    fn metrics_of(method: Method) -> impl FnOnce(MetricsError) -> CompareError {
        move |source| CompareError::Metrics {
            method: method.name(),
            source,
        }
    }
}

/// Deforms `inputs.drawing` by `inputs.pose` with every [`Method`] (the flexible fit when
/// `inputs.flexible` is given) and measures each against the target (the [`crate::compare`] module doc).
///
/// Errors: a pose of the wrong length, a fit that cannot be built, a refit tolerance that is
/// not positive and finite, a result that is not finite (naming the method and path).
///
/// ```
/// use kurbo::{Affine, Point};
/// use splineskin::compare::{compare_methods, CompareInputs, CompareOptions, Method};
/// use splineskin::drawing::{read_svg, ImportOptions};
/// use splineskin::weights::{Shepard, ShepardOptions};
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg"><path d="M0 0 C30 40 70 40 100 0"/></svg>"#;
/// let drawing = read_svg(svg, &ImportOptions::default())?;
/// let weights = Shepard::new(&[Point::new(0.0, 0.0), Point::new(100.0, 0.0)], ShepardOptions::default());
/// let pose = [Affine::IDENTITY, Affine::rotate_about(0.6, Point::new(100.0, 0.0))];
/// let inputs = CompareInputs {
///     drawing: &drawing, weights: &weights, gradient: &weights,
///     fit: Default::default(), flexible: None, pose: &pose,
/// };
/// let c = compare_methods(&inputs, &CompareOptions::default())?;
/// assert_eq!(c.methods.len(), 6);
/// let energy = |m| c.get(m).unwrap().metrics.overall.energy;
/// assert!(energy(Method::Ours) < energy(Method::FourControls));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn compare_methods(
    inputs: &CompareInputs<'_>,
    options: &CompareOptions,
) -> Result<Comparison, CompareError> {
    let (drawing, weights, fit) = (inputs.drawing, inputs.weights, &inputs.fit);
    check_inputs(drawing, weights, inputs.pose, options)?;
    let solver = match inputs.flexible {
        Some(flex) => {
            let samples = SampledCurves::sample(drawing, weights, fit);
            Some(FlexibleSolver::new(drawing, &samples, fit, flex)?)
        }
        None => None,
    };
    let fixed_rig;
    let rig = match &solver {
        Some(s) => s.rig(),
        None => {
            fixed_rig = SplineRig::precompute(drawing, weights, fit)?;
            &fixed_rig
        }
    };
    compare_fits(inputs, rig, solver.as_ref(), options)
}

/// [`compare_methods`] on a posed drawing: its rig (and flexible solver, when its junctions
/// are flexible: then `ours-flexible` is compared too) are reused, not rebuilt; a posed
/// drawing whose engine is a naive baseline has no rig, and one is built. The Jacobian
/// baseline takes the analytic gradient of Shepard weights of point handles
/// ([`PosedDrawing::point_shepard`]), else central differences of the weights
/// ([`naive::FiniteDifferences`]).
///
/// ```
/// use kurbo::{Affine, Point};
/// use splineskin::compare::{compare_posed, CompareOptions, Method};
/// use splineskin::scene::{Compat, PosedDrawing, Scene};
/// let scene = Scene::from_json(r#"{"splineskin_scene": 1,
///     "svg_text": "<svg xmlns='http://www.w3.org/2000/svg'><path d='M0 0 C30 40 70 40 100 0'/></svg>",
///     "handles": [{"position": [0, 0]}, {"position": [100, 0]}]}"#, "inline", None)?;
/// let posed = PosedDrawing::from_scene(&scene, Compat::None, false)?;
/// let pose = [Affine::IDENTITY, Affine::rotate_about(0.6, Point::new(100.0, 0.0))];
/// let c = compare_posed(&posed, &pose, &CompareOptions::default())?;
/// let energy = |m| c.get(m).unwrap().metrics.overall.energy;
/// assert!(energy(Method::Ours) < energy(Method::FourControls));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn compare_posed(
    posed: &PosedDrawing,
    pose: &[Affine],
    options: &CompareOptions,
) -> Result<Comparison, CompareError> {
    let (drawing, weights, fit) = (posed.drawing(), posed.weights(), *posed.fit_options());
    check_inputs(drawing, weights, pose, options)?;
    let differences;
    let gradient: &dyn WeightGradient = match posed.point_shepard() {
        Some(s) => s,
        None => {
            differences = naive::FiniteDifferences::for_drawing(weights, drawing);
            &differences
        }
    };
    let inputs = CompareInputs {
        drawing,
        weights,
        gradient,
        fit,
        flexible: posed.flexible_solver().map(|s| *s.options()),
        pose,
    };
    let built;
    let rig = match posed.rig() {
        Some(rig) => rig,
        None => {
            built = SplineRig::precompute(drawing, weights, &fit)?;
            &built
        }
    };
    compare_fits(&inputs, rig, posed.flexible_solver(), options)
}

/// Errors unless `pose` has one map per weight function and the refit tolerance is positive
/// and finite in drawing units; returns that tolerance in drawing units.
fn check_inputs(
    drawing: &Drawing,
    weights: &dyn WeightField,
    pose: &[Affine],
    options: &CompareOptions,
) -> Result<f64, CompareError> {
    check_pose_len(pose, weights.n_handles())?;
    let tolerance = options.refit_tolerance;
    let refit_tolerance = tolerance * drawing.diagonal().max(f64::MIN_POSITIVE);
    if !(tolerance > 0.0 && refit_tolerance.is_finite() && refit_tolerance > 0.0) {
        return Err(CompareError::RefitTolerance(tolerance));
    }
    Ok(refit_tolerance)
}

/// The comparison of `inputs` with the fit's rig and, when given, its flexible solver (built
/// from the same drawing, weights and fit options).
fn compare_fits(
    inputs: &CompareInputs<'_>,
    rig: &SplineRig,
    solver: Option<&FlexibleSolver>,
    options: &CompareOptions,
) -> Result<Comparison, CompareError> {
    let (drawing, weights, gradient, pose) =
        (inputs.drawing, inputs.weights, inputs.gradient, inputs.pose);
    let refit_tolerance = check_inputs(drawing, weights, pose, options)?;
    let diagonal = drawing.diagonal();
    let metrics_options = options.metrics;
    let s = metrics_options.samples_per_curve.max(2);

    // The structured results, each in the rig's layout.
    let mut chains: Vec<(Method, Vec<Point>)> = Vec::new();
    let mut points = vec![Point::ZERO; drawing.n_points()];
    rig.update(pose, &mut points)?;
    chains.push((Method::Ours, points.clone()));
    if let Some(solver) = solver {
        solver.solve(pose, None, &mut points)?;
        chains.push((Method::OursFlexible, points.clone()));
    }
    naive::skin_control_points(drawing, weights, pose, &mut points)?;
    chains.push((Method::FourControls, points.clone()));
    naive::skin_on_curve_points(drawing, weights, pose, &mut points)?;
    chains.push((Method::TwoEndpoints, points.clone()));
    naive::skin_with_jacobian(drawing, gradient, pose, &mut points)?;
    chains.push((Method::Jacobian, points));

    let target = metrics::target_samples(drawing, weights, pose, s);
    let rest = drawing.flat_points();
    let mut methods = Vec::with_capacity(chains.len() + 1);
    for (method, points) in chains {
        let folds = Some(crate::folds::new_self_crossings(drawing, &rest, &points).len());
        let result = Refit::from_chains(drawing, &points).ok_or(PoseError::Output {
            got: points.len(),
            expected: drawing.n_points(),
        })?;
        check_finite(method, &result)?;
        let metrics = metrics::chain_metrics(drawing, weights, pose, &points, &metrics_options)
            .map_err(CompareError::metrics_of(method))?;
        let distances = metrics.distances.clone();
        let closest = metrics::refit_metrics(drawing, weights, pose, &result, &metrics_options)
            .map_err(CompareError::metrics_of(method))?;
        methods.push(MethodResult {
            method,
            result,
            metrics,
            closest,
            distances,
            folds,
        });
    }
    let refit_options = RefitOptions::default().with_tolerance(refit_tolerance);
    let refit = naive::schneider_refit(drawing, weights, pose, &refit_options)?;
    let (same_count, _) =
        naive::schneider_refit_same_count(drawing, weights, pose, &refit_options)?;
    for (method, refit) in [
        (Method::Schneider, refit),
        (Method::SchneiderSameCount, same_count),
    ] {
        check_finite(method, &refit)?;
        let metrics = metrics::refit_metrics(drawing, weights, pose, &refit, &metrics_options)
            .map_err(CompareError::metrics_of(method))?;
        let distances = metrics.distances.clone();
        methods.push(MethodResult {
            method,
            result: refit,
            closest: metrics.clone(),
            metrics,
            distances,
            folds: None,
        });
    }
    if let Some(adaptive) = &options.adaptive {
        let refined =
            crate::adaptive::refine(drawing, weights, &inputs.fit, &[pose.to_vec()], adaptive)?;
        let mut points = vec![Point::ZERO; refined.drawing.n_points()];
        refined.rig.update(pose, &mut points)?;
        let result = Refit::from_chains(&refined.drawing, &points).ok_or(PoseError::Output {
            got: points.len(),
            expected: refined.drawing.n_points(),
        })?;
        let budgets: Vec<usize> = refined.drawing.paths.iter().map(|p| p.n_curves()).collect();
        let rest = refined.drawing.flat_points();
        let folds = Some(crate::folds::new_self_crossings(&refined.drawing, &rest, &points).len());
        let (same, _) =
            naive::schneider_refit_within(drawing, weights, pose, &refit_options, &budgets)?;
        for (method, result, folds) in [
            (Method::OursAdaptive, result, folds),
            (Method::SchneiderAdaptiveCount, same, None),
        ] {
            check_finite(method, &result)?;
            let metrics = metrics::refit_metrics(drawing, weights, pose, &result, &metrics_options)
                .map_err(CompareError::metrics_of(method))?;
            let distances = metrics.distances.clone();
            methods.push(MethodResult {
                method,
                result,
                closest: metrics.clone(),
                metrics,
                distances,
                folds,
            });
        }
    }
    Ok(Comparison {
        methods,
        target,
        samples_per_curve: s,
        path_curves: drawing.paths.iter().map(|p| p.n_curves()).collect(),
        diagonal,
        refit_tolerance,
    })
}

/// The handles of `handles` moved by `pose` (rig order, one map each), as drawn in the
/// comparison: a point handle or cage vertex at `T_i p_i`, a bone from `T_i a` to `T_i b`.
/// Extra or missing maps are ignored (only the handles with a map are returned).
///
/// ```
/// use kurbo::{Affine, Point};
/// use splineskin::compare::posed_markers;
/// use splineskin::scene::HandleSet;
/// use splineskin::weight_map::HandleMarker;
/// let points = [Point::new(1.0, 0.0)];
/// let set = HandleSet { points: &points, bones: &[], cage: None };
/// let m = posed_markers(&set, &[Affine::translate((0.0, 2.0))]);
/// assert_eq!(m, [HandleMarker::Point(Point::new(1.0, 2.0))]);
/// ```
pub fn posed_markers(handles: &HandleSet<'_>, pose: &[Affine]) -> Vec<HandleMarker> {
    handles
        .markers()
        .into_iter()
        .zip(pose)
        .map(|(m, &t)| match m {
            HandleMarker::Point(p) => HandleMarker::Point(t * p),
            HandleMarker::Segment([a, b]) => HandleMarker::Segment([t * a, t * b]),
        })
        .collect()
}

fn check_finite(method: Method, result: &Refit) -> Result<(), CompareError> {
    match result.paths.iter().position(|p| {
        p.points
            .iter()
            .any(|q| !(q.x.is_finite() && q.y.is_finite()))
    }) {
        Some(path) => Err(CompareError::NotFinite {
            method: method.name(),
            path,
        }),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bezier;
    use crate::drawing::{read_svg, ImportOptions};
    use crate::weights::{Shepard, ShepardOptions};

    fn arc() -> (Drawing, Shepard) {
        let svg = r#"<svg xmlns="http://www.w3.org/2000/svg"><path d="M0 0 C30 40 70 40 100 0 S170 -40 200 0"/></svg>"#;
        let drawing = read_svg(svg, &ImportOptions::default()).unwrap();
        let handles = [
            Point::new(0.0, 0.0),
            Point::new(100.0, 0.0),
            Point::new(200.0, 0.0),
        ];
        (drawing, Shepard::new(&handles, ShepardOptions::default()))
    }

    #[test]
    fn compare_distances_are_what_the_metrics_measure() {
        let (drawing, weights) = arc();
        let pose = [
            Affine::IDENTITY,
            Affine::rotate_about(0.4, Point::new(100.0, 0.0)),
            Affine::translate((0.0, 30.0)),
        ];
        let inputs = CompareInputs {
            drawing: &drawing,
            weights: &weights,
            gradient: &weights,
            fit: FitOptions::default(),
            flexible: Some(FlexibleOptions::default()),
            pose: &pose,
        };
        let c = compare_methods(&inputs, &CompareOptions::default()).unwrap();
        let names: Vec<&str> = c.methods.iter().map(|m| m.method.name()).collect();
        assert_eq!(
            names,
            [
                "ours",
                "ours-flexible",
                "fourcontrols",
                "twoendpoints",
                "jacobian",
                "schneider",
                "schneider-same-count"
            ]
        );
        assert_eq!(c.target.len(), 2 * c.samples_per_curve);
        let s = c.samples_per_curve;
        for m in &c.methods {
            if m.method.keeps_structure() {
                // Parametric: the distance at t_k of curve j is ‖R_j(t_k) − target[j S + k]‖.
                for (i, &d) in m.distances.iter().enumerate() {
                    let (j, k) = (i / s, i % s);
                    let p = &m.result.paths[0].points[3 * j..3 * j + 4];
                    let r = bezier::eval(&[p[0], p[1], p[2], p[3]], k as f64 / (s - 1) as f64);
                    assert_eq!(d, (r - c.target[i]).hypot(), "{:?} sample {i}", m.method);
                }
            } else {
                // Closest point: never further than the nearest of dense samples of the refit.
                for (i, &d) in m.distances.iter().enumerate() {
                    let dense = m.result.paths[0]
                        .points
                        .windows(4)
                        .step_by(3)
                        .flat_map(|p| {
                            (0..=200).map(move |k| {
                                bezier::eval(&[p[0], p[1], p[2], p[3]], f64::from(k) / 200.0)
                            })
                        });
                    let sampled = dense
                        .map(|q| (q - c.target[i]).hypot())
                        .fold(f64::INFINITY, f64::min);
                    assert!(
                        d <= sampled + 1e-9 * c.diagonal,
                        "{:?} sample {i}",
                        m.method
                    );
                }
            }
            // The largest sampled distance is the metrics' max (the same samples, the same
            // arithmetic, up to the rounding of dividing by the diagonal), and the RMS pools
            // the same squares.
            let max = m.distances.iter().fold(0.0, |a: f64, &d| a.max(d));
            let relative = (max / c.diagonal - m.metrics.overall.max).abs() / max;
            assert!(relative < 1e-14, "{:?}", m.method);
            let rms =
                (m.distances.iter().map(|d| d * d).sum::<f64>() / m.distances.len() as f64).sqrt();
            assert!((rms / c.diagonal - m.metrics.overall.rms).abs() < 1e-15);
        }
        let energy = |m| c.get(m).unwrap().metrics.overall.energy;
        assert!(energy(Method::OursFlexible) <= energy(Method::Ours));
        for m in [Method::FourControls, Method::TwoEndpoints, Method::Jacobian] {
            assert!(energy(Method::Ours) < energy(m), "{m:?}");
        }
        // The refit is within its tolerance at its own samples, so near the target.
        let refit = c.get(Method::Schneider).unwrap();
        assert!(c.refit_tolerance == 1e-3 * c.diagonal);
        assert!(
            refit.metrics.overall.max < 5e-3,
            "{:?}",
            refit.metrics.overall
        );
    }

    #[test]
    fn compare_rejects_bad_pose_and_tolerance() {
        let (drawing, weights) = arc();
        let pose = [Affine::IDENTITY; 2];
        let inputs = CompareInputs {
            drawing: &drawing,
            weights: &weights,
            gradient: &weights,
            fit: FitOptions::default(),
            flexible: None,
            pose: &pose,
        };
        assert!(matches!(
            compare_methods(&inputs, &CompareOptions::default()),
            Err(CompareError::Pose(PoseError::Transforms {
                got: 2,
                expected: 3
            }))
        ));
        let pose = [Affine::IDENTITY; 3];
        let inputs = CompareInputs {
            pose: &pose,
            ..inputs
        };
        for t in [0.0, -1.0, f64::NAN] {
            assert!(matches!(
                compare_methods(&inputs, &CompareOptions::default().with_refit_tolerance(t)),
                Err(CompareError::RefitTolerance(_))
            ));
        }
    }
}
