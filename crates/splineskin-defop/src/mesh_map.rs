//! A deformation operator's map at any point of the plane, for one handle configuration.
//!
//! The operator gives deformed mesh vertices `u_v(Q) = Σ_i D_vi c_i(Q)` ([`DefOp::eval`]);
//! between vertices its spatial functions are the linear interpolation of their vertex values
//! (the join's own definition, [`super::DefOpRig`]), so the deformation of a point `x` is
//!
//! ```text
//! D(x, Q) = Σ_v λ_v(x) u_v(Q)       λ_v: barycentric coordinates of x in its triangle
//! ```
//!
//! and, outside the mesh, the value at the nearest boundary point (the rule of
//! [`MeshWeights`], which the join applies to curve points outside the mesh too). This is the
//! very map whose spline fit [`super::DefOpRig`] writes, so that what is carried by it (text,
//! gradients: [`splineskin_core::drawing::follow::ElementMaps::from_map`]) moves with the curves.

use kurbo::Point;

use super::error::DefOpError;
use super::operator::DefOp;
use splineskin_core::domain::MeshWeights;
use splineskin_core::mesh::TriMesh;
use splineskin_core::weights::WeightField;

/// The piecewise-linear map of a triangle mesh onto deformed positions of its vertices
/// (module doc): `apply(x) = Σ_v λ_v(x) u_v`, nearest boundary point outside.
///
/// ```text
/// once per configuration:  let map = MeshMap::from_operator(&mesh, &op, &q)?;   (O(n_vertices))
/// per point:               let y = map.apply(x);                                (a grid lookup)
/// ```
///
/// ```
/// use kurbo::{Affine, Point, Rect};
/// use splineskin_defop::MeshMap;
/// use splineskin_core::mesh::TriMesh;
/// let mesh = TriMesh::grid(Rect::new(0., 0., 4., 1.), 8, 2)?;
/// // Vertices moved by an affine map: the interpolation is that map everywhere inside.
/// let t = Affine::new([1.2, 0.3, -0.1, 0.9, 5.0, -2.0]);
/// let moved: Vec<Point> = mesh.vertices.iter().map(|&p| t * p).collect();
/// let map = MeshMap::new(&mesh, &moved)?;
/// let x = Point::new(1.3, 0.7);
/// assert!((map.apply(x) - t * x).hypot() < 1e-12);
/// // Outside: the value at the nearest boundary point, (4, 0.5).
/// assert!((map.apply(Point::new(6.0, 0.5)) - t * Point::new(4.0, 0.5)).hypot() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct MeshMap {
    /// The deformed `x` and `y` of each vertex as a two-"handle" field: interpolating them is
    /// interpolating the positions.
    field: MeshWeights,
}

impl MeshMap {
    /// The map of `mesh` onto `positions` (one per vertex, deformed).
    ///
    /// Errors: an invalid mesh, or a wrong number of positions or a non-finite one
    /// ([`DefOpError::Domain`], naming the vertex).
    pub fn new(mesh: &TriMesh, positions: &[Point]) -> Result<MeshMap, DefOpError> {
        let values: Vec<f64> = positions.iter().flat_map(|p| [p.x, p.y]).collect();
        Ok(MeshMap {
            field: MeshWeights::new(mesh, values, 2)?,
        })
    }

    /// The map of operator `op` (trained or fitted on `mesh`) at the handle configuration `q`:
    /// [`MeshMap::new`] on `op.eval(q)`.
    ///
    /// Errors: those of [`DefOp::eval`] (a configuration of another size, a non-finite
    /// position) and [`MeshMap::new`] (a mesh of another vertex count than the operator's).
    pub fn from_operator(mesh: &TriMesh, op: &DefOp, q: &[Point]) -> Result<MeshMap, DefOpError> {
        if op.n_vertices() != mesh.n_vertices() {
            return Err(DefOpError::BasisMismatch {
                basis_vertices: op.n_vertices(),
                n_vertices: mesh.n_vertices(),
            });
        }
        MeshMap::new(mesh, &op.eval(q)?)
    }

    /// The deformed position of `x` (module doc); NaN for a mesh without boundary
    /// (unreachable for a valid mesh).
    pub fn apply(&self, x: Point) -> Point {
        let mut xy = [0.0; 2];
        self.field.eval(x, &mut xy);
        Point::new(xy[0], xy[1])
    }
}

/// The operator's map as a linear function of its handle functions:
/// `D(x, Q) = Σ_j ψ_j(Q) D_j(x)` with `D_j(x) = Σ_v λ_v(x) U_vj` ([`DefOp::function_positions`]).
/// What is linear in the deformed points (the best-fit maps of carried text, images and
/// paint) is then linear in `ψ(Q)`, and a live view updates it with one small product per frame
/// instead of sampling the map again.
///
/// ```
/// use kurbo::{Point, Rect};
/// use splineskin_defop::{DefOp, DefOpOptions, FunctionMaps, HandleBasisKind, MeshMap, SpatialBasis};
/// use splineskin_core::mesh::TriMesh;
/// let mesh = TriMesh::grid(Rect::new(0., 0., 4., 1.), 8, 2)?;
/// let handles = [9, 17];
/// let configurations: Vec<Vec<Point>> = (0..6)
///     .map(|k| vec![Point::new(0., 0.5 + 0.1 * k as f64), Point::new(4., 0.5)])
///     .collect();
/// let solutions: Vec<Vec<Point>> = (0..6)
///     .map(|k| mesh.vertices.iter().map(|&p| Point::new(p.x, p.y + 0.1 * k as f64 * (1. - p.x / 4.))).collect())
///     .collect();
/// let spatial = SpatialBasis::hats(&mesh)?;
/// let options = DefOpOptions::default().with_handle_basis(HandleBasisKind::Linear);
/// let op = DefOp::fit(&mesh, &handles, &spatial, &configurations, &solutions, &options)?;
/// let maps = FunctionMaps::new(&mesh, &op)?;
/// // Σ_j ψ_j(Q) D_j(x) is the operator's map at Q.
/// let q = [Point::new(0.1, 0.8), Point::new(4.0, 0.4)];
/// let mut psi = vec![0.0; maps.n_functions()];
/// op.handle_basis().eval(&q, &mut psi)?;
/// let mut d = vec![0.0; 2 * maps.n_functions()];
/// let x = Point::new(1.3, 0.6);
/// maps.eval(x, &mut d);
/// let (sx, sy) = psi.iter().enumerate().fold((0., 0.), |(sx, sy), (j, p)| (sx + p * d[2 * j], sy + p * d[2 * j + 1]));
/// let direct = MeshMap::from_operator(&mesh, &op, &q)?.apply(x);
/// assert!((Point::new(sx, sy) - direct).hypot() < 1e-9);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct FunctionMaps {
    /// `D_j`'s x and y for every `j`, as a `2|Ψ|`-"handle" field.
    field: MeshWeights,
}

impl FunctionMaps {
    /// The maps `D_j` of operator `op` (trained or fitted on `mesh`).
    ///
    /// Errors: a mesh of another vertex count than the operator's
    /// ([`DefOpError::BasisMismatch`]) or an invalid mesh.
    pub fn new(mesh: &TriMesh, op: &DefOp) -> Result<FunctionMaps, DefOpError> {
        if op.n_vertices() != mesh.n_vertices() {
            return Err(DefOpError::BasisMismatch {
                basis_vertices: op.n_vertices(),
                n_vertices: mesh.n_vertices(),
            });
        }
        let n_channels = 2 * op.handle_basis().n_functions();
        Ok(FunctionMaps {
            field: MeshWeights::new(mesh, op.function_positions(), n_channels)?,
        })
    }

    /// Number of handle functions `|Ψ|`.
    pub fn n_functions(&self) -> usize {
        self.field.n_handles() / 2
    }

    /// Writes `D_j(x)` into `out[2j]` (x) and `out[2j + 1]` (y), `2|Ψ|` values.
    pub fn eval(&self, x: Point, out: &mut [f64]) {
        self.field.eval(x, out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use kurbo::Rect;

    #[test]
    fn mesh_map_interpolates_vertex_positions_linearly_in_each_triangle() {
        let mesh = TriMesh::grid(Rect::new(0., 0., 2., 2.), 2, 2).unwrap();
        // A non-affine motion of the vertices: x ↦ (x + y², y).
        let f = |p: Point| Point::new(p.x + p.y * p.y, p.y);
        let moved: Vec<Point> = mesh.vertices.iter().map(|&p| f(p)).collect();
        let map = MeshMap::new(&mesh, &moved).unwrap();
        // At every vertex: its own position.
        for (&v, &m) in mesh.vertices.iter().zip(&moved) {
            assert!((map.apply(v) - m).hypot() < 1e-12, "{v:?}");
        }
        // Midpoint of the edge (0, 1)–(0, 2) (on the mesh boundary, x = 0): the mean of its
        // ends' images, (1 + 4)/2 = 2.5 in x, not f's 2.25.
        let mid = map.apply(Point::new(0.0, 1.5));
        assert!((mid - Point::new(2.5, 1.5)).hypot() < 1e-12, "{mid:?}");
    }

    #[test]
    fn mesh_map_refuses_a_wrong_count_or_non_finite_positions() {
        let mesh = TriMesh::grid(Rect::new(0., 0., 1., 1.), 1, 1).unwrap();
        assert!(MeshMap::new(&mesh, &[Point::ZERO; 3]).is_err());
        let mut moved = mesh.vertices.clone();
        moved[2].x = f64::NAN;
        assert!(matches!(
            MeshMap::new(&mesh, &moved),
            Err(DefOpError::Domain(_))
        ));
    }
}
