//! An opened drawing: an SVG document or a scene (ours or the paper authors'), read by the
//! library once, with what the page needs to show and deform it ([`DocumentInfo`]).

use anyhow::{bail, Context, Result};
use splineskin::drawing::carry::carried_parents;
use splineskin::drawing::follow::{stroke_frame_region, ElementMaps, FollowOptions};
use splineskin::drawing::svg_in::MAX_SVG_BYTES;
use splineskin::drawing::svg_out::{
    write_svg_with, write_svg_with_inserted, SvgOptions, ViewBoxRule,
};
use splineskin::drawing::{read_svg_named, Drawing, ImportOptions, SvgSource};
use splineskin::folds::FoldCheck;
use splineskin::scene::pinned::PinnedDrawing;
use splineskin::scene::{
    scene_domain_options, Compat, Engine, JunctionOverride, MeshFamily, Scene, WeightSpec,
};
use splineskin::spline_fit::Measure;

use crate::page_scene::{defop_family, scene_of_page, SceneExtras};
use crate::wire::{
    AnimationWire, DocumentInfo, EditScene, ElementInfo, OperatorInfo, PathInfo, StrokeFrameInfo,
    WeightsWire,
};

/// The attribute that marks each imported element in the shown document with its index
/// ([`splineskin::drawing::svg_out::write_svg_marked`]).
pub const ELEMENT_MARKER: &str = "data-splineskin-element";

/// The attribute that marks each carried `<text>` and `<image>` in the shown document with its
/// index ([`SvgOptions::carried_marker`]): the page sets their `transform` as the pose moves
/// them, by the rig's carry operator (`GET /api/rigs/{id}/carry`).
pub const CARRIED_MARKER: &str = "data-splineskin-carried";

/// The attribute that marks each element's own copy of a user-space paint server in the shown
/// document with the element's index ([`SvgOptions::paint_marker`]): the page sets its
/// transform as the element's map moves it.
pub const PAINT_MARKER: &str = "data-splineskin-paint";

/// The distinct values `k` of `marker="k"` in `svg`, ascending.
fn marked_indices(svg: &str, marker: &str) -> Vec<usize> {
    let key = format!("{marker}=\"");
    let mut found: Vec<usize> = svg
        .match_indices(&key)
        .filter_map(|(at, _)| {
            let rest = &svg[at + key.len()..];
            rest[..rest.find('"')?].parse().ok()
        })
        .collect();
    found.sort_unstable();
    found.dedup();
    found
}

/// Largest upload: an SVG document or a scene, whichever limit is larger
/// ([`MAX_SVG_BYTES`], 64 MiB; scenes of ours hold their drawing inline, so a scene may be a
/// little larger than its drawing: 1 MiB more is allowed).
pub const MAX_UPLOAD_BYTES: usize = MAX_SVG_BYTES + (1 << 20);

/// A drawing opened in the editor.
pub struct Document {
    /// The file name, for messages.
    pub name: String,
    /// The SVG text.
    pub svg_text: String,
    /// What the scene carries besides the page's part.
    pub extras: SceneExtras,
    /// The drawing as imported (junction kinds classified from the geometry).
    pub drawing: Drawing,
    /// What the page is sent (its `id` set by the store).
    pub info: DocumentInfo,
    /// The rest drawing's own crossings, found once: each check of a deformation for folds
    /// ([`crate::document_routes`]'s viewBox report) looks only at the deformed drawing.
    pub folds: FoldCheck,
    /// Per path, per joint: whether adaptive control points inserted the anchor
    /// ([`Document::refined`]); empty for a drawing as opened. Exports mark them
    /// ([`splineskin::drawing::svg_out::INSERTED_ATTRIBUTE`]).
    pub inserted: Vec<Vec<bool>>,
}

impl Document {
    /// Opens an upload (or a file's contents) named `name`: a scene if it is a JSON object,
    /// else an SVG document.
    pub fn open(name: &str, bytes: &[u8]) -> Result<Document> {
        if bytes.len() > MAX_UPLOAD_BYTES {
            bail!(
                "{name}: {} bytes is more than the {MAX_UPLOAD_BYTES}-byte limit",
                bytes.len()
            );
        }
        let text = std::str::from_utf8(bytes).map_err(|e| {
            anyhow::anyhow!(
                "{name}: not UTF-8 text (byte {}); expected an SVG document or a scene (JSON)",
                e.valid_up_to()
            )
        })?;
        if text.trim_start().starts_with('{') {
            let scene = Scene::from_json(text, name, None)?;
            Document::from_scene(scene, name)
        } else {
            Document::from_svg(name, text)
        }
    }

    /// Opens an SVG document: no handles, bounded biharmonic weights (Puppet Warp's shape-aware
    /// behaviour; the page shows the same family on a coarser mesh while they compute).
    pub fn from_svg(name: &str, text: &str) -> Result<Document> {
        let scene = Scene::from_pins(PinnedDrawing {
            drawing: read_svg_named(text, &ImportOptions::default(), name)?,
            svg_text: text.to_string(),
            origin: name.to_string(),
            pins: Vec::new(),
            weights: WeightSpec::Mesh(MeshFamily::Bbw),
            domain: scene_domain_options(),
            pose: Vec::new(),
        })?;
        Document::from_scene(scene, name)
    }

    /// Opens a loaded scene. Its first pose is the one shown. Errors for what the editor cannot
    /// edit yet (bones, cages) and for drawings the library cannot read, naming the file.
    pub fn from_scene(scene: Scene, name: &str) -> Result<Document> {
        let mut warnings = check_editable(&scene, name)?;
        let weights = weights_wire(&scene, name)?;
        // The kinds the rig uses (the authors' saved kinds, then the scene's overrides) and
        // those classified from the geometry: the page gets the latter and, as overrides,
        // every joint where the two differ.
        let drawing = scene.drawing(Compat::None)?;
        // Read once: the scene keeps the drawing for the rig's junction kinds.
        let scene = scene.with_drawing(drawing.clone());
        let (rigged, more) = scene.drawing_with_junctions(Compat::None)?;
        warnings.extend(more);
        let junctions = junction_overrides(&rigged, &drawing);
        let pose = scene
            .pose(0)
            .map(|p| p.transforms.iter().map(|t| t.as_coeffs()).collect())
            .unwrap_or_default();
        let defop = page_defop(&scene, name, &mut warnings);
        let operator = defop.as_ref().map(|settings| OperatorInfo {
            family: defop_family(settings.energy),
            samples: settings.samples,
        });
        let edit = EditScene {
            handles: scene.handles.iter().map(|p| [p.x, p.y]).collect(),
            pose,
            weights: weights.clone(),
            junctions,
            flexible: scene.flexible,
            animation: scene.animation.as_ref().map(AnimationWire::of),
            margin: (scene.domain.margin != splineskin::domain::DEFAULT_MARGIN)
                .then_some(scene.domain.margin),
        };
        let extras = SceneExtras {
            arc_length: scene.measure == Measure::ArcLength,
            domain: (scene.domain != splineskin::scene::scene_domain_options())
                .then(|| scene.domain.clone()),
            defop,
            weights: Some(weights),
        };
        let rest = drawing.flat_points();
        // At rest every map is the identity; each element gets its own copies of its user-space
        // paint servers, which the page turns with the element's map.
        let at_rest = ElementMaps::from_map(&drawing, &mut |p| p, &FollowOptions::default())
            .with_context(|| format!("{name}: preparing the drawing for display"))?;
        let marks = SvgOptions::default()
            .with_marker(ELEMENT_MARKER)
            .with_carried_marker(CARRIED_MARKER)
            .with_follow(Some(&at_rest))
            .with_paint_marker(PAINT_MARKER);
        let svg = write_svg_with(&drawing, &rest, &marks)
            .with_context(|| format!("{name}: preparing the drawing for display"))?;
        let source = drawing
            .source
            .as_ref()
            .context("an imported drawing has its source")?;
        let elements = element_infos(&drawing, source);
        let mut painted = marked_indices(&svg, PAINT_MARKER);
        painted.extend(
            (elements.iter().enumerate()).filter_map(|(k, e)| e.stroke_frame.as_ref().map(|_| k)),
        );
        painted.sort_unstable();
        painted.dedup();
        let carried = carried_parents(&drawing)
            .with_context(|| format!("{name}: finding its text and images"))?;
        let info = DocumentInfo {
            id: String::new(),
            name: name.to_string(),
            svg,
            view_box: {
                let b = source.view_box();
                [b.x0, b.y0, b.width(), b.height()]
            },
            paths: path_infos(&drawing, source),
            elements,
            carried: carried.iter().map(|p| p.as_coeffs()).collect(),
            painted,
            rest: rest.iter().flat_map(|p| [p.x, p.y]).collect(),
            scene: edit,
            operator,
            warnings,
            n_curves: drawing.n_curves(),
        };
        Ok(Document {
            name: name.to_string(),
            svg_text: scene.svg_text.clone(),
            extras,
            folds: FoldCheck::new(&drawing, &rest),
            drawing,
            info,
            inserted: Vec::new(),
        })
    }

    /// The document of this one's drawing with adaptive control points: `drawing` is the
    /// refined rig's ([`splineskin::scene::Puppet::refined`]), `inserted` its new anchors (per
    /// path and joint, relative to this document's drawing), `scene` the page's scene on this
    /// document. The new document's SVG is this one's with the split curves written at rest and
    /// every inserted anchor so far listed in
    /// [`splineskin::drawing::svg_out::INSERTED_ATTRIBUTE`]; the scene's junction kinds move
    /// to the joints' new indices and the new anchors are G¹, as the rig has them.
    pub fn refined(
        &self,
        drawing: &Drawing,
        inserted: &[Vec<bool>],
        scene: &EditScene,
    ) -> Result<Document> {
        let name = &self.name;
        if inserted.len() != self.drawing.paths.len() {
            bail!(
                "{name}: the refined drawing has {} paths, expected {}",
                inserted.len(),
                self.drawing.paths.len()
            );
        }
        // Joint k of this document is the k-th joint of the refined path not inserted now.
        let moved: Vec<Vec<usize>> = inserted
            .iter()
            .map(|flags| (0..flags.len()).filter(|&j| !flags[j]).collect())
            .collect();
        let mut junctions = Vec::new();
        for j in &scene.junctions {
            let joint = moved
                .get(j.path)
                .and_then(|m| m.get(j.joint))
                .with_context(|| {
                    format!("{name}: junction {}:{}: no such joint", j.path, j.joint)
                })?;
            junctions.push(JunctionOverride {
                joint: *joint,
                ..*j
            });
        }
        for (p, flags) in inserted.iter().enumerate() {
            for (joint, _) in flags.iter().enumerate().filter(|(_, &new)| new) {
                junctions.push(JunctionOverride {
                    path: p,
                    joint,
                    kind: drawing.paths[p].joints[joint],
                });
            }
        }
        // Every inserted anchor so far: the earlier ones carried to their new indices.
        let so_far: Vec<Vec<bool>> = inserted
            .iter()
            .enumerate()
            .map(|(p, flags)| {
                let before = self.inserted.get(p);
                let mut all = flags.clone();
                for (k, &j) in moved[p].iter().enumerate() {
                    all[j] = before.and_then(|b| b.get(k)).copied().unwrap_or(false);
                }
                all
            })
            .collect();
        let svg_text = write_svg_with_inserted(
            drawing,
            &drawing.flat_points(),
            ViewBoxRule::Keep,
            None,
            &so_far,
        )
        .with_context(|| format!("{name}: writing the refined drawing"))?;
        let scene = EditScene {
            junctions,
            ..scene.clone()
        };
        let read = read_svg_named(&svg_text, &ImportOptions::default(), name)?;
        let scene = scene_of_page(name, &svg_text, read, &scene, &self.extras)?;
        let mut document = Document::from_scene(scene, name)?;
        if document.drawing.n_curves() != drawing.n_curves() {
            bail!(
                "{name}: the refined drawing read back with {} curves, expected {}",
                document.drawing.n_curves(),
                drawing.n_curves()
            );
        }
        for (path, flags) in document.info.paths.iter_mut().zip(&so_far) {
            path.inserted = flags.clone();
        }
        document.inserted = so_far;
        Ok(document)
    }

    /// The bundled drawing with its handles (the fish of `splineskin demo`).
    pub fn bundled() -> Result<Document> {
        let scene = splineskin::examples::demo_scene();
        let name = scene.origin.clone();
        Document::from_scene(scene, &name)
    }

    /// Opens the file given on the command line.
    pub fn from_path(path: &std::path::Path) -> Result<Document> {
        let name = path.display().to_string();
        let is_json = has_extension(path, "json");
        if is_json {
            // Scene::load resolves an SVG file named relative to the scene.
            let scene = Scene::load(path)?;
            return Document::from_scene(scene, &name);
        }
        let size = std::fs::metadata(path)
            .with_context(|| format!("{name}: cannot read"))?
            .len();
        if size > MAX_UPLOAD_BYTES as u64 {
            bail!("{name}: {size} bytes is more than the {MAX_UPLOAD_BYTES}-byte limit");
        }
        let bytes = std::fs::read(path).with_context(|| format!("{name}: cannot read"))?;
        Document::open(&name, &bytes)
    }
}

/// Whether `path`'s extension is `ext`, in any case.
fn has_extension(path: &std::path::Path, ext: &str) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case(ext))
}

/// Refuses what the editor cannot edit (bones, cages, scenes the library does not support);
/// the warnings of what it leaves out (a naive engine).
fn check_editable(scene: &Scene, name: &str) -> Result<Vec<String>> {
    scene.check_supported()?;
    let mut warnings = Vec::new();
    if !scene.bones.is_empty() || scene.cage.is_some() {
        bail!(
            "{name}: the editor places point handles only; this scene has {} bones{} \
             (deform it with `splineskin deform`)",
            scene.bones.len(),
            if scene.cage.is_some() {
                " and a cage"
            } else {
                ""
            }
        );
    }
    if scene.engine != Engine::Ours {
        warnings.push(format!(
            "{name}: engine '{}' (a naive baseline) is not used: the editor deforms with the \
             spline fit",
            scene.engine.name()
        ));
    }
    Ok(warnings)
}

/// The scene's weights as the page names them; an error for families that need a cage.
fn weights_wire(scene: &Scene, name: &str) -> Result<WeightsWire> {
    Ok(match &scene.weights {
        WeightSpec::Shepard { exponent } => WeightsWire {
            family: "shepard".into(),
            exponent: Some(*exponent),
            samples: None,
            coarse: false,
        },
        WeightSpec::Mesh(family) => WeightsWire {
            family: family.name().into(),
            exponent: None,
            samples: None,
            coarse: false,
        },
        other => bail!(
            "{name}: weight family '{}' needs a cage, which the editor does not edit yet",
            other.name()
        ),
    })
}

/// Every joint whose kind in `rigged` (the rig's) differs from `drawing`'s (classified from
/// the geometry), as the page's overrides.
fn junction_overrides(rigged: &Drawing, drawing: &Drawing) -> Vec<JunctionOverride> {
    let mut junctions = Vec::new();
    for (p, (a, b)) in rigged.paths.iter().zip(&drawing.paths).enumerate() {
        for (j, (&kind, &classified)) in a.joints.iter().zip(&b.joints).enumerate() {
            if kind != classified {
                junctions.push(JunctionOverride {
                    path: p,
                    joint: j,
                    kind,
                });
            }
        }
    }
    junctions
}

/// The scene's `defop` section, kept (and offered to the page) without its mesh and operator
/// files, which the editor does not use (it trains on the drawing's domain when the user picks
/// the operator): a warning for each left out.
fn page_defop(
    scene: &Scene,
    name: &str,
    warnings: &mut Vec<String>,
) -> Option<splineskin::scene::DefOpSettings> {
    let mut defop = scene.defop.clone();
    if let Some(settings) = &mut defop {
        for (key, file) in [
            ("mesh", settings.mesh.take()),
            ("operator", settings.operator.take()),
        ] {
            if let Some(file) = file {
                warnings.push(format!(
                    "{name}: defop.{key} ({}) is not used: the editor trains its operator on \
                     the drawing's domain (and saves the scene without it)",
                    file.display()
                ));
            }
        }
    }
    defop
}

/// Each imported element's paths and root → local map, for the page.
fn element_infos(drawing: &Drawing, source: &SvgSource) -> Vec<ElementInfo> {
    (0..source.n_elements())
        .map(|e| {
            let paths = source.element_paths(e).unwrap_or(0..0);
            let to_local = source
                .element_local_to_root(e)
                .map(|t| t.inverse().as_coeffs())
                .unwrap_or([1.0, 0.0, 0.0, 1.0, 0.0, 0.0]);
            ElementInfo {
                first_path: paths.start,
                end_path: paths.end,
                to_local,
                stroke_frame: stroke_frame_region(drawing, e).map(|r| StrokeFrameInfo {
                    centre: [r.centre.x, r.centre.y],
                    covariance: r.covariance,
                }),
            }
        })
        .collect()
}

/// Each path's shape for the page: closed or not, its points, joints and how it closes.
fn path_infos(drawing: &Drawing, source: &SvgSource) -> Vec<PathInfo> {
    drawing
        .paths
        .iter()
        .enumerate()
        .map(|(i, p)| PathInfo {
            closed: p.closed,
            n_points: p.points.len(),
            joints: p.joints.clone(),
            close_with_z: p.closed && !source.is_closed_without_z(i),
            inserted: vec![false; p.joints.len()],
        })
        .collect()
}
