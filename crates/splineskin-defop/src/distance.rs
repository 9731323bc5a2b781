//! [`l2_distance`]: how far apart two deformations of a mesh are, the error measure of the
//! deformation operators' study (Poranne & Lipman 2016, Fig. 8, measure the fit's objective
//! (8a) per sample).

use kurbo::Point;

use super::error::DefOpError;
use splineskin_core::mesh::operators::consistent_mass_csc;
use splineskin_core::mesh::TriMesh;

/// The root-mean-square distance over the shape between two deformations `a` and `b` of
/// `mesh` (one point per vertex each, linear on each triangle), drawing units:
///
/// ```text
/// l2_distance(a, b) = sqrt( ∫_Ω ‖a(x) − b(x)‖² dx / area(Ω) ) = sqrt( (eₓᵀ M eₓ + e_yᵀ M e_y) / area )
/// ```
///
/// with `e = a − b` at the vertices and `M` the consistent mass matrix, so it is exact for the
/// piecewise linear maps. A uniform offset `d` gives `‖d‖`. Errors on an invalid mesh or
/// point counts other than the vertex count.
///
/// ```
/// use kurbo::{Point, Rect, Vec2};
/// use splineskin_defop::l2_distance;
/// use splineskin_core::mesh::TriMesh;
/// let mesh = TriMesh::grid(Rect::new(0., 0., 2., 1.), 4, 2)?;
/// let moved: Vec<Point> = mesh.vertices.iter().map(|&p| p + Vec2::new(0.3, 0.4)).collect();
/// assert!((l2_distance(&mesh, &mesh.vertices, &moved)? - 0.5).abs() < 1e-14);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn l2_distance(mesh: &TriMesh, a: &[Point], b: &[Point]) -> Result<f64, DefOpError> {
    mesh.check()?;
    let n = mesh.n_vertices();
    for given in [a.len(), b.len()] {
        if given != n {
            return Err(DefOpError::PositionCount {
                given,
                n_vertices: n,
            });
        }
    }
    let mass = consistent_mass_csc(mesh);
    let e: Vec<_> = a.iter().zip(b).map(|(p, q)| *p - *q).collect();
    let mut integral = 0.0;
    for c in 0..n {
        let (rows, values) = mass.column(c);
        for (&r, &m) in rows.iter().zip(values) {
            integral += m * e[r].dot(e[c]);
        }
    }
    Ok((integral.max(0.0) / mesh.total_area()).sqrt())
}
