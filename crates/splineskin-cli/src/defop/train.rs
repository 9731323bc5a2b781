//! `splineskin defop train SCENE -o OP`: trains a deformation operator for the scene's point
//! handles ([`splineskin::defop::train`]) with the settings of the scene's `defop` section
//! ([`splineskin::scene::defop`]) and the command line's overrides, shows a progress bar,
//! writes the operator file ([`OperatorFile`]) and prints a summary: sizes, per-stage times,
//! and the error against the ground truth on a few held-out configurations.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result};
use kurbo::Point;
use splineskin::defop::{
    ground_truths_from_rest, l2_distance, train, Energy, HandleBasisKind, OperatorFile, Sampler,
    TrainingMetadata,
};
use splineskin::scene::{energy_name, Cover, DefOpSettings, Scene, SpatialBasisSpec};

use super::{check_output_folder, progress_bar};

/// `--quick`: training samples.
pub const QUICK_SAMPLES: usize = 100;
/// `--quick`: largest triangle of the drawing's domain, as a fraction of its area.
pub const QUICK_AREA_FRACTION: f64 = 1.0 / 400.0;
/// `--quick`: curve samples per drawing diagonal of the domain.
pub const QUICK_SAMPLES_PER_DIAGONAL: f64 = 40.0;
/// Seed of the held-out configurations of the summary (not the training's).
const HELD_OUT_SEED: u64 = 424_242;

#[derive(clap::Args)]
pub struct Args {
    /// The scene (our format): its point handles, drawing and `defop` section.
    scene: PathBuf,
    /// The operator file to write.
    #[arg(short, long)]
    output: PathBuf,
    /// Training samples besides the rest configuration (default: the scene's, else 1000).
    #[arg(long)]
    samples: Option<usize>,
    /// Ground-truth energy: arap or symmetric-arap (default: the scene's, else
    /// symmetric-arap).
    #[arg(long, value_parser = super::energy_arg)]
    energy: Option<Energy>,
    /// Spatial basis: hats, eigen:N or biharmonic:N (default: the scene's, else hats).
    #[arg(long, value_parser = super::spatial_basis_arg)]
    spatial_basis: Option<SpatialBasisSpec>,
    /// Handle basis: linear, quadratic, cubic or tps (default: the scene's, else tps).
    #[arg(long, value_parser = super::handle_basis_arg)]
    handle_basis: Option<HandleBasisKind>,
    /// Seed of the training sampler (default: the scene's, else 1).
    #[arg(long)]
    seed: Option<u64>,
    /// Also follow the scene's poses (`poses`), or its animation and poses (`animation`): half
    /// the samples are drawn around the way from the rest to them (default: the scene's
    /// `defop.cover`, else `none`).
    #[arg(long, value_parser = cover_arg)]
    cover: Option<Cover>,
    /// A quick run: 100 samples (unless --samples) and a coarser domain.
    #[arg(long)]
    quick: bool,
    /// Held-out configurations whose error the summary reports (0: skip).
    #[arg(long, default_value_t = 10)]
    held_out: usize,
}

/// The scene's settings with the command line's overrides.
pub(super) fn settings(
    scene: &Scene,
    quick: bool,
    energy: Option<Energy>,
    spatial_basis: Option<SpatialBasisSpec>,
    handle_basis: Option<HandleBasisKind>,
    samples: Option<usize>,
    seed: Option<u64>,
) -> DefOpSettings {
    let mut s = scene.defop.clone().unwrap_or_default();
    if quick {
        s.samples = s.samples.min(QUICK_SAMPLES);
        s.domain.max_area_fraction = s.domain.max_area_fraction.max(QUICK_AREA_FRACTION);
        s.domain.samples_per_diagonal = s
            .domain
            .samples_per_diagonal
            .min(QUICK_SAMPLES_PER_DIAGONAL);
    }
    if let Some(e) = energy {
        s.energy = e;
    }
    if let Some(b) = spatial_basis {
        s.spatial_basis = b;
    }
    if let Some(b) = handle_basis {
        s.handle_basis = b;
    }
    if let Some(n) = samples {
        s.samples = n;
    }
    if let Some(seed) = seed {
        s.seed = seed;
    }
    s
}

pub fn run(args: Args) -> Result<()> {
    check_output_folder(&args.output)?;
    anyhow::ensure!(
        args.samples != Some(0),
        "--samples 0: expected at least 1 training sample"
    );
    let scene = Scene::load(&args.scene)?;
    let mut s = settings(
        &scene,
        args.quick,
        args.energy,
        args.spatial_basis,
        args.handle_basis,
        args.samples,
        args.seed,
    );
    if let Some(cover) = args.cover {
        s.cover = cover;
    }
    let clock = Instant::now();
    let shape = scene.defop_shape(&s)?;
    let (mesh, handles) = (&shape.mesh, &shape.handles);
    let shape_seconds = clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    let spatial = s
        .spatial_basis
        .build(mesh, handles)
        .with_context(|| format!("{}: spatial basis {}", shape.origin, s.spatial_basis.name()))?;
    let basis_seconds = clock.elapsed().as_secs_f64();
    let rest: Vec<Point> = handles.iter().map(|&h| mesh.vertices[h]).collect();
    let cover = scene.cover_configurations(s.cover, &rest)?;
    anyhow::ensure!(
        s.cover == Cover::None || !cover.is_empty(),
        "{}: --cover {}: the scene has no {} that move a handle",
        args.scene.display(),
        s.cover.name(),
        if s.cover == Cover::Poses {
            "poses"
        } else {
            "poses or animation"
        }
    );
    let options = s.train_options(mesh).with_cover(cover.clone());
    let region = if cover.is_empty() {
        s.region.describe()
    } else {
        format!(
            "{}, half of them along the way to {} {} configurations",
            s.region.describe(),
            cover.len(),
            s.cover.name()
        )
    };
    eprintln!(
        "{}: {} vertices, {} triangles, {} handles; {}, {} samples ({}), spatial basis {} ({} functions), handle basis {}, {} threads",
        shape.origin,
        mesh.n_vertices(),
        mesh.n_triangles(),
        handles.len(),
        energy_name(s.energy),
        s.samples,
        region,
        s.spatial_basis.name(),
        spatial.n_functions(),
        s.handle_basis.name(),
        rayon_threads(),
    );
    let bar = progress_bar(s.samples, "ground truths");
    let clock = Instant::now();
    let training = train(mesh, handles, &spatial, &options, &|p| {
        bar.set_position(p.solved as u64);
        bar.set_message(format!("stage {}/{}", p.stage + 1, p.n_stages));
    })
    .with_context(|| format!("{}: training", args.scene.display()))?;
    bar.finish_and_clear();
    let training_seconds = clock.elapsed().as_secs_f64();
    let metadata = {
        let mut m = TrainingMetadata::default();
        m.energy = Some(energy_name(s.energy).into());
        m.n_samples = Some(s.samples);
        m.sample_region = Some(region.clone());
        m.seed = Some(s.seed);
        m.training_seconds = Some(training_seconds);
        m.source = Some(args.scene.display().to_string());
        m.spatial_basis = Some(s.spatial_basis.name());
        m
    };
    let file = OperatorFile::new(mesh.clone(), training.op.clone(), metadata)?;
    file.save(&args.output)?;

    println!(
        "{}: {} vertices, {} triangles, {} handles, {} samples; spatial basis {} ({} functions), handle basis {} ({} functions)",
        args.output.display(),
        mesh.n_vertices(),
        mesh.n_triangles(),
        handles.len(),
        s.samples,
        s.spatial_basis.name(),
        spatial.n_functions(),
        s.handle_basis.name(),
        training.op.handle_basis().n_functions(),
    );
    println!("shape {shape_seconds:.2} s, spatial basis {basis_seconds:.2} s");
    for (i, st) in training.stages.iter().enumerate() {
        println!(
            "stage {i}: {:>5} new samples, {:>5} fitted ({}), iterations min {} mean {:.1} max {}, {} rest starts, {} not converged; solve {:.2} s, fit {:.2} s",
            st.n_new,
            st.n_fitted,
            st.handle_basis.name(),
            st.iterations.0,
            st.iterations.1,
            st.iterations.2,
            st.rest_starts,
            st.not_converged,
            st.solve_seconds,
            st.fit_seconds
        );
    }
    println!("training: {training_seconds:.2} s");
    if args.held_out > 0 {
        let rest: Vec<Point> = handles.iter().map(|&h| mesh.vertices[h]).collect();
        let held_out =
            Sampler::new(&rest, &options.regions, HELD_OUT_SEED)?.configurations(args.held_out);
        let clock = Instant::now();
        let truths = ground_truths_from_rest(mesh, handles, &options, &held_out, &|_| {})?;
        let mut sum = 0.0;
        for (q, u) in held_out.iter().zip(&truths) {
            sum += l2_distance(mesh, &training.op.eval(q)?, u)?;
        }
        println!(
            "held-out error: {:.3e} of the bounding-box diagonal ({:.4} drawing units; mean RMS distance over the shape, {} configurations solved from rest in {:.2} s)",
            sum / held_out.len() as f64 / mesh.bounding_box_diagonal(),
            sum / held_out.len() as f64,
            held_out.len(),
            clock.elapsed().as_secs_f64()
        );
    }
    Ok(())
}

/// Threads of rayon's pool (RAYON_NUM_THREADS or the cores).
/// Reads `--cover`: `none`, `poses` or `animation`.
fn cover_arg(name: &str) -> Result<Cover, String> {
    Cover::parse(name).ok_or_else(|| format!("{name:?}: expected none, poses or animation"))
}

pub(super) fn rayon_threads() -> usize {
    std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(
            std::env::var("RAYON_NUM_THREADS")
                .ok()
                .and_then(|v| v.parse().ok())
                .filter(|&n: &usize| n > 0)
                .unwrap_or(usize::MAX),
        )
}
