//! Linearly precise biharmonic coordinates of point handles (Wang, Jacobson, Barbič & Kavan
//! 2015, *Linear Subspace Design for Real-Time Shape Deformation*; libigl's
//! `biharmonic_coordinates(V, F, S, 2, W)` with one vertex per handle).
//!
//! Each column `w` (one per handle) minimises the linearly precise squared-Laplacian energy
//! with the identity prescribed at the handles:
//!
//! ```text
//! minimise  wᵀ A w   subject to  w[handles] = I,      A = Kᵀ W K   (Crouzeix–Raviart variant)
//! ```
//!
//! **Variant.** `A` is libigl 2.6.3's discretisation (Crouzeix–Raviart stiffness and mass on
//! edges, zero weight on boundary edges; `mesh/crouzeix_raviart.rs` spells it out), not the
//! vertex-based `K = L + N` printed in the paper, which its erratum withdraws. The two differ
//! by up to 1.1 on the reference bar (`reference-igl/README.md`). `A` is zero on every linear
//! function, so the coordinates are **linearly precise** (`Σ_i w_i(v) p_i = v` at every vertex
//! `v`) and a partition of unity; unlike bounded biharmonic weights they are not bounded (they
//! range over about `[−0.9, 1.7]` on the reference shapes). They need at least three handles
//! not on one line in every connected part of the mesh.
//!
//! As a spatial basis of a deformation operator (Poranne & Lipman 2016, §3.1: "the linearly
//! precise Laplacian presented in [Wang et al. 2015]"), the coordinates of many control
//! vertices span a smooth subspace that holds the linear functions and interpolates any value
//! at the control vertices (the deformation operators' reduced basis, `defop`).

use super::harmonic::{check_problem, solve_unbounded};
use super::reduced_cholesky::EnergySystem;
use super::{DirichletData, VertexWeights, WeightsError};
use crate::mesh::crouzeix_raviart::linearly_precise_energy_csc;
use crate::mesh::TriMesh;

/// Handles closer to a line than this fraction of their spread count as collinear
/// (dimensionless): the energy's null space (linear functions) then makes the system singular
/// to rounding.
const COLLINEAR_TOLERANCE: f64 = 1e-9;

/// The linearly precise biharmonic coordinates of point handles at the vertices `handles`
/// (`w_i = 1` at `handles[i]`, 0 at the other handles): `n_vertices × handles.len()` weights.
///
/// Errors: an invalid mesh, no handles, a handle out of range or repeated, a vertex in no
/// triangle, a connected part of the mesh without a handle, or fewer than three handles not on
/// one line in a part (see [`WeightsError`]).
///
/// ```
/// use kurbo::Rect;
/// use splineskin_core::mesh::TriMesh;
/// use splineskin_core::weights::biharmonic_coordinates;
/// let mesh = TriMesh::grid(Rect::new(0., 0., 2., 1.), 8, 4)?;
/// let handles = [0, 8, 44, 22]; // three corners and an interior vertex
/// let w = biharmonic_coordinates(&mesh, &handles)?;
/// for (v, p) in mesh.vertices.iter().enumerate() {
///     // Linear precision: the handles' rest positions blend back to the vertex.
///     let (mut x, mut y) = (0.0, 0.0);
///     for (i, &h) in handles.iter().enumerate() {
///         x += w.get(v, i) * mesh.vertices[h].x;
///         y += w.get(v, i) * mesh.vertices[h].y;
///     }
///     assert!((x - p.x).abs() < 1e-10 && (y - p.y).abs() < 1e-10);
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn biharmonic_coordinates(
    mesh: &TriMesh,
    handles: &[usize],
) -> Result<VertexWeights, WeightsError> {
    let data = DirichletData::handles(handles)?;
    check_problem(mesh, &data)?;
    check_not_collinear(mesh, handles)?;
    let system = EnergySystem::new(linearly_precise_energy_csc(mesh))?;
    let columns = solve_unbounded(&system, &data)?;
    Ok(VertexWeights::from_columns(
        mesh.n_vertices(),
        handles.len(),
        &columns,
    ))
}

/// Errors unless every connected part of `mesh` holds three handles not on one line.
fn check_not_collinear(mesh: &TriMesh, handles: &[usize]) -> Result<(), WeightsError> {
    let components = mesh.components();
    let n_components = components.iter().max().map_or(0, |&c| c + 1);
    for c in 0..n_components {
        let points: Vec<_> = handles
            .iter()
            .filter(|&&h| components[h] == c)
            .map(|&h| mesh.vertices[h])
            .collect();
        let spread = points
            .iter()
            .map(|&p| (p - points[0]).hypot())
            .fold(0.0, f64::max);
        let far = points.iter().copied().max_by(|a, b| {
            (*a - points[0])
                .hypot()
                .total_cmp(&(*b - points[0]).hypot())
        });
        let off_line = far.map_or(0.0, |far| {
            let axis = far - points[0];
            points
                .iter()
                .map(|&p| axis.cross(p - points[0]).abs() / spread)
                .fold(0.0, f64::max)
        });
        // `off_line` is NaN when the part holds one handle (spread 0): collinear too.
        let on_a_line = off_line.is_nan() || off_line <= COLLINEAR_TOLERANCE * spread;
        if points.len() < 3 || on_a_line {
            let vertex = components.iter().position(|&x| x == c).unwrap_or(0);
            return Err(WeightsError::CollinearHandles {
                vertex,
                n_handles: points.len(),
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use kurbo::Rect;

    #[test]
    fn biharmonic_coordinates_partition_of_unity_and_identity_at_handles() {
        let mesh = TriMesh::grid(Rect::new(0., 0., 3., 1.), 12, 4).unwrap();
        let handles = [0, 12, 64, 30, 40];
        let w = biharmonic_coordinates(&mesh, &handles).unwrap();
        for v in 0..mesh.n_vertices() {
            let sum: f64 = w.row(v).iter().sum();
            assert!((sum - 1.0).abs() < 1e-10, "vertex {v}: sum {sum}");
        }
        for (i, &h) in handles.iter().enumerate() {
            for j in 0..handles.len() {
                assert_eq!(w.get(h, j), if i == j { 1.0 } else { 0.0 });
            }
        }
    }

    #[test]
    fn biharmonic_coordinates_need_three_handles_off_a_line() {
        let mesh = TriMesh::grid(Rect::new(0., 0., 3., 1.), 6, 2).unwrap();
        // Vertices 7, 9, 11 lie on the line y = 0.5.
        for handles in [&[7, 9][..], &[7, 9, 11][..]] {
            assert_eq!(
                biharmonic_coordinates(&mesh, handles),
                Err(WeightsError::CollinearHandles {
                    vertex: 0,
                    n_handles: handles.len()
                })
            );
        }
        assert!(biharmonic_coordinates(&mesh, &[7, 9, 0]).is_ok());
    }
}
