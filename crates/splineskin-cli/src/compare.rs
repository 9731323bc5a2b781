//! `splineskin compare SCENE -o compare.png [--json] [--pose N] [--flexible] [--tolerance F]`: the spline fit
//! beside the naive baselines, drawn by [`splineskin::compare`], with a table of the metrics
//! on stdout (or, with `--json`, one JSON object per line and method:
//!
//! ```text
//! {"scene": "…", "pose": 0, "method": "ours", "curves": 38, "energy": 1.2e2,
//!  "max": 1.5e-3, "rms": 4.1e-4, "distance": "parametric", "diagonal": 512.3,
//!  "refit_tolerance": null, "folds": 0}
//! ```
//!
//! `max` and `rms` are fractions of the diagonal, `energy` in drawing units² · length,
//! `distance` is `parametric` or `closest_point` (the Schneider refit), `refit_tolerance` its
//! tolerance in drawing units, `null` for the other methods), `folds` the crossings of closed
//! outlines the deformation made (`null` for the refits; [`splineskin::folds`]).

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use serde::Serialize;
use splineskin::adaptive::AdaptiveOptions;
use splineskin::compare::{
    compare_posed, posed_markers, CompareOptions, Comparison, Method,
    DEFAULT_REFIT_TOLERANCE_FRACTION,
};
use splineskin::figure::comparison::{
    render_comparison, PictureOptions, DEFAULT_COMPARE_PANEL_WIDTH,
};
use splineskin::metrics::MetricsOptions;
use splineskin::scene::{Compat, Engine, PosedDrawing, Scene};

use crate::output::{write_atomic, Format};
use crate::posing::CompatArg;

#[derive(clap::Args)]
pub struct Args {
    /// The scene: our JSON format or the paper authors' `*-deformation.json`.
    scene: PathBuf,
    /// Output picture (`.png`): one panel per method, the target dashed and coloured by the
    /// distance to the result.
    #[arg(short, long)]
    output: PathBuf,
    /// Which of the scene's poses to apply: its name, or its index (0 is the first).
    #[arg(long, default_value = "0")]
    pose: String,
    /// Also show the flexible fit (G¹ and fixed-angle tangent ratios free); shown anyway when
    /// the scene asks for it.
    #[arg(long)]
    flexible: bool,
    /// Print one JSON object per method instead of the table.
    #[arg(long)]
    json: bool,
    /// Tolerance of the Schneider refit, as a fraction of the drawing's diagonal.
    #[arg(long, value_name = "FRACTION", default_value_t = DEFAULT_REFIT_TOLERANCE_FRACTION)]
    refit_tolerance: f64,
    /// Also compare adaptive control points: `ours-adaptive` (input curves split at rest until
    /// the fit is within FRACTION of the diagonal of the target for this pose, every input
    /// anchor kept) and `schneider-adaptive-count` (the refit given as many curves per path).
    #[arg(long, value_name = "FRACTION")]
    tolerance: Option<f64>,
    /// Width of each panel in pixels.
    #[arg(long, value_name = "PX", default_value_t = DEFAULT_COMPARE_PANEL_WIDTH)]
    width: u32,
    /// Reproduce another implementation's discretisation exactly.
    #[arg(long, value_enum, default_value_t = CompatArg::None)]
    compat: CompatArg,
}

/// One line of `--json`.
#[derive(Serialize)]
struct JsonRow<'a> {
    scene: String,
    pose: usize,
    method: &'a str,
    curves: usize,
    energy: f64,
    max: f64,
    rms: f64,
    distance: &'a str,
    closest_max: f64,
    closest_rms: f64,
    diagonal: f64,
    refit_tolerance: Option<f64>,
    /// Crossings of closed outlines the deformation made (`null` for the refits).
    folds: Option<usize>,
}

pub fn run(args: Args) -> Result<()> {
    if Format::of(&args.output).ok() != Some(Format::Png) {
        bail!(
            "{}: the comparison is a picture (expected a name ending in .png)",
            args.output.display()
        );
    }
    let scene = Scene::load(&args.scene)?;
    let compat: Compat = args.compat.into();
    let (pose_index, pose) = scene
        .pose_by_key(&args.pose)
        .map_err(|e| anyhow::anyhow!("{}: {e}", args.scene.display()))?;
    let picture_options = PictureOptions::default().with_panel_width(args.width);
    picture_options
        .check(6)
        .with_context(|| format!("{}: --width {}", args.output.display(), args.width))?;
    let mut setup = scene.setup(compat)?;
    setup.options = setup.options.with_parallel(true);
    for w in &setup.warnings {
        eprintln!("warning: {w}");
    }
    // Every method is compared whatever the scene's engine: the fit is built for all.
    let posed = PosedDrawing::with_engine(&scene, setup, compat, Engine::Ours, args.flexible)?;
    let mut options = CompareOptions::default()
        .with_refit_tolerance(args.refit_tolerance)
        .with_metrics(MetricsOptions::default().with_fit(*posed.fit_options()));
    if let Some(tolerance) = args.tolerance {
        options = options.with_adaptive(AdaptiveOptions::default().with_tolerance(tolerance));
    }
    let comparison = compare_posed(&posed, &pose.transforms, &options)
        .with_context(|| format!("{}: pose {pose_index}", args.scene.display()))?;
    let markers = posed_markers(&scene.handle_set(), &pose.transforms);
    let picture = render_comparison(&comparison, &markers, &picture_options)
        .with_context(|| format!("{}: drawing the comparison", args.scene.display()))?;
    write_atomic(&args.output, &picture.png)?;
    if args.json {
        for row in json_rows(&args, &comparison, pose_index) {
            println!("{}", serde_json::to_string(&row)?);
        }
    } else {
        print_table(&args, &comparison, pose_index, pose.name.as_deref());
    }
    eprintln!(
        "{}: pose {}: {} methods -> {} ({}×{} px; colour 1 = {:.3}% of the diagonal)",
        args.scene.display(),
        pose_index,
        comparison.methods.len(),
        args.output.display(),
        picture.grid.width,
        picture.grid.height,
        100.0 * picture.error_scale / comparison.diagonal.max(f64::MIN_POSITIVE)
    );
    Ok(())
}

fn json_rows<'a>(args: &Args, comparison: &'a Comparison, pose_index: usize) -> Vec<JsonRow<'a>> {
    comparison
        .methods
        .iter()
        .map(|m| JsonRow {
            scene: args.scene.display().to_string(),
            pose: pose_index,
            method: m.method.name(),
            curves: m.result.n_curves(),
            energy: m.metrics.overall.energy,
            max: m.metrics.overall.max,
            rms: m.metrics.overall.rms,
            distance: if m.method.keeps_structure() {
                "parametric"
            } else {
                "closest_point"
            },
            closest_max: m.closest.overall.max,
            closest_rms: m.closest.overall.rms,
            diagonal: comparison.diagonal,
            refit_tolerance: (m.method == Method::Schneider).then_some(comparison.refit_tolerance),
            folds: m.folds,
        })
        .collect()
}

fn print_table(args: &Args, comparison: &Comparison, pose_index: usize, pose_name: Option<&str>) {
    let name = pose_name.map(|n| format!(" '{n}'")).unwrap_or_default();
    println!(
        "{} pose {}{name}: distances as % of the diagonal ({:.4} units)",
        args.scene.display(),
        pose_index,
        comparison.diagonal
    );
    println!(
        "{:<24} {:>12} {:>9} {:>9} {:>11} {:>11} {:>7} {:>5}",
        "method", "energy", "max %", "rms %", "closest max", "closest rms", "curves", "folds"
    );
    for m in &comparison.methods {
        let o = m.metrics.overall;
        let note = match m.method {
            Method::Schneider => format!(
                "  (tolerance {:.4} units; closest-point distances)",
                comparison.refit_tolerance
            ),
            Method::SchneiderSameCount => {
                "  (per path, the smallest tolerance within the input's curve count; closest-point distances)"
                    .to_string()
            }
            Method::OursAdaptive => format!(
                "  ({} anchors inserted, every input anchor kept; closest-point distances)",
                m.result.n_curves() - comparison.path_curves.iter().sum::<usize>()
            ),
            Method::SchneiderAdaptiveCount => {
                "  (per path, the smallest tolerance within ours-adaptive's curve count; closest-point distances)"
                    .to_string()
            }
            _ => String::new(),
        };
        let folds = m.folds.map_or("-".to_string(), |n| n.to_string());
        println!(
            "{:<24} {:>12.4e} {:>9.4} {:>9.4} {:>11.4} {:>11.4} {:>7} {folds:>5}{note}",
            m.method.name(),
            o.energy,
            100.0 * o.max,
            100.0 * o.rms,
            100.0 * m.closest.overall.max,
            100.0 * m.closest.overall.rms,
            m.result.n_curves()
        );
    }
}
