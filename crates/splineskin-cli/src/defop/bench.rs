//! `splineskin defop bench OP [--json]`: evaluations per second of an operator file: the
//! median over timed batches of the allocation-free evaluator ([`DefOpEvaluator::eval`]: all
//! vertex positions) at configurations drawn in discs of 5 % of the diagonal, and of the spatial
//! coefficients alone. With `--scene SCENE` (the scene the operator was trained for) also the
//! spline join on its drawing ([`DefOpRig`]): the median of the join's precomputation and of
//! its per-frame update (`G_spline ψ(Q)`, allocation-free), the drawing's per-frame cost.
//!
//! [`DefOpEvaluator::eval`]: splineskin::defop::DefOpEvaluator::eval
//! [`DefOpRig`]: splineskin::defop::DefOpRig

use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::Result;
use kurbo::Point;
use serde::Serialize;
use splineskin::defop::{DefOpRig, OperatorFile, SampleRegion, Sampler, DEFAULT_DISC_FRACTION};
use splineskin::scene::{Compat, Scene};

/// Configurations cycled through.
const CONFIGURATIONS: usize = 32;
/// A timed batch lasts at least this long.
const BATCH: Duration = Duration::from_millis(20);

#[derive(clap::Args)]
pub struct Args {
    /// The operator file.
    operator: PathBuf,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
    /// Timed batches (the median is reported).
    #[arg(long, default_value_t = 25)]
    batches: usize,
    /// Also time the spline join on this scene's drawing (the scene the operator was trained
    /// for): its precomputation and per-frame update.
    #[arg(long)]
    scene: Option<PathBuf>,
}

/// Timed precomputations of the join (the median is reported).
const JOIN_PRECOMPUTES: usize = 5;

#[derive(Serialize)]
struct Report {
    operator: String,
    vertices: usize,
    triangles: usize,
    handles: usize,
    spatial_functions: usize,
    handle_functions: usize,
    handle_basis: &'static str,
    /// Median seconds per evaluation.
    eval_s: f64,
    evals_per_s: f64,
    /// Median seconds of the spatial coefficients `c(Q) = G ψ(Q)` alone (what a drawing's
    /// spline join multiplies; for the hats they are the vertex positions).
    coefficients_s: f64,
    coefficients_per_s: f64,
    /// With `--scene`: the drawing's chain points.
    #[serde(skip_serializing_if = "Option::is_none")]
    join_points: Option<usize>,
    /// With `--scene`: median seconds of the join's precomputation (two threads).
    #[serde(skip_serializing_if = "Option::is_none")]
    join_precompute_s: Option<f64>,
    /// With `--scene`: median seconds of one frame of the join (`G_spline ψ(Q)`).
    #[serde(skip_serializing_if = "Option::is_none")]
    join_update_s: Option<f64>,
}

pub fn run(args: Args) -> Result<()> {
    anyhow::ensure!(args.batches >= 1, "--batches 0: expected at least 1");
    let file = OperatorFile::load(&args.operator)?;
    let op = &file.op;
    let rest = file.rest_handles();
    let radius = DEFAULT_DISC_FRACTION * file.mesh.bounding_box_diagonal();
    let configurations = Sampler::new(&rest, &[(SampleRegion::Disc { radius }, 1.0)], 7)?
        .configurations(CONFIGURATIONS);
    let mut evaluator = op.evaluator();
    let mut positions = vec![Point::ZERO; op.n_vertices()];
    // Batch size: enough evaluations for BATCH (at least one).
    let clock = Instant::now();
    let mut per_batch = 0usize;
    while clock.elapsed() < BATCH || per_batch == 0 {
        evaluator.eval(&configurations[per_batch % CONFIGURATIONS], &mut positions)?;
        per_batch += 1;
    }
    let mut times = Vec::with_capacity(args.batches);
    for _ in 0..args.batches {
        let clock = Instant::now();
        for k in 0..per_batch {
            evaluator.eval(&configurations[k % CONFIGURATIONS], &mut positions)?;
        }
        std::hint::black_box(&positions);
        times.push(clock.elapsed().as_secs_f64() / per_batch as f64);
    }
    let eval_s = median(&mut times);
    times.clear();
    for _ in 0..args.batches {
        let clock = Instant::now();
        for k in 0..per_batch {
            std::hint::black_box(
                evaluator.spatial_coefficients(&configurations[k % CONFIGURATIONS])?,
            );
        }
        times.push(clock.elapsed().as_secs_f64() / per_batch as f64);
    }
    let coefficients_s = median(&mut times);
    let join = match &args.scene {
        None => None,
        Some(path) => Some(time_join(
            path,
            &args.operator,
            &file,
            &configurations,
            per_batch,
            args.batches,
        )?),
    };
    let report = Report {
        operator: args.operator.display().to_string(),
        vertices: op.n_vertices(),
        triangles: file.mesh.n_triangles(),
        handles: op.n_handles(),
        spatial_functions: op.spatial_basis().n_functions(),
        handle_functions: op.handle_basis().n_functions(),
        handle_basis: op.handle_basis().kind().name(),
        eval_s,
        evals_per_s: 1.0 / eval_s,
        coefficients_s,
        coefficients_per_s: 1.0 / coefficients_s,
        join_points: join.map(|j| j.0),
        join_precompute_s: join.map(|j| j.1),
        join_update_s: join.map(|j| j.2),
    };
    if args.json {
        println!("{}", serde_json::to_string(&report)?);
    } else {
        println!(
            "{}: {} vertices, {} handles, {} spatial x {} handle functions ({}): {:.1} us per evaluation, {:.0} evaluations per second (median of {} batches of {}); spatial coefficients alone {:.1} us ({:.0} per second)",
            report.operator,
            report.vertices,
            report.handles,
            report.spatial_functions,
            report.handle_functions,
            report.handle_basis,
            eval_s * 1e6,
            report.evals_per_s,
            args.batches,
            per_batch,
            coefficients_s * 1e6,
            report.coefficients_per_s
        );
        if let (Some(path), Some((points, pre, update))) = (&args.scene, join) {
            println!(
                "{}: join of its drawing ({points} chain points): precompute {:.1} ms (median of {JOIN_PRECOMPUTES}), update {:.1} us per frame",
                path.display(),
                pre * 1e3,
                update * 1e6
            );
        }
    }
    Ok(())
}

/// Times the join of `scene_path`'s drawing with the operator: `(chain points, median
/// precompute seconds, median update seconds)`, the update at `configurations` in batches of
/// `per_batch` (about as many frames as the evaluation's batches held; at least 100).
fn time_join(
    scene_path: &std::path::Path,
    op_path: &std::path::Path,
    file: &OperatorFile,
    configurations: &[Vec<Point>],
    per_batch: usize,
    batches: usize,
) -> Result<(usize, f64, f64)> {
    let scene = Scene::load(scene_path)?;
    super::deform::check_scene_matches(scene_path, &scene, op_path, file)?;
    let (drawing, _) = scene.drawing_with_junctions(Compat::None)?;
    let options = scene.fit_options(Compat::None).with_parallel(true);
    let mut precompute = Vec::with_capacity(JOIN_PRECOMPUTES);
    let mut rig = None;
    for _ in 0..JOIN_PRECOMPUTES {
        let clock = Instant::now();
        rig = Some(DefOpRig::precompute(
            &drawing, &file.mesh, &file.op, &options,
        )?);
        precompute.push(clock.elapsed().as_secs_f64());
    }
    let rig = rig.expect("JOIN_PRECOMPUTES > 0");
    let mut evaluator = rig.evaluator();
    let mut points = vec![Point::ZERO; rig.n_points()];
    let frames = per_batch.max(100);
    let mut times = Vec::with_capacity(batches);
    for _ in 0..batches {
        let clock = Instant::now();
        for k in 0..frames {
            evaluator.update(&configurations[k % configurations.len()], &mut points)?;
        }
        std::hint::black_box(&points);
        times.push(clock.elapsed().as_secs_f64() / frames as f64);
    }
    Ok((rig.n_points(), median(&mut precompute), median(&mut times)))
}

/// The median of `times` (sorted in place; not empty).
fn median(times: &mut [f64]) -> f64 {
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}
