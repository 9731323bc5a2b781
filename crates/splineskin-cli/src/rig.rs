//! `splineskin rig DRAWING.svg -o SCENE.json [--pin X,Y]… [--pins N] [--weights FAMILY]
//! [--inline] [--text-outlines] [--move I:DX,DY]…`: a scene of ours (version 1) for a drawing, its pins placed
//! by [`splineskin::scene::place_pins`] unless given, written by the library's scene writer
//! ([`Scene::to_json`]) and checked by reading it back. The drawing is named relative to the scene's folder, or
//! written into the scene with `--inline`.

use std::path::{Component, Path, PathBuf};

use anyhow::{bail, Context, Result};
use splineskin::drawing::text_outlines::text_to_outlines;
use splineskin::scene::ours_write::SvgRef;
use splineskin::scene::Scene;

use crate::drawing_input::{folder_of, is_svg, PinArgs, PoseArgs, Rigged};
use crate::output::{has_extension, write_atomic};

#[derive(clap::Args)]
pub struct Args {
    /// The drawing (SVG).
    drawing: PathBuf,
    /// The scene to write (JSON, our format).
    #[arg(short, long, value_name = "SCENE.json")]
    output: PathBuf,
    #[command(flatten)]
    pins: PinArgs,
    /// Write the drawing into the scene (`svg_text`) instead of naming its file (`svg`,
    /// relative to the scene's folder).
    #[arg(long)]
    inline: bool,
    // A pose to write into the scene (the rest pose without one).
    #[command(flatten)]
    pose: PoseArgs,
    /// Write the drawing into the scene (as --inline) with every <text> turned into paths of
    /// its glyph outlines, which deform as curves (see `deform --text-outlines`).
    #[arg(long)]
    text_outlines: bool,
}

pub fn run(args: Args) -> Result<()> {
    if !is_svg(&args.drawing) {
        bail!(
            "{}: expected an SVG drawing (a file ending in .svg, or one starting with '<')",
            args.drawing.display()
        );
    }
    let is_json = has_extension(&args.output, "json");
    if !is_json {
        bail!(
            "{}: a scene is JSON (expected a name ending in .json)",
            args.output.display()
        );
    }
    let rigged = Rigged::new(&args.drawing, &args.pins, Some(&args.pose))?;
    // The commands that set a scene up say these with its other warnings; rig says them here.
    crate::info::warn_import(&rigged.drawing);
    let scene_dir = folder_of(&args.output);
    let (text, outlined);
    let svg = if args.inline || args.text_outlines {
        text = std::fs::read_to_string(&args.drawing)
            .with_context(|| format!("{}: cannot read", args.drawing.display()))?;
        let text = if args.text_outlines {
            let origin = args.drawing.display().to_string();
            outlined = text_to_outlines(&text, &origin)?;
            &outlined
        } else {
            &text
        };
        SvgRef::Inline(text)
    } else {
        let relative = relative_path(&args.drawing, &scene_dir)?;
        text = relative
            .to_str()
            .with_context(|| {
                format!(
                    "{}: its path from {} is not UTF-8, which a scene cannot name (use --inline)",
                    args.drawing.display(),
                    scene_dir.display()
                )
            })?
            .to_string();
        SvgRef::File(&text)
    };
    let placed = if rigged.n_given == rigged.pins.len() {
        "as given".to_string()
    } else {
        format!(
            "{} placed automatically",
            rigged.pins.len() - rigged.n_given
        )
    };
    let summary = format!(
        "{} curves in {} paths, {} pins ({placed}): {}; {} weights",
        rigged.drawing.n_curves(),
        rigged.drawing.paths.len(),
        rigged.pins.len(),
        rigged.pin_list(),
        rigged.family.name(),
    );
    let made = rigged.into_scene(&args.drawing.display().to_string())?;
    let json = made.to_json(svg)?;
    // What is written must read back as the scene asked for.
    let scene = Scene::from_json(&json, &args.output.display().to_string(), Some(&scene_dir))
        .with_context(|| {
            format!(
                "{}: the scene written does not read back (a bug)",
                args.output.display()
            )
        })?;
    debug_assert_eq!(scene.handles, made.handles);
    write_atomic(&args.output, json.as_bytes())?;
    eprintln!(
        "{}: {summary} -> {}",
        args.drawing.display(),
        args.output.display()
    );
    Ok(())
}

/// The path of `file` from the folder `dir`, both made absolute first (`../art/fish.svg`).
fn relative_path(file: &Path, dir: &Path) -> Result<PathBuf> {
    let file = file
        .canonicalize()
        .with_context(|| format!("{}: cannot read", file.display()))?;
    let dir = dir.canonicalize().with_context(|| {
        format!(
            "{}: cannot find the scene's folder (expected an existing folder)",
            dir.display()
        )
    })?;
    let file_parts: Vec<Component> = file.components().collect();
    let dir_parts: Vec<Component> = dir.components().collect();
    let common = file_parts
        .iter()
        .zip(&dir_parts)
        .take_while(|(a, b)| a == b)
        .count();
    let mut relative = PathBuf::new();
    for _ in common..dir_parts.len() {
        relative.push("..");
    }
    for part in &file_parts[common..] {
        relative.push(part);
    }
    Ok(relative)
}
