//! `splineskin defop bench OP [--json]`: evaluations per second of an operator file: the
//! median over timed batches of the allocation-free evaluator ([`DefOpEvaluator::eval`]: all
//! vertex positions) at configurations drawn in discs of 5 % of the diagonal, and of the spatial
//! coefficients alone.
//!
//! [`DefOpEvaluator::eval`]: splineskin::defop::DefOpEvaluator::eval

use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::Result;
use kurbo::Point;
use serde::Serialize;
use splineskin::defop::{OperatorFile, SampleRegion, Sampler, DEFAULT_DISC_FRACTION};

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
}

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
    }
    Ok(())
}

/// The median of `times` (sorted in place; not empty).
fn median(times: &mut [f64]) -> f64 {
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}
