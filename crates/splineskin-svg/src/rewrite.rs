//! The document rewriter shared by import (id injection, `use` expansion, hidden layers shown)
//! and export (deformed geometry spliced into the same text): [`rewrite_document`] copies the
//! source text element by element and lets a [`RewritePolicy`] edit geometry elements and
//! attributes; everything else is copied byte for byte.

use std::collections::HashMap;
use std::fmt::Write as _;

use kurbo::{Affine, Size};
use splineskin_core::drawing::source::{ElementKey, ElementKind};

use crate::document::{
    is_svg_element, node_label, number, user_length, SvgError, MAX_SVG_BYTES, XLINK_NS, XML_NS,
};

/// Deepest chain of `use` elements expanded (a `use` in content referenced by a `use` …): 32.
pub const MAX_USE_DEPTH: usize = 32;

/// Largest text the rewriter produces (expanding `use` elements copies content): four times
/// [`MAX_SVG_BYTES`]. Guards against exponential `use` nesting.
pub const MAX_EXPANDED_BYTES: usize = 4 * MAX_SVG_BYTES;

/// A copy of a resource element (a paint server or a marker).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct CopyEdit {
    /// Attributes set on the copy (its new `id` first).
    pub(crate) set: AttributeSet,
    /// Text written as the copy's first content (its animation).
    pub(crate) content: Option<String>,
    /// Text written right after the copy (its animation, when it must not be a child: a pattern
    /// without children inherits its template's, and a child would stop that).
    pub(crate) after: Option<String>,
}

/// Attributes set on a copy: (name, value).
pub(crate) type AttributeSet = Vec<(&'static str, String)>;

/// What the rewriter does to a geometry element.
pub(crate) enum GeometryEdit {
    /// Write it as it is (ids still removed inside copies).
    Keep,
    /// Set its `id` (replacing one, or adding it).
    SetId(String),
    /// Make it a `<path>` with this `d`, if given this text as its first content, and with
    /// these attributes (name, value) set.
    ToPath(String, Option<String>, Vec<(&'static str, String)>),
}

/// The decisions that differ between preparing the import text and exporting.
pub(crate) trait RewritePolicy {
    /// The edit of the geometry element at `key` (`in_copy`: inside an expanded `use`).
    fn geometry(
        &mut self,
        key: &ElementKey,
        node: roxmltree::Node,
        in_copy: bool,
    ) -> Result<GeometryEdit, SvgError>;
    /// Whether the `use` instance `instance` (its `use` chain, outermost first) is expanded.
    fn expand_use(&mut self, instance: &[usize]) -> bool;
    /// Attributes to set on `node` (any element; `in_copy`: inside an expanded `use`),
    /// beyond its geometry edit. Default: none.
    fn attributes(&mut self, node: roxmltree::Node, in_copy: bool) -> Vec<(&'static str, String)> {
        let _ = (node, in_copy);
        Vec::new()
    }
    /// Copies of `node` (outside `use` copies) to write right after it, each with its
    /// attributes set (ids inside removed) and content added. Default: none.
    fn copies(&mut self, node: roxmltree::Node) -> Vec<CopyEdit> {
        let _ = node;
        Vec::new()
    }
    /// Text written as the first content of `node`, a non-geometry element (`in_copy`: inside
    /// an expanded `use`). Default: none.
    fn content(&mut self, node: roxmltree::Node, in_copy: bool) -> Option<String> {
        let _ = (node, in_copy);
        None
    }
}

/// The mapping of `view_box` onto a `width × height` viewport under `aspect`
/// (SVG 1.1 §7.8, as usvg's `ViewBox::to_transform`).
pub(crate) fn view_box_transform(
    view_box: svgtypes::ViewBox,
    aspect: svgtypes::AspectRatio,
    width: f64,
    height: f64,
) -> Affine {
    use svgtypes::Align as A;
    let (mut sx, mut sy) = (width / view_box.w, height / view_box.h);
    if aspect.align != A::None {
        let s = if aspect.slice { sx.max(sy) } else { sx.min(sy) };
        (sx, sy) = (s, s);
    }
    let (x, y) = (-view_box.x * sx, -view_box.y * sy);
    let (w, h) = (width - view_box.w * sx, height - view_box.h * sy);
    let (tx, ty) = match aspect.align {
        A::None | A::XMinYMin => (x, y),
        A::XMidYMin => (x + w / 2.0, y),
        A::XMaxYMin => (x + w, y),
        A::XMinYMid => (x, y + h / 2.0),
        A::XMidYMid => (x + w / 2.0, y + h / 2.0),
        A::XMaxYMid => (x + w, y + h / 2.0),
        A::XMinYMax => (x, y + h),
        A::XMidYMax => (x + w / 2.0, y + h),
        A::XMaxYMax => (x + w, y + h),
    };
    Affine::new([sx, 0.0, 0.0, sy, tx, ty])
}

/// Escapes an attribute value for either quote style.
fn escape_attribute(value: &str) -> String {
    let mut s = String::with_capacity(value.len());
    for c in value.chars() {
        match c {
            '&' => s.push_str("&amp;"),
            '<' => s.push_str("&lt;"),
            '"' => s.push_str("&quot;"),
            '\'' => s.push_str("&apos;"),
            _ => s.push(c),
        }
    }
    s
}

/// Rewrites `src` (parsed as `doc`) under `policy`: geometry elements get the policy's edit,
/// `use` elements outside clip paths are expanded when the policy says so, ids are removed
/// inside expanded copies. With `wrap_root`, the root's content is wrapped in
/// `<g id="wrap_root">`. `viewport` is the root viewport in user units (percentages in `use`
/// lengths).
pub(crate) fn rewrite_document<P: RewritePolicy>(
    src: &str,
    doc: &roxmltree::Document,
    policy: &mut P,
    origin: &str,
    wrap_root: Option<&str>,
    viewport: Size,
) -> Result<String, SvgError> {
    let mut ids = HashMap::new();
    for n in doc.descendants() {
        if let Some(id) = n.attribute("id") {
            ids.entry(id).or_insert(n);
        }
    }
    let root = doc.root_element();
    let mut w = Rewriter {
        src,
        doc,
        ids,
        policy,
        origin,
        viewport,
        out: String::with_capacity(src.len() + src.len() / 8),
    };
    let range = root.range();
    w.out.push_str(&src[..range.start]);
    let mut spec = TagSpec::default();
    spec.set.extend(w.policy.attributes(root, false));
    w.write_with(root, &spec, &Context::default(), wrap_root)?;
    w.out.push_str(&src[range.end..]);
    Ok(w.out)
}

/// The edits of one start tag.
#[derive(Default)]
struct TagSpec<'s> {
    /// New local name (the prefix is kept).
    rename: Option<&'s str>,
    /// Attributes (no namespace) to remove.
    remove: &'s [&'s str],
    /// Whether `id` and `xml:id` are removed.
    strip_ids: bool,
    /// Attributes (no namespace) to set: replaced if present, else added.
    set: Vec<(&'s str, String)>,
    /// Text written as the element's first content (a self-closing element gets an end tag).
    child: Option<String>,
}

/// Where the rewriter is.
#[derive(Clone, Default)]
struct Context {
    /// The `use` chain of the current copy (byte offsets, outermost first).
    uses: Vec<usize>,
    /// The elements referenced along that chain (recursion guard).
    targets: Vec<roxmltree::NodeId>,
    /// Inside an expanded copy.
    in_copy: bool,
    /// Inside a `clipPath` (its `use` children must stay `use`).
    in_clip: bool,
}

/// The byte positions of an element's tags.
struct TagPositions<'i> {
    /// Just after the start tag's name.
    qname_end: usize,
    /// Just after the start tag's `>`.
    tag_end: usize,
    /// `<… />`.
    self_closing: bool,
    /// The name's prefix with its colon (`""`, or e.g. `"svg:"`).
    prefix: &'i str,
}

struct Rewriter<'a, 'i, P> {
    src: &'i str,
    doc: &'a roxmltree::Document<'i>,
    ids: HashMap<&'a str, roxmltree::Node<'a, 'i>>,
    policy: &'a mut P,
    origin: &'a str,
    viewport: Size,
    out: String,
}

impl<'a, 'i, P: RewritePolicy> Rewriter<'a, 'i, P> {
    fn unsupported(&self, node: roxmltree::Node, what: impl Into<String>) -> SvgError {
        SvgError::Unsupported {
            file: self.origin.to_string(),
            element: node_label(self.doc, node),
            what: what.into(),
        }
    }

    fn write_element(
        &mut self,
        node: roxmltree::Node<'a, 'i>,
        ctx: &Context,
    ) -> Result<(), SvgError> {
        if self.out.len() > MAX_EXPANDED_BYTES {
            return Err(SvgError::TooLarge {
                file: self.origin.to_string(),
                size: self.out.len() as u64,
                limit: MAX_EXPANDED_BYTES as u64,
            });
        }
        let tag = if is_svg_element(node) {
            node.tag_name().name()
        } else {
            ""
        };
        if tag == "use" && !ctx.in_clip {
            return self.write_use(node, ctx);
        }
        let mut spec = TagSpec {
            strip_ids: ctx.in_copy,
            ..TagSpec::default()
        };
        if !tag.is_empty() {
            spec.set.extend(self.policy.attributes(node, ctx.in_copy));
            if ElementKind::from_tag(tag).is_none() {
                spec.child = self.policy.content(node, ctx.in_copy);
            }
        }
        if let Some(kind) = ElementKind::from_tag(tag) {
            let key = ElementKey {
                uses: ctx.uses.clone(),
                element: node.range().start,
            };
            match self.policy.geometry(&key, node, ctx.in_copy)? {
                GeometryEdit::Keep => {}
                GeometryEdit::SetId(id) => spec.set.push(("id", id)),
                GeometryEdit::ToPath(d, child, marker) => {
                    if kind != ElementKind::Path {
                        spec.rename = Some("path");
                        spec.remove = kind.geometry_attributes();
                    }
                    spec.set.push(("d", d));
                    spec.set.extend(marker);
                    spec.child = child;
                }
            }
        }
        if tag == "clipPath" && !ctx.in_clip {
            let inner = Context {
                in_clip: true,
                ..ctx.clone()
            };
            return self.write_with(node, &spec, &inner, None);
        }
        self.write_with(node, &spec, ctx, None)?;
        if !ctx.in_copy && !tag.is_empty() {
            for edit in self.policy.copies(node) {
                let copy = TagSpec {
                    strip_ids: true,
                    set: edit.set,
                    child: edit.content,
                    ..TagSpec::default()
                };
                let inner = Context {
                    in_copy: true,
                    ..ctx.clone()
                };
                self.write_with(node, &copy, &inner, None)?;
                if let Some(after) = &edit.after {
                    self.out.push_str(after);
                }
            }
        }
        Ok(())
    }

    /// Locates the tags of `node` in the source.
    fn positions(&self, node: roxmltree::Node) -> Result<TagPositions<'i>, SvgError> {
        let bytes = self.src.as_bytes();
        let start = node.range().start;
        let entity = || self.unsupported(node, "elements created by DTD entity expansion");
        if bytes.get(start) != Some(&b'<') {
            return Err(entity());
        }
        let mut qname_end = start + 1;
        while qname_end < bytes.len()
            && !matches!(bytes[qname_end], b' ' | b'\t' | b'\r' | b'\n' | b'/' | b'>')
        {
            qname_end += 1;
        }
        let qname = &self.src[start + 1..qname_end];
        let prefix = match qname.rfind(':') {
            Some(i) => &self.src[start + 1..start + 2 + i],
            None => "",
        };
        if &qname[prefix.len()..] != node.tag_name().name() {
            return Err(entity());
        }
        // The start tag ends at the first `>` outside quotes.
        let mut quote = None;
        let mut i = qname_end;
        let tag_end = loop {
            let Some(&c) = bytes.get(i) else {
                return Err(SvgError::Internal {
                    file: self.origin.to_string(),
                    what: format!("unterminated start tag at byte {start}"),
                });
            };
            match quote {
                Some(q) if c == q => quote = None,
                Some(_) => {}
                None if c == b'"' || c == b'\'' => quote = Some(c),
                None if c == b'>' => break i + 1,
                None => {}
            }
            i += 1;
        };
        Ok(TagPositions {
            qname_end,
            tag_end,
            self_closing: bytes[tag_end - 2] == b'/',
            prefix,
        })
    }

    /// Writes the start tag of `node` with `spec`'s edits.
    fn write_start_tag(&mut self, node: roxmltree::Node, spec: &TagSpec, pos: &TagPositions) {
        let bytes = self.src.as_bytes();
        let start = node.range().start;
        let mut edits: Vec<(usize, usize, String)> = Vec::new();
        if let Some(name) = spec.rename {
            edits.push((
                start + 1 + pos.prefix.len(),
                pos.qname_end,
                name.to_string(),
            ));
        }
        let mut done = vec![false; spec.set.len()];
        let mut insert_at = pos.qname_end;
        for a in node.attributes() {
            let r = a.range();
            insert_at = insert_at.max(r.end);
            let plain = a.namespace().is_none();
            if let Some(k) = spec.set.iter().position(|(n, _)| plain && *n == a.name()) {
                if !done[k] {
                    done[k] = true;
                    let v = a.range_value();
                    edits.push((v.start, v.end, escape_attribute(&spec.set[k].1)));
                    continue;
                }
            }
            let is_id = (plain || a.namespace() == Some(XML_NS)) && a.name() == "id";
            if (spec.strip_ids && is_id) || (plain && spec.remove.contains(&a.name())) {
                let mut ws = r.start;
                while ws > pos.qname_end && bytes[ws - 1].is_ascii_whitespace() {
                    ws -= 1;
                }
                edits.push((ws, r.end, String::new()));
            }
        }
        let mut added = String::new();
        for ((name, value), done) in spec.set.iter().zip(&done) {
            if !done {
                let _ = write!(added, " {name}=\"{}\"", escape_attribute(value));
            }
        }
        if !added.is_empty() {
            edits.push((insert_at, insert_at, added));
        }
        edits.sort_by_key(|e| (e.0, e.1));
        let mut cursor = start;
        for (from, to, text) in edits {
            self.out.push_str(&self.src[cursor..from]);
            self.out.push_str(&text);
            cursor = to;
        }
        self.out.push_str(&self.src[cursor..pos.tag_end]);
    }

    /// Writes `node` with `spec` applied to its start tag, its element children rewritten in
    /// `child_ctx`, everything else verbatim.
    fn write_with(
        &mut self,
        node: roxmltree::Node<'a, 'i>,
        spec: &TagSpec,
        child_ctx: &Context,
        wrap: Option<&str>,
    ) -> Result<(), SvgError> {
        let pos = self.positions(node)?;
        self.write_start_tag(node, spec, &pos);
        if pos.self_closing {
            if let Some(child) = &spec.child {
                // `<name …/>` becomes `<name …>child</name>`.
                self.out.truncate(self.out.len() - "/>".len());
                self.out.push('>');
                self.out.push_str(child);
                let name = spec.rename.unwrap_or(node.tag_name().name());
                let _ = write!(self.out, "</{}{}>", pos.prefix, name);
            }
            return Ok(());
        }
        if let Some(child) = &spec.child {
            self.out.push_str(child);
        }
        let end = node.range().end;
        let end_tag = match self.src[pos.tag_end..end].rfind("</") {
            Some(i) => pos.tag_end + i,
            None => {
                return Err(SvgError::Internal {
                    file: self.origin.to_string(),
                    what: format!("no end tag for the element at byte {}", node.range().start),
                })
            }
        };
        if let Some(id) = wrap {
            let _ = write!(
                self.out,
                "<{}g id=\"{}\">",
                pos.prefix,
                escape_attribute(id)
            );
        }
        let mut cursor = pos.tag_end;
        for child in node.children().filter(|c| c.is_element()) {
            let r = child.range();
            if r.start < cursor || r.end > end_tag {
                return Err(self.unsupported(child, "elements created by DTD entity expansion"));
            }
            self.out.push_str(&self.src[cursor..r.start]);
            self.write_element(child, child_ctx)?;
            cursor = r.end;
        }
        self.out.push_str(&self.src[cursor..end_tag]);
        if wrap.is_some() {
            let _ = write!(self.out, "</{}g>", pos.prefix);
        }
        match spec.rename {
            Some(name) => {
                let _ = write!(self.out, "</{}{}>", pos.prefix, name);
            }
            None => self.out.push_str(&self.src[end_tag..end]),
        }
        Ok(())
    }

    /// Writes a `use` element: expanded into a `<g>` with a copy of its target when the policy
    /// says so, else as it is.
    fn write_use(&mut self, node: roxmltree::Node<'a, 'i>, ctx: &Context) -> Result<(), SvgError> {
        let plain = TagSpec {
            strip_ids: ctx.in_copy,
            ..TagSpec::default()
        };
        let Some((target, instance)) = self.expanded_use(node, ctx)? else {
            return self.write_with(node, &plain, ctx, None);
        };
        let target_tag = target.tag_name().name();
        let transform = self.use_transform(node, target)?;
        let pos = self.positions(node)?;
        let _ = write!(self.out, "<{}g", pos.prefix);
        for a in node.attributes() {
            let name = a.name();
            let ns = a.namespace();
            let drop = (name == "href" && (ns.is_none() || ns == Some(XLINK_NS)))
                || (ns.is_none() && matches!(name, "x" | "y" | "width" | "height" | "transform"))
                || (ctx.in_copy && name == "id" && (ns.is_none() || ns == Some(XML_NS)));
            if !drop {
                self.out.push(' ');
                self.out.push_str(&self.src[a.range()]);
            }
        }
        if !transform.is_empty() {
            let _ = write!(self.out, " transform=\"{}\"", escape_attribute(&transform));
        }
        self.out.push('>');
        let mut targets = ctx.targets.clone();
        targets.push(target.id());
        let inner = Context {
            uses: instance,
            targets,
            in_copy: true,
            in_clip: false,
        };
        if target_tag == "symbol" {
            const SYMBOL_ONLY: &[&str] = &[
                "viewBox",
                "preserveAspectRatio",
                "x",
                "y",
                "width",
                "height",
                "refX",
                "refY",
            ];
            let spec = TagSpec {
                rename: Some("g"),
                remove: SYMBOL_ONLY,
                strip_ids: true,
                set: Vec::new(),
                child: None,
            };
            self.write_with(target, &spec, &inner, None)?;
        } else if target_tag == "svg" {
            // A use of an <svg>: its copy is a nested viewport, sized by the use's width and
            // height where it has them (SVG 2, §5.6.1 "The 'use' element").
            let set = ["width", "height"]
                .into_iter()
                .filter_map(|name| Some((name, node.attribute(name)?.to_string())))
                .collect();
            let spec = TagSpec {
                strip_ids: true,
                set,
                ..TagSpec::default()
            };
            self.write_with(target, &spec, &inner, None)?;
        } else {
            self.write_element(target, &inner)?;
        }
        let _ = write!(self.out, "</{}g>", pos.prefix);
        Ok(())
    }

    /// The element `use` element `node` references and the `use` chain of its copy, when the
    /// copy is written (a graphic element, not recursive, which the policy expands); `None`
    /// to write the `use` as it is. Errors for what cannot be expanded: uses nested past
    /// [`MAX_USE_DEPTH`], `transform-origin`.
    fn expanded_use(
        &mut self,
        node: roxmltree::Node<'a, 'i>,
        ctx: &Context,
    ) -> Result<Option<(roxmltree::Node<'a, 'i>, Vec<usize>)>, SvgError> {
        let href = node
            .attribute("href")
            .or_else(|| node.attribute((XLINK_NS, "href")));
        let target = href
            .and_then(|h| h.trim().strip_prefix('#'))
            .and_then(|id| self.ids.get(id))
            .copied();
        let Some(target) = target.filter(|t| is_svg_element(*t)) else {
            return Ok(None);
        };
        let target_tag = target.tag_name().name();
        let graphic = matches!(
            target_tag,
            "g" | "symbol"
                | "use"
                | "a"
                | "switch"
                | "path"
                | "rect"
                | "circle"
                | "ellipse"
                | "line"
                | "polyline"
                | "polygon"
                | "text"
                | "image"
                | "svg"
        );
        let recursive = node.ancestors().any(|a| a == target) || ctx.targets.contains(&target.id());
        if recursive {
            tracing::warn!(
                file = self.origin,
                element = %node_label(self.doc, node),
                "recursive use; left as it is (usvg skips it)"
            );
        }
        if !graphic || recursive {
            return Ok(None);
        }
        let mut instance = ctx.uses.clone();
        instance.push(node.range().start);
        if !self.policy.expand_use(&instance) {
            return Ok(None);
        }
        if ctx.uses.len() >= MAX_USE_DEPTH {
            return Err(self.unsupported(
                node,
                format!("use elements nested more than {MAX_USE_DEPTH} deep"),
            ));
        }
        if node.has_attribute("transform-origin") {
            return Err(self.unsupported(node, "transform-origin on a use element"));
        }
        Ok(Some((target, instance)))
    }

    /// The transform of the group replacing `use` element `node`: its own transform, then
    /// `translate(x y)`, then for a `symbol` target its viewBox mapping.
    fn use_transform(
        &self,
        node: roxmltree::Node<'a, 'i>,
        target: roxmltree::Node<'a, 'i>,
    ) -> Result<String, SvgError> {
        let (vw, vh) = (self.viewport.width, self.viewport.height);
        let length = |name: &str, base: f64, default: f64| -> Result<f64, SvgError> {
            match node.attribute(name) {
                Some(v) => user_length(v, base).map_err(|e| {
                    self.unsupported(node, format!("attribute {name}=\"{v}\": expected {e}"))
                }),
                None => Ok(default),
            }
        };
        let (x, y) = (length("x", vw, 0.0)?, length("y", vh, 0.0)?);
        let mut transform = node.attribute("transform").unwrap_or("").trim().to_string();
        let mut push = |part: String| {
            if !transform.is_empty() {
                transform.push(' ');
            }
            transform.push_str(&part);
        };
        if x != 0.0 || y != 0.0 {
            push(format!("translate({} {})", number(x), number(y)));
        }
        if target.tag_name().name() == "symbol" {
            let (w, h) = (length("width", vw, vw)?, length("height", vh, vh)?);
            let view_box = target
                .attribute("viewBox")
                .and_then(|v| <svgtypes::ViewBox as std::str::FromStr>::from_str(v).ok());
            if let Some(vb) = view_box.filter(|_| w > 0.0 && h > 0.0) {
                let aspect = target
                    .attribute("preserveAspectRatio")
                    .and_then(|v| <svgtypes::AspectRatio as std::str::FromStr>::from_str(v).ok())
                    .unwrap_or_default();
                let c = view_box_transform(vb, aspect, w, h).as_coeffs();
                push(format!(
                    "matrix({} {} {} {} {} {})",
                    number(c[0]),
                    number(c[1]),
                    number(c[2]),
                    number(c[3]),
                    number(c[4]),
                    number(c[5])
                ));
            }
        }
        Ok(transform)
    }
}
