//! A scene's animation as Lottie ([`lottie_of_scene`]), as `splineskin animate SCENE -o
//! anim.json` and the editor's Lottie export write it, what is not a curve (gradients, patterns,
//! markers, text, images) carried by each frame's skinning map
//! ([`Setup::element_maps`](splineskin::scene::Setup::element_maps)).

use anyhow::{bail, Context, Result};
use kurbo::Point;
use splineskin::animation::{deform_frames, Animation, PoseSampler};
use splineskin::drawing::follow::{ElementMaps, FollowOptions};
use splineskin::drawing::lottie::{write_lottie, LottieExport, LottieOptions};
use splineskin::scene::{PoseOptions, PosedDrawing, Scene};

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

/// `scene` played by `animation` (its frames at its frame rate, the rig built once as `posing`
/// says; give it `parallel: false`, the frames are deformed in parallel) as a Lottie
/// animation: each frame's
/// gradients following its element maps, keyframes within `options.tolerance`
/// ([`write_lottie`]). Errors name `scene_name`; an animation too long to hold in memory is
/// refused with what to do.
pub fn lottie_of_scene(
    scene: &Scene,
    animation: &Animation,
    posing: PoseOptions,
    options: &LottieOptions,
    scene_name: &str,
) -> Result<SceneLottie> {
    let times = animation
        .frame_times()
        .with_context(|| format!("{scene_name}: animation"))?;
    let sampler = animation
        .sampler(&scene.handle_set().pivots())
        .with_context(|| format!("{scene_name}: animation"))?;
    let posed = PosedDrawing::of_scene(scene, posing)?;
    let rig_warnings = posed.warnings();
    let setup = posed.setup();
    let drawing = &setup.drawing;
    let n_points = drawing.n_points();
    let bytes = times.len() as f64 * n_points as f64 * BYTES_PER_ANIMATED_POINT;
    if bytes > MAX_ANIMATED_SVG_BYTES as f64 {
        bail!(
            "{scene_name}: {} frames of {n_points} points make a Lottie file of about {:.1} GB, more than the limit of {:.1} GB (expected fewer frames: lower the frame rate or the duration)",
            times.len(),
            bytes / 1e9,
            MAX_ANIMATED_SVG_BYTES as f64 / 1e9
        );
    }
    let frames = deform_posed_frames(&posed, &sampler, &times, 0, scene_name)?;
    // Gradients follow each frame's element maps, as in the animated SVG.
    let mut pose = vec![kurbo::Affine::IDENTITY; sampler.n_handles()];
    let maps = times
        .iter()
        .enumerate()
        .map(|(f, &t)| {
            sampler.pose_at(t, &mut pose);
            setup
                .element_maps(&pose, &FollowOptions::default())
                .with_context(|| format!("{scene_name}: frame {f}"))
        })
        .collect::<Result<Vec<_>>>()?
        .into_iter()
        .collect::<Option<Vec<ElementMaps>>>();
    let write = |options: &LottieOptions| {
        write_lottie(
            drawing,
            &frames,
            &times,
            animation.fps(),
            maps.as_deref(),
            options,
        )
        .with_context(|| format!("{scene_name}: writing the Lottie animation"))
    };
    let lottie = write(options)?;
    let every = write(&options.clone().with_tolerance(0.0))?;
    Ok(SceneLottie {
        lottie,
        every_frame_bytes: every.json.len(),
        rig_warnings,
        n_paths: drawing.paths.len(),
        n_frames: times.len(),
    })
}

/// Frames `first..first + times.len()` of an animation: `posed` deformed by `sampler`'s pose
/// at each of `times`, in parallel; a failure names `scene_name`, the frame and its time.
pub fn deform_posed_frames(
    posed: &PosedDrawing,
    sampler: &PoseSampler,
    times: &[f64],
    first: usize,
    scene_name: &str,
) -> Result<Vec<Vec<Point>>> {
    let n_points = posed.setup().drawing.n_points();
    deform_frames(sampler, times, n_points, true, |pose, out| {
        posed
            .update(pose, out)
            .map(|_| ())
            .map_err(|e| anyhow::anyhow!("{e}"))
    })
    .map_err(|e| {
        anyhow::anyhow!(
            "{scene_name}: frame {} (t = {} s): {:#}",
            first + e.frame,
            e.time,
            e.error
        )
    })
}
