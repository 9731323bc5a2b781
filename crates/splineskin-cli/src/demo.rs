//! `splineskin demo`: deform the bundled example drawing by each of its poses and write SVG
//! and PNG files: the curves through the spline fit, the label's text and the gradients by the
//! best-fit affine map over each element, the viewBox grown where the art leaves it.

use std::path::PathBuf;

use anyhow::{Context, Result};
use kurbo::Point;
use splineskin::drawing::follow::FollowOptions;
use splineskin::drawing::svg_out::ViewBoxRule;
use splineskin::examples::demo_scene;
use splineskin::scene::Compat;
use splineskin::spline_fit::SplineRig;

use crate::deform::element_maps;
use crate::output::{write_deformed, write_deformed_view_box};

#[derive(clap::Args)]
pub struct Args {
    /// Folder to write the results to (created if missing).
    #[arg(short, long, default_value = "splineskin-demo")]
    output: PathBuf,
}

pub fn run(args: Args) -> Result<()> {
    std::fs::create_dir_all(&args.output)
        .with_context(|| format!("{}: cannot create folder", args.output.display()))?;
    let scene = demo_scene();
    let mut setup = scene.setup(Compat::None)?;
    setup.options = setup.options.with_parallel(true);
    let rig = SplineRig::precompute(&setup.drawing, setup.weights.as_ref(), &setup.options)?;
    let mut points = vec![Point::ZERO; rig.n_points()];
    let mut written = Vec::new();
    let rest = setup.drawing.flat_points();
    for ext in ["svg", "png"] {
        let path = args.output.join(format!("rest.{ext}"));
        write_deformed(&path, &setup.drawing, &rest)?;
        written.push(path);
    }
    for (k, pose) in scene.poses.iter().enumerate() {
        rig.update(&pose.transforms, &mut points)?;
        let name = pose.name.clone().unwrap_or_else(|| format!("pose-{k}"));
        // The label's text and the gradients follow the pose, as `deform` carries them, and
        // the viewBox grows to hold the art (`deform --viewbox fit`): nothing is cropped.
        let maps = element_maps(&setup, &pose.transforms, &FollowOptions::default())?;
        for ext in ["svg", "png"] {
            let path = args.output.join(format!("{name}.{ext}"));
            write_deformed_view_box(
                &path,
                &setup.drawing,
                &points,
                ViewBoxRule::Fit,
                maps.as_ref(),
            )?;
            written.push(path);
        }
    }
    println!(
        "bundled drawing: {} curves in {} paths, {} handles, {} poses",
        setup.drawing.n_curves(),
        setup.drawing.paths.len(),
        rig.n_handles(),
        scene.poses.len()
    );
    for p in written {
        println!("wrote {}", p.display());
    }
    Ok(())
}
