//! `splineskin defop deform SCENE -o OUT.(svg|png|json) [--pose P] [--operator OP]
//! [--viewbox keep|fit] [--scale-strokes]`: the
//! scene's drawing deformed through a trained operator ([`DefOpRig`], the join of the operator
//! with the spline fit): the pose's maps move the point handles to `Q = (T_ℓ p_ℓ)_ℓ`, and the
//! drawing's control points are `G_spline ψ(Q)`, junction constraints kept. The output is
//! written as `splineskin deform` writes it (the input document with its path geometry
//! replaced, a PNG render, or JSON).
//!
//! What is not a curve follows as in `splineskin deform`: user-space gradients and patterns,
//! fixed-orientation markers, `<text>` and `<image>` are carried by the best-fit affine map
//! ([`ElementMaps::from_map`]) of the **operator's own deformation** over each element. The
//! operator offers point evaluation: its deformed mesh `u(Q) = Dᵀ G ψ(Q)` interpolated
//! linearly in each triangle, nearest boundary point outside ([`MeshMap`]), the very map whose
//! spline fit gives the curves (so a label moves with the curves around it). Fitting the
//! affine to the deformed control points of nearby paths instead would make a label depend
//! on which paths happen to be near and on the fit's junction constraints; it is not done.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use kurbo::Point;
use splineskin::defop::{DefOpRig, MeshMap, OperatorFile};
use splineskin::drawing::follow::ElementMaps;
use splineskin::scene::{Compat, Scene, HANDLE_VERTEX_TOLERANCE};

use crate::output::DeformedOutputArgs;

#[derive(clap::Args)]
pub struct Args {
    /// The scene (our format): drawing, point handles, poses, and `defop.operator`.
    scene: PathBuf,
    /// Output file: `.svg`, `.png` or `.json`.
    #[arg(short, long)]
    output: PathBuf,
    /// Which of the scene's poses to apply: its name, or its index (0 is the first).
    #[arg(long, default_value = "0")]
    pose: String,
    /// The operator file (default: the scene's `defop.operator`).
    #[arg(long)]
    operator: Option<PathBuf>,
    #[command(flatten)]
    written: DeformedOutputArgs,
}

pub fn run(args: Args) -> Result<()> {
    crate::output::Format::of(&args.output)?;
    super::check_output_folder(&args.output)?;
    let scene = Scene::load(&args.scene)?;
    let Some(op_path) = args
        .operator
        .clone()
        .or_else(|| scene.defop.as_ref().and_then(|d| d.operator.clone()))
    else {
        bail!(
            "{}: no operator: pass --operator OP, or name one in the scene's defop.operator (train it with `splineskin defop train {} -o OP`)",
            args.scene.display(),
            args.scene.display()
        );
    };
    let file = OperatorFile::load(&op_path)?;
    check_scene_matches(&args.scene, &scene, &op_path, &file)?;
    let (pose_index, pose) = scene
        .pose_by_key(&args.pose)
        .map_err(|e| anyhow::anyhow!("{}: {e}", args.scene.display()))?;
    let q: Vec<Point> = pose
        .transforms
        .iter()
        .zip(&scene.handles)
        .map(|(t, &p)| *t * p)
        .collect();
    // An operator follows handle positions: a handle's rotation or scaling about its own
    // position moves nothing. Say so rather than drop it silently.
    let turned: Vec<String> = pose
        .transforms
        .iter()
        .enumerate()
        .filter(|(_, t)| {
            let [a, b, c, d, _, _] = t.as_coeffs();
            (a - 1.0).abs() + b.abs() + c.abs() + (d - 1.0).abs() > 1e-12
        })
        .map(|(l, _)| l.to_string())
        .collect();
    if !turned.is_empty() {
        eprintln!(
            "note: pose {pose_index} rotates or scales handles {}; an operator follows handle \
             positions only (each handle moves to T·p), so those turns change nothing",
            turned.join(", ")
        );
    }
    let (drawing, warnings) = scene.drawing_with_junctions(Compat::None)?;
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    let options = scene.fit_options(Compat::None).with_parallel(true);
    let clock = Instant::now();
    let rig =
        DefOpRig::precompute(&drawing, &file.mesh, &file.op, &options).with_context(|| {
            format!(
                "{}: joining the drawing with the operator {}",
                args.scene.display(),
                op_path.display()
            )
        })?;
    let precompute_seconds = clock.elapsed().as_secs_f64();
    let points = rig
        .deform(&q)
        .with_context(|| format!("{}: pose {pose_index}", args.scene.display()))?;
    if let Some(k) = points.iter().position(|p| !p.is_finite()) {
        bail!(
            "{}: pose {pose_index}: deformed point {k} is not finite",
            args.scene.display()
        );
    }
    // JSON holds the curves only: the element maps are for SVG and PNG.
    let maps = match crate::output::Format::of(&args.output)? {
        crate::output::Format::Json => None,
        _ => {
            let map = MeshMap::from_operator(&file.mesh, &file.op, &q).with_context(|| {
                format!(
                    "{}: pose {pose_index}: evaluating the operator {}",
                    args.scene.display(),
                    op_path.display()
                )
            })?;
            let options = args.written.follow_options();
            let maps = ElementMaps::from_map(&drawing, &mut |p| map.apply(p), &options)
                .with_context(|| format!("{}: pose {pose_index}", args.scene.display()))?;
            Some(maps)
        }
    };
    args.written
        .write(&args.output, &drawing, &points, maps.as_ref())?;
    crate::output::warn_folds(&args.output, &drawing, &points);
    eprintln!(
        "{}: {} curves in {} paths, {} handles, operator {} ({} vertices), join {:.2} s, pose {pose_index} -> {}",
        args.scene.display(),
        drawing.n_curves(),
        drawing.paths.len(),
        q.len(),
        op_path.display(),
        file.op.n_vertices(),
        precompute_seconds,
        args.output.display()
    );
    Ok(())
}

/// Refuses a scene that is not the one `file`'s operator was trained for: bones or a cage, a
/// different number of point handles, or a handle away from its rest position in the operator
/// (beyond [`HANDLE_VERTEX_TOLERANCE`] of the mesh's diagonal).
pub(super) fn check_scene_matches(
    scene_path: &Path,
    scene: &Scene,
    op_path: &Path,
    file: &OperatorFile,
) -> Result<()> {
    if !scene.bones.is_empty() || scene.cage.is_some() {
        bail!(
            "{}: an operator is driven by point handles only (expected no bones and no cage)",
            scene_path.display()
        );
    }
    let rest = file.rest_handles();
    if rest.len() != scene.handles.len() {
        bail!(
            "{}: {} point handles, but the operator {} has {} (expected the scene it was trained for)",
            scene_path.display(),
            scene.handles.len(),
            op_path.display(),
            rest.len()
        );
    }
    let tolerance = HANDLE_VERTEX_TOLERANCE * file.mesh.bounding_box_diagonal();
    for (l, (p, q)) in scene.handles.iter().zip(&rest).enumerate() {
        if (*p - *q).hypot() > tolerance {
            bail!(
                "{}: handles[{l}] at ({}, {}), but the operator {} has it at ({}, {}) (expected the scene it was trained for)",
                scene_path.display(),
                p.x,
                p.y,
                op_path.display(),
                q.x,
                q.y
            );
        }
    }
    Ok(())
}
