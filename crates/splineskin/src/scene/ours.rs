//! Our scene format (JSON), version 1.
//!
//! ```json
//! {
//!   "splineskin_scene": 1,
//!   "svg": "drawing.svg",
//!   "handles": [ { "position": [120, 80] }, { "position": [300, 90] } ],
//!   "bones": [ { "ends": [[150, 200], [250, 200]], "transform": "rigid" } ],
//!   "weights": { "family": "bbw" },
//!   "domain": { "min_angle": 25, "max_area_fraction": 0.0002, "holes": false },
//!   "arc_length": false,
//!   "junctions": [ { "path": 0, "joint": 3, "kind": "C1" } ],
//!   "poses": [
//!     { "name": "wave", "transforms": [
//!         { "rotate": 20 }, { "translate": [40, -10], "scale": 1.2 },
//!         { "ends": [[150, 200], [240, 150]] } ] }
//!   ],
//!   "animation": { "fps": 30, "keyframes": [
//!       { "time": 0, "pose": 0 },
//!       { "time": 1.5, "pose": "wave" },
//!       { "time": 2, "pose": [ {}, { "translate": [0, 40] }, { "rotate": -30 } ] } ] }
//! }
//! ```
//!
//! A cage scene (its vertices are the handles):
//!
//! ```json
//! {
//!   "splineskin_scene": 1, "svg": "drawing.svg",
//!   "cage": [[0, 0], [400, 0], [400, 300], [0, 300]],
//!   "weights": { "family": "mvc" },
//!   "poses": [ { "cage_positions": [[0, 0], [450, -20], [400, 300], [0, 300]] } ]
//! }
//! ```
//!
//! | key | meaning |
//! |---|---|
//! | `splineskin_scene` | format version, `1` (required: it marks the format) |
//! | `svg` / `svg_text` | the SVG file (relative to the scene's folder) or the document inline; exactly one |
//! | `handles` | point handles: `position` = rest position in the SVG's user units (viewBox). Default: none |
//! | `bones` | segment handles: `ends` = `[[x0, y0], [x1, y1]]` rest end points (distinct); `transform` = `"rigid"` (default) or `"affine"`, how a posed bone is read ([`super::BoneTransform`]). Default: none |
//! | `cage` | `[[x, y], …]`: a simple polygon of at least 3 vertices, **counter-clockwise** (positive shoelace area `½ Σ p_k × p_{k+1}`; clockwise is refused, not reversed), closed implicitly (do not repeat the first vertex). Each vertex is a handle whose pose is a translation. Default: none |
//! | `weights` | `family`: `shepard` (`exponent`, default 2), `harmonic`, `biharmonic`, `bbw` (computed on a triangulation of the drawing's domain, [`crate::domain`]) or `mvc` (mean value coordinates of the cage, closed form). Which family takes which handles: [`super::WeightSpec::check_handles`] |
//! | `domain` | options of the triangulated domain (mesh families only): `min_angle` (degrees), `max_area_fraction`, `holes` (bool), `max_vertices`, `samples_per_diagonal`, `max_samples_per_curve`, `max_curve_samples`, `padding`, `shape` (`art`, the default: the drawing's painted region grown by `margin`, a fraction of the diagonal, default 0.01, one part per group of touching shapes; or `enclosing`: the largest closed path containing everything, else the bounding box grown by `padding`), `margin`; each optional, defaults and ranges in [`crate::domain::DomainOptions`] |
//! | `arc_length` | integrate with respect to arc length rather than length-weighted `t` (default false) |
//! | `flexible` | `true`: G¹ and fixed-angle junctions keep parallel tangents (fixed angle: their angle) but not their tangent-length ratio, fitted by iteration ([`crate::spline_fit::flexible`]). Default false: the ratio is the input's, a linear fit |
//! | `junctions` | overrides: path index (subpaths in document order), joint index (joint `k` starts curve `k`), `kind` ∈ `C0`, `C1`, `G1`, `angle`. A `C1` or `G1` the drawing does not have there is fitted as what it has, so that the rest pose stays the drawing ([`crate::drawing::junction`]; the setup's warnings count them) |
//! | `pose` / `poses` | one pose (a list of transforms) or a list of `{name?, transforms, cage_positions?}` |
//! | `animation` | keyframed poses: `fps` (frames per second sampled, default 30, at most 1000) and `keyframes`, a non-empty list of `{time, pose, easing?}`: `time` in seconds, ≥ 0, strictly increasing (uneven spacing is fine); `pose` is an index into `poses` (`0` is the identity in a scene without poses), a pose's `name`, a list of transforms (as in `pose`), or `{transforms, cage_positions?}` (as in `poses`). The animation runs from time 0 to the last keyframe; between keyframes each handle's map is interpolated by parts about its pivot ([`crate::animation`]), so every map must be invertible; `easing` says how the segment from this keyframe to the next runs: `linear` (default), `ease-in`, `ease-out`, `ease-in-out` or `hold` ([`crate::animation::Easing`]). Default: none |
//! | `defop` | training settings of a deformation operator for the point handles: `energy`, `spatial_basis`, `handle_basis`, `samples`, `region`, `seed`, `domain`, `mesh`, `operator`; keys, defaults and meaning in [`super::defop`] (`splineskin defop train`). Default: none (the defaults) |
//!
//! **Handle order.** The rig and every pose number the handles: point handles first (in
//! `handles` order), then bones, then cage vertices ([`super::handles`]). A pose's
//! `transforms` has one entry per handle in that order — or one per point handle and bone
//! when `cage_positions` (`[[x, y], …]`, one per cage vertex) gives the cage vertices' posed
//! positions.
//!
//! A transform is one of
//! * `[a, b, c, d, e, f]`: the SVG matrix mapping `(x, y)` to `(a x + c y + e, b x + d y + f)`;
//! * `{"a": …, "b": …, "c": …, "d": …, "e": …, "f": …}`: the same, by name;
//! * `{"translate": [dx, dy], "rotate": degrees, "scale": s | [sx, sy]}` (each optional): scale,
//!   then rotate **about the handle's pivot** (a point handle's rest position, a bone's first
//!   end, a cage vertex), then translate;
//! * `{"ends": [[x0, y0], [x1, y1]]}` (bones only): the posed end points; a rigid bone turns
//!   about its first end to the posed direction (length ignored), an affine bone takes the
//!   similarity mapping both ends exactly ([`super::Bone::posed_by_ends`]);
//! * `{"position": [x, y]}` (point handles and cage vertices): the posed position, a
//!   translation.
//!
//! A rigid bone given a matrix must be given a rotation and translation
//! ([`super::handles::RIGID_TOLERANCE`]). A cage vertex given a map `T` moves to `T·v`: its
//! handle's map is the translation by `T·v − v` (so one affine map on every cage vertex maps
//! the drawing by it, for linearly precise cage coordinates).

use std::path::Path as FsPath;

use kurbo::{Affine, Point, Vec2};
use serde::Deserialize;

use super::domain_file::DomainFile;
use super::handles::{cage_vertex_map, transform_about, translation_to};
use super::setup::check_rest_handles;
use super::{
    check_affine, check_point, handle_element, json_error, Bone, BoneTransform, Engine, HandleKind,
    HandleSet, JunctionOverride, Pose, Scene, SceneError, SceneFormat, WeightSpec, MAX_SCENE_BYTES,
};
use crate::animation::file::{pose_named, AnimationFile};
use crate::animation::Animation;
use crate::drawing::JointKind;
use crate::spline_fit::Measure;

/// The format version this library writes and reads.
pub const SCENE_VERSION: u32 = 1;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    splineskin_scene: u32,
    #[serde(default)]
    svg: Option<String>,
    #[serde(default)]
    svg_text: Option<String>,
    #[serde(default)]
    handles: Vec<HandleFile>,
    #[serde(default)]
    bones: Vec<BoneFile>,
    #[serde(default)]
    cage: Option<Vec<[f64; 2]>>,
    #[serde(default)]
    weights: Option<WeightsFile>,
    #[serde(default)]
    domain: Option<DomainFile>,
    #[serde(default)]
    arc_length: bool,
    #[serde(default)]
    flexible: bool,
    #[serde(default)]
    engine: Option<String>,
    #[serde(default)]
    junctions: Vec<JunctionOverride>,
    #[serde(default)]
    pose: Option<Vec<TransformFile>>,
    #[serde(default)]
    poses: Option<Vec<PoseFile>>,
    #[serde(default)]
    animation: Option<AnimationFile<KeyframePoseFile>>,
    #[serde(default)]
    defop: Option<super::defop::DefOpFile>,
}

/// A keyframe's pose: an index into `poses`, a pose's name, a list of transforms, or a pose
/// object (`{"transforms": …, "cage_positions": …}`).
#[derive(Deserialize)]
#[serde(untagged)]
enum KeyframePoseFile {
    Index(usize),
    Name(String),
    Transforms(Vec<TransformFile>),
    Pose(PoseFile),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct HandleFile {
    position: [f64; 2],
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct BoneFile {
    ends: [[f64; 2]; 2],
    #[serde(default)]
    transform: BoneTransformFile,
}

#[derive(Deserialize, Default, Clone, Copy)]
#[serde(rename_all = "lowercase")]
enum BoneTransformFile {
    #[default]
    Rigid,
    Affine,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct WeightsFile {
    family: String,
    #[serde(default)]
    exponent: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PoseFile {
    #[serde(default)]
    name: Option<String>,
    #[serde(default)]
    transforms: Vec<TransformFile>,
    #[serde(default)]
    cage_positions: Option<Vec<[f64; 2]>>,
}

#[derive(Deserialize)]
#[serde(untagged)]
enum TransformFile {
    Matrix([f64; 6]),
    Named(NamedTransform),
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct NamedTransform {
    a: Option<f64>,
    b: Option<f64>,
    c: Option<f64>,
    d: Option<f64>,
    e: Option<f64>,
    f: Option<f64>,
    translate: Option<[f64; 2]>,
    rotate: Option<f64>,
    scale: Option<ScaleFile>,
    ends: Option<[[f64; 2]; 2]>,
    position: Option<[f64; 2]>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(untagged)]
enum ScaleFile {
    Uniform(f64),
    NonUniform([f64; 2]),
}

impl TransformFile {
    /// The map of handle `kind` (rest geometry in `set`) posed by this transform.
    fn resolve(
        &self,
        kind: HandleKind,
        set: &HandleSet<'_>,
        origin: &str,
        element: &str,
    ) -> Result<Affine, SceneError> {
        let invalid = |message: String| SceneError::invalid(origin, element, message);
        let named = match self {
            TransformFile::Named(n) => Some(n),
            TransformFile::Matrix(_) => None,
        };
        let ends = named.and_then(|n| n.ends);
        let position = named.and_then(|n| n.position);
        if let Some(n) = named.filter(|_| ends.is_some() || position.is_some()) {
            let others = [n.a, n.b, n.c, n.d, n.e, n.f, n.rotate]
                .iter()
                .any(Option::is_some)
                || n.translate.is_some()
                || n.scale.is_some()
                || (n.ends.is_some() && n.position.is_some());
            if others {
                return Err(invalid(
                    "\"ends\" and \"position\" stand alone: give one of them, or a matrix, or \
                     translate/rotate/scale"
                        .into(),
                ));
            }
        }
        let pivot = set.pivots()[kind_index(kind, set)];
        match (kind, ends, position) {
            (HandleKind::Bone(b), Some(ends), None) => {
                let posed = [
                    check_point(ends[0], origin, format!("{element}.ends[0]"))?,
                    check_point(ends[1], origin, format!("{element}.ends[1]"))?,
                ];
                set.bones[b].posed_by_ends(posed).map_err(|e| {
                    invalid(format!(
                        "{e} (bones[{b}] is {})",
                        set.bones[b].transform.name()
                    ))
                })
            }
            (_, Some(_), None) => Err(invalid(
                "\"ends\" poses a bone; this handle is not one (use \"position\" or a transform)"
                    .into(),
            )),
            (HandleKind::Bone(_), None, Some(_)) => Err(invalid(
                "a bone is posed by \"ends\" or a transform, not by \"position\"".into(),
            )),
            (_, None, Some(q)) => Ok(translation_to(
                pivot,
                check_point(q, origin, format!("{element}.position"))?,
            )),
            _ => {
                let map =
                    check_affine(self.affine(pivot, origin, element)?, origin, element.into())?;
                match kind {
                    HandleKind::Point(_) => Ok(map),
                    HandleKind::Bone(b) => set.bones[b].check_map(map).map_err(|e| {
                        invalid(format!(
                            "{e} (bones[{b}] is rigid; declare it \"transform\": \"affine\" to allow any map)"
                        ))
                    }),
                    HandleKind::CageVertex(_) => Ok(cage_vertex_map(pivot, map)),
                }
            }
        }
    }

    fn affine(
        &self,
        pivot: kurbo::Point,
        origin: &str,
        element: &str,
    ) -> Result<Affine, SceneError> {
        let invalid = |message: String| SceneError::invalid(origin, element, message);
        match self {
            TransformFile::Matrix(m) => Ok(Affine::new(*m)),
            TransformFile::Named(n) => {
                let matrix = [n.a, n.b, n.c, n.d, n.e, n.f];
                let has_matrix = matrix.iter().any(Option::is_some);
                let has_parts = n.translate.is_some() || n.rotate.is_some() || n.scale.is_some();
                if has_matrix && has_parts {
                    return Err(invalid(
                        "give either the matrix a..f or translate/rotate/scale, not both".into(),
                    ));
                }
                if has_matrix {
                    let m: Option<Vec<f64>> = matrix.iter().copied().collect();
                    let m =
                        m.ok_or_else(|| invalid("a matrix needs all of a, b, c, d, e, f".into()))?;
                    return Ok(Affine::new([m[0], m[1], m[2], m[3], m[4], m[5]]));
                }
                let (sx, sy) = match n.scale {
                    None => (1.0, 1.0),
                    Some(ScaleFile::Uniform(s)) => (s, s),
                    Some(ScaleFile::NonUniform([sx, sy])) => (sx, sy),
                };
                let t = n.translate.unwrap_or([0.0, 0.0]);
                Ok(transform_about(
                    pivot,
                    Vec2::new(t[0], t[1]),
                    n.rotate.unwrap_or(0.0),
                    (sx, sy),
                ))
            }
        }
    }
}

/// What a file that is neither of the scene formats is told: the formats, and the two ways
/// from a drawing to a scene.
const NOT_A_SCENE: &str = "not a scene: expected our format (with \"splineskin_scene\": 1) or \
    the paper authors' (with \"gInputSVGText\"); to start from a drawing, give the SVG itself \
    (`splineskin deform DRAWING.svg --pin X,Y --move 0:DX,DY -o OUT.svg`; pins are placed \
    automatically when no --pin is given) or write a scene with `splineskin rig DRAWING.svg -o \
    SCENE.json`";

pub(crate) fn parse(
    text: &str,
    origin: &str,
    base_dir: Option<&FsPath>,
) -> Result<Scene, SceneError> {
    let mut file = read_scene_file(text, origin)?;
    let (svg_text, svg_origin) =
        drawing_text(file.svg.take(), file.svg_text.take(), origin, base_dir)?;
    let (handles, bones, cage) = rest_handles(&file, origin)?;
    let set = HandleSet {
        points: &handles,
        bones: &bones,
        cage: cage.as_deref(),
    };
    check_rest_handles(&set, origin, SceneFormat::Ours)?;
    let weights = match &file.weights {
        Some(w) => WeightSpec::parse(&w.family, w.exponent, origin)?,
        None => WeightSpec::parse("shepard", None, origin)?,
    };
    weights.check_handles(&set, origin, "weights")?;
    let domain = match &file.domain {
        Some(_) if !matches!(weights, WeightSpec::Mesh(_)) => {
            return Err(SceneError::invalid(
                origin,
                "domain",
                format!(
                    "domain options apply to the mesh families (harmonic, biharmonic, bbw), \
                     not to '{}'",
                    weights.name()
                ),
            ))
        }
        Some(d) => d.options(),
        None => super::domain_file::scene_domain_options(),
    };
    let engine = Engine::parse(file.engine.as_deref().unwrap_or("ours"), origin)?;
    let junctions = junction_overrides(&file, origin)?;
    let poses = scene_poses(&file, &set, origin)?;
    let animation = file
        .animation
        .as_ref()
        .map(|a| animation(a, &poses, &set, origin))
        .transpose()?;
    Ok(Scene {
        origin: origin.to_string(),
        svg_text,
        svg_origin,
        handles,
        bones,
        cage,
        weights,
        domain,
        engine,
        measure: Measure::from_arc_length(file.arc_length),
        junctions,
        authors_joints: None,
        poses,
        flexible: file.flexible,
        animation,
        defop: file
            .defop
            .as_ref()
            .map(|d| d.settings(origin, base_dir))
            .transpose()?,
        format: SceneFormat::Ours,
        read: Default::default(),
    })
}

/// `text` read as a scene file of ours, of the version this library writes.
fn read_scene_file(text: &str, origin: &str) -> Result<SceneFile, SceneError> {
    let file: SceneFile = serde_json::from_str(text).map_err(|e| {
        if !text.contains("\"splineskin_scene\"") {
            SceneError::Json {
                origin: origin.to_string(),
                message: NOT_A_SCENE.into(),
            }
        } else {
            json_error(origin, e)
        }
    })?;
    if file.splineskin_scene != SCENE_VERSION {
        return Err(SceneError::invalid(
            origin,
            "splineskin_scene",
            format!(
                "version {} is not supported (expected {SCENE_VERSION})",
                file.splineskin_scene
            ),
        ));
    }
    Ok(file)
}

/// The drawing's text and its origin for messages: `svg_text` inline, or the file `svg` names
/// (relative to `base_dir`, the scene's folder; without one no file is read).
fn drawing_text(
    svg: Option<String>,
    svg_text: Option<String>,
    origin: &str,
    base_dir: Option<&FsPath>,
) -> Result<(String, String), SceneError> {
    let invalid = |message: String| SceneError::invalid(origin, "svg", message);
    let name = match (svg, svg_text) {
        (Some(_), Some(_)) => return Err(invalid("give either svg or svg_text, not both".into())),
        (None, None) => return Err(invalid("missing: give svg (a file) or svg_text".into())),
        (None, Some(text)) => return Ok((text, format!("{origin} (svg_text)"))),
        (Some(name), None) => name,
    };
    // Without a folder (inline text, an upload) no file is read, as Scene::from_json documents:
    // the scene's text alone must not open files.
    let Some(dir) = base_dir else {
        return Err(invalid(format!(
            "names the file {name}, but this scene was not read from a folder, so no file is \
             read: give the drawing inline as svg_text"
        )));
    };
    let path = dir.join(&name);
    // The message names the scene and its `svg` field as well as the file: a missing drawing
    // is an error in the scene.
    let unreadable = |e: std::io::Error| {
        invalid(format!(
            "cannot read the drawing {}: {e} (expected an SVG file; a relative name is taken \
             from the scene's folder)",
            path.display()
        ))
    };
    let meta = std::fs::metadata(&path).map_err(unreadable)?;
    if meta.len() > MAX_SCENE_BYTES {
        return Err(SceneError::TooLarge {
            path,
            size: meta.len(),
            limit: MAX_SCENE_BYTES,
        });
    }
    let text = std::fs::read_to_string(&path).map_err(unreadable)?;
    Ok((text, path.display().to_string()))
}

/// The rest point handles, bones and cage of `file`, each point checked finite.
#[allow(clippy::type_complexity)]
fn rest_handles(
    file: &SceneFile,
    origin: &str,
) -> Result<(Vec<Point>, Vec<Bone>, Option<Vec<Point>>), SceneError> {
    let handles = file
        .handles
        .iter()
        .enumerate()
        .map(|(i, h)| check_point(h.position, origin, format!("handles[{i}].position")))
        .collect::<Result<Vec<_>, _>>()?;
    let bones = file
        .bones
        .iter()
        .enumerate()
        .map(|(b, f)| {
            Ok(Bone {
                ends: [
                    check_point(f.ends[0], origin, format!("bones[{b}].ends[0]"))?,
                    check_point(f.ends[1], origin, format!("bones[{b}].ends[1]"))?,
                ],
                transform: match f.transform {
                    BoneTransformFile::Rigid => BoneTransform::Rigid,
                    BoneTransformFile::Affine => BoneTransform::Affine,
                },
            })
        })
        .collect::<Result<Vec<_>, SceneError>>()?;
    let cage = file
        .cage
        .as_ref()
        .map(|c| {
            c.iter()
                .enumerate()
                .map(|(k, p)| check_point(*p, origin, format!("cage[{k}]")))
                .collect::<Result<Vec<_>, _>>()
        })
        .transpose()?;
    Ok((handles, bones, cage))
}

/// The junction kinds `file` imposes (`end` cannot be).
fn junction_overrides(file: &SceneFile, origin: &str) -> Result<Vec<JunctionOverride>, SceneError> {
    check_junction_overrides(&file.junctions, origin)?;
    Ok(file.junctions.clone())
}

/// Refuses an imposed `end` (a joint's being an end is the drawing's, not a choice), naming the
/// element `junctions[i].kind`.
pub(crate) fn check_junction_overrides(
    overrides: &[JunctionOverride],
    origin: &str,
) -> Result<(), SceneError> {
    match overrides.iter().position(|j| j.kind == JointKind::End) {
        Some(i) => Err(SceneError::invalid(
            origin,
            format!("junctions[{i}].kind"),
            "'end' cannot be imposed (expected C0, C1, G1 or angle)",
        )),
        None => Ok(()),
    }
}

/// The poses of `file` (`pose`, or `poses` with names and cage positions), each a map per
/// handle of `set`.
fn scene_poses(
    file: &SceneFile,
    set: &HandleSet<'_>,
    origin: &str,
) -> Result<Vec<Pose>, SceneError> {
    type PoseParts<'f> = (Option<String>, &'f [TransformFile], Option<&'f [[f64; 2]]>);
    let pose_files: Vec<PoseParts<'_>> = match (&file.pose, &file.poses) {
        (Some(_), Some(_)) => {
            return Err(SceneError::invalid(
                origin,
                "pose",
                "give either pose or poses, not both",
            ))
        }
        (Some(p), None) => vec![(None, p.as_slice(), None)],
        (None, Some(ps)) => ps
            .iter()
            .map(|p| {
                (
                    p.name.clone(),
                    p.transforms.as_slice(),
                    p.cage_positions.as_deref(),
                )
            })
            .collect(),
        (None, None) => Vec::new(),
    };
    let mut poses = Vec::with_capacity(pose_files.len());
    for (k, (name, transforms, cage_positions)) in pose_files.into_iter().enumerate() {
        poses.push(Pose {
            name,
            transforms: pose_transforms(
                set,
                transforms,
                cage_positions,
                origin,
                &format!("poses[{k}]"),
            )?,
        });
    }
    Ok(poses)
}

/// The scene's animation: each keyframe's pose resolved (a pose of `poses` by index or name,
/// or inline transforms), then checked by [`Animation::new`].
fn animation(
    file: &AnimationFile<KeyframePoseFile>,
    poses: &[Pose],
    set: &HandleSet<'_>,
    origin: &str,
) -> Result<Animation, SceneError> {
    let invalid = |element: String, message: String| SceneError::invalid(origin, element, message);
    let n_poses = poses.len().max(1);
    let pose = |k: usize, pose: &KeyframePoseFile| {
        let element = format!("animation.keyframes[{k}].pose");
        Ok(match pose {
            KeyframePoseFile::Index(p) => match poses.get(*p) {
                Some(pose) => pose.transforms.clone(),
                // As everywhere, a scene without poses has the identity pose 0.
                None if poses.is_empty() && *p == 0 => vec![Affine::IDENTITY; set.n_handles()],
                None => {
                    return Err(invalid(
                        element,
                        format!(
                            "pose {p} does not exist (the scene has {n_poses}, numbered from 0)"
                        ),
                    ))
                }
            },
            KeyframePoseFile::Name(name) => pose_named(poses, name, |p| p.name.as_deref())
                .map_err(|message| invalid(element, message))?
                .transforms
                .clone(),
            KeyframePoseFile::Transforms(list) => {
                pose_transforms(set, list, None, origin, &element)?
            }
            KeyframePoseFile::Pose(pose) => pose_transforms(
                set,
                &pose.transforms,
                pose.cage_positions.as_deref(),
                origin,
                &element,
            )?,
        })
    };
    file.resolve(pose, invalid)
}

/// Index of `kind` in rig order.
fn kind_index(kind: HandleKind, set: &HandleSet<'_>) -> usize {
    match kind {
        HandleKind::Point(i) => i,
        HandleKind::Bone(b) => set.points.len() + b,
        HandleKind::CageVertex(k) => set.points.len() + set.bones.len() + k,
    }
}

/// The maps of pose `k`: `transforms` for the handles in rig order (without the cage vertices
/// when `cage_positions` gives them).
fn pose_transforms(
    set: &HandleSet<'_>,
    transforms: &[TransformFile],
    cage_positions: Option<&[[f64; 2]]>,
    origin: &str,
    pose: &str,
) -> Result<Vec<Affine>, SceneError> {
    let invalid = |element: String, message: String| SceneError::invalid(origin, element, message);
    let (n_p, n_b, n_c) = (set.points.len(), set.bones.len(), set.n_cage_vertices());
    let listed = match cage_positions {
        Some(_) => n_p + n_b,
        None => set.n_handles(),
    };
    if transforms.len() != listed {
        let parts = [
            (n_p, "point handles"),
            (n_b, "bones"),
            (n_c, "cage vertices"),
        ]
        .iter()
        .filter(|(n, _)| *n > 0)
        .map(|(n, what)| format!("{n} {what}"))
        .collect::<Vec<_>>()
        .join(", then ");
        let what = if cage_positions.is_some() {
            "the point handles and bones; cage_positions gives the cage"
        } else {
            "handles"
        };
        return Err(invalid(
            pose.to_string(),
            format!(
                "{} transforms for {listed} {what} (one per handle expected, in the order {parts})",
                transforms.len()
            ),
        ));
    }
    let mut out = Vec::with_capacity(set.n_handles());
    for (i, t) in transforms.iter().enumerate() {
        let kind = set.kind(i).expect("i < n_handles");
        let mut element = format!("{pose}.transforms[{i}]");
        if !matches!(kind, HandleKind::Point(_)) {
            element = format!("{element} ({})", handle_element(SceneFormat::Ours, kind));
        }
        out.push(t.resolve(kind, set, origin, &element)?);
    }
    if let Some(positions) = cage_positions {
        let Some(cage) = set.cage else {
            return Err(invalid(
                format!("{pose}.cage_positions"),
                "the scene has no cage".into(),
            ));
        };
        if positions.len() != n_c {
            return Err(invalid(
                format!("{pose}.cage_positions"),
                format!(
                    "{} positions for {n_c} cage vertices (one per vertex expected)",
                    positions.len()
                ),
            ));
        }
        for (v, (q, &rest)) in positions.iter().zip(cage).enumerate() {
            let q: Point = check_point(*q, origin, format!("{pose}.cage_positions[{v}]"))?;
            out.push(translation_to(rest, q));
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use kurbo::Point;

    const SVG: &str = "<svg xmlns='http://www.w3.org/2000/svg'><path d='M0 0 C1 1 2 1 3 0'/></svg>";

    fn scene(extra: &str) -> Result<Scene, SceneError> {
        let json = format!(
            r#"{{"splineskin_scene": 1, "svg_text": "{SVG}", "handles": [{{"position": [10, 20]}}]{extra}}}"#
        );
        parse(&json, "test", None)
    }

    #[test]
    fn scene_transform_about_handle() {
        let s = scene(r#", "pose": [{"rotate": 90, "translate": [1, 0]}]"#).unwrap();
        let t = s.poses[0].transforms[0];
        // The handle itself only translates.
        assert!((t * Point::new(10.0, 20.0) - Point::new(11.0, 20.0)).hypot() < 1e-12);
        // A point 1 to the right of it turns to 1 below it (y down in SVG: +90° maps x to y).
        assert!((t * Point::new(11.0, 20.0) - Point::new(11.0, 21.0)).hypot() < 1e-12);
    }

    #[test]
    fn scene_matrix_forms_agree() {
        let a = scene(r#", "pose": [[1, 2, 3, 4, 5, 6]]"#).unwrap();
        let b = scene(r#", "pose": [{"a": 1, "b": 2, "c": 3, "d": 4, "e": 5, "f": 6}]"#).unwrap();
        assert_eq!(a.poses, b.poses);
        assert_eq!(
            a.poses[0].transforms[0].as_coeffs(),
            [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]
        );
    }

    #[test]
    fn scene_errors_name_the_element() {
        let e = scene(r#", "pose": [[1, 2, 3, 4, 5, 6], [1, 0, 0, 1, 0, 0]]"#).unwrap_err();
        assert!(e.to_string().contains("poses[0]"), "{e}");
        let e = scene(r#", "pose": [[1e308, 0, 0, 1, 0, 0]]"#).unwrap_err();
        assert!(e.to_string().contains("poses[0].transforms[0]"), "{e}");
        let e = scene(r#", "weights": {"family": "magic"}"#).unwrap_err();
        assert!(
            e.to_string().contains("unknown weight family 'magic'"),
            "{e}"
        );
        let e = scene(r#", "junctions": [{"path": 0, "joint": 1, "kind": "C3"}]"#).unwrap_err();
        assert!(e.to_string().contains("test"), "{e}");
        let e = parse("{}", "x.json", None).unwrap_err();
        assert!(e.to_string().contains("not a scene"), "{e}");
        let e = parse(
            "{\"splineskin_scene\": 1, \"svg\": \"missing.svg\", \"handles\": []}",
            "x.json",
            None,
        )
        .unwrap_err();
        assert!(e.to_string().contains("missing.svg"), "{e}");
    }

    #[test]
    fn scene_mvc_takes_a_cage_only() {
        let cage = r#"{"splineskin_scene": 1, "svg_text": "<svg/>", "cage": [[0, 0], [5, 0], [0, 5]], "weights": {"family": "mvc"}}"#;
        let s = parse(cage, "test", None).unwrap();
        assert_eq!(s.weights, WeightSpec::MeanValue);
        assert!(s.check_supported().is_ok());
        let e = scene(r#", "weights": {"family": "mvc"}"#).unwrap_err();
        assert!(
            e.to_string().contains("weights: mean value coordinates"),
            "{e}"
        );
        let s = scene(r#", "weights": {"family": "bbw"}"#).unwrap();
        assert_eq!(s.weights, WeightSpec::Mesh(crate::scene::MeshFamily::Bbw));
        assert!(s.check_supported().is_ok());
    }
}
