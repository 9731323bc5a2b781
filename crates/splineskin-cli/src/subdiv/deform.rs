//! `splineskin subdiv deform SCENE -o OUT.obj [--pose N | --frame N] [--limit-mesh MESH.obj --level K]`:
//! the cage fitted so that its limit surface follows the skinned surface, as OBJ with the
//! input's faces and tags; optionally the deformed limit surface itself, sampled as a quad
//! mesh (the topology of the `K`-th uniform refinement, vertices on the limit surface).

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use splineskin::subdiv::{to_obj_string, LimitMesh, SubdivScene, MAX_LIMIT_MESH_LEVEL};

use crate::output::write_all_atomic;

#[derive(clap::Args)]
pub struct Args {
    /// The scene (JSON, `"splineskin_subdiv_scene": 1`).
    scene: PathBuf,
    /// The deformed cage (`.obj`).
    #[arg(short, long)]
    output: PathBuf,
    /// Which of the scene's poses to apply (0 is the first; the identity if it has none).
    #[arg(long, default_value_t = 0, conflicts_with = "frame")]
    pose: usize,
    /// Apply frame N of the scene's animation instead (0 is the first; `subdiv animate`
    /// writes the same frames).
    #[arg(long, value_name = "N")]
    frame: Option<usize>,
    /// Also write the deformed limit surface as a quad mesh (`.obj`).
    #[arg(long, value_name = "MESH.obj")]
    limit_mesh: Option<PathBuf>,
    /// Level of `--limit-mesh`: (2^K)² quads per cage quad.
    #[arg(long, default_value_t = 3, requires = "limit_mesh",
          value_parser = clap::value_parser!(u8).range(1..=MAX_LIMIT_MESH_LEVEL as i64))]
    level: u8,
}

pub fn run(args: Args) -> Result<()> {
    super::require_extension(&args.output, "obj")?;
    if let Some(mesh) = &args.limit_mesh {
        super::require_extension(mesh, "obj")?;
        if mesh == &args.output {
            bail!(
                "{}: the cage and the limit mesh would overwrite each other",
                mesh.display()
            );
        }
    }
    let scene = SubdivScene::load(&args.scene)?;
    let (pose, what) = match args.frame {
        None => (scene.pose(args.pose)?, format!("pose {}", args.pose)),
        Some(f) => {
            let mut frames = scene.animation_frames()?;
            if f >= frames.len() {
                bail!(
                    "{}: --frame {f}: the animation has {} frames (0-based)",
                    args.scene.display(),
                    frames.len()
                );
            }
            let (t, pose) = frames.swap_remove(f);
            (pose, format!("frame {f} (t = {t} s)"))
        }
    };
    let setup = scene.setup()?;
    let mut deformed = vec![[0.0; 3]; setup.cage.n_vertices()];
    setup
        .rig
        .update(&pose, &mut deformed)
        .with_context(|| format!("{}: {what}", args.scene.display()))?;
    let mut cage = setup.cage.clone();
    cage.set_positions(deformed.clone()).with_context(|| {
        format!(
            "{}: {what}: the deformed cage is not finite",
            args.scene.display()
        )
    })?;
    let cage_text = to_obj_string(&cage);
    let mesh_text = match &args.limit_mesh {
        None => None,
        Some(path) => {
            let surface = setup
                .full_surface()
                .with_context(|| format!("{}: the limit surface", args.scene.display()))?;
            let mesh = LimitMesh::new(&setup.cage, &surface, usize::from(args.level))
                .with_context(|| format!("{}: sampling the limit surface", args.scene.display()))?;
            let mut positions = vec![[0.0; 3]; mesh.n_vertices()];
            mesh.positions(&deformed, &mut positions);
            let quads = mesh
                .to_cage(positions)
                .with_context(|| format!("{}: the limit mesh", path.display()))?;
            Some((path, to_obj_string(&quads), mesh.quads().len()))
        }
    };
    // Both files or neither: a failure writing the limit mesh leaves the cage file as it was.
    let mut files: Vec<(&std::path::Path, &[u8])> = vec![(&args.output, cage_text.as_bytes())];
    if let Some((path, text, _)) = &mesh_text {
        files.push((path, text.as_bytes()));
    }
    write_all_atomic(&files)?;
    if let Some((path, _, n_quads)) = &mesh_text {
        eprintln!(
            "{}: {n_quads} quads of the deformed limit surface",
            path.display()
        );
    }
    eprintln!(
        "{}: {what} of {} handles, {} vertices, {} faces",
        args.output.display(),
        scene.handles.n_handles(),
        cage.n_vertices(),
        cage.n_faces()
    );
    Ok(())
}
