//! `splineskin defop eval OP --handles Q.json -o OUT.(json|png)`: the operator at one handle
//! configuration. `Q.json` is `[[x, y], …]` (one point per handle, in the operator's handle
//! order) or `{"handles": [[x, y], …]}`. JSON output: `{"vertices": [[x, y], …], "triangles":
//! [[a, b, c], …], "handles": [[x, y], …]}`; PNG output: the deformed mesh (fill and edges)
//! over the rest mesh drawn faintly, the handles as dots.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use kurbo::Point;
use serde::Serialize;
use splineskin::defop::OperatorFile;
use splineskin::mesh::TriMesh;

use crate::output::{write_atomic, Format, PNG_SIZE};

#[derive(clap::Args)]
pub struct Args {
    /// The operator file (`splineskin defop train`).
    operator: PathBuf,
    /// Handle positions: `[[x, y], …]` or `{"handles": [[x, y], …]}`.
    #[arg(long)]
    handles: PathBuf,
    /// Output: .json (deformed vertices and triangles) or .png (a picture).
    #[arg(short, long)]
    output: PathBuf,
}

#[derive(Serialize)]
struct Deformed<'a> {
    vertices: Vec<[f64; 2]>,
    triangles: &'a [[usize; 3]],
    handles: Vec<[f64; 2]>,
}

/// Reads `n` handle positions from `path` (either form), each finite.
pub(super) fn read_handles(path: &Path, n: usize) -> Result<Vec<Point>> {
    let value = super::read_json(path)?;
    let list = match &value {
        serde_json::Value::Object(map) => map.get("handles").with_context(|| {
            format!(
                "{}: expected [[x, y], …] or {{\"handles\": [[x, y], …]}}",
                path.display()
            )
        })?,
        other => other,
    };
    let points: Vec<[f64; 2]> = serde_json::from_value(list.clone()).with_context(|| {
        format!(
            "{}: expected a list of [x, y] number pairs, one per handle",
            path.display()
        )
    })?;
    if points.len() != n {
        bail!(
            "{}: {} handle positions, but the operator has {n} handles (expected one [x, y] per handle)",
            path.display(),
            points.len()
        );
    }
    points
        .iter()
        .enumerate()
        .map(|(l, &[x, y])| {
            if x.is_finite() && y.is_finite() {
                Ok(Point::new(x, y))
            } else {
                bail!("{}: handle {l}: ({x}, {y}) is not finite", path.display())
            }
        })
        .collect()
}

pub fn run(args: Args) -> Result<()> {
    let format = Format::of(&args.output)?;
    if format == Format::Svg {
        bail!(
            "{}: expected a name ending in .json or .png",
            args.output.display()
        );
    }
    super::check_output_folder(&args.output)?;
    let file = OperatorFile::load(&args.operator)?;
    let q = read_handles(&args.handles, file.op.n_handles())?;
    let positions = file
        .op
        .eval(&q)
        .with_context(|| format!("{}: evaluating", args.operator.display()))?;
    let bytes = match format {
        Format::Json => serde_json::to_vec(&Deformed {
            vertices: positions.iter().map(|p| [p.x, p.y]).collect(),
            triangles: &file.mesh.triangles,
            handles: q.iter().map(|p| [p.x, p.y]).collect(),
        })?,
        _ => {
            let svg = mesh_svg(&file.mesh, &positions, &q);
            splineskin::render::render_png(&svg, PNG_SIZE).context("rendering the PNG")?
        }
    };
    write_atomic(&args.output, &bytes)
}

/// An SVG of the rest mesh (faint) under the deformed one (filled, edges drawn), handles as
/// dots, framed to hold both.
fn mesh_svg(mesh: &TriMesh, deformed: &[Point], handles: &[Point]) -> String {
    let all = mesh.vertices.iter().chain(deformed);
    let (mut lo, mut hi) = (
        Point::new(f64::INFINITY, f64::INFINITY),
        Point::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
    );
    for p in all {
        lo = Point::new(lo.x.min(p.x), lo.y.min(p.y));
        hi = Point::new(hi.x.max(p.x), hi.y.max(p.y));
    }
    let size = (hi - lo).hypot().max(1e-9);
    let margin = 0.04 * size;
    let (x0, y0) = (lo.x - margin, lo.y - margin);
    let (w, h) = (hi.x - lo.x + 2.0 * margin, hi.y - lo.y + 2.0 * margin);
    let stroke = 0.001 * size;
    let triangles = |points: &[Point]| {
        let mut d = String::new();
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|v| points[v]);
            let _ = write!(d, "M{} {}L{} {}L{} {}Z", a.x, a.y, b.x, b.y, c.x, c.y);
        }
        d
    };
    let mut svg = format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="{x0} {y0} {w} {h}"><rect x="{x0}" y="{y0}" width="{w}" height="{h}" fill="white"/>"#
    );
    let _ = write!(
        svg,
        r##"<path d="{}" fill="#d8d8d8" fill-opacity="0.5" stroke="#b0b0b0" stroke-width="{}" stroke-linejoin="round"/>"##,
        triangles(&mesh.vertices),
        stroke * 0.6
    );
    let _ = write!(
        svg,
        r##"<path d="{}" fill="#8ec5e8" stroke="#1f5f8b" stroke-opacity="0.7" stroke-width="{stroke}" stroke-linejoin="round"/>"##,
        triangles(deformed)
    );
    for p in handles {
        let _ = write!(
            svg,
            r##"<circle cx="{}" cy="{}" r="{}" fill="#d62728" stroke="white" stroke-width="{}"/>"##,
            p.x,
            p.y,
            0.008 * size,
            stroke
        );
    }
    svg.push_str("</svg>");
    svg
}
