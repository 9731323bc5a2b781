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

use splineskin_core::drawing::junction::tangent_neighbours;
use splineskin_core::drawing::{Drawing, JointKind, Path};

mod path_data;
use path_data::*;

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
        warnings: Vec::new(),
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
