//! Subdivision-surface scenes (JSON), version 1: a cage, handles, weights and poses.
//!
//! ```json
//! {
//!   "splineskin_subdiv_scene": 1,
//!   "obj": "car.obj",
//!   "handles": [ { "position": [-2.0, 0.5, 0.0] }, { "position": [2.0, 0.5, 0.0] } ],
//!   "bones": [ { "ends": [[0, 0, -1], [0, 0, 1]] } ],
//!   "weights": { "family": "bone_heat", "level": 2 },
//!   "quadrature": 4,
//!   "poses": [
//!     { "name": "twist", "transforms": [
//!         {},
//!         { "rotate": { "axis": [1, 0, 0], "degrees": 30 }, "translate": [0, 0.2, 0] },
//!         { "matrix": [[1, 0, 0, 0], [0, 1, 0, 0.5], [0, 0, 1, 0]] } ] }
//!   ]
//! }
//! ```
//!
//! | key | meaning |
//! |---|---|
//! | `splineskin_subdiv_scene` | format version, `1` (required: it marks the format) |
//! | `obj` | the cage, an OBJ file relative to the scene's folder ([`super::obj`]: polygons of any size, `t crease`/`corner`/`hole` tags) |
//! | `handles` | point handles: `position` = `[x, y, z]` in the OBJ's units. Default: none |
//! | `bones` | segment handles: `ends` = `[[x, y, z], [x, y, z]]`, distinct. Default: none |
//! | `weights` | `family`: `shepard` (`exponent`, default 2: inverse distance to points and to bones' segments, [`Shepard3`]), `bone_heat` (`level` of the limit mesh, default automatic; `visibility`, default true: [`BoneHeat`]), `file` (`path`: a CSV file relative to the scene's folder, one row per cage vertex, one column per handle: [`CageVertexWeights`](super::CageVertexWeights)) or `bbw` (`resolution`: grid cells along the longest side, default [`DEFAULT_VOLUME_RESOLUTION`](super::surface_weights::DEFAULT_VOLUME_RESOLUTION): bounded biharmonic weights on the enclosed volume, [`VolumeBbw`]). Default: `shepard` |
//! | `quadrature` | Gauss–Legendre nodes per axis per ptex face, 1 ..= [`MAX_QUADRATURE_POINTS`]. Default: [`DEFAULT_GAUSS_POINTS`] (exact on regular faces) |
//! | `poses` | a list of `{name?, transforms}`, `transforms` one per handle. Default: none (pose 0 is then the identity) |
//! | `animation` | keyframed poses: `fps` (frames per second, default 30, at most 1000) and `keyframes`, a non-empty list of `{time, pose, easing?}`: `time` in seconds, ≥ 0, strictly increasing; `pose` an index into `poses` (`0` is the identity in a scene without poses), a pose's `name`, or a list of transforms (as in `poses`); `easing` how the segment to the next keyframe runs (`linear` (default), `ease-in`, `ease-out`, `ease-in-out`, `hold`). Between keyframes each handle's map is interpolated by parts about its pivot ([`splineskin_core::animation::SpaceParts`]: position, rotation along the shortest arc, stretch), so every map must be invertible. Default: none |
//!
//! **Handle order.** Point handles first (in `handles` order), then bones: the order of
//! `transforms`, of weight-file columns and of the rig.
//!
//! A transform is one of
//! * `{"matrix": [[a, b, c, d], [e, f, g, h], [i, j, k, l]]}`: the 3 × 4 matrix mapping
//!   `(x, y, z)` to `(a x + b y + c z + d, …)` ([`Affine3`]);
//! * `{"translate": [dx, dy, dz], "rotate": {"axis": [x, y, z], "degrees": θ}, "scale": s | [sx, sy, sz]}`
//!   (each optional; `"quaternion": [w, x, y, z]` instead of `rotate`): scale, then rotate
//!   **about the handle's pivot** (a point handle's position, a bone's first end), then
//!   translate. `{}` is the identity.
//!
//! Every error names the scene file and the element (`poses[1].transforms[2].rotate`).

use std::borrow::Cow;
use std::path::{Path, PathBuf};

use serde::Deserialize;

use super::affine3::Affine3;
use super::cage::{Cage, Point3};
use super::error::SubdivError;
use super::handles::Handles3;
use super::limit::{LimitOptions, LimitSurface, DEFAULT_ISOLATION_LEVEL};
use super::obj::{read_obj, ObjError};
use super::quadrature::{LimitQuadrature, DEFAULT_GAUSS_POINTS};
use super::rig::SubdivRig;
use super::scene_pose::{resolve_animation, KeyPoseFile, Pose3, PoseFile};
use super::surface_weights::{
    node_weights, read_weight_csv, BoneHeat, BoneHeatOptions, Shepard3, SurfaceWeights,
    SurfaceWeightsError, VolumeBbw, VolumeBbwOptions, MAX_VOLUME_RESOLUTION,
};
use splineskin_core::animation::file::AnimationFile;
use splineskin_core::animation::Animation;
use splineskin_core::weights::ShepardOptions;

/// The format version this library reads.
pub const SUBDIV_SCENE_VERSION: u32 = 1;

/// The largest scene file read, in bytes (16 MiB: a scene holds handles and poses, the
/// geometry is in the OBJ).
pub const MAX_SUBDIV_SCENE_BYTES: u64 = 16 << 20;

/// The most Gauss nodes per axis a scene may ask for: 16 (256 nodes per ptex face).
pub const MAX_QUADRATURE_POINTS: usize = 16;

/// Why a scene could not be read or set up. Every variant names the scene file.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SubdivSceneError {
    /// The file could not be read.
    #[error("{file}: cannot read the scene: {source}")]
    Read {
        /// The scene.
        file: String,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
    /// Not JSON, or JSON of the wrong shape.
    #[error("{file}: {message}")]
    Json {
        /// The scene.
        file: String,
        /// What serde_json reported, with line and column.
        message: String,
    },
    /// A well-formed value that is not valid.
    #[error("{file}: {element}: {message}")]
    Invalid {
        /// The scene.
        file: String,
        /// Which element (`bones[0].ends`).
        element: String,
        /// What is wrong and what was expected.
        message: String,
    },
    /// The cage could not be read (the error names the OBJ file and line).
    #[error("{file}: {source}")]
    Obj {
        /// The scene.
        file: String,
        /// The OBJ reader's error.
        #[source]
        source: ObjError,
    },
    /// The weights could not be computed.
    #[error("{file}: weights: {source}")]
    Weights {
        /// The scene.
        file: String,
        /// What went wrong.
        #[source]
        source: SurfaceWeightsError,
    },
    /// Refinement, limit evaluation or the rig failed.
    #[error("{file}: {source}")]
    Subdiv {
        /// The scene.
        file: String,
        /// What went wrong.
        #[source]
        source: SubdivError,
    },
}

/// A weight family and its options, as a scene gives it.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum SurfaceWeightSpec {
    /// [`Shepard3`] with these options.
    Shepard(ShepardOptions),
    /// [`BoneHeat`] with these options.
    BoneHeat(BoneHeatOptions),
    /// [`CageVertexWeights`](super::CageVertexWeights) read from this CSV file.
    File(PathBuf),
    /// [`VolumeBbw`] with these options.
    Bbw(VolumeBbwOptions),
}

impl SurfaceWeightSpec {
    /// The family's name in scenes.
    pub fn name(&self) -> &'static str {
        match self {
            SurfaceWeightSpec::Shepard(_) => "shepard",
            SurfaceWeightSpec::BoneHeat(_) => "bone_heat",
            SurfaceWeightSpec::File(_) => "file",
            SurfaceWeightSpec::Bbw(_) => "bbw",
        }
    }

    /// Builds the weights of `handles` on `cage` (with its limit surface `surface`; bone heat
    /// samples it on a grid, which needs the default isolation: [`LimitQuadrature::for_cage`]).
    pub fn build(
        &self,
        cage: &Cage,
        surface: &LimitSurface,
        handles: &Handles3,
    ) -> Result<Box<dyn SurfaceWeights>, SurfaceWeightsError> {
        Ok(match self {
            SurfaceWeightSpec::Shepard(o) => Box::new(Shepard3::new(handles.clone(), *o)?),
            SurfaceWeightSpec::BoneHeat(o) => Box::new(BoneHeat::new(cage, surface, handles, o)?),
            SurfaceWeightSpec::File(path) => Box::new(read_weight_csv(
                path,
                cage.n_vertices(),
                handles.n_handles(),
            )?),
            SurfaceWeightSpec::Bbw(o) => Box::new(VolumeBbw::new(cage, surface, handles, o)?),
        })
    }
}

/// A subdivision-surface scene (module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct SubdivScene {
    /// The scene file as given (for messages).
    pub file: String,
    /// The cage's OBJ file, resolved against the scene's folder.
    pub obj: PathBuf,
    /// The handles.
    pub handles: Handles3,
    /// The weights.
    pub weights: SurfaceWeightSpec,
    /// Gauss nodes per axis per ptex face.
    pub quadrature: usize,
    /// The poses.
    pub poses: Vec<Pose3>,
    /// Keyframed poses, if the scene has an `animation`.
    pub animation: Option<Animation<Affine3>>,
}

/// Everything a scene precomputes: the cage, its limit surface, the quadrature, the weights
/// and the rig.
pub struct SubdivSetup {
    /// The cage.
    pub cage: Cage,
    /// Its limit surface, refined as deep as the quadrature needs
    /// ([`LimitQuadrature::for_cage`]); [`SubdivSetup::full_surface`] for sampling it on a
    /// grid.
    pub surface: LimitSurface,
    /// The quadrature of the fit.
    pub quadrature: LimitQuadrature,
    /// The handle weights.
    pub weights: Box<dyn SurfaceWeights>,
    /// The rig.
    pub rig: SubdivRig,
}

impl SubdivSetup {
    /// The limit surface at the default isolation ([`DEFAULT_ISOLATION_LEVEL`]), which
    /// resolves grid samples on ptex edges and near irregular features
    /// ([`LimitMesh`](super::LimitMesh)): [`SubdivSetup::surface`] itself when it is that
    /// deep, else built.
    pub fn full_surface(&self) -> Result<Cow<'_, LimitSurface>, SubdivError> {
        if self.surface.isolation_level() >= DEFAULT_ISOLATION_LEVEL {
            Ok(Cow::Borrowed(&self.surface))
        } else {
            LimitSurface::new(&self.cage, &LimitOptions::default()).map(Cow::Owned)
        }
    }
}

impl SubdivScene {
    /// Reads the scene file `path` (relative paths inside it are resolved against its folder).
    /// The OBJ and weight files are read by [`SubdivScene::setup`].
    pub fn load(path: &Path) -> Result<Self, SubdivSceneError> {
        let file = path.display().to_string();
        let read = |source| SubdivSceneError::Read {
            file: file.clone(),
            source,
        };
        let size = std::fs::metadata(path).map_err(read)?.len();
        if size > MAX_SUBDIV_SCENE_BYTES {
            return Err(SubdivSceneError::Json {
                file,
                message: format!(
                    "{size} bytes is more than the limit of {MAX_SUBDIV_SCENE_BYTES} bytes for scenes"
                ),
            });
        }
        let text = std::fs::read_to_string(path).map_err(read)?;
        let base = path.parent().unwrap_or(Path::new(""));
        Self::parse(&text, &file, base)
    }

    /// Parses a scene's text; `file` names it in errors, `base` is the folder relative paths
    /// are resolved against.
    ///
    /// ```
    /// use std::path::Path;
    /// use splineskin_subdiv::{affine3_apply, SubdivScene};
    ///
    /// let text = r#"{"splineskin_subdiv_scene": 1, "obj": "box.obj",
    ///     "handles": [{"position": [0, 0, 0]}, {"position": [4, 0, 0]}],
    ///     "poses": [{"transforms": [{}, {"translate": [0, 1, 0], "scale": 2}]}]}"#;
    /// let scene = SubdivScene::parse(text, "scene.json", Path::new("models"))?;
    /// assert_eq!(scene.obj, Path::new("models/box.obj"));
    /// // Scaled about the handle's position (4, 0, 0), then moved up.
    /// let pose = scene.pose(0)?;
    /// assert_eq!(affine3_apply(&pose[1], [5.0, 0.0, 0.0]), [6.0, 1.0, 0.0]);
    /// # Ok::<(), splineskin_subdiv::SubdivSceneError>(())
    /// ```
    pub fn parse(text: &str, file: &str, base: &Path) -> Result<Self, SubdivSceneError> {
        let parsed: SceneFile = serde_json::from_str(text).map_err(|e| SubdivSceneError::Json {
            file: file.to_owned(),
            message: if text.contains("\"splineskin_subdiv_scene\"") {
                format!("invalid scene JSON: {e}")
            } else {
                format!("not a subdivision scene (expected \"splineskin_subdiv_scene\": 1): {e}")
            },
        })?;
        let invalid = |element: &str, message: String| SubdivSceneError::Invalid {
            file: file.to_owned(),
            element: element.to_owned(),
            message,
        };
        if parsed.splineskin_subdiv_scene != SUBDIV_SCENE_VERSION {
            return Err(invalid(
                "splineskin_subdiv_scene",
                format!(
                    "version {}; expected {SUBDIV_SCENE_VERSION}",
                    parsed.splineskin_subdiv_scene
                ),
            ));
        }
        let points = parsed
            .handles
            .iter()
            .enumerate()
            .map(|(i, h)| check_point(h.position, &format!("handles[{i}].position"), &invalid))
            .collect::<Result<Vec<_>, _>>()?;
        let bones = parsed
            .bones
            .iter()
            .enumerate()
            .map(|(b, bone)| {
                Ok([
                    check_point(bone.ends[0], &format!("bones[{b}].ends[0]"), &invalid)?,
                    check_point(bone.ends[1], &format!("bones[{b}].ends[1]"), &invalid)?,
                ])
            })
            .collect::<Result<Vec<_>, _>>()?;
        let n_points = points.len();
        let handles = Handles3::new(points, bones).map_err(|e| match e {
            SurfaceWeightsError::BadHandle { handle, what } => {
                let element = if handle < n_points {
                    format!("handles[{handle}]")
                } else {
                    format!("bones[{}]", handle - n_points)
                };
                invalid(&element, what)
            }
            other => invalid("handles", other.to_string()),
        })?;
        let weights = parsed.weights.unwrap_or_default().resolve(base, &invalid)?;
        let quadrature = parsed.quadrature.unwrap_or(DEFAULT_GAUSS_POINTS);
        if !(1..=MAX_QUADRATURE_POINTS).contains(&quadrature) {
            return Err(invalid(
                "quadrature",
                format!("{quadrature} nodes per axis; expected 1 ..= {MAX_QUADRATURE_POINTS}"),
            ));
        }
        let poses = parsed
            .poses
            .iter()
            .enumerate()
            .map(|(p, pose)| {
                let element = format!("poses[{p}].transforms");
                if pose.transforms.len() != handles.n_handles() {
                    return Err(invalid(
                        &element,
                        format!(
                            "{} transforms; expected one per handle, {} ({} points, then {} bones)",
                            pose.transforms.len(),
                            handles.n_handles(),
                            handles.points().len(),
                            handles.bones().len()
                        ),
                    ));
                }
                let transforms = pose
                    .transforms
                    .iter()
                    .enumerate()
                    .map(|(i, t)| t.resolve(handles.pivot(i), &format!("{element}[{i}]"), &invalid))
                    .collect::<Result<Vec<_>, _>>()?;
                Ok(Pose3 {
                    name: pose.name.clone(),
                    transforms,
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        if parsed.obj.is_empty() {
            return Err(invalid("obj", "empty path; expected an OBJ file".into()));
        }
        let animation = parsed
            .animation
            .map(|a| resolve_animation(&a, &poses, &handles, &invalid))
            .transpose()?;
        Ok(SubdivScene {
            file: file.to_owned(),
            obj: base.join(&parsed.obj),
            handles,
            weights,
            quadrature,
            poses,
            animation,
        })
    }

    /// The transforms of pose `index`: the identity on every handle for pose 0 of a scene
    /// without poses.
    pub fn pose(&self, index: usize) -> Result<Vec<Affine3>, SubdivSceneError> {
        if self.poses.is_empty() && index == 0 {
            return Ok(vec![
                super::affine3::AFFINE3_IDENTITY;
                self.handles.n_handles()
            ]);
        }
        self.poses
            .get(index)
            .map(|p| p.transforms.clone())
            .ok_or_else(|| SubdivSceneError::Invalid {
                file: self.file.clone(),
                element: "poses".into(),
                message: format!(
                    "pose {index} asked for; the scene has {} (0-based)",
                    self.poses.len()
                ),
            })
    }

    /// The frames of the scene's animation: every frame's time (seconds,
    /// [`Animation::frame_times`]) and pose (one map per handle, interpolated about the
    /// handles' pivots).
    ///
    /// ```
    /// use std::path::Path;
    /// use splineskin_subdiv::{affine3_apply, SubdivScene};
    ///
    /// let text = r#"{"splineskin_subdiv_scene": 1, "obj": "box.obj",
    ///     "handles": [{"position": [1, 0, 0]}],
    ///     "animation": {"fps": 2, "keyframes": [
    ///         {"time": 0, "pose": [{}]},
    ///         {"time": 1, "pose": [{"rotate": {"axis": [0, 0, 1], "degrees": 90}}]}]}}"#;
    /// let scene = SubdivScene::parse(text, "scene.json", Path::new(""))?;
    /// let frames = scene.animation_frames()?;
    /// assert_eq!(frames.iter().map(|f| f.0).collect::<Vec<_>>(), [0.0, 0.5, 1.0]);
    /// // Halfway: an eighth turn about the handle at (1, 0, 0).
    /// let p = affine3_apply(&frames[1].1[0], [2.0, 0.0, 0.0]);
    /// let h = std::f64::consts::FRAC_1_SQRT_2;
    /// assert!((p[0] - (1.0 + h)).abs() < 1e-15 && (p[1] - h).abs() < 1e-15);
    /// # Ok::<(), splineskin_subdiv::SubdivSceneError>(())
    /// ```
    pub fn animation_frames(&self) -> Result<Vec<(f64, Vec<Affine3>)>, SubdivSceneError> {
        let invalid = |message: String| SubdivSceneError::Invalid {
            file: self.file.clone(),
            element: "animation".into(),
            message,
        };
        let animation = self.animation.as_ref().ok_or_else(|| {
            invalid(
                "the scene has no animation (expected an \"animation\" key with keyframes)".into(),
            )
        })?;
        let pivots: Vec<Point3> = (0..self.handles.n_handles())
            .map(|i| self.handles.pivot(i))
            .collect();
        let sampler = animation
            .sampler(&pivots)
            .map_err(|e| invalid(e.to_string()))?;
        let times = animation
            .frame_times()
            .map_err(|e| invalid(e.to_string()))?;
        Ok(times
            .into_iter()
            .map(|t| {
                let mut pose = vec![super::affine3::AFFINE3_IDENTITY; pivots.len()];
                sampler.pose_at(t, &mut pose);
                (t, pose)
            })
            .collect())
    }

    /// Reads the cage and precomputes everything: limit surface, quadrature, weights at the
    /// nodes and the rig.
    pub fn setup(&self) -> Result<SubdivSetup, SubdivSceneError> {
        let cage = read_obj(&self.obj).map_err(|source| SubdivSceneError::Obj {
            file: self.file.clone(),
            source,
        })?;
        self.setup_with(cage)
    }

    /// [`SubdivScene::setup`] on a cage already read.
    pub fn setup_with(&self, cage: Cage) -> Result<SubdivSetup, SubdivSceneError> {
        let subdiv = |source| SubdivSceneError::Subdiv {
            file: self.file.clone(),
            source,
        };
        let weights_error = |source| SubdivSceneError::Weights {
            file: self.file.clone(),
            source,
        };
        let (surface, quadrature) =
            LimitQuadrature::for_cage(&cage, self.quadrature).map_err(subdiv)?;
        let weights = match &self.weights {
            // Bone heat and the volume's weights sample the surface on a grid: at the default
            // isolation.
            SurfaceWeightSpec::BoneHeat(_) | SurfaceWeightSpec::Bbw(_)
                if surface.isolation_level() < DEFAULT_ISOLATION_LEVEL =>
            {
                let full = LimitSurface::new(&cage, &LimitOptions::default()).map_err(subdiv)?;
                self.weights.build(&cage, &full, &self.handles)
            }
            _ => self.weights.build(&cage, &surface, &self.handles),
        }
        .map_err(weights_error)?;
        let w = node_weights(weights.as_ref(), &cage, &quadrature).map_err(weights_error)?;
        let rig = SubdivRig::precompute(&cage, &quadrature, &w, self.handles.n_handles())
            .map_err(subdiv)?;
        Ok(SubdivSetup {
            cage,
            surface,
            quadrature,
            weights,
            rig,
        })
    }
}

fn check_point<E>(
    p: [f64; 3],
    element: &str,
    invalid: &impl Fn(&str, String) -> E,
) -> Result<Point3, E> {
    if p.iter().all(|c| c.is_finite()) {
        Ok(p)
    } else {
        Err(invalid(
            element,
            format!("{p:?}; expected finite coordinates"),
        ))
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    splineskin_subdiv_scene: u32,
    obj: String,
    #[serde(default)]
    handles: Vec<HandleFile>,
    #[serde(default)]
    bones: Vec<BoneFile>,
    #[serde(default)]
    weights: Option<WeightsFile>,
    #[serde(default)]
    quadrature: Option<usize>,
    #[serde(default)]
    poses: Vec<PoseFile>,
    #[serde(default)]
    animation: Option<AnimationFile<KeyPoseFile>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct HandleFile {
    position: [f64; 3],
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct BoneFile {
    ends: [[f64; 3]; 2],
}

#[derive(Deserialize)]
#[serde(tag = "family", rename_all = "snake_case", deny_unknown_fields)]
enum WeightsFile {
    Shepard {
        #[serde(default)]
        exponent: Option<f64>,
    },
    BoneHeat {
        #[serde(default)]
        level: Option<usize>,
        #[serde(default)]
        visibility: Option<bool>,
    },
    File {
        path: String,
    },
    Bbw {
        #[serde(default)]
        resolution: Option<usize>,
    },
}

impl Default for WeightsFile {
    fn default() -> Self {
        WeightsFile::Shepard { exponent: None }
    }
}

impl WeightsFile {
    fn resolve<E>(
        self,
        base: &Path,
        invalid: &impl Fn(&str, String) -> E,
    ) -> Result<SurfaceWeightSpec, E> {
        Ok(match self {
            WeightsFile::Shepard { exponent } => {
                let mut o = ShepardOptions::default();
                if let Some(a) = exponent {
                    if !(a > 0.0 && a.is_finite()) {
                        return Err(invalid(
                            "weights.exponent",
                            format!("{a}; expected a positive finite number"),
                        ));
                    }
                    o = o.with_exponent(a);
                }
                SurfaceWeightSpec::Shepard(o)
            }
            WeightsFile::BoneHeat { level, visibility } => {
                let max = super::limit_mesh::MAX_LIMIT_MESH_LEVEL;
                if let Some(l) = level.filter(|l| !(1..=max).contains(l)) {
                    return Err(invalid(
                        "weights.level",
                        format!("{l}; expected 1 ..= {max}"),
                    ));
                }
                SurfaceWeightSpec::BoneHeat(
                    BoneHeatOptions::default()
                        .with_level(level)
                        .with_visibility(visibility.unwrap_or(true)),
                )
            }
            WeightsFile::File { path } => {
                if path.is_empty() {
                    return Err(invalid(
                        "weights.path",
                        "empty path; expected a CSV file".into(),
                    ));
                }
                SurfaceWeightSpec::File(base.join(path))
            }
            WeightsFile::Bbw { resolution } => {
                let mut o = VolumeBbwOptions::default();
                if let Some(r) = resolution {
                    if !(4..=MAX_VOLUME_RESOLUTION).contains(&r) {
                        return Err(invalid(
                            "weights.resolution",
                            format!("{r} cells; expected 4 ..= {MAX_VOLUME_RESOLUTION}"),
                        ));
                    }
                    o = o.with_resolution(r);
                }
                SurfaceWeightSpec::Bbw(o)
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::affine3_apply;

    fn parse(text: &str) -> Result<SubdivScene, SubdivSceneError> {
        SubdivScene::parse(text, "scene.json", Path::new("/scenes"))
    }

    #[test]
    fn subdiv_scene_reads_handles_weights_and_poses() {
        let scene = parse(
            r#"{"splineskin_subdiv_scene": 1, "obj": "car.obj",
                "handles": [{"position": [1, 0, 0]}],
                "bones": [{"ends": [[0, 0, 0], [0, 0, 2]]}],
                "weights": {"family": "bone_heat", "level": 3},
                "poses": [{"name": "p", "transforms": [
                    {"rotate": {"axis": [0, 0, 1], "degrees": 90}, "translate": [0, 0, 1]},
                    {"scale": [2, 1, 1], "quaternion": [1, 0, 0, 0]}]}]}"#,
        )
        .unwrap();
        assert_eq!(scene.obj, Path::new("/scenes/car.obj"));
        assert_eq!(scene.handles.n_handles(), 2);
        assert_eq!(scene.quadrature, DEFAULT_GAUSS_POINTS);
        assert!(matches!(
            scene.weights,
            SurfaceWeightSpec::BoneHeat(BoneHeatOptions {
                level: Some(3),
                visibility: true,
                ..
            })
        ));
        let pose = scene.pose(0).unwrap();
        // A quarter turn about z through the point handle (1, 0, 0), then up by 1.
        let p = affine3_apply(&pose[0], [2.0, 0.0, 0.0]);
        let expected = [1.0, 1.0, 1.0];
        assert!((0..3).all(|k| (p[k] - expected[k]).abs() < 1e-15), "{p:?}");
        // Scale about the bone's first end.
        assert_eq!(affine3_apply(&pose[1], [1.0, 1.0, 1.0]), [2.0, 1.0, 1.0]);
        assert!(scene.pose(1).is_err());
    }

    #[test]
    fn subdiv_scene_errors_name_file_and_element() {
        let message = |text: &str| parse(text).unwrap_err().to_string();
        assert_eq!(
            message(r#"{"splineskin_subdiv_scene": 1, "obj": "a.obj", "bones": [{"ends": [[0, 0, 0], [0, 0, 0]]}]}"#),
            "scene.json: bones[0]: bone ends [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]] coincide; expected two distinct points"
        );
        assert_eq!(
            message(r#"{"splineskin_subdiv_scene": 1, "obj": "a.obj", "handles": [{"position": [0, 0, 0]}],
                "poses": [{"transforms": [{"rotate": {"axis": [0, 0, 0], "degrees": 3}}]}]}"#),
            "scene.json: poses[0].transforms[0].rotate: axis [0.0, 0.0, 0.0], 3 degrees; expected a non-zero finite axis and a finite angle"
        );
        assert_eq!(
            message(r#"{"splineskin_subdiv_scene": 1, "obj": "a.obj", "handles": [{"position": [0, 0, 0]}],
                "poses": [{"transforms": [{}, {}]}]}"#),
            "scene.json: poses[0].transforms: 2 transforms; expected one per handle, 1 (1 points, then 0 bones)"
        );
        assert_eq!(
            message(
                r#"{"splineskin_subdiv_scene": 1, "obj": "a.obj", "handles": [{"position": [0, 0, 0]}],
                "quadrature": 0}"#
            ),
            "scene.json: quadrature: 0 nodes per axis; expected 1 ..= 16"
        );
        let nan = message(
            r#"{"splineskin_subdiv_scene": 1, "obj": "a.obj", "handles": [{"position": [NaN, 0, 0]}]}"#,
        );
        assert!(nan.starts_with("scene.json: invalid scene JSON: "), "{nan}");
        let unknown = message(
            r#"{"splineskin_subdiv_scene": 1, "obj": "a.obj", "weights": {"family": "tetgen"}}"#,
        );
        assert!(unknown.contains("unknown variant `tetgen`"), "{unknown}");
        assert_eq!(
            message(
                r#"{"splineskin_subdiv_scene": 1, "obj": "a.obj", "handles": [{"position": [0, 0, 0]}],
                "weights": {"family": "bbw", "resolution": 2}}"#
            ),
            "scene.json: weights.resolution: 2 cells; expected 4 ..= 128"
        );
        assert!(message("{}").starts_with("scene.json: not a subdivision scene"));
    }
}
