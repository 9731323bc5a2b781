//! `splineskin subdiv …`: Catmull–Clark cages (OBJ) skinned so that their limit surface
//! follows the skinned surface (Liu, Jacobson & Gingold 2014 §3; [`splineskin::subdiv`]).
//! One file per subcommand.

mod animate;
mod bench;
mod compare;
mod deform;
mod refine;

use std::path::Path;

use crate::output::has_extension;
use anyhow::{bail, Result};
use clap::Subcommand;

#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Deform a scene's cage by one of its poses and write it as OBJ (tags kept).
    Deform(deform::Args),
    /// Play a scene's animation and hand it off: USD (the cage, Catmull-Clark, time-sampled
    /// points), binary glTF (the tessellated limit surface, morph targets) or OBJ frames.
    Animate(animate::Args),
    /// Our fit against skinning the cage, each against the skinned limit surface: errors and a
    /// PNG of both surfaces coloured by their error.
    Compare(compare::Args),
    /// Time precomputation and per-frame update on scenes or bare OBJ cages.
    Bench(bench::Args),
    /// Refine a cage uniformly and write the result as a new cage (tags carried).
    Refine(refine::Args),
}

pub fn run(args: Args) -> Result<()> {
    match args.command {
        Command::Deform(a) => deform::run(a),
        Command::Animate(a) => animate::run(a),
        Command::Compare(a) => compare::run(a),
        Command::Bench(a) => bench::run(a),
        Command::Refine(a) => refine::run(a),
    }
}

/// Refuses an output name that does not end in `.ext` (any case), before any work is done.
fn require_extension(path: &Path, ext: &str) -> Result<()> {
    let ok = has_extension(path, ext);
    if !ok {
        bail!("{}: expected a file name ending in .{ext}", path.display());
    }
    Ok(())
}
