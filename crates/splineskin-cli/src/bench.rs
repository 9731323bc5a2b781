//! `splineskin bench SCENE… [--json]`: medians of the scene's setup (reading the drawing and,
//! for the mesh families, building the domain and solving the weights), weight sampling,
//! precomputation and per-frame update, separately; for drawings with G¹ or fixed-angle
//! junctions also the flexible solve, cold and warm-started, and the fold check run after an
//! update ([`splineskin::folds::FoldCheck`]). The update's bytes per second (its
//! operator read once) are printed beside the machine's read bandwidth
//! ([`crate::read_bandwidth`]) and their ratio.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use kurbo::{Affine, Point};
use serde::Serialize;
use splineskin::scene::{Compat, Deformer, Engine, HandleSet, PosedDrawing, Scene, Setup};
use splineskin::spline_fit::quadrature::SampledCurves;
use splineskin::spline_fit::{FlexibleOptions, FlexibleSolver, SplineRig};

use crate::posing::CompatArg;

/// Fewest timed updates per scene.
const MIN_UPDATES: usize = 200;
/// Fewest timed precomputations per scene.
const MIN_PRECOMPUTES: usize = 3;
/// Timed scene setups per scene (each solves the weights: seconds for big mesh domains).
const SETUPS: usize = 3;
/// Timed flexible solves per scene (cold, and warm-started from the previous pose's).
const FLEXIBLE_SOLVES: usize = 21;
/// Precomputations are repeated until this much time has been spent (or 50 runs).
const PRECOMPUTE_BUDGET: Duration = Duration::from_secs(2);
const MAX_PRECOMPUTES: usize = 50;
/// Largest `--synthetic` drawing, in curves: 1 000 000. Its rig (five handles) holds about
/// 1.6 GB of operator; far larger requests would fail to allocate (or overflow the size
/// computation) rather than report an error.
const MAX_SYNTHETIC_CURVES: usize = 1_000_000;

#[derive(clap::Args)]
pub struct Args {
    /// Scenes (our format or the paper authors').
    scenes: Vec<PathBuf>,
    /// Print one JSON object per line instead of a table.
    #[arg(long)]
    json: bool,
    /// Number of timed updates (at least 200).
    #[arg(long, default_value_t = 1000)]
    updates: usize,
    /// Also time a synthetic drawing of at least this many curves: the bundled drawing tiled,
    /// with five handles spread over it.
    #[arg(long)]
    synthetic: Option<usize>,
    /// Discretisation to time.
    #[arg(long, value_enum, default_value_t = CompatArg::None)]
    compat: CompatArg,
}

#[derive(Serialize)]
struct Row {
    scene: String,
    curves: usize,
    paths: usize,
    handles: usize,
    constraints: usize,
    /// Vertices of the triangulated domain (mesh weight families only).
    #[serde(skip_serializing_if = "Option::is_none")]
    domain_vertices: Option<usize>,
    /// Median seconds of `Scene::setup`: drawing read, domain built and weights solved.
    setup_s: f64,
    weights_s: f64,
    precompute_s: f64,
    update_s: f64,
    /// Median seconds of checking an updated drawing for folds (crossings of closed outlines
    /// the deformation made, [`splineskin::folds::FoldCheck`]), the rest's found once.
    folds_s: f64,
    /// Median seconds of a flexible G¹ solve from the rig's result (scenes with G¹ or
    /// fixed-angle junctions only).
    #[serde(skip_serializing_if = "Option::is_none")]
    flexible_s: Option<f64>,
    /// The same, warm-started from the previous pose's flexible solution (a drag).
    #[serde(skip_serializing_if = "Option::is_none")]
    flexible_warm_s: Option<f64>,
    /// Bytes of the rig's operator, which each update reads once.
    update_bytes: usize,
    /// `update_bytes / update_s`.
    update_bytes_per_s: f64,
    /// The machine's read bandwidth ([`crate::read_bandwidth`]), measured once per run.
    read_bytes_per_s: f64,
    /// `update_bytes_per_s / read_bytes_per_s`: how close the update is to streaming its
    /// operator at memory speed (1).
    bandwidth_ratio: f64,
    /// Threads the update runs on ([`SplineRig::update_threads`]).
    update_threads: usize,
    /// Median seconds of the same updates reading the operator rounded to `f32`
    /// ([`SplineRig::with_single_precision`]).
    update_f32_s: f64,
    /// Largest distance of an `f32` update's point from the `f64` one, over the timed poses,
    /// relative to the drawing's diagonal.
    f32_error: f64,
}

pub fn run(args: Args) -> Result<()> {
    anyhow::ensure!(
        !args.scenes.is_empty() || args.synthetic.is_some(),
        "no scenes given (and no --synthetic)"
    );
    if let Some(n) = args.synthetic {
        anyhow::ensure!(
            n <= MAX_SYNTHETIC_CURVES,
            "--synthetic {n}: expected at most {MAX_SYNTHETIC_CURVES} curves"
        );
    }
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let read_bytes_per_s = crate::read_bandwidth::read_bandwidth(threads);
    if !args.json {
        println!(
            "memory read bandwidth: {:.1} GB/s (a sum over {} MiB on {threads} threads, median of {} passes)",
            read_bytes_per_s / 1e9,
            crate::read_bandwidth::BUFFER_BYTES >> 20,
            crate::read_bandwidth::PASSES
        );
        println!(
            "{:<60} {:>7} {:>7} {:>11} {:>9} {:>10} {:>12} {:>14} {:>12} {:>10} {:>7} {:>12} {:>9} {:>12} {:>10}",
            "scene",
            "curves",
            "handles",
            "constraints",
            "domain V",
            "setup (s)",
            "weights (s)",
            "precompute (s)",
            "update (s)",
            "folds (s)",
            "threads",
            "update GB/s",
            "of memory",
            "f32 upd (s)",
            "f32 error"
        );
    }
    for path in &args.scenes {
        let scene = Scene::load(path)?;
        anyhow::ensure!(
            scene.engine == Engine::Ours,
            "{}: engine '{}' is a naive baseline; bench times engine 'ours' only",
            path.display(),
            scene.engine.name()
        );
        let mut setup_times = Vec::with_capacity(SETUPS);
        let mut setup = None;
        for _ in 0..SETUPS {
            let t = Instant::now();
            let s = scene.setup(args.compat.into())?;
            setup_times.push(t.elapsed().as_secs_f64());
            setup = Some(s);
        }
        let mut setup = setup.expect("SETUPS > 0");
        setup.options = setup.options.with_parallel(true);
        let base = scene.pose(0).map(|p| p.transforms).unwrap_or_default();
        let compat: Compat = args.compat.into();
        let flexible = scene
            .flexible_options_or(true, compat)
            .unwrap_or_else(|| compat.flexible_options());
        let domain_vertices = setup.domain.as_ref().map(|d| d.mesh.n_vertices());
        let mut row = measure(
            &path.display().to_string(),
            setup,
            &base,
            &scene.handle_set(),
            args.updates,
            flexible,
            read_bytes_per_s,
        )
        .with_context(|| format!("{}: building the rig", path.display()))?;
        row.setup_s = median(setup_times);
        row.domain_vertices = domain_vertices;
        print_row(&row, args.json);
    }
    if let Some(min_curves) = args.synthetic {
        let scene = splineskin::examples::demo_scene();
        let start = Instant::now();
        let mut setup = scene.setup(args.compat.into())?;
        let (drawing, handles) =
            splineskin::examples::tile(&setup.drawing, &scene.handles, min_curves);
        setup.drawing = drawing;
        setup.weights = std::sync::Arc::new(splineskin::weights::Shepard::new(
            &handles,
            splineskin::weights::ShepardOptions::default(),
        ));
        setup.options = setup.options.with_parallel(true);
        let base = vec![Affine::IDENTITY; handles.len()];
        let name = format!("synthetic: bundled drawing tiled to {min_curves}+ curves");
        let set = HandleSet {
            points: &handles,
            bones: &[],
            cage: None,
        };
        let setup_s = start.elapsed().as_secs_f64();
        let mut row = measure(
            &name,
            setup,
            &base,
            &set,
            args.updates,
            FlexibleOptions::default(),
            read_bytes_per_s,
        )?;
        row.setup_s = setup_s;
        print_row(&row, args.json);
    }
    Ok(())
}

fn print_row(row: &Row, json: bool) {
    if json {
        println!(
            "{}",
            serde_json::to_string(row).expect("plain numbers serialise")
        );
    } else {
        println!(
            "{:<60} {:>7} {:>7} {:>11} {:>9} {:>10.3e} {:>12.3e} {:>14.3e} {:>12.3e} {:>10.3e} {:>7} {:>12.2} {:>9.2} {:>12.3e} {:>10.1e}",
            row.scene,
            row.curves,
            row.handles,
            row.constraints,
            row.domain_vertices
                .map_or("-".to_string(), |n| n.to_string()),
            row.setup_s,
            row.weights_s,
            row.precompute_s,
            row.update_s,
            row.folds_s,
            row.update_threads,
            row.update_bytes_per_s / 1e9,
            row.bandwidth_ratio,
            row.update_f32_s,
            row.f32_error
        );
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Times the phases of posing `setup`'s drawing: weight sampling, precomputation, the update
/// of the fixed-ratio [`PosedDrawing`] and, with G¹ or fixed-angle junctions, that of the
/// flexible one.
fn measure(
    name: &str,
    setup: Setup,
    base: &[Affine],
    handles: &HandleSet<'_>,
    updates: usize,
    flexible: FlexibleOptions,
    read_bytes_per_s: f64,
) -> Result<Row> {
    let (drawing, weights) = (&setup.drawing, setup.weights.as_ref());
    let start = Instant::now();
    let mut weight_times = Vec::new();
    let mut samples = None;
    while weight_times.len() < MIN_PRECOMPUTES
        || (start.elapsed() < PRECOMPUTE_BUDGET / 2 && weight_times.len() < MAX_PRECOMPUTES)
    {
        let t = Instant::now();
        let s = SampledCurves::sample(drawing, weights, &setup.options);
        weight_times.push(t.elapsed().as_secs_f64());
        samples = Some(s);
    }
    let samples = samples.context("no samples")?;
    let start = Instant::now();
    let mut pre_times = Vec::new();
    let mut rig = None;
    while pre_times.len() < MIN_PRECOMPUTES
        || (start.elapsed() < PRECOMPUTE_BUDGET && pre_times.len() < MAX_PRECOMPUTES)
    {
        let t = Instant::now();
        let r = SplineRig::from_samples(drawing, &samples, &setup.options)?;
        pre_times.push(t.elapsed().as_secs_f64());
        rig = Some(r);
    }
    let rig = rig.context("no rig")?;
    // Varying poses: every handle's saved transform followed by a small rotation about the
    // handle's pivot (a small translation for cage vertices) that changes from frame to frame.
    let n = updates.max(MIN_UPDATES);
    let poses: Vec<Vec<Affine>> = (0..n)
        .map(|k| {
            handles
                .wobble(|i| 0.2 * ((k as f64) * 0.05 + i as f64).sin())
                .iter()
                .zip(base)
                .map(|(w, t)| *w * *t)
                .collect()
        })
        .collect();
    let (curves, paths) = (drawing.n_curves(), drawing.paths.len());
    let (n_handles, n_constraints) = (rig.n_handles(), rig.n_constraints());
    let update_bytes = std::mem::size_of_val(rig.operator());
    let flexible_solver = FlexibleSolver::from_rig(
        rig.clone(),
        &setup.drawing,
        &samples,
        &setup.options,
        flexible,
    )?;
    let update_threads = rig.update_threads();
    let single = rig.with_single_precision(true);
    let posed = PosedDrawing::from_parts(name, setup, Deformer::Fixed(rig));
    let mut out = vec![Point::ZERO; posed.n_points()];
    let mut update_times = Vec::with_capacity(n);
    let mut fold_times = Vec::with_capacity(n);
    let fold_check =
        splineskin::folds::FoldCheck::new(posed.drawing(), &posed.drawing().flat_points());
    let mut fold_scratch = splineskin::folds::FoldScratch::default();
    let mut folds = Vec::new();
    for pose in &poses {
        let t = Instant::now();
        posed.update(pose, &mut out)?;
        update_times.push(t.elapsed().as_secs_f64());
        std::hint::black_box(&out);
        let t = Instant::now();
        fold_check.new_crossings_into(posed.drawing(), &out, &mut fold_scratch, &mut folds);
        std::hint::black_box(&folds);
        fold_times.push(t.elapsed().as_secs_f64());
    }
    // The same updates reading the operator rounded to f32, and how far their points land
    // from the f64 ones (largest distance over the poses, relative to the diagonal).
    let mut full = vec![Point::ZERO; posed.n_points()];
    let diagonal = posed.drawing().diagonal();
    let full_rig = posed.rig().context("a fixed rig")?.clone();
    let posed = PosedDrawing::from_parts(name, posed.into_setup(), Deformer::Fixed(single));
    let mut f32_times = Vec::with_capacity(n);
    let mut f32_gap: f64 = 0.0;
    for pose in &poses {
        let t = Instant::now();
        posed.update(pose, &mut out)?;
        f32_times.push(t.elapsed().as_secs_f64());
        full_rig.update(pose, &mut full)?;
        let gap = out
            .iter()
            .zip(&full)
            .map(|(a, b)| (*a - *b).hypot())
            .fold(0.0, f64::max);
        f32_gap = f32_gap.max(gap);
    }
    let posed = PosedDrawing::from_parts(
        name,
        posed.into_setup(),
        Deformer::Flexible(Box::new(flexible_solver)),
    );
    let (flexible_s, flexible_warm_s) = measure_flexible(&posed, &poses)?;
    let update_s = median(update_times);
    let update_bytes_per_s = update_bytes as f64 / update_s;
    Ok(Row {
        scene: name.to_string(),
        curves,
        paths,
        handles: n_handles,
        constraints: n_constraints,
        domain_vertices: None,
        setup_s: 0.0,
        weights_s: median(weight_times),
        precompute_s: median(pre_times),
        update_s,
        folds_s: median(fold_times),
        flexible_s,
        flexible_warm_s,
        update_bytes,
        update_bytes_per_s,
        read_bytes_per_s,
        bandwidth_ratio: update_bytes_per_s / read_bytes_per_s,
        update_threads,
        update_f32_s: median(f32_times),
        f32_error: f32_gap / diagonal,
    })
}

/// Medians of the flexible solve over the first [`FLEXIBLE_SOLVES`] of `poses` (consecutive
/// poses differ by a small rotation, as in a drag): cold (from the rig's result) and warm
/// (from the previous pose's flexible solution). `None` when the drawing has no G¹ or
/// fixed-angle junction.
fn measure_flexible(
    posed: &PosedDrawing,
    poses: &[Vec<Affine>],
) -> Result<(Option<f64>, Option<f64>)> {
    if posed
        .flexible_solver()
        .map_or(0, |s| s.n_flexible_junctions())
        == 0
    {
        return Ok((None, None));
    }
    let n = FLEXIBLE_SOLVES.min(poses.len());
    let mut out = vec![Point::ZERO; posed.n_points()];
    let mut previous = vec![Point::ZERO; posed.n_points()];
    let (mut cold, mut warm) = (Vec::with_capacity(n), Vec::with_capacity(n));
    for (k, pose) in poses.iter().take(n).enumerate() {
        let t = Instant::now();
        posed.update(pose, &mut out)?;
        cold.push(t.elapsed().as_secs_f64());
        if k > 0 {
            let t = Instant::now();
            posed.update_from(pose, Some(&previous), &mut out)?;
            warm.push(t.elapsed().as_secs_f64());
        }
        std::mem::swap(&mut previous, &mut out);
    }
    Ok((Some(median(cold)), Some(median(warm))))
}
