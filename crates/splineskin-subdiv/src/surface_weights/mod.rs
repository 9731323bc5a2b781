//! Handle weights `w_i` on a subdivision surface: how much each handle moves each point of
//! the limit surface (DESIGN.md §2, "3D").
//!
//! | family | module | handles | defined |
//! |---|---|---|---|
//! | Shepard (inverse distance; to a bone: to its segment) | [`Shepard3`] | points, bones | everywhere in space |
//! | bone heat (Baran & Popović 2007) | [`BoneHeat`] | points, bones | on the limit surface (a [`LimitMesh`]) |
//! | per cage vertex, from a file | [`CageVertexWeights`] | any | on the cage vertices, carried to the surface by the limit stencils |
//! | bounded biharmonic (Jacobson et al. 2011) on the enclosed volume | [`VolumeBbw`] | points, bones | on a grid of the volume inside the limit surface |
//!
//! Every family implements [`SurfaceWeights`]: weights at a point of the surface (given by its
//! location, position and limit stencil: each family uses what it needs) and at a cage vertex
//! (what the naive method skins the vertex with). [`node_weights`], [`sample_weights`] and
//! [`cage_weights`] evaluate a family at the quadrature nodes, at the vertices of a limit
//! mesh and at the cage vertices, and **normalise** every row to sum to one (so the rig's
//! invariants hold whatever rounding the family leaves).

mod bone_heat;
mod shepard;
mod vertex_table;
mod volume_bbw;
mod volume_grid;

pub use super::error::SurfaceWeightsError;
pub use bone_heat::{
    BoneHeat, BoneHeatOptions, BONE_HEAT_MAX_LEVEL, BONE_HEAT_MIN_LEVEL, BONE_HEAT_MIN_QUADS,
};
pub use shepard::Shepard3;
pub use vertex_table::{parse_weight_csv, read_weight_csv, CageVertexWeights};
pub use volume_bbw::{
    VolumeBbw, VolumeBbwOptions, DEFAULT_VOLUME_RESOLUTION, MAX_VOLUME_RESOLUTION,
};

use super::cage::{Cage, Point3};
use super::limit::SurfaceLocation;
use super::limit_mesh::LimitMesh;
use super::quadrature::LimitQuadrature;

/// A point of the limit surface: where it is in the parameter domain, where in space, and its
/// limit stencil (`position = Σ_j weights[j] · P[indices[j]]`).
#[derive(Clone, Copy, Debug)]
pub struct SurfaceSample<'a> {
    /// The location.
    pub location: SurfaceLocation,
    /// The limit position on the rest cage.
    pub position: Point3,
    /// Cage vertices of the limit stencil.
    pub indices: &'a [u32],
    /// Their weights.
    pub weights: &'a [f64],
}

/// Handle weights on a subdivision surface (module documentation). Immutable once built,
/// shareable between threads.
pub trait SurfaceWeights: Send + Sync {
    /// Number of handles `h`.
    fn n_handles(&self) -> usize;

    /// Writes `w_i` at the surface point `at` for every handle `i` into `out` (`h` long).
    fn eval(&self, at: &SurfaceSample<'_>, out: &mut [f64]) -> Result<(), SurfaceWeightsError>;

    /// Writes the weights the naive method skins cage vertex `vertex` (at `position`) with.
    fn eval_cage_vertex(
        &self,
        vertex: u32,
        position: Point3,
        out: &mut [f64],
    ) -> Result<(), SurfaceWeightsError>;
}

/// Weights defined at every point of space (Shepard's, the volume's): a [`SurfaceWeights`]
/// whose surface and cage-vertex weights are its values at their positions.
pub(crate) trait SpatialWeights: Send + Sync {
    /// Number of handles `h`.
    fn n_spatial_handles(&self) -> usize;
    /// The weights at `x`, into `out` (`h` long).
    fn weights_at(&self, x: Point3, out: &mut [f64]);
}

impl<T: SpatialWeights> SurfaceWeights for T {
    fn n_handles(&self) -> usize {
        self.n_spatial_handles()
    }

    fn eval(&self, at: &SurfaceSample<'_>, out: &mut [f64]) -> Result<(), SurfaceWeightsError> {
        self.weights_at(at.position, out);
        Ok(())
    }

    fn eval_cage_vertex(
        &self,
        _vertex: u32,
        position: Point3,
        out: &mut [f64],
    ) -> Result<(), SurfaceWeightsError> {
        self.weights_at(position, out);
        Ok(())
    }
}

/// The weights of every node of `quadrature` (on `cage`), normalised, node-major
/// (`n_nodes · h`, `[k · h + i]`): what [`SubdivRig::precompute`](super::SubdivRig::precompute)
/// takes.
pub fn node_weights(
    field: &dyn SurfaceWeights,
    cage: &Cage,
    quadrature: &LimitQuadrature,
) -> Result<Vec<f64>, SurfaceWeightsError> {
    let mut g = vec![[0.0; 3]; quadrature.n_nodes()];
    quadrature.positions(cage.positions(), &mut g);
    let nodes = quadrature.nodes();
    weights_at_samples(
        field,
        nodes.len(),
        |k| {
            let st = quadrature.stencil(k);
            SurfaceSample {
                location: nodes[k].location,
                position: g[k],
                indices: &st.indices,
                weights: &st.weights,
            }
        },
        |k| format!("quadrature node {k} at {:?}", nodes[k].location),
    )
}

/// The weights at every vertex of `mesh` (a limit mesh of `cage`), normalised, vertex-major
/// (`n_vertices · h`).
pub fn sample_weights(
    field: &dyn SurfaceWeights,
    cage: &Cage,
    mesh: &LimitMesh,
) -> Result<Vec<f64>, SurfaceWeightsError> {
    let mut p = vec![[0.0; 3]; mesh.n_vertices()];
    mesh.positions(cage.positions(), &mut p);
    let stencils = mesh.stencils();
    weights_at_samples(
        field,
        mesh.n_vertices(),
        |v| {
            let (indices, weights) = stencils.stencil(v);
            SurfaceSample {
                location: mesh.locations()[v],
                position: p[v],
                indices,
                weights,
            }
        },
        |v| format!("limit mesh vertex {v}"),
    )
}

/// `field` at the samples `sample(0) … sample(n − 1)`, each row normalised (`name(k)` names
/// sample `k` in errors), sample-major (`n · h`).
fn weights_at_samples<'a>(
    field: &dyn SurfaceWeights,
    n: usize,
    sample: impl Fn(usize) -> SurfaceSample<'a>,
    name: impl Fn(usize) -> String,
) -> Result<Vec<f64>, SurfaceWeightsError> {
    let h = field.n_handles();
    let mut out = vec![0.0; n * h];
    for (k, row) in out.chunks_exact_mut(h).enumerate() {
        field.eval(&sample(k), row)?;
        normalise(row, || name(k))?;
    }
    Ok(out)
}

/// The weights of every cage vertex for the naive method, normalised, vertex-major
/// (`n_vertices · h`).
pub fn cage_weights(
    field: &dyn SurfaceWeights,
    cage: &Cage,
) -> Result<Vec<f64>, SurfaceWeightsError> {
    let h = field.n_handles();
    let mut out = vec![0.0; cage.n_vertices() * h];
    for (v, row) in out.chunks_exact_mut(h).enumerate() {
        field.eval_cage_vertex(v as u32, cage.positions()[v], row)?;
        normalise(row, || format!("cage vertex {v}"))?;
    }
    Ok(out)
}

/// Divides `row` by its sum; an error (naming the place `at`) if that is not possible.
fn normalise(row: &mut [f64], at: impl Fn() -> String) -> Result<(), SurfaceWeightsError> {
    let sum: f64 = row.iter().sum();
    if !(sum > 0.0 && sum.is_finite()) || row.iter().any(|w| !w.is_finite()) {
        return Err(SurfaceWeightsError::NotNormalisable {
            at: at(),
            weights: row.to_vec(),
        });
    }
    for w in row.iter_mut() {
        *w /= sum;
    }
    Ok(())
}
