//! The `animation` key of scene files, read the same way by 2D scenes and Catmull–Clark scenes:
//! `fps` (default [`DEFAULT_FPS`]) and `keyframes`, each `{time, pose, easing?}` where `pose` is
//! whatever the scene format lets a keyframe name (an index, a pose's name, transforms…) and
//! `easing` an [`Easing`] name.

use serde::Deserialize;

use super::{Animation, AnimationError, Easing, KeyMap, Keyframe, DEFAULT_FPS};

/// A scene's `animation` as written, keyframe poses of type `P` not yet resolved.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnimationFile<P> {
    /// Frames per second, if given.
    #[serde(default)]
    pub fps: Option<f64>,
    /// The keyframes, in file order.
    pub keyframes: Vec<KeyframeFile<P>>,
}

/// One keyframe as written.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KeyframeFile<P> {
    /// Seconds.
    pub time: f64,
    /// The pose, as the scene format gives it.
    pub pose: P,
    /// The easing's name, if given.
    #[serde(default)]
    pub easing: Option<String>,
}

impl<P> AnimationFile<P> {
    /// The animation: keyframe `k`'s maps are `pose(k, &its pose)`; easings are parsed and the
    /// whole checked by [`Animation::new`]. Errors other than `pose`'s are
    /// `invalid(element, message)` with the element `animation.keyframes[k].easing`,
    /// `animation.fps` or `animation` ([`error_element`]).
    ///
    /// ```
    /// use kurbo::Affine;
    /// use splineskin_core::animation::file::AnimationFile;
    ///
    /// let file: AnimationFile<f64> = serde_json::from_str(
    ///     r#"{"fps": 10, "keyframes": [{"time": 0, "pose": 0}, {"time": 1, "pose": 2, "easing": "hold"}]}"#,
    /// ).unwrap();
    /// let invalid = |element: String, message: String| format!("{element}: {message}");
    /// let shift = |_k: usize, dx: &f64| Ok::<_, String>(vec![Affine::translate((*dx, 0.0))]);
    /// let animation = file.resolve(shift, invalid).unwrap();
    /// assert_eq!(animation.frame_times().unwrap().len(), 11);
    /// ```
    pub fn resolve<M: KeyMap, E>(
        &self,
        mut pose: impl FnMut(usize, &P) -> Result<Vec<M>, E>,
        invalid: impl Fn(String, String) -> E,
    ) -> Result<Animation<M>, E> {
        let mut keyframes = Vec::with_capacity(self.keyframes.len());
        for (k, key) in self.keyframes.iter().enumerate() {
            let transforms = pose(k, &key.pose)?;
            let easing = match key.easing.as_deref() {
                None => Easing::Linear,
                Some(name) => Easing::parse(name).map_err(|e| {
                    invalid(format!("animation.keyframes[{k}].easing"), e.to_string())
                })?,
            };
            keyframes.push(Keyframe {
                time: key.time,
                transforms,
                easing,
            });
        }
        Animation::new(self.fps.unwrap_or(DEFAULT_FPS), keyframes)
            .map_err(|e| invalid(error_element(&e).to_owned(), e.to_string()))
    }
}

/// The scene element an [`AnimationError`] is about: `animation.fps` for a frame rate, else
/// `animation` (the message names the keyframe).
pub fn error_element(e: &AnimationError) -> &'static str {
    match e {
        AnimationError::Fps { .. } => "animation.fps",
        _ => "animation",
    }
}

/// The one pose of `poses` named `name` (`name_of` gives a pose's name), or a message saying
/// there is none or several.
///
/// ```
/// use splineskin_core::animation::file::pose_named;
/// struct Pose { name: Option<String>, value: i32 }
/// let pose = |name: &str, value| Pose { name: Some(name.into()), value };
/// let poses = [pose("a", 1), pose("b", 2), pose("b", 3)];
/// let named = |name| pose_named(&poses, name, |p| p.name.as_deref()).map(|p| p.value);
/// assert_eq!(named("a"), Ok(1));
/// assert_eq!(named("c"), Err("no pose is named 'c'".to_string()));
/// assert!(named("b").unwrap_err().starts_with("several poses"));
/// ```
pub fn pose_named<'a, T>(
    poses: &'a [T],
    name: &str,
    name_of: impl Fn(&T) -> Option<&str>,
) -> Result<&'a T, String> {
    let mut named = poses.iter().filter(|p| name_of(p) == Some(name));
    match (named.next(), named.next()) {
        (Some(pose), None) => Ok(pose),
        (None, _) => Err(format!("no pose is named '{name}'")),
        (Some(_), Some(_)) => Err(format!(
            "several poses are named '{name}'; refer to one by index"
        )),
    }
}
