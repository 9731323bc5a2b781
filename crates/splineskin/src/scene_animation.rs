//! A scene's animation written out: as Lottie ([`lottie_of_scene`]), and frame by frame
//! ([`SceneFrames`]) as an animated SVG or an animated image (APNG, GIF), as `splineskin
//! animate` and the editor's exports write them: the rig built once, the frames deformed in
//! parallel ([`deform_posed_frames`]), what is not a curve (gradients, patterns, markers, text,
//! images) carried by each frame's skinning map ([`Setup::element_maps`]), keyframes kept
//! within the tolerance ([`write_lottie`]).
//!
//! [`Setup::element_maps`]: crate::scene::Setup::element_maps

use kurbo::{Affine, Point, Rect};

use crate::animation::{deform_frames, Animation, AnimationError, PoseSampler};
use crate::drawing::animated_image::{AnimatedFormat, AnimatedImage, AnimatedImageError};
use crate::drawing::follow::{ElementMaps, FollowOptions};
use crate::drawing::lottie::{write_lottie, LottieError, LottieExport, LottieOptions};
use crate::drawing::svg_animate::{write_animated_svg_with, AnimateError, AnimatedSvgOptions};
use crate::drawing::svg_out::{art_bounds, write_svg_with, SvgOptions, ViewBoxRule};
use crate::drawing::{Drawing, SvgError};
use crate::render::{render_rgba, RenderError};
use crate::scene::{PoseOptions, PosedDrawing, Scene, SceneError};

/// Bytes of animated SVG text per point and frame, for the size check: about 40 (two numbers
/// of up to 17 significant digits and separators).
pub const BYTES_PER_ANIMATED_POINT: f64 = 40.0;

/// Largest animated SVG written: 2 GB (every frame is held in memory and in the one file).
pub const MAX_ANIMATED_SVG_BYTES: u64 = 2_000_000_000;

/// Pixels on the longer side of an animated image's frames unless asked otherwise: 480 (a
/// preview that any viewer plays; `splineskin animate --image-size`).
pub const ANIMATED_IMAGE_SIZE: u32 = 480;

/// Frames deformed at a time where they are written one by one (an animated image, a folder
/// of frames): 64, so that memory does not grow with the animation's length.
pub const FRAME_CHUNK: usize = 64;

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
    /// The drawing's diagonal ([`crate::drawing::Drawing::diagonal`]), which the tolerance
    /// is a fraction of.
    pub diagonal: f64,
}

impl SceneLottie {
    /// `K path keyframes of N (P paths × F frames) within T of the diagonal (D units); B bytes
    /// (E with every frame)`, `D` the tolerance in the drawing's units.
    pub fn summary(&self, options: &LottieOptions) -> String {
        format!(
            "{} path keyframes of {} ({} paths × {} frames) within {} of the diagonal ({:.6} units); {} bytes ({} with every frame)",
            self.lottie.keyframes,
            self.lottie.every_frame_keyframes,
            self.n_paths,
            self.n_frames,
            options.tolerance,
            options.tolerance * self.diagonal,
            self.lottie.json.len(),
            self.every_frame_bytes
        )
    }
}

/// Why a scene's animation could not be written as Lottie. Every variant names the scene.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SceneAnimationError {
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
        "{scene}: {frames} frames of {n_points} points make an animation file of about {:.1} GB, \
         more than the limit of {:.1} GB (expected fewer frames: lower the frame rate or the \
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
    /// A frame could not be written as SVG.
    #[error("{scene}: {what}: {source}")]
    Svg {
        /// The scene's name.
        scene: String,
        /// What was written (`frame 3: writing the SVG`).
        what: String,
        /// Why.
        source: Box<SvgError>,
    },
    /// The animated SVG could not be written.
    #[error("{scene}: writing the animated SVG: {source}")]
    Animated {
        /// The scene's name.
        scene: String,
        /// Why.
        source: Box<AnimateError>,
    },
    /// A frame could not be rendered.
    #[error("{scene}: frame {frame}: rendering: {source}")]
    Render {
        /// The scene's name.
        scene: String,
        /// The frame.
        frame: usize,
        /// Why.
        source: RenderError,
    },
    /// The animated image could not be encoded.
    #[error("{scene}: the animated image: {source}")]
    Image {
        /// The scene's name.
        scene: String,
        /// Why.
        source: AnimatedImageError,
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
/// use splineskin::scene_animation::lottie_of_scene;
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
) -> Result<SceneLottie, SceneAnimationError> {
    let rig = AnimationRig::of_scene(scene, animation, posing, scene_name)?;
    let frames = rig.frames();
    frames.check_size()?;
    let (drawing, times) = (frames.drawing(), frames.times());
    let points = frames.deform_chunk(0, times)?;
    let maps = frames.maps()?;
    let write = |options: &LottieOptions| {
        write_lottie(
            drawing,
            &points,
            times,
            animation.fps(),
            maps.as_deref(),
            options,
        )
        .map_err(|source| SceneAnimationError::Lottie {
            scene: scene_name.to_string(),
            source: Box::new(source),
        })
    };
    let lottie = write(options)?;
    let every = write(&options.clone().with_tolerance(0.0))?;
    Ok(SceneLottie {
        lottie,
        every_frame_bytes: every.json.len(),
        rig_warnings: rig.posed.warnings(),
        n_paths: drawing.paths.len(),
        n_frames: times.len(),
        diagonal: drawing.diagonal(),
    })
}

/// A scene's animation ready to write: its rig built once (as `posing` says; give it
/// `parallel: false`, the frames are deformed in parallel), the sampler of its keyframes and
/// its frames' times, errors naming the scene.
pub struct AnimationRig {
    /// The rig.
    pub posed: PosedDrawing,
    /// The keyframes' poses at any time.
    pub sampler: PoseSampler,
    /// The frames' times, seconds.
    pub times: Vec<f64>,
    /// The scene's name, as errors give it.
    pub name: String,
}

impl AnimationRig {
    /// `scene` played by `animation`, its rig built as `posing` says.
    pub fn of_scene(
        scene: &Scene,
        animation: &Animation,
        posing: PoseOptions,
        name: &str,
    ) -> Result<AnimationRig, SceneAnimationError> {
        let sampled = |source| SceneAnimationError::Animation {
            scene: name.to_string(),
            source,
        };
        Ok(AnimationRig {
            times: animation.frame_times().map_err(sampled)?,
            sampler: animation
                .sampler(&scene.handle_set().pivots())
                .map_err(sampled)?,
            posed: PosedDrawing::of_scene(scene, posing)?,
            name: name.to_string(),
        })
    }

    /// Its frames, to write.
    pub fn frames(&self) -> SceneFrames<'_> {
        SceneFrames::new(&self.posed, &self.sampler, &self.times, &self.name)
    }
}

/// Adds the art's bounding box at `points` to `bounds`.
fn add_art_bounds(bounds: &mut Option<Rect>, drawing: &Drawing, points: &[Point]) {
    if let Ok(Some(r)) = art_bounds(drawing, points) {
        *bounds = Some(bounds.map_or(r, |b| b.union(r)));
    }
}

/// A scene's animation to write frame by frame: the rig (`posed`, built once), the poses'
/// sampler and the frames' times, named `name` in errors. What `splineskin animate` writes as
/// an animated SVG or image and a folder of frames, and the editor's exports.
///
/// ```
/// use splineskin::animation::{Animation, Keyframe};
/// use splineskin::drawing::animated_image::AnimatedFormat;
/// use splineskin::drawing::svg_out::ViewBoxRule;
/// use splineskin::scene::{PoseOptions, PosedDrawing};
/// use splineskin::scene_animation::SceneFrames;
/// let scene = splineskin::examples::demo_scene();
/// let rest = vec![kurbo::Affine::IDENTITY; scene.n_handles()];
/// let moved = vec![kurbo::Affine::translate((10.0, 0.0)); scene.n_handles()];
/// let animation = Animation::new(4.0, vec![Keyframe::new(0.0, rest), Keyframe::new(1.0, moved)])?;
/// let posed = PosedDrawing::of_scene(&scene, PoseOptions::default())?;
/// let sampler = animation.sampler(&scene.handle_set().pivots())?;
/// let times = animation.frame_times()?;
/// let frames = SceneFrames::new(&posed, &sampler, &times, "demo");
/// let svg = frames.animated_svg(false, |_, _| {})?;
/// assert!(svg.contains("<animate"));
/// let gif = frames.animated_image(AnimatedFormat::Gif, 64, ViewBoxRule::Keep, |_, _, _| {})?;
/// assert!(gif.starts_with(b"GIF89a"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct SceneFrames<'a> {
    posed: &'a PosedDrawing,
    sampler: &'a PoseSampler,
    times: &'a [f64],
    name: &'a str,
}

impl<'a> SceneFrames<'a> {
    /// The frames at `times` of `sampler`'s poses on `posed`.
    pub fn new(
        posed: &'a PosedDrawing,
        sampler: &'a PoseSampler,
        times: &'a [f64],
        name: &'a str,
    ) -> Self {
        SceneFrames {
            posed,
            sampler,
            times,
            name,
        }
    }

    /// The drawing deformed.
    pub fn drawing(&self) -> &Drawing {
        &self.posed.setup().drawing
    }

    /// The frames' times, seconds.
    pub fn times(&self) -> &[f64] {
        self.times
    }

    /// The name errors give.
    pub fn name(&self) -> &str {
        self.name
    }

    /// Frames `first..first + times.len()` (`times` a run of the frames' times), deformed in
    /// parallel.
    pub fn deform_chunk(
        &self,
        first: usize,
        times: &[f64],
    ) -> Result<Vec<Vec<Point>>, SceneAnimationError> {
        deform_posed_frames(self.posed, self.sampler, times, first, self.name)
    }

    /// Frame `f`'s element maps: its gradients, patterns, markers, text and images follow its
    /// pose (`None` for a drawing without its document).
    pub fn maps_at(&self, f: usize) -> Result<Option<ElementMaps>, SceneAnimationError> {
        let mut pose = vec![Affine::IDENTITY; self.sampler.n_handles()];
        self.sampler.pose_at(self.times[f], &mut pose);
        self.posed
            .setup()
            .element_maps(&pose, &FollowOptions::default())
            .map_err(|source| SceneAnimationError::Maps {
                scene: self.name.to_string(),
                frame: f,
                source: Box::new(source),
            })
    }

    /// Frame `f` (its deformed `points`) as an SVG document with viewBox `rule`.
    pub fn frame_svg(
        &self,
        f: usize,
        points: &[Point],
        rule: ViewBoxRule,
    ) -> Result<String, SceneAnimationError> {
        let maps = self.maps_at(f)?;
        let options = SvgOptions::default()
            .with_view_box(rule)
            .with_follow(maps.as_ref());
        write_svg_with(self.drawing(), points, &options).map_err(|source| {
            SceneAnimationError::Svg {
                scene: self.name.to_string(),
                what: format!("frame {f}: writing the SVG"),
                source: Box::new(source),
            }
        })
    }

    /// Every frame's element maps (gradients follow them, as in the animated SVG), or `None`
    /// where the poses do not have one map per weight function.
    pub fn maps(&self) -> Result<Option<Vec<ElementMaps>>, SceneAnimationError> {
        let maps = (0..self.times.len())
            .map(|f| self.maps_at(f))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(maps.into_iter().collect())
    }

    /// Refuses an animation whose every frame is too much to hold in memory
    /// ([`MAX_ANIMATED_SVG_BYTES`], estimated), saying what to do.
    pub fn check_size(&self) -> Result<(), SceneAnimationError> {
        let n_points = self.drawing().n_points();
        let bytes = self.times.len() as f64 * n_points as f64 * BYTES_PER_ANIMATED_POINT;
        if bytes > MAX_ANIMATED_SVG_BYTES as f64 {
            return Err(SceneAnimationError::TooLarge {
                scene: self.name.to_string(),
                frames: self.times.len(),
                n_points,
                bytes,
            });
        }
        Ok(())
    }

    /// The viewBox rule of frames written one by one: the drawing's, or with `fit` the union
    /// of the art's bounding boxes over every frame (deformed [`FRAME_CHUNK`] at a time, only
    /// then), one viewBox that crops no frame.
    pub fn view_box(&self, fit: bool) -> Result<ViewBoxRule, SceneAnimationError> {
        if !fit {
            return Ok(ViewBoxRule::Keep);
        }
        let mut bounds: Option<Rect> = None;
        for (c, chunk) in self.times.chunks(FRAME_CHUNK).enumerate() {
            for points in self.deform_chunk(c * FRAME_CHUNK, chunk)? {
                add_art_bounds(&mut bounds, self.drawing(), &points);
            }
        }
        Ok(bounds.map_or(ViewBoxRule::Keep, ViewBoxRule::FitTo))
    }

    /// The animation as one animated SVG (SMIL; refused past [`MAX_ANIMATED_SVG_BYTES`],
    /// estimated): every frame with the drawing's viewBox, or with `fit` one viewBox holding
    /// the art of every frame. `each(f, points)` sees every frame's deformed points.
    pub fn animated_svg(
        &self,
        fit: bool,
        mut each: impl FnMut(usize, &[Point]),
    ) -> Result<String, SceneAnimationError> {
        self.check_size()?;
        let (times, drawing) = (self.times, self.drawing());
        let frames = self.deform_chunk(0, times)?;
        let mut bounds: Option<Rect> = None;
        for (f, points) in frames.iter().enumerate() {
            each(f, points);
            add_art_bounds(&mut bounds, drawing, points);
        }
        let rule = match bounds {
            Some(bounds) if fit => ViewBoxRule::FitTo(bounds),
            _ => ViewBoxRule::Keep,
        };
        let maps = self.maps()?;
        let options = AnimatedSvgOptions::default()
            .with_view_box(rule)
            .with_follow(maps.as_deref());
        write_animated_svg_with(drawing, &frames, times, &options).map_err(|source| {
            SceneAnimationError::Animated {
                scene: self.name.to_string(),
                source: Box::new(source),
            }
        })
    }

    /// The animation rendered into an animated image of `format`, `size` pixels on the longer
    /// side, every frame with viewBox `rule`, shown until the next frame's time (the last for
    /// the last interval). `each(f, points, svg)` sees every frame as it is written (deformed
    /// [`FRAME_CHUNK`] at a time).
    pub fn animated_image(
        &self,
        format: AnimatedFormat,
        size: u32,
        rule: ViewBoxRule,
        mut each: impl FnMut(usize, &[Point], &str),
    ) -> Result<Vec<u8>, SceneAnimationError> {
        let times = self.times;
        let image_error = |source| SceneAnimationError::Image {
            scene: self.name.to_string(),
            source,
        };
        let mut image: Option<AnimatedImage> = None;
        for (c, chunk) in times.chunks(FRAME_CHUNK).enumerate() {
            let first = c * FRAME_CHUNK;
            for (k, points) in self.deform_chunk(first, chunk)?.iter().enumerate() {
                let f = first + k;
                let svg = self.frame_svg(f, points, rule)?;
                each(f, points, &svg);
                let pixels =
                    render_rgba(&svg, size).map_err(|source| SceneAnimationError::Render {
                        scene: self.name.to_string(),
                        frame: f,
                        source,
                    })?;
                let image = match &mut image {
                    Some(image) => image,
                    None => image.insert(
                        AnimatedImage::new(format, pixels.width, pixels.height, times.len())
                            .map_err(image_error)?,
                    ),
                };
                // Shown until the next frame; the last one for the last interval (a single
                // frame for a second).
                let delay = if f + 1 < times.len() {
                    times[f + 1] - times[f]
                } else if f > 0 {
                    times[f] - times[f - 1]
                } else {
                    1.0
                };
                image.push(&pixels, delay).map_err(image_error)?;
            }
        }
        let image = image.ok_or_else(|| {
            image_error(AnimatedImageError::Invalid {
                what: "no frames (expected an animation of one frame or more)".to_string(),
            })
        })?;
        image.finish().map_err(image_error)
    }
}

/// Frames `first..first + times.len()` of an animation: `posed` deformed by `sampler`'s pose
/// at each of `times`, in parallel; a failure names `scene_name`, the frame and its time.
pub fn deform_posed_frames(
    posed: &PosedDrawing,
    sampler: &PoseSampler,
    times: &[f64],
    first: usize,
    scene_name: &str,
) -> Result<Vec<Vec<Point>>, SceneAnimationError> {
    let n_points = posed.setup().drawing.n_points();
    deform_frames(sampler, times, n_points, true, |pose, out| {
        posed.update(pose, out).map(|_| ())
    })
    .map_err(|e| SceneAnimationError::Frame {
        scene: scene_name.to_string(),
        frame: first + e.frame,
        time: e.time,
        message: crate::errors::message_with_causes(&e.error),
    })
}
