//! [`PosedDrawing`]: one drawing and everything that poses it — the drawing with its junction
//! kinds, its weights (and their domain, for the mesh families), the fit options, and the
//! engine ([`Deformer`]): the spline fit's rig, the flexible solver, or a naive baseline.
//! `deform`, `animate`, `compare`, `bench` and the editor (through [`super::Puppet`], the
//! editable layer over it) pose drawings with it.
//!
//! ```text
//! once:        let posed = PosedDrawing::from_scene(&scene, Compat::None, false)?;
//! each frame:  let report = posed.update(&pose, &mut points)?;
//! ```
//!
//! [`PosedDrawing::update`] is the one place where a result is checked on its way out: every
//! deformed point must be finite. A rank-deficient system solved without a fallback (as the
//! authors' code does, in compatibility mode) can give NaN, which no output format can hold;
//! the error names the first path concerned, its SVG element and why. With the fixed-ratio rig
//! an update is one matrix–vector product and that check, and allocates nothing; the check
//! costs `O(h)` there when a bound proves the product finite ([`finite_product_bound`]).

use kurbo::{Affine, Point};

use super::compat::Compat;
use super::deformer::Deformer;
use super::setup::Setup;
use super::{Engine, Scene, SceneError};
use crate::domain::Domain;
use crate::drawing::Drawing;
use crate::naive::{self, FiniteDifferences};
use crate::spline_fit::{
    FitOptions, FlexibleError, FlexibleReport, FlexibleSolver, PoseError, SplineRig,
};
use crate::weights::{Shepard, WeightField};

/// A drawing with its weights and the engine that poses it (module doc).
///
/// ```
/// use kurbo::{Affine, Point};
/// use splineskin::scene::{Compat, PosedDrawing, Scene};
/// let scene = Scene::from_json(r#"{"splineskin_scene": 1,
///     "svg_text": "<svg xmlns='http://www.w3.org/2000/svg'><path d='M0 0 C1 1 2 1 3 0'/></svg>",
///     "handles": [{"position": [0, 0]}, {"position": [3, 0]}]}"#, "inline", None)?;
/// let posed = PosedDrawing::from_scene(&scene, Compat::None, false)?;
/// let mut points = vec![Point::ZERO; posed.n_points()];
/// // The same map on every handle moves the drawing by exactly that map.
/// let report = posed.update(&[Affine::translate((2.0, 1.0)); 2], &mut points)?;
/// assert!(report.flexible.is_none() && report.note().is_none());
/// assert!((points[3] - Point::new(5.0, 1.0)).hypot() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct PosedDrawing {
    origin: String,
    setup: Setup,
    deformer: Deformer,
    /// The scene's weights as an analytic [`Shepard`] field when they are Shepard weights of
    /// point handles (the Jacobian baseline's gradient).
    shepard: Option<Shepard>,
    /// [`finite_product_bound`] of the fixed-ratio rig (`None`: scan every result).
    bound: Option<f64>,
}

/// How a scene is posed ([`PosedDrawing::of_scene`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PoseOptions {
    /// The discretisation: ours, or another implementation's ([`Compat`]).
    pub compat: Compat,
    /// Flexible G¹ and fixed-angle junctions even where the scene does not ask for them
    /// (a command line's `--flexible`; [`Scene::flexible_options_or`]).
    pub flexible: bool,
    /// Whether the per-frame product may use a second thread on big operators
    /// ([`crate::spline_fit::FitOptions::parallel`]): not for a frame loop that is itself
    /// parallel, nor in a page's one-thread WebAssembly.
    pub parallel: bool,
}

impl PosedDrawing {
    /// `scene` set up ([`Scene::setup`]) and rigged ([`PosedDrawing::new`]) under `options`:
    /// the one way from a scene to its per-frame update. What the user should know about the
    /// result is [`PosedDrawing::warnings`].
    ///
    /// ```
    /// use kurbo::Point;
    /// use splineskin::scene::{PoseOptions, PosedDrawing};
    /// let scene = splineskin::examples::demo_scene();
    /// let posed = PosedDrawing::of_scene(&scene, PoseOptions::default())?;
    /// let mut points = vec![Point::ZERO; posed.n_points()];
    /// posed.update(&scene.pose(0).expect("a pose").transforms, &mut points)?;
    /// assert!(posed.warnings().is_empty());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn of_scene(scene: &Scene, options: PoseOptions) -> Result<PosedDrawing, SceneError> {
        let mut setup = scene.setup(options.compat)?;
        setup.options = setup.options.with_parallel(options.parallel);
        PosedDrawing::new(scene, setup, options.compat, options.flexible)
    }

    /// What the user should know about the posed drawing: the setup's warnings (saved
    /// junction kinds that do not fit the drawing, [`Setup::warnings`]) and one line per path
    /// whose system is rank deficient (its result is not unique).
    pub fn warnings(&self) -> Vec<String> {
        let rank = self.rank_deficient_paths().iter().map(|p| {
            format!("path {p}: its system is rank deficient (a curve with no length); its result is not unique")
        });
        self.setup.warnings.iter().cloned().chain(rank).collect()
    }

    /// [`PosedDrawing::of_scene`] with the per-frame product on one thread.
    pub fn from_scene(
        scene: &Scene,
        compat: Compat,
        flexible: bool,
    ) -> Result<PosedDrawing, SceneError> {
        let options = PoseOptions {
            compat,
            flexible,
            parallel: false,
        };
        PosedDrawing::of_scene(scene, options)
    }

    /// Keeps `setup` (of `scene`, in `compat`) with the engine the scene asks for: a naive
    /// baseline when the scene's engine is one, else the flexible solve when `flexible` is
    /// `true` or the scene asks for it ([`Scene::flexible_options_or`]), else the fixed-ratio
    /// rig. Errors: `flexible` with a naive engine, or a rig that cannot be built (naming the
    /// scene).
    pub fn new(
        scene: &Scene,
        setup: Setup,
        compat: Compat,
        flexible: bool,
    ) -> Result<PosedDrawing, SceneError> {
        PosedDrawing::with_engine(scene, setup, compat, scene.engine, flexible)
    }

    /// [`PosedDrawing::new`] with `engine` in place of the scene's (`compare` fits every
    /// scene, whatever its engine).
    pub fn with_engine(
        scene: &Scene,
        setup: Setup,
        compat: Compat,
        engine: Engine,
        flexible: bool,
    ) -> Result<PosedDrawing, SceneError> {
        let deformer = Deformer::for_engine(scene, &setup, compat, engine, flexible)?;
        Ok(PosedDrawing {
            origin: scene.origin.clone(),
            setup,
            bound: finite_product_bound(&deformer),
            deformer,
            shepard: scene.point_shepard(compat),
        })
    }

    /// Joins a setup and an engine built from it (by [`Deformer::fit`], or a rig built from
    /// the same drawing, weights and fit options). `origin` names the drawing in messages.
    /// The Jacobian baseline, if it is the engine, takes the gradient the deformer carries.
    pub fn from_parts(origin: impl Into<String>, setup: Setup, deformer: Deformer) -> Self {
        let shepard = match &deformer {
            Deformer::Naive { shepard, .. } => shepard.clone(),
            _ => None,
        };
        PosedDrawing {
            origin: origin.into(),
            setup,
            bound: finite_product_bound(&deformer),
            deformer,
            shepard,
        }
    }

    /// Gives back the setup (drawing, weights, fit options), dropping the engine.
    pub fn into_setup(self) -> Setup {
        self.setup
    }

    /// Writes the drawing deformed by `pose` (one map per handle, rig order) into `out`
    /// (length [`PosedDrawing::n_points`], layout of [`Drawing::flat_points`]) and says what
    /// was done. The flexible solve starts from the rig's result (a cold start).
    ///
    /// Errors: a pose or buffer of the wrong size, a flexible solve that fails, or a result
    /// that is not finite ([`UpdateError::NotFinite`]: then `out` holds it, but nothing should
    /// be written from it). With the fixed-ratio rig this allocates nothing.
    pub fn update(&self, pose: &[Affine], out: &mut [Point]) -> Result<PoseReport, UpdateError> {
        self.update_from(pose, None, out)
    }

    /// [`PosedDrawing::update`], the flexible solve warm-started from `warm` (a previous
    /// result, same layout: a drag moves the pose a little between frames;
    /// [`FlexibleSolver::solve`]). The other engines ignore `warm`.
    pub fn update_from(
        &self,
        pose: &[Affine],
        warm: Option<&[Point]>,
        out: &mut [Point],
    ) -> Result<PoseReport, UpdateError> {
        let (drawing, weights) = (&self.setup.drawing, self.setup.weights.as_ref());
        pose_drawing(
            &self.deformer,
            drawing,
            weights,
            (pose, warm),
            self.bound,
            out,
        )
    }

    /// Where the drawing came from (the scene's origin), for messages.
    pub fn origin(&self) -> &str {
        &self.origin
    }

    /// The setup: drawing, weights, fit options, warnings, domain.
    pub fn setup(&self) -> &Setup {
        &self.setup
    }

    /// The drawing (with its junction kinds).
    pub fn drawing(&self) -> &Drawing {
        &self.setup.drawing
    }

    /// The weights, one function per handle.
    pub fn weights(&self) -> &dyn WeightField {
        self.setup.weights.as_ref()
    }

    /// The triangulated domain of the weights (mesh families only).
    pub fn domain(&self) -> Option<&Domain> {
        self.setup.domain.as_ref()
    }

    /// The fit options.
    pub fn fit_options(&self) -> &FitOptions {
        &self.setup.options
    }

    /// The engine.
    pub fn deformer(&self) -> &Deformer {
        &self.deformer
    }

    /// Which engine deforms: [`Engine::Ours`] for the fit, flexible or not.
    pub fn engine(&self) -> Engine {
        self.deformer.engine()
    }

    /// The fixed-ratio rig (also the flexible solve's start); `None` for a naive baseline.
    pub fn rig(&self) -> Option<&SplineRig> {
        self.deformer.rig()
    }

    /// The flexible solver, when junctions are flexible.
    pub fn flexible_solver(&self) -> Option<&FlexibleSolver> {
        self.deformer.flexible_solver()
    }

    /// Whether G¹ and fixed-angle junctions are flexible.
    pub fn is_flexible(&self) -> bool {
        self.flexible_solver().is_some()
    }

    /// The weights as an analytic Shepard field, when they are Shepard weights of point
    /// handles (the Jacobian baseline's gradient; otherwise it takes central differences).
    pub fn point_shepard(&self) -> Option<&Shepard> {
        self.shepard.as_ref()
    }

    /// Paths whose fit system is rank deficient ([`SplineRig::rank_deficient_paths`]; none for
    /// a naive baseline): their result is not unique.
    pub fn rank_deficient_paths(&self) -> &[usize] {
        self.rig().map(|r| r.rank_deficient_paths()).unwrap_or(&[])
    }

    /// Number of handles (maps in a pose).
    pub fn n_handles(&self) -> usize {
        self.setup.weights.n_handles()
    }

    /// Number of chain points an update writes.
    pub fn n_points(&self) -> usize {
        self.setup.drawing.n_points()
    }
}

/// What one [`PosedDrawing::update`] did.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct PoseReport {
    /// The engine that deformed the drawing.
    pub engine: Engine,
    /// Flexible G¹ and fixed-angle junctions over all paths (0 unless junctions are
    /// flexible).
    pub flexible_junctions: usize,
    /// The flexible solve's report (paths iterated, steps, energies), when junctions are
    /// flexible.
    pub flexible: Option<FlexibleReport>,
}

impl PoseReport {
    /// What a user is told about the update, `None` for the fixed-ratio fit:
    /// `flexible: J junctions on P paths, S steps, energy E₀ -> E` (E₀ the fixed-ratio
    /// result's energy, E the flexible one's) or `engine NAME (a naive baseline)`.
    ///
    /// ```
    /// use splineskin::scene::{Compat, PosedDrawing, Scene};
    /// let scene = Scene::from_json(r#"{"splineskin_scene": 1, "engine": "jacobian",
    ///     "svg_text": "<svg xmlns='http://www.w3.org/2000/svg'><path d='M0 0 C1 1 2 1 3 0'/></svg>",
    ///     "handles": [{"position": [0, 0]}]}"#, "inline", None)?;
    /// let posed = PosedDrawing::from_scene(&scene, Compat::None, false)?;
    /// let mut points = vec![kurbo::Point::ZERO; posed.n_points()];
    /// let report = posed.update(&[kurbo::Affine::IDENTITY], &mut points)?;
    /// assert_eq!(report.note().as_deref(), Some("engine jacobian (a naive baseline)"));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn note(&self) -> Option<String> {
        if let Some(report) = &self.flexible {
            return Some(format!(
                "flexible: {} junctions on {} paths, {} steps, energy {:.4e} -> {:.4e}",
                self.flexible_junctions,
                report.paths,
                report.steps,
                report.fixed_ratio_energy,
                report.energy()
            ));
        }
        (self.engine != Engine::Ours)
            .then(|| format!("engine {} (a naive baseline)", self.engine.name()))
    }
}

/// Why a [`PosedDrawing::update`] gave no result.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum UpdateError {
    /// The rig refused the pose or the output buffer (wrong sizes).
    #[error(transparent)]
    Pose(#[from] PoseError),
    /// The flexible solve failed.
    #[error("flexible solve: {0}")]
    Flexible(#[from] FlexibleError),
    /// A naive baseline refused the pose or the output buffer.
    #[error("engine '{}': {source}", .engine.name())]
    Naive {
        /// The baseline.
        engine: Engine,
        /// What it refused.
        source: PoseError,
    },
    /// A deformed point is not finite.
    #[error(
        "path {path}{}: deformed points are not finite (expected finite coordinates): {}",
        in_parentheses(.element),
        not_finite_reason(*.rank_deficient)
    )]
    NotFinite {
        /// The first path with such a point.
        path: usize,
        /// Its SVG element, when the drawing was read from a document.
        element: Option<String>,
        /// Whether the path's fit system is rank deficient (the likely cause).
        rank_deficient: bool,
    },
}

fn in_parentheses(element: &Option<String>) -> String {
    element
        .as_ref()
        .map(|e| format!(" ({e})"))
        .unwrap_or_default()
}

fn not_finite_reason(rank_deficient: bool) -> &'static str {
    if rank_deficient {
        "its fit system is rank deficient, e.g. a curve of zero length"
    } else {
        "the fit is numerically unstable"
    }
}

impl Deformer {
    /// Writes the drawing of `setup` deformed by `pose` (one map per handle) into `out`
    /// (length [`crate::drawing::Drawing::n_points`]): [`super::PosedDrawing::update`]'s work
    /// (a result that is not finite is an error) for a setup kept apart from its deformer.
    pub fn deform(
        &self,
        setup: &Setup,
        pose: &[Affine],
        out: &mut [Point],
    ) -> Result<(), Box<dyn std::error::Error + Send + Sync>> {
        let (drawing, weights) = (&setup.drawing, setup.weights.as_ref());
        pose_drawing(self, drawing, weights, (pose, None), None, out)?;
        Ok(())
    }
}

/// Deforms `drawing` (weighted by `weights`) by `pose` (and the flexible solve's `warm` start)
/// with `deformer` into `out`, then checks that the result is finite — unless `bound`
/// ([`finite_product_bound`] of the deformer) proves it: the work of
/// [`PosedDrawing::update_from`] and [`Deformer::deform`].
pub(super) fn pose_drawing(
    deformer: &Deformer,
    drawing: &Drawing,
    weights: &dyn WeightField,
    (pose, warm): (&[Affine], Option<&[Point]>),
    bound: Option<f64>,
    out: &mut [Point],
) -> Result<PoseReport, UpdateError> {
    let mut report = PoseReport {
        engine: deformer.engine(),
        flexible_junctions: 0,
        flexible: None,
    };
    match deformer {
        Deformer::Fixed(rig) => rig.update(pose, out)?,
        Deformer::Flexible(solver) => {
            report.flexible = Some(solver.solve(pose, warm, out)?);
            report.flexible_junctions = solver.n_flexible_junctions();
        }
        Deformer::Naive { engine, shepard } => {
            skin_naive(*engine, drawing, weights, shepard.as_ref(), pose, out).map_err(
                |source| UpdateError::Naive {
                    engine: *engine,
                    source,
                },
            )?
        }
    }
    if !bound.is_some_and(|b| keeps_finite(pose, b)) {
        check_finite(drawing, out, deformer.rig())?;
    }
    Ok(report)
}

/// Largest pose coefficient times [`finite_product_bound`] below which the rig's product is
/// finite without looking: a quarter of `f64::MAX`, far more than the rounding of a sum of
/// `6h` terms can add.
const FINITE_PRODUCT_LIMIT: f64 = 0.25 * f64::MAX;

/// For the fixed-ratio rig, `B = max_r Σ_c |O_rc|` over the rows of its operator `O`
/// ([`SplineRig::operator`]). A point coordinate is `x_r = Σ_c O_rc t_c` with `t` the pose's
/// coefficients, so `|x_r| ≤ m B` where `m = max_c |t_c|`: a finite pose with
/// `m B ≤` [`FINITE_PRODUCT_LIMIT`] gives finite points and [`PosedDrawing::update`] need not
/// scan them. `None` for the other engines, or when `B` is not finite (a rank-deficient system
/// solved without a fallback can leave NaN in `O`).
fn finite_product_bound(deformer: &Deformer) -> Option<f64> {
    let Deformer::Fixed(rig) = deformer else {
        return None;
    };
    let n_cols = 6 * rig.n_handles();
    let bound = rig
        .operator()
        .chunks_exact(n_cols.max(1))
        .map(|row| row.iter().map(|o| o.abs()).sum::<f64>())
        .fold(0.0, f64::max);
    let all_finite = rig.operator().iter().all(|o| o.is_finite());
    (all_finite && bound.is_finite()).then_some(bound)
}

/// Whether every coefficient of `pose` is finite and the largest, times `bound`
/// ([`finite_product_bound`]), is at most [`FINITE_PRODUCT_LIMIT`].
fn keeps_finite(pose: &[Affine], bound: f64) -> bool {
    let mut largest = 0.0f64;
    for c in pose.iter().flat_map(|t| t.as_coeffs()) {
        if !c.is_finite() {
            return false;
        }
        largest = largest.max(c.abs());
    }
    largest * bound <= FINITE_PRODUCT_LIMIT
}

/// Applies the naive baseline `engine` ([`crate::naive`]); the Jacobian takes the analytic
/// gradient of `shepard` when given, else central differences of `weights`.
fn skin_naive(
    engine: Engine,
    drawing: &Drawing,
    weights: &dyn WeightField,
    shepard: Option<&Shepard>,
    pose: &[Affine],
    out: &mut [Point],
) -> Result<(), PoseError> {
    match (engine, shepard) {
        (Engine::FourControls, _) => naive::skin_control_points(drawing, weights, pose, out),
        (Engine::TwoEndpoints, _) => naive::skin_on_curve_points(drawing, weights, pose, out),
        (_, Some(shepard)) => naive::skin_with_jacobian(drawing, shepard, pose, out),
        (_, None) => {
            let gradient = FiniteDifferences::for_drawing(weights, drawing);
            naive::skin_with_jacobian(drawing, &gradient, pose, out)
        }
    }
}

/// Errors, naming the first path concerned, if a point of `points` (the layout of
/// [`Drawing::flat_points`]) is not finite.
fn check_finite(
    drawing: &Drawing,
    points: &[Point],
    rig: Option<&SplineRig>,
) -> Result<(), UpdateError> {
    if points
        .iter()
        .fold(true, |ok, p| ok & p.x.is_finite() & p.y.is_finite())
    {
        return Ok(());
    }
    let path = drawing
        .path_ranges()
        .position(|r| {
            points
                .get(r)
                .is_none_or(|ps| !ps.iter().all(|p| p.is_finite()))
        })
        .unwrap_or(0);
    Err(UpdateError::NotFinite {
        path,
        element: drawing.source.as_ref().map(|s| s.element_label(path)),
        rank_deficient: rig.is_some_and(|r| r.rank_deficient_paths().contains(&path)),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(extra: &str) -> Scene {
        let json = format!(
            r#"{{"splineskin_scene": 1{extra},
            "svg_text": "<svg xmlns='http://www.w3.org/2000/svg'><path d='M0 0 C30 40 70 40 100 0 C160 -80 170 -40 200 0'/><path d='M0 500 L200 500'/></svg>",
            "handles": [{{"position": [0, 0]}}, {{"position": [200, 0]}}]}}"#
        );
        Scene::from_json(&json, "posed.json", None).unwrap()
    }

    fn pose() -> [Affine; 2] {
        [
            Affine::IDENTITY,
            Affine::rotate_about(0.6, Point::new(200.0, 0.0)),
        ]
    }

    /// Each engine's update gives exactly what that engine gives on its own, and the report
    /// says which ran.
    #[test]
    fn posed_update_is_the_engine_result() {
        let s = scene("");
        let posed = PosedDrawing::from_scene(&s, Compat::None, false).unwrap();
        let setup = s.setup(Compat::None).unwrap();
        let rig =
            SplineRig::precompute(&setup.drawing, setup.weights.as_ref(), &setup.options).unwrap();
        let n = posed.n_points();
        let (mut out, mut expected) = (vec![Point::ZERO; n], vec![Point::ZERO; n]);
        let report = posed.update(&pose(), &mut out).unwrap();
        rig.update(&pose(), &mut expected).unwrap();
        assert_eq!(out, expected);
        assert_eq!((report.engine, report.flexible), (Engine::Ours, None));

        let flexible = PosedDrawing::from_scene(&s, Compat::None, true).unwrap();
        let report = flexible.update(&pose(), &mut out).unwrap();
        let solver = flexible.flexible_solver().unwrap();
        solver.solve(&pose(), None, &mut expected).unwrap();
        assert_eq!(out, expected);
        assert_eq!(report.flexible_junctions, 1);
        let note = report.note().unwrap();
        assert!(
            note.starts_with("flexible: 1 junctions on 1 paths"),
            "{note}"
        );

        let naive = scene(r#", "engine": "fourcontrols""#);
        let posed = PosedDrawing::from_scene(&naive, Compat::None, false).unwrap();
        let report = posed.update(&pose(), &mut out).unwrap();
        naive::skin_control_points(
            &setup.drawing,
            setup.weights.as_ref(),
            &pose(),
            &mut expected,
        )
        .unwrap();
        assert_eq!(out, expected);
        assert_eq!(report.engine, Engine::FourControls);
        assert!(posed.rig().is_none() && posed.rank_deficient_paths().is_empty());
    }

    /// A result that is not finite is refused, naming the first path with such a point and
    /// its element; wrong sizes are refused as the engine refuses them.
    #[test]
    fn posed_update_refuses_points_that_are_not_finite() {
        let posed = PosedDrawing::from_scene(&scene(""), Compat::None, false).unwrap();
        let mut out = vec![Point::ZERO; posed.n_points()];
        // A vertical stretch by 1e306 keeps the first path (|y| ≤ 80) finite and sends the
        // second (y = 500) beyond f64::MAX.
        let far = Affine::new([1.0, 0.0, 0.0, 1e306, 0.0, 0.0]);
        let e = posed.update(&[far, far], &mut out).unwrap_err();
        let text = e.to_string();
        assert!(
            matches!(e, UpdateError::NotFinite { path: 1, .. }),
            "{text}"
        );
        assert!(
            text.starts_with("path 1 (")
                && text.contains("deformed points are not finite (expected finite coordinates)")
                && text.contains("numerically unstable"),
            "{text}"
        );
        let e = posed.update(&pose()[..1], &mut out).unwrap_err();
        assert!(matches!(
            e,
            UpdateError::Pose(PoseError::Transforms {
                got: 1,
                expected: 2
            })
        ));
        let e = posed.update(&pose(), &mut out[1..]).unwrap_err();
        assert!(matches!(e, UpdateError::Pose(PoseError::Output { .. })));
        // A NaN coefficient is not covered by the bound: the result is scanned and refused.
        let nan = Affine::new([1.0, 0.0, 0.0, 1.0, f64::NAN, 0.0]);
        let e = posed
            .update(&[Affine::IDENTITY, nan], &mut out)
            .unwrap_err();
        assert!(matches!(e, UpdateError::NotFinite { path: 0, .. }), "{e}");
    }

    /// The bound that lets the fixed rig's update skip its scan holds: every coordinate of a
    /// result is at most the largest pose coefficient times the bound, and poses near the
    /// limit are still scanned.
    #[test]
    fn posed_finite_product_bound_bounds_the_points() {
        let posed = PosedDrawing::from_scene(&scene(""), Compat::None, false).unwrap();
        let bound = finite_product_bound(posed.deformer()).unwrap();
        // The drawing reaches y = 500 and the identity reproduces it: B ≥ 500.
        assert!(bound >= 500.0, "{bound}");
        let mut out = vec![Point::ZERO; posed.n_points()];
        for pose in [pose(), [Affine::new([3.0, -2.0, 0.5, 7.0, -40.0, 9.0]); 2]] {
            posed.update(&pose, &mut out).unwrap();
            let m = pose
                .iter()
                .flat_map(|t| t.as_coeffs())
                .fold(0.0f64, |m, c| m.max(c.abs()));
            let largest = out
                .iter()
                .fold(0.0f64, |l, p| l.max(p.x.abs()).max(p.y.abs()));
            assert!(largest <= m * bound, "{largest} > {m} · {bound}");
            assert!(keeps_finite(&pose, bound));
        }
        let huge = Affine::scale(FINITE_PRODUCT_LIMIT / bound * 2.0);
        assert!(!keeps_finite(&[huge; 2], bound));
    }
}
