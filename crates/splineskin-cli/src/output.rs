//! Writing results: by extension (`.svg`, `.png`, `.json`), always atomically (a temporary file
//! in the same folder, then a rename), so a failure never leaves a half-written file.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{bail, ensure, Context, Result};
use kurbo::Point;
use serde::Serialize;
use splineskin::drawing::svg_out::{art_outside_view_box, write_svg_view_box, ViewBoxRule};
use splineskin::drawing::Drawing;

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

/// `--viewbox`: what SVG and PNG outputs do when the deformed art leaves the input's viewBox.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ViewBoxArg {
    /// Keep the input's viewBox; a warning names the paths that leave it and how far.
    Keep,
    /// Grow the viewBox (and width/height in proportion) to include the deformed art.
    Fit,
}

impl From<ViewBoxArg> for ViewBoxRule {
    fn from(v: ViewBoxArg) -> ViewBoxRule {
        match v {
            ViewBoxArg::Keep => ViewBoxRule::Keep,
            ViewBoxArg::Fit => ViewBoxRule::Fit,
        }
    }
}

/// Paths named in the warning of [`warn_outside_view_box`] before "and N more".
const MAX_NAMED_OUTSIDE: usize = 5;

/// Says on stderr which paths of the deformed drawing leave the input's viewBox and how far
/// (with `keep`: they are cropped; with `fit`: the viewBox grows), for SVG and PNG outputs.
pub fn warn_outside_view_box(path: &Path, drawing: &Drawing, points: &[Point], rule: ViewBoxArg) {
    if Format::of(path).ok() == Some(Format::Json) {
        return;
    }
    let Ok(mut outside) = art_outside_view_box(drawing, points) else {
        return; // the writer reports bad points
    };
    if outside.is_empty() {
        return;
    }
    outside.sort_by(|a, b| b.distance.total_cmp(&a.distance));
    let named: Vec<String> = outside
        .iter()
        .take(MAX_NAMED_OUTSIDE)
        .map(|o| format!("{} by {:.3}", o.element, o.distance))
        .collect();
    let more = outside.len().saturating_sub(MAX_NAMED_OUTSIDE);
    let more = if more > 0 {
        format!(" and {more} more")
    } else {
        String::new()
    };
    match rule {
        ViewBoxArg::Keep => eprintln!(
            "warning: {}: the deformed art leaves the viewBox (cropped): {}{more} (user units); \
             --viewbox fit grows the viewBox to include it",
            path.display(),
            named.join(", ")
        ),
        ViewBoxArg::Fit => eprintln!(
            "note: {}: the viewBox grows to include {} path(s) that leave it, farthest {}",
            path.display(),
            outside.len(),
            named[0]
        ),
    }
}

/// Writes the deformed drawing to `path` in the format its extension asks for.
pub fn write_deformed(path: &Path, drawing: &Drawing, points: &[Point]) -> Result<()> {
    write_deformed_view_box(path, drawing, points, ViewBoxRule::Keep)
}

/// [`write_deformed`] with the SVG's root viewBox chosen by `rule` (SVG and PNG outputs).
pub fn write_deformed_view_box(
    path: &Path,
    drawing: &Drawing,
    points: &[Point],
    rule: ViewBoxRule,
) -> Result<()> {
    let bytes = match Format::of(path)? {
        Format::Json => paths_json(drawing, points)
            .context("writing the deformed JSON")?
            .into_bytes(),
        Format::Svg => write_svg_view_box(drawing, points, rule)
            .context("writing the deformed SVG")?
            .into_bytes(),
        Format::Png => {
            let svg =
                write_svg_view_box(drawing, points, rule).context("writing the deformed SVG")?;
            note_font_substitutes(path, &svg);
            splineskin::render::render_png(&svg, PNG_SIZE).context("rendering the PNG")?
        }
    };
    write_atomic(path, &bytes)
}

/// Says on stderr which font families a PNG made from `svg` draws in DejaVu Sans instead
/// ([`splineskin::render::substituted_families`]: PNG renders use the font shipped with
/// splineskin, never a system font), if any; SVG outputs keep the text as it is.
pub fn note_font_substitutes(path: &Path, svg: &str) {
    let families = splineskin::render::substituted_families(svg);
    if !families.is_empty() {
        eprintln!(
            "note: {}: text drawn in {} in place of {} (fonts are not read from the system; \
             the SVG keeps the text as it is)",
            path.display(),
            splineskin::fonts::FAMILY,
            families.join(", ")
        );
    }
}

/// Writes `bytes` to `path` through a temporary file in the same folder and a rename.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    write_all_atomic(&[(path, bytes)])
}

/// Writes several files as one: every file's bytes go to a temporary file beside it first, and
/// only when all of them are written are they renamed into place. A failure while writing
/// leaves every destination as it was (its temporary files removed); a rename failing after
/// others succeeded (the disk vanishing between two renames) is reported naming the files
/// already replaced.
pub fn write_all_atomic(files: &[(&Path, &[u8])]) -> Result<()> {
    let mut temporaries = Vec::with_capacity(files.len());
    let remove_all = |temporaries: &[PathBuf]| {
        for t in temporaries {
            let _ = std::fs::remove_file(t);
        }
    };
    for (path, bytes) in files {
        let tmp = match temporary_beside(path) {
            Ok(tmp) => tmp,
            Err(e) => {
                remove_all(&temporaries);
                return Err(e);
            }
        };
        let written = (|| -> std::io::Result<()> {
            let mut f = std::fs::File::create(&tmp)?;
            f.write_all(bytes)?;
            f.sync_all()
        })();
        temporaries.push(tmp);
        if let Err(e) = written {
            remove_all(&temporaries);
            return Err(e).with_context(|| format!("{}: cannot write", path.display()));
        }
    }
    for (k, ((path, _), tmp)) in files.iter().zip(&temporaries).enumerate() {
        if let Err(e) = std::fs::rename(tmp, path) {
            remove_all(&temporaries[k..]);
            let done: Vec<String> = files[..k]
                .iter()
                .map(|(p, _)| p.display().to_string())
                .collect();
            let done = if done.is_empty() {
                String::new()
            } else {
                format!(" ({} already written)", done.join(", "))
            };
            return Err(e).with_context(|| format!("{}: cannot write{done}", path.display()));
        }
    }
    Ok(())
}

/// A temporary file name in `path`'s folder: `.NAME.tmp-PID`.
fn temporary_beside(path: &Path) -> Result<PathBuf> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = path
        .file_name()
        .with_context(|| format!("{}: not a file name", path.display()))?;
    Ok(dir.join(format!(
        ".{}.tmp-{}",
        name.to_string_lossy(),
        std::process::id()
    )))
}
