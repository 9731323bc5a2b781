//! `splineskin info FILE`: paths, curves and junction kinds of an SVG (or of a scene's drawing);
//! for a scene also its handles by kind and, for the mesh weight families, the size of the
//! triangulated domain.

use std::collections::BTreeMap;
use std::path::PathBuf;

use anyhow::Result;
use splineskin::domain::Domain;
use splineskin::drawing::{read_svg_file, Drawing, ImportOptions, JointKind};
use splineskin::scene::{Compat, Scene};

use crate::output::has_extension;
use crate::posing::CompatArg;

#[derive(clap::Args)]
pub struct Args {
    /// An SVG file, or a scene (`.json`) whose drawing to describe.
    file: PathBuf,
    /// Read the drawing as another implementation does.
    #[arg(long, value_enum, default_value_t = CompatArg::None)]
    compat: CompatArg,
}

pub fn run(args: Args) -> Result<()> {
    let compat: Compat = args.compat.into();
    let is_scene = has_extension(&args.file, "json");
    let drawing = if is_scene {
        let scene = Scene::load(&args.file)?;
        print!("{}", describe_scene(&scene));
        match scene.setup(compat) {
            Ok(setup) => {
                for w in &setup.warnings {
                    eprintln!("warning: {w}");
                }
                if let Some(domain) = &setup.domain {
                    println!("{}", describe_domain(domain));
                }
                setup.drawing
            }
            // The drawing alone may still be readable (e.g. the weights are not implemented):
            // describe it after a note. If it is not, its error is the one to report (once).
            Err(e) => {
                let drawing = scene.drawing(compat)?;
                eprintln!("note: {e}");
                drawing
            }
        }
    } else if compat == Compat::VectorSkinning {
        let text = std::fs::read_to_string(&args.file)
            .map_err(|e| anyhow::anyhow!("{}: cannot read: {e}", args.file.display()))?;
        let drawing = splineskin::drawing::authors_svg::read_authors_drawing(&text)
            .map_err(|e| anyhow::anyhow!("{}: {e}", args.file.display()))?;
        // As in our mode (`SvgError::NoPaths`): a drawing without paths is an error.
        anyhow::ensure!(
            !drawing.paths.is_empty(),
            "{}: no paths: expected at least one <path> element with a segment (compatibility \
             mode reads only <path> elements)",
            args.file.display()
        );
        drawing
    } else {
        let drawing = read_svg_file(&args.file, &ImportOptions::default())?;
        warn_import(&drawing);
        drawing
    };
    print!("{}", describe(&drawing));
    Ok(())
}

/// The scene's summary: handles by kind (in rig order), poses, weights and engine.
fn describe_scene(scene: &Scene) -> String {
    let set = scene.handle_set();
    let mut kinds = Vec::new();
    if !set.points.is_empty() || set.n_handles() == 0 {
        kinds.push(format!("{} points", set.points.len()));
    }
    if !set.bones.is_empty() {
        let rigid = set
            .bones
            .iter()
            .filter(|b| b.transform == splineskin::scene::BoneTransform::Rigid)
            .count();
        kinds.push(format!(
            "{} bones ({rigid} rigid, {} affine)",
            set.bones.len(),
            set.bones.len() - rigid
        ));
    }
    if let Some(cage) = set.cage {
        kinds.push(format!("{} cage vertices", cage.len()));
    }
    format!(
        "scene: {} handles ({}), {} poses, weights {}, engine {}\n",
        set.n_handles(),
        kinds.join(", then "),
        scene.poses.len(),
        scene.weights.name(),
        scene.engine.name()
    )
}

/// The domain's summary line.
fn describe_domain(domain: &Domain) -> String {
    let boundary = domain.boundary;
    format!(
        "domain: {} vertices, {} triangles, boundary {boundary}, {} holes, {} curve samples, \
         min angle {:.1}°{}",
        domain.mesh.n_vertices(),
        domain.mesh.n_triangles(),
        domain.n_holes(),
        domain.n_curve_samples,
        Domain::min_angle_of(&domain.mesh),
        if domain.refinement_complete {
            ""
        } else {
            " (refinement stopped at the vertex cap)"
        }
    )
}

/// The text `info` prints for a drawing.
fn describe(drawing: &Drawing) -> String {
    let mut totals: BTreeMap<&str, usize> = BTreeMap::new();
    let mut lines = String::new();
    for (i, path) in drawing.paths.iter().enumerate() {
        let label = drawing
            .source
            .as_ref()
            .map(|s| s.element_label(i))
            .unwrap_or_default();
        let kinds: Vec<&str> = path
            .joints
            .iter()
            .map(|k| {
                *totals.entry(k.name()).or_default() += 1;
                k.name()
            })
            .collect();
        lines.push_str(&format!(
            "  path {i:>4}  {:<6} {:>4} curves  {label}\n            joints: {}\n",
            if path.closed { "closed" } else { "open" },
            path.n_curves(),
            kinds.join(" ")
        ));
    }
    let summary: Vec<String> = [
        JointKind::C0,
        JointKind::C1,
        JointKind::G1,
        JointKind::FixedAngle,
        JointKind::End,
    ]
    .iter()
    .map(|k| {
        format!(
            "{} {}",
            k.name(),
            totals.get(k.name()).copied().unwrap_or(0)
        )
    })
    .collect();
    format!(
        "{} paths, {} curves; joints: {}\n{lines}",
        drawing.paths.len(),
        drawing.n_curves(),
        summary.join(", ")
    )
}

/// Prints on stderr what the import of `drawing` drew other than written (path data drawn up
/// to its first error, as browsers draw it).
pub fn warn_import(drawing: &Drawing) {
    if let Some(source) = &drawing.source {
        for w in &source.warnings {
            eprintln!("warning: {w}");
        }
    }
}
