//! The as-rigid-as-possible (ARAP) energy of a deformed triangle mesh.
//!
//! ```text
//! E_ARAP(u) = Σ_t A_t ‖J_t − R_t‖²_F = Σ_t A_t ((Σ_t − 1)² + (σ_t − 1)²)
//! ```
//!
//! with `J_t` the deformation gradient on triangle `t`, `R_t ∈ SO(2)` its closest rotation,
//! `A_t` the rest area and `Σ_t ≥ |σ_t|` the singular values, `σ_t` negative where `det J_t < 0`
//! (Poranne & Lipman 2016, Eq. (10); [`super::deformation_gradient`] for the closed forms). It
//! equals libigl's edge form `Σ_t Σ_{(i,j) ∈ t} ½ cot θ_ij ‖(u_i − u_j) − R_t (p_i − p_j)‖²`
//! (`ARAP_ENERGY_TYPE_ELEMENTS`), because `Σ_{(i,j) ∈ t} ½ cot θ_ij e_ij e_ijᵀ = A_t I` for the
//! rest edges `e_ij` of a triangle.

use kurbo::Point;

use super::deformation_gradient::TriangleGradients;
use super::error::DefOpError;
use super::handles::check_position_count;
use splineskin_core::mesh::TriMesh;

/// `E_ARAP` of `mesh` deformed to `positions` (one per vertex; the rest pose is
/// `mesh.vertices`). In squared drawing units (area × a dimensionless distortion).
///
/// ```
/// use kurbo::{Affine, Point};
/// use splineskin_defop::arap_energy;
/// use splineskin_core::mesh::TriMesh;
/// let v = vec![Point::new(0., 0.), Point::new(2., 0.), Point::new(0., 1.)];
/// let mesh = TriMesh::new(v.clone(), vec![[0, 1, 2]])?;
/// // A rigid motion costs nothing; a uniform scale by 2 costs A (1² + 1²) = 1 · 2.
/// let moved: Vec<Point> = v.iter().map(|&p| Affine::rotate(0.3).then_translate((4., 1.).into()) * p).collect();
/// assert!(arap_energy(&mesh, &moved)? < 1e-28);
/// let doubled: Vec<Point> = v.iter().map(|&p| Point::new(2. * p.x, 2. * p.y)).collect();
/// assert!((arap_energy(&mesh, &doubled)? - 2.0).abs() < 1e-14);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn arap_energy(mesh: &TriMesh, positions: &[Point]) -> Result<f64, DefOpError> {
    mesh.check()?;
    check_position_count(positions, mesh.n_vertices())?;
    Ok(arap_energy_of(&TriangleGradients::new(mesh), positions))
}

/// `E_ARAP` from precomputed rest data.
pub(crate) fn arap_energy_of(rest: &TriangleGradients, u: &[Point]) -> f64 {
    (0..rest.n_triangles())
        .map(|t| rest.area[t] * rest.jacobian(t, u).split().arap_density())
        .sum()
}
