//! usvg's paths mapped back to the elements they come from and converted to the drawing's
//! paths ([`Importer`]): each element once (a clip path or mask used twice is deformed for its
//! first use), with its role, paint and label, and the drawing's source assembled at the end.

use std::collections::HashMap;
use std::sync::Arc;

use kurbo::{Affine, Rect, Size};
use splineskin_core::drawing::source::{ElementKey, ElementKind, ImportedElement, SvgSource};
use splineskin_core::drawing::{Drawing, Path, PathRole};

use super::segments::{convert_segments, same_structure, segments_of_path_data, segments_of_usvg};
use super::{
    collinear, element_paint, key_label, same_placement, Context, ImportOptions, SvgError,
};

/// The drawing being read: what has been imported so far, and the document it comes from.
pub(super) struct Importer<'d, 'i> {
    doc: &'d roxmltree::Document<'i>,
    ids: &'d HashMap<String, ElementKey>,
    options: &'d ImportOptions,
    origin: &'d str,
    /// Every element by its byte offset.
    nodes: HashMap<usize, roxmltree::Node<'d, 'i>>,
    /// Every `<path>` element's position in document order (the authors' numbering), by its
    /// byte offset.
    path_tags: HashMap<usize, usize>,
    paths: Vec<Path>,
    /// Each path's element (an index into `elements`).
    path_elements: Vec<usize>,
    closed_without_z: Vec<bool>,
    elements: Vec<ImportedElement>,
    element_of_key: HashMap<ElementKey, usize>,
    /// Clip paths in `objectBoundingBox` units: their byte offset and units map.
    bbox_clips: Vec<(usize, Affine)>,
    /// Paths usvg emitted without a source element.
    n_unmapped: usize,
}

impl<'d, 'i> Importer<'d, 'i> {
    /// An importer of the paths of `doc`, whose usvg ids map to elements by `ids`.
    pub(super) fn new(
        doc: &'d roxmltree::Document<'i>,
        ids: &'d HashMap<String, ElementKey>,
        options: &'d ImportOptions,
        origin: &'d str,
    ) -> Importer<'d, 'i> {
        let path_tags = doc
            .descendants()
            .filter(|n| crate::document::is_svg_element(*n) && n.tag_name().name() == "path")
            .enumerate()
            .map(|(k, n)| (n.range().start, k))
            .collect();
        let nodes = doc
            .descendants()
            .filter(|n| n.is_element())
            .map(|n| (n.range().start, n))
            .collect();
        Importer {
            doc,
            ids,
            options,
            origin,
            nodes,
            path_tags,
            paths: Vec::new(),
            path_elements: Vec::new(),
            closed_without_z: Vec::new(),
            elements: Vec::new(),
            element_of_key: HashMap::new(),
            bbox_clips: Vec::new(),
            n_unmapped: 0,
        }
    }

    /// Imports usvg's path `usvg_path` (local → root map `local_to_root`, found in `context`;
    /// `hidden`: missing from the reading without hidden layers) as paths of its element.
    pub(super) fn add(
        &mut self,
        usvg_path: &usvg::Path,
        local_to_root: Affine,
        context: Context,
        hidden: bool,
    ) -> Result<(), SvgError> {
        let Some(key) = self.ids.get(usvg_path.id()) else {
            self.n_unmapped += 1;
            return Ok(());
        };
        let Some(&node) = self.nodes.get(&key.element) else {
            return Err(SvgError::Internal {
                file: self.origin.to_string(),
                what: format!("no element at byte {}", key.element),
            });
        };
        let role = match context {
            Context::Art if hidden => PathRole::Hidden,
            Context::Art if !usvg_path.is_visible() => PathRole::Unpainted,
            Context::Art => PathRole::Visible,
            Context::Clip { .. } => PathRole::ClipPath,
            Context::Mask { .. } => PathRole::Mask,
        };
        if self.mask_in_bounding_box_units(context, key) {
            return Ok(());
        }
        let Some(index) = self.element_index(key, node, usvg_path, local_to_root, context, role)?
        else {
            return Ok(());
        };
        self.convert(index, node, usvg_path, role)
    }

    /// Whether `context` is the content of a mask in `objectBoundingBox` units, which is not
    /// deformed (said with a warning).
    fn mask_in_bounding_box_units(&self, context: Context, key: &ElementKey) -> bool {
        let Context::Mask { mask } = context else {
            return false;
        };
        if self
            .nodes
            .get(&mask)
            .and_then(|m| m.attribute("maskContentUnits"))
            != Some("objectBoundingBox")
        {
            return false;
        }
        let label = key_label(self.doc, &self.nodes, key);
        tracing::warn!(
            file = self.origin,
            element = %label,
            "mask content in objectBoundingBox units is not deformed (left at rest)"
        );
        true
    }

    /// The index of `key`'s element in `elements`, added if new; `None` when this path of it
    /// is not imported (a clip path or mask imported for an earlier use, or a second copy
    /// usvg emitted apart).
    fn element_index(
        &mut self,
        key: &ElementKey,
        node: roxmltree::Node,
        usvg_path: &usvg::Path,
        local_to_root: Affine,
        context: Context,
        role: PathRole,
    ) -> Result<Option<usize>, SvgError> {
        let origin = self.origin;
        match self.element_of_key.get(key) {
            Some(&i) if matches!(role, PathRole::ClipPath | PathRole::Mask) => {
                // A clip path or mask used by several elements: deformed once.
                if !same_placement(self.elements[i].local_to_root, local_to_root) {
                    tracing::warn!(
                        file = origin,
                        element = %self.elements[i].label,
                        "this clip path or mask is used by elements in different coordinates; \
                         it is deformed for its first use only (give each element its own copy \
                         to deform it for each)"
                    );
                }
                Ok(None)
            }
            Some(&i) => {
                if self.elements[i].paths.end != self.paths.len() {
                    tracing::warn!(
                        file = origin,
                        element = %self.elements[i].label,
                        "usvg emitted this element twice, not contiguously; the second copy is \
                         not imported"
                    );
                    return Ok(None);
                }
                Ok(Some(i))
            }
            None => {
                let kind = ElementKind::from_tag(node.tag_name().name()).ok_or_else(|| {
                    SvgError::Internal {
                        file: origin.to_string(),
                        what: format!("<{}> mapped as geometry", node.tag_name().name()),
                    }
                })?;
                if let Context::Clip { clip, units } = context {
                    let bbox_units = self
                        .nodes
                        .get(&clip)
                        .and_then(|c| c.attribute("clipPathUnits"))
                        == Some("objectBoundingBox");
                    if bbox_units && !self.bbox_clips.iter().any(|(c, _)| *c == clip) {
                        self.bbox_clips.push((clip, units));
                    }
                }
                self.elements.push(ImportedElement {
                    key: key.clone(),
                    kind,
                    label: key_label(self.doc, &self.nodes, key),
                    range: node.range(),
                    local_to_root,
                    paths: self.paths.len()..self.paths.len(),
                    role,
                    path_tag_index: (kind == ElementKind::Path && key.uses.is_empty())
                        .then(|| self.path_tags.get(&key.element).copied())
                        .flatten(),
                    zero_area_fill: false,
                    paint: element_paint(usvg_path),
                });
                self.element_of_key
                    .insert(key.clone(), self.elements.len() - 1);
                Ok(Some(self.elements.len() - 1))
            }
        }
    }

    /// Converts `usvg_path` into paths of element `index` (a `<path>`'s own `d` read in `f64`
    /// when usvg kept its structure, else usvg's `f32` data).
    fn convert(
        &mut self,
        index: usize,
        node: roxmltree::Node,
        usvg_path: &usvg::Path,
        role: PathRole,
    ) -> Result<(), SvgError> {
        let element = &mut self.elements[index];
        let before = self.paths.len();
        let usvg_segments = segments_of_usvg(usvg_path.data());
        let segments = match (element.kind, node.attribute("d")) {
            (ElementKind::Path, Some(d)) => {
                let exact = segments_of_path_data(d);
                if same_structure(&exact, &usvg_segments) {
                    exact
                } else {
                    tracing::warn!(
                        file = self.origin,
                        element = %element.label,
                        "path data read in f64 differs from usvg's; using usvg's f32 data"
                    );
                    usvg_segments
                }
            }
            _ => usvg_segments,
        };
        convert_segments(
            &segments,
            element.local_to_root,
            self.options,
            self.origin,
            &element.label,
            &mut self.paths,
            &mut self.closed_without_z,
        )?;
        element.paths.end = self.paths.len();
        element.zero_area_fill = matches!(role, PathRole::Visible | PathRole::Hidden)
            && usvg_path.fill().is_some()
            && self.paths[element.paths.clone()]
                .iter()
                .all(|p| collinear(&p.points));
        self.path_elements
            .extend(std::iter::repeat_n(index, self.paths.len() - before));
        Ok(())
    }

    /// The drawing read from `text` (its size `size` and viewBox `view_box`): the paths, and
    /// the elements that produced at least one (those whose subpaths were all degenerate are
    /// not kept). An error when there is no path at all.
    pub(super) fn finish(
        self,
        text: &str,
        size: Size,
        view_box: Rect,
        warnings: Vec<String>,
    ) -> Result<Drawing, SvgError> {
        if self.n_unmapped > 0 {
            tracing::warn!(
                file = self.origin,
                count = self.n_unmapped,
                "paths without a source element (marker contents or paint-order split copies) \
                 are not imported"
            );
        }
        if self.paths.is_empty() {
            return Err(SvgError::NoPaths {
                file: self.origin.to_string(),
                why: Vec::new(),
            });
        }
        let mut remap = vec![usize::MAX; self.elements.len()];
        let mut kept = Vec::new();
        for (i, e) in self.elements.into_iter().enumerate() {
            if !e.paths.is_empty() {
                remap[i] = kept.len();
                kept.push(e);
            }
        }
        let path_elements = self.path_elements.into_iter().map(|i| remap[i]).collect();
        let source = SvgSource {
            origin: self.origin.to_string(),
            text: text.to_string(),
            elements: kept,
            path_elements,
            closed_without_z: self.closed_without_z,
            size,
            view_box,
            bbox_clips: self.bbox_clips,
            warnings,
        };
        Ok(Drawing {
            paths: self.paths,
            source: Some(Arc::new(source)),
        })
    }
}
