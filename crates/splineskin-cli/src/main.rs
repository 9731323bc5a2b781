//! `splineskin`: deform SVG drawings with spline skinning from the command line.
//!
//! One file per subcommand; the library does all the computing, this crate parses arguments,
//! formats results and writes files atomically.

mod animate;
mod bench;
mod compare;
mod defop;
mod deform;
mod demo;
mod dotlottie;
mod drawing_input;
mod frames_folder;
mod info;
mod output;
mod posing;
mod read_bandwidth;
mod rig;
mod serve;
mod subdiv;
#[cfg(test)]
mod test_support;
mod weights;

use clap::{Parser, Subcommand};

/// Deform vector drawings with point handles and keep them Bézier splines.
#[derive(Parser)]
#[command(name = "splineskin", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Deform a scene's drawing by one of its poses, or an SVG by pins and a pose given on the
    /// command line, and write SVG, PNG or JSON.
    Deform(deform::Args),
    /// Rig a drawing: write a scene with its pins (placed automatically unless given) and
    /// weights, ready for deform, animate, weights and serve.
    Rig(rig::Args),
    /// Animate a scene's keyframes: an animated SVG (SMIL) or a folder of numbered frames.
    Animate(animate::Args),
    /// Draw the spline fit beside the naive baselines (PNG) and print their metrics.
    Compare(compare::Args),
    /// Summarise a drawing: paths, curves and junction kinds.
    Info(info::Args),
    /// Time precomputation and per-frame update on scenes.
    Bench(bench::Args),
    /// Deform the bundled example drawing and write SVG and PNG files.
    Demo(demo::Args),
    /// Draw a scene's handle weights as PNG, or compute weights on a triangle mesh.
    Weights(weights::Args),
    /// Start the editor: a local web page to place and drag handles and watch the drawing
    /// follow live.
    Serve(serve::Args),
    /// Catmull–Clark cages (OBJ): deform, compare with skinning the cage, benchmark, refine.
    Subdiv(subdiv::Args),
    /// Deformation operators: train on a scene's point handles, evaluate, benchmark, and the
    /// convergence study.
    Defop(defop::Args),
}

fn main() -> std::process::ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Deform(a) => deform::run(a),
        Command::Rig(a) => rig::run(a),
        Command::Animate(a) => animate::run(a),
        Command::Compare(a) => compare::run(a),
        Command::Info(a) => info::run(a),
        Command::Bench(a) => bench::run(a),
        Command::Demo(a) => demo::run(a),
        Command::Weights(a) => weights::run(a),
        Command::Serve(a) => serve::run(a),
        Command::Subdiv(a) => subdiv::run(a),
        Command::Defop(a) => defop::run(a),
    };
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!(
                "error: {}",
                splineskin::errors::message_with_causes(e.as_ref())
            );
            std::process::ExitCode::FAILURE
        }
    }
}
