//! [`Deformer`]: the engine inside a [`super::PosedDrawing`] — what turns a pose into deformed
//! control points: the spline fit's rig (one matrix–vector product per pose), the flexible
//! solve (G¹ and fixed-angle ratios free, [`crate::spline_fit::flexible`]), or one of the
//! paper's naive baselines ([`crate::naive`]) when the scene's engine asks for it. It holds no
//! drawing and no weights: [`super::PosedDrawing`] owns them with it, and its
//! [`super::PosedDrawing::update`] is the way to apply a pose.

use super::compat::Compat;
use super::setup::Setup;
use super::{Engine, Scene, SceneError};
use crate::drawing::Drawing;
use crate::spline_fit::quadrature::SampledCurves;
use crate::spline_fit::{FitError, FitOptions, FlexibleOptions, FlexibleSolver, SplineRig};
use crate::weights::{Shepard, WeightField};

/// How a scene's poses are applied.
pub enum Deformer {
    /// The spline fit with every junction's ratio fixed: [`SplineRig::update`].
    Fixed(SplineRig),
    /// The spline fit with flexible G¹ and fixed-angle junctions:
    /// [`FlexibleSolver::solve`], from the rig's result.
    Flexible(Box<FlexibleSolver>),
    /// A naive baseline (the scene's engine is not `ours`).
    Naive {
        /// Which one: [`Engine::FourControls`], [`Engine::TwoEndpoints`] or
        /// [`Engine::Jacobian`].
        engine: Engine,
        /// The scene's Shepard weights as a [`Shepard`] when they are Shepard weights of point
        /// handles: the Jacobian baseline's analytic gradient. Otherwise the Jacobian uses
        /// central differences of the setup's weights.
        shepard: Option<Shepard>,
    },
}

impl Deformer {
    /// The deformer of `scene` set up as `setup` in `compat`: a naive baseline when the
    /// scene's engine is one, else the flexible solve when `flexible` is `true` or the scene
    /// asks for it ([`Scene::flexible_options`]; the mode's default options when only
    /// `flexible` asks), else the rig. Errors: `flexible` with a naive engine, or a rig that
    /// cannot be built (naming the scene).
    ///
    /// [`super::PosedDrawing::new`] builds the same engine and keeps it with the setup.
    ///
    /// ```
    /// use kurbo::{Affine, Point};
    /// use splineskin::scene::{Compat, Deformer, Scene};
    /// let scene = Scene::from_json(r#"{"splineskin_scene": 1, "engine": "fourcontrols",
    ///     "svg_text": "<svg xmlns='http://www.w3.org/2000/svg'><path d='M0 0 C1 1 2 1 3 0'/></svg>",
    ///     "handles": [{"position": [0, 0]}]}"#, "inline", None)?;
    /// let setup = scene.setup(Compat::None)?;
    /// let deformer = Deformer::new(&scene, &setup, Compat::None, false)?;
    /// let mut out = vec![Point::ZERO; setup.drawing.n_points()];
    /// deformer.deform(&setup, &[Affine::translate((1.0, 0.0))], &mut out)?;
    /// assert_eq!(out[0], Point::new(1.0, 0.0));
    /// # Ok::<(), Box<dyn std::error::Error + Send + Sync>>(())
    /// ```
    pub fn new(
        scene: &Scene,
        setup: &Setup,
        compat: Compat,
        flexible: bool,
    ) -> Result<Deformer, SceneError> {
        Deformer::for_engine(scene, setup, compat, scene.engine, flexible)
    }

    /// [`Deformer::new`] with `engine` in place of the scene's (e.g. [`Engine::Ours`] to fit
    /// a scene whose engine is a naive baseline).
    pub fn for_engine(
        scene: &Scene,
        setup: &Setup,
        compat: Compat,
        engine: Engine,
        flexible: bool,
    ) -> Result<Deformer, SceneError> {
        if engine != Engine::Ours {
            if flexible {
                return Err(SceneError::Invalid {
                    origin: scene.origin.clone(),
                    element: "engine".into(),
                    message: format!(
                        "flexible junctions apply to engine 'ours'; this scene's engine is '{}'",
                        engine.name()
                    ),
                });
            }
            return Ok(Deformer::Naive {
                engine,
                shepard: scene.point_shepard(compat),
            });
        }
        let flexible = scene.flexible_options_or(flexible, compat);
        Deformer::fit(
            &setup.drawing,
            setup.weights.as_ref(),
            &setup.options,
            flexible,
        )
        .map_err(|e| SceneError::Rig {
            origin: scene.origin.clone(),
            source: Box::new(e),
        })
    }

    /// The spline fit of `drawing` with `weights` and `fit`: the flexible solver when
    /// `flexible` options are given ([`FlexibleSolver::new`] on the weights sampled at the
    /// quadrature nodes), else the fixed-ratio rig ([`SplineRig::precompute`]).
    pub fn fit(
        drawing: &Drawing,
        weights: &dyn WeightField,
        fit: &FitOptions,
        flexible: Option<FlexibleOptions>,
    ) -> Result<Deformer, FitError> {
        Ok(match flexible {
            Some(options) => {
                let samples = SampledCurves::sample(drawing, weights, fit);
                Deformer::Flexible(Box::new(FlexibleSolver::new(
                    drawing, &samples, fit, options,
                )?))
            }
            None => Deformer::Fixed(SplineRig::precompute(drawing, weights, fit)?),
        })
    }

    /// The rig (`None` for a naive baseline).
    pub fn rig(&self) -> Option<&SplineRig> {
        match self {
            Deformer::Fixed(rig) => Some(rig),
            Deformer::Flexible(solver) => Some(solver.rig()),
            Deformer::Naive { .. } => None,
        }
    }

    /// The flexible solver (`None` unless junctions are flexible).
    pub fn flexible_solver(&self) -> Option<&FlexibleSolver> {
        match self {
            Deformer::Flexible(solver) => Some(solver),
            _ => None,
        }
    }

    /// The engine: [`Engine::Ours`] for the fit, flexible or not, else the baseline's.
    pub fn engine(&self) -> Engine {
        match self {
            Deformer::Naive { engine, .. } => *engine,
            _ => Engine::Ours,
        }
    }
}
