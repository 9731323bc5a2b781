//! Text to outlines: every `<text>` element of a document replaced by `<path>` elements
//! holding its glyph outlines, before the document is imported
//! ([`crate::svg_in::TextMode::Outlines`]).
//!
//! usvg lays the text out with the font of [`crate::fonts`] (DejaVu Sans, whatever family the
//! text names) exactly as [`crate::render`] draws it, and gives each text span's glyph
//! outlines, and each decoration line (underline, overline, line-through), as one path in the
//! text element's own coordinates (inside its `transform`). Each such path is written with its
//! outlines as `d` (TrueType quadratics as `Q`, which the import elevates exactly to cubics, as
//! for any path) and its resolved paint as an inline `style`: `fill`, `fill-opacity`,
//! `fill-rule`, `stroke`, `stroke-width`, `stroke-opacity`, line caps and joins, miter limit,
//! dashes, `paint-order` and `visibility`. A gradient or pattern is written as `url(#id)` when
//! that id is in the document; otherwise (usvg's copy of an `objectBoundingBox` paint server
//! for the text's box) the property is left to inherit from the element, so the paint is then
//! mapped onto the box of the outlines rather than that of the text.
//!
//! The replacement carries the text element's own attributes but its layout ones (`x y dx dy
//! rotate textLength lengthAdjust`, font and text properties): its `id`, `class`, `style`
//! (followed by the resolved paint, which wins), `transform`, `opacity`, `clip-path`, `mask`,
//! `filter`, `display`, … When all paths have the same paint (one span, no decoration) it is
//! one `<path>`; otherwise a `<g>` with one `<path>` per span. Inside a `<clipPath>` (where a
//! group is not allowed, and only geometry counts) it is always one `<path>`. The replacement
//! takes as many lines as the element did, so that line numbers in messages still point into
//! the user's file.
//!
//! **What is lost**: the string itself. The outlines cannot be edited as text, searched,
//! selected, read by screen readers or re-flowed, a different font can no longer be chosen,
//! and a viewer with the intended font installed shows DejaVu Sans shapes. Text that usvg
//! cannot lay out (no character of it in DejaVu Sans) or that declares XML namespaces on its
//! own start tag is kept as text, with a `tracing` warning; empty text is kept as it is.
//!
//! A text not drawn where it stands (drawn through `use` or a marker, unused in `<defs>`, in a
//! `<switch>` branch not taken: its conditional attributes are carried) is laid out on its
//! own, at the end of the document: properties it would inherit from a `use` (a `fill` set on
//! the `use`) are not applied to its outlines, which carry the paint of the document's root
//! instead.

use std::collections::{HashMap, HashSet};
use std::fmt::Write as _;

use crate::document::{check_size, parse_xml, SvgError, MAX_SVG_BYTES, SHOW_HIDDEN_CSS};
use crate::document::{is_svg_element, outermost_texts};

/// Attributes of `<text>` that only lay text out: not carried to its outlines.
const LAYOUT_ATTRIBUTES: &[&str] = &[
    "x",
    "y",
    "dx",
    "dy",
    "rotate",
    "textLength",
    "lengthAdjust",
    "font",
    "font-family",
    "font-size",
    "font-size-adjust",
    "font-stretch",
    "font-style",
    "font-variant",
    "font-weight",
    "font-kerning",
    "letter-spacing",
    "word-spacing",
    "text-anchor",
    "text-decoration",
    "text-rendering",
    "writing-mode",
    "direction",
    "unicode-bidi",
    "dominant-baseline",
    "alignment-baseline",
    "baseline-shift",
    "glyph-orientation-horizontal",
    "glyph-orientation-vertical",
];

/// Conditional processing attributes (SVG 1.1 §5.8): dropped from the copy of a text laid
/// out on its own, so that a `<switch>` branch not taken is laid out too.
const CONDITIONS: &[&str] = &["systemLanguage", "requiredFeatures", "requiredExtensions"];

/// One outline path of a text: its path data (text coordinates) and resolved paint.
struct Outline {
    d: String,
    style: String,
}

/// The SVG document `text` with every `<text>` element replaced by `<path>` elements of its
/// glyph outlines (module doc); the document as it is when it has no text laid out. `origin`
/// names the document in errors and warnings.
///
/// This is what [`crate::svg_in::TextMode::Outlines`] does before the import; a scene's SVG
/// text can be converted with it before the scene is set up.
///
/// Errors: [`SvgError::TooLarge`] above [`MAX_SVG_BYTES`], [`SvgError::Xml`] for text that is
/// not well-formed XML.
///
/// ```
/// use splineskin_svg::text_outlines::text_to_outlines;
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 60 20">
///   <text x="2" y="16" font-size="16" stroke="red">A<tspan fill="blue">b</tspan></text></svg>"#;
/// let out = text_to_outlines(svg, "label.svg").unwrap();
/// assert!(!out.contains("<text"), "{out}");
/// // Two spans of different paint: a group of two paths, stroke inherited by both.
/// assert!(out.contains(r#"<g stroke="red"><path d="M"#), "{out}");
/// assert_eq!(out.matches("stroke:#ff0000").count(), 2, "{out}");
/// assert!(out.contains("fill:#0000ff"), "{out}");
/// ```
pub fn text_to_outlines(text: &str, origin: &str) -> Result<String, SvgError> {
    check_size(origin, text.len() as u64)?;
    Ok(outline_text(text, origin)?.unwrap_or_else(|| text.to_string()))
}

/// `text` with every `<text>` element replaced by its outlines (module doc), or `None` when
/// there is nothing to replace (no text laid out, or a document above [`MAX_SVG_BYTES`], which
/// the import refuses anyway).
pub(crate) fn outline_text(text: &str, origin: &str) -> Result<Option<String>, SvgError> {
    if text.len() > MAX_SVG_BYTES || !text.contains("text") {
        return Ok(None);
    }
    let doc = parse_xml(text, origin)?;
    let texts: Vec<roxmltree::Node> = outermost_texts(&doc).collect();
    if texts.is_empty() {
        return Ok(None);
    }
    if !crate::fonts::HAS_FONTS {
        return Err(SvgError::Unsupported {
            file: origin.to_string(),
            element: "<text>".to_string(),
            what: "text to outlines needs fonts, and this build has none (the WebAssembly \
                   build leaves them out: keep the text as text, or convert it with the \
                   command-line tool)"
                .to_string(),
        });
    }

    let ids: HashSet<&str> = doc
        .descendants()
        .filter_map(|n| n.attribute("id"))
        .collect();
    let mut prefix = String::from("splineskin-text-");
    while ids.iter().any(|id| id.starts_with(&prefix)) {
        prefix.push('x');
    }
    let (prepared, text_ids) = with_text_ids(text, &doc, &texts, &prefix);
    let index: HashMap<&str, usize> = text_ids
        .iter()
        .enumerate()
        .map(|(k, id)| (id.as_str(), k))
        .collect();
    let mut outlines: Vec<Option<Vec<Outline>>> = (0..texts.len()).map(|_| None).collect();
    read_outlines(
        &prepared,
        &index,
        crate::fonts::usvg_options(false),
        &ids,
        &mut outlines,
    );
    if outlines.iter().any(Option::is_none) && text.contains("display") {
        // Hidden text (display: none) is laid out too, so that unhiding its layer shows it.
        read_outlines(&prepared, &index, show_hidden(), &ids, &mut outlines);
    }
    if outlines.iter().any(Option::is_none) {
        lay_out_undrawn(text, &doc, &texts, &prepared, &prefix, &ids, &mut outlines);
    }
    let edits = outline_edits(text, &doc, &texts, outlines, origin);
    if edits.is_empty() {
        return Ok(None);
    }
    Ok(Some(splice(text, edits)))
}

/// `text` with an id usvg keeps on every text of `texts`: its own when it is the first
/// element with it, else a fresh one (`prefix` and its number; in the copy usvg reads only);
/// and each text's id.
fn with_text_ids(
    text: &str,
    doc: &roxmltree::Document,
    texts: &[roxmltree::Node],
    prefix: &str,
) -> (String, Vec<String>) {
    let mut first_owner: HashMap<&str, roxmltree::NodeId> = HashMap::new();
    for n in doc.descendants() {
        if let Some(id) = n.attribute("id") {
            first_owner.entry(id).or_insert(n.id());
        }
    }
    let mut edits: Vec<(usize, usize, String)> = Vec::new();
    let mut text_ids: Vec<String> = Vec::new();
    for (k, node) in texts.iter().enumerate() {
        let own = node
            .attribute("id")
            .filter(|id| first_owner.get(id) == Some(&node.id()));
        match own {
            Some(id) => text_ids.push(id.to_string()),
            None => {
                let id = format!("{prefix}{k}");
                edits.push(id_edit(text, *node, &id));
                text_ids.push(id);
            }
        }
    }
    (splice(text, edits), text_ids)
}

/// usvg's options with every element shown (`display: none` overridden).
fn show_hidden() -> usvg::Options<'static> {
    usvg::Options {
        style_sheet: Some(SHOW_HIDDEN_CSS.to_string()),
        ..crate::fonts::usvg_options(false)
    }
}

/// Lays `document` out with `options` and records the outlines of the texts whose ids `index`
/// maps (a document usvg refuses records nothing).
fn read_outlines(
    document: &str,
    index: &HashMap<&str, usize>,
    options: usvg::Options,
    ids: &HashSet<&str>,
    outlines: &mut [Option<Vec<Outline>>],
) {
    if let Ok(tree) = usvg::Tree::from_str(document, &options) {
        collect_texts(tree.root(), index, ids, outlines);
    }
}

/// Text not drawn where it is (drawn through `use` or a marker, whose copies lose their ids;
/// unused; a `switch` branch not taken): a copy of it, with an id and without the conditions
/// that kept it from being drawn, placed at the end of `prepared`, is laid out instead.
fn lay_out_undrawn(
    text: &str,
    doc: &roxmltree::Document,
    texts: &[roxmltree::Node],
    prepared: &str,
    prefix: &str,
    ids: &HashSet<&str>,
    outlines: &mut [Option<Vec<Outline>>],
) {
    let end = doc.root_element().range().end;
    let end_tag = text[..end].rfind("</").unwrap_or(end);
    let mut copies = String::new();
    let mut copy_ids = Vec::new();
    for (k, node) in texts.iter().enumerate() {
        if outlines[k].is_none() {
            let id = format!("{prefix}copy{k}");
            let range = node.range();
            let mut edits = vec![id_edit(text, *node, &id)];
            for a in node
                .attributes()
                .filter(|a| a.namespace().is_none() && CONDITIONS.contains(&a.name()))
            {
                edits.push((a.range().start, a.range().end, String::new()));
            }
            let shifted = edits
                .into_iter()
                .map(|(from, to, t)| (from - range.start, to - range.start, t))
                .collect();
            copies.push_str(&splice(&text[range.clone()], shifted));
            copy_ids.push((id, k));
        }
    }
    // Every edit of `prepared` lies before the root's end tag: what follows is the same.
    let at = prepared.len() - (text.len() - end_tag);
    let with_copies = splice(prepared, vec![(at, at, copies)]);
    let index: HashMap<&str, usize> = copy_ids.iter().map(|(id, k)| (id.as_str(), *k)).collect();
    read_outlines(&with_copies, &index, show_hidden(), ids, outlines);
}

/// The edits of `text` replacing each of `texts` laid out (`outlines`) by its paths; a text
/// declaring namespaces on itself or not laid out is kept, with a warning.
fn outline_edits(
    text: &str,
    doc: &roxmltree::Document,
    texts: &[roxmltree::Node],
    outlines: Vec<Option<Vec<Outline>>>,
    origin: &str,
) -> Vec<(usize, usize, String)> {
    let mut edits = Vec::new();
    for (node, outline) in texts.iter().zip(outlines) {
        let label = crate::document::node_label(doc, *node);
        let start_tag = &text[node.range().start..node.range().end];
        let start_tag = &start_tag[..start_tag.find('>').unwrap_or(start_tag.len())];
        if start_tag.contains("xmlns") {
            // Namespace declarations are not attributes to roxmltree: they could not be
            // carried, and prefixes they declare would be left unbound.
            tracing::warn!(
                file = origin,
                element = %label,
                "this text declares XML namespaces on itself; it is kept as text"
            );
            continue;
        }
        match outline {
            Some(paths) if !paths.is_empty() => {
                edits.push((
                    node.range().start,
                    node.range().end,
                    replacement(text, *node, &paths),
                ));
            }
            Some(_) => {}
            None => tracing::warn!(
                file = origin,
                element = %label,
                "this text is not laid out (not rendered, or no glyph of it in DejaVu Sans); \
                 it is kept as text"
            ),
        }
    }
    edits
}

/// The edit of `src` that gives the element `node` the id `id`: its `id` attribute's value
/// replaced, or the attribute added after its name.
fn id_edit(src: &str, node: roxmltree::Node, id: &str) -> (usize, usize, String) {
    match node
        .attributes()
        .find(|a| a.namespace().is_none() && a.name() == "id")
    {
        Some(a) => (a.range_value().start, a.range_value().end, id.to_string()),
        None => {
            let at = node.range().start + 1 + qualified_name(src, node).len();
            (at, at, format!(" id=\"{id}\""))
        }
    }
}

/// The qualified name of `node`'s start tag as written (`text`, `svg:text`).
fn qualified_name<'t>(src: &'t str, node: roxmltree::Node) -> &'t str {
    let start = node.range().start + 1;
    let end = src[start..]
        .find(|c: char| c.is_ascii_whitespace() || c == '/' || c == '>')
        .map_or(src.len(), |i| start + i);
    &src[start..end]
}

/// `src` with the non-overlapping byte ranges of `edits` replaced.
fn splice(src: &str, mut edits: Vec<(usize, usize, String)>) -> String {
    edits.sort_by_key(|e| (e.0, e.1));
    let mut out = String::with_capacity(src.len());
    let mut cursor = 0;
    for (from, to, text) in edits {
        out.push_str(&src[cursor..from]);
        out.push_str(&text);
        cursor = to;
    }
    out.push_str(&src[cursor..]);
    out
}

/// Records, for every text node below `group` (clip paths, masks and patterns included)
/// whose id is in `index` and not yet recorded, its outline paths.
fn collect_texts(
    group: &usvg::Group,
    index: &HashMap<&str, usize>,
    ids: &HashSet<&str>,
    out: &mut [Option<Vec<Outline>>],
) {
    for node in group.children() {
        match node {
            usvg::Node::Group(g) => collect_texts(g, index, ids, out),
            usvg::Node::Text(t) => {
                if let Some(&k) = index.get(t.id()) {
                    if out[k].is_none() {
                        let mut paths = Vec::new();
                        outline_paths(t.flattened(), usvg::Transform::identity(), ids, &mut paths);
                        out[k] = Some(paths);
                    }
                }
            }
            _ => {}
        }
        node.subroots(|g| collect_texts(g, index, ids, out));
    }
}

/// The paths of a text's flattened group, in the text's coordinates (`ts`: the groups between).
fn outline_paths(
    group: &usvg::Group,
    ts: usvg::Transform,
    ids: &HashSet<&str>,
    out: &mut Vec<Outline>,
) {
    for node in group.children() {
        match node {
            usvg::Node::Group(g) => outline_paths(g, ts.pre_concat(g.transform()), ids, out),
            usvg::Node::Path(p) => {
                let data = if ts.is_identity() {
                    Some(p.data().clone())
                } else {
                    p.data().clone().transform(ts)
                };
                if let Some(data) = data {
                    out.push(Outline {
                        d: path_data(&data),
                        style: paint_style(p, ids),
                    });
                }
            }
            _ => {}
        }
    }
}

/// `d` of a tiny-skia path: `M L Q C Z`, numbers in their shortest `f32` form.
fn path_data(data: &usvg::tiny_skia_path::Path) -> String {
    use usvg::tiny_skia_path::PathSegment as S;
    let mut d = String::new();
    let mut put = |cmd: char, pts: &[usvg::tiny_skia_path::Point]| {
        if !d.is_empty() {
            d.push(' ');
        }
        d.push(cmd);
        for (i, p) in pts.iter().enumerate() {
            let sep = if i == 0 { "" } else { " " };
            let _ = write!(d, "{sep}{} {}", p.x, p.y);
        }
    };
    for segment in data.segments() {
        match segment {
            S::MoveTo(p) => put('M', &[p]),
            S::LineTo(p) => put('L', &[p]),
            S::QuadTo(q, p) => put('Q', &[q, p]),
            S::CubicTo(c1, c2, p) => put('C', &[c1, c2, p]),
            S::Close => put('Z', &[]),
        }
    }
    d
}

/// A paint as a CSS value: `#rrggbb`, `url(#id)` for a paint server the document has, `None`
/// for a paint server usvg made (left to inherit).
fn paint_value(paint: &usvg::Paint, ids: &HashSet<&str>) -> Option<String> {
    let server = match paint {
        usvg::Paint::Color(c) => {
            return Some(format!("#{:02x}{:02x}{:02x}", c.red, c.green, c.blue))
        }
        usvg::Paint::LinearGradient(g) => g.id(),
        usvg::Paint::RadialGradient(g) => g.id(),
        usvg::Paint::Pattern(p) => p.id(),
    };
    ids.contains(server).then(|| format!("url(#{server})"))
}

/// The resolved paint of an outline path as inline CSS declarations (module doc).
fn paint_style(path: &usvg::Path, ids: &HashSet<&str>) -> String {
    let mut s = Vec::new();
    match path.fill() {
        None => s.push("fill:none".to_string()),
        Some(fill) => {
            if let Some(v) = paint_value(fill.paint(), ids) {
                s.push(format!("fill:{v}"));
            }
            s.push(format!("fill-opacity:{}", fill.opacity().get()));
            let rule = match fill.rule() {
                usvg::FillRule::NonZero => "nonzero",
                usvg::FillRule::EvenOdd => "evenodd",
            };
            s.push(format!("fill-rule:{rule}"));
        }
    }
    match path.stroke() {
        None => s.push("stroke:none".to_string()),
        Some(stroke) => {
            if let Some(v) = paint_value(stroke.paint(), ids) {
                s.push(format!("stroke:{v}"));
            }
            s.push(format!("stroke-opacity:{}", stroke.opacity().get()));
            s.push(format!("stroke-width:{}", stroke.width().get()));
            let cap = match stroke.linecap() {
                usvg::LineCap::Butt => "butt",
                usvg::LineCap::Round => "round",
                usvg::LineCap::Square => "square",
            };
            let join = match stroke.linejoin() {
                usvg::LineJoin::Miter => "miter",
                usvg::LineJoin::MiterClip => "miter-clip",
                usvg::LineJoin::Round => "round",
                usvg::LineJoin::Bevel => "bevel",
            };
            s.push(format!("stroke-linecap:{cap}"));
            s.push(format!("stroke-linejoin:{join}"));
            s.push(format!("stroke-miterlimit:{}", stroke.miterlimit().get()));
            match stroke.dasharray() {
                Some(dashes) => {
                    let list: Vec<String> = dashes.iter().map(f32::to_string).collect();
                    s.push(format!("stroke-dasharray:{}", list.join(" ")));
                    s.push(format!("stroke-dashoffset:{}", stroke.dashoffset()));
                }
                None => s.push("stroke-dasharray:none".to_string()),
            }
        }
    }
    // Every property written, even at its initial value: the replacement carries the text's
    // own attributes (`paint-order="stroke"` on the text, say), which must not reach a
    // decoration line that usvg paints differently.
    s.push(match path.paint_order() {
        usvg::PaintOrder::StrokeAndFill => "paint-order:stroke".to_string(),
        usvg::PaintOrder::FillAndStroke => "paint-order:normal".to_string(),
    });
    s.push(
        if path.is_visible() {
            "visibility:visible"
        } else {
            "visibility:hidden"
        }
        .to_string(),
    );
    s.join(";")
}

/// The markup that replaces the text element `node` of `src` (module doc).
fn replacement(src: &str, node: roxmltree::Node, paths: &[Outline]) -> String {
    let qname = qualified_name(src, node);
    let prefix = &qname[..qname.len() - "text".len()];
    let in_clip = node
        .ancestors()
        .any(|a| is_svg_element(a) && a.tag_name().name() == "clipPath");
    let mut attributes = String::new();
    let mut own_style = None;
    for a in node.attributes() {
        let plain = a.namespace().is_none();
        if plain && LAYOUT_ATTRIBUTES.contains(&a.name()) {
            continue;
        }
        if plain && a.name() == "style" {
            own_style = Some(a.value());
            continue;
        }
        if a.namespace() == Some("http://www.w3.org/XML/1998/namespace") && a.name() == "space" {
            continue;
        }
        attributes.push(' ');
        attributes.push_str(&src[a.range()]);
    }
    let lines = "\n".repeat(src[node.range()].matches('\n').count());
    let style_with = |paint: &str| {
        let own = own_style.unwrap_or("").trim().trim_end_matches(';').trim();
        let sep = if own.is_empty() || paint.is_empty() {
            ""
        } else {
            ";"
        };
        escape(&format!("{own}{sep}{paint}"))
    };
    let same_paint = paths.iter().all(|p| p.style == paths[0].style);
    if in_clip || same_paint {
        let d: Vec<&str> = paths.iter().map(|p| p.d.as_str()).collect();
        let paint = if in_clip { "" } else { &paths[0].style };
        let style = style_with(paint);
        let style = if style.is_empty() {
            String::new()
        } else {
            format!(" style=\"{style}\"")
        };
        format!(
            "<{prefix}path{attributes} d=\"{}\"{style}{lines}/>",
            d.join(" ")
        )
    } else {
        let mut out = format!("<{prefix}g{attributes}");
        if let Some(own) = own_style {
            let _ = write!(out, " style=\"{}\"", escape(own));
        }
        out.push('>');
        for p in paths {
            let _ = write!(
                out,
                "<{prefix}path d=\"{}\" style=\"{}\"/>",
                p.d,
                escape(&p.style)
            );
        }
        let _ = write!(out, "{lines}</{prefix}g>");
        out
    }
}

/// Escapes an attribute value for double quotes.
fn escape(value: &str) -> String {
    value
        .replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{read_svg, ImportOptions, TextMode};

    const NS: &str = "xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 100 100\"";

    #[test]
    fn text_outlines_keep_line_numbers() {
        let svg = format!(
            "<svg {NS}>\n<text x=\"5\" y=\"30\"\n  font-size=\"20\">\n  Two\n</text>\n\
             <path id=\"after\" d=\"M0 90 L90 90\"/></svg>"
        );
        let options = ImportOptions::default().with_text(TextMode::Outlines);
        let drawing = read_svg(&svg, &options).unwrap();
        let source = drawing.source.as_ref().unwrap();
        let last = drawing.paths.len() - 1;
        assert_eq!(source.element_label(last), "path#after (line 6)");
        assert_eq!(source.element_label(0), "path (line 2)");
        assert_eq!(source.text().lines().count(), svg.lines().count());
    }

    #[test]
    fn text_outlines_of_switch_branches_keep_their_conditions() {
        let svg = format!(
            "<svg {NS}><switch><text systemLanguage=\"xx\" x=\"5\" y=\"30\">A</text>\
             <text x=\"5\" y=\"60\">B</text></switch></svg>"
        );
        let out = text_to_outlines(&svg, "t").unwrap();
        assert!(!out.contains("<text"), "{out}");
        assert!(
            out.contains("<switch><path systemLanguage=\"xx\" d=\"M"),
            "{out}"
        );
    }

    #[test]
    fn text_outlines_leave_text_declaring_namespaces_and_empty_text() {
        let svg = format!(
            "<svg {NS}><text xmlns:a=\"urn:a\" a:b=\"c\" x=\"5\" y=\"30\">A</text>\
             <text x=\"5\" y=\"60\"> </text></svg>"
        );
        assert_eq!(text_to_outlines(&svg, "t").unwrap(), svg);
    }

    #[test]
    fn text_outlines_refuse_what_the_import_refuses() {
        assert!(matches!(
            text_to_outlines("<svg><text>", "bad.svg"),
            Err(SvgError::Xml { .. })
        ));
    }
}
