//! The resources that follow an element's deformation on export: copies of user-space
//! gradients and patterns (transform `L⁻¹ A L G`), fixed-orientation markers turned by the
//! element's rotation, and the attribute edits of text and images (`P⁻¹ A P` before their own
//! transform), computed from the element maps of [`crate::follow`].

use std::collections::HashMap;

use kurbo::{Affine, Rect};
use splineskin_core::drawing::source::ImportedElement;
use splineskin_core::drawing::{ElementKind, SvgSource};

use super::{Follow, FollowEdits, Timing, SINGULAR_DETERMINANT};
use crate::document::{matrix, node_label, number, SvgError, XLINK_NS};
use crate::rewrite::{AttributeSet, CopyEdit};
use crate::{follow, smil};

/// Longest `href` chain followed to resolve a paint server's attributes: 32.
pub(crate) const MAX_HREF_CHAIN: usize = 32;

/// The smallest rotation (radians) a fixed-orientation marker is turned by: 1e-9 (below,
/// the marker is left as it is).
pub(super) const MIN_MARKER_TURN: f64 = 1e-9;

/// The value of attribute `name` on `node` or, through `href`/`xlink:href`, on the template it
/// names (as gradients and patterns inherit).
pub(crate) fn through_href<'a, 'i>(
    node: roxmltree::Node<'a, 'i>,
    name: &str,
    ids: &HashMap<&'a str, roxmltree::Node<'a, 'i>>,
) -> Option<&'a str> {
    let mut n = node;
    for _ in 0..MAX_HREF_CHAIN {
        if let Some(v) = n.attribute(name) {
            return Some(v);
        }
        let href = n
            .attribute("href")
            .or_else(|| n.attribute((XLINK_NS, "href")))?;
        n = *ids.get(href.trim().strip_prefix('#')?)?;
    }
    None
}

/// A paint server in user space: the name of its transform attribute, its transform (through
/// templates), and the unit attributes its copy states explicitly. `None` for other servers
/// (objectBoundingBox units) or other elements.
pub(super) fn user_space_server<'a, 'i>(
    node: roxmltree::Node<'a, 'i>,
    ids: &HashMap<&'a str, roxmltree::Node<'a, 'i>>,
) -> Option<(&'static str, Affine, AttributeSet)> {
    let user = |name: &str, default: &str| {
        through_href(node, name, ids).unwrap_or(default).trim() == "userSpaceOnUse"
    };
    let (transform, units): (&'static str, &[&'static str]) = match node.tag_name().name() {
        "linearGradient" | "radialGradient" if user("gradientUnits", "objectBoundingBox") => {
            ("gradientTransform", &["gradientUnits"])
        }
        "pattern"
            if user("patternUnits", "objectBoundingBox")
                && user("patternContentUnits", "userSpaceOnUse") =>
        {
            ("patternTransform", &["patternUnits", "patternContentUnits"])
        }
        _ => return None,
    };
    let t = through_href(node, transform, ids)
        .and_then(|v| <svgtypes::Transform as std::str::FromStr>::from_str(v).ok())
        .map(|t| Affine::new([t.a, t.b, t.c, t.d, t.e, t.f]))
        .unwrap_or(Affine::IDENTITY);
    let units = units
        .iter()
        .map(|&u| (u, "userSpaceOnUse".to_string()))
        .collect();
    Some((transform, t, units))
}

/// The id in a paint or marker reference `url(#id)` (quotes allowed); `None` for `none` or
/// anything else.
pub(super) fn url_id(value: &str) -> Option<&str> {
    let inner = value.trim().strip_prefix("url(")?;
    let inner = &inner[..inner.find(')')?];
    inner
        .trim()
        .trim_matches(|c| c == '"' || c == '\'')
        .strip_prefix('#')
}

/// The marker `node` uses at `slot` (`start`, `mid`, `end`): `marker-<slot>` or the `marker`
/// shorthand on it or its nearest ancestor that sets either (styles then attributes; style
/// sheets are not read).
pub(super) fn marker_reference<'a>(node: roxmltree::Node<'a, '_>, slot: &str) -> Option<String> {
    let long = format!("marker-{slot}");
    for n in node.ancestors().filter(|n| n.is_element()) {
        let v = follow::declared(n, &long).or_else(|| follow::declared(n, "marker"));
        if let Some(v) = v {
            return url_id(&v).map(str::to_string);
        }
    }
    None
}

/// The edits that carry paint servers, markers, text and images by the maps of
/// `follow.frames` ([`crate::follow`]): for a still document (one frame) the attributes, for an
/// animated one those of the first frame and animation elements through all frames
/// ([`crate::smil`]; a paint server's, marker's or stroke width's is left out where every
/// frame agrees with the first within [`follow::SAME_MAP`] or [`MIN_MARKER_TURN`]; a text's or
/// image's is always written).
///
/// Errors: [`SvgError::SourceMismatch`] when the maps do not belong to this drawing, or their
/// number is not the timing's.
pub(super) fn follow_edits(
    source: &SvgSource,
    doc: &roxmltree::Document,
    follow: &Follow,
) -> Result<FollowEdits, SvgError> {
    check_frames(source, follow)?;
    let mut maker = EditMaker::new(doc);
    maker.paint_marker = follow.paint_marker;
    for (i, e) in source.elements.iter().enumerate() {
        maker.element_edits(i, e, follow);
    }
    maker.carried_edits(source, doc, follow);
    Ok(maker.edits)
}

/// Refuses element maps that do not belong to `follow`'s drawing and `source` (another path or
/// element count, another set of carried elements, a frame count other than the timing's).
fn check_frames(source: &SvgSource, follow: &Follow) -> Result<(), SvgError> {
    let Follow {
        drawing,
        frames,
        timing,
        ..
    } = *follow;
    let mismatch = |what: String| SvgError::SourceMismatch {
        file: source.origin.clone(),
        what,
    };
    let expected = timing.map_or(1, |t| t.n_frames);
    if frames.len() != expected {
        return Err(mismatch(format!(
            "{} element maps for {expected} frames",
            frames.len()
        )));
    }
    for maps in frames {
        if maps.n_paths != drawing.paths.len() || maps.elements.len() != source.elements.len() {
            return Err(mismatch(format!(
                "the element maps were computed for {} paths in {} elements, the drawing has {} \
                 in {}",
                maps.n_paths,
                maps.elements.len(),
                drawing.paths.len(),
                source.elements.len()
            )));
        }
        let same_carried = maps.carried.len() == frames[0].carried.len()
            && maps
                .carried
                .iter()
                .zip(&frames[0].carried)
                .all(|(a, b)| a.offset == b.offset);
        if !same_carried {
            return Err(mismatch(
                "the frames' element maps carry different texts and images".to_string(),
            ));
        }
    }
    Ok(())
}

/// A resource's copy: its local maps (or marker turns), one per frame, and its id.
type Made = (Vec<Affine>, Vec<f64>, String);

/// Whether every frame's map agrees with the first's (at the scale `size`).
fn still_maps(maps: &[Affine], size: f64) -> bool {
    maps.iter().all(|&m| follow::same_map(m, maps[0], size))
}

/// Whether every frame's marker turn agrees with the first's.
fn still_turns(turns: &[f64]) -> bool {
    turns
        .iter()
        .all(|&t| (t - turns[0]).abs() <= MIN_MARKER_TURN)
}

/// The edits being made, and what they are made from: the source document's elements by id
/// and by byte offset, and the copies of resources made so far (one per distinct placement).
struct EditMaker<'a, 'i> {
    ids: HashMap<&'a str, roxmltree::Node<'a, 'i>>,
    nodes: HashMap<usize, roxmltree::Node<'a, 'i>>,
    /// A prefix no id of the document starts with, for the copies' ids.
    prefix: String,
    /// Per resource (byte offset): its copies.
    made: HashMap<usize, Vec<Made>>,
    edits: FollowEdits,
    /// Every element's own paint copies, marked with this attribute ([`Follow::paint_marker`]).
    paint_marker: Option<&'static str>,
}

impl<'a, 'i> EditMaker<'a, 'i> {
    fn new(doc: &'a roxmltree::Document<'i>) -> EditMaker<'a, 'i> {
        let mut ids = HashMap::new();
        let mut nodes = HashMap::new();
        for n in doc.descendants().filter(|n| n.is_element()) {
            if let Some(id) = n.attribute("id") {
                ids.entry(id).or_insert(n);
            }
            nodes.insert(n.range().start, n);
        }
        EditMaker {
            ids,
            nodes,
            prefix: crate::document::unique_prefix(doc),
            made: HashMap::new(),
            edits: FollowEdits::default(),
            paint_marker: None,
        }
    }

    /// The id of a copy of `resource` (id `id`) for maps or turns `key`: an earlier copy when
    /// one is the `same`, else a new one written by `make` (given its id).
    fn copy(
        &mut self,
        resource: roxmltree::Node,
        id: &str,
        same: &dyn Fn(&[Affine], &[f64]) -> bool,
        key: (Vec<Affine>, Vec<f64>),
        make: &dyn Fn(&str) -> CopyEdit,
    ) -> String {
        let list = self.made.entry(resource.range().start).or_default();
        if let Some((_, _, copy)) = list.iter().find(|(m, t, _)| same(m, t)) {
            return copy.clone();
        }
        let copy = format!("{}{id}-{}", self.prefix, list.len() + 1);
        list.push((key.0, key.1, copy.clone()));
        let mut edit = make(&copy);
        edit.set.insert(0, ("id", copy.clone()));
        self.edits
            .copies
            .entry(resource.range().start)
            .or_default()
            .push(edit);
        copy
    }

    /// Imported element `i` (`e`): its user-space paint servers and fixed-orientation markers
    /// replaced by copies that follow it, and its stroke width scaled when asked; animated
    /// when they move.
    fn element_edits(&mut self, i: usize, e: &ImportedElement, follow: &Follow) {
        let mut decls = Vec::new();
        let mut animations = String::new();
        let l = e.local_to_root;
        // The element's local map per frame: `L⁻¹ A L`, or `(F L)⁻¹ A L` when a still
        // document draws it in its stroke frame `F` (crate::follow).
        let ms: Vec<Affine> = follow
            .frames
            .iter()
            .map(|maps| {
                let frame = maps.stroke_frame(i).filter(|_| follow.timing.is_none());
                (frame.unwrap_or(Affine::IDENTITY) * l).inverse() * maps.elements[i] * l
            })
            .collect();
        if let Some(&node) = self.nodes.get(&e.range.start) {
            let diagonal = follow.drawing.paths[e.paths.clone()]
                .iter()
                .flat_map(|p| p.points.iter())
                .fold(None, |r: Option<Rect>, &p| {
                    Some(r.map_or(Rect::from_points(p, p), |r| r.union_pt(p)))
                })
                .map_or(0.0, |r| r.width().hypot(r.height()));
            let size = diagonal / follow::local_scale(l);
            self.paint_edits(i, e, &ms, size, follow.timing, &mut decls);
            self.marker_edits(i, e, node, &ms, follow.timing, &mut decls);
            if follow.frames[0].options.scale_strokes {
                if let Some(w) = e.paint.stroke_width {
                    let widths: Vec<f64> = ms.iter().map(|&m| w * follow::local_scale(m)).collect();
                    decls.push(("stroke-width".to_string(), number(widths[0])));
                    if let Some(timing) = follow.timing.filter(|_| !still_maps(&ms, size)) {
                        smil::push_animate(&mut animations, "stroke-width", &widths, timing);
                    }
                }
            }
        }
        self.edits.styles.push(decls);
        self.edits.animations.push(animations);
    }

    /// `e`'s fill and stroke servers in user space, replaced by copies whose transform is the
    /// element's local map `ms` (per frame) times their own.
    fn paint_edits(
        &mut self,
        i: usize,
        e: &ImportedElement,
        ms: &[Affine],
        size: f64,
        timing: Option<&Timing>,
        decls: &mut Vec<(String, String)>,
    ) {
        for (slot, server) in [
            ("fill", &e.paint.fill_server),
            ("stroke", &e.paint.stroke_server),
        ] {
            let Some(&server) = server.as_deref().and_then(|id| self.ids.get(id)) else {
                continue;
            };
            let Some((name, g, mut set)) = user_space_server(server, &self.ids) else {
                continue;
            };
            set.push((name, matrix(ms[0] * g)));
            if let Some(marker) = self.paint_marker {
                set.push((marker, i.to_string()));
            }
            let animated = timing.filter(|_| !still_maps(ms, size));
            // A server with children gets its animation as a child; one without (a pattern
            // inheriting its template's content) must stay childless: the animation follows
            // it and names it.
            let as_child = server.children().any(|c| c.is_element());
            let make = |copy: &str| {
                let mut edit = CopyEdit {
                    set: set.clone(),
                    ..CopyEdit::default()
                };
                if let Some(timing) = animated {
                    let maps: Vec<Affine> = ms.iter().map(|&m| m * g).collect();
                    let mut animation = String::new();
                    let target = (!as_child).then_some(copy);
                    smil::push_animate_transform(&mut animation, name, &maps, timing, target);
                    match as_child {
                        true => edit.content = Some(animation),
                        false => edit.after = Some(animation),
                    }
                }
                edit
            };
            let id = server.attribute("id").unwrap_or("paint");
            // A live view's copies are the element's own: none is shared.
            let shared = self.paint_marker.is_none();
            let same = |other: &[Affine], _: &[f64]| {
                shared
                    && other
                        .iter()
                        .zip(ms)
                        .all(|(&o, &m)| follow::same_map(o, m, size))
            };

            let copy = self.copy(server, id, &same, (ms.to_vec(), Vec::new()), &make);
            decls.push((slot.to_string(), format!("url(#{copy})")));
        }
    }

    /// `e`'s markers of fixed orientation (`node`: its element), replaced by copies turned with
    /// the element's local maps `ms` (per frame).
    fn marker_edits(
        &mut self,
        i: usize,
        e: &ImportedElement,
        node: roxmltree::Node,
        ms: &[Affine],
        timing: Option<&Timing>,
        decls: &mut Vec<(String, String)>,
    ) {
        let mut turns: Vec<f64> = ms.iter().map(|&m| follow::rotation_angle(m)).collect();
        smil::unwrap_angles(&mut turns);
        let has_markers = matches!(
            e.kind,
            ElementKind::Path | ElementKind::Line | ElementKind::Polyline | ElementKind::Polygon
        );
        // A live view's markers get their own copies at rest too: the page turns them.
        let unturned = turns.iter().all(|t| t.abs() <= MIN_MARKER_TURN);
        if !has_markers || (unturned && self.paint_marker.is_none()) {
            return;
        }
        for slot in ["start", "mid", "end"] {
            let Some(id) = marker_reference(node, slot) else {
                continue;
            };
            let Some(&marker) = self.ids.get(id.as_str()) else {
                continue;
            };
            if marker.tag_name().name() != "marker" {
                continue;
            }
            let orient = marker.attribute("orient").unwrap_or("0").trim();
            if orient.starts_with("auto") {
                continue;
            }
            let Ok(angle) = <svgtypes::Angle as std::str::FromStr>::from_str(orient) else {
                continue;
            };
            let degrees: Vec<f64> = turns
                .iter()
                .map(|t| angle.to_degrees() + t.to_degrees())
                .collect();
            let mut set = vec![("orient", number(degrees[0]))];
            if let Some(marker) = self.paint_marker {
                set.push((marker, i.to_string()));
            }
            let make = |_: &str| {
                let mut edit = CopyEdit {
                    set: set.clone(),
                    ..CopyEdit::default()
                };
                if let Some(timing) = timing.filter(|_| !still_turns(&turns)) {
                    let mut animation = String::new();
                    smil::push_animate(&mut animation, "orient", &degrees, timing);
                    edit.content = Some(animation);
                }
                edit
            };
            let shared = self.paint_marker.is_none();
            let same = |_: &[Affine], other: &[f64]| {
                shared
                    && other
                        .iter()
                        .zip(&turns)
                        .all(|(o, t)| (o - t).abs() <= MIN_MARKER_TURN)
            };
            let copy = self.copy(marker, &id, &same, (Vec::new(), turns.clone()), &make);
            decls.push((format!("marker-{slot}"), format!("url(#{copy})")));
        }
    }

    /// The carried texts and images: a `transform` (the frame's map in their parent's
    /// coordinates, then their own), animated when the document is; left at rest, with a
    /// warning, under a singular parent transform.
    fn carried_edits(&mut self, source: &SvgSource, doc: &roxmltree::Document, follow: &Follow) {
        for (k, c) in follow.frames[0].carried.iter().enumerate() {
            let Some(&node) = self.nodes.get(&c.offset) else {
                continue;
            };
            let p = c.parent_to_root;
            let [a, b, cc, d, _, _] = p.as_coeffs();
            let det = a * d - b * cc;
            let invertible =
                det.abs() > SINGULAR_DETERMINANT * (a.abs() + b.abs()) * (cc.abs() + d.abs());
            if !invertible {
                tracing::warn!(
                    file = source.origin.as_str(),
                    element = %node_label(doc, node),
                    "its parent's transform is singular; left at rest"
                );
                continue;
            }
            let local: Vec<Affine> = follow
                .frames
                .iter()
                .map(|maps| p.inverse() * maps.carried[k].map * p)
                .collect();
            let mut t = matrix(local[0]);
            if let Some(own) = node.attribute("transform").filter(|v| !v.trim().is_empty()) {
                t.push(' ');
                t.push_str(own.trim());
            }
            self.edits.transforms.insert(c.offset, t);
            if let Some(timing) = follow.timing {
                // The element's own transform is composed on the right of every frame's map.
                let own = follow::own_transform(node);
                let maps: Vec<Affine> = local.iter().map(|&m| m * own).collect();
                let mut animation = String::new();
                smil::push_animate_transform(&mut animation, "transform", &maps, timing, None);
                self.edits.contents.insert(c.offset, animation);
            }
        }
    }
}
