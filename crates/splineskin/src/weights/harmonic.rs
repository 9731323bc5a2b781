//! Harmonic (`k = 1`) and biharmonic (`k = 2`) weights on a triangle mesh, with Dirichlet
//! data at handle vertices (DESIGN.md §2; libigl's `harmonic(V, F, b, bc, k, W)`).
//!
//! Each column `w` (one per handle) minimises the polyharmonic energy with its values at the
//! fixed vertices prescribed:
//!
//! ```text
//! minimise  wᵀ Q_k w   subject to  w[b] = bc,      Q_1 = −L,   Q_2 = L M⁻¹ L
//! ```
//!
//! (`L` the cotangent Laplacian, `M` the Voronoi lumped mass;
//! [`crate::mesh::operators::polyharmonic_energy`]). `k = 1` is the discrete Laplace equation
//! `L w = 0` at the free vertices (harmonic coordinates, Joshi et al. 2007, when `bc` is a
//! cage's piecewise linear data); `k = 2` the biharmonic equation with natural boundary
//! conditions (Jacobson et al. 2011 §3, without the bounds). Harmonic weights lie in the range
//! of the data (maximum principle, exact for Delaunay meshes, whose cotangent weights are
//! non-negative); biharmonic ones do not, and are not linearly precise.
//!
//! One sparse Cholesky factorisation of `Q_ff` serves every column.

use super::reduced_cholesky::EnergySystem;
use super::{DirichletData, VertexWeights, WeightsError};
use crate::mesh::operators::{polyharmonic_energy, Csc};
use crate::mesh::TriMesh;

/// Highest supported order `k`: each order widens the energy's stencil by one ring of
/// neighbours (and the factor's fill with it); the weight families of DESIGN.md §2 need 1 and 2,
/// and 3 (triharmonic) is kept for experiments.
pub const MAX_ORDER: usize = 3;

/// Weights of point handles at vertices `handles` (`w_i = 1` at `handles[i]`, 0 at the other
/// handles) minimising the order-`k` energy: `k = 1` harmonic, `k = 2` biharmonic. Returns
/// `n_vertices × handles.len()` weights.
///
/// Errors: an invalid mesh, no handles, a handle out of range or repeated, `k` outside
/// `1 ..= MAX_ORDER`, a vertex in no triangle, or a connected part of the mesh without a
/// handle (see [`WeightsError`]).
///
/// ```
/// use kurbo::Point;
/// use splineskin::mesh::TriMesh;
/// use splineskin::weights::harmonic::harmonic_weights;
/// // A strip of two squares; handles at the two ends' bottom corners.
/// let v = [(0., 0.), (1., 0.), (2., 0.), (0., 1.), (1., 1.), (2., 1.)].map(Point::from);
/// let t = vec![[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4]];
/// let mesh = TriMesh::new(v.to_vec(), t)?;
/// let w = harmonic_weights(&mesh, &[0, 2], 1)?;
/// assert_eq!(w.row(0), &[1.0, 0.0]);
/// assert_eq!(w.row(2), &[0.0, 1.0]);
/// for v in 0..6 {
///     let sum: f64 = w.row(v).iter().sum();
///     assert!((sum - 1.0).abs() < 1e-12); // the data sum to 1, so do harmonic weights
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn harmonic_weights(
    mesh: &TriMesh,
    handles: &[usize],
    k: usize,
) -> Result<VertexWeights, WeightsError> {
    harmonic(mesh, &DirichletData::handles(handles)?, k)
}

/// The order-`k` polyharmonic functions with the values `data` at its vertices, one per
/// column of `data` (`n_vertices × data.n_columns()`). The general form of
/// [`harmonic_weights`], for cages (piecewise linear data along the cage's edges) or any
/// other boundary data. Errors as [`harmonic_weights`].
///
/// ```
/// use kurbo::Point;
/// use splineskin::mesh::TriMesh;
/// use splineskin::weights::{harmonic::harmonic, DirichletData};
/// // The unit square split in two; fixing the function x at three corners reproduces it at
/// // the fourth: linear functions are harmonic.
/// let v = [(0., 0.), (1., 0.), (1., 1.), (0., 1.)].map(Point::from);
/// let mesh = TriMesh::new(v.to_vec(), vec![[0, 1, 2], [0, 2, 3]])?;
/// let w = harmonic(&mesh, &DirichletData::new(vec![0, 1, 2], vec![0.0, 1.0, 1.0], 1)?, 1)?;
/// assert!(w.get(3, 0).abs() < 1e-15);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn harmonic(
    mesh: &TriMesh,
    data: &DirichletData,
    k: usize,
) -> Result<VertexWeights, WeightsError> {
    let system = prepare(mesh, data, k)?;
    let columns = solve_unbounded(&system, data)?;
    Ok(VertexWeights::from_columns(
        mesh.n_vertices(),
        data.n_columns(),
        &columns,
    ))
}

/// Checks `mesh` and `data` and builds the order-`k` energy with its ordering.
pub(crate) fn prepare(
    mesh: &TriMesh,
    data: &DirichletData,
    k: usize,
) -> Result<EnergySystem, WeightsError> {
    if !(1..=MAX_ORDER).contains(&k) {
        return Err(WeightsError::UnsupportedOrder {
            order: k,
            max: MAX_ORDER,
        });
    }
    mesh.check()?;
    let n = mesh.n_vertices();
    data.check_range(n)?;
    if let Some(vertex) = mesh.referenced_vertices().iter().position(|&used| !used) {
        return Err(WeightsError::UnreferencedVertex { vertex });
    }
    let components = mesh.components();
    let n_components = components.iter().max().map_or(0, |&c| c + 1);
    let mut constrained = vec![false; n_components];
    for &v in data.vertices() {
        constrained[components[v]] = true;
    }
    if let Some(c) = constrained.iter().position(|&held| !held) {
        // Components are numbered in the order of their smallest vertex.
        let vertex = components.iter().position(|&x| x == c).unwrap_or(0);
        return Err(WeightsError::UnconstrainedComponent { vertex });
    }
    EnergySystem::new(Csc::from_faer(&polyharmonic_energy(mesh, k)))
}

/// The unbounded minimisers, column-major (`n_columns` contiguous columns of `n_vertices`),
/// from one factorisation.
pub(crate) fn solve_unbounded(
    system: &EnergySystem,
    data: &DirichletData,
) -> Result<Vec<f64>, WeightsError> {
    let n = system.n();
    let h = data.n_columns();
    let mut free = vec![true; n];
    let mut columns = vec![0.0; n * h];
    for (row, &v) in data.vertices().iter().enumerate() {
        free[v] = false;
        for (j, &value) in data.values_at(row).iter().enumerate() {
            columns[j * n + v] = value;
        }
    }
    let mut factor = system.factor(&free)?;
    factor.solve_free(system, &mut columns);
    Ok(columns)
}
