//! A drawing given on the command line instead of a scene: `deform`, `animate`, `weights` and
//! `rig` take an SVG with pins (`--pin X,Y`, `--pins N`: placed by
//! [`splineskin::scene::place_pins`] when none are given), a weight family (`--weights`) and a
//! pose (`--move I:DX,DY`, `--rotate I:DEG`, `--scale I:S`). The scene is made of the drawing
//! as read, with no scene file in between ([`splineskin::scene::Scene::from_pins`]), checked as
//! a scene file is; `splineskin rig` writes that same scene ([`Scene::to_json`]), so that an SVG
//! with flags and the scene `rig` writes for the same flags are one and the same scene.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use kurbo::{Affine, Point, Vec2};
use splineskin::animation::{Animation, Keyframe, DEFAULT_FPS};
use splineskin::drawing::text_outlines::text_to_outlines;
use splineskin::drawing::{read_svg_file, Drawing, ImportOptions, SvgError};
use splineskin::scene::handles::transform_about;
use splineskin::scene::pinned::PinnedDrawing;
use splineskin::scene::{
    place_pins, scene_domain_options, PinCount, PinOptions, Scene, WeightSpec, MAX_COORDINATE,
};

use crate::output::has_extension;

/// Pins and weights for an SVG input.
#[derive(clap::Args, Clone, Debug, Default)]
#[command(next_help_heading = "Pins (when the input is an SVG)")]
pub struct PinArgs {
    /// A pin at X,Y in the drawing's user units (its viewBox), e.g. `--pin 10,20`; repeat for
    /// more. Pins are numbered from 0 in the order given, automatic ones after them. With
    /// --pin and no --pins, the pins are exactly these.
    #[arg(long = "pin", value_name = "X,Y", value_parser = parse_pin, allow_hyphen_values = true)]
    pub pins: Vec<Point>,
    /// How many pins in all: automatic pins are added after the --pin ones up to N. Without
    /// --pin or --pins: as many as the drawing needs (3 to 6), spread over its filled shapes.
    #[arg(long = "pins", value_name = "N")]
    pub count: Option<usize>,
    /// Weight family of the pins: bbw (bounded biharmonic, default), shepard (inverse
    /// distance, instant), harmonic, biharmonic.
    #[arg(long, value_enum, value_name = "FAMILY")]
    pub weights: Option<Family>,
    /// How far the weights' domain reaches beyond the art (Puppet Warp's "expansion"), as a
    /// fraction of the drawing's diagonal, 0 to 1 (default 0.01). Parts of the art closer than
    /// about twice this are joined; farther apart, a pin on one does not move the other. Mesh
    /// families only (bbw, harmonic, biharmonic).
    #[arg(long, value_name = "FRACTION", value_parser = parse_margin)]
    pub margin: Option<f64>,
}

/// What `deform` and `animate` take besides a scene: an SVG's pins and pose, and what becomes
/// of the drawing's text.
#[derive(clap::Args, Clone, Debug, Default)]
pub struct SvgInputArgs {
    #[command(flatten)]
    pub pins: PinArgs,
    #[command(flatten)]
    pub pose: PoseArgs,
    #[command(flatten)]
    pub text: TextArgs,
}

impl SvgInputArgs {
    /// The scene `input` names ([`load`]: a scene file, or the SVG with its pins and pose),
    /// its text turned to outlines when asked ([`TextArgs::apply`]).
    pub fn scene(&self, input: &Path) -> Result<Scene> {
        let mut scene = load(input, &self.pins, Some(&self.pose))?;
        self.text.apply(&mut scene)?;
        Ok(scene)
    }
}

/// What becomes of the drawing's text (scene or SVG input).
#[derive(clap::Args, Clone, Debug, Default)]
pub struct TextArgs {
    /// Convert text to outlines: each <text> becomes paths of its glyphs (in DejaVu Sans, the
    /// font PNG renders use), which deform as curves with the art; the output has these paths
    /// where the text was, and the string can no longer be edited as text. Without it, text
    /// stays text.
    #[arg(long)]
    pub text_outlines: bool,
}

impl TextArgs {
    /// Replaces the scene's SVG text by its text-as-outlines version when asked
    /// ([`splineskin::drawing::text_outlines::text_to_outlines`]).
    pub fn apply(&self, scene: &mut Scene) -> Result<()> {
        if self.text_outlines {
            scene.svg_text = text_to_outlines(&scene.svg_text, &scene.svg_origin)?;
        }
        Ok(())
    }
}

/// A pose of the pins, for an SVG input.
#[derive(clap::Args, Clone, Debug, Default)]
#[command(next_help_heading = "Pose (when the input is an SVG)")]
pub struct PoseArgs {
    /// Move pin I by DX,DY (user units), e.g. `--move 1:5,-3`. Repeat for other pins.
    #[arg(long = "move", value_name = "I:DX,DY", value_parser = parse_move, allow_hyphen_values = true)]
    pub moves: Vec<(usize, Vec2)>,
    /// Turn pin I by DEG degrees about itself, and the art it holds with it (clockwise on
    /// screen: SVG's y points down), e.g. `--rotate 0:15`.
    #[arg(long = "rotate", value_name = "I:DEG", value_parser = parse_rotate, allow_hyphen_values = true)]
    pub rotations: Vec<(usize, f64)>,
    /// Scale pin I by S, or by SX,SY, about itself, and the art it holds with it, e.g.
    /// `--scale 2:1.5`. A pin is scaled, then turned, then moved.
    #[arg(long = "scale", value_name = "I:S", value_parser = parse_scale, allow_hyphen_values = true)]
    pub scales: Vec<(usize, (f64, f64))>,
}

impl PinArgs {
    /// The flags given, by name, for messages.
    pub fn given(&self) -> Vec<&'static str> {
        let mut flags = Vec::new();
        if !self.pins.is_empty() {
            flags.push("--pin");
        }
        if self.count.is_some() {
            flags.push("--pins");
        }
        if self.weights.is_some() {
            flags.push("--weights");
        }
        if self.margin.is_some() {
            flags.push("--margin");
        }
        flags
    }
}

impl PoseArgs {
    fn given(&self) -> Vec<&'static str> {
        let mut flags = Vec::new();
        if !self.moves.is_empty() {
            flags.push("--move");
        }
        if !self.rotations.is_empty() {
            flags.push("--rotate");
        }
        if !self.scales.is_empty() {
            flags.push("--scale");
        }
        flags
    }

    /// Whether any pin is posed.
    pub fn is_empty(&self) -> bool {
        self.given().is_empty()
    }

    /// One map per pin: each pin's `--scale`, then `--rotate` about it, then `--move`
    /// ([`transform_about`], the scene format's `{"translate", "rotate", "scale"}`). Errors
    /// name the flag for a pin index out of range or a pin posed twice by one flag.
    pub fn transforms(&self, pins: &[Point]) -> Result<Vec<Affine>> {
        let n = pins.len();
        let mut parts = vec![(Vec2::ZERO, 0.0, (1.0, 1.0)); n];
        let mut seen = vec![[false; 3]; n];
        let mut check = |flag: &str, slot: usize, i: usize| -> Result<()> {
            if i >= n {
                bail!(
                    "{flag} {i}:…: there is no pin {i} (expected an index below {n}: {n} pins, \
                     numbered from 0; `splineskin rig` lists them)"
                );
            }
            if std::mem::replace(&mut seen[i][slot], true) {
                bail!("{flag} is given twice for pin {i} (expected at most once per pin)");
            }
            Ok(())
        };
        for &(i, d) in &self.moves {
            check("--move", 0, i)?;
            parts[i].0 = d;
        }
        for &(i, degrees) in &self.rotations {
            check("--rotate", 1, i)?;
            parts[i].1 = degrees;
        }
        for &(i, s) in &self.scales {
            check("--scale", 2, i)?;
            parts[i].2 = s;
        }
        Ok(pins
            .iter()
            .zip(&parts)
            .map(|(&p, &(t, r, s))| transform_about(p, t, r, s))
            .collect())
    }
}

/// The `--weights` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Family {
    /// Bounded biharmonic weights on a triangulation of the drawing (Puppet Warp's behaviour).
    Bbw,
    /// Shepard (inverse squared distance) weights: closed form, instant.
    Shepard,
    /// Harmonic weights on a triangulation of the drawing.
    Harmonic,
    /// Biharmonic weights (unbounded) on a triangulation of the drawing.
    Biharmonic,
}

impl Family {
    /// The default family of an SVG input.
    pub const DEFAULT: Family = Family::Bbw;

    /// The name used in scenes.
    pub fn name(self) -> &'static str {
        match self {
            Family::Bbw => "bbw",
            Family::Shepard => "shepard",
            Family::Harmonic => "harmonic",
            Family::Biharmonic => "biharmonic",
        }
    }
}

/// Whether `path` is an SVG document rather than a scene: its name ends in `.svg`, or its first
/// non-blank character is `<` (scenes are JSON objects). An unreadable file is not one (the
/// scene reader then says why it cannot read it).
pub fn is_svg(path: &Path) -> bool {
    if has_extension(path, "svg") {
        return true;
    }
    use std::io::Read;
    let mut head = [0u8; 256];
    let Ok(n) = std::fs::File::open(path).and_then(|mut f| f.read(&mut head)) else {
        return false;
    };
    let text = String::from_utf8_lossy(&head[..n]);
    text.trim_start_matches('\u{feff}')
        .trim_start()
        .starts_with('<')
}

/// The scene `input` names: read as a scene file, or built from the SVG `input` and the pin
/// and pose flags. A scene given pin or pose flags is an error naming them (its handles and
/// poses are its own).
pub fn load(input: &Path, pins: &PinArgs, pose: Option<&PoseArgs>) -> Result<Scene> {
    if !is_svg(input) {
        let mut flags = pins.given();
        flags.extend(pose.map(PoseArgs::given).unwrap_or_default());
        if !flags.is_empty() {
            bail!(
                "{}: {} apply to an SVG drawing; this is a scene, with its own handles, \
                 weights and poses (edit the scene, or give its SVG instead)",
                input.display(),
                flags.join(", ")
            );
        }
        return Ok(Scene::load(input)?);
    }
    let rigged = Rigged::new(input, pins, pose)?;
    let (pin_list, family) = (rigged.pin_list(), rigged.family);
    let scene = rigged
        .into_scene(&input.display().to_string())
        .with_context(|| format!("{}: the scene of its pins", input.display()))?;
    eprintln!(
        "{}: pins {pin_list}; {} weights",
        input.display(),
        family.name()
    );
    Ok(scene)
}

/// Seconds from rest to the pose in [`there_and_back`]: 1.
pub const SECONDS_TO_POSE: f64 = 1.0;

/// The animation of an SVG input: rest at 0 s, the scene's pose (its first) at
/// [`SECONDS_TO_POSE`], rest again at twice that, so that it loops without a jump; sampled at
/// [`splineskin::animation::DEFAULT_FPS`].
pub fn there_and_back(scene: &Scene) -> Result<Animation> {
    let rest = vec![Affine::IDENTITY; scene.n_handles()];
    let pose = scene
        .pose(0)
        .with_context(|| format!("{}: no pose (a bug)", scene.origin))?;
    let keyframes = [
        (0.0, &rest),
        (SECONDS_TO_POSE, &pose.transforms),
        (2.0 * SECONDS_TO_POSE, &rest),
    ]
    .into_iter()
    .map(|(time, transforms)| Keyframe::new(time, transforms.clone()))
    .collect();
    Animation::new(DEFAULT_FPS, keyframes)
        .with_context(|| format!("{}: the animation to the pose", scene.origin))
}

/// An SVG drawing with its pins, weight family and pose: what a scene is made of.
pub struct Rigged {
    /// The drawing.
    pub drawing: Drawing,
    /// The pins: the `--pin` ones, then the automatic ones.
    pub pins: Vec<Point>,
    /// How many of `pins` were given by `--pin`.
    pub n_given: usize,
    /// The weight family.
    pub family: Family,
    /// One map per pin.
    pub pose: Vec<Affine>,
    /// The domain's margin (`--margin`), when given.
    pub margin: Option<f64>,
}

impl Rigged {
    /// Reads `svg`, places its pins ([`place_pins`]: `--pin` ones first, kept exactly) and
    /// resolves the pose. Errors name the file and the flag.
    pub fn new(svg: &Path, args: &PinArgs, pose: Option<&PoseArgs>) -> Result<Rigged> {
        let drawing = read_svg_file(svg, &ImportOptions::default()).map_err(|e| match e {
            SvgError::NoPaths { .. } => anyhow::anyhow!("{e} (nothing to pin)"),
            e => e.into(),
        })?;
        for (k, p) in args.pins.iter().enumerate() {
            if let Some(j) = args.pins[..k].iter().position(|q| q == p) {
                bail!(
                    "--pin {},{}: given twice (pins {j} and {k}; expected distinct points)",
                    p.x,
                    p.y
                );
            }
        }
        let count = match (args.count, args.pins.is_empty()) {
            (Some(n), _) => PinCount::Exactly(n),
            (None, true) => PinCount::Auto,
            (None, false) => PinCount::Exactly(args.pins.len()),
        };
        let pins = place_pins(
            &drawing,
            &args.pins,
            &PinOptions::default().with_count(count),
        )
        .map_err(|e| {
            let flag = if args.count.is_some() {
                " (--pins)"
            } else {
                ""
            };
            anyhow::anyhow!("{}: placing pins{flag}: {e}", svg.display())
        })?;
        let family = args.weights.unwrap_or(Family::DEFAULT);
        if args.margin.is_some() && family == Family::Shepard {
            bail!(
                "--margin: the shepard weights have no domain (expected --weights bbw, harmonic \
                 or biharmonic with --margin)"
            );
        }
        let pose = match pose {
            Some(p) => p.transforms(&pins)?,
            None => vec![Affine::IDENTITY; pins.len()],
        };
        Ok(Rigged {
            drawing,
            n_given: args.pins.len(),
            pins,
            family,
            pose,
            margin: args.margin,
        })
    }

    /// The scene of the drawing, its pins, weights, margin and pose ([`Scene::from_pins`]):
    /// no scene file is written, and the drawing is not read again. `origin` names the drawing
    /// in messages.
    pub fn into_scene(self, origin: &str) -> Result<Scene> {
        let svg_text = match &self.drawing.source {
            Some(source) => source.text.clone(),
            None => bail!("{origin}: the drawing has no source text (a bug)"),
        };
        let domain = scene_domain_options();
        Ok(Scene::from_pins(PinnedDrawing {
            weights: WeightSpec::parse(self.family.name(), None, origin)?,
            domain: match self.margin {
                Some(margin) => domain.with_margin(margin),
                None => domain,
            },
            drawing: self.drawing,
            svg_text,
            origin: origin.to_string(),
            pins: self.pins,
            pose: self.pose,
        })?)
    }

    /// The pins as `0 (x, y), 1 (x, y), …`, the `--pin` ones marked `given`.
    pub fn pin_list(&self) -> String {
        self.pins
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let given = if i < self.n_given { " given" } else { "" };
                format!("{i} ({}, {}){given}", p.x, p.y)
            })
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// The folder of `path` (`.` for a bare file name).
pub fn folder_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// `X,Y` as a finite point within the scene format's coordinate limit.
fn parse_margin(text: &str) -> Result<f64, String> {
    let m = parse_number(text, "a fraction of the diagonal, 0 to 1")?;
    if (0.0..=splineskin::domain::MAX_MARGIN).contains(&m) {
        Ok(m)
    } else {
        Err(format!(
            "{text}: expected a fraction of the diagonal, 0 to 1"
        ))
    }
}

fn parse_pin(text: &str) -> Result<Point, String> {
    let [x, y] = parse_pair(text, "X,Y, two numbers in user units, e.g. 10,20")?;
    Ok(Point::new(x, y))
}

/// `I:DX,DY`.
fn parse_move(text: &str) -> Result<(usize, Vec2), String> {
    let (i, rest) = split_index(text, "I:DX,DY, e.g. 1:5,-3")?;
    let [dx, dy] = parse_pair(rest, "I:DX,DY, e.g. 1:5,-3")?;
    Ok((i, Vec2::new(dx, dy)))
}

/// `I:DEG`.
fn parse_rotate(text: &str) -> Result<(usize, f64), String> {
    let expected = "I:DEG, a pin index and degrees, e.g. 0:15";
    let (i, rest) = split_index(text, expected)?;
    Ok((i, parse_number(rest, expected)?))
}

/// `I:S` or `I:SX,SY`.
fn parse_scale(text: &str) -> Result<(usize, (f64, f64)), String> {
    let expected = "I:S or I:SX,SY, e.g. 2:1.5";
    let (i, rest) = split_index(text, expected)?;
    if rest.contains(',') {
        let [sx, sy] = parse_pair(rest, expected)?;
        Ok((i, (sx, sy)))
    } else {
        let s = parse_number(rest, expected)?;
        Ok((i, (s, s)))
    }
}

fn split_index<'t>(text: &'t str, expected: &str) -> Result<(usize, &'t str), String> {
    let (i, rest) = text
        .split_once(':')
        .ok_or_else(|| format!("expected {expected}"))?;
    let i = i
        .trim()
        .parse::<usize>()
        .map_err(|_| format!("'{i}' is not a pin index (expected {expected})"))?;
    Ok((i, rest))
}

fn parse_pair(text: &str, expected: &str) -> Result<[f64; 2], String> {
    let Some((a, b)) = text.split_once(',') else {
        return Err(format!("expected {expected}"));
    };
    Ok([parse_number(a, expected)?, parse_number(b, expected)?])
}

fn parse_number(text: &str, expected: &str) -> Result<f64, String> {
    let v: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("'{}' is not a number (expected {expected})", text.trim()))?;
    if !(v.is_finite() && v.abs() <= MAX_COORDINATE) {
        return Err(format!(
            "{} is not a finite number within ±{MAX_COORDINATE:e} (expected {expected})",
            text.trim()
        ));
    }
    Ok(v)
}
