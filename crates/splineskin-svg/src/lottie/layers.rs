//! The document's content as Lottie layers: Lottie masks whole layers, so a clipped group gets
//! a layer of its own, masked by its clip path's shapes, and what is above and below it goes into
//! the layers around it, in order.

use serde_json::{json, Value};

use super::{group_transform, Writer};

/// The document's content split into Lottie layers, topmost first: a clipped group has a layer
/// of its own whose masks are the clip path's shapes; what is above and below it fills the
/// layers around it.
#[derive(Default)]
pub(super) struct Runs {
    /// Finished layers, topmost first.
    pub(super) done: Vec<Run>,
    /// Items of the unclipped layer being filled, topmost first.
    current: Vec<Value>,
}

/// One layer's content.
pub(super) struct Run {
    pub(super) shapes: Vec<Value>,
    /// Lottie masks (`masksProperties`); empty: none.
    pub(super) masks: Vec<Value>,
    /// The layer's opacity, 0–1.
    pub(super) opacity: f64,
    /// The layer's name (the clipped group's), or the animation's.
    pub(super) name: Option<String>,
}

impl Runs {
    /// Ends the unclipped layer being filled, if it has anything.
    pub(super) fn finish(&mut self) {
        if !self.current.is_empty() {
            self.done.push(Run {
                shapes: std::mem::take(&mut self.current),
                masks: Vec::new(),
                opacity: 1.0,
                name: None,
            });
        }
    }
}

/// Whether a clip path applies in `group` or below it.
fn contains_clip(group: &usvg::Group) -> bool {
    group.clip_path().is_some()
        || group.children().iter().any(|c| match c {
            usvg::Node::Group(g) => contains_clip(g),
            _ => false,
        })
}

/// Every path under `group` (the content of a clip path), in document order.
fn paths_under<'a>(group: &'a usvg::Group, out: &mut Vec<&'a usvg::Path>) {
    for child in group.children() {
        match child {
            usvg::Node::Group(g) => paths_under(g, out),
            usvg::Node::Path(p) => out.push(p),
            _ => {}
        }
    }
}

impl Writer<'_> {
    /// Walks a usvg group's children topmost first into layers ([`Runs`]): a group with a
    /// clip path that Lottie masks can express becomes a layer of its own; other content goes
    /// into the unclipped layers between, as [`Writer::group_items`] writes it. `opacity`: the
    /// product of the enclosing groups' opacities (applied to each part when a group with
    /// opacity holds a clipped one).
    pub(super) fn layer_runs(
        &mut self,
        group: &usvg::Group,
        lookup: &dyn Fn(&str) -> Option<usize>,
        opacity: f64,
        runs: &mut Runs,
    ) {
        let wrap = |items: Vec<Value>, opacity: f64, label: &str| -> Vec<Value> {
            if opacity < 1.0 {
                let mut it = items;
                it.push(group_transform(opacity));
                vec![json!({"ty": "gr", "nm": label, "it": it})]
            } else {
                items
            }
        };
        for child in group.children().iter().rev() {
            let usvg::Node::Group(g) = child else {
                let mut items = Vec::new();
                self.node_items(child, lookup, &mut items);
                runs.current.extend(wrap(items, opacity, "a group"));
                continue;
            };
            if !contains_clip(g) {
                let mut items = Vec::new();
                self.node_items(child, lookup, &mut items);
                runs.current.extend(wrap(items, opacity, "a group"));
                continue;
            }
            let label = if g.id().is_empty() { "a group" } else { g.id() }.to_string();
            let own = opacity * f64::from(g.opacity().get());
            let masks = g
                .clip_path()
                .and_then(|clip| self.clip_masks(clip, lookup, &label));
            match masks {
                Some(masks) => {
                    self.warnings.unwritten_effects(g, &label);
                    // Its content, inner clip paths included, in one masked layer.
                    let mut shapes = Vec::new();
                    self.group_items(g, lookup, &mut shapes);
                    runs.finish();
                    runs.done.push(Run {
                        shapes,
                        masks,
                        opacity: own,
                        name: Some(label),
                    });
                }
                None if g.clip_path().is_some() => {
                    // Not expressible (said by clip_masks): drawn unclipped, as before.
                    let mut items = Vec::new();
                    self.node_items(child, lookup, &mut items);
                    runs.current.extend(wrap(items, opacity, &label));
                }
                None => {
                    // One child: nothing to show through.
                    if own < 1.0 && g.children().len() > 1 {
                        self.warnings.add(format!(
                            "{label}: its opacity is applied to each of its parts (it holds a \
                             clipped group, which has a layer of its own), so where they overlap \
                             they show through each other"
                        ));
                    }
                    self.layer_runs(g, lookup, own, runs);
                }
            }
        }
    }

    /// The Lottie masks of a clip path: one mask (mode add: their union) per path of its
    /// shapes, keyframed as any path; `None` with a warning when it has nothing Lottie can use.
    fn clip_masks(
        &mut self,
        clip: &usvg::ClipPath,
        lookup: &dyn Fn(&str) -> Option<usize>,
        label: &str,
    ) -> Option<Vec<Value>> {
        if clip.clip_path().is_some() {
            self.warnings.add(format!(
                "{label}: its clip path is itself clipped; the inner clip is not written"
            ));
        }
        let mut paths = Vec::new();
        paths_under(clip.root(), &mut paths);
        let mut masks = Vec::new();
        for p in paths {
            let Some(element) = lookup(p.id()) else {
                continue;
            };
            let range = self.source.elements[element].paths.clone();
            if range.len() > 1
                || p.fill()
                    .is_some_and(|f| f.rule() == usvg::FillRule::EvenOdd)
            {
                self.warnings.add(format!(
                    "{label}: its clip path's {} is written as the union of its subpaths (Lottie \
                     masks add up: holes are filled)",
                    self.source.elements[element].label
                ));
            }
            for pi in range {
                let closed = self.drawing.paths[pi].closed && !self.source.closed_without_z[pi];
                let shape = self.path_shape(pi, closed);
                masks.push(json!({
                    "nm": format!("clip {pi}"),
                    "inv": false,
                    "mode": "a",
                    "pt": shape["ks"],
                    "o": {"a": 0, "k": 100.0},
                    "x": {"a": 0, "k": 0.0}
                }));
            }
        }
        if masks.is_empty() {
            self.warnings.add(format!(
                "{label}: its clip path has no shapes Lottie can mask with (text, or nothing \
                 imported): the content is drawn unclipped"
            ));
            return None;
        }
        Some(masks)
    }
}
