//! Writing a scene as a file of ours ([`Scene::to_json`]): the inverse of the reader in
//! [`super::ours`], so that what the library reads it can write, and reading the written file
//! gives the same scene. `splineskin rig` writes the scene of a drawing and its pins with it.

use serde::Serialize;

use super::defop::{energy_name, Cover, DefOpSettings, RegionSpec};
use super::ours::SCENE_VERSION;
use super::{
    scene_domain_options, BoneTransform, Engine, JunctionOverride, Scene, SceneError, SceneFormat,
    WeightSpec,
};
use crate::animation::Animation;
use crate::domain::DomainOptions;
use crate::spline_fit::Measure;

/// Where a written scene's drawing is.
#[derive(Clone, Copy, Debug)]
pub enum SvgRef<'a> {
    /// The document itself, inline (`svg_text`).
    Inline(&'a str),
    /// A file name, relative to the scene's folder (`svg`).
    File(&'a str),
}

#[derive(Serialize)]
struct SceneOut<'a> {
    splineskin_scene: u32,
    #[serde(skip_serializing_if = "Option::is_none")]
    svg: Option<&'a str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    svg_text: Option<&'a str>,
    handles: Vec<HandleOut>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    bones: Vec<BoneOut>,
    #[serde(skip_serializing_if = "Option::is_none")]
    cage: Option<Vec<[f64; 2]>>,
    weights: WeightsOut,
    #[serde(skip_serializing_if = "Option::is_none")]
    domain: Option<DomainOut>,
    arc_length: bool,
    flexible: bool,
    #[serde(skip_serializing_if = "Option::is_none")]
    engine: Option<&'static str>,
    junctions: &'a [JunctionOverride],
    #[serde(skip_serializing_if = "Option::is_none")]
    pose: Option<Vec<[f64; 6]>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    poses: Option<Vec<PoseOut>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    animation: Option<AnimationOut>,
    #[serde(skip_serializing_if = "Option::is_none")]
    defop: Option<DefOpOut>,
}

#[derive(Serialize)]
struct HandleOut {
    position: [f64; 2],
}

#[derive(Serialize)]
struct BoneOut {
    ends: [[f64; 2]; 2],
    transform: &'static str,
}

#[derive(Serialize)]
struct WeightsOut {
    family: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    exponent: Option<f64>,
}

#[derive(Serialize)]
struct PoseOut {
    #[serde(skip_serializing_if = "Option::is_none")]
    name: Option<String>,
    transforms: Vec<[f64; 6]>,
}

#[derive(Serialize)]
struct AnimationOut {
    fps: f64,
    keyframes: Vec<KeyframeOut>,
}

#[derive(Serialize)]
struct KeyframeOut {
    time: f64,
    pose: Vec<[f64; 6]>,
    easing: &'static str,
}

/// A scene's `domain` section as written: every option (the reader sets each over its
/// defaults).
#[derive(Clone, Debug, Serialize)]
struct DomainOut {
    min_angle: f64,
    max_area_fraction: f64,
    holes: bool,
    max_vertices: usize,
    samples_per_diagonal: f64,
    max_samples_per_curve: usize,
    max_curve_samples: usize,
    padding: f64,
    shape: &'static str,
    margin: f64,
}

impl DomainOut {
    /// The section of `d`.
    fn of(d: &DomainOptions) -> DomainOut {
        DomainOut {
            min_angle: d.min_angle,
            max_area_fraction: d.max_area_fraction,
            holes: d.holes,
            max_vertices: d.max_vertices,
            samples_per_diagonal: d.samples_per_diagonal,
            max_samples_per_curve: d.max_samples_per_curve,
            max_curve_samples: d.max_curve_samples,
            padding: d.padding,
            shape: d.shape.name(),
            margin: d.margin,
        }
    }
}

/// A scene's `defop` section as written (the keys [`super::defop`] reads).
#[derive(Clone, Debug, Serialize)]
struct DefOpOut {
    energy: &'static str,
    spatial_basis: String,
    handle_basis: &'static str,
    samples: usize,
    region: RegionOut,
    seed: u64,
    #[serde(skip_serializing_if = "is_no_cover")]
    cover: &'static str,
    domain: DomainOut,
}

fn is_no_cover(cover: &&'static str) -> bool {
    *cover == Cover::None.name()
}

#[derive(Clone, Copy, Debug, Serialize)]
#[serde(rename_all = "lowercase")]
enum RegionOut {
    Disc(f64),
    Circle(f64),
    Gaussian(f64),
}

impl Scene {
    /// The scene as a file of ours (pretty JSON, `splineskin_scene: 1`), its drawing at `svg`:
    /// reading it back ([`Scene::from_json`], from the folder a file name is relative to) gives
    /// the same handles, weights, domain, junction kinds, poses, animation and operator
    /// settings. A single unnamed pose is written as `pose`, more as `poses`; the domain only
    /// for a mesh family whose options are not the defaults.
    ///
    /// Errors ([`SceneError::Invalid`], naming the scene): a scene read from the authors'
    /// format (its saved junction kinds per path have no equivalent of ours), and an operator
    /// section naming a mesh or operator file (their paths were resolved against the folder
    /// the scene was read from).
    ///
    /// ```
    /// use splineskin::scene::{ours_write::SvgRef, Scene};
    /// let scene = splineskin::examples::demo_scene();
    /// let json = scene.to_json(SvgRef::Inline(&scene.svg_text))?;
    /// let back = Scene::from_json(&json, "again.json", None)?;
    /// assert_eq!(back.handles, scene.handles);
    /// assert_eq!(back.weights, scene.weights);
    /// assert_eq!(back.poses, scene.poses);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn to_json(&self, svg: SvgRef<'_>) -> Result<String, SceneError> {
        let invalid = |element: &str, message: &str| {
            Err(SceneError::invalid(
                &self.origin,
                element,
                message.to_string(),
            ))
        };
        if self.format == SceneFormat::Authors {
            return invalid(
                "gInputSVGText",
                "a scene of the authors' format is not written as ours (its saved junction kinds \
                 per path have no equivalent)",
            );
        }
        let defop = match &self.defop {
            Some(d) if d.mesh.is_some() || d.operator.is_some() => {
                return invalid(
                    "defop",
                    "an operator section naming a mesh or operator file is not written (the \
                     paths were resolved against the scene's folder)",
                )
            }
            Some(d) => Some(DefOpOut::of(d)),
            None => None,
        };
        let (pose, poses) = poses_out(self);
        let file = SceneOut {
            splineskin_scene: SCENE_VERSION,
            svg: match svg {
                SvgRef::File(name) => Some(name),
                SvgRef::Inline(_) => None,
            },
            svg_text: match svg {
                SvgRef::Inline(text) => Some(text),
                SvgRef::File(_) => None,
            },
            handles: self
                .handles
                .iter()
                .map(|p| HandleOut {
                    position: [p.x, p.y],
                })
                .collect(),
            bones: self.bones.iter().map(bone_out).collect(),
            cage: self
                .cage
                .as_ref()
                .map(|c| c.iter().map(|p| [p.x, p.y]).collect()),
            weights: weights_out(&self.weights),
            domain: (matches!(self.weights, WeightSpec::Mesh(_))
                && self.domain != scene_domain_options())
            .then(|| DomainOut::of(&self.domain)),
            arc_length: self.measure == Measure::ArcLength,
            flexible: self.flexible,
            engine: (self.engine != Engine::Ours).then(|| self.engine.name()),
            junctions: &self.junctions,
            pose,
            poses,
            animation: self.animation.as_ref().map(animation_out),
            defop,
        };
        serde_json::to_string_pretty(&file)
            .map_err(|e| SceneError::invalid(&self.origin, "scene", format!("writing it: {e}")))
    }
}

/// The scene's poses as written: one unnamed pose as `pose` (first), others as `poses`.
#[allow(clippy::type_complexity)]
fn poses_out(scene: &Scene) -> (Option<Vec<[f64; 6]>>, Option<Vec<PoseOut>>) {
    let matrices =
        |transforms: &[kurbo::Affine]| transforms.iter().map(|t| t.as_coeffs()).collect();
    match scene.poses.as_slice() {
        [] => (None, None),
        [only] if only.name.is_none() => (Some(matrices(&only.transforms)), None),
        poses => {
            let poses = poses
                .iter()
                .map(|p| PoseOut {
                    name: p.name.clone(),
                    transforms: matrices(&p.transforms),
                })
                .collect();
            (None, Some(poses))
        }
    }
}

fn bone_out(bone: &super::Bone) -> BoneOut {
    let [a, b] = bone.ends;
    BoneOut {
        ends: [[a.x, a.y], [b.x, b.y]],
        transform: match bone.transform {
            BoneTransform::Rigid => "rigid",
            BoneTransform::Affine => "affine",
        },
    }
}

fn weights_out(weights: &WeightSpec) -> WeightsOut {
    WeightsOut {
        family: weights.name().to_string(),
        exponent: match weights {
            WeightSpec::Shepard { exponent } => Some(*exponent),
            _ => None,
        },
    }
}

fn animation_out(animation: &Animation) -> AnimationOut {
    AnimationOut {
        fps: animation.fps(),
        keyframes: animation
            .keyframes()
            .iter()
            .map(|k| KeyframeOut {
                time: k.time,
                pose: k.transforms.iter().map(|t| t.as_coeffs()).collect(),
                easing: k.easing.name(),
            })
            .collect(),
    }
}

impl DefOpOut {
    /// The section of `d` (its mesh and operator file names left out: see [`Scene::to_json`]).
    pub fn of(d: &DefOpSettings) -> DefOpOut {
        DefOpOut {
            energy: energy_name(d.energy),
            spatial_basis: d.spatial_basis.name(),
            handle_basis: d.handle_basis.name(),
            samples: d.samples,
            region: match d.region {
                RegionSpec::Disc(f) => RegionOut::Disc(f),
                RegionSpec::Circle(f) => RegionOut::Circle(f),
                RegionSpec::Gaussian(f) => RegionOut::Gaussian(f),
            },
            seed: d.seed,
            cover: d.cover.name(),
            domain: DomainOut::of(&d.domain),
        }
    }
}

#[cfg(test)]
mod tests {
    use kurbo::Point;

    use super::*;
    use crate::drawing::{read_svg, ImportOptions};
    use crate::scene::pinned::PinnedDrawing;

    const SVG: &str = "<svg xmlns='http://www.w3.org/2000/svg' viewBox='0 0 10 10'>\
        <path d='M1 1 C2 1 3 1 4 1 C5 2 5 3 4 4 C3 4 2 4 1 4 Z' fill='red'/></svg>";

    /// `scene` written inline and read back under the same name: the same scene (whose drawing
    /// origin is then the inline text's).
    fn round_trip(scene: &Scene) {
        let json = scene
            .to_json(SvgRef::Inline(&scene.svg_text))
            .expect("written");
        let back = Scene::from_json(&json, &scene.origin, None).expect("read back");
        let expected = Scene {
            svg_origin: format!("{} (svg_text)", scene.origin),
            ..scene.clone()
        };
        assert_eq!(back, expected, "{json}");
        // And written again, the same text.
        assert_eq!(back.to_json(SvgRef::Inline(&back.svg_text)).unwrap(), json);
    }

    #[test]
    fn bundled_scenes_round_trip() {
        for scene in [
            crate::examples::demo_scene(),
            crate::examples::octopus_scene(),
            crate::examples::script_scene(),
        ] {
            round_trip(&scene);
        }
    }

    /// Bones, a cage, named poses, an animation with easings, junction kinds, a domain, arc
    /// length, flexible junctions and an operator section: every part of the format.
    #[test]
    fn every_part_of_the_format_round_trips() {
        let svg = serde_json::to_string(SVG).unwrap();
        let json = format!(
            r#"{{"splineskin_scene": 1, "svg_text": {svg},
              "handles": [{{"position": [2, 2]}}],
              "bones": [{{"ends": [[3, 2], [3, 3]]}}, {{"ends": [[2, 3], [2.5, 3.5]], "transform": "affine"}}],
              "cage": [[0, 0], [9, 0], [9, 9], [0, 9]],
              "weights": {{"family": "bbw"}},
              "domain": {{"margin": 0.05, "min_angle": 25}},
              "arc_length": true, "flexible": true,
              "junctions": [{{"path": 0, "joint": 1, "kind": "G1"}}],
              "poses": [
                {{"name": "rest", "transforms": [[1,0,0,1,0,0],[1,0,0,1,0,0],[1,0,0,1,0,0],[1,0,0,1,0,0],[1,0,0,1,0,0],[1,0,0,1,0,0],[1,0,0,1,0,0]]}},
                {{"name": "up", "transforms": [{{"translate": [0, -1]}}, {{"rotate": 10}}, {{"translate": [1, 0]}}, {{}}, {{}}, {{"translate": [0.5, 0]}}, {{}}]}}
              ],
              "animation": {{"fps": 12, "keyframes": [
                {{"time": 0, "pose": "rest", "easing": "ease-in"}},
                {{"time": 1.5, "pose": 1, "easing": "hold"}},
                {{"time": 2, "pose": 0}}
              ]}},
              "defop": {{"energy": "arap", "samples": 12, "region": {{"circle": 0.1}}, "seed": 7, "cover": "poses"}}
            }}"#
        );
        let scene = Scene::from_json(&json, "every.json", None).expect("the test scene reads");
        assert_eq!(scene.n_handles(), 1 + 2 + 4);
        round_trip(&scene);
    }

    #[test]
    fn pinned_drawing_round_trips_with_its_margin() {
        let pins = vec![Point::new(1.0, 1.0), Point::new(4.0, 4.0)];
        let scene = Scene::from_pins(PinnedDrawing {
            drawing: read_svg(SVG, &ImportOptions::default()).unwrap(),
            svg_text: SVG.into(),
            origin: "square.svg".into(),
            pins,
            weights: WeightSpec::parse("bbw", None, "square.svg").unwrap(),
            domain: scene_domain_options().with_margin(0.1),
            pose: vec![
                kurbo::Affine::IDENTITY,
                kurbo::Affine::translate((1.0, 0.0)),
            ],
        })
        .unwrap();
        let json = scene.to_json(SvgRef::File("square.svg")).unwrap();
        let value: serde_json::Value = serde_json::from_str(&json).unwrap();
        assert_eq!(value["svg"], "square.svg");
        assert_eq!(value["domain"]["margin"], 0.1);
        assert_eq!(
            value["pose"][1],
            serde_json::json!([1.0, 0.0, 0.0, 1.0, 1.0, 0.0])
        );
        round_trip(&scene);
    }

    #[test]
    fn authors_scenes_are_not_written_as_ours() {
        let mut scene = crate::examples::demo_scene();
        scene.format = SceneFormat::Authors;
        let err = scene.to_json(SvgRef::Inline("")).unwrap_err().to_string();
        assert!(err.contains("authors' format"), "{err}");
    }
}
