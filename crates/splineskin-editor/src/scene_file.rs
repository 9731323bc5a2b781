//! The page's scene written as a scene file of ours (`splineskin_scene: 1`, format in
//! `splineskin::scene::ours`), with the drawing inline (`svg_text`): what "Save scene"
//! downloads, and what the server reads back ([`splineskin::scene::Scene::from_json`]) to
//! validate and rig the page's scene, so that the editor and the command line agree on every
//! scene.

use serde::Serialize;
use splineskin::defop::Energy;
use splineskin::domain::DomainOptions;
pub use splineskin::scene::ours_write::SvgRef;
use splineskin::scene::ours_write::{DefOpOut, DomainOut};
use splineskin::scene::DefOpSettings;

use crate::wire::{AnimationWire, EditScene, JunctionWire, WeightsWire};

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
/// use splineskin_editor::scene_file::defop_energy;
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
/// [`editor_defop_settings`]).
pub fn defop_settings(scene: &EditScene, extras: &SceneExtras) -> Option<DefOpSettings> {
    match defop_energy(&scene.weights.family) {
        Some(energy) => {
            let mut settings = extras.defop.clone().unwrap_or_else(editor_defop_settings);
            settings.energy = energy;
            if let Some(samples) = scene.weights.samples {
                settings.samples = samples;
            }
            Some(settings)
        }
        None => extras.defop.clone(),
    }
}

#[derive(Serialize)]
struct SceneFile<'a> {
    splineskin_scene: u32,
    #[serde(skip_serializing_if = "Option::is_none")]
    svg: Option<&'a str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    svg_text: Option<&'a str>,
    handles: Vec<HandleFile>,
    weights: &'a WeightsWire,
    #[serde(skip_serializing_if = "Option::is_none")]
    domain: Option<DomainOut>,
    arc_length: bool,
    flexible: bool,
    junctions: &'a [JunctionWire],
    pose: &'a [[f64; 6]],
    #[serde(skip_serializing_if = "Option::is_none")]
    animation: Option<&'a AnimationWire>,
    #[serde(skip_serializing_if = "Option::is_none")]
    defop: Option<DefOpOut>,
}

#[derive(Serialize)]
struct HandleFile {
    position: [f64; 2],
}

/// Whether `family` (a scene's weight family name) is solved on a triangulated domain.
fn is_mesh_family(family: &str) -> bool {
    use splineskin::scene::MeshFamily;
    [
        MeshFamily::Harmonic,
        MeshFamily::Biharmonic,
        MeshFamily::Bbw,
    ]
    .iter()
    .any(|f| f.name() == family)
}

/// The domain options a written scene carries: the opened scene's (`None`: the defaults) with
/// the page's margin ([`EditScene::margin`]) when it set one.
fn page_domain(scene: &EditScene, extras: &SceneExtras) -> Option<DomainOptions> {
    match scene.margin {
        None => extras.domain.clone(),
        Some(margin) => {
            let mut domain = extras
                .domain
                .clone()
                .unwrap_or_else(splineskin::scene::scene_domain_options);
            domain.margin = margin;
            Some(domain)
        }
    }
}

/// The scene file text (pretty JSON) of `scene` on the drawing `svg_text`, inline. While the
/// page shows an operator, the file's weights are the opened scene's
/// ([`SceneExtras::weights`], default Shepard) and its `defop` section says how the operator
/// was trained ([`defop_settings`]).
pub fn scene_json(svg_text: &str, scene: &EditScene, extras: &SceneExtras) -> String {
    scene_json_with(SvgRef::Inline(svg_text), scene, extras)
}

/// [`scene_json`] with the drawing inline or named as a file ([`SvgRef`]).
pub fn scene_json_with(svg: SvgRef<'_>, scene: &EditScene, extras: &SceneExtras) -> String {
    let shepard = WeightsWire {
        family: "shepard".into(),
        exponent: Some(2.0),
        samples: None,
        coarse: false,
    };
    let weights = if defop_energy(&scene.weights.family).is_some() {
        extras.weights.as_ref().unwrap_or(&shepard)
    } else {
        &scene.weights
    };
    let defop = defop_settings(scene, extras).map(|s| DefOpOut::of(&s));
    let file = SceneFile {
        splineskin_scene: splineskin::scene::ours::SCENE_VERSION,
        svg: match svg {
            SvgRef::File(name) => Some(name),
            SvgRef::Inline(_) => None,
        },
        svg_text: match svg {
            SvgRef::Inline(text) => Some(text),
            SvgRef::File(_) => None,
        },
        handles: scene
            .handles
            .iter()
            .map(|&position| HandleFile { position })
            .collect(),
        weights,
        // Domain options apply to the mesh families only (the reader refuses them otherwise):
        // an authors' scene keeps its enclosing domain while its weights are on a mesh.
        domain: page_domain(scene, extras)
            .as_ref()
            .filter(|_| is_mesh_family(&weights.family))
            .map(DomainOut::of),
        arc_length: extras.arc_length,
        flexible: scene.flexible,
        junctions: &scene.junctions,
        pose: &scene.pose,
        animation: scene.animation.as_ref(),
        defop,
    };
    serde_json::to_string_pretty(&file).expect("plain structs of strings and numbers serialise")
}
