//! From a [`Scene`] to what a rig is built from: the drawing (with the scene's junction
//! kinds), the weight functions and the fit options, in our default mode or in the paper
//! authors' compatibility mode.

use crate::drawing::authors_svg::read_authors_drawing_named;
use crate::drawing::{read_svg_named, Drawing, ImportOptions, JointKind};
use crate::spline_fit::FitOptions;
use crate::weights::{Shepard, ShepardOptions, WeightField};

use super::{MeshFamily, Scene, SceneError, WeightSpec};
use crate::domain::{Domain, DomainOptions, MeshWeights};
use crate::weights::bbw::{bbw_weights, BbwOptions};
use crate::weights::harmonic::harmonic_weights;

/// Squared distance under which a quadrature sample takes a handle's weight outright in the
/// authors' Shepard code: 1e-8 squared drawing units.
pub const AUTHORS_SHEPARD_SNAP: f64 = 1e-8;

/// Which discretisation to use.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum Compat {
    /// Ours: usvg import with exact degree elevation, Gauss quadrature consistent between both
    /// sides, strict C¹, constraints through the next distinct control point.
    #[default]
    None,
    /// The paper authors' code exactly (`--compat vectorskinning`): their SVG reading (only
    /// `<path>`, no transforms, lines as `start, start, end, end`), 100-sample midpoint
    /// integration, polyline-length weighting, their constraint rows, their Shepard snapping.
    VectorSkinning,
}

impl Compat {
    /// Parses the CLI's name (`vectorskinning`).
    pub fn from_name(name: &str) -> Option<Compat> {
        match name {
            "none" | "ours" => Some(Compat::None),
            "vectorskinning" => Some(Compat::VectorSkinning),
            _ => None,
        }
    }
}

/// Everything a rig is built from.
pub struct Setup {
    /// The drawing, with the scene's junction kinds applied.
    pub drawing: Drawing,
    /// One weight function per handle.
    pub weights: Box<dyn WeightField>,
    /// The fit options.
    pub options: FitOptions,
    /// Things the user should know (e.g. saved junction kinds that did not fit the drawing).
    pub warnings: Vec<String>,
    /// The triangulated domain the weights were solved on (mesh weight families only), for
    /// showing the mesh and reporting its size.
    pub domain: Option<Domain>,
}

impl Scene {
    /// Reads the scene's drawing, applies its junction kinds, and builds its weights and fit
    /// options for `compat`. Errors if the scene needs something not implemented
    /// ([`Scene::check_supported`]) or its drawing cannot be read.
    pub fn setup(&self, compat: Compat) -> Result<Setup, SceneError> {
        self.check_supported()?;
        let mut warnings = Vec::new();
        let mut drawing = self.drawing(compat)?;
        if let Some(kinds) = &self.authors_joints {
            if let Some(w) = apply_authors_joints(&mut drawing, kinds, compat) {
                warnings.push(format!("{}: {w}", self.origin));
            }
        }
        for (i, o) in self.junctions.iter().enumerate() {
            let invalid = |message: String| SceneError::Invalid {
                origin: self.origin.clone(),
                element: format!("junctions[{i}]"),
                message,
            };
            let n_paths = drawing.paths.len();
            let path = drawing.paths.get_mut(o.path).ok_or_else(|| {
                invalid(format!(
                    "path {} does not exist (the drawing has {n_paths})",
                    o.path
                ))
            })?;
            let n_joints = path.joints.len();
            let slot = path.joints.get_mut(o.joint).ok_or_else(|| {
                invalid(format!(
                    "joint {} does not exist (path {} has {n_joints})",
                    o.joint, o.path
                ))
            })?;
            if *slot == JointKind::End {
                return Err(invalid(format!(
                    "joint {} of path {} is an open end: it has no junction",
                    o.joint, o.path
                )));
            }
            *slot = o.kind;
        }
        let (options, snap) = match compat {
            Compat::None => (FitOptions::default().with_measure(self.measure), 0.0),
            Compat::VectorSkinning => (
                FitOptions::vectorskinning(self.measure == crate::spline_fit::Measure::ArcLength),
                AUTHORS_SHEPARD_SNAP,
            ),
        };
        if self.handles.is_empty() {
            return Err(SceneError::Invalid {
                origin: self.origin.clone(),
                element: "handles".into(),
                message: "no handles: place at least one".into(),
            });
        }
        let mut domain = None;
        let weights: Box<dyn WeightField> = match &self.weights {
            WeightSpec::Shepard { exponent } => Box::new(Shepard::new(
                &self.handles,
                ShepardOptions::default()
                    .with_exponent(*exponent)
                    .with_snap_distance_squared(snap),
            )),
            WeightSpec::Mesh(family) => {
                let (weights, mesh_domain) =
                    mesh_weights(&drawing, &self.handles, *family, &self.origin)?;
                domain = Some(mesh_domain);
                Box::new(weights)
            }
            WeightSpec::NotImplemented(name) => {
                return Err(SceneError::NotImplemented {
                    origin: self.origin.clone(),
                    what: format!("weight function '{name}'"),
                })
            }
        };
        Ok(Setup {
            drawing,
            weights,
            options,
            warnings,
            domain,
        })
    }

    /// Reads the scene's SVG with the importer of `compat`, joints classified by it. Errors
    /// name [`Scene::svg_origin`] (our importer's as [`SceneError::Svg`], the authors' reader's
    /// as [`SceneError::Drawing`]); in our mode the drawing's [`crate::drawing::SvgSource`]
    /// carries it too, so export errors name it as well.
    pub fn drawing(&self, compat: Compat) -> Result<Drawing, SceneError> {
        match compat {
            Compat::None => Ok(read_svg_named(
                &self.svg_text,
                &ImportOptions::default(),
                &self.svg_origin,
            )?),
            Compat::VectorSkinning => read_authors_drawing_named(&self.svg_text, &self.svg_origin)
                .map_err(|e| SceneError::Drawing {
                    origin: self.svg_origin.clone(),
                    source: Box::new(e),
                }),
        }
    }
}

/// Weights of `family` for point `handles`: the drawing's domain is triangulated with its
/// handles and curve samples as vertices ([`Domain::build`] with default options), the
/// family's solve runs on that mesh, and [`MeshWeights`] interpolates the vertex weights
/// (exact piecewise-linear, with the mesh edges as quadrature kinks). Returns the weights and
/// the domain they were solved on.
pub fn mesh_weights(
    drawing: &Drawing,
    handles: &[kurbo::Point],
    family: MeshFamily,
    origin: &str,
) -> Result<(MeshWeights, Domain), SceneError> {
    let wrap = |source: Box<dyn std::error::Error + Send + Sync>| SceneError::Weights {
        origin: origin.to_string(),
        family: family.name(),
        source,
    };
    let domain = Domain::build(drawing, handles, &[], &DomainOptions::default())
        .map_err(|e| wrap(Box::new(e)))?;
    let vertices = &domain.handle_vertices;
    let weights = match family {
        MeshFamily::Harmonic => harmonic_weights(&domain.mesh, vertices, 1),
        MeshFamily::Biharmonic => harmonic_weights(&domain.mesh, vertices, 2),
        MeshFamily::Bbw => bbw_weights(&domain.mesh, vertices, &BbwOptions::default()),
    }
    .map_err(|e| wrap(Box::new(e)))?;
    let weights = MeshWeights::new(&domain.mesh, weights.into_values(), handles.len())
        .map_err(|e| wrap(Box::new(e)))?;
    Ok((weights, domain))
}

/// Applies the authors' saved per-joint kinds when the drawing has their structure (same
/// number of paths, each with their number of joints); otherwise returns why not.
///
/// Their `C1` is not strict C¹: their solver writes it as a tangent of fixed direction and
/// fixed length *ratio* (the input's), which is our [`JointKind::G1`]. In default mode it is
/// read as such, so a junction whose tangents have different lengths keeps its shape (strict
/// C¹ would make the lengths equal). Compatibility mode keeps the label: its constraint form
/// writes their rows for both.
fn apply_authors_joints(
    drawing: &mut Drawing,
    kinds: &[Vec<JointKind>],
    compat: Compat,
) -> Option<String> {
    if kinds.is_empty() {
        return None;
    }
    let fits = kinds.len() == drawing.paths.len()
        && drawing
            .paths
            .iter()
            .zip(kinds)
            .all(|(p, k)| k.len() == p.n_curves() || k.len() == p.joints.len());
    if !fits {
        return Some(format!(
            "the saved junction kinds ({} paths) do not match the drawing as read ({} paths); they are ignored and junctions are classified from the geometry",
            kinds.len(),
            drawing.paths.len()
        ));
    }
    for (path, k) in drawing.paths.iter_mut().zip(kinds) {
        let n = path.joints.len();
        for (j, slot) in path.joints.iter_mut().enumerate() {
            let open_end = !path.closed && (j == 0 || j + 1 == n);
            if open_end {
                *slot = JointKind::End;
            } else if let Some(&kind) = k.get(j) {
                *slot = match (kind, compat) {
                    (JointKind::End, _) => *slot,
                    (JointKind::C1, Compat::None) => JointKind::G1,
                    _ => kind,
                };
            }
        }
    }
    None
}
