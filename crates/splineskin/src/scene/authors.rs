//! The paper authors' scene format (`*-deformation.json`, saved by their web editor).
//!
//! | key | meaning |
//! |---|---|
//! | `gInputSVGText` | the SVG document |
//! | `gHandles` | `[{ "pos": [x, y], "transform": {a, b, c, d, e, f} }]`: rest position and the SVG matrix `[[a, c, e], [b, d, f]]` applied to absolute points |
//! | `gPathsControlPointConstraints` | per path, per joint `{ "continuity": "C0"│"C1"│"G1"│"A", "fixed": bool }`; `fixed` pins the joint to its rest position in their solver (not supported: refused; every saved scene has `false`) |
//! | `weightFunction` | `shepard`, `bbw`, `harmonic` |
//! | `engineType` | `ours` (default), `fourcontrols`, `twoendpoints`, `jacobian` |
//! | `usingArcLengthParameterization` | arc-length measure |
//! | `animationFrames` | optional list of frames, each a list of transforms (one per handle) |
//!
//! Pose 0 is the handles' saved transforms; animation frames follow as poses 1, 2, ….
//!
//! The animation frames are also the scene's [`Scene::animation`]: frame `k` is a keyframe at
//! time `k / AUTHORS_FPS` seconds (the file records no rate; their editor stored one entry per
//! drawn frame, which we take as 30 per second), sampled at [`AUTHORS_FPS`]. A scene whose
//! `animationFrames` is empty or missing has no animation.
//!
//! Their solver treats every `G1` and `A` joint as flexible (its tangent-length ratio free,
//! iterated; [`crate::spline_fit::flexible`]), so these scenes are read with
//! [`Scene::flexible`] set.

use kurbo::Affine;
use serde::Deserialize;

use crate::animation::{Animation, Keyframe, DEFAULT_FPS};

/// The time between the authors' `animationFrames` entries is `1 / AUTHORS_FPS` seconds:
/// [`DEFAULT_FPS`], 30 frames per second (their files record no rate).
pub const AUTHORS_FPS: f64 = DEFAULT_FPS;

use super::{
    check_affine, check_point, json_error, Engine, Pose, Scene, SceneError, SceneFormat, WeightSpec,
};
use crate::drawing::JointKind;
use crate::spline_fit::Measure;

#[derive(Deserialize)]
struct AuthorsFile {
    #[serde(rename = "gInputSVGText")]
    svg_text: String,
    #[serde(rename = "gHandles")]
    handles: Vec<AuthorsHandle>,
    #[serde(rename = "gPathsControlPointConstraints", default)]
    constraints: Vec<Vec<AuthorsConstraint>>,
    #[serde(rename = "weightFunction", default = "default_weight_function")]
    weight_function: String,
    #[serde(rename = "engineType", default)]
    engine_type: Option<String>,
    #[serde(rename = "usingArcLengthParameterization", default)]
    arc_length: bool,
    #[serde(rename = "animationFrames", default)]
    animation_frames: Vec<Vec<AuthorsMatrix>>,
    #[serde(default)]
    filename: Option<String>,
}

fn default_weight_function() -> String {
    "shepard".into()
}

#[derive(Deserialize)]
struct AuthorsHandle {
    pos: [f64; 2],
    transform: AuthorsMatrix,
}

#[derive(Deserialize, Clone, Copy)]
struct AuthorsMatrix {
    a: f64,
    b: f64,
    c: f64,
    d: f64,
    e: f64,
    f: f64,
}

impl AuthorsMatrix {
    fn affine(self) -> Affine {
        Affine::new([self.a, self.b, self.c, self.d, self.e, self.f])
    }
}

#[derive(Deserialize)]
struct AuthorsConstraint {
    continuity: String,
    #[serde(default)]
    fixed: bool,
}

/// Whether `text` looks like the authors' format (it has their `gInputSVGText` key).
pub(crate) fn looks_like_authors(text: &str) -> bool {
    text.contains("\"gInputSVGText\"")
}

/// Maps the authors' continuity names to ours.
pub fn authors_kind(name: &str) -> Option<JointKind> {
    Some(match name {
        "C0" => JointKind::C0,
        "C1" => JointKind::C1,
        "G1" => JointKind::G1,
        "A" => JointKind::FixedAngle,
        "None" => JointKind::End,
        _ => return None,
    })
}

pub(crate) fn parse(text: &str, origin: &str) -> Result<Scene, SceneError> {
    let file: AuthorsFile = serde_json::from_str(text).map_err(|e| json_error(origin, e))?;
    let handles = file
        .handles
        .iter()
        .enumerate()
        .map(|(i, h)| check_point(h.pos, origin, format!("gHandles[{i}].pos")))
        .collect::<Result<Vec<_>, _>>()?;
    let transforms = file
        .handles
        .iter()
        .enumerate()
        .map(|(i, h)| {
            check_affine(
                h.transform.affine(),
                origin,
                format!("gHandles[{i}].transform"),
            )
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mut poses = vec![Pose {
        name: None,
        transforms,
    }];
    for (k, frame) in file.animation_frames.iter().enumerate() {
        if frame.len() != handles.len() {
            return Err(SceneError::Invalid {
                origin: origin.to_string(),
                element: format!("animationFrames[{k}]"),
                message: format!("{} transforms for {} handles", frame.len(), handles.len()),
            });
        }
        let transforms = frame
            .iter()
            .enumerate()
            .map(|(i, m)| check_affine(m.affine(), origin, format!("animationFrames[{k}][{i}]")))
            .collect::<Result<Vec<_>, _>>()?;
        poses.push(Pose {
            name: Some(format!("frame {k}")),
            transforms,
        });
    }
    let animation = match poses.len() {
        1 => None,
        _ => {
            let keyframes = poses[1..]
                .iter()
                .enumerate()
                .map(|(k, p)| Keyframe::new(k as f64 / AUTHORS_FPS, p.transforms.clone()))
                .collect();
            Some(
                Animation::new(AUTHORS_FPS, keyframes).map_err(|e| SceneError::Invalid {
                    origin: origin.to_string(),
                    element: "animationFrames (keyframes[k] is animationFrames[k])".into(),
                    message: e.to_string(),
                })?,
            )
        }
    };
    let joints = file
        .constraints
        .iter()
        .enumerate()
        .map(|(p, path)| {
            path.iter()
                .enumerate()
                .map(|(j, c)| {
                    if c.fixed {
                        return Err(SceneError::NotImplemented {
                            origin: origin.to_string(),
                            what: format!(
                                "gPathsControlPointConstraints[{p}][{j}]: a fixed (pinned) joint"
                            ),
                        });
                    }
                    authors_kind(&c.continuity).ok_or_else(|| SceneError::Invalid {
                        origin: origin.to_string(),
                        element: format!("gPathsControlPointConstraints[{p}][{j}]"),
                        message: format!(
                            "unknown continuity '{}' (expected C0, C1, G1 or A)",
                            c.continuity
                        ),
                    })
                })
                .collect::<Result<Vec<_>, _>>()
        })
        .collect::<Result<Vec<_>, _>>()?;
    let engine = Engine::parse(file.engine_type.as_deref().unwrap_or("ours"), origin)?;
    let weights = WeightSpec::parse(&file.weight_function, None, origin)?;
    Ok(Scene {
        origin: origin.to_string(),
        svg_text: file.svg_text,
        svg_origin: format!(
            "{origin} (gInputSVGText{})",
            file.filename.map(|f| format!(", {f}")).unwrap_or_default()
        ),
        handles,
        bones: Vec::new(),
        cage: None,
        weights,
        domain: crate::domain::DomainOptions::default(),
        engine,
        measure: Measure::from_arc_length(file.arc_length),
        junctions: Vec::new(),
        authors_joints: Some(joints),
        poses,
        flexible: true,
        animation,
        defop: None,
        format: SceneFormat::Authors,
        read: Default::default(),
    })
}
