//! Uniform refinement: every face split, level after level, with each refined vertex as an
//! `f64` stencil over the cage vertices (OpenSubdiv's `RefineUniform` +
//! `StencilTableFactory`).

use super::cage::{Cage, CageError, CornerTag, CreaseTag, Point3, SubdivTags};
use super::error::SubdivError;
use super::hierarchy::{Hierarchy, Refine};
use super::masks::{self, Origin, Weights};
use super::stencil::StencilTable;

/// The deepest uniform level [`refine_uniform`] builds: the face count grows 4× per level, so
/// level 8 of a 1 000-face cage is already 65 million quads.
pub const MAX_UNIFORM_LEVEL: usize = 8;

/// One level of a uniform refinement.
///
/// Vertex numbering (as OpenSubdiv's reference numbering): first the children of the previous
/// level's vertices in their order — so cage vertex `i` is vertex `i` at every level — then one
/// face point per previous-level face, then one edge point per previous-level edge (edges in
/// `opensubdiv-rs`'s order: first occurrence along the faces for the cage). All faces are quads;
/// faces appear grouped by parent face, in parent order.
#[derive(Clone, Debug)]
pub struct UniformLevel {
    level: usize,
    faces: Vec<[u32; 4]>,
    parent_faces: Vec<u32>,
    parent_edges: Vec<[u32; 2]>,
    holes: Vec<u32>,
    tags: SubdivTags,
    stencils: StencilTable,
    positions: Vec<Point3>,
}

impl UniformLevel {
    /// The level, 1 for the first refinement.
    pub fn level(&self) -> usize {
        self.level
    }

    /// Number of vertices.
    pub fn n_vertices(&self) -> usize {
        self.positions.len()
    }

    /// The quads, vertex indices of this level.
    pub fn faces(&self) -> &[[u32; 4]] {
        &self.faces
    }

    /// For every face, its parent face in the previous level.
    pub fn parent_faces(&self) -> &[u32] {
        &self.parent_faces
    }

    /// The previous level's edges (as vertex pairs of the previous level), in the order of
    /// their edge points: edge point `n_prev_vertices + n_prev_faces + e` belongs to
    /// `parent_edges()[e]`.
    pub fn parent_edges(&self) -> &[[u32; 2]] {
        &self.parent_edges
    }

    /// The faces that are holes (children of holes), increasing.
    pub fn holes(&self) -> &[u32] {
        &self.holes
    }

    /// The subdivision tags of this level as a cage of its own: the decayed sharpness of every
    /// sharp edge with two faces (boundary and non-manifold edges are sharp by rule) and of
    /// every sharp vertex, the hole faces, and the cage's kept option tags.
    pub fn tags(&self) -> &SubdivTags {
        &self.tags
    }

    /// This level as a cage of its own: positions, quads and [`UniformLevel::tags`]. Its limit
    /// surface is the original cage's (the rules at every later level depend only on the
    /// current level's topology and sharpness): what "refine a cage" means.
    ///
    /// ```
    /// use splineskin_subdiv::{parse_obj, refine_uniform};
    ///
    /// // Two quads with a crease of sharpness 2.5 on their shared edge (vertices 1 and 4).
    /// let text = "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\n\
    ///             f 1 2 5 4\nf 2 3 6 5\nt crease 2/1/0 1 4 2.5\n";
    /// let cage = parse_obj(text, "strip.obj")?;
    /// let level1 = refine_uniform(&cage, 1)?.levels()[0].to_cage()?;
    /// assert_eq!((level1.n_vertices(), level1.n_faces()), (15, 8));
    /// // The crease's two halves keep sharpness 2.5 − 1; the four boundary corners are
    /// // infinitely sharp corners (VTX_BOUNDARY_EDGE_AND_CORNER).
    /// let creases = &level1.tags().creases;
    /// assert_eq!(creases.len(), 2);
    /// assert!(creases.iter().all(|c| c.sharpness == 1.5));
    /// assert_eq!(level1.tags().corners.len(), 4);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn to_cage(&self) -> Result<Cage, CageError> {
        Cage::new(
            self.positions.clone(),
            self.faces.iter().map(|f| f.to_vec()).collect(),
            self.tags.clone(),
        )
    }

    /// Every vertex as a stencil over the cage vertices.
    pub fn stencils(&self) -> &StencilTable {
        &self.stencils
    }

    /// Vertex positions for the cage the refinement was built from (its stencils applied to
    /// the cage positions).
    pub fn positions(&self) -> &[Point3] {
        &self.positions
    }
}

/// A uniform refinement of a cage, levels `1..=n`.
#[derive(Clone, Debug)]
pub struct UniformRefinement {
    levels: Vec<UniformLevel>,
}

impl UniformRefinement {
    /// The refined levels, `levels()[k]` being level `k + 1`.
    pub fn levels(&self) -> &[UniformLevel] {
        &self.levels
    }
}

/// Refines `cage` uniformly `n_levels` times (1 ..= [`MAX_UNIFORM_LEVEL`]).
///
/// ```
/// use splineskin_subdiv::{parse_obj, refine_uniform};
///
/// // A triangle becomes three quads with a centroid face point.
/// let cage = parse_obj("v 0 0 0\nv 3 0 0\nv 0 3 0\nf 1 2 3\n", "tri.obj")?;
/// let refined = refine_uniform(&cage, 2)?;
/// let level1 = &refined.levels()[0];
/// assert_eq!(level1.faces().len(), 3);
/// assert_eq!(level1.positions()[3], [1.0, 1.0, 0.0]);
/// // Corners of a single face are pinned (VTX_BOUNDARY_EDGE_AND_CORNER).
/// assert_eq!(refined.levels()[1].positions()[1], [3.0, 0.0, 0.0]);
/// assert_eq!(refined.levels()[1].faces().len(), 12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn refine_uniform(cage: &Cage, n_levels: usize) -> Result<UniformRefinement, SubdivError> {
    if n_levels == 0 || n_levels > MAX_UNIFORM_LEVEL {
        return Err(SubdivError::BadLevel {
            level: n_levels,
            max: MAX_UNIFORM_LEVEL,
        });
    }
    let h = Hierarchy::new(cage, Refine::Uniform(n_levels))?;
    let n_base = cage.n_vertices();
    // ours[crate index] at the current level; identity on the cage. Vertices used by no face
    // have no child in opensubdiv-rs (OpenSubdiv keeps them, unchanged): ours keeps them too,
    // so the numbering has `n_ours` vertices and some have no crate counterpart.
    let mut ours: Vec<u32> = (0..n_base as u32).collect();
    let mut n_ours = n_base;
    // The previous level's stencils in our numbering.
    let mut prev = StencilTable::new(n_base);
    for v in 0..n_base as u32 {
        prev.push(&[(v, 1.0)]);
    }
    let mut acc = vec![0.0f64; n_base];
    let mut touched: Vec<u32> = Vec::new();
    let mut mask = Weights::new();
    let mut levels = Vec::with_capacity(n_levels);
    for l in 1..=n_levels {
        let parent = h.level(l - 1);
        let child = h.level(l);
        let refinement = h.refiner.refinement(l);
        let (nv, nf) = (n_ours as u32, parent.num_faces() as u32);
        let child_ours: Vec<u32> = (0..child.num_vertices() as u32)
            .map(|c| match h.origin(l, c) {
                Origin::Vertex(v) => ours[v as usize],
                Origin::Face(f) => nv + f,
                Origin::Edge(e) => nv + nf + e,
            })
            .collect();
        let n_child_ours = n_ours + parent.num_faces() + parent.num_edges();
        // The crate vertex of each of ours, or None for a vertex without faces.
        let mut by_ours: Vec<Option<u32>> = vec![None; n_child_ours];
        for (c, &o) in child_ours.iter().enumerate() {
            by_ours[o as usize] = Some(c as u32);
        }
        let mut table = StencilTable::new(n_base);
        let mut stencil = Weights::new();
        for (o, &c) in by_ours.iter().enumerate() {
            let Some(c) = c else {
                if o >= n_ours {
                    return Err(SubdivError::Internal {
                        what: format!("uniform level {l}: vertex numbering has a gap at {o}"),
                    });
                }
                // A vertex without faces stays where it is.
                let (idx, w) = prev.stencil(o);
                stencil.clear();
                stencil.extend(idx.iter().copied().zip(w.iter().copied()));
                table.push(&stencil);
                continue;
            };
            masks::child_mask(&h.crease, parent, refinement, h.origin(l, c), &mut mask);
            for &(p, w) in &mask {
                let (idx, pw) = prev.stencil(ours[p as usize] as usize);
                for (&i, &x) in idx.iter().zip(pw) {
                    if acc[i as usize] == 0.0 {
                        touched.push(i);
                    }
                    acc[i as usize] += w * x;
                }
            }
            touched.sort_unstable();
            touched.dedup();
            stencil.clear();
            for &i in &touched {
                if acc[i as usize] != 0.0 {
                    stencil.push((i, acc[i as usize]));
                }
                acc[i as usize] = 0.0;
            }
            touched.clear();
            table.push(&stencil);
        }
        let faces = (0..child.num_faces())
            .map(|f| {
                let fv = child.face_vertices(f);
                if fv.len() != 4 {
                    return Err(SubdivError::Internal {
                        what: format!("uniform level {l}: face {f} is not a quad"),
                    });
                }
                Ok([0, 1, 2, 3].map(|k| child_ours[fv[k] as usize]))
            })
            .collect::<Result<Vec<_>, _>>()?;
        let parent_faces = (0..child.num_faces())
            .map(|f| refinement.child_face_parent_face(f))
            .collect();
        let parent_edges = (0..parent.num_edges())
            .map(|e| parent.edge_vertices(e).map(|v| ours[v as usize]))
            .collect();
        let mut tags = SubdivTags {
            other: cage.tags().other.clone(),
            ..Default::default()
        };
        for e in 0..child.num_edges() {
            let s = child.edge_sharpness(e);
            if s > 0.0 && child.edge_faces(e).len() == 2 {
                tags.creases.push(CreaseTag {
                    vertices: child.edge_vertices(e).map(|v| child_ours[v as usize]),
                    sharpness: f64::from(s),
                });
            }
        }
        for v in 0..child.num_vertices() {
            let s = child.vertex_sharpness(v);
            if s > 0.0 {
                tags.corners.push(CornerTag {
                    vertex: child_ours[v],
                    sharpness: f64::from(s),
                });
            }
        }
        let holes: Vec<u32> = (0..child.num_faces() as u32)
            .filter(|&f| child.is_face_hole(f as usize))
            .collect();
        let mut positions = vec![[0.0; 3]; table.n_stencils()];
        table.apply(cage.positions(), &mut positions);
        levels.push(UniformLevel {
            level: l,
            faces,
            parent_faces,
            parent_edges,
            tags: SubdivTags {
                holes: holes.clone(),
                ..tags
            },
            holes,
            stencils: table.clone(),
            positions,
        });
        prev = table;
        ours = child_ours;
        n_ours = n_child_ours;
    }
    Ok(UniformRefinement { levels })
}
