//! The record an import keeps of its source document ([`SvgSource`]): the original text, and for
//! every imported element (or `use` instance of one) its kind, place in the text, local → root
//! map, paint and the [`Drawing::paths`](super::Drawing::paths) it produced; also the document's size and viewBox.
//!
//! The record is plain data: `splineskin_svg` fills it when it reads a document and reads it
//! when it writes deformed geometry back into the same text; the model keeps it so that a
//! [`Drawing`](super::Drawing) carries its document wherever it goes.

use std::ops::Range;

use kurbo::{Affine, Rect, Size};

use super::PathRole;

/// The kind of a geometry element.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum ElementKind {
    /// `<path>`.
    Path,
    /// `<rect>`.
    Rect,
    /// `<circle>`.
    Circle,
    /// `<ellipse>`.
    Ellipse,
    /// `<line>`.
    Line,
    /// `<polyline>`.
    Polyline,
    /// `<polygon>`.
    Polygon,
}

impl ElementKind {
    /// The element's tag name.
    pub fn tag(self) -> &'static str {
        match self {
            ElementKind::Path => "path",
            ElementKind::Rect => "rect",
            ElementKind::Circle => "circle",
            ElementKind::Ellipse => "ellipse",
            ElementKind::Line => "line",
            ElementKind::Polyline => "polyline",
            ElementKind::Polygon => "polygon",
        }
    }

    /// The kind of a tag name, if it is a geometry element.
    pub fn from_tag(tag: &str) -> Option<ElementKind> {
        Some(match tag {
            "path" => ElementKind::Path,
            "rect" => ElementKind::Rect,
            "circle" => ElementKind::Circle,
            "ellipse" => ElementKind::Ellipse,
            "line" => ElementKind::Line,
            "polyline" => ElementKind::Polyline,
            "polygon" => ElementKind::Polygon,
            _ => return None,
        })
    }

    /// The attributes that hold this kind's geometry (replaced by `d` on export).
    pub fn geometry_attributes(self) -> &'static [&'static str] {
        match self {
            ElementKind::Path => &["d"],
            ElementKind::Rect => &["x", "y", "width", "height", "rx", "ry"],
            ElementKind::Circle => &["cx", "cy", "r"],
            ElementKind::Ellipse => &["cx", "cy", "rx", "ry"],
            ElementKind::Line => &["x1", "y1", "x2", "y2"],
            ElementKind::Polyline | ElementKind::Polygon => &["points"],
        }
    }
}

/// One imported element (or one instance of it through `use`).
#[derive(Clone, Debug)]
pub struct ImportedElement {
    /// Where it is in the original text (byte offsets of the `use` chain and of the element).
    pub key: ElementKey,
    /// Its kind.
    pub kind: ElementKind,
    /// `tag#id (line n)`, with `in use#… (line m)` for instances.
    pub label: String,
    /// Byte range of the element in the original text.
    pub range: Range<usize>,
    /// Its local coordinates (those of its `d` or shape attributes) → root user space.
    pub local_to_root: Affine,
    /// The indices of [`Drawing::paths`](super::Drawing::paths) it produced.
    pub paths: Range<usize>,
    /// What its paths are in the document (hidden, clip geometry, …).
    pub role: PathRole,
    /// For a `<path>` element outside `use` copies: its position among the document's `<path>`
    /// elements (SVG namespace or none), in document order, wherever they are (`defs`, clip
    /// paths, hidden layers). The paper authors' editor numbers paths this way.
    pub path_tag_index: Option<usize>,
    /// Whether it is filled but its fill covers no area at rest: every subpath's chain points
    /// lie on one line (within `splineskin_svg::svg_in::ZERO_AREA` of its size), e.g. an open path of straight
    /// segments back and forth, or a `<line>`. Export writes `fill: none` on it, so that the
    /// deformed (bent) geometry does not show a fill that was invisible.
    pub zero_area_fill: bool,
    /// What it paints with, as usvg resolved it (styles, CSS, inheritance): whether it has a
    /// fill, its stroke width in local units (none without a stroke), and the ids of the
    /// gradients or patterns of its fill and stroke (`splineskin_svg::follow` carries user-space ones
    /// with the deformation).
    pub paint: ElementPaint,
}

/// The paint of an imported element ([`ImportedElement::paint`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ElementPaint {
    /// Whether it is filled.
    pub filled: bool,
    /// Whether its fill rule is `evenodd` (`nonzero` otherwise, SVG's default).
    pub even_odd: bool,
    /// Its stroke width in its local units, when stroked.
    pub stroke_width: Option<f64>,
    /// The id of the gradient or pattern of its fill, if any.
    pub fill_server: Option<String>,
    /// The id of the gradient or pattern of its stroke, if any.
    pub stroke_server: Option<String>,
}

/// Where an element is: the byte offsets, in the original text, of the `use` elements it is
/// instantiated through (outermost first; empty for the element itself) and of the element.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct ElementKey {
    /// Offsets of the `use` chain, outermost first.
    pub uses: Vec<usize>,
    /// Offset of the element (`<` of its start tag).
    pub element: usize,
}

/// What is kept of the source document to write deformed geometry back into it: the original
/// text, and for every imported element (or `use` instance of one) its kind, byte range, local
/// → root transform and the [`Drawing::paths`](super::Drawing::paths) it produced. Also the document's size and
/// viewBox, for rendering.
#[derive(Clone, Debug)]
pub struct SvgSource {
    /// The file name (or `"<svg text>"`), for messages.
    pub origin: String,
    /// The text, as given, or as a browser reads it where the import rewrote what usvg would
    /// read otherwise ([`SvgSource::warnings`] says what); not the id-injected one usvg saw.
    pub text: String,
    /// Imported elements, in the order of their first path.
    pub elements: Vec<ImportedElement>,
    /// For each path of the drawing, the index of its element in `elements`.
    pub path_elements: Vec<usize>,
    /// For each path of the drawing, whether it is closed without a `Z` in the source (its
    /// last point returns exactly to its first): export then writes no `Z` either.
    pub closed_without_z: Vec<bool>,
    /// The root viewport size (usvg's resolution of `width`/`height`).
    pub size: Size,
    /// The root viewBox (`0 0 width height` when absent).
    pub view_box: Rect,
    /// `<clipPath clipPathUnits="objectBoundingBox">` elements whose geometry was imported:
    /// the byte offset of the `<clipPath>` and its content → referencing user space map
    /// (its `transform` times the rest bounding-box map). Export rewrites them in
    /// `userSpaceOnUse` units with that map as their `transform`, so that the deformed
    /// geometry does not move again with the deformed element's bounding box.
    pub bbox_clips: Vec<(usize, Affine)>,
    /// What the import read other than written, as sentences naming the file and element:
    /// invalid attribute values ignored and CSS units resolved as browsers do, entities
    /// expanded, path data and `points` drawn up to their first error. `text` is the document
    /// as read (entities expanded, those values rewritten), so it draws the same everywhere.
    pub warnings: Vec<String>,
}

impl SvgSource {
    /// The file the document came from (or `"<svg text>"`).
    pub fn origin(&self) -> &str {
        &self.origin
    }

    /// The original text of the document.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// Number of imported elements (a `use` instance of an element counts separately).
    pub fn n_elements(&self) -> usize {
        self.elements.len()
    }

    /// Number of paths the document produced (`Drawing::paths.len()` at import).
    pub fn n_paths(&self) -> usize {
        self.path_elements.len()
    }

    /// Whether path `path_index` is closed although its source subpath has no `Z` (it ends
    /// exactly where it starts); `false` if out of range.
    pub fn is_closed_without_z(&self, path_index: usize) -> bool {
        self.closed_without_z
            .get(path_index)
            .copied()
            .unwrap_or(false)
    }

    /// The role of path `path_index` in the document ([`PathRole`]); `Visible` if out of
    /// range.
    pub fn path_role(&self, path_index: usize) -> PathRole {
        self.element_of_path(path_index)
            .map_or(PathRole::Visible, |e| self.elements[e].role)
    }

    /// Where path `path_index` comes from in the numbering of the paper authors' editor:
    /// `(k, s)` when it is subpath `s` (0-based, among the subpaths with at least one segment)
    /// of the document's `k`-th `<path>` element (0-based, document order, every `<path>`
    /// counted: hidden ones, those in `defs` and clip paths). `None` for other shapes, `use`
    /// copies and out-of-range indices.
    pub fn path_tag_position(&self, path_index: usize) -> Option<(usize, usize)> {
        let e = &self.elements[self.element_of_path(path_index)?];
        Some((e.path_tag_index?, path_index - e.paths.start))
    }

    /// The index of the element that produced path `path_index`, if in range.
    pub fn element_of_path(&self, path_index: usize) -> Option<usize> {
        self.path_elements.get(path_index).copied()
    }

    /// The kind of element `element`, if in range.
    pub fn element_kind(&self, element: usize) -> Option<ElementKind> {
        self.elements.get(element).map(|e| e.kind)
    }

    /// The paths (indices into [`Drawing::paths`](super::Drawing::paths)) element `element` produced, if in range.
    pub fn element_paths(&self, element: usize) -> Option<Range<usize>> {
        self.elements.get(element).map(|e| e.paths.clone())
    }

    /// The map from element `element`'s local coordinates (those of its `d` or shape
    /// attributes) to root user space, if in range.
    pub fn element_local_to_root(&self, element: usize) -> Option<Affine> {
        self.elements.get(element).map(|e| e.local_to_root)
    }

    /// A human-readable name of the element that produced path `path_index`, for messages:
    /// `path#leaf (line 12)`, `rect (line 3) in use#u1 (line 9)` for a `use` instance, or
    /// `path index 7 (no such path)` when out of range.
    pub fn element_label(&self, path_index: usize) -> String {
        match self.element_of_path(path_index) {
            Some(e) => self.elements[e].label.clone(),
            None => format!("path index {path_index} (no such path)"),
        }
    }

    /// The root viewport size in pixels, as resolved by usvg from `width`/`height`/`viewBox`.
    pub fn size(&self) -> Size {
        self.size
    }

    /// The root viewBox, in root user units (`0 0 width height` when the root has none): the
    /// frame the drawing's coordinates are in.
    pub fn view_box(&self) -> Rect {
        self.view_box
    }
}
