//! `splineskin demo`: deform the bundled example drawing by each of its poses and write SVG
//! and PNG files.

use std::path::PathBuf;

use anyhow::{Context, Result};
use kurbo::Point;
use splineskin::examples::demo_scene;
use splineskin::scene::Compat;
use splineskin::spline_fit::SplineRig;

use crate::output::write_deformed;

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
        for ext in ["svg", "png"] {
            let path = args.output.join(format!("{name}.{ext}"));
            write_deformed(&path, &setup.drawing, &points)?;
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
