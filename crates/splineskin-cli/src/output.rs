//! Writing results: by extension (`.svg`, `.png`, `.json`), always atomically (a temporary file
//! in the same folder, then a rename), so a failure never leaves a half-written file.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{bail, ensure, Context, Result};
use kurbo::Point;
use serde::Serialize;
use splineskin::drawing::{svg_out::write_svg, Drawing};

/// Longest side of PNG renders, in pixels.
pub const PNG_SIZE: u32 = 1200;

/// What a file name asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Svg,
    Png,
    Json,
}

impl Format {
    pub fn of(path: &Path) -> Result<Format> {
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .as_deref()
        {
            Some("svg") => Ok(Format::Svg),
            Some("png") => Ok(Format::Png),
            Some("json") => Ok(Format::Json),
            _ => bail!(
                "{}: unknown output type (expected a name ending in .svg, .png or .json)",
                path.display()
            ),
        }
    }
}

#[derive(Serialize)]
struct JsonPaths {
    paths: Vec<JsonPath>,
}

#[derive(Serialize)]
struct JsonPath {
    closed: bool,
    points: Vec<[f64; 2]>,
}

/// `{"paths":[{"closed":bool,"points":[[x,y],…]}]}`: per subpath its `3n+1` chain points.
///
/// Errors if a point is not finite (JSON has no NaN or infinity: serde_json would write `null`)
/// or if `points` does not hold the drawing's points.
pub fn paths_json(drawing: &Drawing, points: &[Point]) -> Result<String> {
    ensure!(
        points.len() == drawing.n_points(),
        "{} deformed points for a drawing of {}",
        points.len(),
        drawing.n_points()
    );
    if let Some(k) = points
        .iter()
        .position(|q| !(q.x.is_finite() && q.y.is_finite()))
    {
        bail!("deformed point {k} is not finite; expected finite coordinates");
    }
    let mut offset = 0;
    let paths = drawing
        .paths
        .iter()
        .map(|p| {
            let n = p.points.len();
            let pts = points[offset..offset + n]
                .iter()
                .map(|q| [q.x, q.y])
                .collect();
            offset += n;
            JsonPath {
                closed: p.closed,
                points: pts,
            }
        })
        .collect();
    Ok(serde_json::to_string(&JsonPaths { paths })?)
}

/// Writes the deformed drawing to `path` in the format its extension asks for.
pub fn write_deformed(path: &Path, drawing: &Drawing, points: &[Point]) -> Result<()> {
    let bytes = match Format::of(path)? {
        Format::Json => paths_json(drawing, points)
            .context("writing the deformed JSON")?
            .into_bytes(),
        Format::Svg => write_svg(drawing, points)
            .context("writing the deformed SVG")?
            .into_bytes(),
        Format::Png => {
            let svg = write_svg(drawing, points).context("writing the deformed SVG")?;
            splineskin::render::render_png(&svg, PNG_SIZE).context("rendering the PNG")?
        }
    };
    write_atomic(path, &bytes)
}

/// Writes `bytes` to `path` through a temporary file in the same folder and a rename.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = path
        .file_name()
        .with_context(|| format!("{}: not a file name", path.display()))?;
    let tmp = dir.join(format!(
        ".{}.tmp-{}",
        name.to_string_lossy(),
        std::process::id()
    ));
    let result = (|| -> std::io::Result<()> {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(e).with_context(|| format!("{}: cannot write", path.display()));
    }
    Ok(())
}
