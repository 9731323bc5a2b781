//! `splineskin weights`, two modes:
//!
//! * `splineskin weights SCENE -o weights.png [--handle I] [--mesh-lines] [--iso-lines]
//!   [--width PX]`: a picture of the scene's weights, one panel per handle, drawn by
//!   [`splineskin::weight_map`];
//! * `splineskin weights --mesh MESH.json --kind harmonic|biharmonic|bbw -o OUT.json`: handle
//!   weights on a given triangle mesh.
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
use splineskin::scene::Compat;
use splineskin::weight_map::{
    render_weight_map, WeightMapOptions, DEFAULT_ISO_STEP, DEFAULT_PANEL_WIDTH,
};
use splineskin::weights::{bbw_weights, harmonic_weights, BbwOptions, VertexWeights};

use crate::output::{has_extension, write_atomic, Format};

#[derive(clap::Args)]
#[command(group(
    clap::ArgGroup::new("input").required(true).args(["scene", "mesh"]),
))]
pub struct Args {
    /// A scene (our JSON format or the paper authors' `*-deformation.json`), or an SVG drawing
    /// with its pins given by the flags below, whose weights to draw as PNG: one panel per
    /// handle, the weight in viridis from 0 (dark purple) to 1 (yellow), values below 0 in red
    /// and above 1 in pink, the drawing's curves on top.
    #[arg(value_name = "SCENE|SVG")]
    scene: Option<PathBuf>,
    /// A triangle mesh with handle vertices, in the reference-igl JSON layout:
    /// `{"mesh": {"V": [[x,y],…], "F": [[i,j,k],…]}, "handles": {"indices": [v,…]}}`
    /// (counter-clockwise triangles, 0-based indices).
    #[arg(long, value_name = "MESH.json")]
    mesh: Option<PathBuf>,
    /// With --mesh: the weight family: harmonic (k = 1), biharmonic (k = 2, unbounded), or
    /// bounded biharmonic (normalised to sum to 1). A scene names its own.
    #[arg(long, value_enum, default_value_t = Kind::Bbw, conflicts_with = "scene")]
    kind: Kind,
    /// Output file: `.png` for a scene; `.json` with --mesh,
    /// `{"weights": [[w per handle] per vertex]}`.
    #[arg(short, long)]
    output: PathBuf,
    /// Draw only this handle's weights (0 is the first handle), in one panel.
    #[arg(long, value_name = "I", conflicts_with = "mesh")]
    handle: Option<usize>,
    /// Draw the edges of the triangulated domain the weights were solved on (harmonic,
    /// biharmonic and bbw scenes).
    #[arg(long, conflicts_with = "mesh")]
    mesh_lines: bool,
    /// Draw iso-lines where the weight crosses 0.1, 0.2, …, 0.9 (and every 0.1 beyond
    /// [0, 1]).
    #[arg(long, conflicts_with = "mesh")]
    iso_lines: bool,
    /// Width of each panel in pixels (its height follows the drawing's proportions).
    #[arg(long, value_name = "PX", default_value_t = DEFAULT_PANEL_WIDTH, conflicts_with = "mesh")]
    width: u32,
    #[command(flatten)]
    pins: crate::drawing_input::PinArgs,
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
    if let (Some(mesh), [flag, ..]) = (&args.mesh, args.pins.given().as_slice()) {
        bail!(
            "{}: {flag} applies to an SVG drawing; a mesh's handles are its handles.indices and \
             its family --kind",
            mesh.display()
        );
    }
    let Some(mesh_path) = &args.mesh else {
        let scene = args.scene.as_deref().unwrap_or(Path::new("?"));
        return draw_scene(scene, &args);
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

/// The scene mode: the scene's weights as a PNG picture.
fn draw_scene(scene_path: &Path, args: &Args) -> Result<()> {
    let is_png = has_extension(&args.output, "png");
    if !is_png {
        bail!(
            "{}: a scene's weights are drawn as PNG (expected a name ending in .png)",
            args.output.display()
        );
    }
    let scene = crate::drawing_input::load(scene_path, &args.pins, None)?;
    let n_handles = scene.n_handles();
    if let Some(i) = args.handle.filter(|&i| i >= n_handles) {
        bail!(
            "{}: --handle {i}: no such handle (the scene has {n_handles}, numbered from 0: \
             points, then bones, then cage vertices)",
            scene_path.display()
        );
    }
    let family = scene.weights.name().to_string();
    let start = Instant::now();
    let setup = scene.setup(Compat::None)?;
    for w in &setup.warnings {
        eprintln!("warning: {w}");
    }
    let mesh = setup.domain.as_ref().map(|d| &d.mesh);
    if args.mesh_lines && mesh.is_none() {
        eprintln!("warning: --mesh-lines: {family} weights are not solved on a mesh; none drawn");
    }
    let markers = scene.handle_set().markers();
    let options = WeightMapOptions::default()
        .with_panel_width(args.width)
        .with_handle(args.handle)
        .with_mesh_lines(args.mesh_lines)
        .with_iso_step(args.iso_lines.then_some(DEFAULT_ISO_STEP))
        .with_parallel(true);
    let map = render_weight_map(
        &setup.drawing,
        &markers,
        setup.weights.as_ref(),
        mesh,
        &options,
    )
    .with_context(|| format!("{}: drawing the weights", scene_path.display()))?;
    write_atomic(&args.output, &map.png)?;
    let on_mesh = setup
        .domain
        .as_ref()
        .map(|d| {
            format!(
                " (domain of {} vertices over {})",
                d.mesh.n_vertices(),
                d.boundary
            )
        })
        .unwrap_or_default();
    eprintln!(
        "{}: {family} weights{on_mesh}, {} of {n_handles} handles in {:.2} s -> {} ({}×{} px)",
        scene_path.display(),
        map.layout.panels.len(),
        start.elapsed().as_secs_f64(),
        args.output.display(),
        map.layout.width,
        map.layout.height
    );
    let handles = scene.handle_set();
    for r in map.ranges.iter().filter(|r| !r.is_within_unit()) {
        let element = handles
            .kind(r.handle)
            .map(|k| format!(" ({})", scene.element(k)))
            .unwrap_or_default();
        eprintln!(
            "note: handle {}{element}: weights from {:.4} to {:.4}, outside [0, 1] (below 0 in \
             red, above 1 in pink)",
            r.handle, r.min, r.max
        );
    }
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
