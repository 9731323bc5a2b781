//! Triangle meshes of a planar domain, the support of the mesh-based weight families
//! (harmonic, biharmonic, bounded biharmonic; DESIGN.md §2).
//!
//! A [`TriMesh`] is an indexed triangle list in the drawing's coordinates. Triangles are
//! counter-clockwise (positive signed area) — every constructor and reader checks it.
//!
//! [`operators`] builds the discrete operators on a mesh: the cotangent Laplacian (of both
//! dimensions in [`cotangent`]), the lumped mass matrices and the polyharmonic energies the
//! weight families minimise.

pub mod cotangent;
pub mod crouzeix_raviart;
pub mod operators;
pub mod vec3;

use std::collections::HashMap;

use kurbo::Point;

use crate::union_find;

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
    /// An edge is used twice in the same direction (two triangles that overlap or disagree
    /// on orientation) or by more than two triangles.
    #[error("edge ({from}, {to}): used by more than one triangle in the same direction (triangles {first} and {second}); expected a manifold, consistently oriented mesh")]
    NonManifoldEdge {
        /// First vertex of the directed edge.
        from: usize,
        /// Second vertex of the directed edge.
        to: usize,
        /// A triangle holding the directed edge.
        first: usize,
        /// Another triangle holding it.
        second: usize,
    },
    /// Boundary edges do not form simple closed loops (a vertex where the boundary pinches:
    /// two boundary edges leave it).
    #[error("vertex {vertex}: {count} boundary edges leave it (expected one: the boundary pinches there)")]
    NonManifoldVertex {
        /// The vertex.
        vertex: usize,
        /// Number of outgoing boundary edges.
        count: usize,
    },
}

impl TriMesh {
    /// Builds a mesh and checks it: indices in range, finite coordinates, every triangle
    /// counter-clockwise with positive area.
    ///
    /// ```
    /// use kurbo::Point;
    /// use splineskin_core::mesh::TriMesh;
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

    /// A regular grid of `nx × ny` cells over `rect`, each cell cut into two triangles along
    /// alternating diagonals (so no direction is favoured): `(nx + 1)(ny + 1)` vertices, row by
    /// row from `(rect.x0, rect.y0)`, and `2 nx ny` counter-clockwise triangles. For tests and
    /// benchmarks. Errors if a count is zero or `rect` has no area.
    ///
    /// ```
    /// use kurbo::Rect;
    /// use splineskin_core::mesh::TriMesh;
    /// let mesh = TriMesh::grid(Rect::new(0., 0., 2., 1.), 4, 2)?;
    /// assert_eq!((mesh.n_vertices(), mesh.n_triangles()), (15, 16));
    /// assert!((mesh.total_area() - 2.0).abs() < 1e-15);
    /// # Ok::<(), splineskin_core::mesh::MeshError>(())
    /// ```
    pub fn grid(rect: kurbo::Rect, nx: usize, ny: usize) -> Result<TriMesh, MeshError> {
        let id = |x: usize, y: usize| y * (nx + 1) + x;
        let mut vertices = Vec::with_capacity((nx + 1) * (ny + 1));
        for y in 0..=ny {
            for x in 0..=nx {
                vertices.push(Point::new(
                    rect.x0 + rect.width() * x as f64 / nx as f64,
                    rect.y0 + rect.height() * y as f64 / ny as f64,
                ));
            }
        }
        let mut triangles = Vec::with_capacity(2 * nx * ny);
        for y in 0..ny {
            for x in 0..nx {
                let (a, b, c, d) = (id(x, y), id(x + 1, y), id(x + 1, y + 1), id(x, y + 1));
                if (x + y) % 2 == 0 {
                    triangles.extend([[a, b, c], [a, c, d]]);
                } else {
                    triangles.extend([[a, b, d], [b, c, d]]);
                }
            }
        }
        TriMesh::new(vertices, triangles)
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

    /// Sum of the triangles' areas.
    ///
    /// ```
    /// use kurbo::Point;
    /// use splineskin_core::mesh::TriMesh;
    /// let v = vec![Point::new(0., 0.), Point::new(2., 0.), Point::new(2., 1.), Point::new(0., 1.)];
    /// let mesh = TriMesh::new(v, vec![[0, 1, 2], [0, 2, 3]])?;
    /// assert_eq!(mesh.total_area(), 2.0);
    /// # Ok::<(), splineskin_core::mesh::MeshError>(())
    /// ```
    pub fn total_area(&self) -> f64 {
        (0..self.n_triangles()).map(|t| self.signed_area(t)).sum()
    }

    /// The length of the diagonal of the vertices' bounding box (0 for one vertex or none):
    /// the length unit of tolerances and errors on a mesh.
    ///
    /// ```
    /// use kurbo::{Point, Rect};
    /// use splineskin_core::mesh::TriMesh;
    /// let mesh = TriMesh::grid(Rect::new(0., 0., 4., 3.), 4, 3)?;
    /// assert_eq!(mesh.bounding_box_diagonal(), 5.0);
    /// # Ok::<(), splineskin_core::mesh::MeshError>(())
    /// ```
    pub fn bounding_box_diagonal(&self) -> f64 {
        if self.vertices.is_empty() {
            return 0.0;
        }
        let mut lo = Point::new(f64::INFINITY, f64::INFINITY);
        let mut hi = Point::new(f64::NEG_INFINITY, f64::NEG_INFINITY);
        for p in &self.vertices {
            lo = Point::new(lo.x.min(p.x), lo.y.min(p.y));
            hi = Point::new(hi.x.max(p.x), hi.y.max(p.y));
        }
        (hi - lo).hypot()
    }

    /// Whether each vertex belongs to at least one triangle (length [`TriMesh::n_vertices`]).
    /// A vertex in no triangle has no neighbourhood: every mesh operator is zero on it.
    pub fn referenced_vertices(&self) -> Vec<bool> {
        let mut used = vec![false; self.n_vertices()];
        for t in &self.triangles {
            for &i in t {
                used[i] = true;
            }
        }
        used
    }

    /// The connected component of each vertex, through shared triangle edges and corners
    /// (length [`TriMesh::n_vertices`]); components are numbered from 0 in the order of
    /// their smallest vertex. A vertex in no triangle is a component of its own.
    ///
    /// ```
    /// use kurbo::Point;
    /// use splineskin_core::mesh::TriMesh;
    /// let v = vec![Point::new(0., 0.), Point::new(1., 0.), Point::new(0., 1.),
    ///              Point::new(5., 5.), Point::new(6., 5.), Point::new(5., 6.)];
    /// let mesh = TriMesh::new(v, vec![[0, 1, 2], [3, 4, 5]])?;
    /// assert_eq!(mesh.components(), vec![0, 0, 0, 1, 1, 1]);
    /// # Ok::<(), splineskin_core::mesh::MeshError>(())
    /// ```
    pub fn components(&self) -> Vec<usize> {
        // Union–find over the triangles' corners.
        let mut parent = union_find::singletons(self.n_vertices());
        for t in &self.triangles {
            for k in 1..3 {
                union_find::union(&mut parent, t[0], t[k]);
            }
        }
        union_find::labels(&mut parent).0
    }

    /// The boundary edges, each directed as its triangle traverses it (so the domain lies to
    /// the left: outer boundaries run counter-clockwise, holes clockwise), in the order of
    /// their triangles. An edge is on the boundary when exactly one triangle uses it.
    ///
    /// Errors when a directed edge is used twice (overlapping or inconsistently oriented
    /// triangles, or an edge shared by more than two triangles).
    ///
    /// ```
    /// use kurbo::Point;
    /// use splineskin_core::mesh::TriMesh;
    /// let v = vec![Point::new(0., 0.), Point::new(1., 0.), Point::new(1., 1.), Point::new(0., 1.)];
    /// let mesh = TriMesh::new(v, vec![[0, 1, 2], [0, 2, 3]])?;
    /// assert_eq!(mesh.boundary_edges()?, vec![[0, 1], [1, 2], [2, 3], [3, 0]]);
    /// # Ok::<(), splineskin_core::mesh::MeshError>(())
    /// ```
    pub fn boundary_edges(&self) -> Result<Vec<[usize; 2]>, MeshError> {
        let mut directed: HashMap<(usize, usize), usize> =
            HashMap::with_capacity(3 * self.n_triangles());
        for (t, tri) in self.triangles.iter().enumerate() {
            for k in 0..3 {
                let (from, to) = (tri[k], tri[(k + 1) % 3]);
                if let Some(&first) = directed.get(&(from, to)) {
                    return Err(MeshError::NonManifoldEdge {
                        from,
                        to,
                        first,
                        second: t,
                    });
                }
                directed.insert((from, to), t);
            }
        }
        let mut edges = Vec::new();
        for tri in &self.triangles {
            for k in 0..3 {
                let (from, to) = (tri[k], tri[(k + 1) % 3]);
                if !directed.contains_key(&(to, from)) {
                    edges.push([from, to]);
                }
            }
        }
        Ok(edges)
    }

    /// The boundary as closed loops of vertex indices, each following
    /// [`TriMesh::boundary_edges`]' direction (domain on the left) and starting at its
    /// smallest vertex; loops are sorted by their first vertex. A mesh without boundary (none
    /// in the plane, but possible for a hand-made index list) gives no loops.
    ///
    /// Errors as [`TriMesh::boundary_edges`] does, and when the boundary pinches (a vertex
    /// with two outgoing boundary edges, where loops would be ambiguous).
    ///
    /// ```
    /// use kurbo::Point;
    /// use splineskin_core::mesh::TriMesh;
    /// let v = vec![Point::new(0., 0.), Point::new(1., 0.), Point::new(1., 1.), Point::new(0., 1.)];
    /// let mesh = TriMesh::new(v, vec![[1, 2, 0], [2, 3, 0]])?;
    /// assert_eq!(mesh.boundary_loops()?, vec![vec![0, 1, 2, 3]]);
    /// # Ok::<(), splineskin_core::mesh::MeshError>(())
    /// ```
    pub fn boundary_loops(&self) -> Result<Vec<Vec<usize>>, MeshError> {
        let edges = self.boundary_edges()?;
        let mut next = vec![usize::MAX; self.n_vertices()];
        for &[from, to] in &edges {
            if next[from] != usize::MAX {
                let count = edges.iter().filter(|e| e[0] == from).count();
                return Err(MeshError::NonManifoldVertex {
                    vertex: from,
                    count,
                });
            }
            next[from] = to;
        }
        // Every boundary vertex has one outgoing and (counting edges) one incoming edge, so
        // following `next` from any of them returns to it.
        let mut starts: Vec<usize> = edges.iter().map(|e| e[0]).collect();
        starts.sort_unstable();
        let mut seen = vec![false; self.n_vertices()];
        let mut loops = Vec::new();
        for s in starts {
            if seen[s] {
                continue;
            }
            let mut lp = Vec::new();
            let mut v = s;
            while !seen[v] {
                seen[v] = true;
                lp.push(v);
                v = next[v];
            }
            loops.push(lp);
        }
        Ok(loops)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support::pts;
    use kurbo::Rect;

    /// A 3 × 3 grid with its centre cell removed: one outer loop and one hole.
    fn ring() -> TriMesh {
        let mut mesh = TriMesh::grid(Rect::new(0.0, 0.0, 3.0, 3.0), 3, 3).unwrap();
        // Cell (1, 1) is triangles 8 and 9 (two per cell, row by row).
        mesh.triangles.drain(8..10);
        mesh
    }

    #[test]
    fn boundary_loops_of_a_ring_run_outer_ccw_and_hole_cw() {
        let mesh = ring();
        let loops = mesh.boundary_loops().unwrap();
        assert_eq!(loops.len(), 2);
        // Vertices are row-major, 4 per row: the outer loop starts at 0 and runs along y = 0.
        assert_eq!(loops[0], vec![0, 1, 2, 3, 7, 11, 15, 14, 13, 12, 8, 4]);
        // The hole (vertices 5, 6, 10, 9) runs clockwise: the domain is on its left.
        assert_eq!(loops[1], vec![5, 9, 10, 6]);
        let signed_area = |lp: &[usize]| -> f64 {
            (0..lp.len())
                .map(|k| {
                    let (a, b) = (mesh.vertices[lp[k]], mesh.vertices[lp[(k + 1) % lp.len()]]);
                    0.5 * (a.x * b.y - b.x * a.y)
                })
                .sum()
        };
        assert_eq!(signed_area(&loops[0]), 9.0);
        assert_eq!(signed_area(&loops[1]), -1.0);
        assert_eq!(mesh.total_area(), 8.0);
    }

    #[test]
    fn boundary_edges_reject_overlaps_and_pinches() {
        let v = pts(&[(0., 0.), (1., 0.), (0., 1.), (-1., 0.), (0., -1.)]);
        // The same triangle twice: its edges are used twice in the same direction.
        let twice = TriMesh::new(v.clone(), vec![[0, 1, 2], [1, 2, 0]]).unwrap();
        assert_eq!(
            twice.boundary_edges(),
            Err(MeshError::NonManifoldEdge {
                from: 1,
                to: 2,
                first: 0,
                second: 1
            })
        );
        // Two triangles sharing only vertex 0: the boundary pinches there.
        let bowtie = TriMesh::new(v, vec![[0, 1, 2], [0, 3, 4]]).unwrap();
        assert_eq!(bowtie.boundary_edges().unwrap().len(), 6);
        assert_eq!(
            bowtie.boundary_loops(),
            Err(MeshError::NonManifoldVertex {
                vertex: 0,
                count: 2
            })
        );
        assert_eq!(bowtie.components(), vec![0, 0, 0, 0, 0]);
    }

    #[test]
    fn grid_rejects_empty_and_inverted_rectangles() {
        assert_eq!(
            TriMesh::grid(Rect::new(0., 0., 1., 1.), 0, 3),
            Err(MeshError::Empty)
        );
        assert!(matches!(
            TriMesh::grid(Rect::new(1., 0., 0., 1.), 2, 2),
            Err(MeshError::BadOrientation { triangle: 0, .. })
        ));
        let mesh = TriMesh::grid(Rect::new(0., 0., 2., 1.), 4, 2).unwrap();
        assert!(mesh.referenced_vertices().iter().all(|&r| r));
        assert!(mesh.components().iter().all(|&c| c == 0));
    }
}
