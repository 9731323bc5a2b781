//! [`HandleSet`]: point handles at mesh vertices, checked against the mesh, and the numbering
//! of the free (unconstrained) vertices that every ground-truth system is written in.

use kurbo::Point;

use super::error::DefOpError;
use splineskin_core::mesh::TriMesh;

/// Marks a vertex that is not free in [`HandleSet::free_index`].
pub(crate) const NOT_FREE: usize = usize::MAX;

/// Point handles at distinct vertices of a mesh, and the free vertices.
///
/// A vertex is *free* when it is in at least one triangle and is not a handle. Free vertices
/// are numbered `0..n_free` in increasing vertex order, so restricting a matrix with sorted
/// rows to them keeps its rows sorted. A vertex in no triangle has no energy: it is neither a
/// handle's nor free, and keeps its initial position (documented at the solvers).
#[derive(Clone, Debug)]
pub(crate) struct HandleSet {
    /// The handle vertices, in the caller's order.
    pub vertices: Vec<usize>,
    /// `free_index[v]`: the free index of vertex `v`, or [`NOT_FREE`].
    pub free_index: Vec<usize>,
    /// `free[r]`: the vertex of free index `r`.
    pub free: Vec<usize>,
}

impl HandleSet {
    /// Checks `vertices` against `mesh`: at least one, in range, distinct, and one in every
    /// connected part of the mesh (else that part could move freely).
    pub fn new(mesh: &TriMesh, vertices: &[usize]) -> Result<HandleSet, DefOpError> {
        mesh.check()?;
        if vertices.is_empty() {
            return Err(DefOpError::NoHandles);
        }
        let n_vertices = mesh.n_vertices();
        if let Some(handle) = vertices.iter().position(|&v| v >= n_vertices) {
            return Err(DefOpError::HandleOutOfRange {
                handle,
                vertex: vertices[handle],
                n_vertices,
            });
        }
        let mut owner = vec![usize::MAX; n_vertices];
        for (handle, &v) in vertices.iter().enumerate() {
            if owner[v] != usize::MAX {
                return Err(DefOpError::DuplicateHandle {
                    vertex: v,
                    first: owner[v],
                    second: handle,
                });
            }
            owner[v] = handle;
        }
        let referenced = mesh.referenced_vertices();
        let components = mesh.components();
        let n_components = components.iter().max().map_or(0, |&c| c + 1);
        let mut held = vec![false; n_components];
        for &v in vertices {
            held[components[v]] = true;
        }
        // Components are numbered in the order of their smallest vertex, so the first vertex
        // met of an unheld, referenced component is its smallest.
        if let Some(vertex) = (0..n_vertices).find(|&v| referenced[v] && !held[components[v]]) {
            return Err(DefOpError::PartWithoutHandle { vertex });
        }
        let mut free_index = vec![NOT_FREE; n_vertices];
        let mut free = Vec::new();
        for v in 0..n_vertices {
            if referenced[v] && owner[v] == usize::MAX {
                free_index[v] = free.len();
                free.push(v);
            }
        }
        Ok(HandleSet {
            vertices: vertices.to_vec(),
            free_index,
            free,
        })
    }

    /// Number of handles.
    pub fn n_handles(&self) -> usize {
        self.vertices.len()
    }

    /// Number of free vertices.
    pub fn n_free(&self) -> usize {
        self.free.len()
    }

    /// Checks a solve's inputs: one finite target per handle, one finite position per vertex.
    pub fn check_inputs(&self, targets: &[Point], positions: &[Point]) -> Result<(), DefOpError> {
        if targets.len() != self.n_handles() {
            return Err(DefOpError::TargetCount {
                given: targets.len(),
                n_handles: self.n_handles(),
            });
        }
        check_finite_targets(targets)?;
        check_position_count(positions, self.free_index.len())?;
        if let Some(vertex) = positions.iter().position(|p| !p.is_finite()) {
            let p = positions[vertex];
            return Err(DefOpError::NonFinitePosition {
                vertex,
                x: p.x,
                y: p.y,
            });
        }
        Ok(())
    }
}

/// Checks handle positions (targets, or a rest configuration): every one finite, else
/// [`DefOpError::NonFiniteTarget`] for the first that is not.
pub(crate) fn check_finite_targets(targets: &[Point]) -> Result<(), DefOpError> {
    match targets.iter().position(|p| !p.is_finite()) {
        Some(handle) => Err(DefOpError::NonFiniteTarget {
            handle,
            x: targets[handle].x,
            y: targets[handle].y,
        }),
        None => Ok(()),
    }
}

/// Checks a rest configuration of handles: at least one ([`DefOpError::NoHandles`]), every
/// one finite ([`check_finite_targets`]).
pub(crate) fn check_rest_handles(rest: &[Point]) -> Result<(), DefOpError> {
    if rest.is_empty() {
        return Err(DefOpError::NoHandles);
    }
    check_finite_targets(rest)
}

/// Checks that there is one position per vertex of a mesh of `n_vertices`, else
/// [`DefOpError::PositionCount`].
pub(crate) fn check_position_count(
    positions: &[Point],
    n_vertices: usize,
) -> Result<(), DefOpError> {
    if positions.len() != n_vertices {
        return Err(DefOpError::PositionCount {
            given: positions.len(),
            n_vertices,
        });
    }
    Ok(())
}

/// The diagonal of `mesh`'s bounding box: the length unit of the solvers' step tolerances
/// ([`TriMesh::bounding_box_diagonal`]).
pub(crate) fn bounding_box_diagonal(mesh: &TriMesh) -> f64 {
    mesh.bounding_box_diagonal()
}
