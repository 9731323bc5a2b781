//! `splineskin subdiv compare SCENE -o OUT.png [--json] [--pose N]`: ours (the limit surface
//! of the fitted cage) and naive (the limit surface of the skinned cage), each against the
//! skinned limit surface ([`splineskin::subdiv::compare_subdiv`]); a PNG of both coloured by
//! that distance, and a table on stdout — or with `--json` one object per method:
//!
//! ```text
//! {"scene": "car.json", "pose": 0, "method": "ours", "vertices": 1642, "faces": 1575,
//!  "handles": 4, "samples": 100197, "max": 1.9e-3, "rms": 2.3e-4, "diagonal": 4.13}
//! ```
//!
//! `max` and `rms` are fractions of the cage's bounding-box diagonal (`diagonal`, OBJ units),
//! over the `samples` vertices of the limit mesh at `--level`.

use std::path::PathBuf;

use anyhow::{Context, Result};
use serde::Serialize;
use splineskin::subdiv::{
    compare_subdiv, render_comparison_png, ComparisonPictureOptions, ComparisonSamples,
    SubdivScene, DEFAULT_COMPARE_LEVEL, DEFAULT_PANEL_WIDTH, MAX_LIMIT_MESH_LEVEL,
};

use crate::output::write_atomic;

#[derive(clap::Args)]
pub struct Args {
    /// The scene (JSON, `"splineskin_subdiv_scene": 1`).
    scene: PathBuf,
    /// The picture (`.png`): ours left, naive right.
    #[arg(short, long)]
    output: PathBuf,
    /// Which of the scene's poses to apply (0 is the first).
    #[arg(long, default_value_t = 0)]
    pose: usize,
    /// Print one JSON object per method instead of the table.
    #[arg(long)]
    json: bool,
    /// Level of the sample mesh: (2^K + 1)² samples per cage quad.
    #[arg(long, default_value_t = DEFAULT_COMPARE_LEVEL as u8,
          value_parser = clap::value_parser!(u8).range(1..=MAX_LIMIT_MESH_LEVEL as i64))]
    level: u8,
    /// Width of each panel in pixels.
    #[arg(long, value_name = "PX", default_value_t = DEFAULT_PANEL_WIDTH,
          value_parser = clap::value_parser!(u32).range(64..=4096))]
    width: u32,
    /// The axis drawn upwards (default: the one along which the cage is thinnest).
    #[arg(long, value_enum)]
    up: Option<Axis>,
    /// Camera azimuth about the up axis, degrees.
    #[arg(long, default_value_t = 35.0, allow_negative_numbers = true)]
    azimuth: f64,
    /// Camera elevation, degrees.
    #[arg(long, default_value_t = 25.0, allow_negative_numbers = true)]
    elevation: f64,
}

#[derive(Clone, Copy, Debug, clap::ValueEnum)]
enum Axis {
    X,
    Y,
    Z,
}

/// One line of `--json`.
#[derive(Serialize)]
struct Row<'a> {
    scene: String,
    pose: usize,
    method: &'a str,
    vertices: usize,
    faces: usize,
    handles: usize,
    samples: usize,
    max: f64,
    rms: f64,
    diagonal: f64,
}

pub fn run(args: Args) -> Result<()> {
    super::require_extension(&args.output, "png")?;
    anyhow::ensure!(
        args.azimuth.is_finite() && args.elevation.is_finite(),
        "--azimuth and --elevation must be finite numbers"
    );
    let scene = SubdivScene::load(&args.scene)?;
    let pose = scene.pose(args.pose)?;
    let setup = scene.setup()?;
    let name = args.scene.display().to_string();
    let samples = ComparisonSamples::new(&setup, usize::from(args.level))
        .with_context(|| format!("{name}: sampling the limit surface"))?;
    let comparison = compare_subdiv(&setup, &samples, &pose)
        .with_context(|| format!("{name}: pose {}", args.pose))?;
    let options = ComparisonPictureOptions::default()
        .with_panel_width(args.width)
        .with_up(args.up.map(|a| a as usize))
        .with_view(args.azimuth, args.elevation);
    let png = render_comparison_png(&samples, &comparison, &options)
        .with_context(|| format!("{name}: drawing {}", args.output.display()))?;
    write_atomic(&args.output, &png)?;
    let rows = [("ours", &comparison.ours), ("naive", &comparison.naive)].map(|(method, r)| Row {
        scene: name.clone(),
        pose: args.pose,
        method,
        vertices: setup.cage.n_vertices(),
        faces: setup.cage.n_faces(),
        handles: scene.handles.n_handles(),
        samples: samples.mesh().n_vertices(),
        max: r.summary.max,
        rms: r.summary.rms,
        diagonal: samples.diagonal(),
    });
    if args.json {
        for row in &rows {
            println!("{}", serde_json::to_string(row)?);
        }
    } else {
        println!(
            "{name}: pose {}, {} handles, {} samples; distance to the skinned surface, fraction of the diagonal ({:.4})",
            args.pose,
            scene.handles.n_handles(),
            samples.mesh().n_vertices(),
            samples.diagonal()
        );
        println!("{:<8} {:>12} {:>12}", "method", "max", "rms");
        for row in &rows {
            println!("{:<8} {:>12.4e} {:>12.4e}", row.method, row.max, row.rms);
        }
    }
    Ok(())
}
