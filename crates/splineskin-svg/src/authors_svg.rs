//! The paper authors' SVG reading, reproduced bit for bit for compatibility mode.
//!
//! The authors' editor (`web-gui.html` in `songrun/VectorSkinning`) loads an SVG into the
//! browser, normalises every `<path>` with Snap.svg 0.2.0 and reads the browser's
//! `pathSegList`, whose coordinates are `float32`. This module redoes that pipeline without a
//! browser. Per `<path>` element, in document order (nesting, `transform`s and the `viewBox`
//! are ignored, other shapes are not read):
//!
//! 1. **Absolute.** Relative commands are made absolute in `f64` (Snap's `toAbsolute`): the
//!    pen accumulates in double precision, not in `float32`.
//! 2. **Redundant closes.** A `Z` whose preceding end point equals the subpath start in
//!    `float32` is removed (for `H`/`V` the end point is the full point they reach).
//! 3. **Re-serialisation.** If a `Z` was removed the browser rewrites the element's `d` from its
//!    `float32` segment list, so every coordinate of *that element* (arc radii and rotation
//!    included) is rounded to `float32` before step 4. Elements without a removed `Z` keep
//!    their `f64` values here.
//! 4. **Cubics** (Snap's `path2curve`, in `f64`):
//!    * `L`, `H`, `V` and a remaining `Z` become `start, start, end, end` (control points **at
//!      the ends**, not at thirds);
//!    * `S` reflects the second control point of the previous cubic *whatever its command* (a
//!      line's is its end point, so the reflection is the current point). As in Snap, a
//!      previous control coordinate of exactly `0` counts as absent (JavaScript `||`) and
//!      the current coordinate is used instead;
//!    * `Q` becomes `(⅓ p₀ + ⅔ c, ⅓ p₁ + ⅔ c, p₁)`; `T` reflects the previous `Q`/`T` control
//!      point (the current point after anything else; a `0` coordinate again counts as absent);
//!    * `A` follows Snap's `a2c`: radii scaled up when too small but not made positive, the
//!      start and end angles from `asin` of a value rounded to 9 decimals, pieces of at most
//!      120°, one cubic per piece. Its `sin`/`cos`/`tan`/`asin` are the platform's, so arcs
//!      may differ from a browser by an ulp before the final `float32` rounding; no reference
//!      scene contains an arc.
//! 5. **Chains.** Every moveto starts a chain; each coordinate is rounded to `float32` (the
//!    browser parses the cubic path again) and widened back to `f64`. A subpath without any
//!    segment is skipped, as the editor does, with a `tracing` warning. A chain is closed
//!    exactly when its first and last points are equal; a closing line added by a `Z` makes
//!    them equal.
//!
//! [`authors_joints`] is the editor's default junction detection. Conformance: the chains and
//! closedness equal, bitwise, the `input_paths` of every case in
//! `../shared/data/vectorskinning/authors-solver-outputs` (`tests/authors_svg.rs`). Against
//! Snap's normalisation run in Node on 3000 random paths of every command, all paths without
//! arcs agree bitwise; 14 of the 1634 with arcs differ by 1–6 `float32` ulps (trigonometry).
//!
//! `float32` appears here only as rounding (`as f32`, widened back at once): all arithmetic is
//! `f64`, as in Snap.
//!
//! ```
//! use kurbo::Point;
//! use splineskin_svg::authors_svg::read_authors_paths;
//! let svg = r#"<svg xmlns="http://www.w3.org/2000/svg"><path d="M0,0 L3,0 L3,3 Z"/></svg>"#;
//! let paths = read_authors_paths(svg).unwrap();
//! assert_eq!(paths.len(), 1);
//! assert!(paths[0].closed);
//! // Three lines, each with its control points on its ends.
//! let pts = [(0., 0.), (0., 0.), (3., 0.), (3., 0.), (3., 0.), (3., 3.), (3., 3.),
//!            (3., 3.), (0., 0.), (0., 0.)].map(Point::from);
//! assert_eq!(paths[0].points, pts);
//! ```

use std::fmt;
use std::str::FromStr;

use kurbo::Point;
use svgtypes::{PathParser, PathSegment};

use splineskin_core::drawing::junction::tangent_neighbours;
use splineskin_core::drawing::{Drawing, JointKind, Path};

/// `|û·v̂ − 1|` at or below which the authors' detection calls a junction G¹ (unit incoming and
/// outgoing tangents, dimensionless): 1e-2, about 8° (README of the reference outputs, "The
/// authors' discretisation").
pub const AUTHORS_G1_DOT_TOLERANCE: f64 = 1e-2;

/// `|û·v̂|` at or below which the authors' detection calls a junction a right angle kept fixed
/// ([`JointKind::FixedAngle`], their `A`): 1e-3, about 0.06° from 90°.
pub const AUTHORS_RIGHT_ANGLE_DOT_TOLERANCE: f64 = 1e-3;

/// The SVG namespace; `<path>` elements in no namespace are read too (as a browser's HTML parser
/// would place them in the SVG namespace).
const SVG_NAMESPACE: &str = "http://www.w3.org/2000/svg";

/// Snap's `_13` and `_23`, the weights of a quadratic's degree elevation.
const ONE_THIRD: f64 = 1.0 / 3.0;
const TWO_THIRDS: f64 = 2.0 / 3.0;

/// Snap's `a2c` splits arcs into pieces of at most this angle (radians, written as Snap
/// computes it: `PI * 120 / 180`).
const ARC_PIECE_MAX_ANGLE: f64 = std::f64::consts::PI * 120.0 / 180.0;

/// Snap's `a2c` rounds the sines of the end angles to this many decimals (`toFixed(9)`) before
/// taking `asin`.
const ARC_ASIN_DECIMALS: usize = 9;

/// `2^10`: a double is a tie when rounded to [`ARC_ASIN_DECIMALS`] decimals exactly when it is
/// an odd multiple of `2^-10` (`x·10⁹ = j·5⁹/2`).
const TIE_SCALE: f64 = 1024.0;

/// `5^9`, with [`TIE_SCALE`] the factor between `j` and the scaled decimal of a tie.
const FIVE_POW_DECIMALS: u128 = 1_953_125;

/// `10^9`, the scale of [`ARC_ASIN_DECIMALS`] decimals.
const TEN_POW_DECIMALS: u128 = 1_000_000_000;

/// JavaScript's `toFixed` falls back to `String(x)` at and above this magnitude.
const JS_TO_FIXED_LIMIT: f64 = 1e21;

/// Which `<path>` element an error or a chain comes from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PathElement {
    /// Position among the document's `<path>` elements, 0-based, in document order.
    pub index: usize,
    /// The element's `id` attribute, if any.
    pub id: Option<String>,
}

impl fmt::Display for PathElement {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "<path> #{}", self.index)?;
        if let Some(id) = &self.id {
            write!(f, " (id \"{id}\")")?;
        }
        Ok(())
    }
}

/// Why the authors' reading of a document failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum AuthorsSvgError {
    /// The document is not well-formed XML.
    #[error("SVG document: expected well-formed XML: {0}")]
    Xml(#[from] roxmltree::Error),
    /// A `d` attribute is not valid SVG path data.
    #[error("{element}: expected valid SVG path data in `d`: {source}")]
    PathData {
        /// The offending element.
        element: PathElement,
        /// What the path-data parser found.
        #[source]
        source: svgtypes::Error,
    },
    /// A segment yields a coordinate that is not a finite `float32` (too large, or an arc the
    /// authors' arc conversion cannot handle, such as a zero radius).
    #[error(
        "{element}: segment {segment} ('{command}') of `d` gives a control point outside the \
         finite float32 range (expected |coordinate| ≤ 3.4e38 and, for arcs, non-zero radii)"
    )]
    NotFinite {
        /// The offending element.
        element: PathElement,
        /// 0-based index of the segment among the parsed segments of `d`.
        segment: usize,
        /// The segment's command letter as written (`'a'`, `'C'`, …).
        command: char,
    },
    /// The reader produced an invalid chain: a bug in this module.
    #[error("{element}: internal error (bug): the reader produced an invalid chain")]
    InvalidChain {
        /// The element the chain came from.
        element: PathElement,
    },
}

/// One chain as the authors' editor sends it to their solver.
#[derive(Clone, Debug, PartialEq)]
pub struct AuthorsPath {
    /// The `3n + 1` chain points (`n ≥ 1`), `float32` values widened to `f64`; a closed chain
    /// repeats its first point at the end.
    pub points: Vec<Point>,
    /// Whether the first and last points coincide.
    pub closed: bool,
    /// Index of the `<path>` element it comes from (document order, as in [`PathElement`]).
    pub element: usize,
}

impl AuthorsPath {
    /// Number of cubic curves `n`.
    pub fn n_curves(&self) -> usize {
        self.points.len().saturating_sub(1) / 3
    }

    /// This chain as a [`Path`] whose joints come from [`authors_joints`] (not from
    /// [`Path::new`]'s classification). `None` if `points` is not a chain of `3n + 1 ≥ 4`
    /// points, or `closed` with different ends.
    ///
    /// ```
    /// use kurbo::Point;
    /// use splineskin_core::drawing::JointKind;
    /// use splineskin_svg::authors_svg::AuthorsPath;
    /// let pts = [(0., 0.), (0., 0.), (2., 0.), (2., 0.)].map(Point::from).to_vec();
    /// let path = AuthorsPath { points: pts, closed: false, element: 0 }.to_path().unwrap();
    /// assert_eq!(path.joints, vec![JointKind::End, JointKind::End]);
    /// ```
    pub fn to_path(&self) -> Option<Path> {
        let joints = authors_joints(&self.points, self.closed)?;
        Some(Path {
            points: self.points.clone(),
            closed: self.closed,
            joints,
        })
    }
}

/// Reads every `<path>` of `svg_text` as the authors' editor does (see the module doc).
///
/// Returns the chains in document order, subpaths of one element consecutively.
///
/// ```
/// use kurbo::Point;
/// use splineskin_svg::authors_svg::read_authors_paths;
/// // `S` after a cubic reflects its second control point (3, 4) about (5, 5).
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg">
///     <path d="M0,0 C1,2 3,4 5,5 S9,8 10,10"/></svg>"#;
/// let paths = read_authors_paths(svg).unwrap();
/// assert_eq!(paths[0].points[4], Point::new(7.0, 6.0));
/// assert!(!paths[0].closed);
/// ```
pub fn read_authors_paths(svg_text: &str) -> Result<Vec<AuthorsPath>, AuthorsSvgError> {
    let options = roxmltree::ParsingOptions {
        // Illustrator exports carry a DOCTYPE (and sometimes internal entities).
        allow_dtd: true,
        ..roxmltree::ParsingOptions::default()
    };
    let document = roxmltree::Document::parse_with_options(svg_text, options)?;
    let path_nodes = document.descendants().filter(|node| {
        node.is_element()
            && node.tag_name().name() == "path"
            && matches!(node.tag_name().namespace(), None | Some(SVG_NAMESPACE))
    });
    let mut paths = Vec::new();
    for (index, node) in path_nodes.enumerate() {
        let element = PathElement {
            index,
            id: node.attribute("id").map(str::to_owned),
        };
        let d = node.attribute("d").unwrap_or("");
        read_element(d, &element, &mut paths)?;
    }
    Ok(paths)
}

/// [`read_authors_paths`] as a [`Drawing`] whose joints come from [`authors_joints`].
///
/// The drawing keeps the document as its [`Drawing::source`], so that
/// [`crate::svg_out::write_svg`] writes deformed chains back into the same `<path>` elements
/// (everything else untouched). As the authors read `d` without transforms, the chains are in
/// each element's own coordinates and are written back as such. A closed chain gets a `Z` when
/// its element's `d` has one.
///
/// ```
/// use splineskin_core::drawing::JointKind;
/// use splineskin_svg::authors_svg::read_authors_drawing;
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg"><path d="M0,0 H4 V4 H0 Z"/></svg>"#;
/// let drawing = read_authors_drawing(svg).unwrap();
/// // Four lines meeting at right angles, the last one added by the Z.
/// assert_eq!(drawing.paths[0].joints, vec![JointKind::FixedAngle; 4]);
/// ```
pub fn read_authors_drawing(svg_text: &str) -> Result<Drawing, AuthorsSvgError> {
    read_authors_drawing_named(svg_text, "<svg text>")
}

/// [`read_authors_drawing`] with the file name used in messages (`origin`).
pub fn read_authors_drawing_named(
    svg_text: &str,
    origin: &str,
) -> Result<Drawing, AuthorsSvgError> {
    let chains = read_authors_paths(svg_text)?;
    let paths = chains
        .iter()
        .map(|chain| {
            chain.to_path().ok_or(AuthorsSvgError::InvalidChain {
                element: PathElement {
                    index: chain.element,
                    id: None,
                },
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    let source = authors_source(svg_text, origin, &chains)?;
    Ok(Drawing {
        paths,
        source: Some(std::sync::Arc::new(source)),
    })
}

/// The export record of a document read the authors' way: one element per `<path>` that
/// produced chains, with the identity as its transform.
fn authors_source(
    svg_text: &str,
    origin: &str,
    chains: &[AuthorsPath],
) -> Result<splineskin_core::drawing::SvgSource, AuthorsSvgError> {
    use splineskin_core::drawing::source::{ElementKey, ElementKind, ImportedElement};
    let options = roxmltree::ParsingOptions {
        allow_dtd: true,
        ..roxmltree::ParsingOptions::default()
    };
    let document = roxmltree::Document::parse_with_options(svg_text, options)?;
    let nodes: Vec<roxmltree::Node> = document
        .descendants()
        .filter(|node| {
            node.is_element()
                && node.tag_name().name() == "path"
                && matches!(node.tag_name().namespace(), None | Some(SVG_NAMESPACE))
        })
        .collect();
    let mut elements: Vec<ImportedElement> = Vec::new();
    let mut path_elements = Vec::with_capacity(chains.len());
    let mut closed_without_z = Vec::with_capacity(chains.len());
    for (i, chain) in chains.iter().enumerate() {
        let node = nodes[chain.element];
        let has_z = node.attribute("d").is_some_and(|d| d.contains(['z', 'Z']));
        closed_without_z.push(chain.closed && !has_z);
        match elements.last_mut() {
            Some(e) if e.key.element == node.range().start => e.paths.end = i + 1,
            _ => {
                let label = PathElement {
                    index: chain.element,
                    id: node.attribute("id").map(str::to_owned),
                };
                let line = document.text_pos_at(node.range().start).row;
                elements.push(ImportedElement {
                    key: ElementKey {
                        uses: Vec::new(),
                        element: node.range().start,
                    },
                    kind: ElementKind::Path,
                    label: format!("{label} (line {line})"),
                    range: node.range(),
                    local_to_root: kurbo::Affine::IDENTITY,
                    paths: i..i + 1,
                    // The authors' reading ignores styles: every path counts as drawn.
                    role: splineskin_core::drawing::PathRole::Visible,
                    path_tag_index: Some(chain.element),
                    zero_area_fill: false,
                    paint: Default::default(),
                });
            }
        }
        path_elements.push(elements.len() - 1);
    }
    let root = document.root_element();
    let number = |name: &str| {
        root.attribute(name)
            .and_then(|v| v.trim_end_matches("px").trim().parse::<f64>().ok())
            .filter(|v| v.is_finite() && *v > 0.0)
    };
    let view_box = root
        .attribute("viewBox")
        .and_then(|v| svgtypes::ViewBox::from_str(v).ok())
        .filter(|vb| vb.w > 0.0 && vb.h > 0.0)
        .map(|vb| kurbo::Rect::new(vb.x, vb.y, vb.x + vb.w, vb.y + vb.h))
        .unwrap_or_else(|| {
            kurbo::Rect::new(
                0.0,
                0.0,
                number("width").unwrap_or(100.0),
                number("height").unwrap_or(100.0),
            )
        });
    let size = kurbo::Size::new(
        number("width").unwrap_or(view_box.width()),
        number("height").unwrap_or(view_box.height()),
    );
    Ok(splineskin_core::drawing::SvgSource {
        origin: origin.to_string(),
        text: svg_text.to_string(),
        elements,
        path_elements,
        closed_without_z,
        size,
        view_box,
        bbox_clips: Vec::new(),
    })
}

/// The authors' default junction detection on a chain of `3n + 1` points (closed chains repeat
/// the first point at the end).
///
/// At each on-curve point `p`, `u` runs from the first previous control point different from
/// `p` (`c₂`, else `c₁`, else `c₀` of the curve ending there) to `p`, and `v` from `p` to the
/// first different next one (`d₁`, `d₂`, `d₃`). With `û·v̂` the dot product of the unit vectors:
///
/// | condition | kind |
/// |---|---|
/// | open end | [`JointKind::End`] |
/// | `u` or `v` has no distinct point | [`JointKind::C0`] |
/// | `|û·v̂ − 1| ≤` [`AUTHORS_G1_DOT_TOLERANCE`] | [`JointKind::G1`] |
/// | `|û·v̂| ≤` [`AUTHORS_RIGHT_ANGLE_DOT_TOLERANCE`] | [`JointKind::FixedAngle`] |
/// | otherwise | [`JointKind::C0`] |
///
/// Returns `n + 1` kinds for an open chain, `n` for a closed one (as [`Path::joints`]), or
/// `None` if `points.len()` is not `3n + 1` with `n ≥ 1` or a closed chain's ends differ.
///
/// ```
/// use kurbo::Point;
/// use splineskin_core::drawing::JointKind;
/// use splineskin_svg::authors_svg::authors_joints;
/// // A line then a curve leaving it in the same direction: G1, although the line's own
/// // control points sit on its ends.
/// let pts = [(0., 0.), (0., 0.), (3., 0.), (3., 0.), (5., 0.), (6., 1.), (7., 0.)]
///     .map(Point::from);
/// let kinds = authors_joints(&pts, false).unwrap();
/// assert_eq!(kinds, vec![JointKind::End, JointKind::G1, JointKind::End]);
/// ```
pub fn authors_joints(points: &[Point], closed: bool) -> Option<Vec<JointKind>> {
    if !splineskin_core::drawing::is_chain(points, closed) {
        return None;
    }
    let n = (points.len() - 1) / 3;
    let count = if closed { n } else { n + 1 };
    let kinds = (0..count)
        .map(|k| {
            if !closed && (k == 0 || k == n) {
                return JointKind::End;
            }
            let p = 3 * k;
            // A distance of 0: "distinct" means not equal, as in the authors' code.
            let (Some(a), Some(b)) = tangent_neighbours(points, closed, p, 0.0) else {
                return JointKind::C0;
            };
            let u = points[p] - points[a];
            let v = points[b] - points[p];
            let (lu, lv) = (u.dot(u).sqrt(), v.dot(v).sqrt());
            let dot = (u.x / lu) * (v.x / lv) + (u.y / lu) * (v.y / lv);
            if (dot - 1.0).abs() <= AUTHORS_G1_DOT_TOLERANCE {
                JointKind::G1
            } else if dot.abs() <= AUTHORS_RIGHT_ANGLE_DOT_TOLERANCE {
                JointKind::FixedAngle
            } else {
                JointKind::C0
            }
        })
        .collect();
    Some(kinds)
}

/// A segment of `d` after step 1 (absolute coordinates), with where it came from.
#[derive(Clone, Copy, Debug)]
struct AbsSegment {
    kind: AbsKind,
    /// 0-based index among the parsed segments of `d`.
    index: usize,
    /// The command letter as written.
    command: char,
}

/// The absolute segment kinds of SVG path data.
#[derive(Clone, Copy, Debug)]
enum AbsKind {
    Move(Point),
    Line(Point),
    Horizontal(f64),
    Vertical(f64),
    Cubic(Point, Point, Point),
    SmoothCubic(Point, Point),
    Quadratic(Point, Point),
    SmoothQuadratic(Point),
    Arc {
        rx: f64,
        ry: f64,
        rotation_degrees: f64,
        large_arc: bool,
        sweep: bool,
        to: Point,
    },
    Close,
}

/// Steps 1–5 for one element's `d`, appending its chains to `out`.
fn read_element(
    d: &str,
    element: &PathElement,
    out: &mut Vec<AuthorsPath>,
) -> Result<(), AuthorsSvgError> {
    let mut segments = to_absolute(d).map_err(|source| AuthorsSvgError::PathData {
        element: element.clone(),
        source,
    })?;
    if segments.is_empty() {
        tracing::warn!("{element}: no path data; skipped, as the authors' editor does");
        return Ok(());
    }
    if drop_redundant_closes(&mut segments) {
        round_segments_to_f32(&mut segments);
    }
    let mut pen = SnapPen::default();
    let mut chain: Vec<Point> = Vec::new();
    for segment in &segments {
        let not_finite = || AuthorsSvgError::NotFinite {
            element: element.clone(),
            segment: segment.index,
            command: segment.command,
        };
        match pen.convert(segment.kind) {
            Converted::Move(p) => {
                finish_chain(std::mem::take(&mut chain), element, out);
                chain.push(round_to_f32(p).ok_or_else(not_finite)?);
            }
            Converted::Cubics(cubics) => {
                for c in cubics {
                    for p in c {
                        chain.push(round_to_f32(p).ok_or_else(not_finite)?);
                    }
                }
            }
        }
    }
    finish_chain(chain, element, out);
    Ok(())
}

/// Appends a finished chain, or skips (with a warning) a subpath without any segment, as the
/// editor's `append_path` does.
fn finish_chain(chain: Vec<Point>, element: &PathElement, out: &mut Vec<AuthorsPath>) {
    if chain.is_empty() {
        return;
    }
    if chain.len() < 4 {
        tracing::warn!(
            "{element}: subpath at {:?} has no segment; skipped, as the authors' editor does",
            chain[0]
        );
        return;
    }
    let closed = chain[0] == chain[chain.len() - 1];
    out.push(AuthorsPath {
        points: chain,
        closed,
        element: element.index,
    });
}

/// Rounds both coordinates to `float32` and back; `None` if either is not finite then.
fn round_to_f32(p: Point) -> Option<Point> {
    let q = Point::new(f32_round(p.x), f32_round(p.y));
    q.is_finite().then_some(q)
}

/// `v` rounded to `float32` and widened back (infinite beyond the `float32` range).
fn f32_round(v: f64) -> f64 {
    f64::from(v as f32)
}

/// `v + origin` for a relative coordinate, `v` itself for an absolute one.
fn offset(v: f64, origin: f64, abs: bool) -> f64 {
    if abs {
        v
    } else {
        v + origin
    }
}

/// The command letter of a parsed segment.
fn command_letter(segment: &PathSegment) -> char {
    let (upper, abs) = match *segment {
        PathSegment::MoveTo { abs, .. } => ('M', abs),
        PathSegment::LineTo { abs, .. } => ('L', abs),
        PathSegment::HorizontalLineTo { abs, .. } => ('H', abs),
        PathSegment::VerticalLineTo { abs, .. } => ('V', abs),
        PathSegment::CurveTo { abs, .. } => ('C', abs),
        PathSegment::SmoothCurveTo { abs, .. } => ('S', abs),
        PathSegment::Quadratic { abs, .. } => ('Q', abs),
        PathSegment::SmoothQuadratic { abs, .. } => ('T', abs),
        PathSegment::EllipticalArc { abs, .. } => ('A', abs),
        PathSegment::ClosePath { abs } => ('Z', abs),
    };
    if abs {
        upper
    } else {
        upper.to_ascii_lowercase()
    }
}

/// Step 1: parses `d` and makes every segment absolute, accumulating the pen in `f64` (Snap's
/// `toAbsolute`).
fn to_absolute(d: &str) -> Result<Vec<AbsSegment>, svgtypes::Error> {
    let mut out = Vec::new();
    let mut pen = Point::ZERO;
    let mut start = Point::ZERO;
    for (index, parsed) in PathParser::from(d).enumerate() {
        let parsed = parsed?;
        let command = command_letter(&parsed);
        let at =
            |x: f64, y: f64, abs: bool| Point::new(offset(x, pen.x, abs), offset(y, pen.y, abs));
        let kind = match parsed {
            PathSegment::MoveTo { abs, x, y } => AbsKind::Move(at(x, y, abs)),
            PathSegment::LineTo { abs, x, y } => AbsKind::Line(at(x, y, abs)),
            PathSegment::HorizontalLineTo { abs, x } => AbsKind::Horizontal(offset(x, pen.x, abs)),
            PathSegment::VerticalLineTo { abs, y } => AbsKind::Vertical(offset(y, pen.y, abs)),
            PathSegment::CurveTo {
                abs,
                x1,
                y1,
                x2,
                y2,
                x,
                y,
            } => AbsKind::Cubic(at(x1, y1, abs), at(x2, y2, abs), at(x, y, abs)),
            PathSegment::SmoothCurveTo { abs, x2, y2, x, y } => {
                AbsKind::SmoothCubic(at(x2, y2, abs), at(x, y, abs))
            }
            PathSegment::Quadratic { abs, x1, y1, x, y } => {
                AbsKind::Quadratic(at(x1, y1, abs), at(x, y, abs))
            }
            PathSegment::SmoothQuadratic { abs, x, y } => AbsKind::SmoothQuadratic(at(x, y, abs)),
            PathSegment::EllipticalArc {
                abs,
                rx,
                ry,
                x_axis_rotation,
                large_arc,
                sweep,
                x,
                y,
            } => AbsKind::Arc {
                rx,
                ry,
                rotation_degrees: x_axis_rotation,
                large_arc,
                sweep,
                to: at(x, y, abs),
            },
            PathSegment::ClosePath { .. } => AbsKind::Close,
        };
        pen = end_point(kind, pen, start);
        if let AbsKind::Move(p) = kind {
            start = p;
        }
        out.push(AbsSegment {
            kind,
            index,
            command,
        });
    }
    Ok(out)
}

/// Where the pen is after `kind`, drawn from `pen` in a subpath starting at `start`.
fn end_point(kind: AbsKind, pen: Point, start: Point) -> Point {
    match kind {
        AbsKind::Move(p)
        | AbsKind::Line(p)
        | AbsKind::Cubic(_, _, p)
        | AbsKind::SmoothCubic(_, p)
        | AbsKind::Quadratic(_, p)
        | AbsKind::SmoothQuadratic(p)
        | AbsKind::Arc { to: p, .. } => p,
        AbsKind::Horizontal(x) => Point::new(x, pen.y),
        AbsKind::Vertical(y) => Point::new(pen.x, y),
        AbsKind::Close => start,
    }
}

/// Step 2: removes every `Z` whose preceding end point equals its subpath's start in
/// `float32`. Returns whether any was removed.
fn drop_redundant_closes(segments: &mut Vec<AbsSegment>) -> bool {
    let same_in_f32 =
        |a: Point, b: Point| f32_round(a.x) == f32_round(b.x) && f32_round(a.y) == f32_round(b.y);
    let n_before = segments.len();
    let mut pen = Point::ZERO;
    let mut start = Point::ZERO;
    segments.retain(|segment| {
        if matches!(segment.kind, AbsKind::Close) && same_in_f32(pen, start) {
            return false;
        }
        pen = end_point(segment.kind, pen, start);
        if let AbsKind::Move(p) = segment.kind {
            start = p;
        }
        true
    });
    segments.len() != n_before
}

/// Step 3: rounds every number of every segment to `float32` (the browser's rewrite of `d`).
fn round_segments_to_f32(segments: &mut [AbsSegment]) {
    let r = |p: Point| Point::new(f32_round(p.x), f32_round(p.y));
    for segment in segments {
        segment.kind = match segment.kind {
            AbsKind::Move(p) => AbsKind::Move(r(p)),
            AbsKind::Line(p) => AbsKind::Line(r(p)),
            AbsKind::Horizontal(x) => AbsKind::Horizontal(f32_round(x)),
            AbsKind::Vertical(y) => AbsKind::Vertical(f32_round(y)),
            AbsKind::Cubic(a, b, p) => AbsKind::Cubic(r(a), r(b), r(p)),
            AbsKind::SmoothCubic(b, p) => AbsKind::SmoothCubic(r(b), r(p)),
            AbsKind::Quadratic(a, p) => AbsKind::Quadratic(r(a), r(p)),
            AbsKind::SmoothQuadratic(p) => AbsKind::SmoothQuadratic(r(p)),
            AbsKind::Arc {
                rx,
                ry,
                rotation_degrees,
                large_arc,
                sweep,
                to,
            } => AbsKind::Arc {
                rx: f32_round(rx),
                ry: f32_round(ry),
                rotation_degrees: f32_round(rotation_degrees),
                large_arc,
                sweep,
                to: r(to),
            },
            AbsKind::Close => AbsKind::Close,
        };
    }
}

/// JavaScript's `a || b` for a number `a` that may be `null` (`None`): `b` when `a` is
/// `null`, `0` or `NaN`.
fn js_or(a: Option<f64>, b: f64) -> f64 {
    match a {
        Some(v) if v != 0.0 && !v.is_nan() => v,
        _ => b,
    }
}

/// What one segment becomes in step 4.
enum Converted {
    /// A moveto: a new chain starts at this point.
    Move(Point),
    /// Cubics `[c₁, c₂, end]` continuing from the pen.
    Cubics(Vec<[Point; 3]>),
}

/// The state of Snap's `path2curve` (its `attrs`): pen, reflection point for `S`, last
/// quadratic control for `T`, subpath start.
#[derive(Clone, Copy, Debug, Default)]
struct SnapPen {
    /// Current point.
    pen: Point,
    /// Second control point of the last cubic, each coordinate already `c || pen` (Snap's
    /// `bx`, `by`).
    reflect: Point,
    /// Last quadratic control point (`qx`, `qy`), `None` when the last segment was not `Q`/`T`.
    quad: (Option<f64>, Option<f64>),
    /// Start of the current subpath (`X`, `Y`).
    start: Point,
}

impl SnapPen {
    /// Converts one absolute segment (Snap's `processPath`) and advances the state.
    fn convert(&mut self, kind: AbsKind) -> Converted {
        if !matches!(kind, AbsKind::Quadratic(..) | AbsKind::SmoothQuadratic(_)) {
            self.quad = (None, None);
        }
        let p0 = self.pen;
        let line = |to: Point| vec![[p0, to, to]];
        let cubics = match kind {
            AbsKind::Move(p) => {
                self.start = p;
                self.pen = p;
                // Snap reads the missing control of a moveto as NaN, hence the pen.
                self.reflect = p;
                return Converted::Move(p);
            }
            AbsKind::Line(p) => line(p),
            AbsKind::Horizontal(x) => line(Point::new(x, p0.y)),
            AbsKind::Vertical(y) => line(Point::new(p0.x, y)),
            AbsKind::Close => line(self.start),
            AbsKind::Cubic(a, b, p) => vec![[a, b, p]],
            AbsKind::SmoothCubic(b, p) => {
                let a = Point::new(
                    p0.x + (p0.x - js_or(Some(self.reflect.x), p0.x)),
                    p0.y + (p0.y - js_or(Some(self.reflect.y), p0.y)),
                );
                vec![[a, b, p]]
            }
            AbsKind::Quadratic(c, p) => {
                self.quad = (Some(c.x), Some(c.y));
                vec![quadratic_to_cubic(p0, c, p)]
            }
            AbsKind::SmoothQuadratic(p) => {
                let c = Point::new(
                    p0.x + (p0.x - js_or(self.quad.0, p0.x)),
                    p0.y + (p0.y - js_or(self.quad.1, p0.y)),
                );
                self.quad = (Some(c.x), Some(c.y));
                vec![quadratic_to_cubic(p0, c, p)]
            }
            AbsKind::Arc {
                rx,
                ry,
                rotation_degrees,
                large_arc,
                sweep,
                to,
            } => arc_to_cubics(p0, rx, ry, rotation_degrees, large_arc, sweep, to),
        };
        if let Some(&[_, b, p]) = cubics.last() {
            self.pen = p;
            self.reflect = Point::new(js_or(Some(b.x), p.x), js_or(Some(b.y), p.y));
        }
        Converted::Cubics(cubics)
    }
}

/// Snap's `q2c`: the cubic of the quadratic `p0, c, p` (degree elevation, evaluated as Snap
/// writes it).
fn quadratic_to_cubic(p0: Point, c: Point, p: Point) -> [Point; 3] {
    [
        Point::new(
            ONE_THIRD * p0.x + TWO_THIRDS * c.x,
            ONE_THIRD * p0.y + TWO_THIRDS * c.y,
        ),
        Point::new(
            ONE_THIRD * p.x + TWO_THIRDS * c.x,
            ONE_THIRD * p.y + TWO_THIRDS * c.y,
        ),
        p,
    ]
}

/// JavaScript's `Number(x.toFixed(9))`: `x` rounded to [`ARC_ASIN_DECIMALS`] decimals, ties
/// away from zero (Rust's formatting rounds ties to even).
fn js_to_fixed_9(x: f64) -> f64 {
    if !x.is_finite() || x.abs() >= JS_TO_FIXED_LIMIT {
        return x;
    }
    let scaled = x.abs() * TIE_SCALE; // exact: a power of two
    let is_tie = scaled.fract() == 0.0 && scaled % 2.0 == 1.0;
    if !is_tie {
        return format!("{x:.ARC_ASIN_DECIMALS$}").parse().unwrap_or(x);
    }
    // |x| = j / 2^10 with j odd: |x|·10⁹ = j·5⁹ / 2, rounded up in magnitude.
    let j = scaled as u128; // exact: an integer below 2^80
    let n = (j * FIVE_POW_DECIMALS).div_ceil(2);
    let sign = if x < 0.0 { "-" } else { "" };
    let text = format!(
        "{sign}{}.{:0width$}",
        n / TEN_POW_DECIMALS,
        n % TEN_POW_DECIMALS,
        width = ARC_ASIN_DECIMALS
    );
    text.parse().unwrap_or(x)
}

/// Rotation of `(x, y)` by `rad` as Snap's `a2c` writes it.
fn snap_rotate(x: f64, y: f64, rad: f64) -> Point {
    Point::new(x * rad.cos() - y * rad.sin(), x * rad.sin() + y * rad.cos())
}

/// The end angles and centre of an arc piece in `a2c`'s recursion.
#[derive(Clone, Copy, Debug)]
struct ArcPiece {
    f1: f64,
    f2: f64,
    cx: f64,
    cy: f64,
}

/// Snap 0.2.0's `a2c`: the cubics of the arc from `p0` to `to` (SVG arc parameters, rotation
/// in degrees), in the arc's rotated frame until the final rotation back.
fn arc_to_cubics(
    p0: Point,
    rx: f64,
    ry: f64,
    rotation_degrees: f64,
    large_arc: bool,
    sweep: bool,
    to: Point,
) -> Vec<[Point; 3]> {
    use std::f64::consts::PI;
    // `+angle || 0`
    let rad = PI / 180.0 * js_or(Some(rotation_degrees), 0.0);
    let a = snap_rotate(p0.x, p0.y, -rad);
    let b = snap_rotate(to.x, to.y, -rad);
    let (x1, y1, x2, y2) = (a.x, a.y, b.x, b.y);
    let x = (x1 - x2) / 2.0;
    let y = (y1 - y2) / 2.0;
    let (mut rx, mut ry) = (rx, ry);
    let h = (x * x) / (rx * rx) + (y * y) / (ry * ry);
    if h > 1.0 {
        let h = h.sqrt();
        rx *= h;
        ry *= h;
    }
    let rx2 = rx * rx;
    let ry2 = ry * ry;
    let k_sign = if large_arc == sweep { -1.0 } else { 1.0 };
    let k = k_sign
        * ((rx2 * ry2 - rx2 * y * y - ry2 * x * x) / (rx2 * y * y + ry2 * x * x))
            .abs()
            .sqrt();
    let cx = k * rx * y / ry + (x1 + x2) / 2.0;
    let cy = k * -ry * x / rx + (y1 + y2) / 2.0;
    let mut f1 = js_to_fixed_9((y1 - cy) / ry).asin();
    let mut f2 = js_to_fixed_9((y2 - cy) / ry).asin();
    if x1 < cx {
        f1 = PI - f1;
    }
    if x2 < cx {
        f2 = PI - f2;
    }
    if f1 < 0.0 {
        f1 += PI * 2.0;
    }
    if f2 < 0.0 {
        f2 += PI * 2.0;
    }
    if sweep && f1 > f2 {
        f1 -= PI * 2.0;
    }
    if !sweep && f2 > f1 {
        f2 -= PI * 2.0;
    }
    let mut flat = Vec::new();
    arc_pieces(
        Point::new(x1, y1),
        Point::new(x2, y2),
        rx,
        ry,
        sweep,
        ArcPiece { f1, f2, cx, cy },
        &mut flat,
    );
    // Rotate back to the drawing's frame.
    flat.iter()
        .map(|c| c.map(|p| snap_rotate(p.x, p.y, rad)))
        .collect()
}

/// The recursive part of `a2c`: appends to `out` the cubics of the piece from `start` (angle
/// `f1`) to `end` (angle `f2`), first splitting off pieces of [`ARC_PIECE_MAX_ANGLE`].
///
/// Terminates: `f1` and `f2` lie in `[−2π, 3π]`, and each level moves `f1` by 120° towards
/// `f2` (a NaN angle difference stops at once).
fn arc_pieces(
    start: Point,
    end: Point,
    rx: f64,
    ry: f64,
    sweep: bool,
    piece: ArcPiece,
    out: &mut Vec<[Point; 3]>,
) {
    let ArcPiece { f1, mut f2, cx, cy } = piece;
    let (x1, y1) = (start.x, start.y);
    let (mut x2, mut y2) = (end.x, end.y);
    let mut rest = Vec::new();
    if (f2 - f1).abs() > ARC_PIECE_MAX_ANGLE {
        let (f2_old, end_old) = (f2, Point::new(x2, y2));
        let direction = if sweep && f2 > f1 { 1.0 } else { -1.0 };
        f2 = f1 + ARC_PIECE_MAX_ANGLE * direction;
        x2 = cx + rx * f2.cos();
        y2 = cy + ry * f2.sin();
        let next = ArcPiece {
            f1: f2,
            f2: f2_old,
            cx,
            cy,
        };
        arc_pieces(Point::new(x2, y2), end_old, rx, ry, sweep, next, &mut rest);
    }
    let df = f2 - f1;
    let (c1, s1, c2, s2) = (f1.cos(), f1.sin(), f2.cos(), f2.sin());
    let t = (df / 4.0).tan();
    let hx = 4.0 / 3.0 * rx * t;
    let hy = 4.0 / 3.0 * ry * t;
    let m2 = Point::new(x1 + hx * s1, y1 - hy * c1);
    let m2 = Point::new(2.0 * x1 - m2.x, 2.0 * y1 - m2.y);
    let m3 = Point::new(x2 + hx * s2, y2 - hy * c2);
    out.push([m2, m3, Point::new(x2, y2)]);
    out.extend(rest);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(d: &str) -> Vec<AuthorsPath> {
        let svg = format!(r#"<svg xmlns="http://www.w3.org/2000/svg"><path d="{d}"/></svg>"#);
        read_authors_paths(&svg).unwrap()
    }

    fn pts(v: &[(f64, f64)]) -> Vec<Point> {
        v.iter().map(|&p| Point::from(p)).collect()
    }

    /// `float32` rounding of a point, as every output coordinate is.
    fn f32p(x: f64, y: f64) -> Point {
        Point::new(f32_round(x), f32_round(y))
    }

    #[test]
    fn authors_svg_line_has_controls_at_its_ends() {
        let p = read("M1,2 L7,5");
        assert_eq!(p.len(), 1);
        assert_eq!(p[0].points, pts(&[(1., 2.), (1., 2.), (7., 5.), (7., 5.)]));
        assert!(!p[0].closed);
    }

    #[test]
    fn authors_svg_horizontal_and_vertical_lines() {
        let p = read("M1,1 H5 V7 h-2 v1");
        let expected = pts(&[
            (1., 1.),
            (1., 1.),
            (5., 1.),
            (5., 1.),
            (5., 1.),
            (5., 7.),
            (5., 7.),
            (5., 7.),
            (3., 7.),
            (3., 7.),
            (3., 7.),
            (3., 8.),
            (3., 8.),
        ]);
        assert_eq!(p[0].points, expected);
    }

    #[test]
    fn authors_svg_redundant_close_is_dropped() {
        let p = read("M0,0 L10,0 L10,10 L0,0 Z");
        assert_eq!(p[0].n_curves(), 3);
        assert!(p[0].closed);
    }

    #[test]
    fn authors_svg_close_after_vertical_line_to_start_is_redundant() {
        // The end point of V is the full point it reaches.
        let p = read("M0,0 L5,0 L0,5 V0 z");
        assert_eq!(p[0].n_curves(), 3);
        assert!(p[0].closed);
    }

    #[test]
    fn authors_svg_closing_z_adds_a_line_cubic() {
        let p = read("M0,0 L10,0 L10,10 Z");
        assert_eq!(p[0].n_curves(), 3);
        assert_eq!(
            p[0].curve_tail(),
            pts(&[(10., 10.), (10., 10.), (0., 0.), (0., 0.)])
        );
        assert!(p[0].closed);
    }

    #[test]
    fn authors_svg_closedness_is_decided_in_float32() {
        // 100.000001 and 100 are the same float32: the chain is closed without any Z.
        let p = read("M100,0 L101,0 L101,1 L100.000001,0");
        assert!(p[0].closed);
        assert_eq!(p[0].points[0], p[0].points[9]);
        let open = read("M100,0 L101,0 L101,1 L100.0001,0");
        assert!(!open[0].closed);
    }

    #[test]
    fn authors_svg_smooth_cubic_reflects_previous_control() {
        let p = read("M0,0 C1,2 3,4 5,5 S9,8 10,10");
        assert_eq!(p[0].points[4], Point::new(7., 6.));
    }

    #[test]
    fn authors_svg_smooth_cubic_after_line_starts_at_pen() {
        let p = read("M0,0 L4,4 S9,8 10,10");
        assert_eq!(p[0].points[4], Point::new(4., 4.));
    }

    #[test]
    fn authors_svg_smooth_cubic_treats_zero_control_as_absent() {
        // Snap's `bx || x`: the previous control x is 0, so the current x (2) is used.
        let p = read("M0,0 C1,1 0,3 2,4 S5,5 6,6");
        assert_eq!(p[0].points[4], Point::new(2., 5.));
    }

    #[test]
    fn authors_svg_quadratic_and_smooth_quadratic() {
        let p = read("M0,0 Q3,3 6,0 T12,0");
        let expected = pts(&[
            (0., 0.),
            (2., 2.),
            (4., 2.),
            (6., 0.),
            (8., -2.),
            (10., -2.),
            (12., 0.),
        ]);
        assert_eq!(p[0].points, expected);
    }

    #[test]
    fn authors_svg_relative_commands_accumulate_in_f64() {
        // The pen is 0.1 + 0.2 in double precision, rounded to float32 only at the end.
        let p = read("m0.1,0.1 l0.2,0.2 c0.1,0 0.1,0 0.3,0.3");
        let a = 0.1 + 0.2;
        let b = a + 0.3;
        let expected = vec![
            f32p(0.1, 0.1),
            f32p(0.1, 0.1),
            f32p(a, a),
            f32p(a, a),
            f32p(a + 0.1, a),
            f32p(a + 0.1, a),
            f32p(b, b),
        ];
        assert_eq!(p[0].points, expected);
        // Relative and absolute spellings of the same integers agree exactly.
        assert_eq!(
            read("m1,2 l3,0 v4 h-3 z")[0].points,
            read("M1,2 L4,2 V6 H1 Z")[0].points
        );
    }

    #[test]
    fn authors_svg_dropped_close_rounds_the_element_to_f32_first() {
        // From wide-pebblish: the S reflection is computed from float32 inputs when the
        // element lost a redundant Z, from double inputs otherwise.
        let d = "M331.833,144.365c0,42.896,0,77.671-116,77.671s-116-34.775-116-77.671";
        let open = read(d);
        let closed = read(&format!(
            "{d}s0-77.67,116-77.67S331.833,101.469,331.833,144.365z"
        ));
        assert_eq!(open[0].points[4].x, 99.83300018310547);
        assert_eq!(closed[0].points[4].x, 99.83297729492188);
        assert!(closed[0].closed);
        assert_eq!(closed[0].n_curves(), 4);
    }

    #[test]
    fn authors_svg_quarter_arc_matches_the_circle_approximation() {
        // Largest error allowed: float32 rounding at magnitude 10 is below 1e-6.
        const F32_ACCURACY: f64 = 1e-6;
        let p = read("M10,0 A10,10 0 0,1 0,10");
        let kappa = 10.0 * 4.0 / 3.0 * (std::f64::consts::PI / 8.0).tan();
        let expected = pts(&[(10., 0.), (10., kappa), (kappa, 10.), (0., 10.)]);
        assert_eq!(p[0].points.len(), 4);
        for (a, b) in p[0].points.iter().zip(&expected) {
            assert!((*a - *b).hypot() < F32_ACCURACY, "{a:?} vs {b:?}");
        }
        assert_eq!(p[0].points[3], Point::new(0., 10.));
    }

    #[test]
    fn authors_svg_half_arc_is_split_into_pieces_of_120_degrees() {
        const F32_ACCURACY: f64 = 1e-5;
        let p = read("M10,0 A10,10 0 0,1 -10,0");
        assert_eq!(p[0].n_curves(), 2);
        // The split is at 120°, on the circle.
        let q = p[0].points[3];
        let angle = 120f64.to_radians();
        assert!((q - Point::new(10. * angle.cos(), 10. * angle.sin())).hypot() < F32_ACCURACY);
        assert_eq!(p[0].points[6], Point::new(-10., 0.));
    }

    #[test]
    fn authors_svg_to_fixed_rounds_ties_away_from_zero() {
        assert_eq!(js_to_fixed_9(1.0 / 1024.0), 0.000976563);
        assert_eq!(js_to_fixed_9(-3.0 / 1024.0), -0.002929688);
        assert_eq!(js_to_fixed_9(0.1234567894), 0.123456789);
        assert_eq!(js_to_fixed_9(0.5), 0.5);
    }

    #[test]
    fn authors_svg_every_subpath_is_a_chain_and_empty_ones_are_skipped() {
        let p = read("M0,0 L1,0 M5,5 M6,6 L7,7 Z");
        assert_eq!(p.len(), 2);
        assert_eq!(p[1].points[0], Point::new(6., 6.));
        assert!(p[1].closed);
    }

    #[test]
    fn authors_svg_reads_only_paths_without_transforms() {
        let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 5 5">
            <rect width="3" height="3"/>
            <g transform="translate(100,0)"><path id="a" d="M0,0 L1,0"/></g>
            <path d="M2,2 L3,3"/></svg>"#;
        let p = read_authors_paths(svg).unwrap();
        assert_eq!(p.len(), 2);
        assert_eq!(p[0].points[0], Point::ZERO);
        assert_eq!((p[0].element, p[1].element), (0, 1));
    }

    #[test]
    fn authors_svg_malformed_path_data_names_the_element() {
        let svg = r#"<svg xmlns="http://www.w3.org/2000/svg">
            <path d="M0,0 L1,1"/><path id="bad" d="M0,0 L10"/></svg>"#;
        let err = read_authors_paths(svg).unwrap_err();
        let message = err.to_string();
        assert!(matches!(&err, AuthorsSvgError::PathData { element, .. } if element.index == 1));
        assert!(
            message.contains("#1") && message.contains("\"bad\""),
            "{message}"
        );
        assert!(message.contains("path data"), "{message}");
    }

    #[test]
    fn authors_svg_path_data_must_start_with_a_moveto() {
        let svg = r#"<svg xmlns="http://www.w3.org/2000/svg"><path d="L1,1"/></svg>"#;
        assert!(matches!(
            read_authors_paths(svg),
            Err(AuthorsSvgError::PathData { .. })
        ));
    }

    #[test]
    fn authors_svg_out_of_range_coordinates_are_an_error() {
        let svg = r#"<svg xmlns="http://www.w3.org/2000/svg"><path d="M0,0 L1e39,0"/></svg>"#;
        let err = read_authors_paths(svg).unwrap_err();
        assert!(matches!(
            err,
            AuthorsSvgError::NotFinite {
                segment: 1,
                command: 'L',
                ..
            }
        ));
        // A zero radius breaks the authors' arc conversion.
        let svg =
            r#"<svg xmlns="http://www.w3.org/2000/svg"><path d="M0,0 a0,0 0 0 1 5,5"/></svg>"#;
        let err = read_authors_paths(svg).unwrap_err();
        assert!(
            matches!(err, AuthorsSvgError::NotFinite { command: 'a', .. }),
            "{err}"
        );
    }

    #[test]
    fn authors_svg_malformed_xml_is_an_error() {
        assert!(matches!(
            read_authors_paths("<svg><path d='M0,0 L1,1'></svg>"),
            Err(AuthorsSvgError::Xml(_))
        ));
    }

    #[test]
    fn authors_joints_kinds() {
        // Right angle, then a smooth junction, then a 45° corner.
        let p = pts(&[
            (0., 0.),
            (0., 0.),
            (3., 0.),
            (3., 0.),
            (3., 0.),
            (3., 3.),
            (3., 3.),
            (3., 4.),
            (3., 5.),
            (3., 6.),
            (4., 7.),
            (5., 8.),
            (6., 9.),
        ]);
        let k = authors_joints(&p, false).unwrap();
        let expected = [
            JointKind::End,
            JointKind::FixedAngle,
            JointKind::G1,
            JointKind::C0,
            JointKind::End,
        ];
        assert_eq!(k, expected);
    }

    #[test]
    fn authors_joints_g1_tolerance_is_on_the_dot_product() {
        // cos 8° ≈ 0.9903 is within 1e-2 of 1; cos 9° ≈ 0.9877 is not.
        let bend = |deg: f64| {
            let (s, c) = deg.to_radians().sin_cos();
            pts(&[
                (-3., 0.),
                (-2., 0.),
                (-1., 0.),
                (0., 0.),
                (c, s),
                (2. * c, 2. * s),
                (3. * c, 3. * s),
            ])
        };
        assert_eq!(authors_joints(&bend(8.0), false).unwrap()[1], JointKind::G1);
        assert_eq!(authors_joints(&bend(9.0), false).unwrap()[1], JointKind::C0);
    }

    #[test]
    fn authors_joints_closed_and_degenerate() {
        // A closed square of lines: every corner a right angle.
        let drawing = read_authors_drawing(
            r#"<svg xmlns="http://www.w3.org/2000/svg"><path d="M0,0 H4 V4 H0 Z"/></svg>"#,
        )
        .unwrap();
        assert_eq!(drawing.paths[0].joints, vec![JointKind::FixedAngle; 4]);
        // A curve collapsed to its start point has no direction: C0.
        let p = pts(&[
            (0., 0.),
            (1., 0.),
            (2., 0.),
            (3., 0.),
            (3., 0.),
            (3., 0.),
            (3., 0.),
        ]);
        assert_eq!(authors_joints(&p, false).unwrap()[1], JointKind::C0);
        // Not a chain, or a closed chain with different ends.
        assert_eq!(authors_joints(&p[..5], false), None);
        assert_eq!(authors_joints(&p, true), None);
    }

    impl AuthorsPath {
        /// The last curve's four points.
        fn curve_tail(&self) -> Vec<Point> {
            self.points[self.points.len() - 4..].to_vec()
        }
    }
}
