//! The limit surface sampled on a uniform grid of every ptex face and stitched into one quad
//! mesh: the mesh on which bone-heat weights are solved, the samples of the comparison, and
//! what is rendered and written as `--limit-mesh`.
//!
//! # Grid
//!
//! At level `L` a quad face's ptex square gets the `(2^L + 1)²` parameters
//! `(u, v) = (i, j) / 2^L`, and each sub-face of an n-gon (itself a quarter of the face after
//! one refinement) the `(2^(L−1) + 1)²` parameters `(i, j) / 2^(L−1)`. These are exactly the
//! parameters of the vertices of the `L`-th uniform refinement, so the mesh has the topology
//! of that refinement, every vertex placed on its **limit point** (not at its refined
//! position): the quads of a `LimitMesh` at level `L` are those of
//! [`refine_uniform`](super::refine_uniform)`(cage, L)` (hole faces left out), vertex numbers
//! differ.
//!
//! Grid points shared by neighbouring ptex faces (along cage edges, along the edges between an
//! n-gon's sub-faces, at cage vertices and n-gon centres) are one vertex: they are identified
//! by topology (cage vertex; cage edge and step along it; n-gon, spoke and step), never by
//! position. Each vertex's limit stencil is computed once, from the first ptex face that has
//! it.
//!
//! # Interpolation
//!
//! [`LimitMesh::locate`] finds the grid cell of a surface location and its bilinear weights
//! over the cell's four vertices: how values solved on the mesh (bone-heat weights) are read
//! at quadrature nodes. Bilinear weights are non-negative and sum to one, so interpolated
//! weights keep a partition of unity and their bounds.

use std::collections::HashMap;

use super::cage::{Cage, Point3};
use super::error::SubdivError;
use super::limit::{LimitSurface, SurfaceLocation};
use super::stencil::StencilTable;

/// The deepest level of a [`LimitMesh`]: 6, that is 4 096 quads per cage quad (the mesh of a
/// 1 000-face cage then has 4 million quads).
pub const MAX_LIMIT_MESH_LEVEL: usize = 6;

/// A uniformly sampled limit surface (module documentation).
///
/// ```
/// use splineskin_subdiv::{parse_obj, LimitMesh, LimitOptions, LimitSurface, SurfaceLocation};
///
/// let cube = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
///             f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
/// let cage = parse_obj(cube, "cube.obj")?;
/// let surface = LimitSurface::new(&cage, &LimitOptions::default())?;
/// let mesh = LimitMesh::new(&cage, &surface, 2)?;
/// // The topology of the second uniform refinement of the cube: 96 quads, 98 vertices.
/// assert_eq!((mesh.quads().len(), mesh.n_vertices()), (96, 98));
/// // Every cage vertex is a mesh vertex, at its limit point (1/4, 1/4, 1/4) for vertex 0.
/// let mut p = vec![[0.0; 3]; mesh.n_vertices()];
/// mesh.positions(cage.positions(), &mut p);
/// let v0 = mesh.cage_vertex(0).unwrap();
/// assert!(p[v0 as usize].iter().all(|c| (c - 0.25).abs() < 1e-15));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct LimitMesh {
    level: usize,
    /// First patch of every cage face, `NO_PATCH` for holes.
    face_patch: Vec<u32>,
    /// Grid side (cells per axis) of every patch.
    sides: Vec<u32>,
    /// Offset of every patch's grid in `grid`.
    grid_offsets: Vec<usize>,
    /// Vertex of every grid point, `(side + 1)²` per patch, `v` slower than `u`.
    grid: Vec<u32>,
    quads: Vec<[u32; 4]>,
    locations: Vec<SurfaceLocation>,
    stencils: StencilTable,
    /// Mesh vertex of every cage vertex (`NO_VERTEX` for a vertex only in holes or in no
    /// face).
    of_cage_vertex: Vec<u32>,
}

const NO_PATCH: u32 = u32::MAX;
const NO_VERTEX: u32 = u32::MAX;

/// What a grid point is, topologically (module documentation).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Key {
    /// A cage vertex.
    Vertex(u32),
    /// Step `k` (of `2^L`) along the cage edge from its smaller vertex `a` to `b`.
    Edge(u32, u32, u32),
    /// Step `k` (of `2^(L−1)`) from the midpoint of n-gon `face`'s edge `spoke` towards its
    /// centre (exclusive at both ends).
    Spoke(u32, u32, u32),
    /// The centre of n-gon `face`.
    Centre(u32),
    /// A point inside a ptex face: face, sub-face, `i`, `j`.
    Inside(u32, u32, u32, u32),
}

impl LimitMesh {
    /// Samples `surface` (the limit surface of `cage`) at level `level` (1 ..=
    /// [`MAX_LIMIT_MESH_LEVEL`]).
    pub fn new(cage: &Cage, surface: &LimitSurface, level: usize) -> Result<Self, SubdivError> {
        if level == 0 || level > MAX_LIMIT_MESH_LEVEL {
            return Err(SubdivError::BadLevel {
                level,
                max: MAX_LIMIT_MESH_LEVEL,
            });
        }
        if surface.n_control() != cage.n_vertices() || surface.n_faces() != cage.n_faces() {
            return Err(SubdivError::Internal {
                what: format!(
                    "LimitMesh::new: a surface of {} vertices and {} faces for a cage of {} and {}",
                    surface.n_control(),
                    surface.n_faces(),
                    cage.n_vertices(),
                    cage.n_faces()
                ),
            });
        }
        let full = 1u32 << level;
        let mut ids: HashMap<Key, u32> = HashMap::new();
        let mut locations = Vec::new();
        let mut face_patch = Vec::with_capacity(cage.n_faces());
        let (mut sides, mut grid_offsets, mut grid) = (Vec::new(), Vec::new(), Vec::new());
        let mut quads = Vec::new();
        let mut of_cage_vertex = vec![NO_VERTEX; cage.n_vertices()];
        for face in 0..cage.n_faces() as u32 {
            if surface.is_hole(face) {
                face_patch.push(NO_PATCH);
                continue;
            }
            face_patch.push(sides.len() as u32);
            let fv = cage.face(face as usize);
            let n = fv.len();
            let (n_sub, side) = if n == 4 {
                (1, full)
            } else {
                (n as u32, full / 2)
            };
            for subface in 0..n_sub {
                let offset = grid.len();
                sides.push(side);
                grid_offsets.push(offset);
                for j in 0..=side {
                    for i in 0..=side {
                        let key = grid_key(fv, face, subface, i, j, side, full);
                        let next = locations.len() as u32;
                        let id = *ids.entry(key).or_insert(next);
                        if id == next {
                            locations.push(SurfaceLocation {
                                face,
                                subface,
                                u: f64::from(i) / f64::from(side),
                                v: f64::from(j) / f64::from(side),
                            });
                            if let Key::Vertex(c) = key {
                                of_cage_vertex[c as usize] = id;
                            }
                        }
                        grid.push(id);
                    }
                }
                let w = side as usize + 1;
                let g = |i: usize, j: usize| grid[offset + j * w + i];
                for j in 0..side as usize {
                    for i in 0..side as usize {
                        quads.push([g(i, j), g(i + 1, j), g(i + 1, j + 1), g(i, j + 1)]);
                    }
                }
            }
        }
        let mut stencils = StencilTable::new(cage.n_vertices());
        let mut pairs = Vec::new();
        for st in surface.stencils(&locations)? {
            pairs.clear();
            pairs.extend(st.indices.iter().copied().zip(st.weights.iter().copied()));
            stencils.push(&pairs);
        }
        Ok(LimitMesh {
            level,
            face_patch,
            sides,
            grid_offsets,
            grid,
            quads,
            locations,
            stencils,
            of_cage_vertex,
        })
    }

    /// The level.
    pub fn level(&self) -> usize {
        self.level
    }

    /// Number of vertices.
    pub fn n_vertices(&self) -> usize {
        self.locations.len()
    }

    /// The quads, ptex face by ptex face, each in the orientation of its face (corners at
    /// `(u, v) = (0,0), (1,0), (1,1), (0,1)` of its cell).
    pub fn quads(&self) -> &[[u32; 4]] {
        &self.quads
    }

    /// The surface location of every vertex (one of them where several ptex faces meet).
    pub fn locations(&self) -> &[SurfaceLocation] {
        &self.locations
    }

    /// The limit stencil (position weights over the cage vertices) of every vertex.
    pub fn stencils(&self) -> &StencilTable {
        &self.stencils
    }

    /// The vertex positions for the cage positions `control`, into `out` (`n_vertices` long).
    ///
    /// # Panics
    /// If the lengths do not match.
    pub fn positions(&self, control: &[Point3], out: &mut [Point3]) {
        self.stencils.apply(control, out);
    }

    /// The mesh vertex at cage vertex `v`'s limit point, `None` if `v` is in no non-hole face
    /// (or out of range).
    pub fn cage_vertex(&self, v: u32) -> Option<u32> {
        self.of_cage_vertex
            .get(v as usize)
            .copied()
            .filter(|&m| m != NO_VERTEX)
    }

    /// The four vertices of the grid cell holding `at` and their bilinear weights (module
    /// documentation). Errors for a location on a hole, out of range, or outside `[0, 1]²`.
    pub fn locate(&self, at: SurfaceLocation) -> Result<[(u32, f64); 4], SubdivError> {
        let bad = |what: &str| at.error(what);
        let first = *self
            .face_patch
            .get(at.face as usize)
            .ok_or_else(|| bad("no such face"))?;
        if first == NO_PATCH {
            return Err(SubdivError::InHole { face: at.face });
        }
        let patch = first as usize + at.subface as usize;
        let next_face_first = self.face_patch[at.face as usize + 1..]
            .iter()
            .find(|&&p| p != NO_PATCH)
            .map_or(self.sides.len(), |&p| p as usize);
        if patch >= next_face_first {
            return Err(bad("no such sub-face"));
        }
        if !(0.0..=1.0).contains(&at.u) || !(0.0..=1.0).contains(&at.v) {
            return Err(bad("expected u and v in [0, 1]"));
        }
        let side = self.sides[patch];
        let w = side as usize + 1;
        let cell = |t: f64| {
            let x = t * f64::from(side);
            let i = (x.floor() as u32).min(side - 1);
            (i as usize, x - f64::from(i))
        };
        let (i, s) = cell(at.u);
        let (j, t) = cell(at.v);
        let g = |i: usize, j: usize| self.grid[self.grid_offsets[patch] + j * w + i];
        Ok([
            (g(i, j), (1.0 - s) * (1.0 - t)),
            (g(i + 1, j), s * (1.0 - t)),
            (g(i + 1, j + 1), s * t),
            (g(i, j + 1), (1.0 - s) * t),
        ])
    }

    /// The mesh as a cage of its own (quads, no tags) at `positions` (`n_vertices` long): for
    /// writing the limit surface as OBJ.
    pub fn to_cage(&self, positions: Vec<Point3>) -> Result<Cage, super::cage::CageError> {
        Cage::new(
            positions,
            self.quads.iter().map(|q| q.to_vec()).collect(),
            Default::default(),
        )
    }

    /// The triangles of the mesh, each quad split along its shorter diagonal at `positions`
    /// (`2 · quads().len()`, counter-clockwise in the quads' orientation).
    pub fn triangles(&self, positions: &[Point3]) -> Vec<[u32; 3]> {
        let mut out = Vec::with_capacity(2 * self.quads.len());
        for q in &self.quads {
            let p = |k: usize| positions[q[k] as usize];
            let d02 = super::affine3::distance2(p(0), p(2));
            let d13 = super::affine3::distance2(p(1), p(3));
            if d02 <= d13 {
                out.push([q[0], q[1], q[2]]);
                out.push([q[0], q[2], q[3]]);
            } else {
                out.push([q[0], q[1], q[3]]);
                out.push([q[1], q[2], q[3]]);
            }
        }
        out
    }
}

/// The key of grid point `(i, j)` of sub-face `subface` (grid side `side`) of face `face`
/// with vertices `fv`; `full = 2^L` steps along a cage edge.
fn grid_key(fv: &[u32], face: u32, subface: u32, i: u32, j: u32, side: u32, full: u32) -> Key {
    let n = fv.len();
    // Step `k` of `full` along the cage edge from `a` to `b`.
    let edge = |a: u32, b: u32, k: u32| {
        if k == 0 {
            Key::Vertex(a)
        } else if k == full {
            Key::Vertex(b)
        } else if a < b {
            Key::Edge(a, b, k)
        } else {
            Key::Edge(b, a, full - k)
        }
    };
    if n == 4 {
        let m = side;
        return match (i, j) {
            (_, 0) => edge(fv[0], fv[1], i),
            (_, j) if j == m => edge(fv[3], fv[2], i),
            (0, _) => edge(fv[0], fv[3], j),
            (i, _) if i == m => edge(fv[1], fv[2], j),
            _ => Key::Inside(face, 0, i, j),
        };
    }
    let s = subface as usize;
    let (here, next, prev) = (fv[s], fv[(s + 1) % n], fv[(s + n - 1) % n]);
    let m = side;
    // The spoke from the midpoint of face edge `e` (from vertex e to e + 1) towards the
    // centre, step `k` of `m`.
    let spoke = |e: usize, k: u32| {
        if k == 0 {
            edge(fv[e], fv[(e + 1) % n], m)
        } else if k == m {
            Key::Centre(face)
        } else {
            Key::Spoke(face, e as u32, k)
        }
    };
    match (i, j) {
        // v = 0: from this vertex towards the next, half the edge.
        (_, 0) => edge(here, next, i),
        // u = 0: from this vertex towards the previous one.
        (0, _) => edge(here, prev, j),
        // u = 1: the spoke of edge (s, s + 1), from its midpoint (v = 0) to the centre.
        (i, _) if i == m => spoke(s, j),
        // v = 1: the spoke of edge (s − 1, s), from its midpoint (u = 0) to the centre.
        (_, j) if j == m => spoke((s + n - 1) % n, i),
        _ => Key::Inside(face, subface, i, j),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{parse_obj, refine_uniform, LimitOptions};

    /// A quad, a triangle and a pentagon sharing edges.
    const MIXED: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0.5 0\nv -0.5 1.5 0.3\nv 0.5 2 0.1\nv -0.6 0.6 0.2\n\
                         f 1 2 3 4\nf 2 5 3\nf 4 3 7 6 8\n";

    const CUBE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
                        f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

    #[test]
    fn limit_mesh_has_the_uniform_refinement_topology() {
        for (text, name) in [(MIXED, "mixed"), (CUBE, "cube")] {
            let cage = parse_obj(text, name).unwrap();
            let surface = LimitSurface::new(&cage, &LimitOptions::default()).unwrap();
            for level in 1..=3 {
                let mesh = LimitMesh::new(&cage, &surface, level).unwrap();
                let refined = refine_uniform(&cage, level).unwrap();
                let last = &refined.levels()[level - 1];
                assert_eq!(mesh.quads().len(), last.faces().len(), "{name} {level}");
                assert_eq!(mesh.n_vertices(), last.n_vertices(), "{name} {level}");
                // Every mesh vertex sits at the limit of a refined vertex: the refined cage's
                // vertex limit points, as a set, are the mesh positions.
                let mut p = vec![[0.0; 3]; mesh.n_vertices()];
                mesh.positions(cage.positions(), &mut p);
                let level_cage = last.to_cage().unwrap();
                let fine = LimitSurface::new(&level_cage, &LimitOptions::default()).unwrap();
                for v in 0..level_cage.n_vertices() as u32 {
                    let q = fine
                        .vertex_limit(v)
                        .unwrap()
                        .position(level_cage.positions());
                    let nearest = p
                        .iter()
                        .map(|x| crate::affine3::distance2(*x, q))
                        .fold(f64::INFINITY, f64::min);
                    assert!(
                        nearest < 1e-20,
                        "{name} level {level} vertex {v}: {nearest}"
                    );
                }
            }
        }
    }

    #[test]
    fn limit_mesh_locate_interpolates_the_grid() {
        let cage = parse_obj(MIXED, "mixed").unwrap();
        let surface = LimitSurface::new(&cage, &LimitOptions::default()).unwrap();
        let mesh = LimitMesh::new(&cage, &surface, 2).unwrap();
        let mut p = vec![[0.0; 3]; mesh.n_vertices()];
        mesh.positions(cage.positions(), &mut p);
        // At a grid parameter the cell's corner carries all the weight, and it is the vertex
        // with that location.
        for (v, at) in mesh.locations().iter().enumerate() {
            let w = mesh.locate(*at).unwrap();
            let sum: f64 = w.iter().map(|x| x.1).sum();
            assert!((sum - 1.0).abs() < 1e-15);
            let hit = w.iter().find(|x| x.1 == 1.0).unwrap();
            let d = crate::affine3::distance2(p[hit.0 as usize], p[v]);
            assert!(d < 1e-28, "vertex {v} at {at:?}");
        }
        assert!(mesh
            .locate(SurfaceLocation {
                face: 1,
                subface: 3,
                u: 0.5,
                v: 0.5
            })
            .is_err());
    }
}
