//! `splineskin defop study [SCENE] -o study.png [--json] [--quick]`: the convergence study of
//! Poranne & Lipman 2016, Fig. 8 ([`splineskin::defop::study()`]): for the linear, quadratic,
//! cubic and thin-plate handle bases, the error against the ground truth on held-out handle
//! configurations (solved from the rest pose) as the number of training samples grows
//! geometrically. Error = mean over the held-out configurations of the RMS distance over the
//! shape, as a fraction of the rest shape's bounding-box diagonal. Prints a table (or, with
//! `--json`, one object per line: `basis`, `samples`, `error`, `max_error`, `fit_s`,
//! `energy`, `spatial_basis`, `triangles`, `held_out`) and writes
//! the log-log plot. Without a scene: the bundled octopus
//! ([`splineskin::examples::octopus_scene`]).

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result};
use serde::Serialize;
use splineskin::defop::{geometric_sample_counts, study, Energy, StudyOptions, StudyProgress};
use splineskin::scene::{energy_name, Scene, SpatialBasisSpec};

use super::{check_output_folder, progress_bar};
use crate::output::write_atomic;

/// Sample counts of the full study: 6 from 25 to 1000, geometrically.
const COUNTS: (usize, usize, usize) = (25, 1000, 6);
/// Sample counts of `--quick`: 4 from 25 to 200.
const QUICK_COUNTS: (usize, usize, usize) = (25, 200, 4);
/// Held-out configurations (full, quick).
const HELD_OUT: (usize, usize) = (20, 10);

#[derive(clap::Args)]
pub struct Args {
    /// The scene (our format; default: the bundled octopus).
    scene: Option<PathBuf>,
    /// The plot to write (.png).
    #[arg(short, long)]
    output: PathBuf,
    /// Print one JSON object per line instead of the table.
    #[arg(long)]
    json: bool,
    /// A quick run (under a minute): a coarser domain, 25 to 200 samples, 10 held out.
    #[arg(long)]
    quick: bool,
    /// Ground-truth energy: arap or symmetric-arap (default: the scene's, else
    /// symmetric-arap).
    #[arg(long, value_parser = super::energy_arg)]
    energy: Option<Energy>,
    /// Spatial basis: hats, eigen:N or biharmonic:N (default: the scene's, else hats).
    #[arg(long, value_parser = super::spatial_basis_arg)]
    spatial_basis: Option<SpatialBasisSpec>,
    /// Largest number of training samples (default 1000, quick 200).
    #[arg(long)]
    max_samples: Option<usize>,
    /// Held-out configurations (default 20, quick 10).
    #[arg(long)]
    held_out: Option<usize>,
}

#[derive(Serialize)]
struct Row<'a> {
    basis: &'a str,
    samples: usize,
    error: f64,
    max_error: f64,
    fit_s: f64,
    energy: &'a str,
    spatial_basis: &'a str,
    triangles: usize,
    held_out: usize,
}

pub fn run(args: Args) -> Result<()> {
    if crate::output::Format::of(&args.output).ok() != Some(crate::output::Format::Png) {
        anyhow::bail!("{}: expected a name ending in .png", args.output.display());
    }
    check_output_folder(&args.output)?;
    let scene = match &args.scene {
        Some(path) => Scene::load(path)?,
        None => splineskin::examples::octopus_scene(),
    };
    let s = super::train::settings(
        &scene,
        args.quick,
        args.energy,
        args.spatial_basis,
        None,
        None,
        None,
    );
    let (first, last, n) = if args.quick { QUICK_COUNTS } else { COUNTS };
    let last = args.max_samples.unwrap_or(last);
    anyhow::ensure!(
        last >= 1,
        "--max-samples {last}: expected at least 1 training sample"
    );
    let counts = geometric_sample_counts(first.min(last), last, n);
    let held_out = args
        .held_out
        .unwrap_or(if args.quick { HELD_OUT.1 } else { HELD_OUT.0 });
    let shape = scene.defop_shape(&s)?;
    let (mesh, handles) = (&shape.mesh, &shape.handles);
    let spatial = s
        .spatial_basis
        .build(mesh, handles)
        .with_context(|| format!("{}: spatial basis {}", shape.origin, s.spatial_basis.name()))?;
    eprintln!(
        "{}: {} vertices, {} triangles, {} handles; {}, {}, spatial basis {}; samples {:?}, {} held out, {} threads",
        shape.origin,
        mesh.n_vertices(),
        mesh.n_triangles(),
        handles.len(),
        energy_name(s.energy),
        s.region.describe(),
        s.spatial_basis.name(),
        counts,
        held_out,
        super::train::rayon_threads()
    );
    // The study replaces the sample count and the handle basis by its own.
    let train = s.train_options(mesh);
    let mut options = StudyOptions::new(train, counts.clone());
    options.n_held_out = held_out;
    let largest = counts.iter().copied().max().unwrap_or(0);
    let bar = progress_bar(largest + held_out, "ground truths");
    let clock = Instant::now();
    let result = study(mesh, handles, &spatial, &options, &|p| match p {
        StudyProgress::Training(p) => {
            bar.set_position(p.solved as u64);
            bar.set_message(format!("training stage {}/{}", p.stage + 1, p.n_stages));
        }
        StudyProgress::HeldOut { done, .. } => {
            bar.set_position((largest + done) as u64);
            bar.set_message("held out (from rest)");
        }
    })
    .with_context(|| format!("{}: study", scene.origin))?;
    bar.finish_and_clear();
    let seconds = clock.elapsed().as_secs_f64();

    let title = format!(
        "{} HANDLES, {} TRIANGLES, {}, {} HELD OUT",
        handles.len(),
        mesh.n_triangles(),
        energy_name(s.energy),
        held_out
    );
    let png =
        splineskin::figure::study_plot_png(&result, &title).context("drawing the study plot")?;
    write_atomic(&args.output, &png)?;

    if args.json {
        let spatial_name = s.spatial_basis.name();
        for r in &result.rows {
            println!(
                "{}",
                serde_json::to_string(&Row {
                    basis: r.basis.name(),
                    samples: r.samples,
                    error: r.error,
                    max_error: r.max_error,
                    fit_s: r.fit_seconds,
                    energy: energy_name(s.energy),
                    spatial_basis: &spatial_name,
                    triangles: mesh.n_triangles(),
                    held_out,
                })?
            );
        }
    } else {
        println!(
            "error = mean RMS distance over the shape to the held-out ground truth / bbox diagonal ({:.4}); {} held-out configurations solved from rest",
            result.diagonal, held_out
        );
        print!("{:>10}", "samples");
        for c in &counts {
            print!(" {c:>10}");
        }
        println!();
        for &basis in &options.bases {
            print!("{:>10}", basis.name());
            for &c in &counts {
                match result
                    .rows
                    .iter()
                    .find(|r| r.basis == basis && r.samples == c)
                {
                    Some(r) => print!(" {:>10.3e}", r.error),
                    None => print!(" {:>10}", "-"),
                }
            }
            println!();
        }
        println!(
            "training {:.1} s, held-out solves {:.1} s, total {seconds:.1} s; plot {}",
            result.training_seconds,
            result.held_out_seconds,
            args.output.display()
        );
    }
    Ok(())
}
