//! Writing results: by extension (`.svg`, `.png`, `.json`), always atomically (a temporary file
//! in the same folder, then a rename), so a failure never leaves a half-written file.

use std::path::Path;

use anyhow::{bail, ensure, Context, Result};
use kurbo::{Point, Rect};
use serde::Serialize;
use splineskin::drawing::follow::{ElementMaps, FollowOptions};
use splineskin::drawing::svg_out::{
    art_bounds, art_outside_view_box, write_svg_with, SvgOptions, ViewBoxRule,
};
use splineskin::drawing::Drawing;

/// Longest side of PNG renders, in pixels.
pub const PNG_SIZE: u32 = 1200;

/// Whether `path`'s name ends in `.ext`, in any case (`ext` without the dot).
pub fn has_extension(path: &Path, ext: &str) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case(ext))
}

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
    /// Where the deformation folds a closed outline over itself.
    folds: Vec<JsonFold>,
}

#[derive(Serialize)]
struct JsonFold {
    path: usize,
    curves: [usize; 2],
    at: [f64; 2],
}

#[derive(Serialize)]
struct JsonPath {
    closed: bool,
    points: Vec<[f64; 2]>,
    /// Joints (anchor `k` is chain point `3k`) inserted by adaptive control points.
    #[serde(skip_serializing_if = "Option::is_none")]
    inserted: Option<Vec<usize>>,
}

/// `{"paths":[{"closed":bool,"points":[[x,y],…]}],"folds":[{"path":p,"curves":[i,j],"at":[x,y]}]}`:
/// per subpath its `3n+1` chain points, and every crossing of a closed outline the
/// deformation made (curves `i` and `j` of path `p` cross at `(x, y)` and did not at rest;
/// [`splineskin::folds::new_self_crossings`]). With `inserted` (per path, per joint), each path
/// also lists `"inserted": [k, …]`, the anchors adaptive control points added.
///
/// Errors if a point is not finite (JSON has no NaN or infinity: serde_json would write `null`)
/// or if `points` does not hold the drawing's points.
pub fn paths_json(
    drawing: &Drawing,
    points: &[Point],
    inserted: Option<&[Vec<bool>]>,
) -> Result<String> {
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
    let paths = drawing
        .paths
        .iter()
        .zip(drawing.path_ranges())
        .enumerate()
        .map(|(i, (p, range))| JsonPath {
            closed: p.closed,
            points: points[range].iter().map(|q| [q.x, q.y]).collect(),
            inserted: inserted
                .and_then(|marks| marks.get(i))
                .map(|marks| (0..marks.len()).filter(|&k| marks[k]).collect()),
        })
        .collect();
    let folds = splineskin::folds::new_self_crossings(drawing, &drawing.flat_points(), points)
        .into_iter()
        .map(|f| JsonFold {
            path: f.path,
            curves: [f.curves.0, f.curves.1],
            at: [f.at.x, f.at.y],
        })
        .collect();
    Ok(serde_json::to_string(&JsonPaths { paths, folds })?)
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

/// How `deform` and `defop deform` write the deformed drawing: `--viewbox` and
/// `--scale-strokes`.
#[derive(clap::Args)]
pub struct DeformedOutputArgs {
    /// When the deformed art leaves the input's viewBox: `keep` it (a warning names the paths
    /// and how far) or `fit` it (viewBox and width/height grow to include the art).
    #[arg(long, value_enum, default_value_t = ViewBoxArg::Keep)]
    pub viewbox: ViewBoxArg,
    /// Scale stroke widths by the local scale of the deformation over each element (off by
    /// default, as Illustrator's Puppet Warp leaves stroke weights as they are).
    #[arg(long)]
    pub scale_strokes: bool,
}

impl DeformedOutputArgs {
    /// The options of the element maps ([`splineskin::drawing::follow`]).
    pub fn follow_options(&self) -> FollowOptions {
        FollowOptions::default().with_scale_strokes(self.scale_strokes)
    }

    /// Warns when the art leaves the viewBox ([`warn_outside_view_box`]), then writes `path`
    /// ([`write_deformed_view_box`]).
    pub fn write(
        &self,
        path: &Path,
        drawing: &Drawing,
        points: &[Point],
        maps: Option<&ElementMaps>,
    ) -> Result<()> {
        self.write_marked(path, drawing, points, maps, None)
    }

    /// [`DeformedOutputArgs::write`] of a drawing whose anchors `inserted` (per path, per
    /// joint) were added by adaptive control points: the JSON output lists them.
    pub fn write_marked(
        &self,
        path: &Path,
        drawing: &Drawing,
        points: &[Point],
        maps: Option<&ElementMaps>,
        inserted: Option<&[Vec<bool>]>,
    ) -> Result<()> {
        warn_outside_view_box(path, drawing, points, self.viewbox);
        write_deformed_marked(path, drawing, points, self.viewbox.into(), maps, inserted)
    }
}

/// Paths named in the warning of [`warn_outside_view_box`] before "and N more".
const MAX_NAMED_OUTSIDE: usize = 5;

/// A length in user units for messages: three decimals, or as many as four significant
/// digits need, so that the overshoot of a drawing a millionth of a unit across does not read
/// `0.000`.
///
/// `user_units(20.0) == "20.000"`, `user_units(2.5e-7) == "0.0000002500"`.
fn user_units(v: f64) -> String {
    let magnitude = if v != 0.0 && v.is_finite() {
        v.abs().log10().floor() as i32
    } else {
        0
    };
    let decimals = (3 - magnitude).clamp(3, 17) as usize;
    format!("{v:.decimals$}")
}

/// Says on stderr where the deformation folds a closed outline over itself: the crossings of
/// the deformed drawing between curves that do not cross at rest
/// ([`splineskin::folds::new_self_crossings`]), the first [`MAX_NAMED_OUTSIDE`] with their
/// positions (root user units). Returns how many there are.
pub fn warn_folds(output: &Path, drawing: &Drawing, points: &[Point]) -> usize {
    let rest = drawing.flat_points();
    let folds = splineskin::folds::new_self_crossings(drawing, &rest, points);
    for f in folds.iter().take(MAX_NAMED_OUTSIDE) {
        eprintln!(
            "warning: {}: path {} folds over itself: its curves {} and {} cross at ({}, {}) \
             (they do not at rest)",
            output.display(),
            f.path,
            f.curves.0,
            f.curves.1,
            f.at.x,
            f.at.y
        );
    }
    if folds.len() > MAX_NAMED_OUTSIDE {
        eprintln!(
            "warning: {}: and {} more crossings the deformation made",
            output.display(),
            folds.len() - MAX_NAMED_OUTSIDE
        );
    }
    folds.len()
}

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
    let named = named_list(
        outside
            .iter()
            .map(|o| format!("{} by {}", o.element, user_units(o.distance))),
        outside.len(),
    );
    match rule {
        ViewBoxArg::Keep => eprintln!(
            "warning: {}: the deformed art leaves the viewBox (cropped): {named} (user units); \
             --viewbox fit grows the viewBox to include it",
            path.display(),
        ),
        ViewBoxArg::Fit => eprintln!(
            "note: {}: the viewBox grows to include {} path(s) that leave it, farthest {} by {}",
            path.display(),
            outside.len(),
            outside[0].element,
            user_units(outside[0].distance)
        ),
    }
}

/// Where the frames of an animation leave the input's viewBox, gathered frame by frame
/// ([`FramesOutside::add`]): for `animate --viewbox keep` a warning naming the frames, paths
/// and how far ([`FramesOutside::report`]); for `fit` the union of the art's bounding boxes
/// over all frames ([`FramesOutside::rule`]), one viewBox for the whole animation.
#[derive(Debug, Default)]
pub struct FramesOutside {
    /// Frames seen.
    n_frames: usize,
    /// Frames in which some path leaves the viewBox, and the first and last of them.
    n_frames_outside: usize,
    first_last: Option<(usize, usize)>,
    /// Per path index (leaving the viewBox in some frame): its element, in how many frames it
    /// leaves, and its largest overshoot with the frame of it.
    paths: std::collections::BTreeMap<usize, PathOutside>,
    /// The union of the art's bounding boxes over the frames ([`art_bounds`]).
    bounds: Option<Rect>,
}

#[derive(Debug)]
struct PathOutside {
    element: String,
    n_frames: usize,
    distance: f64,
    frame: usize,
}

impl FramesOutside {
    /// Takes frame `frame`'s deformed points (frames in any order, each once). Points the
    /// writer would refuse (wrong count, not finite) are skipped here: the writer reports them.
    pub fn add(&mut self, frame: usize, drawing: &Drawing, points: &[Point]) {
        self.n_frames += 1;
        if let Ok(Some(r)) = art_bounds(drawing, points) {
            self.bounds = Some(self.bounds.map_or(r, |b| b.union(r)));
        }
        let Ok(outside) = art_outside_view_box(drawing, points) else {
            return;
        };
        if outside.is_empty() {
            return;
        }
        self.n_frames_outside += 1;
        self.first_last = Some(match self.first_last {
            None => (frame, frame),
            Some((a, b)) => (a.min(frame), b.max(frame)),
        });
        for o in outside {
            let entry = self.paths.entry(o.path_index).or_insert(PathOutside {
                element: o.element,
                n_frames: 0,
                distance: o.distance,
                frame,
            });
            entry.n_frames += 1;
            if o.distance > entry.distance {
                entry.distance = o.distance;
                entry.frame = frame;
            }
        }
    }

    /// The viewBox rule of every frame under `arg`: `fit` is [`ViewBoxRule::FitTo`] the union
    /// of the art over all frames added (the same viewBox for each frame).
    pub fn rule(&self, arg: ViewBoxArg) -> ViewBoxRule {
        match (arg, self.bounds) {
            (ViewBoxArg::Fit, Some(bounds)) => ViewBoxRule::FitTo(bounds),
            _ => ViewBoxRule::Keep,
        }
    }

    /// Says on stderr which paths leave the input's viewBox, in which frames and how far
    /// (nothing when none does), for output `path` written with `arg`.
    pub fn report(&self, path: &Path, arg: ViewBoxArg) {
        let Some((first, last)) = self.first_last else {
            return;
        };
        let mut paths: Vec<&PathOutside> = self.paths.values().collect();
        paths.sort_by(|a, b| b.distance.total_cmp(&a.distance));
        let frames = if first == last {
            format!("frame {first}")
        } else {
            format!("frames {first}–{last}")
        };
        let named = named_list(
            paths.iter().map(|p| {
                format!(
                    "{} by {} at frame {} (outside in {} frame{})",
                    p.element,
                    user_units(p.distance),
                    p.frame,
                    p.n_frames,
                    if p.n_frames == 1 { "" } else { "s" }
                )
            }),
            paths.len(),
        );
        match arg {
            ViewBoxArg::Keep => eprintln!(
                "warning: {}: the deformed art leaves the viewBox (cropped) in {} of {} frames \
                 ({frames}): {named} (user units); --viewbox fit gives every frame one viewBox \
                 that holds them all",
                path.display(),
                self.n_frames_outside,
                self.n_frames
            ),
            ViewBoxArg::Fit => {
                let r = self.bounds.unwrap_or_default();
                eprintln!(
                    "note: {}: the viewBox grows to hold every frame ({} path(s) leave the \
                     input's in {} of {} frames, {frames}; farthest {} by {} at frame {}); \
                     the art spans x {} … {}, y {} … {}",
                    path.display(),
                    paths.len(),
                    self.n_frames_outside,
                    self.n_frames,
                    paths[0].element,
                    user_units(paths[0].distance),
                    paths[0].frame,
                    user_units(r.x0),
                    user_units(r.x1),
                    user_units(r.y0),
                    user_units(r.y1)
                )
            }
        }
    }
}

/// The first [`MAX_NAMED_OUTSIDE`] of `items` joined by commas, then "and N more" of `total`.
fn named_list(items: impl Iterator<Item = String>, total: usize) -> String {
    let mut s = items.take(MAX_NAMED_OUTSIDE).collect::<Vec<_>>().join(", ");
    let more = total.saturating_sub(MAX_NAMED_OUTSIDE);
    if more > 0 {
        s.push_str(&format!(" and {more} more"));
    }
    s
}

/// Writes the deformed drawing to `path` in the format its extension asks for.
pub fn write_deformed(path: &Path, drawing: &Drawing, points: &[Point]) -> Result<()> {
    write_deformed_view_box(path, drawing, points, ViewBoxRule::Keep, None)
}

/// [`write_deformed`] with the SVG's root viewBox chosen by `rule` and, with `maps`, gradients,
/// patterns, markers, text and images carried by them (SVG and PNG outputs).
pub fn write_deformed_view_box(
    path: &Path,
    drawing: &Drawing,
    points: &[Point],
    rule: ViewBoxRule,
    maps: Option<&ElementMaps>,
) -> Result<()> {
    write_deformed_marked(path, drawing, points, rule, maps, None)
}

/// [`write_deformed_view_box`] with the anchors inserted by adaptive control points (per path,
/// per joint) marked: listed per path in the JSON output, and on each element of an SVG in
/// `data-splineskin-inserted` (`splineskin::drawing::svg_out::INSERTED_ATTRIBUTE`).
pub fn write_deformed_marked(
    path: &Path,
    drawing: &Drawing,
    points: &[Point],
    rule: ViewBoxRule,
    maps: Option<&ElementMaps>,
    inserted: Option<&[Vec<bool>]>,
) -> Result<()> {
    let options = SvgOptions::default()
        .with_view_box(rule)
        .with_follow(maps)
        .with_inserted(inserted);
    let svg = || write_svg_with(drawing, points, &options);
    let bytes = match Format::of(path)? {
        Format::Json => paths_json(drawing, points, inserted)
            .context("writing the deformed JSON")?
            .into_bytes(),
        Format::Svg => svg().context("writing the deformed SVG")?.into_bytes(),
        Format::Png => {
            let svg = svg().context("writing the deformed SVG")?;
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

/// Writes several files as one ([`splineskin::atomic_write::write_all_atomically`]): a failure
/// while writing leaves every destination as it was; a rename failing after others succeeded
/// (the disk vanishing between two renames) is reported naming the files already replaced.
pub fn write_all_atomic(files: &[(&Path, &[u8])]) -> Result<()> {
    splineskin::atomic_write::write_all_atomically(files).map_err(|e| {
        let done: Vec<String> = files[..e.replaced]
            .iter()
            .map(|(p, _)| p.display().to_string())
            .collect();
        let done = if done.is_empty() {
            String::new()
        } else {
            format!(" ({} already written)", done.join(", "))
        };
        anyhow::Error::new(e.source)
            .context(format!("{}: cannot write{done}", files[e.file].0.display()))
    })
}

#[cfg(test)]
mod tests {
    use super::user_units;

    #[test]
    fn user_units_keep_four_significant_digits_at_any_size() {
        assert_eq!(user_units(20.0), "20.000");
        assert_eq!(user_units(-1234.5), "-1234.500");
        assert_eq!(user_units(0.0), "0.000");
        assert_eq!(user_units(2.5e-7), "0.0000002500");
        assert_eq!(user_units(0.01234), "0.01234");
        // A drawing scaled by 1e-6 reads like the original, scaled.
        assert_eq!(user_units(20.0e-6), "0.00002000");
    }
}
