//! A scene's `defop` section: how to train a deformation operator ([`crate::defop`]) for the
//! scene's point handles, and on which shape ([`Scene::defop_shape`]).
//!
//! ```json
//! "defop": {
//!   "energy": "symmetric-arap",
//!   "spatial_basis": "hats",
//!   "handle_basis": "tps",
//!   "samples": 1000,
//!   "region": { "disc": 0.05 },
//!   "seed": 1,
//!   "domain": { "max_area_fraction": 0.0005 },
//!   "mesh": "octopus.obj",
//!   "operator": "octopus.defop"
//! }
//! ```
//!
//! | key | meaning (default) |
//! |---|---|
//! | `energy` | `"arap"` or `"symmetric-arap"` (`symmetric-arap`) |
//! | `spatial_basis` | `"hats"`, `"eigen N"` (`1, x, y` and Laplacian eigenfunctions, `N` functions) or `"biharmonic N"` (biharmonic coordinates of the handles and farthest-point samples, `N` functions) (`hats`) |
//! | `handle_basis` | `"linear"`, `"quadratic"`, `"cubic"` or `"tps"` (`tps`) |
//! | `samples` | training samples besides the rest configuration, ≥ 1 ([`DEFAULT_TRAINING_SAMPLES`]) |
//! | `region` | where a handle's samples lie around its rest position, sizes as fractions of the shape's bounding-box diagonal: `{"disc": r}` (uniform in a disc), `{"circle": r}` (on a circle), `{"gaussian": σ}` (`{"disc": 0.05}`) |
//! | `seed` | the sampler's seed (1) |
//! | `cover` | configurations the operator must also follow: `"poses"` (the scene's poses), `"animation"` (its animation's frames, and its poses) or `"none"`; half the samples are then drawn around the way from the rest to them ([`crate::defop::Sampler::with_cover`]) (`"none"`) |
//! | `domain` | options of the triangulated drawing domain, keys as the scene's `domain` (defaults: [`crate::defop::training_domain_options`], coarser than the weights' domain: about 2 000–4 000 triangles for the bundled drawings) |
//! | `mesh` | a triangle mesh file (OBJ, `z = 0`, triangles only, relative to the scene's folder) to train on instead of the drawing's domain; every point handle must be one of its vertices |
//! | `operator` | a trained operator file (relative to the scene's folder) |
//!
//! Only point handles drive an operator: a scene with bones or a cage is refused.

use std::path::{Path, PathBuf};

use kurbo::Point;
use serde::Deserialize;

use super::{Compat, Scene, SceneError};
use crate::defop::{
    DefOpError, EigenOperator, Energy, HandleBasisKind, SampleRegion, SpatialBasis, TrainOptions,
    DEFAULT_DISC_FRACTION, DEFAULT_TRAINING_SAMPLES,
};
use crate::domain::{Domain, DomainOptions};
use crate::mesh::TriMesh;

/// Largest distance between a point handle and the mesh vertex it is matched to, as a
/// fraction of the mesh's bounding-box diagonal (1e-9: "the same point" up to rounding).
pub const HANDLE_VERTEX_TOLERANCE: f64 = 1e-9;

/// A spatial basis as a scene or the CLI names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpatialBasisSpec {
    /// The hat functions ([`SpatialBasis::hats`]).
    Hats,
    /// `N` functions: `1, x, y` and linearly precise Laplacian eigenfunctions
    /// ([`SpatialBasis::laplacian_eigenfunctions`] with [`EigenOperator::LinearlyPrecise`]).
    Eigen(usize),
    /// `N` biharmonic coordinates: the handles and farthest-point samples
    /// ([`SpatialBasis::biharmonic_coordinates_sampled`]).
    Biharmonic(usize),
}

impl SpatialBasisSpec {
    /// Reads `hats`, `eigen N` or `biharmonic N` (a space, `:` or `=` before `N`).
    ///
    /// ```
    /// use splineskin::scene::SpatialBasisSpec;
    /// assert_eq!(SpatialBasisSpec::parse("eigen 100"), Some(SpatialBasisSpec::Eigen(100)));
    /// assert_eq!(SpatialBasisSpec::parse("biharmonic:40"), Some(SpatialBasisSpec::Biharmonic(40)));
    /// assert_eq!(SpatialBasisSpec::parse("hats"), Some(SpatialBasisSpec::Hats));
    /// assert_eq!(SpatialBasisSpec::parse("eigen"), None);
    /// ```
    pub fn parse(text: &str) -> Option<SpatialBasisSpec> {
        let text = text.trim();
        if text == "hats" {
            return Some(SpatialBasisSpec::Hats);
        }
        let (name, n) = text.split_once([' ', ':', '='])?;
        let n: usize = n.trim().parse().ok()?;
        match name {
            "eigen" => Some(SpatialBasisSpec::Eigen(n)),
            "biharmonic" => Some(SpatialBasisSpec::Biharmonic(n)),
            _ => None,
        }
    }

    /// The name [`SpatialBasisSpec::parse`] reads.
    pub fn name(self) -> String {
        match self {
            SpatialBasisSpec::Hats => "hats".into(),
            SpatialBasisSpec::Eigen(n) => format!("eigen {n}"),
            SpatialBasisSpec::Biharmonic(n) => format!("biharmonic {n}"),
        }
    }

    /// The basis on `mesh` with handles at `handles`.
    pub fn build(self, mesh: &TriMesh, handles: &[usize]) -> Result<SpatialBasis, DefOpError> {
        match self {
            SpatialBasisSpec::Hats => SpatialBasis::hats(mesh),
            SpatialBasisSpec::Eigen(n) => {
                SpatialBasis::laplacian_eigenfunctions(mesh, n, EigenOperator::LinearlyPrecise)
            }
            SpatialBasisSpec::Biharmonic(n) => {
                SpatialBasis::biharmonic_coordinates_sampled(mesh, handles, n)
            }
        }
    }
}

/// Where a handle's samples lie, sizes as fractions of the shape's bounding-box diagonal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RegionSpec {
    /// Uniform in a disc of this radius.
    Disc(f64),
    /// Uniform on a circle of this radius.
    Circle(f64),
    /// Normal with this standard deviation per coordinate.
    Gaussian(f64),
}

impl RegionSpec {
    /// The region in drawing units for a shape of bounding-box diagonal `diagonal`.
    pub fn region(self, diagonal: f64) -> SampleRegion {
        match self {
            RegionSpec::Disc(f) => SampleRegion::Disc {
                radius: f * diagonal,
            },
            RegionSpec::Circle(f) => SampleRegion::Circle {
                radius: f * diagonal,
            },
            RegionSpec::Gaussian(f) => SampleRegion::Gaussian {
                sigma: f * diagonal,
            },
        }
    }

    /// A short description, e.g. `disc 0.05 of the diagonal`.
    pub fn describe(self) -> String {
        match self {
            RegionSpec::Disc(f) => format!("disc {f} of the diagonal"),
            RegionSpec::Circle(f) => format!("circle {f} of the diagonal"),
            RegionSpec::Gaussian(f) => format!("gaussian {f} of the diagonal"),
        }
    }
}

/// A scene's `defop` section (module documentation), every default filled in.
///
/// ```
/// use splineskin::scene::{DefOpSettings, SpatialBasisSpec};
/// let settings = DefOpSettings::default();
/// assert_eq!(settings.spatial_basis, SpatialBasisSpec::Hats);
/// assert_eq!(settings.samples, 1000);
/// ```
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct DefOpSettings {
    /// The ground truth's energy.
    pub energy: Energy,
    /// The spatial basis.
    pub spatial_basis: SpatialBasisSpec,
    /// The handle basis.
    pub handle_basis: HandleBasisKind,
    /// Training samples besides the rest configuration.
    pub samples: usize,
    /// The sampling region.
    pub region: RegionSpec,
    /// The sampler's seed.
    pub seed: u64,
    /// Which of the scene's configurations the samples also cover.
    pub cover: Cover,
    /// Options of the triangulated drawing domain trained on.
    pub domain: DomainOptions,
    /// A mesh file to train on instead (resolved against the scene's folder).
    pub mesh: Option<PathBuf>,
    /// A trained operator file (resolved against the scene's folder).
    pub operator: Option<PathBuf>,
}

impl Default for DefOpSettings {
    fn default() -> Self {
        DefOpSettings {
            energy: Energy::SymmetricArap,
            spatial_basis: SpatialBasisSpec::Hats,
            handle_basis: HandleBasisKind::ThinPlateSpline,
            samples: DEFAULT_TRAINING_SAMPLES,
            region: RegionSpec::Disc(DEFAULT_DISC_FRACTION),
            seed: 1,
            cover: Cover::None,
            domain: crate::defop::training_domain_options(),
            mesh: None,
            operator: None,
        }
    }
}

impl DefOpSettings {
    /// The training options these settings ask for on `mesh` (its bounding-box diagonal sizes
    /// the sampling region), solving on rayon's pool: what `splineskin defop train`, the
    /// study and the editor train with, so that a saved scene trains the same operator
    /// everywhere.
    ///
    /// ```
    /// use kurbo::Rect;
    /// use splineskin::mesh::TriMesh;
    /// use splineskin::scene::DefOpSettings;
    /// let mesh = TriMesh::grid(Rect::new(0., 0., 4., 3.), 4, 3)?;
    /// let options = DefOpSettings::default().train_options(&mesh);
    /// assert_eq!(options.n_samples, 1000);
    /// # Ok::<(), splineskin::mesh::MeshError>(())
    /// ```
    pub fn train_options(&self, mesh: &TriMesh) -> TrainOptions {
        TrainOptions::default()
            .with_energy(self.energy)
            .with_n_samples(self.samples)
            .with_regions(vec![(
                self.region.region(mesh.bounding_box_diagonal()),
                1.0,
            )])
            .with_seed(self.seed)
            .with_handle_basis(self.handle_basis)
            .with_parallel(true)
    }
}

/// Which configurations of a scene a trained operator must follow besides small moves about
/// the rest ([`DefOpSettings::cover`]; [`Scene::cover_configurations`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Cover {
    /// Only the sampling region about the rest.
    #[default]
    None,
    /// The scene's poses.
    Poses,
    /// The scene's animation frames (at its frame rate) and its poses.
    Animation,
}

impl Cover {
    /// Reads `none`, `poses` or `animation`.
    pub fn parse(name: &str) -> Option<Cover> {
        match name {
            "none" => Some(Cover::None),
            "poses" => Some(Cover::Poses),
            "animation" => Some(Cover::Animation),
            _ => None,
        }
    }

    /// The name [`Cover::parse`] reads.
    pub fn name(self) -> &'static str {
        match self {
            Cover::None => "none",
            Cover::Poses => "poses",
            Cover::Animation => "animation",
        }
    }
}

impl Scene {
    /// The configurations of the point handles whose rest positions are `rest` (one per point
    /// handle, e.g. the training shape's handle vertices) that `cover` asks an operator to
    /// follow: each pose's (and with [`Cover::Animation`] each animation frame's) map of every
    /// point handle applied to its rest position. Poses that are the identity are left out.
    ///
    /// ```
    /// use kurbo::Point;
    /// use splineskin::scene::{Cover, Scene};
    /// let scene = Scene::from_json(r#"{"splineskin_scene": 1,
    ///     "svg_text": "<svg xmlns='http://www.w3.org/2000/svg'><path d='M0 0 C30 40 70 40 100 0'/></svg>",
    ///     "handles": [{"position": [0, 0]}, {"position": [100, 0]}],
    ///     "poses": [{"transforms": [{}, {"translate": [0, 30]}]}]}"#, "inline", None)?;
    /// let rest = [Point::new(0.0, 0.0), Point::new(100.0, 0.0)];
    /// let cover = scene.cover_configurations(Cover::Poses, &rest)?;
    /// assert_eq!(cover, vec![vec![Point::new(0.0, 0.0), Point::new(100.0, 30.0)]]);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn cover_configurations(
        &self,
        cover: Cover,
        rest: &[Point],
    ) -> Result<Vec<Vec<Point>>, SceneError> {
        let mut poses: Vec<Vec<kurbo::Affine>> = match cover {
            Cover::None => return Ok(Vec::new()),
            Cover::Poses | Cover::Animation => {
                self.poses.iter().map(|p| p.transforms.clone()).collect()
            }
        };
        if cover == Cover::Animation {
            if let Some(animation) = &self.animation {
                let pivots = self.handle_set().pivots();
                let invalid = |e: String| SceneError::invalid(&self.origin, "animation", e);
                let times = animation
                    .frame_times()
                    .map_err(|e| invalid(e.to_string()))?;
                let sampler = animation
                    .sampler(&pivots)
                    .map_err(|e| invalid(e.to_string()))?;
                for t in times {
                    let mut pose = vec![kurbo::Affine::IDENTITY; sampler.n_handles()];
                    sampler.pose_at(t, &mut pose);
                    poses.push(pose);
                }
            }
        }
        Ok(poses
            .iter()
            .map(|pose| {
                rest.iter()
                    .zip(pose)
                    .map(|(&p, &t)| t * p)
                    .collect::<Vec<Point>>()
            })
            .filter(|q| q.iter().zip(rest).any(|(a, b)| a != b))
            .collect())
    }
}

/// Reads an energy name: `arap` or `symmetric-arap` (also `sarap`).
pub fn parse_energy(name: &str) -> Option<Energy> {
    match name {
        "arap" => Some(Energy::Arap),
        "symmetric-arap" | "sarap" => Some(Energy::SymmetricArap),
        _ => None,
    }
}

/// The name [`parse_energy`] reads.
pub fn energy_name(energy: Energy) -> &'static str {
    match energy {
        Energy::Arap => "arap",
        Energy::SymmetricArap => "symmetric-arap",
    }
}

/// Reads a handle basis name: `linear`, `quadratic`, `cubic`, `tps`.
pub fn parse_handle_basis(name: &str) -> Option<HandleBasisKind> {
    match name {
        "linear" => Some(HandleBasisKind::Linear),
        "quadratic" => Some(HandleBasisKind::Quadratic),
        "cubic" => Some(HandleBasisKind::Cubic),
        "tps" | "thin-plate" => Some(HandleBasisKind::ThinPlateSpline),
        _ => None,
    }
}

/// The section as written.
#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(crate) struct DefOpFile {
    #[serde(default)]
    energy: Option<String>,
    #[serde(default)]
    spatial_basis: Option<String>,
    #[serde(default)]
    handle_basis: Option<String>,
    #[serde(default)]
    samples: Option<usize>,
    #[serde(default)]
    region: Option<RegionFile>,
    #[serde(default)]
    seed: Option<u64>,
    #[serde(default)]
    cover: Option<String>,
    #[serde(default)]
    domain: Option<super::domain_file::DomainFile>,
    #[serde(default)]
    mesh: Option<String>,
    #[serde(default)]
    operator: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, rename_all = "lowercase")]
enum RegionFile {
    Disc(f64),
    Circle(f64),
    Gaussian(f64),
}

impl DefOpFile {
    /// The settings, checked; `base_dir` resolves file names.
    pub(crate) fn settings(
        &self,
        origin: &str,
        base_dir: Option<&Path>,
    ) -> Result<DefOpSettings, SceneError> {
        let invalid = |element: &str, message: String| {
            SceneError::invalid(origin, format!("defop.{element}"), message)
        };
        // A name that is none of the `expected` ones.
        let unknown = |element: &str, text: &str, expected: &str| {
            invalid(element, format!("{text:?}: expected {expected}"))
        };
        let mut s = DefOpSettings::default();
        if let Some(e) = &self.energy {
            let expected = "\"arap\" or \"symmetric-arap\"";
            s.energy = parse_energy(e).ok_or_else(|| unknown("energy", e, expected))?;
        }
        if let Some(b) = &self.spatial_basis {
            let expected = "\"hats\", \"eigen N\" or \"biharmonic N\"";
            s.spatial_basis =
                SpatialBasisSpec::parse(b).ok_or_else(|| unknown("spatial_basis", b, expected))?;
        }
        if let Some(b) = &self.handle_basis {
            let expected = "\"linear\", \"quadratic\", \"cubic\" or \"tps\"";
            s.handle_basis =
                parse_handle_basis(b).ok_or_else(|| unknown("handle_basis", b, expected))?;
        }
        if let Some(n) = self.samples {
            if n == 0 {
                return Err(invalid("samples", "0: expected at least 1".into()));
            }
            s.samples = n;
        }
        if let Some(r) = &self.region {
            let (name, f, spec) = match *r {
                RegionFile::Disc(f) => ("disc", f, RegionSpec::Disc(f)),
                RegionFile::Circle(f) => ("circle", f, RegionSpec::Circle(f)),
                RegionFile::Gaussian(f) => ("gaussian", f, RegionSpec::Gaussian(f)),
            };
            if !(f.is_finite() && f > 0.0) {
                return Err(invalid(
                    "region",
                    format!("{name} {f}: expected a positive fraction of the diagonal"),
                ));
            }
            s.region = spec;
        }
        if let Some(seed) = self.seed {
            s.seed = seed;
        }
        if let Some(c) = &self.cover {
            let expected = "\"poses\", \"animation\" or \"none\"";
            s.cover = Cover::parse(c).ok_or_else(|| unknown("cover", c, expected))?;
        }
        if let Some(d) = &self.domain {
            s.domain = d.options_over(s.domain.clone());
        }
        let resolve = |element: &str, name: &String| -> Result<PathBuf, SceneError> {
            match base_dir {
                Some(dir) => Ok(dir.join(name)),
                None => Err(invalid(
                    element,
                    format!(
                        "names the file {name}, but this scene was not read from a folder, so no file is read"
                    ),
                )),
            }
        };
        s.mesh = self.mesh.as_ref().map(|m| resolve("mesh", m)).transpose()?;
        s.operator = self
            .operator
            .as_ref()
            .map(|m| resolve("operator", m))
            .transpose()?;
        Ok(s)
    }
}

/// The shape an operator is trained on: a triangle mesh and the vertex of each point handle.
#[derive(Clone, Debug, PartialEq)]
pub struct DefOpShape {
    /// The mesh.
    pub mesh: TriMesh,
    /// The vertex of each point handle, in the scene's handle order.
    pub handles: Vec<usize>,
    /// Where the mesh came from (the mesh file, or the drawing's domain).
    pub origin: String,
}

impl Scene {
    /// The shape `settings` train on: the mesh file [`DefOpSettings::mesh`] with every point
    /// handle matched to the vertex at its position (within [`HANDLE_VERTEX_TOLERANCE`] of the
    /// diagonal), or else the drawing's domain triangulated with [`DefOpSettings::domain`] and
    /// the handles as vertices ([`Domain::build`]). Errors name the scene element or the mesh
    /// file: a scene with bones or a cage or without point handles, an unreadable mesh, a
    /// face that is not a triangle, `z ≠ 0`, a handle that is not a vertex.
    pub fn defop_shape(&self, settings: &DefOpSettings) -> Result<DefOpShape, SceneError> {
        let invalid =
            |element: &str, message: String| SceneError::invalid(&self.origin, element, message);
        if !self.bones.is_empty() || self.cage.is_some() {
            return Err(invalid(
                "handles",
                "a deformation operator is driven by point handles only (expected no bones and no cage)".into(),
            ));
        }
        if self.handles.is_empty() {
            return Err(invalid(
                "handles",
                "no point handles (expected at least one)".into(),
            ));
        }
        match &settings.mesh {
            Some(path) => {
                let mesh = read_triangle_mesh(path)?;
                let handles = match_handles(&mesh, &self.handles, &path.display().to_string())?;
                Ok(DefOpShape {
                    mesh,
                    handles,
                    origin: path.display().to_string(),
                })
            }
            None => {
                let drawing = self.drawing(Compat::None)?;
                let domain = Domain::build(&drawing, &self.handles, &[], &settings.domain)
                    .map_err(|e| invalid("defop.domain", e.to_string()))?;
                Ok(DefOpShape {
                    mesh: domain.mesh,
                    handles: domain.handle_vertices,
                    origin: format!("{} (domain)", self.svg_origin),
                })
            }
        }
    }
}

/// Reads a 2D triangle mesh from an OBJ file: `v x y [z]` with `z = 0`, triangular faces.
fn read_triangle_mesh(path: &Path) -> Result<TriMesh, SceneError> {
    let origin = path.display().to_string();
    let invalid = |message: String| SceneError::Json {
        origin: origin.clone(),
        message,
    };
    let cage = splineskin_subdiv::obj::read_obj(path).map_err(|e| invalid(e.to_string()))?;
    let mut vertices = Vec::with_capacity(cage.n_vertices());
    for (v, p) in cage.positions().iter().enumerate() {
        if p[2] != 0.0 {
            return Err(invalid(format!(
                "vertex {v}: z = {} (expected a planar mesh with z = 0)",
                p[2]
            )));
        }
        vertices.push(Point::new(p[0], p[1]));
    }
    let mut triangles = Vec::with_capacity(cage.n_faces());
    for (f, face) in cage.faces().enumerate() {
        let [a, b, c] = face else {
            return Err(invalid(format!(
                "face {f} has {} corners (expected triangles only)",
                face.len()
            )));
        };
        triangles.push([*a as usize, *b as usize, *c as usize]);
    }
    TriMesh::new(vertices, triangles).map_err(|e| invalid(format!("invalid mesh: {e}")))
}

/// The vertex at each handle's position, or an error naming the handle and the nearest vertex.
fn match_handles(
    mesh: &TriMesh,
    handles: &[Point],
    origin: &str,
) -> Result<Vec<usize>, SceneError> {
    let tolerance = HANDLE_VERTEX_TOLERANCE * mesh.bounding_box_diagonal();
    handles
        .iter()
        .enumerate()
        .map(|(l, &h)| {
            let (v, d) = mesh
                .vertices
                .iter()
                .enumerate()
                .map(|(v, &p)| (v, (p - h).hypot()))
                .fold((0, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a });
            if d <= tolerance {
                Ok(v)
            } else {
                Err(SceneError::Invalid {
                    origin: origin.to_string(),
                    element: format!("handles[{l}]"),
                    message: format!(
                        "the handle at ({}, {}) is not a vertex of the mesh (nearest: vertex {v} at distance {d:.3e}; expected every point handle at a mesh vertex)",
                        h.x, h.y
                    ),
                })
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(defop: &str) -> Result<Scene, SceneError> {
        let json = format!(
            r#"{{"splineskin_scene": 1,
                "svg_text": "<svg xmlns='http://www.w3.org/2000/svg' viewBox='0 0 100 30'><path d='M0 0 H100 V30 H0 Z'/></svg>",
                "handles": [{{"position": [10, 15]}}, {{"position": [90, 15]}}],
                "defop": {defop}}}"#
        );
        Scene::from_json(&json, "bar.json", None)
    }

    #[test]
    fn defop_section_reads_every_key_and_names_bad_ones() {
        let s = scene(
            r#"{"energy": "arap", "spatial_basis": "eigen 20", "handle_basis": "cubic",
                "samples": 50, "region": {"circle": 0.1}, "seed": 9, "cover": "animation",
                "domain": {"max_area_fraction": 0.01}}"#,
        )
        .unwrap();
        let d = s.defop.clone().unwrap();
        assert_eq!(d.energy, Energy::Arap);
        assert_eq!(d.spatial_basis, SpatialBasisSpec::Eigen(20));
        assert_eq!(d.handle_basis, HandleBasisKind::Cubic);
        assert_eq!((d.samples, d.seed), (50, 9));
        assert_eq!(d.region, RegionSpec::Circle(0.1));
        assert_eq!(d.cover, Cover::Animation);
        assert_eq!(d.domain.max_area_fraction, 0.01);
        assert_eq!(
            d.domain.samples_per_diagonal,
            crate::defop::TRAINING_SAMPLES_PER_DIAGONAL
        );
        let shape = s.defop_shape(&d).unwrap();
        assert_eq!(shape.handles.len(), 2);
        for (&v, p) in shape.handles.iter().zip(&s.handles) {
            assert_eq!(shape.mesh.vertices[v], *p);
        }
        for (bad, element) in [
            (r#"{"energy": "rigid"}"#, "defop.energy"),
            (r#"{"spatial_basis": "eigen"}"#, "defop.spatial_basis"),
            (r#"{"handle_basis": "quartic"}"#, "defop.handle_basis"),
            (r#"{"samples": 0}"#, "defop.samples"),
            (r#"{"region": {"disc": -1}}"#, "defop.region"),
            (r#"{"cover": "everything"}"#, "defop.cover"),
            (r#"{"mesh": "m.obj"}"#, "defop.mesh"),
            (r#"{"colour": 3}"#, "colour"),
        ] {
            let message = scene(bad).unwrap_err().to_string();
            assert!(
                message.contains("bar.json") && message.contains(element),
                "{bad}: {message}"
            );
        }
    }
}
