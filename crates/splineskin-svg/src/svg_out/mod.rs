//! SVG export: deformed chain points written back into the document they came from.
//!
//! The original text is spliced, not regenerated: every element, attribute, style, gradient,
//! text, comment and the order of all of them are kept byte for byte, except for the geometry
//! of imported elements:
//!
//! - `<path>`: its `d` value is replaced.
//! - `<rect>`, `<circle>`, `<ellipse>`, `<line>`, `<polyline>`, `<polygon>`: renamed to
//!   `<path>` (start and end tag), their geometric attributes (`x y width height rx ry`,
//!   `cx cy r`, `x1 y1 x2 y2`, `points`) removed and `d` added.
//! - `<use>` whose instance was imported: replaced by a `<g>` carrying the `use`'s attributes
//!   except `href`, `xlink:href`, `x`, `y`, `width`, `height`, with
//!   `transform` = the `use`'s transform, then `translate(x y)` (then the referenced symbol's
//!   viewBox mapping), holding a copy of the referenced element (ids inside removed; a `symbol`
//!   becomes a `g`) whose geometry elements carry the deformed instance geometry.
//!
//! With [`write_svg_following`] and the [`ElementMaps`] of the pose, what is not a curve
//! follows too ([`crate::follow`]): copies of user-space gradients, patterns and
//! fixed-orientation markers are written after their originals and named by an inline `style`
//! on each element that uses them; `<text>` and `<image>` get a `transform`; strokes may scale.
//! The animated export ([`crate::svg_animate::write_animated_svg_following`]) writes the same
//! attributes for its first frame and animates them through the others ([`crate::smil`]).
//!
//! Each element's points are mapped back to its local coordinates with the inverse of its
//! local → root transform and written as `M x y C … [Z]`, one `C` per cubic, numbers in the
//! shortest form that reads back to the same `f64`. A closed path's last cubic ends on its first
//! point (`P_0`, not `P_3n`), so that `Z` adds no closing segment. Reading the output back with
//! [`crate::svg_in::read_svg`] gives the same paths and curve counts.
//!
//! The same rewriting machinery (with another `RewritePolicy`) prepares the text usvg reads at
//! import: it injects ids and expands `use` elements exactly as export does, so that import and
//! export agree on the structure of every instance.

use std::collections::{HashMap, HashSet};
use std::fmt::Write as _;

use kurbo::{Affine, Point, Rect};

use splineskin_core::drawing::source::{ElementKey, SvgSource};
use splineskin_core::drawing::{Drawing, Path};

use crate::document::{matrix, push_number, push_numbers, SvgError};
use crate::follow::ElementMaps;
use crate::rewrite::{rewrite_document, CopyEdit, GeometryEdit, RewritePolicy};
pub use crate::rewrite::{MAX_EXPANDED_BYTES, MAX_USE_DEPTH};
use crate::smil::Timing;
use resources::follow_edits;

pub(crate) mod resources;
mod view_box;

pub use view_box::{art_bounds, art_outside_view_box, OutsideViewBox, ViewBoxRule};
pub(crate) use view_box::{art_bounds_at, root_attributes};

/// Margin around the points in the viewBox of a standalone export, relative to the larger side
/// of their bounding box: 5 %.
const STANDALONE_MARGIN: f64 = 0.05;

/// Stroke width of a standalone export, relative to the larger side of the points' bounding
/// box: 0.4 %, thin but visible at any zoom that shows the whole drawing.
const STANDALONE_STROKE: f64 = 0.004;

/// Relative size below which an element transform's determinant counts as zero (the transform
/// cannot be inverted to write points in the element's coordinates): 1e-12.
const SINGULAR_DETERMINANT: f64 = 1e-12;

/// Writes `drawing` with its chain points replaced by `points` as SVG text.
///
/// `points` are the deformed chain points concatenated in path order: `drawing.n_points()` of
/// them, laid out like [`Drawing::flat_points`]. If the drawing came from SVG
/// ([`Drawing::source`]), the original document is kept and only the geometry of imported
/// elements changes (module doc). Otherwise a minimal standalone document is written: one
/// `<path>` per [`Path`] (black stroke, no fill) in a viewBox around the points.
///
/// Errors: [`SvgError::PointCount`], [`SvgError::NonFinitePoint`],
/// [`SvgError::SourceMismatch`] (the drawing's paths no longer match its source),
/// [`SvgError::SingularTransform`], [`SvgError::Unsupported`].
///
/// ```
/// use kurbo::Vec2;
/// use splineskin_svg::svg_in::{read_svg, ImportOptions};
/// use splineskin_svg::svg_out::write_svg;
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10">
///   <rect id="box" x="1" y="1" width="2" height="2" fill="red"/></svg>"#;
/// let drawing = read_svg(svg, &ImportOptions::default()).unwrap();
/// let moved: Vec<_> = drawing.flat_points().iter().map(|&p| p + Vec2::new(5.0, 0.0)).collect();
/// let out = write_svg(&drawing, &moved).unwrap();
/// assert!(out.contains(r#"<path id="box" fill="red" d="M6 1 C"#));
/// ```
pub fn write_svg(drawing: &Drawing, points: &[Point]) -> Result<String, SvgError> {
    write_svg_with(drawing, points, &SvgOptions::default())
}

/// [`write_svg`], with every imported element (each `use` instance separately) also given the
/// attribute `marker="k"`, `k` its index in [`SvgSource`]'s elements
/// ([`SvgSource::element_paths`] gives its paths): what an editor needs to find, in the
/// document it shows, the element whose `d` to rewrite as the drawing deforms. `marker` must be
/// a plain attribute name the document does not use (e.g. `data-splineskin-element`). A
/// drawing without a source gets no marker.
///
/// ```
/// use splineskin_svg::svg_in::{read_svg, ImportOptions};
/// use splineskin_svg::svg_out::write_svg_marked;
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg"><rect width="2" height="2"/></svg>"#;
/// let drawing = read_svg(svg, &ImportOptions::default()).unwrap();
/// let out = write_svg_marked(&drawing, &drawing.flat_points(), "data-k").unwrap();
/// assert!(out.contains(r#"<path d="M0 0 C"#) && out.contains(r#" data-k="0"/>"#), "{out}");
/// ```
pub fn write_svg_marked(
    drawing: &Drawing,
    points: &[Point],
    marker: &'static str,
) -> Result<String, SvgError> {
    write_svg_with(drawing, points, &SvgOptions::default().with_marker(marker))
}

/// How [`write_svg_with`] writes a drawing: every option off by default (the input's viewBox
/// kept, nothing carried, no marks), set one by one.
///
/// ```
/// use splineskin_svg::svg_out::{SvgOptions, ViewBoxRule};
/// let options = SvgOptions::default().with_view_box(ViewBoxRule::Fit).with_marker("data-k");
/// assert_eq!(options.view_box, ViewBoxRule::Fit);
/// assert!(options.follow.is_none() && options.inserted.is_none());
/// ```
#[derive(Clone, Copy, Debug, Default)]
#[non_exhaustive]
pub struct SvgOptions<'a> {
    /// What becomes of the root viewBox when the art leaves it.
    pub view_box: ViewBoxRule,
    /// The attribute that marks every imported element with its index (see
    /// [`write_svg_marked`]).
    pub marker: Option<&'static str>,
    /// Maps that carry what is not a curve (see [`write_svg_following`]).
    pub follow: Option<&'a ElementMaps>,
    /// The anchors adaptive control points inserted, per path and joint (see
    /// [`write_svg_with_inserted`]).
    pub inserted: Option<&'a [Vec<bool>]>,
    /// The attribute that marks every carried `<text>` and `<image>` with its index in
    /// document order ([`crate::carry::CarryOperator`]'s): a live view finds there the nodes
    /// whose `transform` to update.
    pub carried_marker: Option<&'static str>,
    /// With [`SvgOptions::follow`]: each element gets its own copy of its user-space paint
    /// servers (gradients, patterns) and fixed-orientation markers, none shared, marked with
    /// this attribute and the element's index, so that a live view can set each copy's
    /// transform (orient) as the element's map moves (turns) it.
    pub paint_marker: Option<&'static str>,
}

impl<'a> SvgOptions<'a> {
    /// Sets [`SvgOptions::view_box`].
    pub fn with_view_box(mut self, view_box: ViewBoxRule) -> Self {
        self.view_box = view_box;
        self
    }

    /// Sets [`SvgOptions::marker`].
    pub fn with_marker(mut self, marker: &'static str) -> Self {
        self.marker = Some(marker);
        self
    }

    /// Sets [`SvgOptions::follow`].
    pub fn with_follow(mut self, maps: Option<&'a ElementMaps>) -> Self {
        self.follow = maps;
        self
    }

    /// Sets [`SvgOptions::inserted`].
    pub fn with_inserted(mut self, inserted: Option<&'a [Vec<bool>]>) -> Self {
        self.inserted = inserted;
        self
    }

    /// Sets [`SvgOptions::carried_marker`].
    pub fn with_carried_marker(mut self, marker: &'static str) -> Self {
        self.carried_marker = Some(marker);
        self
    }

    /// Sets [`SvgOptions::paint_marker`].
    pub fn with_paint_marker(mut self, marker: &'static str) -> Self {
        self.paint_marker = Some(marker);
        self
    }
}

/// Writes `drawing` at `points` as [`write_svg`] does, as `options` say: the one writer the
/// other `write_svg*` functions name a case of.
///
/// ```
/// use kurbo::Vec2;
/// use splineskin_svg::svg_in::{read_svg, ImportOptions};
/// use splineskin_svg::svg_out::{write_svg_with, SvgOptions, ViewBoxRule};
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10"><rect width="2" height="2"/></svg>"#;
/// let drawing = read_svg(svg, &ImportOptions::default())?;
/// let moved: Vec<_> = drawing.flat_points().iter().map(|&p| p + Vec2::new(9.0, 0.0)).collect();
/// let options = SvgOptions::default().with_view_box(ViewBoxRule::Fit).with_marker("data-k");
/// let out = write_svg_with(&drawing, &moved, &options)?;
/// assert!(out.contains(r#"viewBox="0 0 11 10""#) && out.contains(r#"data-k="0""#), "{out}");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_svg_with(
    drawing: &Drawing,
    points: &[Point],
    options: &SvgOptions<'_>,
) -> Result<String, SvgError> {
    let offsets = chain_offsets(drawing, points)?;
    let Some(source) = &drawing.source else {
        return Ok(write_standalone(drawing, points, &offsets, &[]));
    };
    let frames = options
        .follow
        .map_or(&[][..], |maps| &maps.stroke_frames[..]);
    let data = element_path_data(drawing, points, &offsets, source, frames)?;
    let root = root_attributes(drawing, points, &offsets, source, options.view_box)?;
    let follow = options.follow.map(|maps| Follow {
        drawing,
        frames: std::slice::from_ref(maps),
        timing: None,
        paint_marker: options.paint_marker,
    });
    let attributes = options
        .inserted
        .map(|inserted| inserted_attributes(source, inserted))
        .unwrap_or_default();
    let carried_marks = match options.carried_marker {
        Some(name) => Some((name, carried_indices(source)?)),
        None => None,
    };
    export_geometry_follow(
        source,
        data,
        Vec::new(),
        Marks {
            elements: options.marker,
            carried: carried_marks,
        },
        root,
        follow,
        ElementAttributes {
            inserted: attributes,
            frames,
        },
    )
}

/// The index of each carried `<text>` and `<image>` of `source` (by byte offset), in document
/// order.
fn carried_indices(source: &SvgSource) -> Result<HashMap<usize, usize>, SvgError> {
    Ok(crate::follow::carried_regions(source)?
        .iter()
        .enumerate()
        .map(|(j, region)| (region.offset, j))
        .collect())
}

/// The attributes that mark elements for a live view: imported elements by index, and the
/// carried `<text>` and `<image>` elements by index (offset → index).
#[derive(Default)]
struct Marks {
    elements: Option<&'static str>,
    carried: Option<(&'static str, HashMap<usize, usize>)>,
}

/// The attribute on an exported element that lists the anchors adaptive control points
/// inserted in it (so that an editor can tell them from the artist's):
/// `data-splineskin-inserted="s:k …"`, anchor `k` (0-based, the end of the `k`-th cubic) of
/// subpath `s` (0-based, in the order of the element's `d`). Elements with none get none.
pub const INSERTED_ATTRIBUTE: &str = "data-splineskin-inserted";

/// Per element of `source`, the [`INSERTED_ATTRIBUTE`] of the anchors `inserted` marks (per
/// drawing path, per joint), or nothing.
fn inserted_attributes(
    source: &SvgSource,
    inserted: &[Vec<bool>],
) -> Vec<Vec<(&'static str, String)>> {
    source
        .elements
        .iter()
        .map(|element| {
            let mut list = String::new();
            for (s, i) in element.paths.clone().enumerate() {
                for (k, _) in inserted
                    .get(i)
                    .into_iter()
                    .flatten()
                    .enumerate()
                    .filter(|(_, &marked)| marked)
                {
                    if !list.is_empty() {
                        list.push(' ');
                    }
                    let _ = write!(list, "{s}:{k}");
                }
            }
            if list.is_empty() {
                Vec::new()
            } else {
                vec![(INSERTED_ATTRIBUTE, list)]
            }
        })
        .collect()
}

/// [`write_svg_following`] (or [`write_svg_view_box`] without `maps`), each element listing the
/// anchors adaptive control points inserted in it, `inserted` per path and joint (as
/// `splineskin::adaptive::Refined::inserted`), in [`INSERTED_ATTRIBUTE`]. A drawing without a
/// source document is written as by [`write_svg`], without marks.
///
/// ```
/// use splineskin_svg::svg_in::{read_svg, ImportOptions};
/// use splineskin_svg::svg_out::{write_svg_with_inserted, ViewBoxRule};
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10"><path id="p" d="M0 0 C1 1 2 1 3 0 C4 -1 5 -1 6 0"/></svg>"#;
/// let drawing = read_svg(svg, &ImportOptions::default())?;
/// // Joint 1 (between the two cubics) inserted, say by splitting one curve in two.
/// let out = write_svg_with_inserted(&drawing, &drawing.flat_points(), ViewBoxRule::Keep, None, &[vec![false, true, false]])?;
/// assert!(out.contains(r#"data-splineskin-inserted="0:1""#));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_svg_with_inserted(
    drawing: &Drawing,
    points: &[Point],
    view_box: ViewBoxRule,
    maps: Option<&ElementMaps>,
    inserted: &[Vec<bool>],
) -> Result<String, SvgError> {
    let options = SvgOptions::default()
        .with_view_box(view_box)
        .with_follow(maps)
        .with_inserted(Some(inserted));
    write_svg_with(drawing, points, &options)
}

/// [`write_svg`] with the root viewBox chosen by `view_box` ([`ViewBoxRule`]).
///
/// ```
/// use kurbo::Vec2;
/// use splineskin_svg::svg_in::{read_svg, ImportOptions};
/// use splineskin_svg::svg_out::{write_svg_view_box, ViewBoxRule};
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10" width="20mm"
///   height="20mm"><rect x="1" y="1" width="2" height="2"/></svg>"#;
/// let drawing = read_svg(svg, &ImportOptions::default()).unwrap();
/// let moved: Vec<_> = drawing.flat_points().iter().map(|&p| p + Vec2::new(9.0, 0.0)).collect();
/// let out = write_svg_view_box(&drawing, &moved, ViewBoxRule::Fit).unwrap();
/// assert!(out.contains(r#"viewBox="0 0 12 10""#), "{out}");
/// assert!(out.contains(r#"width="24mm""#), "{out}");
/// ```
pub fn write_svg_view_box(
    drawing: &Drawing,
    points: &[Point],
    view_box: ViewBoxRule,
) -> Result<String, SvgError> {
    write_svg_with(
        drawing,
        points,
        &SvgOptions::default().with_view_box(view_box),
    )
}

/// [`write_svg_view_box`], with everything that is not a curve carried by `maps` (computed for
/// this drawing and pose): user-space gradients and patterns, fixed-orientation markers, text
/// and images follow the deformation, and strokes scale if the maps were computed with
/// [`FollowOptions::scale_strokes`](crate::follow::FollowOptions) ([`crate::follow`] says
/// how). A drawing without a source document is written as by [`write_svg`].
///
/// Errors: those of [`write_svg`]; [`SvgError::SourceMismatch`] when `maps` were computed for
/// another drawing.
///
/// ```
/// use kurbo::{Affine, Point};
/// use splineskin_svg::follow::{ElementMaps, FollowOptions};
/// use splineskin_svg::svg_out::{write_svg_following, ViewBoxRule};
/// use splineskin_svg::{read_svg, ImportOptions};
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10">
///   <rect width="4" height="2"/><text x="1" y="8">hi</text></svg>"#;
/// let drawing = read_svg(svg, &ImportOptions::default()).unwrap();
/// let t = Affine::translate((2.0, 0.0));
/// let maps = ElementMaps::from_map(&drawing, &mut |p| t * p, &FollowOptions::default()).unwrap();
/// let moved: Vec<Point> = drawing.flat_points().iter().map(|&p| t * p).collect();
/// let out = write_svg_following(&drawing, &moved, &maps, ViewBoxRule::Keep).unwrap();
/// // The text's new transform is the translation (up to rounding of the fit).
/// assert!(out.contains(r#"<text x="1" y="8" transform="matrix(1 0 "#), "{out}");
/// ```
pub fn write_svg_following(
    drawing: &Drawing,
    points: &[Point],
    maps: &ElementMaps,
    view_box: ViewBoxRule,
) -> Result<String, SvgError> {
    let options = SvgOptions::default()
        .with_view_box(view_box)
        .with_follow(Some(maps));
    write_svg_with(drawing, points, &options)
}

/// Where each path's chain points start in `points` (laid out like [`Drawing::flat_points`]),
/// after checking that there are `drawing.n_points()` of them and all are finite.
///
/// Errors: [`SvgError::PointCount`], [`SvgError::NonFinitePoint`] (naming the element).
pub(crate) fn chain_offsets(drawing: &Drawing, points: &[Point]) -> Result<Vec<usize>, SvgError> {
    let origin = drawing
        .source
        .as_ref()
        .map_or("<drawing>", |s| s.origin.as_str());
    if points.len() != drawing.n_points() {
        return Err(SvgError::PointCount {
            file: origin.to_string(),
            expected: drawing.n_points(),
            found: points.len(),
        });
    }
    let mut offsets = Vec::with_capacity(drawing.paths.len());
    let mut offset = 0;
    for (i, path) in drawing.paths.iter().enumerate() {
        let chunk = &points[offset..offset + path.points.len()];
        if let Some(k) = chunk
            .iter()
            .position(|p| !(p.x.is_finite() && p.y.is_finite()))
        {
            let element = match &drawing.source {
                Some(s) => s.element_label(i),
                None => format!("path {i}"),
            };
            return Err(SvgError::NonFinitePoint {
                file: origin.to_string(),
                element,
                index: offset + k,
            });
        }
        offsets.push(offset);
        offset += path.points.len();
    }
    Ok(offsets)
}

/// A standalone document for a drawing built in code. `children[i]`, when present and not
/// empty, is written as the content of path `i`'s element (e.g. an `<animate>`).
pub(crate) fn write_standalone(
    drawing: &Drawing,
    points: &[Point],
    offsets: &[usize],
    children: &[String],
) -> String {
    let bounds = points
        .iter()
        .fold(None, |r: Option<Rect>, &p| {
            Some(r.map_or(Rect::from_points(p, p), |r| r.union_pt(p)))
        })
        .unwrap_or(Rect::new(0.0, 0.0, 1.0, 1.0));
    let side = bounds.width().max(bounds.height());
    let side = if side > 0.0 { side } else { 1.0 };
    let view = bounds.inflate(STANDALONE_MARGIN * side, STANDALONE_MARGIN * side);
    let mut out = String::from("<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"");
    push_numbers(&mut out, &[view.x0, view.y0, view.width(), view.height()]);
    out.push_str("\">\n");
    for (i, (path, &offset)) in drawing.paths.iter().zip(offsets).enumerate() {
        out.push_str("  <path d=\"");
        push_path_data(
            &mut out,
            path,
            &points[offset..offset + path.points.len()],
            Affine::IDENTITY,
            true,
        );
        out.push_str("\" fill=\"none\" stroke=\"black\" stroke-width=\"");
        push_number(&mut out, STANDALONE_STROKE * side);
        match children.get(i).filter(|c| !c.is_empty()) {
            Some(child) => {
                out.push_str("\">");
                out.push_str(child);
                out.push_str("</path>\n");
            }
            None => out.push_str("\"/>\n"),
        }
    }
    out.push_str("</svg>\n");
    out
}

/// Export policy: imported elements get their deformed `d`; `use` instances that were imported
/// are expanded.
struct ExportPolicy<'e> {
    source: &'e SvgSource,
    element_of_key: HashMap<&'e ElementKey, usize>,
    instances: HashSet<&'e [usize]>,
    data: Vec<String>,
    /// Content written inside each element (empty: none).
    children: Vec<String>,
    /// The attribute that receives each element's index, if any.
    marker: Option<&'static str>,
    /// The attribute that receives each carried text's or image's index, and the indices.
    carried_marks: Option<(&'static str, HashMap<usize, usize>)>,
    /// Attributes set on the root element (the fitted viewBox).
    root: Vec<(&'static str, String)>,
    /// What follows the deformation besides the curves ([`crate::follow`]).
    follow: FollowEdits,
    /// Per imported element, attributes to set (empty: none; e.g. [`INSERTED_ATTRIBUTE`]).
    attributes: Vec<Vec<(&'static str, String)>>,
    /// Per imported element, its stroke frame `F` ([`crate::follow`]; empty: none): it gets the
    /// `transform` `T L⁻¹ F L`.
    frames: &'e [Option<Affine>],
}

/// Attributes set on imported elements besides their geometry.
#[derive(Default)]
struct ElementAttributes<'a> {
    /// Per element, attributes to set (empty: none; e.g. [`INSERTED_ATTRIBUTE`]).
    inserted: Vec<Vec<(&'static str, String)>>,
    /// Per element, its stroke frame ([`crate::follow`]; empty: none).
    frames: &'a [Option<Affine>],
}

/// The edits that carry what is not a curve ([`crate::follow`]); in an animated document
/// ([`Follow::timing`]) they hold the first frame, and the animation elements of the others.
#[derive(Default)]
struct FollowEdits {
    /// Per imported element, style declarations (property, value) to add inline.
    styles: Vec<Vec<(String, String)>>,
    /// Per imported element, animation elements to write inside it (empty: none).
    animations: Vec<String>,
    /// Per resource element (byte offset): the copies written after it.
    copies: HashMap<usize, Vec<CopyEdit>>,
    /// Per carried `<text>`/`<image>` (byte offset): its new `transform`.
    transforms: HashMap<usize, String>,
    /// Per carried `<text>`/`<image>` (byte offset): the animation of its `transform`, written
    /// as its first content.
    contents: HashMap<usize, String>,
}

/// What follows the deformation besides the curves: the element maps of each frame (one for a
/// still document) and, for an animated one, the timing of its animation elements.
pub(crate) struct Follow<'f> {
    /// The drawing the maps belong to.
    pub(crate) drawing: &'f Drawing,
    /// One per frame, at least one.
    pub(crate) frames: &'f [ElementMaps],
    /// `Some` for an animated document (then one map per frame of the timing).
    pub(crate) timing: Option<&'f Timing>,
    /// For a live view ([`SvgOptions::paint_marker`]): every element's own copy of its
    /// user-space paint servers and fixed-orientation markers (none shared), marked with this
    /// attribute and the element's index.
    pub(crate) paint_marker: Option<&'static str>,
}

impl RewritePolicy for ExportPolicy<'_> {
    fn geometry(
        &mut self,
        key: &ElementKey,
        node: roxmltree::Node,
        _in_copy: bool,
    ) -> Result<GeometryEdit, SvgError> {
        let Some(&i) = self.element_of_key.get(key) else {
            return Ok(GeometryEdit::Keep);
        };
        if node.range() != self.source.elements[i].range {
            return Err(SvgError::Internal {
                file: self.source.origin.clone(),
                what: format!("{}: its byte range moved", self.source.elements[i].label),
            });
        }
        let mut child = self.children.get_mut(i).map(std::mem::take);
        if let Some(animation) = self.follow.animations.get_mut(i) {
            child
                .get_or_insert_with(String::new)
                .push_str(&std::mem::take(animation));
        }
        let child = child.filter(|c| !c.is_empty());
        let mut set: Vec<(&'static str, String)> = self
            .marker
            .map(|name| (name, i.to_string()))
            .into_iter()
            .collect();
        if let Some(attributes) = self.attributes.get_mut(i) {
            set.append(attributes);
        }
        if let Some(frame) = self.frames.get(i).copied().flatten() {
            let l = self.source.elements[i].local_to_root;
            let own = crate::follow::own_transform(node);
            set.push(("transform", matrix(own * l.inverse() * frame * l)));
        }
        let mut decls: Vec<(String, String)> =
            self.follow.styles.get(i).cloned().unwrap_or_default();
        if self.source.elements[i].zero_area_fill {
            // Its fill covered no area at rest: keep it invisible once bent (an inline style
            // wins over attributes and style sheets; last, so it wins over a carried fill).
            decls.push(("fill".to_string(), "none".to_string()));
        }
        if !decls.is_empty() {
            let style = node.attribute("style").unwrap_or("").trim();
            let mut style = style.trim_end_matches(';').trim().to_string();
            for (name, value) in decls {
                if !style.is_empty() {
                    style.push(';');
                }
                let _ = write!(style, "{name}:{value}");
            }
            set.push(("style", style));
        }
        Ok(GeometryEdit::ToPath(
            std::mem::take(&mut self.data[i]),
            child,
            set,
        ))
    }

    fn expand_use(&mut self, instance: &[usize]) -> bool {
        self.instances.contains(instance)
    }

    fn copies(&mut self, node: roxmltree::Node) -> Vec<CopyEdit> {
        self.follow
            .copies
            .remove(&node.range().start)
            .unwrap_or_default()
    }

    fn content(&mut self, node: roxmltree::Node, in_copy: bool) -> Option<String> {
        if in_copy {
            return None;
        }
        self.follow.contents.remove(&node.range().start)
    }

    fn attributes(&mut self, node: roxmltree::Node, in_copy: bool) -> Vec<(&'static str, String)> {
        let start = node.range().start;
        let mut set = Vec::new();
        if !in_copy {
            if let Some(t) = self.follow.transforms.get(&start) {
                set.push(("transform", t.clone()));
            }
            if let Some((name, j)) = self
                .carried_marks
                .as_ref()
                .and_then(|(name, marks)| Some((*name, marks.get(&start)?)))
            {
                set.push((name, j.to_string()));
            }
        }
        if node.parent().is_some_and(|p| p.is_root()) {
            set.append(&mut self.root);
        }
        if let Some((_, t)) = self.source.bbox_clips.iter().find(|(c, _)| *c == start) {
            // The rest bounding-box map made explicit: the deformed geometry is written in
            // these coordinates and must not follow the deformed element's bounding box.
            set.push(("clipPathUnits", "userSpaceOnUse".to_string()));
            set.push(("transform", matrix(*t)));
        }
        set
    }
}

/// The new `d` of every imported element of `source` (in [`SvgSource::elements`] order): its
/// subpaths' deformed points mapped back to the element's local coordinates, or to those of
/// its stroke frame `F L` where `frames` has one ([`crate::follow`]; `frames` may be empty).
/// `offsets` from [`chain_offsets`].
///
/// Errors: [`SvgError::SourceMismatch`], [`SvgError::SingularTransform`].
pub(crate) fn element_path_data(
    drawing: &Drawing,
    points: &[Point],
    offsets: &[usize],
    source: &SvgSource,
    frames: &[Option<Affine>],
) -> Result<Vec<String>, SvgError> {
    let origin = source.origin.as_str();
    let mismatch = |what: String| SvgError::SourceMismatch {
        file: origin.to_string(),
        what,
    };
    if drawing.paths.len() != source.n_paths() {
        return Err(mismatch(format!(
            "it has {} paths, the document produced {}",
            drawing.paths.len(),
            source.n_paths()
        )));
    }
    let mut data = Vec::with_capacity(source.elements.len());
    for (k, element) in source.elements.iter().enumerate() {
        let frame = frames.get(k).copied().flatten();
        let t = frame.map_or(element.local_to_root, |f| f * element.local_to_root);
        let [a, b, c, d, _, _] = t.as_coeffs();
        let det = a * d - b * c;
        let scale = (a.abs() + b.abs()) * (c.abs() + d.abs());
        if !(det.abs() > SINGULAR_DETERMINANT * scale && det.is_finite()) {
            return Err(SvgError::SingularTransform {
                file: origin.to_string(),
                element: element.label.clone(),
            });
        }
        let inverse = t.inverse();
        let mut d = String::new();
        for i in element.paths.clone() {
            let path = &drawing.paths[i];
            if !d.is_empty() {
                d.push(' ');
            }
            push_path_data(
                &mut d,
                path,
                &points[offsets[i]..offsets[i] + path.points.len()],
                inverse,
                !source.is_closed_without_z(i),
            );
        }
        data.push(d);
    }
    Ok(data)
}

/// The document of `source` with every imported element's geometry replaced by `data` (one `d`
/// per element, [`element_path_data`]), where `children` (one per element, or empty for none)
/// holds text, that text written as the element's first content, each element given
/// `marker="k"` when `marker` is set ([`write_svg_marked`]), and the root element given the
/// attributes `root` (the fitted viewBox, [`root_attributes`]).
pub(crate) fn export_geometry_root(
    source: &SvgSource,
    data: Vec<String>,
    children: Vec<String>,
    marker: Option<&'static str>,
    root: Vec<(&'static str, String)>,
) -> Result<String, SvgError> {
    let marks = Marks {
        elements: marker,
        carried: None,
    };
    export_geometry_follow(
        source,
        data,
        children,
        marks,
        root,
        None,
        ElementAttributes::default(),
    )
}

/// [`export_geometry_root`] for an animated document: what is not a curve follows each frame's
/// maps, as animation elements with `timing` ([`crate::smil`]).
pub(crate) fn export_geometry_animated(
    source: &SvgSource,
    data: Vec<String>,
    children: Vec<String>,
    root: Vec<(&'static str, String)>,
    follow: Follow,
) -> Result<String, SvgError> {
    let marks = Marks::default();
    export_geometry_follow(
        source,
        data,
        children,
        marks,
        root,
        Some(follow),
        ElementAttributes::default(),
    )
}

/// [`export_geometry_root`], with what is not a curve carried by the maps of `follow`
/// ([`write_svg_following`]).
fn export_geometry_follow(
    source: &SvgSource,
    data: Vec<String>,
    children: Vec<String>,
    marks: Marks,
    root: Vec<(&'static str, String)>,
    follow: Option<Follow>,
    attributes: ElementAttributes<'_>,
) -> Result<String, SvgError> {
    let origin = source.origin.as_str();
    let doc = crate::document::parse_xml(&source.text, origin)?;
    let follow = match follow {
        Some(follow) => follow_edits(source, &doc, &follow)?,
        None => FollowEdits::default(),
    };
    let mut policy = ExportPolicy {
        source,
        element_of_key: source
            .elements
            .iter()
            .enumerate()
            .map(|(i, e)| (&e.key, i))
            .collect(),
        instances: source
            .elements
            .iter()
            .flat_map(|e| (1..=e.key.uses.len()).map(|n| &e.key.uses[..n]))
            .collect(),
        data,
        children,
        marker: marks.elements,
        carried_marks: marks.carried,
        root,
        follow,
        attributes: attributes.inserted,
        frames: attributes.frames,
    };
    let viewport = source.view_box.size();
    rewrite_document(&source.text, &doc, &mut policy, origin, None, viewport)
}

/// Appends one subpath as `M x y C x1 y1 x2 y2 x y … [Z]`, each point mapped by `to_local`.
/// `points` has `path.points.len()` entries; a closed path's last cubic ends on `points[0]`,
/// followed by `Z` when `close_with_z` (a closed path whose source had no `Z` gets none).
pub(crate) fn push_path_data(
    out: &mut String,
    path: &Path,
    points: &[Point],
    to_local: Affine,
    close_with_z: bool,
) {
    let n = path.n_curves();
    let local = |p: Point| {
        let q = to_local * p;
        [q.x, q.y]
    };
    out.push('M');
    push_numbers(out, &local(points[0]));
    for j in 0..n {
        out.push_str(" C");
        for k in 1..=3 {
            let i = 3 * j + k;
            let p = if path.closed && i == 3 * n {
                points[0]
            } else {
                points[i]
            };
            if k > 1 {
                out.push(' ');
            }
            push_numbers(out, &local(p));
        }
    }
    if path.closed && close_with_z {
        out.push_str(" Z");
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::document::{number, user_length};
    use crate::rewrite::view_box_transform;

    fn formatted(v: f64) -> String {
        number(v)
    }

    #[test]
    fn svg_out_number_round_trips_shortest() {
        for v in [
            0.1,
            1.0 / 3.0,
            -2.5,
            1e-17,
            123456789.0,
            1.0e9,
            5e-324,
            -0.0,
            0.0,
        ] {
            let s = formatted(v);
            assert_eq!(s.parse::<f64>().unwrap(), v, "{s}");
        }
        assert_eq!(formatted(10.0), "10");
        assert_eq!(formatted(-0.0), "0");
        assert_eq!(formatted(1.5e-17), "1.5e-17");
        assert_eq!(formatted(0.25), "0.25");
    }

    #[test]
    fn svg_out_view_box_transform_matches_closed_form() {
        let vb = svgtypes::ViewBox::new(-10.0, 0.0, 20.0, 10.0);
        // meet into 100 × 100: scale 5, centred vertically: ty = (100 − 50)/2 = 25.
        let t = view_box_transform(vb, svgtypes::AspectRatio::default(), 100.0, 100.0);
        assert_eq!(t.as_coeffs(), [5.0, 0.0, 0.0, 5.0, 50.0, 25.0]);
        let slice = svgtypes::AspectRatio {
            defer: false,
            align: svgtypes::Align::XMinYMin,
            slice: true,
        };
        let t = view_box_transform(vb, slice, 100.0, 100.0);
        assert_eq!(t.as_coeffs(), [10.0, 0.0, 0.0, 10.0, 100.0, 0.0]);
    }

    #[test]
    fn svg_out_user_length_units() {
        assert_eq!(user_length("10", 50.0), Ok(10.0));
        assert_eq!(user_length("1in", 50.0), Ok(96.0));
        assert_eq!(user_length("50%", 50.0), Ok(25.0));
        assert!(user_length("2em", 50.0).is_err());
    }

    #[test]
    fn svg_out_path_data_closed_ends_on_first_point() {
        let pts: Vec<Point> = [
            (0., 0.),
            (1., 0.),
            (2., 0.),
            (3., 0.),
            (2., 2.),
            (1., 2.),
            (0., 0.),
        ]
        .map(Point::from)
        .to_vec();
        let path = Path::new(pts.clone(), true, &Default::default()).unwrap();
        let mut deformed = pts;
        deformed[6] = Point::new(1e-12, 0.0); // a rig that lets P_3n drift
        let mut s = String::new();
        push_path_data(&mut s, &path, &deformed, Affine::IDENTITY, true);
        assert_eq!(s, "M0 0 C1 0 2 0 3 0 C2 2 1 2 0 0 Z");
    }

    #[test]
    fn svg_out_keeps_a_missing_z() {
        let svg = "<svg xmlns='http://www.w3.org/2000/svg'>\
                   <path d='M0 0 C1 1 2 1 3 0 C2 -1 1 -1 0 0'/>\
                   <path d='M5 0 C6 1 7 1 8 0 C7 -1 6 -1 5 0 Z'/></svg>";
        let drawing = crate::read_svg(svg, &Default::default()).unwrap();
        assert!(drawing.paths.iter().all(|p| p.closed));
        let points: Vec<Point> = drawing
            .flat_points()
            .iter()
            .map(|p| *p + kurbo::Vec2::new(0.0, 1.0))
            .collect();
        let out = write_svg(&drawing, &points).unwrap();
        assert!(out.contains("M0 1 C1 2 2 2 3 1 C2 0 1 0 0 1'"), "{out}");
        assert!(out.contains("M5 1 C6 2 7 2 8 1 C7 0 6 0 5 1 Z'"), "{out}");
    }

    #[test]
    fn svg_out_standalone_has_one_path_per_chain() {
        let pts = [(0., 0.), (1., 1.), (2., 1.), (3., 0.)]
            .map(Point::from)
            .to_vec();
        let path = Path::new(pts.clone(), false, &Default::default()).unwrap();
        let drawing = Drawing {
            paths: vec![path.clone(), path],
            source: None,
        };
        let flat = drawing.flat_points();
        let out = write_svg(&drawing, &flat).unwrap();
        assert_eq!(out.matches("<path ").count(), 2);
        assert!(out.contains("d=\"M0 0 C1 1 2 1 3 0\""));
        let doc = roxmltree::Document::parse(&out).unwrap();
        let vb: Vec<f64> = doc
            .root_element()
            .attribute("viewBox")
            .unwrap()
            .split(' ')
            .map(|v| v.parse().unwrap())
            .collect();
        // bounds (0, 0)–(3, 1), margin 5 % of 3 = 0.15 on every side
        for (v, want) in vb.iter().zip([-0.15, -0.15, 3.3, 1.3]) {
            assert!((v - want).abs() < 1e-12, "{vb:?}");
        }
        let bad = write_svg(&drawing, &flat[1..]);
        assert!(matches!(
            bad,
            Err(SvgError::PointCount {
                expected: 8,
                found: 7,
                ..
            })
        ));
        let mut nan = flat.clone();
        nan[5].y = f64::NAN;
        assert!(matches!(
            write_svg(&drawing, &nan),
            Err(SvgError::NonFinitePoint { index: 5, .. })
        ));
    }
}
