//! `splineskin deform SCENE -o OUT`.

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use kurbo::Point;
use splineskin::drawing::Drawing;
use splineskin::naive::{self, FiniteDifferences};
use splineskin::scene::{Compat, Engine, Scene, Setup};
use splineskin::spline_fit::quadrature::SampledCurves;
use splineskin::spline_fit::{FlexibleOptions, FlexibleSolver, SplineRig};

use crate::output::write_deformed;
use crate::CompatArg;

#[derive(clap::Args)]
pub struct Args {
    /// The scene: our JSON format or the paper authors' `*-deformation.json`.
    scene: PathBuf,
    /// Output file: `.svg` (the input document with deformed paths), `.png`, or `.json`
    /// (`{"paths":[{"closed":…,"points":[[x,y],…]}]}`).
    #[arg(short, long)]
    output: PathBuf,
    /// Which of the scene's poses to apply (0 is the first).
    #[arg(long, default_value_t = 0)]
    pose: usize,
    /// Reproduce another implementation's discretisation exactly.
    #[arg(long, value_enum, default_value_t = CompatArg::None)]
    compat: CompatArg,
    /// Flexible G¹ and fixed-angle junctions: parallel tangents (fixed angle: their angle) with
    /// the tangent-length ratio free, fitted by iteration. Scenes can ask for it themselves
    /// (`"flexible": true`; the authors' scenes always do).
    #[arg(long)]
    flexible: bool,
}

pub fn run(args: Args) -> Result<()> {
    crate::output::Format::of(&args.output)?;
    let scene = Scene::load(&args.scene)?;
    let mut setup = scene.setup(args.compat.into())?;
    setup.options = setup.options.with_parallel(true);
    for w in &setup.warnings {
        eprintln!("warning: {w}");
    }
    let pose = scene.pose(args.pose).with_context(|| {
        format!(
            "{}: pose {} does not exist (the scene has {})",
            args.scene.display(),
            args.pose,
            scene.poses.len().max(1)
        )
    })?;
    let compat: Compat = args.compat.into();
    if scene.engine != Engine::Ours {
        return run_naive(&args, &scene, &setup, &pose.transforms, compat);
    }
    let flexible = match args.flexible {
        true => Some(match compat {
            Compat::VectorSkinning => FlexibleOptions::vectorskinning(),
            _ => FlexibleOptions::default(),
        }),
        false => scene.flexible_options(compat),
    };
    let building = || format!("{}: building the rig", args.scene.display());
    let solver = match flexible {
        Some(options) => {
            let samples =
                SampledCurves::sample(&setup.drawing, setup.weights.as_ref(), &setup.options);
            Some(
                FlexibleSolver::new(&setup.drawing, &samples, &setup.options, options)
                    .with_context(building)?,
            )
        }
        None => None,
    };
    let fixed_rig;
    let rig: &SplineRig = match &solver {
        Some(s) => s.rig(),
        None => {
            fixed_rig =
                SplineRig::precompute(&setup.drawing, setup.weights.as_ref(), &setup.options)
                    .with_context(building)?;
            &fixed_rig
        }
    };
    for p in rig.rank_deficient_paths() {
        eprintln!(
            "warning: path {p}: its system is rank deficient (a curve with no length); its result is not unique"
        );
    }
    let mut points = vec![Point::ZERO; rig.n_points()];
    let flexible_note = match &solver {
        Some(s) => {
            let report = s
                .solve(&pose.transforms, None, &mut points)
                .with_context(|| format!("{}: flexible solve", args.scene.display()))?;
            format!(
                ", flexible: {} junctions on {} paths, {} steps, energy {:.4e} -> {:.4e}",
                s.n_flexible_junctions(),
                report.paths,
                report.steps,
                report.fixed_ratio_energy,
                report.energy()
            )
        }
        None => {
            rig.update(&pose.transforms, &mut points)?;
            String::new()
        }
    };
    check_finite(&args, &setup.drawing, &points, rig.rank_deficient_paths())?;
    write_deformed(&args.output, &setup.drawing, &points)?;
    let set = scene.handle_set();
    let kinds = [
        (set.bones.len(), "bones"),
        (set.n_cage_vertices(), "cage vertices"),
    ]
    .iter()
    .filter(|(n, _)| *n > 0)
    .map(|(n, what)| format!(", {n} {what}"))
    .collect::<String>();
    let domain = setup
        .domain
        .as_ref()
        .map(|d| {
            format!(
                ", {} weights on {} triangles",
                scene.weights.name(),
                d.mesh.n_triangles()
            )
        })
        .unwrap_or_default();
    eprintln!(
        "{}: {} curves in {} paths, {} handles ({} points{kinds}){domain}{flexible_note}, pose {} -> {}",
        args.scene.display(),
        setup.drawing.n_curves(),
        setup.drawing.paths.len(),
        rig.n_handles(),
        set.points.len(),
        args.pose,
        args.output.display()
    );
    Ok(())
}

/// `deform` for a scene whose engine is a naive baseline ([`splineskin::naive`]): every control
/// point skinned (`fourcontrols`), on-curve points skinned and off-curve points carried by
/// their neighbour's blended transform (`twoendpoints`), or carried by the skinning map's
/// Jacobian there (`jacobian`: analytic for Shepard weights of point handles, central
/// differences otherwise).
fn run_naive(
    args: &Args,
    scene: &Scene,
    setup: &Setup,
    pose: &[kurbo::Affine],
    compat: Compat,
) -> Result<()> {
    if args.flexible {
        bail!(
            "{}: --flexible applies to engine 'ours'; this scene's engine is '{}'",
            args.scene.display(),
            scene.engine.name()
        );
    }
    let drawing = &setup.drawing;
    let field = setup.weights.as_ref();
    let mut points = vec![Point::ZERO; drawing.n_points()];
    let solved = match scene.engine {
        Engine::FourControls => naive::skin_control_points(drawing, field, pose, &mut points),
        Engine::TwoEndpoints => naive::skin_on_curve_points(drawing, field, pose, &mut points),
        Engine::Jacobian => match scene.point_shepard(compat) {
            Some(shepard) => naive::skin_with_jacobian(drawing, &shepard, pose, &mut points),
            None => {
                let gradient = FiniteDifferences::for_drawing(field, drawing);
                naive::skin_with_jacobian(drawing, &gradient, pose, &mut points)
            }
        },
        Engine::Ours => unreachable!("run_naive is only called for the naive engines"),
    };
    solved
        .with_context(|| format!("{}: engine '{}'", args.scene.display(), scene.engine.name()))?;
    check_finite(args, drawing, &points, &[])?;
    write_deformed(&args.output, drawing, &points)?;
    eprintln!(
        "{}: {} curves in {} paths, {} handles, engine {} (a naive baseline), pose {} -> {}",
        args.scene.display(),
        drawing.n_curves(),
        drawing.paths.len(),
        field.n_handles(),
        scene.engine.name(),
        args.pose,
        args.output.display()
    );
    Ok(())
}

/// Errors, naming the scene, the pose and the first path concerned, if a deformed point is not
/// finite: a rank-deficient system (compatibility mode solves them as the authors do, without
/// a fallback) can give NaN, which no output format can hold.
fn check_finite(
    args: &Args,
    drawing: &Drawing,
    points: &[Point],
    rank_deficient: &[usize],
) -> Result<()> {
    let mut offset = 0;
    for (i, path) in drawing.paths.iter().enumerate() {
        let n = path.points.len();
        let bad = points[offset..offset + n]
            .iter()
            .any(|p| !(p.x.is_finite() && p.y.is_finite()));
        offset += n;
        if bad {
            let element = drawing
                .source
                .as_ref()
                .map(|s| format!(" ({})", s.element_label(i)))
                .unwrap_or_default();
            let why = if rank_deficient.contains(&i) {
                "its fit system is rank deficient, e.g. a curve of zero length"
            } else {
                "the fit is numerically unstable"
            };
            bail!(
                "{}: pose {}: path {i}{element}: deformed points are not finite (expected finite \
                 coordinates): {why}; nothing written to {}",
                args.scene.display(),
                args.pose,
                args.output.display()
            );
        }
    }
    Ok(())
}
