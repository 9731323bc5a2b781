//! Triangle meshes of a planar domain, the support of the mesh-based weight families
//! (harmonic, biharmonic, bounded biharmonic; DESIGN.md §2).
//!
//! A [`TriMesh`] is an indexed triangle list in the drawing's coordinates. Triangles are
//! counter-clockwise (positive signed area) — every constructor and reader checks it.

use kurbo::Point;

/// An indexed triangle mesh in the plane.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriMesh {
    /// Vertex positions.
    pub vertices: Vec<Point>,
    /// Triangles as vertex indices, counter-clockwise.
    pub triangles: Vec<[usize; 3]>,
}

/// Why a mesh is not usable.
#[derive(Debug, thiserror::Error, PartialEq)]
#[non_exhaustive]
pub enum MeshError {
    /// A triangle refers to a vertex that does not exist.
    #[error("triangle {triangle}: vertex index {index} out of range (the mesh has {n_vertices} vertices)")]
    IndexOutOfRange {
        /// The triangle.
        triangle: usize,
        /// The offending index.
        index: usize,
        /// Number of vertices.
        n_vertices: usize,
    },
    /// A vertex coordinate is NaN or infinite.
    #[error("vertex {vertex}: coordinate is not finite ({x}, {y})")]
    NonFinite {
        /// The vertex.
        vertex: usize,
        /// Its x.
        x: f64,
        /// Its y.
        y: f64,
    },
    /// A triangle has zero or negative signed area (degenerate or clockwise).
    #[error(
        "triangle {triangle}: signed area {area:e} (expected counter-clockwise, positive area)"
    )]
    BadOrientation {
        /// The triangle.
        triangle: usize,
        /// Its signed area.
        area: f64,
    },
    /// The mesh has no triangles.
    #[error("the mesh has no triangles")]
    Empty,
}

impl TriMesh {
    /// Builds a mesh and checks it: indices in range, finite coordinates, every triangle
    /// counter-clockwise with positive area.
    ///
    /// ```
    /// use kurbo::Point;
    /// use splineskin::mesh::TriMesh;
    /// let v = vec![Point::new(0., 0.), Point::new(1., 0.), Point::new(0., 1.)];
    /// assert!(TriMesh::new(v.clone(), vec![[0, 1, 2]]).is_ok());
    /// assert!(TriMesh::new(v, vec![[0, 2, 1]]).is_err()); // clockwise
    /// ```
    pub fn new(vertices: Vec<Point>, triangles: Vec<[usize; 3]>) -> Result<TriMesh, MeshError> {
        let mesh = TriMesh {
            vertices,
            triangles,
        };
        mesh.check()?;
        Ok(mesh)
    }

    /// Checks the invariants listed at [`TriMesh::new`].
    pub fn check(&self) -> Result<(), MeshError> {
        if self.triangles.is_empty() {
            return Err(MeshError::Empty);
        }
        for (vertex, p) in self.vertices.iter().enumerate() {
            if !(p.x.is_finite() && p.y.is_finite()) {
                return Err(MeshError::NonFinite {
                    vertex,
                    x: p.x,
                    y: p.y,
                });
            }
        }
        let n_vertices = self.vertices.len();
        for (triangle, t) in self.triangles.iter().enumerate() {
            if let Some(&index) = t.iter().find(|&&i| i >= n_vertices) {
                return Err(MeshError::IndexOutOfRange {
                    triangle,
                    index,
                    n_vertices,
                });
            }
            let area = self.signed_area(triangle);
            if area.is_nan() || area <= 0.0 {
                return Err(MeshError::BadOrientation { triangle, area });
            }
        }
        Ok(())
    }

    /// Number of vertices.
    pub fn n_vertices(&self) -> usize {
        self.vertices.len()
    }

    /// Number of triangles.
    pub fn n_triangles(&self) -> usize {
        self.triangles.len()
    }

    /// Signed area of triangle `t`: `½ (b − a) × (c − a)`, positive when counter-clockwise.
    pub fn signed_area(&self, t: usize) -> f64 {
        let [a, b, c] = self.triangles[t].map(|i| self.vertices[i]);
        0.5 * (b - a).cross(c - a)
    }
}
