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
use crate::mesh::operators::polyharmonic_csc;
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
/// use splineskin_core::mesh::TriMesh;
/// use splineskin_core::weights::harmonic::harmonic_weights;
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
/// use splineskin_core::mesh::TriMesh;
/// use splineskin_core::weights::{harmonic::harmonic, DirichletData};
/// // The unit square fanned around its centre (vertex 4). Fixing the function x at the
/// // corners reproduces it at the centre: the cotangent Laplacian is exact on linear
/// // functions at interior vertices, so piecewise linear boundary data (a cage's) of a
/// // linear function give that function back.
/// let v = [(0., 0.), (1., 0.), (1., 1.), (0., 1.), (0.5, 0.5)].map(Point::from);
/// let t = vec![[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]];
/// let mesh = TriMesh::new(v.to_vec(), t)?;
/// let data = DirichletData::new(vec![0, 1, 2, 3], vec![0.0, 1.0, 1.0, 0.0], 1)?;
/// let w = harmonic(&mesh, &data, 1)?;
/// assert!((w.get(4, 0) - 0.5).abs() < 1e-15);
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
    check_problem(mesh, data)?;
    EnergySystem::new(polyharmonic_csc(mesh, k))
}

/// Checks that the energy minimisation of `data` on `mesh` is well posed for an energy whose
/// null space is the constants: a valid mesh, the fixed vertices in range, every vertex in a
/// triangle, and a fixed vertex in every connected part.
pub(crate) fn check_problem(mesh: &TriMesh, data: &DirichletData) -> Result<(), WeightsError> {
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
    Ok(())
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

#[cfg(test)]
mod tests {
    use super::*;
    use kurbo::{Point, Rect};

    /// A 6 × 4 grid over [0, 3] × [0, 2], jittered so that no triangle is right-angled (the
    /// cotangent weights are then all different) while staying counter-clockwise.
    fn jittered_grid() -> TriMesh {
        let mut mesh = TriMesh::grid(Rect::new(0.0, 0.0, 3.0, 2.0), 6, 4).unwrap();
        for (i, p) in mesh.vertices.iter_mut().enumerate() {
            let (x, y) = (p.x, p.y);
            let on_x_edge = x == 0.0 || x == 3.0;
            let on_y_edge = y == 0.0 || y == 2.0;
            let s = ((i * 7919) % 13) as f64 / 13.0 - 0.5;
            let c = ((i * 104_729) % 11) as f64 / 11.0 - 0.5;
            *p = Point::new(
                if on_x_edge { x } else { x + 0.12 * s },
                if on_y_edge { y } else { y + 0.12 * c },
            );
        }
        mesh.check().unwrap();
        mesh
    }

    /// `f(p) = a + b·x + c·y` at every vertex.
    fn linear(mesh: &TriMesh, [a, b, c]: [f64; 3]) -> Vec<f64> {
        mesh.vertices
            .iter()
            .map(|p| a + b * p.x + c * p.y)
            .collect()
    }

    /// Vertices within `rings` edges of the boundary.
    fn boundary_rings(mesh: &TriMesh, rings: usize) -> Vec<usize> {
        let mut near = vec![false; mesh.n_vertices()];
        for e in mesh.boundary_edges().unwrap() {
            near[e[0]] = true;
        }
        for _ in 1..rings {
            let current = near.clone();
            for t in &mesh.triangles {
                if t.iter().any(|&v| current[v]) {
                    t.iter().for_each(|&v| near[v] = true);
                }
            }
        }
        (0..mesh.n_vertices()).filter(|&v| near[v]).collect()
    }

    /// Rounding allowance for solved values of order 1 on a 35-vertex mesh.
    const SOLVE_ROUNDING: f64 = 1e-12;

    #[test]
    fn harmonic_reproduces_linear_functions_from_boundary_data() {
        // The cotangent Laplacian is linearly precise: L·f = 0 at interior vertices for linear
        // f. So with f prescribed on the boundary (piecewise linear data, as a cage gives),
        // k = 1 reproduces f inside; k = 2 needs the boundary's neighbours too (Q = L M⁻¹ L
        // reaches two rings), and then reproduces f as well.
        let mesh = jittered_grid();
        let f = [
            linear(&mesh, [0.5, 1.0, -2.0]),
            linear(&mesh, [-1.0, 0.3, 0.7]),
        ];
        for (k, rings) in [(1, 1), (2, 2)] {
            let fixed = boundary_rings(&mesh, rings);
            let values = fixed.iter().flat_map(|&v| [f[0][v], f[1][v]]).collect();
            let data = DirichletData::new(fixed.clone(), values, 2).unwrap();
            let w = harmonic(&mesh, &data, k).unwrap();
            assert!(fixed.len() < mesh.n_vertices(), "some vertices are free");
            for v in 0..mesh.n_vertices() {
                for j in 0..2 {
                    let d = (w.get(v, j) - f[j][v]).abs();
                    assert!(
                        d < SOLVE_ROUNDING,
                        "k={k} vertex {v} column {j}: off by {d:e}"
                    );
                }
            }
        }
        // Control: with only the boundary fixed, k = 2 does not reproduce a linear function
        // (natural conditions act at the boundary's neighbours), so the test above can fail.
        let fixed = boundary_rings(&mesh, 1);
        let values = fixed.iter().map(|&v| f[0][v]).collect();
        let w = harmonic(&mesh, &DirichletData::new(fixed, values, 1).unwrap(), 2).unwrap();
        let worst = (0..mesh.n_vertices())
            .map(|v| (w.get(v, 0) - f[0][v]).abs())
            .fold(0.0, f64::max);
        assert!(worst > 1e-3, "{worst:e}");
    }

    #[test]
    fn harmonic_weights_interpolate_and_sum_to_one() {
        let mesh = jittered_grid();
        let handles = [0, 34, 17, 6];
        for k in 1..=MAX_ORDER {
            let w = harmonic_weights(&mesh, &handles, k).unwrap();
            assert_eq!((w.n_vertices(), w.n_handles()), (35, 4));
            for (i, &v) in handles.iter().enumerate() {
                for j in 0..4 {
                    assert_eq!(w.get(v, j), if i == j { 1.0 } else { 0.0 });
                }
            }
            for v in 0..35 {
                let sum: f64 = w.row(v).iter().sum();
                assert!(
                    (sum - 1.0).abs() < SOLVE_ROUNDING,
                    "k={k} vertex {v}: {sum}"
                );
            }
        }
    }

    #[test]
    fn harmonic_rejects_bad_input() {
        let mesh = jittered_grid();
        assert_eq!(
            harmonic_weights(&mesh, &[], 1),
            Err(WeightsError::NoHandles)
        );
        assert_eq!(
            harmonic_weights(&mesh, &[3, 35], 1),
            Err(WeightsError::HandleOutOfRange {
                handle: 1,
                vertex: 35,
                n_vertices: 35
            })
        );
        assert_eq!(
            harmonic_weights(&mesh, &[3, 8, 3], 1),
            Err(WeightsError::DuplicateHandle {
                vertex: 3,
                first: 0,
                second: 2
            })
        );
        for k in [0, MAX_ORDER + 1] {
            assert_eq!(
                harmonic_weights(&mesh, &[3], k),
                Err(WeightsError::UnsupportedOrder {
                    order: k,
                    max: MAX_ORDER
                })
            );
        }
        // A vertex in no triangle, and a second part of the mesh without a handle.
        let mut extra = mesh.clone();
        extra.vertices.push(Point::new(9.0, 9.0));
        assert_eq!(
            harmonic_weights(&extra, &[3], 1),
            Err(WeightsError::UnreferencedVertex { vertex: 35 })
        );
        extra
            .vertices
            .extend([Point::new(10.0, 9.0), Point::new(9.0, 10.0)]);
        extra.triangles.push([35, 36, 37]);
        assert_eq!(
            harmonic_weights(&extra, &[3], 2),
            Err(WeightsError::UnconstrainedComponent { vertex: 35 })
        );
        assert!(harmonic_weights(&extra, &[3, 36], 2).is_ok());
        // An invalid mesh.
        let mut clockwise = mesh.clone();
        clockwise.triangles[5].swap(0, 1);
        assert!(matches!(
            harmonic_weights(&clockwise, &[3], 1),
            Err(WeightsError::Mesh(crate::mesh::MeshError::BadOrientation {
                triangle: 5,
                ..
            }))
        ));
        // Dirichlet data of the wrong shape or not finite.
        assert_eq!(
            DirichletData::new(vec![1, 2], vec![0.0; 3], 2),
            Err(WeightsError::DirichletShape {
                len: 3,
                n_fixed: 2,
                n_columns: 2
            })
        );
        assert!(matches!(
            DirichletData::new(vec![1, 2], vec![0.0, f64::NAN], 1),
            Err(WeightsError::NonFiniteValue {
                row: 1,
                vertex: 2,
                column: 0,
                ..
            })
        ));
    }
}
