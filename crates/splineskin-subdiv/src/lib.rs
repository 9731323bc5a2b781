//! Catmull–Clark subdivision surfaces with OpenSubdiv 3 semantics (DESIGN.md §3).
//!
//! A [`Cage`] (read from OBJ with [`read_obj`], tags included) is refined and evaluated with the
//! rules of Pixar's OpenSubdiv, with these fixed options (those of the references in
//! `../shared/data/subdiv/reference`):
//!
//! | option | value |
//! |---|---|
//! | scheme | Catmark (`Sdc::SCHEME_CATMARK`); triangles and n-gons by the ordinary rules (`TRI_SUB_CATMARK`): centroid face point, n quads |
//! | boundaries | `VTX_BOUNDARY_EDGE_AND_CORNER`: boundary edges are infinitely sharp creases, a boundary vertex with one face is an infinitely sharp corner |
//! | creases | `CREASE_UNIFORM`: sharpness decreases by one per level; semi-sharp transitions blend the masks |
//! | non-manifold | edges with more than two faces, or two faces running along them in the same direction, are infinitely sharp; non-manifold vertices are infinitely sharp corners unless on a crease of two non-manifold edges (OpenSubdiv's rule) |
//!
//! Option tags in the OBJ (`interpolateboundary`, `creasemethod`, …) are kept but not applied.
//!
//! | what | where |
//! |---|---|
//! | cage, tags, OBJ in/out | [`Cage`], [`read_obj`], [`write_obj`] |
//! | uniform refinement, `f64` stencils over the cage | [`refine_uniform`], [`StencilTable`] |
//! | limit stencils at `(face, u, v)` (the paper's `m_p`) and at cage vertices | [`LimitSurface`], [`LimitStencil`], [`VertexLimit`] |
//! | Gauss nodes per face and the fit's Gram matrices `Â`, `∫ f m mᵀ` | [`LimitQuadrature`] |
//! | the rig: precompute `B_i = Â⁻¹ Ŵ_iᵀ`, update `C'ᵀ = Σ_i B_i T_iᵀ` | [`SubdivRig`] |
//! | 3D affine maps `T_i` (3 × 4) | [`Affine3`], [`affine3_about`], [`rotation_axis_angle`], [`rotation_quaternion`] |
//! | point handles and bones | [`Handles3`] |
//! | handle weights: Shepard, bone heat, per cage vertex from a file | [`surface_weights`]: [`Shepard3`], [`BoneHeat`], [`CageVertexWeights`]; [`node_weights`] |
//! | the limit surface on a uniform grid, as a quad mesh | [`LimitMesh`] |
//! | scenes (JSON: OBJ, handles, weights, poses, animation) | [`SubdivScene`], [`mod@scene`] |
//! | animation out: USD (the cage, Catmull–Clark, time-sampled points), glTF (the tessellated limit surface, morph targets) | [`handoff`]: [`handoff::write_usda`], [`handoff::write_glb`] |
//! | ours against naive, each against the skinned limit surface; the picture | [`compare_subdiv`]; the picture is drawn by the `splineskin` crate (`figure::subdiv_comparison`) |
//!
//! Topology (levels, sharpness and its decay, vertex rules, sparse adaptive levels) comes from
//! the `opensubdiv-rs` port of OpenSubdiv's `Far`/`Vtr`/`Sdc` layers; every weight is computed
//! here in `f64` (the port's weights are `f32`, about 1e-7 relative): the refinement masks in
//! `masks.rs`, regular B-spline patches in `regular_patch.rs`.
mod affine3;
mod cage;
mod compare;
mod error;
mod handles;
pub mod handoff;
mod hierarchy;
pub mod limit;
mod limit_mesh;
mod masks;
pub mod obj;
mod quadrature;
mod regular_patch;
mod rig;
pub mod scene;
mod scene_pose;
mod stencil;
pub mod surface_weights;
#[cfg(test)]
mod test_support;
mod uniform;
mod visibility;

pub use affine3::{
    affine3_about, affine3_apply, affine3_compose, affine3_is_finite, affine3_translation,
    linear3_mul, rotation_axis_angle, rotation_quaternion, Affine3, Linear3, AFFINE3_IDENTITY,
    LINEAR3_IDENTITY,
};
pub use cage::{
    bounds3, Cage, CageError, CornerTag, CreaseTag, OtherTag, Point3, SubdivTags,
    SHARPNESS_INFINITE,
};
pub use compare::{
    compare_subdiv, skin_points, ComparisonSamples, ErrorSummary, MethodResult, SubdivCompareError,
    SubdivComparison, DEFAULT_COMPARE_LEVEL,
};
pub use error::{SubdivError, SurfaceWeightsError};
pub use handles::{farthest_point_sample, Handles3};
pub use limit::{
    LimitOptions, LimitSurface, SurfaceLocation, VertexLimit, DEFAULT_ISOLATION_LEVEL,
    MAX_ISOLATION_LEVEL,
};
pub use limit_mesh::{LimitMesh, MAX_LIMIT_MESH_LEVEL};
pub use obj::{parse_obj, read_obj, to_obj_string, write_obj, ObjError, MAX_OBJ_BYTES};
pub use quadrature::{LimitQuadrature, QuadratureNode, DEFAULT_GAUSS_POINTS};
pub use rig::{SubdivRig, RIG_REGULARIZATION};
pub use scene::{
    SubdivScene, SubdivSceneError, SubdivSetup, SurfaceWeightSpec, MAX_QUADRATURE_POINTS,
    SUBDIV_SCENE_VERSION,
};
pub use scene_pose::Pose3;
pub use stencil::{LimitStencil, StencilTable};
pub use surface_weights::{
    cage_weights, node_weights, parse_weight_csv, read_weight_csv, sample_weights, BoneHeat,
    BoneHeatOptions, CageVertexWeights, Shepard3, SurfaceSample, SurfaceWeights,
};
pub use uniform::{refine_uniform, UniformLevel, UniformRefinement, MAX_UNIFORM_LEVEL};
