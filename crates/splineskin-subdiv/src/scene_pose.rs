//! Poses as subdivision scenes write them: transforms (a matrix, or translate / rotate /
//! quaternion / scale about the handle's pivot), named poses, and the keyframes of `animation`
//! that name a pose by index or name or give transforms ([`super::scene`] documents the keys).

use serde::Deserialize;
use splineskin_core::animation::file::{pose_named, AnimationFile};
use splineskin_core::animation::Animation;

use super::affine3::{
    affine3_about, affine3_is_finite, linear3_mul, rotation_axis_angle, rotation_quaternion,
    Affine3, AFFINE3_IDENTITY, LINEAR3_IDENTITY,
};
use super::cage::Point3;
use super::handles::Handles3;

/// A named pose: one map per handle.
#[derive(Clone, Debug, PartialEq)]
pub struct Pose3 {
    /// The pose's name, if it has one.
    pub name: Option<String>,
    /// One map per handle, in handle order.
    pub transforms: Vec<Affine3>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct PoseFile {
    #[serde(default)]
    pub(crate) name: Option<String>,
    pub(crate) transforms: Vec<TransformFile>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(crate) struct TransformFile {
    #[serde(default)]
    matrix: Option<[[f64; 4]; 3]>,
    #[serde(default)]
    translate: Option<[f64; 3]>,
    #[serde(default)]
    rotate: Option<RotateFile>,
    #[serde(default)]
    quaternion: Option<[f64; 4]>,
    #[serde(default)]
    scale: Option<ScaleFile>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RotateFile {
    axis: [f64; 3],
    degrees: f64,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(untagged)]
enum ScaleFile {
    Uniform(f64),
    PerAxis([f64; 3]),
}

impl TransformFile {
    /// The map this transform gives a handle pivoting at `pivot`.
    pub(crate) fn resolve<E>(
        &self,
        pivot: Point3,
        element: &str,
        invalid: &impl Fn(&str, String) -> E,
    ) -> Result<Affine3, E> {
        let at = |key: &str| format!("{element}.{key}");
        if let Some(m) = self.matrix {
            if self.translate.is_some()
                || self.rotate.is_some()
                || self.quaternion.is_some()
                || self.scale.is_some()
            {
                return Err(invalid(
                    element,
                    "give either \"matrix\" or translate/rotate/quaternion/scale, not both".into(),
                ));
            }
            if !affine3_is_finite(&m) {
                return Err(invalid(
                    &at("matrix"),
                    format!("{m:?}; expected finite entries"),
                ));
            }
            return Ok(m);
        }
        let rotation = match (&self.rotate, self.quaternion) {
            (Some(_), Some(_)) => {
                return Err(invalid(
                    element,
                    "give \"rotate\" or \"quaternion\", not both".into(),
                ))
            }
            (Some(r), None) => rotation_axis_angle(r.axis, r.degrees.to_radians()).ok_or_else(
                || {
                    invalid(
                        &at("rotate"),
                        format!(
                            "axis {:?}, {} degrees; expected a non-zero finite axis and a finite angle",
                            r.axis, r.degrees
                        ),
                    )
                },
            )?,
            (None, Some(q)) => rotation_quaternion(q).ok_or_else(|| {
                invalid(
                    &at("quaternion"),
                    format!("{q:?}; expected a non-zero finite quaternion [w, x, y, z]"),
                )
            })?,
            (None, None) => LINEAR3_IDENTITY,
        };
        let s = match self.scale {
            None => [1.0; 3],
            Some(ScaleFile::Uniform(s)) => [s; 3],
            Some(ScaleFile::PerAxis(s)) => s,
        };
        if !s.iter().all(|x| x.is_finite()) {
            return Err(invalid(
                &at("scale"),
                format!("{s:?}; expected finite factors"),
            ));
        }
        let d = self.translate.unwrap_or([0.0; 3]);
        if !d.iter().all(|x| x.is_finite()) {
            return Err(invalid(
                &at("translate"),
                format!("{d:?}; expected finite coordinates"),
            ));
        }
        let scale = [[s[0], 0.0, 0.0], [0.0, s[1], 0.0], [0.0, 0.0, s[2]]];
        Ok(affine3_about(pivot, &linear3_mul(&rotation, &scale), d))
    }
}

/// How a keyframe gives its pose.
#[derive(Deserialize)]
#[serde(untagged)]
pub(crate) enum KeyPoseFile {
    Index(usize),
    Name(String),
    Transforms(Vec<TransformFile>),
}

/// The scene's animation, each keyframe's pose resolved against `poses` (by index or name) or
/// built from its transforms about `handles`' pivots. Errors name the element
/// (`animation.keyframes[2].pose`).
pub(crate) fn resolve_animation<E>(
    file: &AnimationFile<KeyPoseFile>,
    poses: &[Pose3],
    handles: &Handles3,
    invalid: &impl Fn(&str, String) -> E,
) -> Result<Animation<Affine3>, E> {
    let n = handles.n_handles();
    let pose = |k: usize, pose: &KeyPoseFile| {
        let element = format!("animation.keyframes[{k}].pose");
        Ok(match pose {
            KeyPoseFile::Index(0) if poses.is_empty() => vec![AFFINE3_IDENTITY; n],
            KeyPoseFile::Index(i) => poses
                .get(*i)
                .ok_or_else(|| {
                    let n_poses = poses.len().max(1);
                    invalid(
                        &element,
                        format!(
                            "pose {i} does not exist (the scene has {n_poses}, numbered from 0)"
                        ),
                    )
                })?
                .transforms
                .clone(),
            KeyPoseFile::Name(name) => pose_named(poses, name, |p| p.name.as_deref())
                .map_err(|message| invalid(&element, message))?
                .transforms
                .clone(),
            KeyPoseFile::Transforms(list) => {
                if list.len() != n {
                    return Err(invalid(
                        &element,
                        format!("{} transforms; expected one per handle, {n}", list.len()),
                    ));
                }
                list.iter()
                    .enumerate()
                    .map(|(i, t)| t.resolve(handles.pivot(i), &format!("{element}[{i}]"), invalid))
                    .collect::<Result<Vec<_>, _>>()?
            }
        })
    };
    file.resolve(pose, |element, message| invalid(&element, message))
}
