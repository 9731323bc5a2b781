//! `splineskin deform SCENE -o OUT`, or `splineskin deform DRAWING.svg [--pin X,Y]…
//! [--move I:DX,DY]… -o OUT` ([`crate::drawing_input`]).

use std::path::PathBuf;

use anyhow::{Context, Result};
use kurbo::Point;
use splineskin::scene::{Compat, PosedDrawing};

use crate::output::DeformedOutputArgs;
use crate::CompatArg;

#[derive(clap::Args)]
pub struct Args {
    /// The scene (our JSON format or the paper authors' `*-deformation.json`), or an SVG
    /// drawing with its pins and pose given by the flags below.
    #[arg(value_name = "SCENE|SVG")]
    scene: PathBuf,
    /// Output file: `.svg` (the input document with deformed paths), `.png`, or `.json`
    /// (`{"paths":[{"closed":…,"points":[[x,y],…]}]}`).
    #[arg(short, long)]
    output: PathBuf,
    /// Which of the scene's poses to apply: its name, or its index (0 is the first).
    #[arg(long, default_value = "0")]
    pose: String,
    /// Reproduce another implementation's discretisation exactly.
    #[arg(long, value_enum, default_value_t = CompatArg::None)]
    compat: CompatArg,
    /// Flexible G¹ and fixed-angle junctions: parallel tangents (fixed angle: their angle) with
    /// the tangent-length ratio free, fitted by iteration. Scenes can ask for it themselves
    /// (`"flexible": true`; the authors' scenes always do).
    #[arg(long)]
    flexible: bool,
    #[command(flatten)]
    pins: crate::drawing_input::PinArgs,
    #[command(flatten)]
    pose_args: crate::drawing_input::PoseArgs,
    #[command(flatten)]
    text: crate::drawing_input::TextArgs,
    #[command(flatten)]
    written: DeformedOutputArgs,
}

pub fn run(args: Args) -> Result<()> {
    crate::output::Format::of(&args.output)?;
    let mut scene = crate::drawing_input::load(&args.scene, &args.pins, Some(&args.pose_args))?;
    args.text.apply(&mut scene)?;
    let mut setup = scene.setup(args.compat.into())?;
    setup.options = setup.options.with_parallel(true);
    for w in &setup.warnings {
        eprintln!("warning: {w}");
    }
    let (pose_index, pose) = scene
        .pose_by_key(&args.pose)
        .map_err(|e| anyhow::anyhow!("{}: {e}", args.scene.display()))?;
    let compat: Compat = args.compat.into();
    let posed = PosedDrawing::new(&scene, setup, compat, args.flexible)?;
    for p in posed.rank_deficient_paths() {
        eprintln!(
            "warning: path {p}: its system is rank deficient (a curve with no length); its result is not unique"
        );
    }
    let mut points = vec![Point::ZERO; posed.n_points()];
    let report = posed.update(&pose.transforms, &mut points).map_err(|e| {
        anyhow::anyhow!(
            "{}: pose {pose_index}: {e}; nothing written to {}",
            args.scene.display(),
            args.output.display()
        )
    })?;
    let engine_note = report.note().map(|n| format!(", {n}")).unwrap_or_default();
    let setup = posed.setup();
    let options = args.written.follow_options();
    let maps = element_maps(setup, &pose.transforms, &options)
        .with_context(|| format!("{}: pose {pose_index}", args.scene.display()))?;
    args.written
        .write(&args.output, &setup.drawing, &points, maps.as_ref())?;
    crate::output::warn_folds(&args.output, &setup.drawing, &points);
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
        "{}: {} curves in {} paths, {} handles ({} points{kinds}){domain}{engine_note}, pose {} -> {}",
        args.scene.display(),
        setup.drawing.n_curves(),
        setup.drawing.paths.len(),
        setup.weights.n_handles(),
        set.points.len(),
        pose_index,
        args.output.display()
    );
    Ok(())
}

pub use splineskin_editor::scene_lottie::element_maps;
