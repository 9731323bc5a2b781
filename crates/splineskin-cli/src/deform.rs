//! `splineskin deform SCENE -o OUT`, or `splineskin deform DRAWING.svg [--pin X,Y]…
//! [--move I:DX,DY]… -o OUT` ([`crate::drawing_input`]).

use std::path::PathBuf;

use anyhow::{Context, Result};
use kurbo::{Affine, Point};
use splineskin::adaptive::{AdaptiveOptions, Refined};
use splineskin::drawing::follow::{ElementMaps, FollowOptions};
use splineskin::scene::{PosedDrawing, Setup};

use crate::output::DeformedOutputArgs;

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
    #[command(flatten)]
    posing: crate::posing::PosingArgs,
    /// Adaptive control points: split input curves at rest where the fit is farther than
    /// FRACTION of the diagonal from the skinned target under any of the scene's poses, and
    /// re-rig, until it is within (or 4 times the input's curves are used). Every input anchor
    /// is kept; the JSON output lists the inserted ones per path (`inserted`).
    #[arg(long, value_name = "FRACTION")]
    tolerance: Option<f64>,
    #[command(flatten)]
    svg_input: crate::drawing_input::SvgInputArgs,
    #[command(flatten)]
    written: DeformedOutputArgs,
}

pub fn run(args: Args) -> Result<()> {
    crate::output::Format::of(&args.output)?;
    let scene = args.svg_input.scene(&args.scene)?;
    let (pose_index, pose) = scene
        .pose_by_key(&args.pose)
        .map_err(|e| anyhow::anyhow!("{}: {e}", args.scene.display()))?;
    let posed = PosedDrawing::of_scene(&scene, args.posing.options(true))?;
    for w in posed.warnings() {
        eprintln!("warning: {w}");
    }
    let mut points = vec![Point::ZERO; posed.n_points()];
    let report = posed.update(&pose.transforms, &mut points).map_err(|e| {
        anyhow::anyhow!(
            "{}: pose {pose_index}: {e}; nothing written to {}",
            args.scene.display(),
            args.output.display()
        )
    })?;
    let mut engine_note = report.note().map(|n| format!(", {n}")).unwrap_or_default();
    let setup = posed.setup();
    let options = args.written.follow_options();
    let maps = element_maps(setup, &pose.transforms, &options)
        .with_context(|| format!("{}: pose {pose_index}", args.scene.display()))?;
    let refined = match args.tolerance {
        Some(tolerance) => {
            let refined = refine(&scene, &posed, tolerance, &pose.transforms)
                .with_context(|| format!("{}: --tolerance {tolerance}", args.scene.display()))?;
            engine_note += &format!(
                ", adaptive: {} anchors inserted ({} curves, {} rounds), largest distance {:.3e} of the diagonal{}",
                refined.0.n_inserted(),
                refined.0.drawing.n_curves(),
                refined.0.rounds,
                refined.0.worst,
                if refined.0.met { "" } else { " (the curve budget ran out before the tolerance)" }
            );
            Some(refined)
        }
        None => None,
    };
    let (drawing, points, inserted) = match &refined {
        Some((r, p)) => (&r.drawing, p.as_slice(), Some(r.inserted.as_slice())),
        None => (&setup.drawing, points.as_slice(), None),
    };
    args.written
        .write_marked(&args.output, drawing, points, maps.as_ref(), inserted)?;
    crate::output::warn_folds(&args.output, drawing, points);
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
        drawing.n_curves(),
        setup.drawing.paths.len(),
        setup.weights.n_handles(),
        set.points.len(),
        pose_index,
        args.output.display()
    );
    Ok(())
}

/// The maps that carry gradients, patterns, markers, text and images with the skinning map of
/// `setup`'s weights under `pose` ([`Setup::element_maps`]), saying on stderr when the pose does
/// not have one map per weight function (those elements then stay at rest).
pub fn element_maps(
    setup: &Setup,
    pose: &[Affine],
    options: &FollowOptions,
) -> Result<Option<ElementMaps>> {
    let maps = setup.element_maps(pose, options)?;
    if maps.is_none() {
        eprintln!(
            "note: {} transforms for {} weight functions: gradients, patterns, markers, text \
             and images are left at rest",
            pose.len(),
            setup.weights.n_handles()
        );
    }
    Ok(maps)
}

/// Adaptive control points for `deform --tolerance`: the drawing refined for every pose of the
/// scene (and `pose`, the one written, if it is not one of them), and its deformation by `pose` (the flexible solve on
/// the refined drawing when `posed` is flexible).
fn refine(
    scene: &splineskin::scene::Scene,
    posed: &PosedDrawing,
    tolerance: f64,
    pose: &[kurbo::Affine],
) -> Result<(Refined, Vec<Point>)> {
    let mut poses: Vec<Vec<kurbo::Affine>> =
        scene.poses.iter().map(|p| p.transforms.clone()).collect();
    if !poses.iter().any(|p| p.as_slice() == pose) {
        poses.push(pose.to_vec());
    }
    let setup = posed.setup();
    let refined = splineskin::adaptive::refine(
        &setup.drawing,
        setup.weights.as_ref(),
        &setup.options,
        &poses,
        &AdaptiveOptions::default().with_tolerance(tolerance),
    )?;
    let mut points = vec![Point::ZERO; refined.drawing.n_points()];
    match posed.flexible_solver() {
        Some(solver) => {
            refined
                .flexible_solver(setup.weights.as_ref(), &setup.options, *solver.options())?
                .solve(pose, None, &mut points)?;
        }
        None => refined.rig.update(pose, &mut points)?,
    }
    Ok((refined, points))
}

#[cfg(test)]
mod tests {
    use clap::Parser;

    use super::{run, Args};
    use crate::test_support::svg_readings;

    #[derive(Parser)]
    struct Deform {
        #[command(flatten)]
        args: Args,
    }

    /// `deform DRAWING.svg --pin … --move …` reads the drawing once: the pins are placed on it,
    /// the scene is made of it and the rig set up on it without reading it (or a scene file
    /// written of it) again.
    #[test]
    fn deform_of_an_svg_with_pins_reads_it_once() {
        let dir = tempfile::tempdir().expect("temporary folder");
        let svg = dir.path().join("fish.svg");
        std::fs::write(&svg, splineskin::examples::DEMO_SVG).expect("write the drawing");
        let out = dir.path().join("posed.svg");
        let drawing =
            splineskin::drawing::read_svg(splineskin::examples::DEMO_SVG, &Default::default())
                .expect("the bundled drawing reads");
        let p = drawing.paths[0].points[0];
        let pin = format!("{},{}", p.x, p.y);
        let args = Deform::try_parse_from([
            "deform".as_ref(),
            svg.as_os_str(),
            "--pin".as_ref(),
            pin.as_ref(),
            "--pins".as_ref(),
            "3".as_ref(),
            "--weights".as_ref(),
            "shepard".as_ref(),
            "--move".as_ref(),
            "0:5,-3".as_ref(),
            "-o".as_ref(),
            out.as_os_str(),
        ])
        .expect("the command line parses")
        .args;
        let (ran, readings) = svg_readings(|| run(args));
        ran.expect("deform runs");
        assert!(out.exists(), "the posed drawing is written");
        assert_eq!(readings, 1, "SVG readings during deform");
        let names: Vec<_> = std::fs::read_dir(dir.path())
            .expect("list the folder")
            .map(|e| e.expect("entry").file_name())
            .collect();
        assert_eq!(
            names.len(),
            2,
            "only the drawing and the output in the folder: {names:?}"
        );
    }
}
