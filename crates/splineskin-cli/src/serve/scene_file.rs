//! The page's scene written as a scene file of ours (`splineskin_scene: 1`, format in
//! `splineskin::scene::ours`), with the drawing inline (`svg_text`): what "Save scene"
//! downloads, and what the server reads back ([`splineskin::scene::Scene::from_json`]) to
//! validate and rig the page's scene, so that the editor and the command line agree on every
//! scene.

use serde::Serialize;
use splineskin::domain::DomainOptions;

use super::wire::{EditScene, JunctionWire, WeightsWire};

/// What a scene carries besides the page's [`EditScene`] and is kept as it was opened.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SceneExtras {
    /// Integrate along arc length (the scene's `arc_length`).
    pub arc_length: bool,
    /// Domain options of the mesh families, when not the defaults.
    pub domain: Option<DomainOptions>,
}

#[derive(Serialize)]
struct SceneFile<'a> {
    splineskin_scene: u32,
    svg_text: &'a str,
    handles: Vec<HandleFile>,
    weights: &'a WeightsWire,
    #[serde(skip_serializing_if = "Option::is_none")]
    domain: Option<DomainFile>,
    arc_length: bool,
    flexible: bool,
    junctions: &'a [JunctionWire],
    pose: &'a [[f64; 6]],
}

#[derive(Serialize)]
struct HandleFile {
    position: [f64; 2],
}

#[derive(Serialize)]
struct DomainFile {
    min_angle: f64,
    max_area_fraction: f64,
    holes: bool,
    max_vertices: usize,
    samples_per_diagonal: f64,
    max_samples_per_curve: usize,
    max_curve_samples: usize,
    padding: f64,
}

/// The scene file text (pretty JSON) of `scene` on the drawing `svg_text`.
pub fn scene_json(svg_text: &str, scene: &EditScene, extras: &SceneExtras) -> String {
    let file = SceneFile {
        splineskin_scene: splineskin::scene::ours::SCENE_VERSION,
        svg_text,
        handles: scene
            .handles
            .iter()
            .map(|&position| HandleFile { position })
            .collect(),
        weights: &scene.weights,
        domain: extras.domain.as_ref().map(|d| DomainFile {
            min_angle: d.min_angle,
            max_area_fraction: d.max_area_fraction,
            holes: d.holes,
            max_vertices: d.max_vertices,
            samples_per_diagonal: d.samples_per_diagonal,
            max_samples_per_curve: d.max_samples_per_curve,
            max_curve_samples: d.max_curve_samples,
            padding: d.padding,
        }),
        arc_length: extras.arc_length,
        flexible: scene.flexible,
        junctions: &scene.junctions,
        pose: &scene.pose,
    };
    serde_json::to_string_pretty(&file).expect("plain structs of strings and numbers serialise")
}
