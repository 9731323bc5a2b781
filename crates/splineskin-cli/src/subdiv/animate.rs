//! `splineskin subdiv animate SCENE -o anim.usda | anim.glb | DIR`: the scene's `animation`
//! keyframes sampled at its frame rate, each frame's cage fitted by the rig built once, and
//! handed off ([`splineskin::subdiv::handoff`]):
//!
//! * `-o NAME.usda`: the fitted cage as a Catmull–Clark USD mesh with time-sampled points (what
//!   Blender, Houdini, Maya and usdview subdivide into our limit surface);
//! * `-o NAME.glb`: the limit surface tessellated at `--level` (the grid of
//!   `subdiv deform --limit-mesh`), one morph target per frame;
//! * `-o DIR`: `DIR/frame-0000.obj`, … the fitted cage of every frame, faces and tags kept (an
//!   existing `DIR` is replaced only if it holds nothing but `frame-*.obj` files).
//!
//! Files are written whole or not at all.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use splineskin::subdiv::handoff::{FittedAnimation, UpAxis};
use splineskin::subdiv::{to_obj_string, Point3, SubdivScene, SubdivSetup, MAX_LIMIT_MESH_LEVEL};

use crate::frames_folder::{frame_name, replace_frames_folder, write_synced};
use crate::output::{has_extension, write_atomic};

#[derive(clap::Args)]
pub struct Args {
    /// The scene (JSON, `"splineskin_subdiv_scene": 1`) with an `animation`.
    scene: PathBuf,
    /// `NAME.usda` (USD), `NAME.glb` (binary glTF) or a folder of OBJ frames.
    #[arg(short, long)]
    output: PathBuf,
    /// Level of the glTF's tessellation: (2^K)² quads (two triangles each) per cage quad.
    #[arg(long, default_value_t = 3,
          value_parser = clap::value_parser!(u8).range(1..=MAX_LIMIT_MESH_LEVEL as i64))]
    level: u8,
    /// The model's up axis, written to USD's `upAxis` (glTF is Y-up: a Z-up model is turned
    /// on its node).
    #[arg(long, value_enum, default_value = "y")]
    up: Up,
    /// Frames per second (default: the scene's `animation.fps`).
    #[arg(long)]
    fps: Option<f64>,
}

#[derive(Clone, Copy, Debug, clap::ValueEnum)]
enum Up {
    Y,
    Z,
}

/// What `-o` names.
enum Output {
    Usd,
    Gltf,
    ObjFolder,
}

impl Output {
    fn of(path: &Path) -> Result<Output> {
        Ok(if has_extension(path, "usda") {
            Output::Usd
        } else if has_extension(path, "glb") {
            Output::Gltf
        } else if ["usd", "usdc", "usdz", "gltf", "obj", "fbx", "abc"]
            .iter()
            .any(|e| has_extension(path, e))
        {
            bail!(
                "{}: this command writes .usda (USD text), .glb (binary glTF) or a folder of OBJ frames; \
                 name the output so",
                path.display()
            )
        } else {
            Output::ObjFolder
        })
    }
}

pub fn run(args: Args) -> Result<()> {
    let output = Output::of(&args.output)?;
    let mut scene = SubdivScene::load(&args.scene)?;
    if let Some(fps) = args.fps {
        let animation = scene.animation.as_ref().with_context(|| {
            format!(
                "{}: animation: the scene has no animation to play",
                args.scene.display()
            )
        })?;
        scene.animation = Some(
            animation
                .with_fps(fps)
                .with_context(|| format!("--fps {fps}"))?,
        );
    }
    // Sampled before the precompute: a scene without a playable animation fails at once.
    let frames = scene.animation_frames()?;
    let setup = scene.setup()?;
    let fitted = FittedAnimation::of_frames(&scene, frames, &setup)?;
    let up = match args.up {
        Up::Y => UpAxis::Y,
        Up::Z => UpAxis::Z,
    };
    let name = scene
        .obj
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    match output {
        Output::Usd => {
            let text = fitted
                .usda(&setup, &name, up)
                .with_context(|| format!("{}: writing USD", args.output.display()))?;
            write_atomic(&args.output, text.as_bytes())?;
        }
        Output::Gltf => {
            let glb = fitted
                .glb(&setup, usize::from(args.level), &name, up)
                .with_context(|| format!("{}: writing glTF", args.output.display()))?;
            write_atomic(&args.output, &glb)?;
        }
        Output::ObjFolder => write_obj_frames(&args.output, &setup, &fitted.cages)?,
    }
    let (fps, times) = (fitted.fps, &fitted.times);
    eprintln!(
        "{}: {} frames at {fps} fps ({} s), {} handles, a cage of {} vertices and {} faces",
        args.output.display(),
        times.len(),
        times[times.len() - 1],
        scene.handles.n_handles(),
        setup.cage.n_vertices(),
        setup.cage.n_faces()
    );
    Ok(())
}

/// `dir/frame-0000.obj`, …: every frame's cage (faces and tags of the input).
fn write_obj_frames(dir: &Path, setup: &SubdivSetup, cages: &[Vec<Point3>]) -> Result<()> {
    replace_frames_folder(dir, &["obj"], |tmp| {
        let mut cage = setup.cage.clone();
        for (f, positions) in cages.iter().enumerate() {
            cage.set_positions(positions.clone())
                .with_context(|| format!("frame {f}: the fitted cage is not finite"))?;
            write_synced(
                &tmp.join(frame_name(f, "obj")),
                to_obj_string(&cage).as_bytes(),
            )?;
        }
        Ok(())
    })
}
