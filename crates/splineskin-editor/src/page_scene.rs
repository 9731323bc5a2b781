//! The page's scene as a [`Scene`] of the library: the page's [`EditScene`] on a document's
//! drawing (already read), with what the opened scene carried besides ([`SceneExtras`]),
//! checked as a scene file of ours is checked. "Save scene" writes it with
//! [`Scene::to_json`], the drawing inline; the command line reads that file as the editor
//! made it.

use kurbo::{Affine, Point};
use splineskin::animation::{Animation, Easing, Keyframe};
use splineskin::defop::Energy;
use splineskin::domain::DomainOptions;
use splineskin::drawing::Drawing;
use splineskin::scene::pinned::PinnedDrawing;
use splineskin::scene::{scene_domain_options, DefOpSettings, Scene, SceneError, WeightSpec};
use splineskin::spline_fit::Measure;

use crate::wire::{AnimationWire, EditScene, WeightsWire};

/// Training samples when the page names none: 100. Measured in the editor with a release
/// build on two cores shared with other builds (thin-plate splines, the domain of
/// [`editor_defop_settings`]): the bundled fish (5 handles, 3 714
/// triangles) trains in 4.6 s on symmetric ARAP (8–10 s under a load of 3.5; 19 of its 100
/// samples fall back to a start from the rest pose; 60 samples on ARAP: 0.5–1.1 s), the
/// octopus (9 handles, 2 240 triangles) in 2.7–2.9 s (discs of 0.05 of the diagonal) and
/// 3.8 s (its scene's discs of 0.1) on symmetric ARAP.
pub const DEFAULT_EDITOR_SAMPLES: usize = 100;

/// The operators' ground truths, in the order the page's weights menu lists them.
pub const DEFOP_ENERGIES: [Energy; 2] = [Energy::Arap, Energy::SymmetricArap];

/// The page's "family" name of an operator trained on `energy`: `defop-arap`, `defop-sarap`.
pub fn defop_family(energy: Energy) -> &'static str {
    match energy {
        Energy::Arap => "defop-arap",
        Energy::SymmetricArap => "defop-sarap",
    }
}

/// The ground truth of the operator "family" `family` (see [`defop_family`]), or `None` for a
/// weight family.
///
/// ```
/// use splineskin::defop::Energy;
/// use splineskin_editor::page_scene::defop_energy;
/// assert_eq!(defop_energy("defop-sarap"), Some(Energy::SymmetricArap));
/// assert_eq!(defop_energy("bbw"), None);
/// ```
pub fn defop_energy(family: &str) -> Option<Energy> {
    DEFOP_ENERGIES
        .into_iter()
        .find(|&energy| defop_family(energy) == family)
}

/// What a scene carries besides the page's [`EditScene`] and is kept as it was opened.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SceneExtras {
    /// Integrate along arc length (the scene's `arc_length`).
    pub arc_length: bool,
    /// Domain options of the mesh families, when not the defaults.
    pub domain: Option<DomainOptions>,
    /// The scene's `defop` section (`splineskin::scene::defop`), without `mesh` and
    /// `operator` (the editor trains on the drawing's domain).
    pub defop: Option<DefOpSettings>,
    /// The scene's weights as opened: written back while the page shows an operator (default
    /// Shepard).
    pub weights: Option<WeightsWire>,
}

/// The operator settings the editor trains with when a scene has no `defop` section: the
/// library's defaults ([`DefOpSettings::default`]: the drawing's domain as
/// [`splineskin::defop::training_domain_options`] triangulates it, hats, thin-plate splines, discs of
/// `splineskin::defop::DEFAULT_DISC_FRACTION` of the diagonal, seed 1) with
/// [`DEFAULT_EDITOR_SAMPLES`] samples, for trainings of seconds.
pub fn editor_defop_settings() -> DefOpSettings {
    let mut settings = DefOpSettings::default();
    settings.samples = DEFAULT_EDITOR_SAMPLES;
    settings
}

/// The `defop` section the page's scene implies: `None` unless its "family" is an operator or
/// the opened scene had one; the page's energy and sample count over the opened settings (or
/// [`editor_defop_settings`]). The page's sample count must be at least 1 (error element `defop.samples`, as in a scene
/// file).
fn defop_settings(
    scene: &EditScene,
    extras: &SceneExtras,
    origin: &str,
) -> Result<Option<DefOpSettings>, SceneError> {
    match defop_energy(&scene.weights.family) {
        Some(energy) => {
            let mut settings = extras.defop.clone().unwrap_or_else(editor_defop_settings);
            settings.energy = energy;
            if let Some(samples) = scene.weights.samples {
                if samples == 0 {
                    return Err(SceneError::invalid(
                        origin,
                        "defop.samples",
                        "0: expected at least 1",
                    ));
                }
                settings.samples = samples;
            }
            Ok(Some(settings))
        }
        None => Ok(extras.defop.clone()),
    }
}

/// The domain options of the page's scene: the opened scene's (`None`: the defaults) with the
/// page's margin ([`EditScene::margin`]) when it set one.
fn page_domain(scene: &EditScene, extras: &SceneExtras) -> Option<DomainOptions> {
    match scene.margin {
        None => extras.domain.clone(),
        Some(margin) => {
            let mut domain = extras.domain.clone().unwrap_or_else(scene_domain_options);
            domain.margin = margin;
            Some(domain)
        }
    }
}

/// The weights of the page's scene: its family's, or while it shows an operator the opened
/// scene's ([`SceneExtras::weights`], default Shepard), as a scene file would hold them.
fn page_weights(
    scene: &EditScene,
    extras: &SceneExtras,
    origin: &str,
) -> Result<WeightSpec, SceneError> {
    let wire = match (defop_energy(&scene.weights.family), &extras.weights) {
        (None, _) => &scene.weights,
        (Some(_), Some(opened)) => opened,
        (Some(_), None) => return WeightSpec::parse("shepard", None, origin),
    };
    WeightSpec::parse(&wire.family, wire.exponent, origin)
}

/// The page's timeline as keyframed poses, checked as a scene file's `animation` is (easing
/// names, frame rate, times).
fn page_animation(wire: &AnimationWire, origin: &str) -> Result<Animation, SceneError> {
    let keyframes = wire
        .keyframes
        .iter()
        .enumerate()
        .map(|(k, key)| {
            let easing = Easing::parse(&key.easing).map_err(|e| {
                SceneError::invalid(
                    origin,
                    format!("animation.keyframes[{k}].easing"),
                    e.to_string(),
                )
            })?;
            Ok(Keyframe {
                time: key.time,
                transforms: key.pose.iter().map(|&m| Affine::new(m)).collect(),
                easing,
            })
        })
        .collect::<Result<Vec<_>, SceneError>>()?;
    Animation::new(wire.fps, keyframes).map_err(|e| SceneError::animation(origin, e))
}

/// The scene of the page's `scene` on the drawing `drawing`, read from `svg_text` and named
/// `origin`, with the opened scene's `extras`: the values a scene file of ours written of them
/// would give, checked the same way ([`Scene::from_pins`], [`Scene::with_junctions`],
/// [`Scene::with_animation`]); the drawing is not read again. Domain options are kept for the
/// mesh families only (an authors' scene keeps its enclosing domain while its weights are on a
/// mesh).
pub fn scene_of_page(
    origin: &str,
    svg_text: &str,
    drawing: Drawing,
    scene: &EditScene,
    extras: &SceneExtras,
) -> Result<Scene, SceneError> {
    let weights = page_weights(scene, extras, origin)?;
    let domain = page_domain(scene, extras)
        .filter(|_| matches!(weights, WeightSpec::Mesh(_)))
        .unwrap_or_else(scene_domain_options);
    let defop = defop_settings(scene, extras, origin)?;
    let mut made = Scene::from_pins(PinnedDrawing {
        drawing,
        svg_text: svg_text.to_string(),
        origin: origin.to_string(),
        pins: scene
            .handles
            .iter()
            .map(|&[x, y]| Point::new(x, y))
            .collect(),
        weights,
        domain,
        pose: scene.pose.iter().map(|&m| Affine::new(m)).collect(),
    })?;
    made.measure = Measure::from_arc_length(extras.arc_length);
    made.flexible = scene.flexible;
    made.defop = defop;
    let made = made.with_junctions(scene.junctions.clone())?;
    match &scene.animation {
        Some(wire) => made.with_animation(page_animation(wire, origin)?),
        None => Ok(made),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::document::Document;
    use crate::wire::KeyframeWire;
    use splineskin::drawing::JointKind;
    use splineskin::scene::ours_write::SvgRef;
    use splineskin::scene::JunctionOverride;

    /// The page's scene of the bundled fish, with a junction kind, a margin and a timeline of
    /// two keyframes, on bounded biharmonic weights.
    fn page(document: &Document) -> EditScene {
        let mut scene = document.info.scene.clone();
        scene.weights = WeightsWire {
            family: "bbw".into(),
            exponent: None,
            samples: None,
            coarse: false,
        };
        scene.margin = Some(0.02);
        scene.junctions = vec![JunctionOverride {
            path: 0,
            joint: 1,
            kind: JointKind::C0,
        }];
        scene.pose[1] = [1.0, 0.0, 0.0, 1.0, 12.0, -5.0];
        let key = |time, pose: &Vec<[f64; 6]>| KeyframeWire {
            time,
            pose: pose.clone(),
            easing: "ease-in".into(),
        };
        let rest = vec![[1.0, 0.0, 0.0, 1.0, 0.0, 0.0]; scene.handles.len()];
        scene.animation = Some(AnimationWire {
            fps: 24.0,
            keyframes: vec![key(0.0, &rest), key(1.5, &scene.pose)],
        });
        scene
    }

    fn of_page(document: &Document, scene: &EditScene) -> Result<Scene, SceneError> {
        let name = &document.name;
        let drawing = document.drawing.clone();
        scene_of_page(name, &document.svg_text, drawing, scene, &document.extras)
    }

    /// The page's scene is the scene its saved file reads back as, and holds what the page set.
    #[test]
    fn page_scene_is_what_its_saved_file_reads_back_as() {
        let document = Document::bundled().expect("the bundled fish");
        let scene = page(&document);
        let made = of_page(&document, &scene).expect("the page's scene");
        let file = made
            .to_json(SvgRef::Inline(&document.svg_text))
            .expect("written");
        let mut back = Scene::from_json(&file, &document.name, None).expect("read back");
        // A file names its inline drawing after itself; the editor names it as the document.
        assert_eq!(back.svg_origin, format!("{} (svg_text)", document.name));
        back.svg_origin = made.svg_origin.clone();
        assert_eq!(back, made);
        assert_eq!(made.domain.margin, 0.02);
        assert_eq!(made.junctions.len(), 1);
        assert_eq!(made.poses[0].transforms[1], Affine::translate((12.0, -5.0)));
        let animation = made.animation.as_ref().expect("the timeline");
        assert_eq!(animation.fps(), 24.0);
        assert_eq!(animation.keyframes()[0].easing, Easing::EaseIn);
    }

    /// What a scene file of the same content would be refused for, the page's scene is
    /// refused for, naming the same element.
    #[test]
    fn page_scene_is_refused_as_its_file_would_be() {
        let document = Document::bundled().expect("the bundled fish");
        let refusal = |edit: &dyn Fn(&mut EditScene), element: &str| {
            let mut scene = page(&document);
            edit(&mut scene);
            let e = of_page(&document, &scene).expect_err(element).to_string();
            assert!(e.contains(&format!(": {element}: ")), "{element}: {e}");
        };
        refusal(
            &|s| s.junctions[0].kind = JointKind::End,
            "junctions[0].kind",
        );
        refusal(
            &|s| s.animation.as_mut().unwrap().keyframes[1].easing = "bounce".into(),
            "animation.keyframes[1].easing",
        );
        refusal(
            &|s| s.animation.as_mut().unwrap().fps = 0.0,
            "animation.fps",
        );
        refusal(&|s| s.pose[2][4] = 1e12, "poses[0].transforms[2]");
        refusal(&|s| s.handles[3][0] = -1e12, "handles[3].position");
        refusal(&|s| s.weights.family = "cubic".into(), "weights");
        refusal(
            &|s| {
                s.weights.family = defop_family(Energy::Arap).into();
                s.weights.samples = Some(0);
            },
            "defop.samples",
        );
    }
}
