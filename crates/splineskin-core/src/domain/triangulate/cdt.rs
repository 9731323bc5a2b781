//! The constrained Delaunay triangulation (spade): made from the placed vertices and
//! constraint edges, refined to the options' angle and area, and extracted as a mesh.

use std::collections::HashSet;

use kurbo::Point;
use spade::handles::FixedVertexHandle;
use spade::{
    AngleLimit, ConstrainedDelaunayTriangulation, Point2, RefinementParameters, Triangulation,
};

use super::super::{DomainError, DomainOptions};
use super::placement::Placed;
use crate::mesh::TriMesh;

pub(super) type Cdt = ConstrainedDelaunayTriangulation<Point2<f64>>;

/// The constrained Delaunay triangulation of `placed`, refined to the options' angle, area and
/// vertex cap (spade), with the bones added as constraint edges after refinement (spade's
/// classification of outer faces needs closed constraint loops, and a bone is an open chain).
/// Returns it, its faces outside the domain, and whether refinement met its goals.
pub(super) fn triangulate_and_refine(
    placed: &Placed,
    options: &DomainOptions,
    area: f64,
) -> Result<(Cdt, HashSet<usize>, bool), DomainError> {
    let n_initial = placed.verts.points.len();
    let mut conflicts = Vec::new();
    let mut cdt = Cdt::try_bulk_load_cdt(
        placed
            .verts
            .points
            .iter()
            .map(|p| Point2::new(p.x, p.y))
            .collect(),
        placed.constraints.clone(),
        |e| conflicts.push(e),
    )
    .map_err(|e| DomainError::Triangulation {
        reason: e.to_string(),
    })?;
    if !conflicts.is_empty() {
        return Err(DomainError::Bug(
            "constraint edges of a validated boundary intersect",
        ));
    }
    if cdt.num_vertices() != n_initial {
        return Err(DomainError::Bug(
            "duplicate vertices reached the triangulator",
        ));
    }
    let params = RefinementParameters::<f64>::new()
        .exclude_outer_faces(true)
        .with_angle_limit(AngleLimit::from_deg(options.min_angle))
        .with_max_allowed_area(options.max_area_fraction * area)
        .with_max_additional_vertices(options.max_vertices.saturating_sub(n_initial));
    let result = cdt.refine(params);
    if !result.refinement_complete {
        tracing::warn!(
            max_vertices = options.max_vertices,
            "domain refinement stopped at the vertex cap before meeting its angle and area goals"
        );
    }
    let excluded: HashSet<usize> = result.excluded_faces.iter().map(|f| f.index()).collect();
    for chain in &placed.bone_chains {
        for w in chain.windows(2) {
            if w[0] == w[1] {
                continue;
            }
            let (a, b) = (
                FixedVertexHandle::from_index(w[0]),
                FixedVertexHandle::from_index(w[1]),
            );
            if !cdt.can_add_constraint(a, b) && !cdt.exists_constraint(a, b) {
                return Err(DomainError::Bug("a bone crosses a constraint edge"));
            }
            cdt.add_constraint(a, b);
        }
    }
    Ok((cdt, excluded, result.refinement_complete))
}

/// The kept triangles of `cdt` (not `excluded`) as a mesh of the vertices they use, and the map
/// from the triangulation's vertex indices to the mesh's (`usize::MAX`: not used).
pub(super) fn extract_mesh(
    cdt: &Cdt,
    excluded: &HashSet<usize>,
) -> Result<(TriMesh, Vec<usize>), DomainError> {
    let mut remap = vec![usize::MAX; cdt.num_vertices()];
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for face in cdt.inner_faces() {
        if excluded.contains(&face.fix().index()) {
            continue;
        }
        let tri = face.vertices().map(|v| {
            let i = v.fix().index();
            if remap[i] == usize::MAX {
                remap[i] = vertices.len();
                let p = v.position();
                vertices.push(Point::new(p.x, p.y));
            }
            remap[i]
        });
        triangles.push(tri);
    }
    Ok((TriMesh::new(vertices, triangles)?, remap))
}
