//! An operator trained for a drawing and joined with it, from the drawing and its handles alone
//! ([`DrawingDefOp::train`]): the domain sized for training ([`training_domain_options`]), the
//! training ([`train`]) and the join ([`DefOpRig`]).

use kurbo::Point;
use splineskin_core::domain::{Domain, DomainOptions};
use splineskin_core::drawing::Drawing;
use splineskin_core::spline_fit::FitOptions;

use super::error::DefOpError;
use super::spatial_basis::SpatialBasis;
use super::spline_join::DefOpRig;
use super::train::{train, Progress, TrainOptions, Training};

/// Curve samples per diagonal of the drawing in [`training_domain_options`]: 100 (a boundary
/// or curve vertex every 1 % of the diagonal; the default, 500, is meant for weights solved
/// once, not for 1 000 ground-truth solves).
pub const TRAINING_SAMPLES_PER_DIAGONAL: f64 = 100.0;

/// Largest triangle, as a fraction of the domain's area, in [`training_domain_options`]:
/// 1/1000. On the bundled fish (padded box domain) this gives 1 917 vertices and 3 714
/// triangles, the size of the paper's octopus (and of `splineskin::examples::octopus_domain`
/// with `1/1800`).
pub const TRAINING_MAX_AREA_FRACTION: f64 = 1.0 / 1000.0;

/// [`DomainOptions`] for training an operator on a drawing's domain: the defaults with
/// [`TRAINING_SAMPLES_PER_DIAGONAL`] and [`TRAINING_MAX_AREA_FRACTION`], about 2 000 vertices
/// and 4 000 triangles for a drawing like the bundled fish (58 curves), which keeps a
/// 1 000-sample training near the issue's budget (the octopus, 1 991 vertices: about 20 s on
/// two cores). Drawings with many more curves get more curve vertices: lower
/// `samples_per_diagonal` for them.
///
/// ```
/// use splineskin_defop::{training_domain_options, TRAINING_MAX_AREA_FRACTION};
/// let options = training_domain_options();
/// assert_eq!(options.max_area_fraction, TRAINING_MAX_AREA_FRACTION);
/// ```
pub fn training_domain_options() -> DomainOptions {
    DomainOptions::default()
        .with_samples_per_diagonal(TRAINING_SAMPLES_PER_DIAGONAL)
        .with_max_area_fraction(TRAINING_MAX_AREA_FRACTION)
}

/// Everything from a drawing and its point handles: the triangulated domain, the trained
/// operator (hat functions as the spatial basis) and the rig — the "mesh-free" use, where the
/// mesh is an implementation detail.
///
/// ```text
/// once:        let joined = DrawingDefOp::train(&drawing, &handles, &training_domain_options(),
///                                               &TrainOptions::default(), &FitOptions::default(), &|_| {})?;
/// each frame:  evaluator.update(&q, &mut points)?     (let mut evaluator = joined.rig.evaluator();)
/// ```
///
/// ```
/// use kurbo::{Point, Vec2};
/// use splineskin_defop::{training_domain_options, DrawingDefOp, HandleBasisKind, TrainOptions};
/// use splineskin_svg::{read_svg, ImportOptions};
/// use splineskin_core::spline_fit::FitOptions;
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg"><path d="M0 0 C30 40 70 40 100 0"/></svg>"#;
/// let drawing = read_svg(svg, &ImportOptions::default())?;
/// let handles = [Point::new(0.0, 0.0), Point::new(100.0, 0.0)];
/// // A tiny training for the example: 10 samples, linear handle basis, a coarse domain.
/// let domain = training_domain_options().with_max_area_fraction(0.02).with_samples_per_diagonal(20.0);
/// let training = TrainOptions::default().with_n_samples(10).with_handle_basis(HandleBasisKind::Linear);
/// let joined = DrawingDefOp::train(&drawing, &handles, &domain, &training, &FitOptions::default(), &|_| {})?;
/// // The rest configuration gives the curve back; moving a handle moves it.
/// let input = drawing.flat_points();
/// let rest = joined.rig.deform(&handles)?;
/// assert!(rest.iter().zip(&input).all(|(p, c)| (*p - *c).hypot() < 1e-9));
/// let moved = joined.rig.deform(&[handles[0], handles[1] + Vec2::new(0.0, 8.0)])?;
/// assert!(moved[3].y > 1.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct DrawingDefOp {
    /// The triangulated domain of the drawing, handles at vertices.
    pub domain: Domain,
    /// The training (operator, samples, ground truths, stage reports).
    pub training: Training,
    /// The join of the drawing with the operator.
    pub rig: DefOpRig,
}

impl DrawingDefOp {
    /// Triangulates the domain of `drawing` with point handles `handles`
    /// ([`Domain::build`] with `domain`; [`training_domain_options`] is a reasonable
    /// choice), trains an operator on it with the hat functions as spatial basis ([`train`]
    /// with `training`, `progress` called as it goes) and joins it with the drawing
    /// ([`DefOpRig::precompute`] with `fit`).
    pub fn train(
        drawing: &Drawing,
        handles: &[Point],
        domain: &DomainOptions,
        training: &TrainOptions,
        fit: &FitOptions,
        progress: &(dyn Fn(Progress) + Sync),
    ) -> Result<DrawingDefOp, DefOpError> {
        let domain = Domain::build(drawing, handles, &[], domain)?;
        let spatial = SpatialBasis::hats(&domain.mesh)?;
        let training = train(
            &domain.mesh,
            &domain.handle_vertices,
            &spatial,
            training,
            progress,
        )?;
        let rig = DefOpRig::from_domain(drawing, &domain, &training.op, fit)?;
        Ok(DrawingDefOp {
            domain,
            training,
            rig,
        })
    }
}
