//! Scenes: a drawing, its handles, weights, junction overrides and poses, as a JSON file.
//!
//! Two formats are read, told apart by their keys:
//!
//! * **ours** (marked by `"splineskin_scene": 1`), documented in [`ours`];
//! * **the paper authors'** `*-deformation.json` saved by their web editor (`gInputSVGText`,
//!   `gHandles`, …), read as they are ([`authors`]).
//!
//! Both become a [`Scene`]. Everything is validated on load: numbers finite and within
//! [`MAX_COORDINATE`], one transform per handle in every pose, known weight families and
//! engines, handle kinds the family can weigh ([`WeightSpec::check_handles`]), a cage that is
//! a counter-clockwise simple polygon, no two coincident point handles. A family or engine
//! that exists but is not implemented yet loads (so `info` can show it) and is reported by
//! [`Scene::check_supported`]. What needs the drawing (a handle outside the domain, an empty
//! domain, out-of-range domain options) is reported by [`Scene::setup`], naming the element.
//!
//! Handles come in three kinds ([`handles`]): point handles ([`Scene::handles`]), bones
//! ([`Scene::bones`]) and the vertices of a cage ([`Scene::cage`]); the rig numbers them in
//! that order. [`PosedDrawing`] is a scene's drawing with its weights and the engine that poses
//! it ([`Deformer`]: the rig, the flexible solve or a naive baseline), applied by one
//! `update(&pose, &mut points)`; [`Puppet`] is the editable layer over it, keeping the weights
//! and rig cached while only the pose changes.
//! [`place_pins`] places point handles on a drawing's filled shapes automatically ([`pins`]).

pub mod authors;
mod bbw_columns;
mod compat;
pub mod defop;
mod deformer;
mod domain_file;
pub mod handle_weights;
pub mod handles;
pub mod ours;
pub mod ours_write;
pub mod pinned;
pub mod pins;
mod posed;
mod session;
mod setup;

pub use bbw_columns::bbw_columns;
pub use compat::{Compat, AUTHORS_SHEPARD_SNAP};
pub use defop::{
    energy_name, parse_energy, parse_handle_basis, Cover, DefOpSettings, DefOpShape, RegionSpec,
    SpatialBasisSpec, HANDLE_VERTEX_TOLERANCE,
};
pub use deformer::Deformer;
pub use domain_file::scene_domain_options;
pub use handle_weights::{handle_weights, mesh_weights, SolvedColumns, WeightInputs};
pub use handles::{Bone, BonePoseError, BoneTransform, HandleKind, HandleSet};
pub use pins::{place_pins, PinCount, PinError, PinOptions};
pub use posed::{PoseOptions, PoseReport, PosedDrawing, UpdateError};
pub use session::{Puppet, PuppetStage, PuppetStats, RefinedPuppet};
pub use setup::{Setup, SetupControl};

use std::path::{Path as FsPath, PathBuf};

use kurbo::{Affine, Point};

use crate::domain::DomainOptions;
use crate::drawing::JointKind;
use crate::spline_fit::Measure;

/// Largest absolute coordinate or transform coefficient accepted in a scene: 1e9 drawing units.
/// Beyond it `f64` sums over a drawing lose all sub-unit precision, and such values are always a
/// mistake in a drawing measured in points or pixels.
pub const MAX_COORDINATE: f64 = 1e9;

/// Largest scene file accepted: 256 MiB.
pub const MAX_SCENE_BYTES: u64 = 256 << 20;

/// A loaded scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Where the scene came from (file name or `<inline>`), for messages.
    pub origin: String,
    /// The SVG document text.
    pub svg_text: String,
    /// Where the SVG text came from (a file next to the scene, or the scene itself).
    pub svg_origin: String,
    /// Rest positions of the point handles (rig handles `0 .. handles.len()`).
    pub handles: Vec<Point>,
    /// Bones (rig handles after the point handles). Our format only.
    pub bones: Vec<Bone>,
    /// The cage, a counter-clockwise simple polygon whose vertices are handles (after the
    /// bones); `None` without a cage. Our format only.
    pub cage: Option<Vec<Point>>,
    /// The weight functions.
    pub weights: WeightSpec,
    /// Options of the triangulated domain of the mesh families (its `cage` is unset: the
    /// scene's [`Scene::cage`] is put in by [`Scene::setup`]).
    pub domain: DomainOptions,
    /// The deformation engine.
    pub engine: Engine,
    /// The measure along curves (arc length or length-weighted parameter).
    pub measure: Measure,
    /// Per-junction kinds set by the user: they replace the classification.
    pub junctions: Vec<JunctionOverride>,
    /// The authors' per-path, per-joint kinds (their format only): applied when the drawing's
    /// structure matches theirs (see [`Scene::setup`]).
    pub authors_joints: Option<Vec<Vec<JointKind>>>,
    /// Poses: one transform per handle each. A scene without poses has the identity pose.
    pub poses: Vec<Pose>,
    /// Whether G¹ and fixed-angle junctions are flexible: their tangent-length ratio is left
    /// free ([`crate::spline_fit::flexible`]). Our format's `flexible` key (default false);
    /// always true in the authors' format (their solver iterates every G¹ and angle joint).
    pub flexible: bool,
    /// Keyframed poses, if the scene has any (our `animation` key; the authors'
    /// `animationFrames`, [`authors`]).
    pub animation: Option<crate::animation::Animation>,
    /// Training settings of a deformation operator (our `defop` key, [`defop`]); `None`
    /// without one (then [`DefOpSettings::default`] applies).
    pub defop: Option<DefOpSettings>,
    /// Which format the scene was read from.
    pub format: SceneFormat,
    /// The drawing as the scene's maker already read it ([`Scene::from_pins`]), if it did.
    pub(crate) read: pinned::ReadDrawing,
}

/// The file format a scene was read from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneFormat {
    /// `"splineskin_scene": 1`.
    Ours,
    /// The paper authors' `*-deformation.json`.
    Authors,
}

/// The weight family of a scene.
#[derive(Clone, Debug, PartialEq)]
pub enum WeightSpec {
    /// Shepard weights `1/d^a`, normalised.
    Shepard {
        /// The exponent `a`.
        exponent: f64,
    },
    /// A family computed on a triangulation of the drawing's domain
    /// ([`crate::domain::Domain`]): harmonic, biharmonic or bounded biharmonic weights.
    Mesh(MeshFamily),
    /// Mean value coordinates of the cage (`mvc`; [`crate::weights::MeanValue`]): closed form,
    /// defined in the whole plane.
    MeanValue,
    /// A known family that this version does not implement yet (none at present; kept so a
    /// family can be announced before it lands).
    NotImplemented(String),
}

/// The mesh-based weight families.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshFamily {
    /// `Δw = 0` with `w_i = δ_ij` at the handles (`harmonic`).
    Harmonic,
    /// `Δ²w = 0`, natural boundary (`biharmonic`); not bounded, rows sum to 1.
    Biharmonic,
    /// Bounded biharmonic weights (`bbw`): `Δ²` energy with `0 ≤ w ≤ 1`, rows normalised.
    Bbw,
}

impl MeshFamily {
    /// The name used in scenes.
    pub fn name(self) -> &'static str {
        match self {
            MeshFamily::Harmonic => "harmonic",
            MeshFamily::Biharmonic => "biharmonic",
            MeshFamily::Bbw => "bbw",
        }
    }
}

/// The deformation engine of a scene (the authors' `engineType`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Engine {
    /// The paper's spline fit (`ours`).
    Ours,
    /// Naive baseline: skin all four control points (`fourcontrols`).
    FourControls,
    /// Naive baseline: skin on-curve points, off-curve points follow (`twoendpoints`).
    TwoEndpoints,
    /// Naive baseline: off-curve points by the Jacobian (`jacobian`).
    Jacobian,
}

impl Engine {
    /// The name used in scenes.
    pub fn name(self) -> &'static str {
        match self {
            Engine::Ours => "ours",
            Engine::FourControls => "fourcontrols",
            Engine::TwoEndpoints => "twoendpoints",
            Engine::Jacobian => "jacobian",
        }
    }

    fn parse(name: &str, origin: &str) -> Result<Engine, SceneError> {
        Ok(match name {
            "ours" => Engine::Ours,
            "fourcontrols" => Engine::FourControls,
            "twoendpoints" => Engine::TwoEndpoints,
            "jacobian" => Engine::Jacobian,
            other => {
                return Err(SceneError::Invalid {
                    origin: origin.to_string(),
                    element: "engine".into(),
                    message: format!(
                        "unknown engine '{other}' (expected ours, fourcontrols, twoendpoints or jacobian)"
                    ),
                })
            }
        })
    }
}

impl WeightSpec {
    /// The weight family named `name` in scenes (`shepard` with its `exponent`, default
    /// [`crate::weights::shepard::DEFAULT_EXPONENT`]; `harmonic`, `biharmonic`, `bbw`, `mvc`).
    /// Errors name `origin` and the element `weights`.
    ///
    /// ```
    /// use splineskin::scene::{MeshFamily, WeightSpec};
    /// assert_eq!(WeightSpec::parse("bbw", None, "x.json")?, WeightSpec::Mesh(MeshFamily::Bbw));
    /// assert!(WeightSpec::parse("smooth", None, "x.json").is_err());
    /// # Ok::<(), splineskin::scene::SceneError>(())
    /// ```
    pub fn parse(
        name: &str,
        exponent: Option<f64>,
        origin: &str,
    ) -> Result<WeightSpec, SceneError> {
        match name {
            "shepard" => {
                let exponent = exponent.unwrap_or(crate::weights::shepard::DEFAULT_EXPONENT);
                if !(exponent.is_finite() && exponent > 0.0 && exponent <= 64.0) {
                    return Err(SceneError::invalid(
                        origin,
                        "weights.exponent",
                        format!("Shepard exponent {exponent} is not in (0, 64]"),
                    ));
                }
                Ok(WeightSpec::Shepard { exponent })
            }
            "harmonic" => Ok(WeightSpec::Mesh(MeshFamily::Harmonic)),
            "biharmonic" => Ok(WeightSpec::Mesh(MeshFamily::Biharmonic)),
            "bbw" => Ok(WeightSpec::Mesh(MeshFamily::Bbw)),
            "mvc" => Ok(WeightSpec::MeanValue),
            other => Err(SceneError::Invalid {
                origin: origin.to_string(),
                element: "weights".into(),
                message: format!(
                    "unknown weight family '{other}' (expected shepard, bbw, harmonic, biharmonic or mvc)"
                ),
            }),
        }
    }

    /// Errors unless this family can weigh the handle kinds of `handles`:
    ///
    /// | family | points | bones | cage |
    /// |---|---|---|---|
    /// | `shepard` | yes | yes (distance to the segment) | no |
    /// | `harmonic`, `biharmonic`, `bbw` | yes | yes | yes, alone or with points and bones |
    /// | `mvc` | no | no | yes, alone |
    ///
    /// `element` is what the message names (e.g. `weights`); `origin` the scene.
    pub fn check_handles(
        &self,
        handles: &HandleSet<'_>,
        origin: &str,
        element: &str,
    ) -> Result<(), SceneError> {
        let invalid = |message: String| SceneError::invalid(origin, element, message);
        let has_others = !handles.points.is_empty() || !handles.bones.is_empty();
        match self {
            WeightSpec::Shepard { .. } if handles.cage.is_some() => Err(invalid(
                "shepard weights take point handles and bones, not a cage (use mvc, harmonic, \
                 biharmonic or bbw for a cage)"
                    .into(),
            )),
            WeightSpec::MeanValue if has_others => Err(invalid(
                "mean value coordinates (mvc) weigh a cage's vertices only: remove the point \
                 handles and bones, or use harmonic, biharmonic or bbw"
                    .into(),
            )),
            WeightSpec::NotImplemented(name) if name == "mvc" && handles.cage.is_none() => Err(
                invalid("mean value coordinates (mvc) need a cage (\"cage\": [[x, y], …])".into()),
            ),
            _ => Ok(()),
        }
    }

    /// The family's name.
    pub fn name(&self) -> &str {
        match self {
            WeightSpec::Shepard { .. } => "shepard",
            WeightSpec::Mesh(family) => family.name(),
            WeightSpec::MeanValue => "mvc",
            WeightSpec::NotImplemented(name) => name,
        }
    }
}

/// A junction kind chosen by the user for on-curve point `joint` of path `path` (joint `k` is
/// the start of curve `k`, as in [`crate::drawing::Path::joints`]). In a scene file of ours
/// (and the editor's JSON): `{"path": 0, "joint": 3, "kind": "C1"}`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JunctionOverride {
    /// Path index (subpaths in document order).
    pub path: usize,
    /// On-curve point index within the path.
    pub joint: usize,
    /// The kind to impose.
    pub kind: JointKind,
}

/// One transform per handle.
#[derive(Clone, Debug, PartialEq)]
pub struct Pose {
    /// Optional name (keyframe label).
    pub name: Option<String>,
    /// The handles' affine maps, in handle order.
    pub transforms: Vec<Affine>,
}

/// Why a scene could not be loaded or used.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SceneError {
    /// The file could not be read.
    #[error("{path}: cannot read: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// The file is too large.
    #[error("{path}: {size} bytes is more than the {limit}-byte limit for scenes")]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// Its size.
        size: u64,
        /// [`MAX_SCENE_BYTES`].
        limit: u64,
    },
    /// Not JSON, or JSON of the wrong shape.
    #[error("{origin}: {message}")]
    Json {
        /// The scene.
        origin: String,
        /// serde_json's message, with line and column.
        message: String,
    },
    /// Well-formed JSON with an invalid value.
    #[error("{origin}: {element}: {message}")]
    Invalid {
        /// The scene.
        origin: String,
        /// Which field (e.g. `handles[2].position`).
        element: String,
        /// What was expected.
        message: String,
    },
    /// Our SVG importer could not read the scene's drawing (the error names the drawing's
    /// origin, [`Scene::svg_origin`]).
    #[error(transparent)]
    Svg(#[from] crate::drawing::SvgError),
    /// The authors' SVG reader (compatibility mode) could not read the scene's drawing.
    #[error("{origin}: {source}")]
    Drawing {
        /// Where the SVG came from.
        origin: String,
        /// The importer's error.
        source: Box<dyn std::error::Error + Send + Sync>,
    },
    /// The weights could not be computed (domain triangulation or solve), e.g. a handle
    /// outside the domain or two coincident handles.
    #[error("{origin}: {family} weights: {source}")]
    Weights {
        /// The scene.
        origin: String,
        /// The family's name.
        family: &'static str,
        /// What went wrong.
        source: Box<dyn std::error::Error + Send + Sync>,
    },
    /// The rig could not be built or updated ([`crate::spline_fit::FitError`],
    /// [`crate::spline_fit::PoseError`]).
    #[error("{origin}: rig: {source}")]
    Rig {
        /// The scene.
        origin: String,
        /// What went wrong.
        source: Box<dyn std::error::Error + Send + Sync>,
    },
    /// A feature the scene asks for is not implemented in this version.
    #[error("{origin}: {what} is not implemented yet")]
    NotImplemented {
        /// The scene.
        origin: String,
        /// What (e.g. "weight function 'bbw'").
        what: String,
    },
}

impl SceneError {
    /// [`SceneError::Invalid`]: `element` of the scene `origin` holds a value that is not
    /// what `message` says was expected.
    ///
    /// ```
    /// use splineskin::scene::SceneError;
    /// let e = SceneError::invalid("fish.json", "handles[2].position", "expected [x, y]");
    /// assert_eq!(e.to_string(), "fish.json: handles[2].position: expected [x, y]");
    /// ```
    pub fn invalid(
        origin: &str,
        element: impl Into<String>,
        message: impl Into<String>,
    ) -> SceneError {
        SceneError::Invalid {
            origin: origin.to_string(),
            element: element.into(),
            message: message.into(),
        }
    }

    /// The scene `origin`'s `animation` refused by [`Animation::new`](crate::animation::Animation::new):
    /// [`SceneError::Invalid`] of the element `animation.fps` for a frame rate, else
    /// `animation`.
    ///
    /// ```
    /// use splineskin::animation::{Animation, Keyframe};
    /// use splineskin::scene::SceneError;
    /// let e = Animation::new(0.0, vec![Keyframe::<kurbo::Affine>::new(0.0, vec![])]).unwrap_err();
    /// assert!(SceneError::animation("walk.json", e).to_string().starts_with("walk.json: animation.fps: "));
    /// ```
    pub fn animation(origin: &str, e: crate::animation::AnimationError) -> SceneError {
        let element = crate::animation::file::error_element(&e);
        SceneError::invalid(origin, element, e.to_string())
    }
}

impl Scene {
    /// Reads a scene file (either format). A scene of ours may name its SVG file relative to
    /// the scene's folder.
    pub fn load(path: &FsPath) -> Result<Scene, SceneError> {
        let meta = std::fs::metadata(path).map_err(|source| SceneError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        if meta.len() > MAX_SCENE_BYTES {
            return Err(SceneError::TooLarge {
                path: path.to_path_buf(),
                size: meta.len(),
                limit: MAX_SCENE_BYTES,
            });
        }
        let bytes = std::fs::read(path).map_err(|source| SceneError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let text = String::from_utf8(bytes).map_err(|e| SceneError::Json {
            origin: path.display().to_string(),
            message: format!("not UTF-8 text (byte {})", e.utf8_error().valid_up_to()),
        })?;
        Scene::from_json(&text, &path.display().to_string(), path.parent())
    }

    /// Parses a scene from JSON text. `origin` names it in messages; `base_dir` resolves a
    /// relative SVG file name (none: only inline SVG text is accepted).
    ///
    /// ```
    /// let json = r#"{
    ///   "splineskin_scene": 1,
    ///   "svg_text": "<svg xmlns='http://www.w3.org/2000/svg'><path d='M0 0 C1 1 2 1 3 0'/></svg>",
    ///   "handles": [{"position": [0, 0]}, {"position": [3, 0]}],
    ///   "pose": [{"translate": [0, 0]}, {"translate": [1, 2], "rotate": 30}]
    /// }"#;
    /// let scene = splineskin::scene::Scene::from_json(json, "example", None).unwrap();
    /// assert_eq!(scene.handles.len(), 2);
    /// assert_eq!(scene.poses[0].transforms.len(), 2);
    /// ```
    pub fn from_json(
        text: &str,
        origin: &str,
        base_dir: Option<&FsPath>,
    ) -> Result<Scene, SceneError> {
        if authors::looks_like_authors(text) {
            authors::parse(text, origin)
        } else {
            ours::parse(text, origin, base_dir)
        }
    }

    /// Errors if the scene asks for a weight family not implemented in this version. (Every
    /// engine is: the naive baselines are in [`crate::naive`].)
    pub fn check_supported(&self) -> Result<(), SceneError> {
        if let WeightSpec::NotImplemented(name) = &self.weights {
            return Err(SceneError::NotImplemented {
                origin: self.origin.clone(),
                what: format!(
                    "weight function '{name}' (available: shepard, harmonic, biharmonic, bbw, mvc)"
                ),
            });
        }
        Ok(())
    }

    /// The pose a user asks for by `key`: its index in `poses` as a decimal number (`"0"` is
    /// the first; also the identity pose of a scene without poses) or its `name`. Returns the
    /// index with the pose; `Err` says which poses exist.
    ///
    /// ```
    /// let scene = splineskin::examples::demo_scene();
    /// assert_eq!(scene.pose_by_key("nose-up")?.0, 1);
    /// assert_eq!(scene.pose_by_key("2")?.1.name.as_deref(), Some("flap"));
    /// let err = scene.pose_by_key("jump").unwrap_err();
    /// assert_eq!(err, "pose 'jump' does not exist (poses: 0 'swish', 1 'nose-up', 2 'flap')");
    /// # Ok::<(), String>(())
    /// ```
    pub fn pose_by_key(&self, key: &str) -> Result<(usize, Pose), String> {
        let found = match key.trim().parse::<usize>() {
            Ok(index) => self.pose(index).map(|pose| (index, pose)),
            Err(_) => self
                .poses
                .iter()
                .position(|p| p.name.as_deref() == Some(key))
                .map(|index| (index, self.poses[index].clone())),
        };
        found.ok_or_else(|| {
            let list = if self.poses.is_empty() {
                "the scene has none: 0 is the rest pose".to_string()
            } else {
                let names: Vec<String> = self
                    .poses
                    .iter()
                    .enumerate()
                    .map(|(i, p)| match &p.name {
                        Some(name) => format!("{i} '{name}'"),
                        None => i.to_string(),
                    })
                    .collect();
                format!("poses: {}", names.join(", "))
            };
            format!("pose '{key}' does not exist ({list})")
        })
    }

    /// The pose with index `index`, or the identity pose when the scene has none and `index`
    /// is 0.
    pub fn pose(&self, index: usize) -> Option<Pose> {
        if self.poses.is_empty() && index == 0 {
            return Some(Pose {
                name: None,
                transforms: vec![Affine::IDENTITY; self.n_handles()],
            });
        }
        self.poses.get(index).cloned()
    }

    /// The rest handles, borrowed, in rig order (points, bones, cage vertices).
    pub fn handle_set(&self) -> HandleSet<'_> {
        HandleSet {
            points: &self.handles,
            bones: &self.bones,
            cage: self.cage.as_deref(),
        }
    }

    /// Number of handles of the rig: point handles + bones + cage vertices.
    pub fn n_handles(&self) -> usize {
        self.handle_set().n_handles()
    }

    /// The scene's name for handle `kind` in messages: `handles[i]` (`gHandles[i]` in the
    /// authors' format), `bones[b]`, `cage[k]`.
    pub fn element(&self, kind: HandleKind) -> String {
        handle_element(self.format, kind)
    }
}

/// The name of a handle in a scene of `format` (see [`Scene::element`]).
pub(crate) fn handle_element(format: SceneFormat, kind: HandleKind) -> String {
    match (kind, format) {
        (HandleKind::Point(i), SceneFormat::Authors) => format!("gHandles[{i}]"),
        (HandleKind::Point(i), SceneFormat::Ours) => format!("handles[{i}]"),
        (HandleKind::Bone(b), _) => format!("bones[{b}]"),
        (HandleKind::CageVertex(k), _) => format!("cage[{k}]"),
    }
}

/// Validates a point: finite and within [`MAX_COORDINATE`].
pub(crate) fn check_point(p: [f64; 2], origin: &str, element: String) -> Result<Point, SceneError> {
    if p.iter().all(|v| v.is_finite() && v.abs() <= MAX_COORDINATE) {
        Ok(Point::new(p[0], p[1]))
    } else {
        Err(SceneError::Invalid {
            origin: origin.to_string(),
            element,
            // `{:?}` writes 1e300 as `1e300`, not as 301 digits.
            message: format!(
                "({:?}, {:?}) is not a finite position within ±{MAX_COORDINATE:e}",
                p[0], p[1]
            ),
        })
    }
}

/// Validates an affine map: finite coefficients within [`MAX_COORDINATE`].
pub(crate) fn check_affine(a: Affine, origin: &str, element: String) -> Result<Affine, SceneError> {
    if a.as_coeffs()
        .iter()
        .all(|v| v.is_finite() && v.abs() <= MAX_COORDINATE)
    {
        Ok(a)
    } else {
        Err(SceneError::Invalid {
            origin: origin.to_string(),
            element,
            message: format!(
                "transform {:?} has a coefficient that is not finite or beyond ±{MAX_COORDINATE:e}",
                a.as_coeffs()
            ),
        })
    }
}

/// Converts a serde_json error into [`SceneError::Json`].
pub(crate) fn json_error(origin: &str, e: serde_json::Error) -> SceneError {
    SceneError::Json {
        origin: origin.to_string(),
        message: format!("invalid scene JSON: {e}"),
    }
}
