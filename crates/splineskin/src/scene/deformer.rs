//! [`Deformer`]: what turns a scene's pose into deformed control points, chosen from the scene —
//! the spline fit's rig (one matrix–vector product per pose), the flexible solve (G¹ and
//! fixed-angle ratios free, [`crate::spline_fit::flexible`]), or one of the paper's naive
//! baselines ([`crate::naive`]) when the scene's engine asks for it. `deform`, `animate` and
//! anything else that applies poses share it.

use kurbo::{Affine, Point};

use super::setup::{Compat, Setup};
use super::{Engine, Scene, SceneError};
use crate::naive::{self, FiniteDifferences};
use crate::spline_fit::quadrature::SampledCurves;
use crate::spline_fit::{FlexibleSolver, SplineRig};
use crate::weights::Shepard;

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
        let rig_error = |e: crate::spline_fit::FitError| SceneError::Rig {
            origin: scene.origin.clone(),
            source: Box::new(e),
        };
        if scene.engine != Engine::Ours {
            if flexible {
                return Err(SceneError::Invalid {
                    origin: scene.origin.clone(),
                    element: "engine".into(),
                    message: format!(
                        "flexible junctions apply to engine 'ours'; this scene's engine is '{}'",
                        scene.engine.name()
                    ),
                });
            }
            return Ok(Deformer::Naive {
                engine: scene.engine,
                shepard: scene.point_shepard(compat),
            });
        }
        Ok(match scene.flexible_options_or(flexible, compat) {
            Some(options) => {
                let samples =
                    SampledCurves::sample(&setup.drawing, setup.weights.as_ref(), &setup.options);
                Deformer::Flexible(Box::new(
                    FlexibleSolver::new(&setup.drawing, &samples, &setup.options, options)
                        .map_err(rig_error)?,
                ))
            }
            None => Deformer::Fixed(
                SplineRig::precompute(&setup.drawing, setup.weights.as_ref(), &setup.options)
                    .map_err(rig_error)?,
            ),
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

    /// Writes the drawing of `setup` deformed by `pose` (one map per handle) into `out`
    /// (length [`crate::drawing::Drawing::n_points`]).
    pub fn deform(
        &self,
        setup: &Setup,
        pose: &[Affine],
        out: &mut [Point],
    ) -> Result<(), Box<dyn std::error::Error + Send + Sync>> {
        let drawing = &setup.drawing;
        let field = setup.weights.as_ref();
        match self {
            Deformer::Fixed(rig) => rig.update(pose, out)?,
            Deformer::Flexible(solver) => {
                solver.solve(pose, None, out)?;
            }
            Deformer::Naive { engine, shepard } => match (engine, shepard) {
                (Engine::FourControls, _) => naive::skin_control_points(drawing, field, pose, out)?,
                (Engine::TwoEndpoints, _) => {
                    naive::skin_on_curve_points(drawing, field, pose, out)?
                }
                (_, Some(shepard)) => naive::skin_with_jacobian(drawing, shepard, pose, out)?,
                (_, None) => {
                    let gradient = FiniteDifferences::for_drawing(field, drawing);
                    naive::skin_with_jacobian(drawing, &gradient, pose, out)?
                }
            },
        }
        Ok(())
    }
}
