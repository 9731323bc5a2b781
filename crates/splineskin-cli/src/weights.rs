//! `splineskin weights --mesh MESH.json --kind harmonic|biharmonic|bbw -o OUT.json`: handle
//! weights on a given triangle mesh. (`splineskin weights SCENE -o weights.png`, the weights of
//! a scene's domain drawn over its drawing, is the other mode of this subcommand; not yet
//! implemented.)
//!
//! The mesh file uses the layout of `../shared/data/reference-igl` (whose files are accepted
//! as they are; other keys are ignored):
//!
//! ```text
//! {"mesh": {"V": [[x, y], …], "F": [[i, j, k], …]},      triangles counter-clockwise, 0-based
//!  "handles": {"indices": [v, …]}}                         one vertex per handle
//! ```
//!
//! and the output is `{"weights": [[w_0, …, w_{h−1}], …]}`, one row per vertex, written
//! atomically.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use kurbo::Point;
use serde::{Deserialize, Serialize};
use splineskin::mesh::{MeshError, TriMesh};
use splineskin::weights::{bbw_weights, harmonic_weights, BbwOptions, VertexWeights};

use crate::output::{write_atomic, Format};

#[derive(clap::Args)]
#[command(group(
    clap::ArgGroup::new("input").required(true).args(["scene", "mesh"]),
))]
pub struct Args {
    /// A scene whose domain's weights to draw (`-o weights.png`). Not implemented yet; give
    /// `--mesh` instead.
    scene: Option<PathBuf>,
    /// A triangle mesh with handle vertices, in the reference-igl JSON layout:
    /// `{"mesh": {"V": [[x,y],…], "F": [[i,j,k],…]}, "handles": {"indices": [v,…]}}`
    /// (counter-clockwise triangles, 0-based indices).
    #[arg(long, value_name = "MESH.json")]
    mesh: Option<PathBuf>,
    /// Weight family: harmonic (k = 1), biharmonic (k = 2, unbounded), or bounded biharmonic
    /// (normalised to sum to 1).
    #[arg(long, value_enum, default_value_t = Kind::Bbw)]
    kind: Kind,
    /// Output file: `.json`, `{"weights": [[w per handle] per vertex]}`.
    #[arg(short, long)]
    output: PathBuf,
}

/// The `--kind` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Kind {
    /// Harmonic weights: minimise the Dirichlet energy (k = 1).
    Harmonic,
    /// Biharmonic weights: minimise the squared Laplacian energy (k = 2), unbounded.
    Biharmonic,
    /// Bounded biharmonic weights (Jacobson et al. 2011), rows normalised to sum to 1.
    Bbw,
}

pub fn run(args: Args) -> Result<()> {
    let Some(mesh_path) = &args.mesh else {
        let scene = args.scene.as_deref().unwrap_or(Path::new("?"));
        bail!(
            "{}: drawing a scene's weights is not implemented yet; compute weights on a mesh \
             with --mesh MESH.json --kind harmonic|biharmonic|bbw -o OUT.json",
            scene.display()
        );
    };
    if Format::of(&args.output)? != Format::Json {
        bail!(
            "{}: weights on a mesh are written as JSON (expected a name ending in .json)",
            args.output.display()
        );
    }
    let (mesh, handles) = read_mesh_file(mesh_path)?;
    let start = Instant::now();
    let weights = match args.kind {
        Kind::Harmonic => harmonic_weights(&mesh, &handles, 1),
        Kind::Biharmonic => harmonic_weights(&mesh, &handles, 2),
        Kind::Bbw => bbw_weights(&mesh, &handles, &BbwOptions::default().with_parallel(true)),
    }
    .with_context(|| {
        format!(
            "{}: computing {} weights",
            mesh_path.display(),
            kind_name(args.kind)
        )
    })?;
    let seconds = start.elapsed().as_secs_f64();
    write_atomic(&args.output, weights_json(&weights)?.as_bytes())?;
    eprintln!(
        "{}: {} weights on {} vertices, {} handles in {seconds:.3} s -> {}",
        mesh_path.display(),
        kind_name(args.kind),
        mesh.n_vertices(),
        handles.len(),
        args.output.display()
    );
    Ok(())
}

fn kind_name(kind: Kind) -> &'static str {
    match kind {
        Kind::Harmonic => "harmonic",
        Kind::Biharmonic => "biharmonic",
        Kind::Bbw => "bounded biharmonic",
    }
}

/// The parts of a reference-igl file that the weights need.
#[derive(Deserialize)]
struct MeshFile {
    mesh: MeshPart,
    handles: HandlesPart,
}

#[derive(Deserialize)]
struct MeshPart {
    #[serde(rename = "V")]
    vertices: Vec<[f64; 2]>,
    #[serde(rename = "F")]
    triangles: Vec<[usize; 3]>,
}

#[derive(Deserialize)]
struct HandlesPart {
    indices: Vec<usize>,
}

/// Reads and checks a mesh file: the mesh (finite coordinates, indices in range,
/// counter-clockwise triangles) and its handle vertices (in range and distinct).
fn read_mesh_file(path: &Path) -> Result<(TriMesh, Vec<usize>)> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("{}: cannot read", path.display()))?;
    let file: MeshFile = serde_json::from_str(&text).with_context(|| {
        format!(
            "{}: not a mesh file (expected {{\"mesh\": {{\"V\": [[x, y], …], \"F\": [[i, j, k], …]}}, \"handles\": {{\"indices\": [v, …]}}}})",
            path.display()
        )
    })?;
    let vertices = file
        .mesh
        .vertices
        .iter()
        .map(|&[x, y]| Point::new(x, y))
        .collect();
    let mesh = TriMesh::new(vertices, file.mesh.triangles)
        .map_err(|e| anyhow::anyhow!("{}: {}: {e}", path.display(), mesh_element(&e)))?;
    let handles = file.handles.indices;
    if handles.is_empty() {
        bail!(
            "{}: handles.indices is empty (expected at least one vertex)",
            path.display()
        );
    }
    for (i, &v) in handles.iter().enumerate() {
        if v >= mesh.n_vertices() {
            bail!(
                "{}: handles.indices[{i}] = {v} is not a vertex (the mesh has {} vertices)",
                path.display(),
                mesh.n_vertices()
            );
        }
        if let Some(first) = handles[..i].iter().position(|&u| u == v) {
            bail!(
                "{}: handles.indices[{first}] and handles.indices[{i}] are both vertex {v} (expected distinct vertices)",
                path.display()
            );
        }
    }
    Ok((mesh, handles))
}

/// The JSON element a mesh error is about.
fn mesh_element(e: &MeshError) -> String {
    match e {
        MeshError::IndexOutOfRange { triangle, .. }
        | MeshError::BadOrientation { triangle, .. } => {
            format!("mesh.F[{triangle}]")
        }
        MeshError::NonFinite { vertex, .. } => format!("mesh.V[{vertex}]"),
        _ => "mesh".to_string(),
    }
}

#[derive(Serialize)]
struct WeightsJson<'a> {
    weights: Vec<&'a [f64]>,
}

/// `{"weights": [[w per handle] per vertex]}`; errors if a weight is not finite (JSON has no
/// NaN or infinity).
fn weights_json(weights: &VertexWeights) -> Result<String> {
    if let Some(k) = weights.as_slice().iter().position(|w| !w.is_finite()) {
        let h = weights.n_handles();
        bail!(
            "weight of handle {} at vertex {} is not finite; expected finite weights",
            k % h,
            k / h
        );
    }
    let rows = (0..weights.n_vertices()).map(|v| weights.row(v)).collect();
    Ok(serde_json::to_string(&WeightsJson { weights: rows })?)
}
