//! The control mesh ("cage") of a Catmull–Clark surface: positions, polygons of any size, and
//! OpenSubdiv's subdivision tags (creases, corners, holes).

use std::collections::HashMap;

/// A point or vector in 3D, `[x, y, z]`.
pub type Point3 = [f64; 3];

/// The sharpness OpenSubdiv treats as infinite (`Sdc::Crease::SHARPNESS_INFINITE`): a crease
/// or corner tag with this sharpness or more never softens under refinement. Unitless.
pub const SHARPNESS_INFINITE: f64 = 10.0;

/// A crease tag: the edge between two vertices gets a sharpness.
///
/// Sharpness `s` is unitless: `0` is smooth, `s ≥` [`SHARPNESS_INFINITE`] is an infinitely
/// sharp crease, and in between the edge follows the crease rule for `⌊s⌋` refinement levels
/// and blends the crease and smooth rules by the fractional part at the next (OpenSubdiv's
/// `CREASE_UNIFORM`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CreaseTag {
    /// The edge's end vertices (0-based), in the order they were given.
    pub vertices: [u32; 2],
    /// The sharpness, `≥ 0`.
    pub sharpness: f64,
}

/// A corner tag: a vertex gets a vertex sharpness (`≥` [`SHARPNESS_INFINITE`]: it never
/// moves under refinement).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CornerTag {
    /// The vertex (0-based).
    pub vertex: u32,
    /// The sharpness, `≥ 0`.
    pub sharpness: f64,
}

/// A subdivision tag that is kept but not applied: scheme options such as
/// `interpolateboundary`, `creasemethod`, `smoothtriangles`, and OpenSubdiv 2's hierarchical
/// edits. The refinement always uses the options documented in [`crate`]; these are
/// carried so that export writes them back unchanged.
#[derive(Clone, Debug, PartialEq)]
pub struct OtherTag {
    /// The tag's name (`interpolateboundary`, `vertexedit`, …).
    pub name: String,
    /// Its integer arguments.
    pub ints: Vec<i64>,
    /// Its float arguments.
    pub floats: Vec<f64>,
    /// Its string arguments.
    pub strings: Vec<String>,
}

/// The subdivision tags of a cage.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SubdivTags {
    /// Edge sharpness tags, in file order.
    pub creases: Vec<CreaseTag>,
    /// Vertex sharpness tags, in file order.
    pub corners: Vec<CornerTag>,
    /// Faces that are holes: they are refined and influence their neighbours, but have no
    /// limit surface. In file order.
    pub holes: Vec<u32>,
    /// Tags kept for export but not applied, in file order.
    pub other: Vec<OtherTag>,
}

/// A Catmull–Clark control mesh: vertex positions, faces as vertex loops, and tags.
///
/// Faces have at least 3 distinct vertices; a face's vertex order is its orientation.
/// Accepted, as OpenSubdiv accepts them: boundaries, holes, polygons of any size, vertices used
/// by no face, non-manifold edges — shared by more than two faces, or by two faces that run
/// along it in the same direction (inconsistent orientation, listed by
/// [`Cage::inconsistent_edges`]) — and vertices where separate fans of faces meet. As in
/// OpenSubdiv, non-manifold edges are infinitely sharp and non-manifold vertices infinitely
/// sharp corners, unless on a crease of exactly two non-manifold edges. Refused
/// ([`CageError`]): a vertex repeated within a face (OpenSubdiv accepts such degenerate faces;
/// the `opensubdiv-rs` refiner used here does not).
///
/// ```
/// use splineskin_subdiv::{Cage, SubdivTags};
///
/// let positions = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
/// let cage = Cage::new(positions, vec![vec![0, 1, 2, 3]], SubdivTags::default())?;
/// assert_eq!((cage.n_vertices(), cage.n_faces()), (4, 1));
/// assert_eq!(cage.face(0), &[0, 1, 2, 3]);
/// # Ok::<(), splineskin_subdiv::CageError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Cage {
    positions: Vec<Point3>,
    face_offsets: Vec<usize>,
    face_vertices: Vec<u32>,
    tags: SubdivTags,
}

/// Why a set of positions, faces and tags is not a valid [`Cage`]. Elements are named by their
/// 0-based index.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum CageError {
    /// The cage has no face.
    #[error("the cage has no face; expected at least one polygon")]
    NoFaces,
    /// A coordinate is NaN or infinite.
    #[error("vertex {vertex}: coordinate {value} is not finite")]
    NonFiniteCoordinate {
        /// The vertex.
        vertex: usize,
        /// The offending coordinate.
        value: f64,
    },
    /// A face has fewer than three vertices.
    #[error("face {face}: {size} vertices; expected at least 3")]
    FaceTooSmall {
        /// The face.
        face: usize,
        /// Its number of vertices.
        size: usize,
    },
    /// A face refers to a vertex that does not exist.
    #[error("face {face}: vertex {vertex} out of range; expected < {n_vertices}")]
    VertexOutOfRange {
        /// The face.
        face: usize,
        /// The offending vertex index.
        vertex: u32,
        /// Number of vertices.
        n_vertices: usize,
    },
    /// A face uses a vertex twice.
    #[error("face {face}: vertex {vertex} appears twice; expected distinct vertices (degenerate faces are not supported)")]
    RepeatedVertex {
        /// The face.
        face: usize,
        /// The repeated vertex.
        vertex: u32,
    },
    /// New positions for a cage do not match its vertex count.
    #[error("{found} positions for a cage of {expected} vertices")]
    PositionCount {
        /// The cage's number of vertices.
        expected: usize,
        /// The number of positions given.
        found: usize,
    },
    /// A tag refers to a vertex or face that does not exist, or a crease to a vertex pair
    /// that is no edge of the cage.
    #[error("{tag} tag {index}: {what}")]
    BadTag {
        /// `crease`, `corner` or `hole`.
        tag: &'static str,
        /// The tag's position in its list ([`SubdivTags::creases`], …).
        index: usize,
        /// What is wrong and what was expected.
        what: String,
    },
}

impl Cage {
    /// Builds a cage, checking everything [`CageError`] lists.
    pub fn new(
        positions: Vec<Point3>,
        faces: Vec<Vec<u32>>,
        tags: SubdivTags,
    ) -> Result<Self, CageError> {
        let mut face_offsets = Vec::with_capacity(faces.len() + 1);
        face_offsets.push(0);
        let mut face_vertices = Vec::with_capacity(faces.iter().map(Vec::len).sum());
        for f in &faces {
            face_vertices.extend_from_slice(f);
            face_offsets.push(face_vertices.len());
        }
        let cage = Cage {
            positions,
            face_offsets,
            face_vertices,
            tags,
        };
        cage.validate()?;
        Ok(cage)
    }

    fn validate(&self) -> Result<(), CageError> {
        if self.n_faces() == 0 {
            return Err(CageError::NoFaces);
        }
        for (vertex, p) in self.positions.iter().enumerate() {
            if let Some(&value) = p.iter().find(|c| !c.is_finite()) {
                return Err(CageError::NonFiniteCoordinate { vertex, value });
            }
        }
        let n_vertices = self.n_vertices();
        let mut undirected: HashMap<(u32, u32), u32> = HashMap::new();
        for face in 0..self.n_faces() {
            let fv = self.face(face);
            if fv.len() < 3 {
                return Err(CageError::FaceTooSmall {
                    face,
                    size: fv.len(),
                });
            }
            for (i, &vertex) in fv.iter().enumerate() {
                if vertex as usize >= n_vertices {
                    return Err(CageError::VertexOutOfRange {
                        face,
                        vertex,
                        n_vertices,
                    });
                }
                if fv[..i].contains(&vertex) {
                    return Err(CageError::RepeatedVertex { face, vertex });
                }
            }
            for (a, b) in face_edges(fv) {
                *undirected.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
        for (index, c) in self.tags.creases.iter().enumerate() {
            let bad = |what: String| CageError::BadTag {
                tag: "crease",
                index,
                what,
            };
            let [a, b] = c.vertices;
            if a as usize >= n_vertices || b as usize >= n_vertices {
                return Err(bad(format!(
                    "vertices {a}, {b}; expected indices < {n_vertices}"
                )));
            }
            if !undirected.contains_key(&(a.min(b), a.max(b))) {
                return Err(bad(format!(
                    "vertices {a}, {b} are not joined by an edge of any face"
                )));
            }
            check_sharpness(c.sharpness).map_err(bad)?;
        }
        for (index, c) in self.tags.corners.iter().enumerate() {
            let bad = |what: String| CageError::BadTag {
                tag: "corner",
                index,
                what,
            };
            if c.vertex as usize >= n_vertices {
                return Err(bad(format!(
                    "vertex {}; expected an index < {n_vertices}",
                    c.vertex
                )));
            }
            check_sharpness(c.sharpness).map_err(bad)?;
        }
        for (index, &face) in self.tags.holes.iter().enumerate() {
            if face as usize >= self.n_faces() {
                return Err(CageError::BadTag {
                    tag: "hole",
                    index,
                    what: format!("face {face}; expected an index < {}", self.n_faces()),
                });
            }
        }
        Ok(())
    }

    /// Number of vertices.
    pub fn n_vertices(&self) -> usize {
        self.positions.len()
    }

    /// Number of faces.
    pub fn n_faces(&self) -> usize {
        self.face_offsets.len() - 1
    }

    /// Vertex positions, `n_vertices` long.
    pub fn positions(&self) -> &[Point3] {
        &self.positions
    }

    /// Replaces the positions (same count, finite), keeping topology and tags: how a deformed
    /// cage is made.
    ///
    /// ```
    /// # use splineskin_subdiv::{Cage, SubdivTags};
    /// # let mut cage = Cage::new(vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], vec![vec![0, 1, 2]], SubdivTags::default())?;
    /// cage.set_positions(vec![[0.0; 3], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]])?;
    /// assert_eq!(cage.positions()[1], [2.0, 0.0, 0.0]);
    /// # Ok::<(), splineskin_subdiv::CageError>(())
    /// ```
    pub fn set_positions(&mut self, positions: Vec<Point3>) -> Result<(), CageError> {
        if positions.len() != self.positions.len() {
            return Err(CageError::PositionCount {
                expected: self.positions.len(),
                found: positions.len(),
            });
        }
        for (vertex, p) in positions.iter().enumerate() {
            if let Some(&value) = p.iter().find(|c| !c.is_finite()) {
                return Err(CageError::NonFiniteCoordinate { vertex, value });
            }
        }
        self.positions = positions;
        Ok(())
    }

    /// The vertices of face `face`, in order.
    pub fn face(&self, face: usize) -> &[u32] {
        &self.face_vertices[self.face_offsets[face]..self.face_offsets[face + 1]]
    }

    /// All faces, in order.
    pub fn faces(&self) -> impl ExactSizeIterator<Item = &[u32]> + '_ {
        (0..self.n_faces()).map(|f| self.face(f))
    }

    /// The number of vertices of every face, `n_faces` long (OpenSubdiv's `numVertsPerFace`).
    pub fn face_sizes(&self) -> impl ExactSizeIterator<Item = usize> + '_ {
        self.face_offsets.windows(2).map(|w| w[1] - w[0])
    }

    /// All faces' vertices, concatenated (OpenSubdiv's `vertIndicesPerFace`).
    pub fn face_vertices(&self) -> &[u32] {
        &self.face_vertices
    }

    /// The subdivision tags.
    pub fn tags(&self) -> &SubdivTags {
        &self.tags
    }

    /// The edges shared by exactly two faces that both run along them in the same direction
    /// (inconsistent orientation), as `(from, to, [face, face])`. OpenSubdiv treats them as
    /// non-manifold: infinitely sharp, their ends infinitely sharp corners unless on a
    /// non-manifold crease. Usually a modelling error worth reporting to the user.
    ///
    /// ```
    /// # use splineskin_subdiv::{Cage, SubdivTags};
    /// let p = vec![[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [2.0, 0.0, 0.0], [2.0, 1.0, 0.0]];
    /// // The second face runs from 1 to 2 as the first does.
    /// let cage = Cage::new(p, vec![vec![0, 1, 2, 3], vec![1, 2, 5, 4]], SubdivTags::default())?;
    /// assert_eq!(cage.inconsistent_edges(), vec![(1, 2, [0, 1])]);
    /// # Ok::<(), splineskin_subdiv::CageError>(())
    /// ```
    pub fn inconsistent_edges(&self) -> Vec<(u32, u32, [usize; 2])> {
        let mut faces_of: HashMap<(u32, u32), Vec<(usize, bool)>> = HashMap::new();
        for face in 0..self.n_faces() {
            for (a, b) in face_edges(self.face(face)) {
                faces_of
                    .entry((a.min(b), a.max(b)))
                    .or_default()
                    .push((face, a < b));
            }
        }
        let mut out: Vec<(u32, u32, [usize; 2])> = faces_of
            .into_iter()
            .filter_map(|((lo, hi), f)| match f[..] {
                [(f0, d0), (f1, d1)] if d0 == d1 => {
                    let (from, to) = if d0 { (lo, hi) } else { (hi, lo) };
                    Some((from, to, [f0, f1]))
                }
                _ => None,
            })
            .collect();
        out.sort_unstable();
        out
    }

    /// The length of the diagonal of the axis-aligned bounding box of the positions: the
    /// length unit in which errors of this crate are reported.
    ///
    /// ```
    /// # use splineskin_subdiv::{Cage, SubdivTags};
    /// let cage = Cage::new(vec![[0.0; 3], [3.0, 0.0, 0.0], [0.0, 4.0, 0.0]], vec![vec![0, 1, 2]], SubdivTags::default())?;
    /// assert_eq!(cage.bounding_box_diagonal(), 5.0);
    /// # Ok::<(), splineskin_subdiv::CageError>(())
    /// ```
    pub fn bounding_box_diagonal(&self) -> f64 {
        let (lo, hi) = bounds3(&self.positions);
        (0..3)
            .map(|k| (hi[k] - lo[k]).max(0.0).powi(2))
            .sum::<f64>()
            .sqrt()
    }
}

/// The corners `(lo, hi)` of the axis-aligned bounding box of `points`: their componentwise
/// minimum and maximum (`([∞; 3], [−∞; 3])` for no points).
///
/// ```
/// let (lo, hi) = splineskin_subdiv::bounds3(&[[1.0, 5.0, -2.0], [3.0, 4.0, 0.0]]);
/// assert_eq!((lo, hi), ([1.0, 4.0, -2.0], [3.0, 5.0, 0.0]));
/// ```
pub fn bounds3<'a>(points: impl IntoIterator<Item = &'a Point3>) -> (Point3, Point3) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

/// The directed edges `(v_j, v_{j+1})` of a face loop.
pub(crate) fn face_edges(fv: &[u32]) -> impl Iterator<Item = (u32, u32)> + '_ {
    (0..fv.len()).map(move |j| (fv[j], fv[(j + 1) % fv.len()]))
}

fn check_sharpness(s: f64) -> Result<(), String> {
    if s.is_finite() && s >= 0.0 {
        Ok(())
    } else {
        Err(format!("sharpness {s}; expected a finite number ≥ 0"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> Vec<Point3> {
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [2.0, 0.0, 0.0],
            [2.0, 1.0, 0.0],
        ]
    }

    #[test]
    fn cage_lists_inconsistent_orientation() {
        let cage = Cage::new(
            square(),
            vec![vec![0, 1, 2, 3], vec![1, 2, 5, 4]],
            SubdivTags::default(),
        )
        .unwrap();
        assert_eq!(cage.inconsistent_edges(), vec![(1, 2, [0, 1])]);
        // Reversing the second face makes it consistent.
        let cage = Cage::new(
            square(),
            vec![vec![0, 1, 2, 3], vec![4, 5, 2, 1]],
            SubdivTags::default(),
        )
        .unwrap();
        assert!(cage.inconsistent_edges().is_empty());
    }

    #[test]
    fn cage_refuses_repeated_vertex_and_small_faces() {
        let err = Cage::new(square(), vec![vec![0, 1, 1, 3]], SubdivTags::default());
        assert_eq!(
            err.unwrap_err(),
            CageError::RepeatedVertex { face: 0, vertex: 1 }
        );
        let err = Cage::new(square(), vec![vec![0, 1]], SubdivTags::default());
        assert_eq!(
            err.unwrap_err(),
            CageError::FaceTooSmall { face: 0, size: 2 }
        );
        let err = Cage::new(square(), vec![vec![0, 1, 9]], SubdivTags::default());
        assert!(matches!(
            err.unwrap_err(),
            CageError::VertexOutOfRange { vertex: 9, .. }
        ));
    }

    #[test]
    fn cage_checks_tags() {
        let tags = SubdivTags {
            creases: vec![CreaseTag {
                vertices: [0, 2],
                sharpness: 1.0,
            }],
            ..Default::default()
        };
        let err = Cage::new(square(), vec![vec![0, 1, 2, 3]], tags).unwrap_err();
        assert!(
            matches!(err, CageError::BadTag { tag: "crease", .. }),
            "{err}"
        );
        let tags = SubdivTags {
            holes: vec![1],
            ..Default::default()
        };
        let err = Cage::new(square(), vec![vec![0, 1, 2, 3]], tags).unwrap_err();
        assert!(
            matches!(err, CageError::BadTag { tag: "hole", .. }),
            "{err}"
        );
    }
}
