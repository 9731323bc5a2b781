//! What the server and the page exchange as JSON: the editable part of a scene
//! ([`EditScene`]), and what the page learns about an opened drawing ([`DocumentInfo`]).
//!
//! Binary bodies (the rig operator, deformed points, weight grids) are little-endian
//! `f64`/`f32` arrays without a header; their layouts are documented on the routes
//! (the crate's documentation).

use serde::{Deserialize, Serialize};
use splineskin::drawing::JointKind;
use splineskin::scene::{JunctionOverride, SolvedColumns};

/// The part of a scene the page edits: point handles, their pose, the weight family, junction
/// overrides and flexible G¹. Together with a document's SVG text it is a scene of ours
/// ([`crate::page_scene`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EditScene {
    /// Rest positions of the point handles, root user units.
    pub handles: Vec<[f64; 2]>,
    /// One map per handle, SVG order `[a, b, c, d, e, f]`.
    pub pose: Vec<[f64; 6]>,
    /// The weight family.
    pub weights: WeightsWire,
    /// Junction kinds the user chose, replacing the drawing's classification.
    pub junctions: Vec<JunctionOverride>,
    /// Whether G¹ and fixed-angle junctions are flexible (solved by the server on mouse-up).
    pub flexible: bool,
    /// The timeline's keyframes, if any (a scene's `animation`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub animation: Option<AnimationWire>,
    /// How far the mesh families' art-shaped domain reaches around the art (Puppet Warp's
    /// expansion), a fraction of the drawing's diagonal in `0..=`[`splineskin::domain::MAX_MARGIN`]
    /// (a scene's `domain.margin`): shapes closer than twice this are one part. `None`: the
    /// opened scene's, by default [`splineskin::domain::DEFAULT_MARGIN`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub margin: Option<f64>,
}

/// Keyframed poses as the page edits them and scene files hold them (`animation`): every
/// keyframe's pose inline, one map per handle.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnimationWire {
    /// Frames per second sampled.
    pub fps: f64,
    /// Keyframes, times increasing.
    pub keyframes: Vec<KeyframeWire>,
}

/// One keyframe: its time, its pose, and the easing of the segment after it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KeyframeWire {
    /// Seconds from the start.
    pub time: f64,
    /// One map per handle, SVG order `[a, b, c, d, e, f]`.
    pub pose: Vec<[f64; 6]>,
    /// `linear`, `ease-in`, `ease-out`, `ease-in-out` or `hold`
    /// ([`splineskin::animation::Easing`]).
    #[serde(default = "linear")]
    pub easing: String,
}

fn linear() -> String {
    "linear".into()
}

impl AnimationWire {
    /// The page's form of a scene's animation.
    pub fn of(animation: &splineskin::animation::Animation) -> AnimationWire {
        AnimationWire {
            fps: animation.fps(),
            keyframes: animation
                .keyframes()
                .iter()
                .map(|k| KeyframeWire {
                    time: k.time,
                    pose: k.transforms.iter().map(|t| t.as_coeffs()).collect(),
                    easing: k.easing.name().into(),
                })
                .collect(),
        }
    }
}

/// A weight family by name (`shepard`, `harmonic`, `biharmonic`, `bbw`), with Shepard's
/// exponent; or a trained deformation operator (`defop-arap`, `defop-sarap`: not weights, the
/// page's "family" menu offers them beside the weights, [`crate::defop_routes`]) with its
/// sample count.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WeightsWire {
    /// The family's name, as in scenes.
    pub family: String,
    /// Shepard's exponent (default 2).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub exponent: Option<f64>,
    /// Training samples of a deformation operator (default
    /// [`crate::page_scene::DEFAULT_EDITOR_SAMPLES`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub samples: Option<usize>,
    /// A quick preview of a mesh family: the same family solved on a coarse triangulation of
    /// the same domain ([`splineskin::weights::coarse_to_fine::preview_options`]), shape-aware
    /// like the exact weights (the same parts of the art), in a fraction of their time. A
    /// request's only: never written (scene files and the page's scene leave it out).
    #[serde(default, skip_serializing)]
    pub coarse: bool,
}

/// A request naming a document and carrying the page's scene.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneRequest {
    /// The document's id ([`DocumentInfo::id`]).
    pub document: String,
    /// The page's scene.
    pub scene: EditScene,
}

/// `POST /api/rig`: a document, the page's scene, and optionally bounded biharmonic columns
/// already solved by `POST /api/weights/columns` (the static editor spreads a rig's columns
/// over its workers), taken as they are.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RigRequest {
    /// The document's id ([`DocumentInfo::id`]).
    pub document: String,
    /// The page's scene.
    pub scene: EditScene,
    /// Columns solved apart, on the domain this scene builds (`bbw` only).
    #[serde(default)]
    pub solved: Option<SolvedColumns>,
}

/// `POST /api/weights/columns`: the raw bounded biharmonic columns `columns` (handles in rig
/// order) of the page's scene on a document, answered as [`SolvedColumns`] JSON.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ColumnsRequest {
    /// The document's id ([`DocumentInfo::id`]).
    pub document: String,
    /// The page's scene (weights `bbw`).
    pub scene: EditScene,
    /// The columns to solve.
    pub columns: Vec<usize>,
}

/// A pose for a flexible solve.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PoseRequest {
    /// One map per handle, SVG order `[a, b, c, d, e, f]`.
    pub pose: Vec<[f64; 6]>,
}

/// `POST /api/rigs/{id}/refine`: adaptive control points for the poses the user has seen.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RefineRequest {
    /// The page's scene on the rig's document (its junction kinds move with the joints).
    pub scene: EditScene,
    /// The poses that matter (those seen while dragging, the keyframes'): one map per handle
    /// each, SVG order `[a, b, c, d, e, f]`; at most [`crate::request::MAX_REFINE_POSES`].
    pub poses: Vec<Vec<[f64; 6]>>,
    /// Largest distance of the fit from the skinned target, a fraction of the drawing's
    /// diagonal.
    pub tolerance: f64,
}

/// The answer of `POST /api/rigs/{id}/refine`.
#[derive(Clone, Debug, Serialize)]
pub struct RefineAnswer {
    /// Whether anchors were inserted: then `document` and `rig` are the refined drawing's
    /// (the rig's operator: `GET /api/rigs/{rig}/operator`).
    pub refined: bool,
    /// The refined drawing, its scene the page's with junction kinds moved to the new joint
    /// indices, or `null`.
    pub document: Option<DocumentInfo>,
    /// The refined drawing's rig (sharing the weights of the rig refined), or `null`.
    pub rig: Option<String>,
    /// Per path, for each joint of the rig's document, its index in the refined drawing (the
    /// page moves junction kinds of its undo history with it); empty when nothing was
    /// inserted.
    pub moved: Vec<Vec<usize>>,
    /// Anchors inserted by this request.
    pub n_inserted: usize,
    /// Curves of the drawing now.
    pub n_curves: usize,
    /// The fit's largest distance from the target over the poses, fraction of the diagonal.
    pub worst: f64,
    /// Whether every curve is within the tolerance (else the curve budget ran out).
    pub met: bool,
}

/// What the page needs to show and deform an opened drawing.
#[derive(Clone, Debug, Serialize)]
pub struct DocumentInfo {
    /// The server's id of the document.
    pub id: String,
    /// The file it came from (or the bundled drawing's name).
    pub name: String,
    /// The document to show: the original text with every imported element written as a
    /// `<path>` at rest and marked with [`crate::document::ELEMENT_MARKER`]`="k"`.
    pub svg: String,
    /// The root viewBox `[x, y, width, height]` (root user units): the frame the drawing's
    /// coordinates are in.
    pub view_box: [f64; 4],
    /// Every subpath of the drawing, in order.
    pub paths: Vec<PathInfo>,
    /// The imported elements, in marker order.
    pub elements: Vec<ElementInfo>,
    /// Per carried `<text>` and `<image>` (marked with
    /// [`crate::document::CARRIED_MARKER`]`="j"`), its parent's user space → root user space
    /// `P`, `[a, b, c, d, e, f]`: its shown `transform` is `P⁻¹ A P` before its own, `A` its
    /// best-fit map.
    pub carried: Vec<[f64; 6]>,
    /// The elements (indices, ascending) whose best-fit maps the page needs: those with their
    /// own copies of user-space paint servers in the shown document (marked
    /// [`crate::document::PAINT_MARKER`]`="k"`) and those drawn in a stroke frame
    /// ([`ElementInfo::stroke_frame`]). The carry operator gives their maps after the
    /// carried ones'.
    pub painted: Vec<usize>,
    /// Rest chain points of all paths, concatenated: `x0, y0, x1, y1, …` (root user units).
    pub rest: Vec<f64>,
    /// The scene as opened (a drawing alone: no handles, Shepard weights).
    pub scene: EditScene,
    /// The operator the scene's `defop` section describes, which the page offers when the
    /// user picks an operator (its sample count prefilled); `null` without a section.
    pub operator: Option<OperatorInfo>,
    /// Things the user should know about what was opened.
    pub warnings: Vec<String>,
    /// Number of cubic curves.
    pub n_curves: usize,
}

/// A scene's operator as the page's menu names it.
#[derive(Clone, Debug, Serialize)]
pub struct OperatorInfo {
    /// `defop-arap` or `defop-sarap`.
    pub family: &'static str,
    /// Training samples.
    pub samples: usize,
}

/// One subpath.
#[derive(Clone, Debug, Serialize)]
pub struct PathInfo {
    /// Whether the last curve joins the first.
    pub closed: bool,
    /// Number of chain points (`3n + 1`).
    pub n_points: usize,
    /// Junction kinds as classified from the geometry (before the scene's overrides).
    pub joints: Vec<JointKind>,
    /// Whether its path data ends with `Z` (closed paths whose source had a `Z`).
    pub close_with_z: bool,
    /// Per joint: whether adaptive control points inserted the anchor (`false`: the artist's;
    /// all `false` in a drawing as opened).
    pub inserted: Vec<bool>,
}

/// One imported element: the paths it produced and the map from root user space to its local
/// coordinates (in which its `d` is written).
#[derive(Clone, Debug, Serialize)]
pub struct ElementInfo {
    /// First path.
    pub first_path: usize,
    /// One past the last path.
    pub end_path: usize,
    /// Root user space → local coordinates, `[a, b, c, d, e, f]`.
    pub to_local: [f64; 6],
    /// For an element stroked inside a local map `L` that is not a similarity: where its
    /// stroke frame is fitted ([`splineskin::drawing::follow::stroke_frame_region`]); `null`
    /// for any other. The page draws it as export does: with `A` its best-fit map (it is in
    /// [`DocumentInfo::painted`]) and `F` the frame
    /// ([`splineskin::drawing::follow::StrokeFrameRegion::frame`]), its `transform` is its own
    /// then `L⁻¹ F L`, its path data the points mapped by `(F L)⁻¹`, its paint copies'
    /// transforms `(F L)⁻¹ A L · G`.
    pub stroke_frame: Option<StrokeFrameInfo>,
}

/// Where an element's stroke frame is fitted ([`ElementInfo::stroke_frame`]), root user units.
#[derive(Clone, Debug, Serialize)]
pub struct StrokeFrameInfo {
    /// The mean `p̄` of the element's region, `[x, y]`.
    pub centre: [f64; 2],
    /// The covariance `C` of its region, `[c_xx, c_xy, c_yy]`.
    pub covariance: [f64; 3],
}

/// The query of `POST /api/documents/{id}/animation`.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnimationQuery {
    /// `svg` (an animated SVG), `gif` or `apng` (an animated PNG).
    pub format: String,
    /// `keep` (default: every frame with the drawing's viewBox) or `fit` (one viewBox holding
    /// the art of every frame).
    pub viewbox: Option<String>,
}

/// `POST /api/documents/{id}/pins`: the pins the page has (rest positions), kept first.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PinsRequest {
    /// The page's pins, `[x, y]` at rest (root user units).
    pub handles: Vec<[f64; 2]>,
}

/// An error as the page receives it.
#[derive(Clone, Debug, Serialize)]
pub struct ErrorBody {
    /// The message, naming the file and element concerned.
    pub error: String,
}

/// Where the deformed drawing stands against its document's viewBox (`POST
/// /api/documents/{id}/outside`): the page says so in its status line, and its export offers to
/// keep the viewBox or fit it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ViewBoxReport {
    /// The document's viewBox `[x, y, width, height]` (root user units), what `keep` writes.
    pub view_box: [f64; 4],
    /// The viewBox a `fit` export writes: the union of the document's and the art's bounding
    /// box, `[x, y, width, height]` (the document's when nothing leaves it).
    pub fitted: [f64; 4],
    /// The paths that leave the viewBox, farthest first.
    pub outside: Vec<OutsideWire>,
    /// Where the drawing through the points folds a closed outline over itself (crossings
    /// of curves that do not cross at rest, [`splineskin::folds::new_self_crossings`]).
    pub folds: Vec<FoldWire>,
}

/// A crossing of a closed outline that the deformation made.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FoldWire {
    /// The path (subpath index in the drawing).
    pub path: usize,
    /// The two curves of the path that cross.
    pub curves: [usize; 2],
    /// Where (root user units).
    pub at: [f64; 2],
}

/// A path whose deformed curves leave the viewBox
/// ([`splineskin::drawing::svg_out::OutsideViewBox`]).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct OutsideWire {
    /// Index into the drawing's paths.
    pub path: usize,
    /// Its element, `tag#id (line n)`.
    pub element: String,
    /// How far its curves' bounding box reaches beyond the viewBox, root user units.
    pub distance: f64,
}

/// The query of `POST /api/documents/{id}/export` (every key optional):
/// `?viewbox=keep|fit&rig={id}` or `?viewbox=keep|fit&defop={id}`.
///
/// The body is always the deformed chain points, `f64` LE `x0, y0, x1, y1, …`; without `rig`
/// or `defop` that is all, and gradients, patterns, markers, text and images are written at
/// rest (the request as it was before they followed). With one of them the body goes on with
/// what the deformation was, so that the export carries them by the best-fit affine map of
/// that deformation over each element ([`splineskin::drawing::follow`]), as `splineskin
/// deform` does:
///
/// | key | the rest of the body | the map carried |
/// |---|---|---|
/// | `rig` | the pose, `f64` LE `a, b, c, d, e, f` per handle (SVG order) | the skinning map `p ↦ Σ_i w_i(p) T_i p` of the rig's weights |
/// | `defop` | the configuration `Q`, `f64` LE `x, y` per handle | the operator's deformation (its mesh, [`splineskin::defop::MeshMap`]) |
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExportQuery {
    /// What the export does with the root viewBox when the deformed art leaves it: `keep`
    /// (default) or `fit`.
    pub viewbox: Option<String>,
    /// A rig of `POST /api/rig` (its `x-splineskin-rig` id), built on this document.
    pub rig: Option<String>,
    /// An operator rig of `POST /api/defop` (its id), trained on this document.
    pub defop: Option<String>,
}
