//! SVG import: a document becomes a [`Drawing`] of cubic chains in the root element's user
//! space, plus an [`SvgSource`] that lets [`crate::svg_out`] write deformed geometry back into the
//! same document.
//!
//! # What is read
//!
//! The text is first read as a browser reads it ([`lenient`]: internal DTD entities expanded,
//! CSS units such as `rem` and `vw` resolved, attribute values that do not parse ignored,
//! `points` lists in error handled as chromium handles them, each with a warning kept in
//! [`SvgSource::warnings`](splineskin_core::drawing::SvgSource::warnings)). It is then checked
//! ([`MAX_SVG_BYTES`], well-formed XML, an `<svg>` root, every `d`,
//! `points`, `transform`, `viewBox` and shape/`use` length attribute parsed with `svgtypes` and
//! required to be finite and within [`MAX_COORDINATE`]), then handed to usvg, which resolves
//! styles, nested transforms, nested `svg` viewports and turns every path command (M, L, H, V,
//! C, S, Q, T, A, Z, absolute or relative) and every basic shape (`rect` incl. rounded,
//! `circle`, `ellipse`, `line`, `polyline`, `polygon`) into move / line / quadratic / cubic /
//! close segments. usvg never touches the file system here (no resources directory, images are
//! not loaded).
//!
//! The `d` of a `<path>` is read in `f64` with the same svgtypes simplification usvg applies
//! (and checked against usvg's `f32` copy); shapes use usvg's `f32` points. Each segment then
//! becomes a cubic, in `f64`:
//!
//! ```text
//! line  p0 → p3:          c1 = p0 + (p3 − p0)/3,   c2 = p0 + 2(p3 − p0)/3          (exact)
//! quad  p0, q, p3:        c1 = p0 + 2/3 (q − p0),  c2 = p3 + 2/3 (q − p3)          (exact)
//! cubic:                  kept
//! ```
//!
//! **Straight segments between corners** (neither end a C¹ or G¹ junction: corners, fixed
//! angles, open ends) instead get their control points on their ends, `c1 = p0, c2 = p3` — the
//! same straight line (the form Illustrator stores), parametrised with speed `6t(1−t)·(p3 − p0)`.
//! The fit compares the deformed curve with the skinned one *at equal parameters*, so the
//! parametrisation of a line chooses which cubic best follows its bent image; measured against
//! the exactly skinned segment (random poses, bundled fish, the authors' turtles and U-shape),
//! the end form is 10–40 % closer for segments between corners, while at smooth junctions the
//! thirds are 5–10 times closer (the end form would leave no tangent there). Turn it off with
//! [`ImportOptions::corner_lines_at_ends`].
//!
//! Elliptical arcs (in `d`, rounded-rect corners, circles and ellipses) are approximated by usvg
//! and svgtypes with kurbo's standard arc approximation: at most 90° per cubic, control arms
//! `4/3·tan(θ/4)` times the radius, so the radial error is at most `2.73e-4 × radius` per cubic
//! (the classic quarter-circle figure, 0.0273 %), and at most 0.1 local units (more cubics are
//! used on large arcs). This is the only geometric
//! approximation of the import; everything else is exact up to usvg's `f32` storage of
//! transform coefficients and shape attributes (relative error ≈ 6e-8).
//!
//! # Coordinates
//!
//! All points are in the root `<svg>` element's user space (viewBox units): every transform
//! between the root and an element (group, element, `use`, nested `svg`) is applied, the
//! root's own `transform` and its viewBox → viewport mapping are not. The composition of the
//! individual transforms is done in `f64`.
//!
//! # Subpaths and degenerate input
//!
//! Every subpath becomes one [`Path`] in document order. `Z` closes it: if the last point
//! differs from the first (by more than [`CLOSE_SNAP`] of the subpath's size) a closing line is
//! added as one more cubic, otherwise the last point is set to the first and the path is marked
//! closed. A subpath without `Z` whose last point equals its first exactly (as drawn in
//! illustration tools that close a shape by returning to its start) is closed too: its ends are
//! one point with a junction, so a deformation cannot open it; export writes it back without
//! `Z`, so its stroke caps do not change. Zero-length segments, duplicate consecutive points and control points on top of
//! their end points are **kept** as they are (so the curve count is stable: export writes the
//! same curves back). Subpaths of a single point (`M` alone, `M … Z` with nothing in between)
//! carry no curve: they are skipped with a `tracing` warning and are not written back.
//!
//! # What is not imported
//!
//! - The content of patterns and markers is not imported as art (it is drawn in the paint's or
//!   marker's own coordinates); [`crate::follow`] carries user-space patterns and
//!   fixed-orientation markers by each element's best-fit affine map. Paths that usvg emits
//!   without a source element (marker contents, the two halves of a path split by
//!   `paint-order` around markers) are skipped with a `tracing` warning.
//!
//! # Hidden layers, clip paths and masks
//!
//! Every path gets a [`PathRole`]. usvg drops `display: none` elements, so a document that
//! mentions `display` is read a second time with a user style sheet showing everything
//! (`* { display: inline !important }`); paths of that reading missing from the first are
//! [`PathRole::Hidden`]: they are deformed and written back like the rest (their `display`
//! kept), so unhiding a layer shows it posed. The geometry of a `<clipPath>` and the content of
//! a `<mask>` applied to an element are imported before that element's own paths, in the
//! clipped element's user space (its transforms, the clip's `transform` and, in
//! `clipPathUnits="objectBoundingBox"`, the rest bounding box); export writes such a clip in
//! `userSpaceOnUse` units with that map as its `transform`, so it does not follow the deformed
//! bounding box a second time. A clip path or mask used by several elements is imported once,
//! for its first use: uses in the same coordinates get the same deformation; a use in other
//! coordinates (another transform, another bounding box) would need a second copy, which this
//! version does not write: it says so with a `tracing` warning. Mask content in
//! `maskContentUnits="objectBoundingBox"` is left at rest, with a warning; mask regions
//! (`x y width height` of the `<mask>`) are not moved.
//! - Images are not geometry here: they are kept verbatim on export, or carried by their
//!   best-fit affine map with [`crate::svg_out::write_svg_following`]. So is text, unless
//!   [`ImportOptions::text`] is [`TextMode::Outlines`]: then every `<text>` becomes `<path>`
//!   elements of its glyph outlines before the document is read, and deforms as curves.
//! - `use` elements are expanded before usvg sees them (the same expansion
//!   [`crate::svg_out::write_svg`] writes: a `<g>` holding a copy of the referenced content),
//!   so CSS rules that select the referenced content by id or position do not follow it into the
//!   copy. A `use` of an `<svg>` element and `use` lengths in `em`/`ex` are unsupported
//!   (an error), and the clipping of a referenced `symbol` to its viewport is dropped.
//! - Elements created by DTD entity expansion are unsupported (an error).
//!
//! [`Path`]: splineskin_core::drawing::Path
//! [`PathRole`]: splineskin_core::drawing::PathRole
//! [`PathRole::Hidden`]: splineskin_core::drawing::PathRole::Hidden

use std::borrow::Cow;
use std::collections::HashMap;
use std::str::FromStr;

use kurbo::{Affine, Point, Rect, Size};

use crate::document::{check_size, node_label, parse_xml, unique_prefix, SHOW_HIDDEN_CSS};
mod import_paths;
pub mod lenient;
mod segments;
mod validate;

pub use crate::document::{SvgError, MAX_SVG_BYTES};
use crate::rewrite::{GeometryEdit, RewritePolicy};
use splineskin_core::drawing::source::{ElementKey, ElementPaint, SvgSource};
use splineskin_core::drawing::{Drawing, JunctionOptions};
use validate::*;

/// Largest accepted absolute value of a coordinate, in user units: 1e9. Checked on every number
/// of `d`, `points` and shape attributes, and on every point after transforms (root user
/// space). usvg stores `f32`, whose spacing at 1e9 is already 64 units.
pub const MAX_COORDINATE: f64 = 1e9;

/// Distance, relative to the larger of a subpath's control-point bounding-box diagonal and its
/// largest absolute coordinate (local units), below which the end of a closed subpath counts as
/// its start: 1e-6. usvg's `f32` rounding (≈ 6e-8 relative) can leave arcs and circles ending a
/// few ulps away from where they started; a closing line of that length would be a spurious
/// degenerate curve.
pub const CLOSE_SNAP: f64 = 1e-6;

/// Options of the SVG import.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct ImportOptions {
    /// How the junctions of every imported path are classified.
    /// Default: [`JunctionOptions::default`].
    pub junctions: JunctionOptions,
    /// Place the control points of straight segments between corners on their ends rather
    /// than at their thirds (see the module doc). Default: `true`.
    pub corner_lines_at_ends: bool,
    /// What becomes of `<text>` elements. Default: [`TextMode::Keep`].
    pub text: TextMode,
}

/// What the import does with `<text>` elements ([`ImportOptions::text`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum TextMode {
    /// Text stays text: it is not part of the drawing's curves, and export writes it as the
    /// document has it. The default.
    #[default]
    Keep,
    /// Every `<text>` becomes its glyph outlines before the document is read: `<path>`
    /// elements (one per text span and decoration line, grouped when their paint differs)
    /// with the text's attributes, its resolved paint (fill, stroke, opacities, …) and as `d`
    /// the outlines usvg lays out in DejaVu Sans ([`crate::fonts`]), the font every render
    /// uses, so at rest they draw exactly what a render of the text draws. They are then
    /// imported like any path (quadratics elevated exactly to cubics), deformed as curves by
    /// the fit, and written back as `<path>` elements where the `<text>` was;
    /// [`SvgSource::text`] is the converted document.
    ///
    /// **What is lost**: the string. The outlines can no longer be edited, searched, selected
    /// or read aloud as text, nor drawn in another font; text usvg cannot lay out (no
    /// character of it in DejaVu Sans) stays text.
    /// The extra `<path>` elements also shift the numbering of `<path>` elements that the
    /// paper authors' scenes refer to ([`SvgSource::path_tag_position`]).
    ///
    /// ```
    /// use splineskin_svg::{read_svg, ImportOptions, TextMode};
    /// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 40">
    ///   <rect width="100" height="40" fill="none" stroke="gray"/>
    ///   <text id="t" x="10" y="30" font-size="24" fill="navy">Hi</text></svg>"#;
    /// let kept = read_svg(svg, &ImportOptions::default()).unwrap();
    /// assert_eq!(kept.paths.len(), 1); // the rectangle only
    /// let outlined = read_svg(svg, &ImportOptions::default().with_text(TextMode::Outlines));
    /// let outlined = outlined.unwrap();
    /// assert_eq!(outlined.paths.len(), 1 + 3); // H: one outline, i: its stem and its dot
    /// let source = outlined.source.as_ref().unwrap();
    /// assert_eq!(source.element_label(1), "path#t (line 3)");
    /// assert!(source.text().contains(r#"<path id="t" fill="navy" d="M"#));
    /// ```
    Outlines,
}

impl Default for ImportOptions {
    fn default() -> Self {
        ImportOptions {
            junctions: JunctionOptions::default(),
            corner_lines_at_ends: true,
            text: TextMode::Keep,
        }
    }
}

impl ImportOptions {
    /// Sets [`ImportOptions::corner_lines_at_ends`].
    ///
    /// ```
    /// use splineskin_svg::{read_svg, ImportOptions};
    /// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg"><path d="M0 0 L3 0"/></svg>"#;
    /// let ends = read_svg(svg, &ImportOptions::default()).unwrap();
    /// assert_eq!(ends.paths[0].points[1], kurbo::Point::new(0.0, 0.0));
    /// let thirds = ImportOptions::default().with_corner_lines_at_ends(false);
    /// let thirds = read_svg(svg, &thirds).unwrap();
    /// assert_eq!(thirds.paths[0].points[1], kurbo::Point::new(1.0, 0.0));
    /// ```
    pub fn with_corner_lines_at_ends(mut self, on: bool) -> Self {
        self.corner_lines_at_ends = on;
        self
    }

    /// Sets [`ImportOptions::junctions`].
    pub fn with_junctions(mut self, junctions: JunctionOptions) -> Self {
        self.junctions = junctions;
        self
    }

    /// Sets [`ImportOptions::text`].
    pub fn with_text(mut self, text: TextMode) -> Self {
        self.text = text;
        self
    }
}

/// The paint of a usvg path ([`ElementPaint`]).
fn element_paint(path: &usvg::Path) -> ElementPaint {
    let server = |paint: &usvg::Paint| match paint {
        usvg::Paint::Color(_) => None,
        usvg::Paint::LinearGradient(g) => Some(g.id().to_string()),
        usvg::Paint::RadialGradient(g) => Some(g.id().to_string()),
        usvg::Paint::Pattern(p) => Some(p.id().to_string()),
    };
    ElementPaint {
        filled: path.fill().is_some(),
        even_odd: path
            .fill()
            .is_some_and(|f| f.rule() == usvg::FillRule::EvenOdd),
        stroke_width: path.stroke().map(|s| f64::from(s.width().get())),
        fill_server: path.fill().and_then(|f| server(f.paint())),
        stroke_server: path.stroke().and_then(|s| server(s.paint())),
    }
}

/// Name used in errors for documents that did not come from a file.
const TEXT_ORIGIN: &str = "<svg text>";

/// Longest attribute value quoted in an error message, in characters.
const MAX_QUOTED_VALUE: usize = 60;

/// Reads an SVG document into a [`Drawing`] whose [`Drawing::source`] allows writing it back.
///
/// See the module doc for what is read and how. Errors: [`SvgError::TooLarge`],
/// [`SvgError::Empty`], [`SvgError::Xml`], [`SvgError::NoSvgRoot`],
/// [`SvgError::InvalidAttribute`], [`SvgError::CoordinateOutOfRange`], [`SvgError::NoPaths`],
/// [`SvgError::Usvg`], [`SvgError::Unsupported`].
///
/// ```
/// use splineskin_svg::svg_in::{read_svg, ImportOptions};
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100" width="200">
///   <g transform="translate(10 0)"><rect width="20" height="10"/></g>
/// </svg>"#;
/// let drawing = read_svg(svg, &ImportOptions::default()).unwrap();
/// assert_eq!(drawing.paths.len(), 1);
/// let rect = &drawing.paths[0];
/// assert!(rect.closed);
/// assert_eq!(rect.n_curves(), 4); // four sides, the last one the closing line
/// assert_eq!(rect.points[3], kurbo::Point::new(30.0, 0.0)); // viewBox units, not pixels
/// ```
pub fn read_svg(text: &str, options: &ImportOptions) -> Result<Drawing, SvgError> {
    read_svg_impl(text, options, TEXT_ORIGIN)
}

/// Reads an SVG document held in memory like [`read_svg`], naming it `origin` (the file or the
/// scene it came from) in errors and in [`SvgSource::origin`] instead of `"<svg text>"`.
///
/// ```
/// use splineskin_svg::svg_in::{read_svg_named, ImportOptions};
/// let err = read_svg_named("<svg", &ImportOptions::default(), "fish.svg").unwrap_err();
/// assert!(err.to_string().starts_with("fish.svg:1:"), "{err}");
/// ```
pub fn read_svg_named(
    text: &str,
    options: &ImportOptions,
    origin: &str,
) -> Result<Drawing, SvgError> {
    read_svg_impl(text, options, origin)
}

/// Reads an SVG file (UTF-8, at most [`MAX_SVG_BYTES`]) like [`read_svg`]; errors name the
/// file.
///
/// ```
/// use splineskin_svg::svg_in::{read_svg_file, ImportOptions, SvgError};
/// let err = read_svg_file(std::path::Path::new("/no/such.svg"), &ImportOptions::default());
/// assert!(matches!(err, Err(SvgError::Io { .. })));
/// ```
pub fn read_svg_file(path: &std::path::Path, options: &ImportOptions) -> Result<Drawing, SvgError> {
    use std::io::Read;
    let origin = path.display().to_string();
    let io = |source| SvgError::Io {
        file: origin.clone(),
        source,
    };
    let file = std::fs::File::open(path).map_err(io)?;
    let len = file.metadata().map_err(io)?.len();
    check_size(&origin, len)?;
    let mut bytes = Vec::new();
    file.take(MAX_SVG_BYTES as u64 + 1)
        .read_to_end(&mut bytes)
        .map_err(io)?;
    check_size(&origin, bytes.len() as u64)?;
    let text = String::from_utf8(bytes).map_err(|_| SvgError::NotUtf8 {
        file: origin.clone(),
    })?;
    read_svg_impl(&text, options, &origin)
}

/// usvg options that keep usvg away from the file system: no resources directory, and no
/// image is loaded (images are irrelevant to the geometry).
fn usvg_options() -> usvg::Options<'static> {
    usvg::Options {
        resources_dir: None,
        image_href_resolver: usvg::ImageHrefResolver {
            resolve_data: Box::new(|_, _, _| None),
            resolve_string: Box::new(|_, _| None),
        },
        ..usvg::Options::default()
    }
}

/// [`usvg_options`] with [`SHOW_HIDDEN_CSS`].
fn usvg_options_showing_hidden() -> usvg::Options<'static> {
    usvg::Options {
        style_sheet: Some(SHOW_HIDDEN_CSS.to_string()),
        ..usvg_options()
    }
}

fn read_svg_impl(text: &str, options: &ImportOptions, origin: &str) -> Result<Drawing, SvgError> {
    // The one place a document is read: `RUST_LOG=splineskin_svg=debug` shows every reading
    // (and a test counts them).
    tracing::debug!(origin, bytes = text.len(), "reading an SVG document");
    check_size(origin, text.len() as u64)?;
    // What a browser would draw differently from what usvg reads is rewritten first (lenient).
    let (text, lenient_warnings) = lenient::browser_reading(text, origin)?;
    let text: &str = &text;
    if options.text == TextMode::Outlines {
        if let Some(converted) = crate::text_outlines::outline_text(text, origin)? {
            let rest = ImportOptions {
                text: TextMode::Keep,
                ..*options
            };
            return read_svg_impl(&converted, &rest, origin);
        }
    }
    let (doc, mut warnings) = parse_svg_document(text, origin)?;
    warnings.splice(0..0, lenient_warnings);
    let Prepared {
        text: prepared,
        ids,
        wrapper_id,
    } = prepare(text, &doc, origin)?;
    let usvg_error = |e: usvg::Error| SvgError::Usvg {
        file: origin.to_string(),
        message: e.to_string(),
    };
    let shown = usvg::Tree::from_str(&prepared, &usvg_options()).map_err(usvg_error)?;
    // Hidden layers: usvg drops `display: none` elements, so the document is read a second time
    // with them shown; the paths of that reading missing from the first are hidden. Only when
    // the text can hide anything (the property's name appears in it).
    let with_hidden = if text.contains("display") {
        Some(usvg::Tree::from_str(&prepared, &usvg_options_showing_hidden()).map_err(usvg_error)?)
    } else {
        None
    };
    let tree = with_hidden.as_ref().unwrap_or(&shown);
    let clip_offsets: HashMap<String, usize> = doc
        .descendants()
        .filter(|n| crate::document::is_svg_element(*n))
        .filter(|n| matches!(n.tag_name().name(), "clipPath" | "mask"))
        .filter_map(|n| Some((n.attribute("id")?.to_string(), n.range().start)))
        .collect();
    let shown_ids: Option<std::collections::HashSet<&str>> = with_hidden.as_ref().map(|_| {
        paths_under(&shown, &wrapper_id, &clip_offsets)
            .into_iter()
            .map(|(p, _, _)| p.id())
            .collect()
    });
    let mut importer = import_paths::Importer::new(&doc, &ids, options, origin);
    for (usvg_path, local_to_root, context) in paths_under(tree, &wrapper_id, &clip_offsets) {
        let hidden = shown_ids
            .as_ref()
            .is_some_and(|s| !s.contains(usvg_path.id()));
        importer.add(usvg_path, local_to_root, context, hidden)?;
    }
    let size = Size::new(
        f64::from(tree.size().width()),
        f64::from(tree.size().height()),
    );
    let view_box = doc
        .root_element()
        .attribute("viewBox")
        .and_then(|v| svgtypes::ViewBox::from_str(v).ok())
        .map(|vb| Rect::new(vb.x, vb.y, vb.x + vb.w, vb.y + vb.h))
        .unwrap_or_else(|| Rect::from_origin_size(Point::ORIGIN, size));
    importer
        .finish(text, size, view_box, warnings.clone())
        .map_err(|e| match e {
            // Nothing drawn because the path data stops before its first segment: say so.
            SvgError::NoPaths { file, .. } => SvgError::NoPaths {
                file,
                why: warnings,
            },
            e => e,
        })
}

/// The text a drawing read from `text` (from `origin`, default options) keeps as its source
/// ([`SvgSource::text`]): `text` as a browser reads it (entities expanded, values browsers
/// ignore removed, CSS units written in user units: [`lenient`]), borrowed when that reading
/// changes nothing. A cache of drawings by the text they were read from compares with it.
///
/// ```
/// use splineskin_svg::svg_in::source_text;
/// use splineskin_svg::{read_svg, ImportOptions};
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10">
///   <rect width="2rem" height="5"/></svg>"#;
/// let read = read_svg(svg, &ImportOptions::default())?;
/// let kept = source_text(svg, "<string>")?;
/// assert_eq!(read.source.as_ref().unwrap().text, kept.as_ref());
/// assert!(kept.contains(r#"width="32""#));
/// # Ok::<(), splineskin_svg::SvgError>(())
/// ```
pub fn source_text<'t>(text: &'t str, origin: &str) -> Result<Cow<'t, str>, SvgError> {
    check_size(origin, text.len() as u64)?;
    Ok(lenient::browser_reading(text, origin)?.0)
}

/// The warnings reading `text` (from `origin`) gives of what is drawn other than written, as
/// sentences naming the file and element: path data drawn up to its first error, as browsers
/// draw it. Empty for a document without any, and for one the import refuses (its error says
/// why).
///
/// ```
/// use splineskin_svg::svg_in::import_warnings;
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10">
///   <path id="cut" d="M1 1 L9 1 L9 9 L x 5"/></svg>"#;
/// let warnings = import_warnings(svg, "cut.svg");
/// assert_eq!(warnings.len(), 1);
/// assert!(warnings[0].starts_with("cut.svg: path#cut"), "{}", warnings[0]);
/// assert!(warnings[0].contains("byte 17"), "{}", warnings[0]); // the `x`
/// ```
pub fn import_warnings(text: &str, origin: &str) -> Vec<String> {
    let Ok((text, mut warnings)) = lenient::browser_reading(text, origin) else {
        return Vec::new();
    };
    let validated = parse_xml(&text, origin)
        .ok()
        .and_then(|doc| validate_document(&doc, origin).ok());
    match validated {
        Some(more) => {
            warnings.extend(more);
            warnings
        }
        None => Vec::new(),
    }
}

/// `text` parsed, its root checked to be an SVG `<svg>` and the document validated (sizes,
/// coordinates, what is unsupported: [`validate_document`]), with the validation's warnings.
fn parse_svg_document<'i>(
    text: &'i str,
    origin: &str,
) -> Result<(roxmltree::Document<'i>, Vec<String>), SvgError> {
    check_size(origin, text.len() as u64)?;
    if text.trim().is_empty() {
        return Err(SvgError::Empty {
            file: origin.to_string(),
        });
    }
    let doc = parse_xml(text, origin)?;
    let root = doc.root_element();
    if !(crate::document::is_svg_element(root) && root.tag_name().name() == "svg") {
        let found = match root.tag_name().namespace() {
            Some(ns) => format!("{} (namespace {ns})", root.tag_name().name()),
            None => root.tag_name().name().to_string(),
        };
        return Err(SvgError::NoSvgRoot {
            file: origin.to_string(),
            found,
        });
    }
    let warnings = validate_document(&doc, origin)?;
    Ok((doc, warnings))
}

/// The paths of `tree` inside the group `wrapper_id` (the root's content), in drawing order,
/// with their local → root map and where they were found ([`collect_paths_in`]).
fn paths_under<'t>(
    tree: &'t usvg::Tree,
    wrapper_id: &str,
    clip_offsets: &HashMap<String, usize>,
) -> Vec<(&'t usvg::Path, Affine, Context)> {
    let mut found = Vec::new();
    if let Some(usvg::Node::Group(wrapper)) = tree.node_by_id(wrapper_id) {
        collect_paths_in(
            wrapper,
            Affine::IDENTITY,
            Context::Art,
            clip_offsets,
            &mut found,
        );
    }
    found
}

/// The root viewport in user units (viewBox size, else absolute width/height, else 100 × 100
/// as usvg assumes): what percentages in `use` lengths refer to.
fn root_viewport(root: roxmltree::Node) -> Size {
    if let Some(vb) = root
        .attribute("viewBox")
        .and_then(|v| svgtypes::ViewBox::from_str(v).ok())
    {
        return Size::new(vb.w, vb.h);
    }
    let length = |name| {
        root.attribute(name)
            .and_then(|v| crate::document::user_length(v, 100.0).ok())
            .filter(|v| v.is_finite() && *v > 0.0)
            .unwrap_or(100.0)
    };
    Size::new(length("width"), length("height"))
}

/// A document made ready for usvg: every geometry element given an id usvg keeps (`ids` maps
/// each back to its element), every `use` expanded, and the root's content wrapped in a group
/// of id `wrapper_id`, so that the root transform can be told apart.
pub(crate) struct Prepared {
    /// The rewritten text.
    pub text: String,
    /// usvg path id → the element (and `use` chain) it comes from.
    pub ids: HashMap<String, ElementKey>,
    /// Id of the group wrapping the root's content.
    pub wrapper_id: String,
}

/// Prepares `text` (parsed as `doc`, already validated) for usvg ([`Prepared`]).
pub(crate) fn prepare(
    text: &str,
    doc: &roxmltree::Document,
    origin: &str,
) -> Result<Prepared, SvgError> {
    let prefix = unique_prefix(doc);
    let wrapper_id = format!("{prefix}root");
    let mut policy = PreparePolicy::new(doc, &prefix);
    let text = crate::rewrite::rewrite_document(
        text,
        doc,
        &mut policy,
        origin,
        Some(&wrapper_id),
        root_viewport(doc.root_element()),
    )?;
    Ok(Prepared {
        text,
        ids: policy.ids,
        wrapper_id,
    })
}

/// The usvg tree of a drawing's source document, as the import read it ([`prepare`] and
/// usvg with the import's options), with the map from usvg path ids to elements and the id of
/// the group wrapping the root's content: for exporters that need the resolved paint of each
/// imported element.
pub(crate) fn source_tree(source: &SvgSource) -> Result<(usvg::Tree, Prepared), SvgError> {
    let origin = source.origin.as_str();
    let doc = parse_xml(&source.text, origin)?;
    let prepared = prepare(&source.text, &doc, origin)?;
    let tree =
        usvg::Tree::from_str(&prepared.text, &usvg_options()).map_err(|e| SvgError::Usvg {
            file: origin.to_string(),
            message: e.to_string(),
        })?;
    Ok((tree, prepared))
}

/// Import policy for the rewriter: keeps first-occurrence ids of direct geometry elements,
/// gives every other geometry element (and every copy inside an expanded `use`) a synthetic
/// id, records id → element, and expands every `use`.
struct PreparePolicy<'p> {
    prefix: &'p str,
    /// Byte offset of the first element carrying each id.
    first_owner: HashMap<&'p str, usize>,
    ids: HashMap<String, ElementKey>,
    n_synthetic: usize,
}

impl<'p> PreparePolicy<'p> {
    fn new(doc: &'p roxmltree::Document, prefix: &'p str) -> Self {
        let mut first_owner = HashMap::new();
        for n in doc.descendants() {
            if let Some(id) = n.attribute("id") {
                first_owner.entry(id).or_insert(n.range().start);
            }
        }
        PreparePolicy {
            prefix,
            first_owner,
            ids: HashMap::new(),
            n_synthetic: 0,
        }
    }
}

impl RewritePolicy for PreparePolicy<'_> {
    fn geometry(
        &mut self,
        key: &ElementKey,
        node: roxmltree::Node,
        in_copy: bool,
    ) -> Result<GeometryEdit, SvgError> {
        if !in_copy {
            if let Some(id) = node.attribute("id") {
                if self.first_owner.get(id) == Some(&key.element) {
                    self.ids.insert(id.to_string(), key.clone());
                    return Ok(GeometryEdit::Keep);
                }
            }
        }
        let id = format!("{}{}", self.prefix, self.n_synthetic);
        self.n_synthetic += 1;
        self.ids.insert(id.clone(), key.clone());
        Ok(GeometryEdit::SetId(id))
    }

    fn expand_use(&mut self, _instance: &[usize]) -> bool {
        true
    }
}

/// Largest distance of a chain point from the line through a subpath's two farthest-apart
/// points, relative to their distance, for the subpath to count as having zero fill area:
/// 1e-9 (`f64` rounding of lines elevated to cubics and of transforms).
pub const ZERO_AREA: f64 = 1e-9;

/// Whether all of `points` lie on one line, within [`ZERO_AREA`] of their extent.
fn collinear(points: &[Point]) -> bool {
    let Some(&a) = points.first() else {
        return true;
    };
    let b = points
        .iter()
        .copied()
        .max_by(|p, q| (*p - a).hypot2().total_cmp(&(*q - a).hypot2()))
        .unwrap_or(a);
    let d = b - a;
    let len = d.hypot();
    if len == 0.0 {
        return true;
    }
    points
        .iter()
        .all(|p| (d.cross(*p - a)).abs() / len <= ZERO_AREA * len)
}

/// Where usvg emitted a path.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Context {
    /// Drawn content.
    Art,
    /// Inside the `<clipPath>` at byte offset `clip`, whose content → referencing user space
    /// map (its `transform`, times the bounding-box map in `objectBoundingBox` units) is
    /// `units`.
    Clip { clip: usize, units: Affine },
    /// Inside the `<mask>` at byte offset `mask`.
    Mask { mask: usize },
}

/// Largest difference between coefficients, relative to their size, of two placements of a
/// shared clip path or mask that still count as the same: 1e-9 (both come from the same
/// `f32` transforms, composed in `f64`).
const SAME_PLACEMENT: f64 = 1e-9;

fn same_placement(a: Affine, b: Affine) -> bool {
    let (a, b) = (a.as_coeffs(), b.as_coeffs());
    let scale = a.iter().chain(&b).fold(1.0f64, |m, v| m.max(v.abs()));
    a.iter()
        .zip(&b)
        .all(|(x, y)| (x - y).abs() <= SAME_PLACEMENT * scale)
}

/// The byte offset, in the text usvg read, of the element with `id`, as recorded in the
/// ids usvg keeps for `<clipPath>` and `<mask>` (their own ids). Returns `usize::MAX` when
/// unknown (then no special units are handled).
fn offset_of_id(offsets: &HashMap<String, usize>, id: &str) -> usize {
    offsets.get(id).copied().unwrap_or(usize::MAX)
}

/// The paths below `group` with their local → (wrapper) root transform, composed in `f64`,
/// and where they were found. The geometry of clip paths and the content of masks applied
/// to a group come first, in the group's coordinates (after its own transform), as resvg
/// draws them; `clip_offsets` maps their ids to their byte offsets.
fn collect_paths_in<'t>(
    group: &'t usvg::Group,
    ts: Affine,
    context: Context,
    offsets: &HashMap<String, usize>,
    out: &mut Vec<(&'t usvg::Path, Affine, Context)>,
) {
    for child in group.children() {
        match child {
            usvg::Node::Group(g) => {
                let inner = ts * affine(g.transform());
                let mut clip = g.clip_path();
                while let Some(c) = clip {
                    let units = affine(c.transform());
                    let content = inner * units;
                    let ctx = Context::Clip {
                        clip: offset_of_id(offsets, c.id()),
                        units,
                    };
                    collect_paths_in(c.root(), content, ctx, offsets, out);
                    clip = c.clip_path();
                }
                let mut mask = g.mask();
                while let Some(m) = mask {
                    let ctx = Context::Mask {
                        mask: offset_of_id(offsets, m.id()),
                    };
                    collect_paths_in(m.root(), inner, ctx, offsets, out);
                    mask = m.mask();
                }
                collect_paths_in(g, inner, context, offsets, out);
            }
            usvg::Node::Path(p) => out.push((p, ts, context)),
            _ => {}
        }
    }
}

/// A tiny-skia transform as a kurbo affine (`x' = sx·x + kx·y + tx`, `y' = ky·x + sy·y + ty`,
/// i.e. SVG's `matrix(sx ky kx sy tx ty)`), in `f64`.
pub(crate) fn affine(t: usvg::Transform) -> Affine {
    Affine::new([
        f64::from(t.sx),
        f64::from(t.ky),
        f64::from(t.kx),
        f64::from(t.sy),
        f64::from(t.tx),
        f64::from(t.ty),
    ])
}

/// The label of an element key: the element, then the `use` elements it is instantiated
/// through, innermost first.
fn key_label(
    doc: &roxmltree::Document,
    nodes: &HashMap<usize, roxmltree::Node>,
    key: &ElementKey,
) -> String {
    let label = |offset: &usize| match nodes.get(offset) {
        Some(&n) => node_label(doc, n),
        None => format!("element at byte {offset}"),
    };
    let mut s = label(&key.element);
    for u in key.uses.iter().rev() {
        s.push_str(" in ");
        s.push_str(&label(u));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::segments::*;
    use super::*;
    use splineskin_core::drawing::JointKind;

    fn svg(body: &str) -> String {
        format!("<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 100 100\">{body}</svg>")
    }

    fn read(body: &str) -> Result<Drawing, SvgError> {
        read_svg(&svg(body), &ImportOptions::default())
    }

    #[test]
    fn svg_in_line_is_elevated_exactly() {
        let thirds = ImportOptions::default().with_corner_lines_at_ends(false);
        let d = read_svg(&svg("<path d='M0 0 L3 6'/>"), &thirds).unwrap();
        let p = &d.paths[0].points;
        assert_eq!(p.len(), 4);
        assert_eq!(p[1], Point::new(1.0, 2.0));
        assert_eq!(p[2], Point::new(2.0, 4.0));
        assert_eq!(p[3], Point::new(3.0, 6.0));
    }

    #[test]
    fn svg_in_corner_lines_have_control_points_on_their_ends() {
        // A square: four lines (the last one added by Z) between right-angle corners.
        let d = read("<path d='M0 0 H3 V3 H0 Z'/>").unwrap();
        let p = &d.paths[0].points;
        assert_eq!(p.len(), 13);
        for k in 0..4 {
            assert_eq!(p[3 * k + 1], p[3 * k], "curve {k}");
            assert_eq!(p[3 * k + 2], p[3 * k + 3], "curve {k}");
        }
        // A line leaving a curve smoothly keeps its thirds (it carries the tangent).
        let d = read("<path d='M0 0 C1 1 2 1 3 1 L6 1 L6 4'/>").unwrap();
        let p = &d.paths[0].points;
        assert!(matches!(
            d.paths[0].joints[1],
            JointKind::C1 | JointKind::G1
        ));
        assert_eq!(p[4], Point::new(4.0, 1.0));
        assert_eq!(p[5], Point::new(5.0, 1.0));
        // The last line runs from a corner to an open end: on its ends.
        assert_eq!(p[7], Point::new(6.0, 1.0));
        assert_eq!(p[8], Point::new(6.0, 4.0));
        // Curves are never touched.
        assert_eq!(p[1], Point::new(1.0, 1.0));
    }

    #[test]
    fn svg_in_quadratic_is_elevated_exactly() {
        // Q with control (3, 6): c1 = p0 + 2/3 (q − p0) = (2, 4), c2 = p3 + 2/3 (q − p3) = (4, 4).
        let d = read("<path d='M0 0 Q3 6 6 0'/>").unwrap();
        let p = &d.paths[0].points;
        assert_eq!(
            p,
            &[(0., 0.), (2., 4.), (4., 4.), (6., 0.)].map(Point::from)
        );
    }

    #[test]
    fn svg_in_close_adds_line_or_snaps() {
        let open_end = read("<path d='M0 0 L10 0 L10 10 Z'/>").unwrap();
        assert!(open_end.paths[0].closed);
        assert_eq!(open_end.paths[0].n_curves(), 3);
        let same_end = read("<path d='M0 0 L10 0 L10 10 L0 0 Z'/>").unwrap();
        assert!(same_end.paths[0].closed);
        assert_eq!(same_end.paths[0].n_curves(), 3);
    }

    #[test]
    fn svg_in_return_to_start_without_z_is_closed() {
        let d = read("<path d='M0 0 C1 1 2 1 3 0 C2 -1 1 -1 0 0'/>").unwrap();
        assert!(d.paths[0].closed);
        assert_eq!(d.paths[0].joints.len(), 2);
        assert!(d.source.as_ref().unwrap().is_closed_without_z(0));
        // Ending near, but not exactly on, the start leaves the subpath open.
        let open = read("<path d='M0 0 C1 1 2 1 3 0 C2 -1 1 -1 0 0.001'/>").unwrap();
        assert!(!open.paths[0].closed);
        assert!(!open.source.as_ref().unwrap().is_closed_without_z(0));
        let with_z = read("<path d='M0 0 C1 1 2 1 3 0 C2 -1 1 -1 0 0 Z'/>").unwrap();
        assert!(with_z.paths[0].closed);
        assert!(!with_z.source.as_ref().unwrap().is_closed_without_z(0));
    }

    #[test]
    fn svg_in_close_snap_absorbs_float_noise() {
        let mut pts = vec![
            Point::new(0.0, 0.0),
            Point::new(1.0, 0.0),
            Point::new(2.0, 0.0),
            Point::new(3.0, 0.0),
            Point::new(3.0, 1.0),
            Point::new(0.0, 1.0),
            Point::new(1e-9, 0.0),
        ];
        close_subpath(&mut pts);
        assert_eq!(pts.len(), 7);
        assert_eq!(pts[6], pts[0]);
    }

    #[test]
    fn svg_in_transform_validation_rejects_non_finite() {
        assert!(check_transform("translate(1e999 0)").is_err());
        assert!(check_transform("rotate(30) scale(2)").is_ok());
        assert!(check_transform("rotate(30").is_err());
        // Finite but beyond MAX_COORDINATE: usvg would drop the element in f32.
        assert!(check_transform("scale(1e300)").is_err());
        assert!(check_transform("matrix(1 0 0 1 0 2e9)").is_err());
        assert!(check_transform("translate(1e9 -1e9)").is_ok());
    }

    #[test]
    fn svg_in_points_validation() {
        assert!(check_points("0,0 1,1").is_ok());
        assert!(check_points("0,0 1").is_err());
        assert!(check_points("0,0 1,x").is_err());
    }

    #[test]
    fn svg_in_f64_path_data_has_usvg_structure() {
        for d in [
            "M0 0 L1 1",
            "M0 0 Z Z L1 1 Z",
            "M1 1 M2 2 L3 3 M4 4",
            "M0 0 L1 1 Z L2 2",
            "m1 1 h2 v2 s1 1 2 0 t2 0 q1 1 2 2 z m3 3 l1 0",
            "M10 0 A10 10 0 1 0 0 10 A3 7 30 0 1 5 5 A0 0 0 0 1 6 6",
            "M0.1 0.2 C0.3 0.4 0.5 0.6 0.7 0.8",
        ] {
            let text = svg(&format!("<path id='p' d='{d}'/>"));
            let tree = usvg::Tree::from_str(&text, &usvg_options()).unwrap();
            let Some(usvg::Node::Path(p)) = tree.node_by_id("p") else {
                panic!("{d}: no path");
            };
            let ours = segments_of_path_data(d);
            let theirs = segments_of_usvg(p.data());
            assert!(same_structure(&ours, &theirs), "{d}:\n{ours:?}\n{theirs:?}");
        }
    }

    #[test]
    fn svg_in_prefix_avoids_existing_ids() {
        let text = svg("<path id='splineskin-0' d='M0 0 L1 1'/>");
        let doc = parse_xml(&text, "t").unwrap();
        assert_eq!(unique_prefix(&doc), "splineskin-x");
    }
}
