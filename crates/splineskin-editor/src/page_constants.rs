//! The names and limits the page shares with the routes, written as the JavaScript module
//! `crates/splineskin-cli/web/constants.js`, so that the page imports them instead of copying
//! them by hand: the weight families, operator families and their sample limits, the junction
//! kinds a click cycles through, the easings and frame rates of the timeline, the handle bases
//! of an operator, the domain's margin, the most poses one refinement measures and the
//! attributes that mark the shown document's elements, and the margin by which a stroke frame
//! is a reflection.
//!
//! The file is generated: `SPLINESKIN_WRITE_CONSTANTS=1 cargo test -p splineskin-cli
//! page_constants` writes it again, and the same test without the variable fails while the
//! file differs from [`javascript`].

use std::fmt::Write;

use splineskin::animation::{Easing, DEFAULT_FPS, MAX_FPS};
use splineskin::defop::HandleBasisKind;
use splineskin::domain::{DEFAULT_MARGIN, MAX_MARGIN};
use splineskin::drawing::follow::REFLECTION_MARGIN;
use splineskin::drawing::JointKind;
use splineskin::scene::MeshFamily;

use crate::defop_routes::MAX_EDITOR_SAMPLES;
use crate::document::{CARRIED_MARKER, ELEMENT_MARKER, PAINT_MARKER};
use crate::page_scene::{defop_family, DEFAULT_EDITOR_SAMPLES, DEFOP_ENERGIES};
use crate::request::MAX_REFINE_POSES;

/// The junction kinds a click on a junction marker cycles through, in that order.
pub const CYCLED_JUNCTION_KINDS: [JointKind; 4] = [
    JointKind::C0,
    JointKind::C1,
    JointKind::G1,
    JointKind::FixedAngle,
];

/// The weight families solved on a triangulated domain, as the page's menu lists them.
pub const MESH_FAMILIES: [MeshFamily; 3] = [
    MeshFamily::Bbw,
    MeshFamily::Harmonic,
    MeshFamily::Biharmonic,
];

/// The text of `constants.js`: one `export const` per shared value, each with the Rust item it
/// comes from.
///
/// ```
/// let js = splineskin_editor::page_constants::javascript();
/// assert!(js.contains("export const MAX_FPS = 1000;"));
/// assert!(js.contains("export const EASINGS = ['linear', 'ease-in', 'ease-out', 'ease-in-out', 'hold'];"));
/// ```
pub fn javascript() -> String {
    let mut js = String::from(
        "// Generated from Rust (splineskin_editor::page_constants): do not edit. After a change there,\n\
         // SPLINESKIN_WRITE_CONSTANTS=1 cargo test -p splineskin-cli page_constants writes it again.\n",
    );
    let mut constant = |doc: &str, name: &str, value: String| {
        // Writing to a String cannot fail.
        let _ = write!(js, "\n/** {doc} */\nexport const {name} = {value};\n");
    };
    constant(
        "Weight families solved on a triangulated domain (splineskin::scene::MeshFamily).",
        "MESH_FAMILIES",
        list(MESH_FAMILIES.map(MeshFamily::name)),
    );
    constant(
        "Operator families, by ground truth (splineskin_editor::page_scene::defop_family).",
        "DEFOP_FAMILIES",
        list(DEFOP_ENERGIES.map(defop_family)),
    );
    constant(
        "Training samples of an operator when the user has not chosen (DEFAULT_EDITOR_SAMPLES).",
        "DEFAULT_DEFOP_SAMPLES",
        DEFAULT_EDITOR_SAMPLES.to_string(),
    );
    constant(
        "Most training samples the routes take (MAX_EDITOR_SAMPLES).",
        "MAX_DEFOP_SAMPLES",
        MAX_EDITOR_SAMPLES.to_string(),
    );
    constant(
        "Handle bases of an operator (splineskin::defop::HandleBasisKind).",
        "HANDLE_BASIS_KINDS",
        list(HandleBasisKind::ALL.map(HandleBasisKind::name)),
    );
    constant(
        "Junction kinds a click on a junction marker cycles through (splineskin::drawing::JointKind).",
        "JUNCTION_KINDS",
        list(CYCLED_JUNCTION_KINDS.map(JointKind::name)),
    );
    constant(
        "Easings of a keyframe, in menu order (splineskin::animation::Easing).",
        "EASINGS",
        list(Easing::ALL.map(Easing::name)),
    );
    constant(
        "Frames per second of an animation that names none.",
        "DEFAULT_FPS",
        DEFAULT_FPS.to_string(),
    );
    constant(
        "Most frames per second of an animation.",
        "MAX_FPS",
        MAX_FPS.to_string(),
    );
    constant(
        "The art-shaped domain's margin, a fraction of the diagonal: its default (splineskin::domain).",
        "DEFAULT_MARGIN",
        DEFAULT_MARGIN.to_string(),
    );
    constant(
        "The largest margin (splineskin::domain::MAX_MARGIN).",
        "MAX_MARGIN",
        MAX_MARGIN.to_string(),
    );
    constant(
        "Most poses one refinement request measures (MAX_REFINE_POSES).",
        "MAX_REFINE_POSES",
        MAX_REFINE_POSES.to_string(),
    );
    constant(
        "The attribute marking each imported element of the shown document (ELEMENT_MARKER).",
        "ELEMENT_MARKER",
        format!("'{ELEMENT_MARKER}'"),
    );
    constant(
        "The attribute marking each carried text and image of the shown document (CARRIED_MARKER).",
        "CARRIED_MARKER",
        format!("'{CARRIED_MARKER}'"),
    );
    constant(
        "The attribute marking each element's own copy of a user-space paint server (PAINT_MARKER).",
        "PAINT_MARKER",
        format!("'{PAINT_MARKER}'"),
    );
    constant(
        "How much better a reflection must fit an element's region than a rotation to be its stroke frame (splineskin::drawing::follow::REFLECTION_MARGIN).",
        "REFLECTION_MARGIN",
        REFLECTION_MARGIN.to_string(),
    );
    js
}

/// A JavaScript array of strings, `['a', 'b']`.
fn list<const N: usize>(names: [&str; N]) -> String {
    let quoted: Vec<String> = names.iter().map(|name| format!("'{name}'")).collect();
    format!("[{}]", quoted.join(", "))
}
