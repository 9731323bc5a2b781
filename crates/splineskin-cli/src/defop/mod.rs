//! `splineskin defop …`: deformation operators (Poranne & Lipman 2016; [`splineskin::defop`]):
//! train one for a scene's point handles, evaluate it, benchmark it, and reproduce the
//! paper's convergence study. One file per subcommand.

mod bench;
mod deform;
mod eval;
mod study;
mod train;

use std::path::Path;

use anyhow::{bail, Context, Result};
use clap::Subcommand;
use indicatif::{ProgressBar, ProgressStyle};
use splineskin::defop::{Energy, HandleBasisKind};
use splineskin::scene::{parse_energy, parse_handle_basis, SpatialBasisSpec};

#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Train an operator for a scene's point handles (its drawing's domain or a mesh file) and
    /// write it to an operator file.
    Train(train::Args),
    /// Deform a scene's drawing by one of its poses through a trained operator (the join of
    /// the operator with the spline fit) and write SVG, PNG or JSON.
    Deform(deform::Args),
    /// Evaluate an operator at handle positions: deformed vertices as JSON, or a PNG.
    Eval(eval::Args),
    /// The convergence study (the paper's Fig. 8): error against held-out ground truth per
    /// handle basis as the number of training samples grows; a table, a PNG plot, JSON lines.
    Study(study::Args),
    /// Evaluations per second of an operator file.
    Bench(bench::Args),
}

pub fn run(args: Args) -> Result<()> {
    match args.command {
        Command::Train(a) => train::run(a),
        Command::Deform(a) => deform::run(a),
        Command::Eval(a) => eval::run(a),
        Command::Study(a) => study::run(a),
        Command::Bench(a) => bench::run(a),
    }
}

/// `--energy` values.
fn energy_arg(text: &str) -> Result<Energy, String> {
    parse_energy(text).ok_or_else(|| format!("{text:?}: expected arap or symmetric-arap"))
}

/// `--handle-basis` values.
fn handle_basis_arg(text: &str) -> Result<HandleBasisKind, String> {
    parse_handle_basis(text)
        .ok_or_else(|| format!("{text:?}: expected linear, quadratic, cubic or tps"))
}

/// `--spatial-basis` values.
fn spatial_basis_arg(text: &str) -> Result<SpatialBasisSpec, String> {
    SpatialBasisSpec::parse(text)
        .ok_or_else(|| format!("{text:?}: expected hats, eigen:N or biharmonic:N"))
}

/// A progress bar on stderr (hidden when stderr is not a terminal, as indicatif does).
fn progress_bar(len: usize, what: &str) -> ProgressBar {
    let bar = ProgressBar::new(len as u64);
    let template = format!("{{elapsed_precise}} [{{bar:40}}] {{pos}}/{{len}} {what} {{msg}}");
    if let Ok(style) = ProgressStyle::with_template(&template) {
        bar.set_style(style);
    }
    bar
}

/// Refuses an output whose folder does not exist, before any work is done.
fn check_output_folder(path: &Path) -> Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        if !dir.is_dir() {
            bail!(
                "{}: cannot write: the folder {} does not exist",
                path.display(),
                dir.display()
            );
        }
    }
    Ok(())
}

/// Reads a JSON file with a message naming it.
fn read_json(path: &Path) -> Result<serde_json::Value> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("{}: cannot read", path.display()))?;
    serde_json::from_str(&text).with_context(|| format!("{}: not valid JSON", path.display()))
}
