//! Keyframed animation of handle poses: each handle's map is split into parts about its
//! pivot (where the pivot goes, a rotation, scales and shear) and the parts are interpolated
//! between keyframes — not the matrix entries, which would shrink a turning handle (a half
//! turn lerped entry-wise passes through the zero matrix).
//!
//! ```text
//! once:        Animation (keyframes, fps) ──► sampler(pivots) ──► PoseSampler (parts per keyframe)
//!              rig = SplineRig::precompute(…)
//! each frame:  sampler.pose_at(t, &mut pose);  rig.update(&pose, &mut points)   (a mat-vec)
//! ```
//!
//! The maps are those of the plane ([`kurbo::Affine`], split by [`AffineParts`]: module
//! [`plane`]) or of space (3 × 4 matrices, split by [`SpaceParts`]: module [`space`]); both
//! implement [`KeyMap`], and everything here is written once for either.
//!
//! **Interpolation** between keyframes `(t₀, T₀)` and `(t₁, T₁)` runs at `u = e((t − t₀)/(t₁ − t₀))`,
//! `e` the first keyframe's [`Easing`] (linear by default). At `u = 0` and `u = 1` the
//! keyframe's own map is returned, bit for bit. Rotations about the pivot stay rotations about
//! it (a bone's rigid maps stay rigid); translations stay translations. Keyframe times may be
//! uneven; before the first keyframe its pose holds, after the last the last pose holds. A turn
//! of more than half a circle between two keyframes needs a keyframe in between (the shortest
//! arc is taken).

pub mod file;
pub mod plane;
pub mod space;

pub use plane::{interpolate_map, shortest_turn, AffineParts};
pub use space::SpaceParts;

use kurbo::Affine;

/// A map that keyframes carry, split into parts about a pivot to be interpolated: the plane's
/// [`kurbo::Affine`] ([`AffineParts`]) and space's 3 × 4 matrices `[[f64; 4]; 3]`
/// ([`SpaceParts`]).
///
/// ```
/// use kurbo::{Affine, Point};
/// use splineskin_core::animation::KeyMap;
/// let c = Point::new(1.0, 2.0);
/// let turn = Affine::rotate_about(1.0, c);
/// let parts = turn.split(c).unwrap();
/// let back = Affine::join(&Affine::blend(&parts, &parts, 0.5), c);
/// assert!((back.as_coeffs()[0] - 1f64.cos()).abs() < 1e-15);
/// ```
pub trait KeyMap: Copy + PartialEq + std::fmt::Debug + Send + Sync + 'static {
    /// A point of the map's space: a handle's pivot, a deformed point.
    type Point: Copy + Default + PartialEq + std::fmt::Debug + Send + Sync + 'static;
    /// The map's parts about a pivot.
    type Parts: Copy + std::fmt::Debug + Send + Sync + 'static;
    /// The identity map.
    const IDENTITY: Self;
    /// Splits the map about `pivot`; `None` if it is not finite or its linear part is
    /// singular (it has no rotation and scale to interpolate).
    fn split(self, pivot: Self::Point) -> Option<Self::Parts>;
    /// The map made of `parts` about `pivot`: `join(split(T, c), c) = T` up to rounding.
    fn join(parts: &Self::Parts, pivot: Self::Point) -> Self;
    /// The parts at fraction `u` from `from` (`u = 0`) to `to` (`u = 1`); exactly `from` and
    /// `to` at the ends.
    fn blend(from: &Self::Parts, to: &Self::Parts, u: f64) -> Self::Parts;
    /// The map's coefficients, row by row, for error messages.
    fn coefficients(&self) -> Vec<f64>;
}

/// Frames per second when a scene does not say: 30.
pub const DEFAULT_FPS: f64 = 30.0;

/// Largest frame rate accepted: 1000 frames per second (more is never visible and is always a
/// typing mistake).
pub const MAX_FPS: f64 = 1000.0;

/// Most frames one sampling may produce: 100 000 (at 30 fps, almost an hour).
pub const MAX_FRAMES: usize = 100_000;

/// Slack when counting frame intervals in a duration, in frames: `1e-9`. A duration of
/// `n / fps` seconds computed in floating point may exceed `n / fps` by an ulp; it is `n`
/// intervals, not `n + 1` with a vanishing last one.
const FRAME_COUNT_SLACK: f64 = 1e-9;

/// One keyframe: a time, one affine map per handle (rig order), and the easing of the segment
/// from it to the next keyframe.
#[derive(Clone, Debug, PartialEq)]
pub struct Keyframe<M = Affine> {
    /// Time in seconds (≥ 0).
    pub time: f64,
    /// One map per handle.
    pub transforms: Vec<M>,
    /// How the segment from this keyframe to the next runs (unused on the last keyframe).
    pub easing: Easing,
}

impl<M> Keyframe<M> {
    /// A keyframe at `time` with maps `transforms` and a linear segment after it.
    ///
    /// ```
    /// use kurbo::Affine;
    /// use splineskin_core::animation::{Easing, Keyframe};
    /// let key = Keyframe::new(0.5, vec![Affine::IDENTITY]);
    /// assert_eq!(key.easing, Easing::Linear);
    /// ```
    pub fn new(time: f64, transforms: Vec<M>) -> Keyframe<M> {
        Keyframe {
            time,
            transforms,
            easing: Easing::Linear,
        }
    }
}

/// How a segment between two keyframes runs: a map `e` from the segment's fraction of elapsed
/// time `u ∈ [0, 1]` to the fraction of the way from the first pose to the second
/// ([`AffineParts::interpolate`]). Every easing has `e(0) = 0` and `e(1) = 1` (the hold jumps
/// to 1 only at the next keyframe's time).
///
/// ```text
/// linear        e(u) = u
/// ease-in       e(u) = u²                 starts at rest
/// ease-out      e(u) = u (2 − u)          arrives at rest
/// ease-in-out   e(u) = u² (3 − 2u)        both (smoothstep)
/// hold          e(u) = 0 for u < 1        the first pose until the next keyframe
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Easing {
    /// Constant speed.
    #[default]
    Linear,
    /// Starts at rest, speeds up.
    EaseIn,
    /// Slows down to rest.
    EaseOut,
    /// Starts and arrives at rest.
    EaseInOut,
    /// No motion: the first pose holds until the next keyframe.
    Hold,
}

impl Easing {
    /// Every easing, in the order menus list them.
    pub const ALL: [Easing; 5] = [
        Easing::Linear,
        Easing::EaseIn,
        Easing::EaseOut,
        Easing::EaseInOut,
        Easing::Hold,
    ];

    /// The easing's name in scene files: `linear`, `ease-in`, `ease-out`, `ease-in-out`,
    /// `hold`.
    pub fn name(self) -> &'static str {
        match self {
            Easing::Linear => "linear",
            Easing::EaseIn => "ease-in",
            Easing::EaseOut => "ease-out",
            Easing::EaseInOut => "ease-in-out",
            Easing::Hold => "hold",
        }
    }

    /// The easing named `name` ([`Easing::name`]), if any.
    ///
    /// ```
    /// use splineskin_core::animation::Easing;
    /// assert_eq!(Easing::from_name("ease-in-out"), Some(Easing::EaseInOut));
    /// assert_eq!(Easing::from_name("bounce"), None);
    /// ```
    pub fn from_name(name: &str) -> Option<Easing> {
        Easing::ALL.into_iter().find(|e| e.name() == name)
    }

    /// The easing named `name`, or an error naming the easings there are.
    ///
    /// ```
    /// use splineskin_core::animation::Easing;
    /// assert_eq!(Easing::parse("hold"), Ok(Easing::Hold));
    /// let e = Easing::parse("bounce").unwrap_err();
    /// assert_eq!(
    ///     e.to_string(),
    ///     "'bounce' is not an easing (expected one of linear, ease-in, ease-out, ease-in-out, hold)"
    /// );
    /// ```
    pub fn parse(name: &str) -> Result<Easing, UnknownEasing> {
        Easing::from_name(name).ok_or_else(|| UnknownEasing(name.to_string()))
    }

    /// `e(u)` for `u ∈ [0, 1]` (type doc); exact at 0 and 1.
    ///
    /// ```
    /// use splineskin_core::animation::Easing;
    /// assert_eq!(Easing::EaseInOut.apply(0.5), 0.5);
    /// assert_eq!(Easing::EaseIn.apply(0.5), 0.25);
    /// assert_eq!(Easing::EaseOut.apply(0.5), 0.75);
    /// assert_eq!(Easing::Hold.apply(0.999), 0.0);
    /// assert_eq!(Easing::Hold.apply(1.0), 1.0);
    /// ```
    pub fn apply(self, u: f64) -> f64 {
        match self {
            Easing::Linear => u,
            Easing::EaseIn => u * u,
            Easing::EaseOut => u * (2.0 - u),
            Easing::EaseInOut => u * u * (3.0 - 2.0 * u),
            Easing::Hold => {
                if u >= 1.0 {
                    1.0
                } else {
                    0.0
                }
            }
        }
    }
}

/// A name that is none of the easings' ([`Easing::parse`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownEasing(pub String);

impl std::fmt::Display for UnknownEasing {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let names: Vec<&str> = Easing::ALL.iter().map(|e| e.name()).collect();
        write!(
            f,
            "'{}' is not an easing (expected one of {})",
            self.0,
            names.join(", ")
        )
    }
}

impl std::error::Error for UnknownEasing {}

/// Keyframes with strictly increasing times, and a frame rate.
#[derive(Clone, Debug, PartialEq)]
pub struct Animation<M = Affine> {
    fps: f64,
    keyframes: Vec<Keyframe<M>>,
}

/// Why an animation is invalid or cannot be sampled. Keyframes are numbered from 0.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum AnimationError {
    /// No keyframes.
    #[error("no keyframes (expected at least one, at time 0 or later)")]
    NoKeyframes,
    /// A frame rate that is not in `(0, MAX_FPS]`.
    #[error("frame rate {fps} is not in (0, {MAX_FPS}] frames per second")]
    Fps {
        /// The rate given.
        fps: f64,
    },
    /// A keyframe time that is NaN, infinite or negative.
    #[error("keyframes[{keyframe}]: time {time} is not a finite number of seconds ≥ 0")]
    Time {
        /// The keyframe.
        keyframe: usize,
        /// Its time.
        time: f64,
    },
    /// A keyframe not later than the one before.
    #[error("keyframes[{keyframe}]: time {time} is not after keyframes[{}]'s {previous} (times must increase)", keyframe - 1)]
    NotIncreasing {
        /// The keyframe.
        keyframe: usize,
        /// Its time.
        time: f64,
        /// The time of the keyframe before.
        previous: f64,
    },
    /// Keyframes with different numbers of maps, or not one per pivot.
    #[error("keyframes[{keyframe}]: {got} transforms for {expected} handles")]
    TransformCount {
        /// The keyframe.
        keyframe: usize,
        /// Maps it has.
        got: usize,
        /// Maps expected.
        expected: usize,
    },
    /// A map that is not finite or whose linear part is singular: it has no rotation and
    /// scale to interpolate.
    #[error("keyframes[{keyframe}].transforms[{handle}]: {coefficients:?} is not finite or its linear part is singular (determinant 0), so it cannot be interpolated")]
    Singular {
        /// The keyframe.
        keyframe: usize,
        /// The handle.
        handle: usize,
        /// The map's coefficients ([`KeyMap::coefficients`]).
        coefficients: Vec<f64>,
    },
    /// The animation lasts no time (its last keyframe is at 0): there is nothing to play.
    #[error(
        "the animation lasts 0 s (its last keyframe is at time 0); give a keyframe at a later time"
    )]
    ZeroDuration,
    /// A playing duration that is not finite and positive.
    #[error("duration {duration} s is not a finite positive number of seconds")]
    Duration {
        /// The duration given.
        duration: f64,
    },
    /// Sampling would produce more than [`MAX_FRAMES`] frames.
    #[error("{n_frames} frames is more than the limit of {MAX_FRAMES}; lower the frame rate or the duration")]
    TooManyFrames {
        /// Frames asked for.
        n_frames: usize,
    },
}

impl<M: KeyMap> Animation<M> {
    /// Checks and builds an animation: at least one keyframe, `fps` in `(0, MAX_FPS]`, times
    /// finite, ≥ 0 and strictly increasing, the same number of maps in every keyframe, every
    /// map finite with an invertible linear part ([`AffineParts::decompose`]).
    ///
    /// ```
    /// use kurbo::Affine;
    /// use splineskin_core::animation::{Animation, AnimationError, Keyframe};
    /// let key = |time: f64| Keyframe::new(time, vec![Affine::IDENTITY]);
    /// assert!(Animation::new(30.0, vec![key(0.0), key(0.5), key(2.0)]).is_ok());
    /// assert_eq!(
    ///     Animation::new(30.0, vec![key(0.0), key(0.0)]),
    ///     Err(AnimationError::NotIncreasing { keyframe: 1, time: 0.0, previous: 0.0 })
    /// );
    /// ```
    pub fn new(fps: f64, keyframes: Vec<Keyframe<M>>) -> Result<Animation<M>, AnimationError> {
        if !(fps > 0.0 && fps <= MAX_FPS) {
            return Err(AnimationError::Fps { fps });
        }
        let first = keyframes.first().ok_or(AnimationError::NoKeyframes)?;
        let n_handles = first.transforms.len();
        for (k, key) in keyframes.iter().enumerate() {
            if !(key.time.is_finite() && key.time >= 0.0) {
                return Err(AnimationError::Time {
                    keyframe: k,
                    time: key.time,
                });
            }
            if k > 0 && key.time <= keyframes[k - 1].time {
                return Err(AnimationError::NotIncreasing {
                    keyframe: k,
                    time: key.time,
                    previous: keyframes[k - 1].time,
                });
            }
            if key.transforms.len() != n_handles {
                return Err(AnimationError::TransformCount {
                    keyframe: k,
                    got: key.transforms.len(),
                    expected: n_handles,
                });
            }
            for (i, &t) in key.transforms.iter().enumerate() {
                if t.split(M::Point::default()).is_none() {
                    return Err(AnimationError::Singular {
                        keyframe: k,
                        handle: i,
                        coefficients: t.coefficients(),
                    });
                }
            }
        }
        Ok(Animation { fps, keyframes })
    }

    /// The frame rate, frames per second.
    pub fn fps(&self) -> f64 {
        self.fps
    }

    /// The keyframes, times increasing.
    pub fn keyframes(&self) -> &[Keyframe<M>] {
        &self.keyframes
    }

    /// Number of handles (maps per keyframe).
    pub fn n_handles(&self) -> usize {
        self.keyframes[0].transforms.len()
    }

    /// How long the animation plays: from time 0 to its last keyframe, seconds.
    pub fn duration(&self) -> f64 {
        self.keyframes[self.keyframes.len() - 1].time
    }

    /// The same animation at another frame rate.
    pub fn with_fps(&self, fps: f64) -> Result<Animation<M>, AnimationError> {
        Animation::new(fps, self.keyframes.clone())
    }

    /// The same animation retimed to last `duration` seconds: every keyframe time is scaled by
    /// `duration / self.duration()` (the last becomes `duration` exactly).
    ///
    /// Errors: [`AnimationError::Duration`] for a duration that is not finite and positive,
    /// [`AnimationError::ZeroDuration`] when the animation has no length to scale.
    pub fn with_duration(&self, duration: f64) -> Result<Animation<M>, AnimationError> {
        if !(duration.is_finite() && duration > 0.0) {
            return Err(AnimationError::Duration { duration });
        }
        let old = self.duration();
        if old <= 0.0 {
            return Err(AnimationError::ZeroDuration);
        }
        let last = self.keyframes.len() - 1;
        let keyframes = self
            .keyframes
            .iter()
            .enumerate()
            .map(|(k, key)| Keyframe {
                // The last lands on `duration` exactly, not on `old · (duration / old)`.
                time: if k == last {
                    duration
                } else {
                    key.time * (duration / old)
                },
                transforms: key.transforms.clone(),
                easing: key.easing,
            })
            .collect();
        Animation::new(self.fps, keyframes)
    }

    /// The times of the frames, seconds: `f / fps` for `f = 0, 1, …` while below the duration
    /// `D`, then `D` itself, so the first frame is at 0 and the last at `D` (`⌈D · fps⌉ + 1`
    /// frames).
    ///
    /// Errors: [`AnimationError::ZeroDuration`], [`AnimationError::TooManyFrames`].
    ///
    /// ```
    /// use kurbo::Affine;
    /// use splineskin_core::animation::{Animation, Keyframe};
    /// let key = |time: f64| Keyframe::new(time, vec![Affine::IDENTITY]);
    /// let a = Animation::new(4.0, vec![key(0.0), key(0.6)])?;
    /// assert_eq!(a.frame_times()?, vec![0.0, 0.25, 0.5, 0.6]);
    /// # Ok::<(), splineskin_core::animation::AnimationError>(())
    /// ```
    pub fn frame_times(&self) -> Result<Vec<f64>, AnimationError> {
        let duration = self.duration();
        if duration <= 0.0 {
            return Err(AnimationError::ZeroDuration);
        }
        let intervals = (duration * self.fps - FRAME_COUNT_SLACK).ceil().max(1.0);
        if intervals >= MAX_FRAMES as f64 {
            return Err(AnimationError::TooManyFrames {
                n_frames: if intervals < usize::MAX as f64 {
                    intervals as usize + 1
                } else {
                    usize::MAX
                },
            });
        }
        let n = intervals as usize;
        let mut times: Vec<f64> = (0..n).map(|f| f as f64 / self.fps).collect();
        times.push(duration);
        Ok(times)
    }

    /// Decomposes every keyframe map about its handle's pivot (`pivots`, rig order: a point
    /// handle's rest position, a bone's first end, a cage vertex) once, for [`PoseSampler`].
    ///
    /// Errors: [`AnimationError::TransformCount`] if `pivots` is not one per handle.
    pub fn sampler(&self, pivots: &[M::Point]) -> Result<PoseSampler<M>, AnimationError> {
        if pivots.len() != self.n_handles() {
            return Err(AnimationError::TransformCount {
                keyframe: 0,
                got: self.n_handles(),
                expected: pivots.len(),
            });
        }
        let mut parts = Vec::with_capacity(self.keyframes.len() * pivots.len());
        for (k, key) in self.keyframes.iter().enumerate() {
            for (i, (&t, &c)) in key.transforms.iter().zip(pivots).enumerate() {
                parts.push(t.split(c).ok_or_else(|| AnimationError::Singular {
                    keyframe: k,
                    handle: i,
                    coefficients: t.coefficients(),
                })?);
            }
        }
        Ok(PoseSampler {
            animation: self.clone(),
            pivots: pivots.to_vec(),
            parts,
        })
    }
}

/// An [`Animation`] with its keyframe maps decomposed ([`AffineParts`]): evaluates the pose at
/// any time without allocating.
#[derive(Clone, Debug)]
pub struct PoseSampler<M: KeyMap = Affine> {
    animation: Animation<M>,
    pivots: Vec<M::Point>,
    /// `parts[k · n_handles + i]`: keyframe `k`, handle `i`.
    parts: Vec<M::Parts>,
}

impl<M: KeyMap> PoseSampler<M> {
    /// The animation sampled.
    pub fn animation(&self) -> &Animation<M> {
        &self.animation
    }

    /// Number of handles: the length of a pose.
    pub fn n_handles(&self) -> usize {
        self.pivots.len()
    }

    /// Writes the pose at time `t` (seconds) into `out` (length [`PoseSampler::n_handles`]):
    /// each handle's map interpolated between the keyframes around `t` (module doc), at the
    /// fraction the first keyframe's [`Easing`] gives. At a
    /// keyframe's time, and before the first or after the last keyframe, a keyframe's maps
    /// are copied exactly. No allocation.
    ///
    /// Panics if `out` has the wrong length (a caller's bug, not data).
    ///
    /// ```
    /// use kurbo::{Affine, Point};
    /// use splineskin_core::animation::{Animation, Keyframe};
    /// let c = Point::new(10.0, 0.0);
    /// let quarter = Affine::rotate_about(std::f64::consts::FRAC_PI_2, c);
    /// let a = Animation::new(30.0, vec![
    ///     Keyframe::new(0.0, vec![Affine::IDENTITY]),
    ///     Keyframe::new(2.0, vec![quarter]),
    /// ])?;
    /// let sampler = a.sampler(&[c])?;
    /// let mut pose = [Affine::IDENTITY];
    /// sampler.pose_at(1.0, &mut pose);
    /// // Halfway: the eighth turn about the pivot.
    /// let eighth = Affine::rotate_about(std::f64::consts::FRAC_PI_4, c);
    /// for (g, w) in pose[0].as_coeffs().iter().zip(eighth.as_coeffs()) {
    ///     assert!((g - w).abs() < 1e-14);
    /// }
    /// # Ok::<(), splineskin_core::animation::AnimationError>(())
    /// ```
    pub fn pose_at(&self, t: f64, out: &mut [M]) {
        let n = self.n_handles();
        assert_eq!(out.len(), n, "pose_at: output length");
        let keys = &self.animation.keyframes;
        // First keyframe later than t.
        let next = keys.partition_point(|k| k.time <= t);
        if next == 0 || next == keys.len() || keys[next - 1].time == t {
            let k = next.saturating_sub(1);
            out.copy_from_slice(&keys[k].transforms);
            return;
        }
        let (k0, k1) = (next - 1, next);
        let u = keys[k0]
            .easing
            .apply((t - keys[k0].time) / (keys[k1].time - keys[k0].time));
        // A hold (or an easing at an end) is a keyframe's own maps, bit for bit.
        if u == 0.0 || u == 1.0 {
            out.copy_from_slice(&keys[if u == 0.0 { k0 } else { k1 }].transforms);
            return;
        }
        for (i, (slot, &c)) in out.iter_mut().zip(&self.pivots).enumerate() {
            let p0 = &self.parts[k0 * n + i];
            let p1 = &self.parts[k1 * n + i];
            *slot = M::join(&M::blend(p0, p1, u), c);
        }
    }
}

/// Deforming frame `frame` (at `time` seconds) failed.
#[derive(Debug, thiserror::Error)]
#[error("frame {frame} (t = {time} s): {error}")]
pub struct FrameError<E: std::fmt::Display + std::fmt::Debug> {
    /// The frame index.
    pub frame: usize,
    /// Its time.
    pub time: f64,
    /// What the deformer reported.
    pub error: E,
}

/// Deforms the drawing at every time in `times`: the pose from `sampler`, then
/// `deform(pose, out)` (e.g. [`crate::spline_fit::SplineRig::update`], a mat-vec), into one
/// buffer of `n_points` points per frame. Frames are independent; with `parallel` they run on
/// rayon's pool.
///
/// ```
/// use kurbo::{Affine, Point};
/// use splineskin_core::animation::{deform_frames, Animation, Keyframe};
/// let a = Animation::new(2.0, vec![
///     Keyframe::new(0.0, vec![Affine::IDENTITY]),
///     Keyframe::new(1.0, vec![Affine::translate((4.0, 0.0))]),
/// ])?;
/// let sampler = a.sampler(&[Point::ZERO])?;
/// // A toy deformer: the handle's map applied to one point.
/// let frames = deform_frames(&sampler, &a.frame_times()?, 1, false, |pose, out| {
///     out[0] = pose[0] * Point::new(1.0, 1.0);
///     Ok::<(), std::convert::Infallible>(())
/// }).unwrap();
/// assert_eq!(frames, vec![vec![Point::new(1.0, 1.0)], vec![Point::new(3.0, 1.0)], vec![Point::new(5.0, 1.0)]]);
/// # Ok::<(), splineskin_core::animation::AnimationError>(())
/// ```
pub fn deform_frames<M, P, E, F>(
    sampler: &PoseSampler<M>,
    times: &[f64],
    n_points: usize,
    parallel: bool,
    deform: F,
) -> Result<Vec<Vec<P>>, FrameError<E>>
where
    M: KeyMap,
    P: Copy + Default + Send,
    E: std::fmt::Display + std::fmt::Debug + Send,
    F: Fn(&[M], &mut [P]) -> Result<(), E> + Sync,
{
    let one = |(frame, &time): (usize, &f64)| {
        let mut pose = vec![M::IDENTITY; sampler.n_handles()];
        sampler.pose_at(time, &mut pose);
        let mut points = vec![P::default(); n_points];
        deform(&pose, &mut points).map_err(|error| FrameError { frame, time, error })?;
        Ok(points)
    };
    if parallel {
        use rayon::prelude::*;
        times.par_iter().enumerate().map(one).collect()
    } else {
        times.iter().enumerate().map(one).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn shortest_turn_wraps() {
        assert!((shortest_turn(-0.1, 2.0 * PI - 0.1)).abs() < 1e-15);
        assert!((shortest_turn(3.0, -3.0) - (2.0 * PI - 6.0)).abs() < 1e-15);
        assert!((shortest_turn(-3.0, 3.0) + (2.0 * PI - 6.0)).abs() < 1e-15);
    }

    #[test]
    fn frame_times_end_on_duration() {
        let key = |time: f64| Keyframe::new(time, vec![Affine::IDENTITY]);
        // 2143 / 30 s at 30 fps: 2143 intervals, not 2144 with a sliver.
        let a = Animation::new(30.0, vec![key(0.0), key(2143.0 / 30.0)]).unwrap();
        let t = a.frame_times().unwrap();
        assert_eq!(t.len(), 2144);
        assert_eq!(t[2143], 2143.0 / 30.0);
        assert_eq!(t[15], 0.5);
        let single = Animation::new(30.0, vec![key(0.0)]).unwrap();
        assert_eq!(single.frame_times(), Err(AnimationError::ZeroDuration));
    }
}
