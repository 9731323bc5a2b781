//! `splineskin animate SCENE -o out.svg | -o frames/`, or `splineskin animate DRAWING.svg
//! [--pin X,Y]… --move I:DX,DY… -o out.svg`: the pins go from rest to the pose and back
//! ([`crate::drawing_input::there_and_back`]).
//!
//! The scene's keyframes ([`splineskin::animation`]) are sampled at its frame rate; each frame's
//! pose is deformed with the rig built once (fixed ratio: one mat-vec per frame; flexible: one
//! flexible solve per frame), frames in parallel.
//!
//! * `-o NAME.svg`: one SVG whose deformed paths carry SMIL `<animate>` of their `d`, and
//!   whose text, images, user-space gradients and patterns and fixed-orientation markers carry
//!   animations of their transform (orient) through each frame's element maps
//!   ([`splineskin::drawing::svg_animate::write_animated_svg_with`]); written atomically
//!   (temporary file, rename).
//! * `-o NAME.json`: a Lottie animation ([`splineskin::drawing::lottie`]): one path shape per
//!   path, keyframed only where the player's linear interpolation would stray from the
//!   deformation by more than `--lottie-tolerance` of the drawing's diagonal; paint from the
//!   document, and a warning for each thing Lottie cannot express. Prints the keyframe count
//!   and the file's size against keeping every frame. `-o NAME.lottie`: the same animation in
//!   a dotLottie archive ([`crate::dotlottie`]).
//! * `-o NAME.png` / `-o NAME.gif`: an animated PNG (APNG) or GIF preview that any viewer
//!   plays ([`splineskin::drawing::animated_image`]): each frame rendered as `--png` renders it,
//!   `--image-size` pixels on the longer side, shown until the next frame's time (the last for
//!   the last interval), looping.
//! * `-o DIR` (any other name): `DIR/frame-0000.svg`, … and with `--png` also
//!   `frame-0000.png`, …. The frames are written into a temporary folder beside `DIR`, which is
//!   then renamed to `DIR`. An existing `DIR` is replaced only if it holds nothing but
//!   `frame-*.svg`/`frame-*.png` files (an earlier run's output); otherwise it is an error and
//!   nothing is touched. Frames are deformed and written [`FRAME_CHUNK`] at a time, so memory
//!   does not grow with the animation's length; an animated SVG holds every frame, and is
//!   refused above [`MAX_ANIMATED_SVG_BYTES`] (estimated) with a message saying what to do.
//!
//! `--viewbox keep` (the default) keeps the input's viewBox in every frame and warns naming the
//! frames and paths that leave it and by how far; `--viewbox fit` gives every frame (the
//! animated SVG, or each file of the folder) one viewBox: the union of the input's and of the
//! art's bounding boxes over all frames, so nothing is cropped and the animation does not jump.
//! A frames folder is then deformed twice (once for the union, once to write), memory still
//! that of [`FRAME_CHUNK`] frames.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use kurbo::Point;
use splineskin::animation::Animation;
use splineskin::drawing::animated_image::AnimatedFormat;
use splineskin::drawing::lottie::LottieOptions;
use splineskin::drawing::svg_out::ViewBoxRule;
use splineskin::drawing::Drawing;
use splineskin::render::MAX_RENDER_SIZE;
use splineskin::scene::{PosedDrawing, Scene};

use crate::frames_folder::{frame_name, replace_frames_folder, write_synced};

use splineskin::scene_animation::{
    lottie_of_scene, SceneAnimationError, SceneFrames, ANIMATED_IMAGE_SIZE, FRAME_CHUNK,
    MAX_ANIMATED_SVG_BYTES,
};

use crate::output::{has_extension, write_atomic, FramesOutside, ViewBoxArg, PNG_SIZE};

#[derive(clap::Args)]
pub struct Args {
    /// The scene (our JSON format with an `animation`, or the paper authors'
    /// `*-deformation.json` with `animationFrames`), or an SVG drawing with its pins and pose
    /// given by the flags below: it plays rest, pose, rest over 2 s (see --duration).
    #[arg(value_name = "SCENE|SVG")]
    scene: PathBuf,
    /// `NAME.svg`: an animated SVG (SMIL, plays in browsers). `NAME.json`: a Lottie animation
    /// (path keyframes; plays in Lottie players). `NAME.lottie`: the same in a dotLottie
    /// archive (the dotLottie players). `NAME.png` / `NAME.gif`: an animated PNG
    /// (APNG) or GIF that any viewer plays. Any other name: a folder of numbered frames
    /// `frame-0000.svg`, … (replaced if it holds only an earlier run's frames).
    #[arg(short, long)]
    output: PathBuf,
    /// Also write `frame-NNNN.png` into the frames folder.
    #[arg(long)]
    png: bool,
    /// Frames per second sampled (default: the scene's `animation.fps`, else 30).
    #[arg(long)]
    fps: Option<f64>,
    /// Play the animation in this many seconds: keyframe times are scaled so that the last
    /// keyframe falls at the end (default: the last keyframe's time).
    #[arg(long)]
    duration: Option<f64>,
    #[command(flatten)]
    posing: crate::posing::PosingArgs,
    /// Adaptive control points (as in `deform --tolerance`): input curves split at rest until
    /// the fit is within FRACTION of the diagonal of the skinned target in every frame.
    #[arg(long, value_name = "FRACTION")]
    tolerance: Option<f64>,
    #[command(flatten)]
    svg_input: crate::drawing_input::SvgInputArgs,
    /// When the deformed art leaves the input's viewBox: `keep` it in every frame (a warning
    /// names the frames and paths and how far) or `fit` it (one viewBox for all frames, the
    /// union of the art over the animation; width/height grow in proportion).
    #[arg(long, value_enum, default_value_t = ViewBoxArg::Keep)]
    viewbox: ViewBoxArg,
    /// Animated PNG or GIF output: pixels on the image's longer side.
    #[arg(long, default_value_t = ANIMATED_IMAGE_SIZE)]
    image_size: u32,
    /// Lottie output: the largest distance allowed between the deformation and the player's
    /// interpolation of the written keyframes, as a fraction of the drawing's bounding-box
    /// diagonal (0 keeps every frame).
    #[arg(long, default_value_t = splineskin::drawing::lottie::DEFAULT_TOLERANCE)]
    lottie_tolerance: f64,
}

/// What `-o` names: the kind of output (module documentation).
#[derive(Clone, Copy)]
enum Output {
    Lottie,
    Image(AnimatedFormat),
    Svg,
    Frames,
}

pub fn run(args: Args) -> Result<()> {
    let output = output_kind(&args)?;
    let scene_name = args.scene.display().to_string();
    let (scene, animation) = load_animation(&args, &scene_name)?;
    if let Output::Lottie = output {
        return write_lottie(&args, &scene, &animation, &scene_name);
    }
    let times = animation
        .frame_times()
        .with_context(|| format!("{scene_name}: animation"))?;
    let sampler = animation
        .sampler(&scene.handle_set().pivots())
        .with_context(|| format!("{scene_name}: animation"))?;
    // One thread per frame product: the frames are deformed in parallel.
    let posed = PosedDrawing::of_scene(&scene, args.posing.options(false))?;
    for w in posed.warnings() {
        eprintln!("warning: {w}");
    }
    let posed = match args.tolerance {
        Some(tolerance) => refined_for_frames(posed, &sampler, &times, tolerance)
            .with_context(|| format!("{scene_name}: --tolerance {tolerance}"))?,
        None => posed,
    };
    let job = Job {
        args: &args,
        frames: SceneFrames::new(&posed, &sampler, &times, &scene_name),
    };
    match output {
        Output::Image(format) => job.write_image(format)?,
        Output::Svg => job.write_animated_svg()?,
        _ => job.write_frames()?,
    }
    let drawing = &posed.setup().drawing;
    eprintln!(
        "{scene_name}: {} curves in {} paths, {} handles, {} keyframes, {} frames at {} fps over {} s{} -> {}",
        drawing.n_curves(),
        drawing.paths.len(),
        posed.setup().weights.n_handles(),
        animation.keyframes().len(),
        times.len(),
        animation.fps(),
        animation.duration(),
        if posed.is_flexible() {
            " (flexible)"
        } else {
            ""
        },
        args.output.display()
    );
    Ok(())
}

/// The kind of output `-o` names, its flags checked against it.
fn output_kind(args: &Args) -> Result<Output> {
    let output = if has_extension(&args.output, "json") || has_extension(&args.output, "lottie") {
        Output::Lottie
    } else if has_extension(&args.output, "png") {
        Output::Image(AnimatedFormat::Apng)
    } else if has_extension(&args.output, "gif") {
        Output::Image(AnimatedFormat::Gif)
    } else if is_svg_name(&args.output) {
        Output::Svg
    } else {
        Output::Frames
    };
    if let Some(ext) = args
        .output
        .extension()
        .and_then(|e| e.to_str())
        .filter(|e| FILE_EXTENSIONS.iter().any(|f| e.eq_ignore_ascii_case(f)))
    {
        bail!(
            "{}: an animation is written as an animated .svg file, a Lottie .json or .lottie \
             file, an animated .png or .gif, or a folder of frames (expected one of those extensions, or \
             a folder name without a .{ext} extension)",
            args.output.display()
        );
    }
    let as_image = matches!(output, Output::Image(_));
    if as_image && args.png {
        bail!(
            "{}: --png writes PNG frames into a folder; an animated .png or .gif is one file",
            args.output.display()
        );
    }
    if as_image && !(1..=MAX_RENDER_SIZE).contains(&args.image_size) {
        bail!(
            "--image-size {}: expected 1 to {MAX_RENDER_SIZE} pixels",
            args.image_size
        );
    }
    if matches!(output, Output::Lottie) && (args.png || args.viewbox == ViewBoxArg::Fit) {
        bail!(
            "{}: --png and --viewbox fit are for SVG output; a Lottie animation keeps the \
             drawing's viewBox",
            args.output.display()
        );
    }
    if !(args.lottie_tolerance.is_finite() && args.lottie_tolerance >= 0.0) {
        bail!(
            "--lottie-tolerance {}: expected a finite number, 0 or more (a fraction of the \
             drawing's diagonal)",
            args.lottie_tolerance
        );
    }
    if matches!(output, Output::Svg) && args.png {
        bail!(
            "{}: --png writes PNG frames into a folder; give a folder name instead of an .svg file",
            args.output.display()
        );
    }
    Ok(output)
}

/// The scene (a drawing with pins going there and back, or a scene file) and its animation
/// with `--fps` and `--duration` applied.
fn load_animation(args: &Args, scene_name: &str) -> Result<(Scene, Animation)> {
    let from_svg = crate::drawing_input::is_svg(&args.scene);
    if from_svg && args.svg_input.pose.is_empty() {
        bail!(
            "{scene_name}: nothing moves: give the pose the animation goes to with --move \
             I:DX,DY, --rotate I:DEG or --scale I:S (pins numbered from 0)"
        );
    }
    let mut scene = args.svg_input.scene(&args.scene)?;
    if from_svg {
        scene.animation = Some(crate::drawing_input::there_and_back(&scene)?);
    }
    let Some(animation) = &scene.animation else {
        bail!(
            "{scene_name}: the scene has no animation (expected an \"animation\" with keyframes \
             in our format, or a non-empty \"animationFrames\" in the authors')"
        );
    };
    let mut animation = animation.clone();
    if let Some(fps) = args.fps {
        animation = animation
            .with_fps(fps)
            .with_context(|| format!("{scene_name}: --fps"))?;
    }
    if let Some(duration) = args.duration {
        animation = animation
            .with_duration(duration)
            .with_context(|| format!("{scene_name}: --duration"))?;
    }
    Ok((scene, animation))
}

/// Writes the Lottie animation of `scene` (`-o NAME.json`).
fn write_lottie(args: &Args, scene: &Scene, animation: &Animation, scene_name: &str) -> Result<()> {
    let name = args
        .scene
        .file_stem()
        .map_or("splineskin".into(), |s| s.to_string_lossy().into_owned());
    let options = LottieOptions::default()
        .with_tolerance(args.lottie_tolerance)
        .with_name(name);
    let made = lottie_of_scene(
        scene,
        animation,
        args.posing.options(false),
        &options,
        scene_name,
    )?;
    for w in &made.rig_warnings {
        eprintln!("warning: {w}");
    }
    for w in &made.lottie.warnings {
        eprintln!("warning: {}: {w}", args.output.display());
    }
    for n in &made.lottie.player_notes {
        eprintln!("note: {}: {n}", args.output.display());
    }
    if has_extension(&args.output, "lottie") {
        let archive = crate::dotlottie::dotlottie(&made.lottie.json, &options.name)?;
        write_atomic(&args.output, &archive)?;
        eprintln!(
            "{}: {}; {} bytes as .lottie",
            args.output.display(),
            made.summary(&options),
            archive.len()
        );
    } else {
        write_atomic(&args.output, made.lottie.json.as_bytes())?;
        eprintln!("{}: {}", args.output.display(), made.summary(&options));
    }
    Ok(())
}

/// An animation to write frame by frame ([`SceneFrames`]), with the command's arguments.
struct Job<'a> {
    args: &'a Args,
    frames: SceneFrames<'a>,
}

impl Job<'_> {
    fn drawing(&self) -> &Drawing {
        self.frames.drawing()
    }

    /// `--viewbox fit` for outputs written frame by frame: the union over every frame,
    /// deformed [`FRAME_CHUNK`] at a time, before any frame is written.
    fn union_first(&self, outside: &mut FramesOutside) -> Result<()> {
        if self.args.viewbox == ViewBoxArg::Fit {
            for (c, chunk) in self.times().chunks(FRAME_CHUNK).enumerate() {
                let first = c * FRAME_CHUNK;
                for (k, points) in self.frames.deform_chunk(first, chunk)?.iter().enumerate() {
                    outside.add(first + k, self.drawing(), points);
                }
            }
        }
        Ok(())
    }

    fn times(&self) -> &[f64] {
        self.frames.times()
    }

    fn scene_name(&self) -> &str {
        self.frames.name()
    }

    /// `-o NAME.png` / `-o NAME.gif`: every frame rendered into an animated image
    /// ([`SceneFrames::animated_image`]).
    fn write_image(&self, format: AnimatedFormat) -> Result<()> {
        let args = self.args;
        let mut outside = FramesOutside::default();
        self.union_first(&mut outside)?;
        let rule = outside.rule(args.viewbox);
        let keep = args.viewbox == ViewBoxArg::Keep;
        let bytes =
            self.frames
                .animated_image(format, args.image_size, rule, |f, points, svg| {
                    if keep {
                        outside.add(f, self.drawing(), points);
                    }
                    if f == 0 {
                        crate::output::note_font_substitutes(&args.output, svg);
                    }
                })?;
        write_atomic(&args.output, &bytes)?;
        outside.report(&args.output, args.viewbox);
        Ok(())
    }

    /// `-o NAME.svg`: one animated SVG holding every frame ([`SceneFrames::animated_svg`];
    /// refused past [`MAX_ANIMATED_SVG_BYTES`], estimated).
    fn write_animated_svg(&self) -> Result<()> {
        let (args, drawing) = (self.args, self.drawing());
        let mut outside = FramesOutside::default();
        let fit = args.viewbox == ViewBoxArg::Fit;
        let svg = match self
            .frames
            .animated_svg(fit, |f, points| outside.add(f, drawing, points))
        {
            Err(SceneAnimationError::TooLarge {
                frames,
                n_points,
                bytes,
                ..
            }) => bail!(
                "{}: {frames} frames of {n_points} points make an animated SVG of about {:.1} GB, \
                 more than the limit of {:.1} GB (expected fewer frames: lower --fps or \
                 --duration, or write a frames folder, which is written frame by frame)",
                args.output.display(),
                bytes / 1e9,
                MAX_ANIMATED_SVG_BYTES as f64 / 1e9
            ),
            made => made?,
        };
        write_atomic(&args.output, svg.as_bytes())?;
        outside.report(&args.output, args.viewbox);
        Ok(())
    }

    /// `-o DIR`: a folder of frames ([`write_frames`]).
    fn write_frames(&self) -> Result<()> {
        let mut outside = FramesOutside::default();
        self.union_first(&mut outside)?;
        let rule = outside.rule(self.args.viewbox);
        let gather = (self.args.viewbox == ViewBoxArg::Keep).then_some(&mut outside);
        write_frames(
            self.args,
            self.scene_name(),
            self.drawing(),
            self.times(),
            (rule, gather),
            |first, times| Ok(self.frames.deform_chunk(first, times)?),
            |f, points, rule| Ok(self.frames.frame_svg(f, points, rule)?),
        )?;
        outside.report(&self.args.output, self.args.viewbox);
        Ok(())
    }
}

/// Writes `bytes` to `path` and flushes it to disk (frames are complete before their folder is
/// renamed into place); errors name the file.
/// `posed` with its drawing refined by adaptive control points for the pose of every frame
/// ([`splineskin::adaptive::refine`]), rigged (flexible again when `posed` is).
fn refined_for_frames(
    posed: PosedDrawing,
    sampler: &splineskin::animation::PoseSampler,
    times: &[f64],
    tolerance: f64,
) -> Result<PosedDrawing> {
    use splineskin::adaptive::{refine, AdaptiveOptions};
    use splineskin::scene::Deformer;
    let poses: Vec<Vec<kurbo::Affine>> = times
        .iter()
        .map(|&t| {
            let mut pose = vec![kurbo::Affine::IDENTITY; sampler.n_handles()];
            sampler.pose_at(t, &mut pose);
            pose
        })
        .collect();
    let flexible = posed.flexible_solver().map(|s| *s.options());
    let origin = posed.origin().to_string();
    let mut setup = posed.into_setup();
    let refined = refine(
        &setup.drawing,
        setup.weights.as_ref(),
        &setup.options,
        &poses,
        &AdaptiveOptions::default().with_tolerance(tolerance),
    )?;
    eprintln!(
        "note: adaptive: {} anchors inserted ({} curves, {} rounds), largest distance {:.3e} of the diagonal over {} frames{}",
        refined.n_inserted(),
        refined.drawing.n_curves(),
        refined.rounds,
        refined.worst,
        poses.len(),
        if refined.met { "" } else { " (the curve budget ran out before the tolerance)" }
    );
    let deformer = match flexible {
        Some(options) => Deformer::Flexible(Box::new(refined.flexible_solver(
            setup.weights.as_ref(),
            &setup.options,
            options,
        )?)),
        None => Deformer::Fixed(refined.rig),
    };
    setup.drawing = refined.drawing;
    Ok(PosedDrawing::from_parts(origin, setup, deformer))
}

/// Extensions of single files that are not an animated SVG: an output named so is refused
/// rather than becoming a frames folder of that name.
const FILE_EXTENSIONS: [&str; 6] = ["jpg", "jpeg", "webp", "pdf", "html", "mp4"];

/// Whether `path` names an `.svg` file (otherwise it names a frames folder).
fn is_svg_name(path: &Path) -> bool {
    has_extension(path, "svg")
}

/// Writes the frames (deformed [`FRAME_CHUNK`] at a time by `deform_chunk(first, times)`) into
/// a temporary folder beside `args.output`, then renames it into place (module doc), each as
/// `frame_svg(f, points, view.0)` writes it; `view.1`, if given, is told every frame written.
fn write_frames(
    args: &Args,
    scene_name: &str,
    drawing: &splineskin::drawing::Drawing,
    times: &[f64],
    view: (ViewBoxRule, Option<&mut FramesOutside>),

    deform_chunk: impl Fn(usize, &[f64]) -> Result<Vec<Vec<Point>>>,
    frame_svg: impl Fn(usize, &[Point], ViewBoxRule) -> Result<String>,
) -> Result<()> {
    let (view_box, mut gather) = view;
    let dir = &args.output;
    replace_frames_folder(dir, &["svg", "png"], |tmp| {
        let write_one = |f: usize, points: &Vec<Point>| -> Result<()> {
            let svg = frame_svg(f, points, view_box)?;
            write_synced(&tmp.join(frame_name(f, "svg")), svg.as_bytes())?;
            if args.png {
                if f == 0 {
                    crate::output::note_font_substitutes(&dir.join(frame_name(f, "png")), &svg);
                }
                let png = splineskin::render::render_png(&svg, PNG_SIZE)
                    .with_context(|| format!("{scene_name}: frame {f}: rendering the PNG"))?;
                write_synced(&tmp.join(frame_name(f, "png")), &png)?;
            }
            Ok(())
        };
        for (c, chunk) in times.chunks(FRAME_CHUNK).enumerate() {
            let first = c * FRAME_CHUNK;
            for (k, points) in deform_chunk(first, chunk)?.iter().enumerate() {
                write_one(first + k, points)?;
                if let Some(gather) = gather.as_deref_mut() {
                    gather.add(first + k, drawing, points);
                }
            }
        }
        Ok(())
    })
}
