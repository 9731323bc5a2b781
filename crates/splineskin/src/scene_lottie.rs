//! A scene's animation as Lottie ([`lottie_of_scene`]), as `splineskin animate SCENE -o
//! anim.json` and the editor's Lottie export write it: the rig built once, the frames deformed
//! in parallel ([`deform_posed_frames`]), what is not a curve (gradients, patterns, markers,
//! text, images) carried by each frame's skinning map ([`Setup::element_maps`]), keyframes kept
//! within the tolerance ([`write_lottie`]).
//!
//! [`Setup::element_maps`]: crate::scene::Setup::element_maps

use kurbo::{Affine, Point};

use crate::animation::{deform_frames, Animation, AnimationError, PoseSampler};
use crate::drawing::follow::{ElementMaps, FollowOptions};
use crate::drawing::lottie::{write_lottie, LottieError, LottieExport, LottieOptions};
use crate::drawing::SvgError;
use crate::scene::{PoseOptions, PosedDrawing, Scene, SceneError};

/// Bytes of animated SVG text per point and frame, for the size check: about 40 (two numbers
/// of up to 17 significant digits and separators).
pub const BYTES_PER_ANIMATED_POINT: f64 = 40.0;

/// Largest animated SVG written: 2 GB (every frame is held in memory and in the one file).
pub const MAX_ANIMATED_SVG_BYTES: u64 = 2_000_000_000;

/// A scene's animation written as Lottie ([`lottie_of_scene`]).
pub struct SceneLottie {
    /// The animation, keyframed within the options' tolerance.
    pub lottie: LottieExport,
    /// Bytes of the same animation with every frame a keyframe (for comparison).
    pub every_frame_bytes: usize,
    /// What setting up the rig warned about (each names the scene).
    pub rig_warnings: Vec<String>,
    /// Paths of the drawing.
    pub n_paths: usize,
    /// Frames sampled.
    pub n_frames: usize,
}

impl SceneLottie {
    /// `K path keyframes of N (P paths × F frames) within T of the diagonal; B bytes (E with
    /// every frame)`.
    pub fn summary(&self, options: &LottieOptions) -> String {
        format!(
            "{} path keyframes of {} ({} paths × {} frames) within {} of the diagonal; {} bytes ({} with every frame)",
            self.lottie.keyframes,
            self.lottie.every_frame_keyframes,
            self.n_paths,
            self.n_frames,
            options.tolerance,
            self.lottie.json.len(),
            self.every_frame_bytes
        )
    }
}

/// Why a scene's animation could not be written as Lottie. Every variant names the scene.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SceneLottieError {
    /// The animation's frames or poses cannot be sampled.
    #[error("{scene}: animation: {source}")]
    Animation {
        /// The scene's name.
        scene: String,
        /// Why.
        source: AnimationError,
    },
    /// The scene cannot be set up or rigged.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The animation is too long to hold in memory.
    #[error(
        "{scene}: {frames} frames of {n_points} points make a Lottie file of about {:.1} GB, more \
         than the limit of {:.1} GB (expected fewer frames: lower the frame rate or the \
         duration)",
        .bytes / 1e9,
        MAX_ANIMATED_SVG_BYTES as f64 / 1e9
    )]
    TooLarge {
        /// The scene's name.
        scene: String,
        /// Frames sampled.
        frames: usize,
        /// Chain points of the drawing.
        n_points: usize,
        /// Estimated bytes.
        bytes: f64,
    },
    /// A frame could not be deformed.
    #[error("{scene}: frame {frame} (t = {time} s): {message}")]
    Frame {
        /// The scene's name.
        scene: String,
        /// The frame.
        frame: usize,
        /// Its time, seconds.
        time: f64,
        /// Why, with its causes.
        message: String,
    },
    /// A frame's element maps could not be computed.
    #[error("{scene}: frame {frame}: {source}")]
    Maps {
        /// The scene's name.
        scene: String,
        /// The frame.
        frame: usize,
        /// Why.
        source: Box<SvgError>,
    },
    /// The Lottie writer refused the frames.
    #[error("{scene}: writing the Lottie animation: {source}")]
    Lottie {
        /// The scene's name.
        scene: String,
        /// Why.
        source: Box<LottieError>,
    },
}

/// `scene` played by `animation` (its frames at its frame rate, the rig built once as `posing`
/// says; give it `parallel: false`, the frames are deformed in parallel) as a Lottie
/// animation: each frame's gradients following its element maps, keyframes within
/// `options.tolerance` ([`write_lottie`]). Errors name `scene_name`; an animation too long to
/// hold in memory is refused with what to do.
///
/// ```
/// use splineskin::animation::{Animation, Keyframe};
/// use splineskin::drawing::lottie::LottieOptions;
/// use splineskin::scene::PoseOptions;
/// use splineskin::scene_lottie::lottie_of_scene;
/// let scene = splineskin::examples::demo_scene();
/// let rest = vec![kurbo::Affine::IDENTITY; scene.n_handles()];
/// let moved = vec![kurbo::Affine::translate((10.0, 0.0)); scene.n_handles()];
/// let animation = Animation::new(4.0, vec![Keyframe::new(0.0, rest), Keyframe::new(1.0, moved)])?;
/// let made = lottie_of_scene(&scene, &animation, PoseOptions::default(), &LottieOptions::default(), "demo")?;
/// assert_eq!(made.n_frames, 5);
/// assert!(made.lottie.json.starts_with('{'));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn lottie_of_scene(
    scene: &Scene,
    animation: &Animation,
    posing: PoseOptions,
    options: &LottieOptions,
    scene_name: &str,
) -> Result<SceneLottie, SceneLottieError> {
    let sampled = |source| SceneLottieError::Animation {
        scene: scene_name.to_string(),
        source,
    };
    let times = animation.frame_times().map_err(sampled)?;
    let sampler = animation
        .sampler(&scene.handle_set().pivots())
        .map_err(sampled)?;
    let posed = PosedDrawing::of_scene(scene, posing)?;
    let setup = posed.setup();
    let drawing = &setup.drawing;
    let n_points = drawing.n_points();
    let bytes = times.len() as f64 * n_points as f64 * BYTES_PER_ANIMATED_POINT;
    if bytes > MAX_ANIMATED_SVG_BYTES as f64 {
        return Err(SceneLottieError::TooLarge {
            scene: scene_name.to_string(),
            frames: times.len(),
            n_points,
            bytes,
        });
    }
    let frames = deform_posed_frames(&posed, &sampler, &times, 0, scene_name)?;
    let maps = frame_maps(&posed, &sampler, &times, scene_name)?;
    let write = |options: &LottieOptions| {
        write_lottie(
            drawing,
            &frames,
            &times,
            animation.fps(),
            maps.as_deref(),
            options,
        )
        .map_err(|source| SceneLottieError::Lottie {
            scene: scene_name.to_string(),
            source: Box::new(source),
        })
    };
    let lottie = write(options)?;
    let every = write(&options.clone().with_tolerance(0.0))?;
    Ok(SceneLottie {
        lottie,
        every_frame_bytes: every.json.len(),
        rig_warnings: posed.warnings(),
        n_paths: drawing.paths.len(),
        n_frames: times.len(),
    })
}

/// Each frame's element maps (gradients follow them, as in the animated SVG), or `None` where
/// the poses do not have one map per weight function.
fn frame_maps(
    posed: &PosedDrawing,
    sampler: &PoseSampler,
    times: &[f64],
    scene_name: &str,
) -> Result<Option<Vec<ElementMaps>>, SceneLottieError> {
    let mut pose = vec![Affine::IDENTITY; sampler.n_handles()];
    let maps = times
        .iter()
        .enumerate()
        .map(|(frame, &t)| {
            sampler.pose_at(t, &mut pose);
            posed
                .setup()
                .element_maps(&pose, &FollowOptions::default())
                .map_err(|source| SceneLottieError::Maps {
                    scene: scene_name.to_string(),
                    frame,
                    source: Box::new(source),
                })
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(maps.into_iter().collect())
}

/// Frames `first..first + times.len()` of an animation: `posed` deformed by `sampler`'s pose
/// at each of `times`, in parallel; a failure names `scene_name`, the frame and its time.
pub fn deform_posed_frames(
    posed: &PosedDrawing,
    sampler: &PoseSampler,
    times: &[f64],
    first: usize,
    scene_name: &str,
) -> Result<Vec<Vec<Point>>, SceneLottieError> {
    let n_points = posed.setup().drawing.n_points();
    deform_frames(sampler, times, n_points, true, |pose, out| {
        posed.update(pose, out).map(|_| ())
    })
    .map_err(|e| SceneLottieError::Frame {
        scene: scene_name.to_string(),
        frame: first + e.frame,
        time: e.time,
        message: crate::errors::message_with_causes(&e.error),
    })
}
