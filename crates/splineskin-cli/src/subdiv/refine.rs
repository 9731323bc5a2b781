//! `splineskin subdiv refine IN.obj --levels K -o OUT.obj`: the `K`-th uniform refinement of a
//! cage as a cage of its own, with the decayed crease and corner sharpness, holes and option
//! tags carried ([`splineskin::subdiv::UniformLevel::to_cage`]): its limit surface is the
//! input's.

use std::path::PathBuf;

use anyhow::{Context, Result};
use splineskin::subdiv::{read_obj, refine_uniform, to_obj_string, MAX_UNIFORM_LEVEL};

use crate::output::write_atomic;

#[derive(clap::Args)]
pub struct Args {
    /// The cage (OBJ, with OpenSubdiv's `t crease`/`corner`/`hole` tags).
    input: PathBuf,
    /// Number of uniform refinement steps (each splits every face into quads: ×4 faces).
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=MAX_UNIFORM_LEVEL as i64))]
    levels: u8,
    /// The refined cage (`.obj`).
    #[arg(short, long)]
    output: PathBuf,
}

pub fn run(args: Args) -> Result<()> {
    super::require_extension(&args.output, "obj")?;
    let cage = read_obj(&args.input)?;
    let levels = usize::from(args.levels);
    let refined = refine_uniform(&cage, levels)
        .with_context(|| format!("{}: refining {levels} levels", args.input.display()))?;
    let last = refined
        .levels()
        .last()
        .context("no refined level (a bug)")?;
    let fine = last
        .to_cage()
        .with_context(|| format!("{}: the refined cage", args.input.display()))?;
    write_atomic(&args.output, to_obj_string(&fine).as_bytes())?;
    eprintln!(
        "{}: {} vertices, {} faces -> {}: {} vertices, {} faces ({} creases, {} corners, {} holes)",
        args.input.display(),
        cage.n_vertices(),
        cage.n_faces(),
        args.output.display(),
        fine.n_vertices(),
        fine.n_faces(),
        fine.tags().creases.len(),
        fine.tags().corners.len(),
        fine.tags().holes.len()
    );
    Ok(())
}
