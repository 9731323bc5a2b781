//! What the triangulated mesh holds besides its triangles: its boundary loops, the vertices
//! along each bone, and the attachment of the art's parts left out to its boundary.

use std::collections::{HashMap, HashSet};

use kurbo::Point;

use super::super::polygon::{segment_distance, signed_area};
use super::super::{Attachment, DomainError};
use crate::mesh::TriMesh;

/// Largest number of point pairs compared to find a part's nearest boundary vertex: 4 Mi (both
/// sides are thinned evenly beyond it).
pub(super) const MAX_ATTACH_PAIRS: usize = 1 << 22;

/// Each part left out, attached to the boundary vertex of `mesh` nearest to its outline.
pub(super) fn attach(
    mesh: &TriMesh,
    boundary_loops: &[Vec<usize>],
    unpinned: Vec<Vec<Vec<Point>>>,
) -> Vec<Attachment> {
    let boundary: Vec<usize> = boundary_loops.iter().flatten().copied().collect();
    unpinned
        .into_iter()
        .filter_map(|loops| {
            let outline: Vec<Point> = loops.iter().flatten().copied().collect();
            let pairs = outline.len().saturating_mul(boundary.len()).max(1);
            let thin = ((pairs as f64 / MAX_ATTACH_PAIRS as f64).sqrt().ceil() as usize).max(1);
            let vertex = boundary
                .iter()
                .step_by(thin)
                .map(|&v| {
                    let p = mesh.vertices[v];
                    let d = outline
                        .iter()
                        .step_by(thin)
                        .map(|q| (*q - p).hypot2())
                        .fold(f64::INFINITY, f64::min);
                    (d, v)
                })
                .min_by(|a, b| a.0.total_cmp(&b.0))?
                .1;
            Some(Attachment { loops, vertex })
        })
        .collect()
}

/// The mesh vertices within `tol` of the segment `a b`, ordered from `a` to `b`.
pub(super) fn vertices_on_segment(mesh: &TriMesh, a: Point, b: Point, tol: f64) -> Vec<usize> {
    let mut on: Vec<(f64, usize)> = mesh
        .vertices
        .iter()
        .enumerate()
        .filter_map(|(i, &p)| {
            let (d, s) = segment_distance(p, a, b);
            (d <= tol).then_some((s, i))
        })
        .collect();
    on.sort_by(|x, y| x.0.total_cmp(&y.0));
    on.into_iter().map(|(_, i)| i).collect()
}

/// The boundary of the mesh as closed loops of vertices (each boundary edge oriented with the
/// mesh on its left), the loop of largest signed area first.
pub(super) fn boundary_loops(mesh: &TriMesh) -> Result<Vec<Vec<usize>>, DomainError> {
    let mut directed: HashSet<(usize, usize)> = HashSet::new();
    for t in &mesh.triangles {
        for k in 0..3 {
            directed.insert((t[k], t[(k + 1) % 3]));
        }
    }
    let mut next: HashMap<usize, usize> = HashMap::new();
    for &(a, b) in &directed {
        if !directed.contains(&(b, a)) && next.insert(a, b).is_some() {
            return Err(DomainError::Bug(
                "a boundary vertex starts two boundary edges (the domain pinches)",
            ));
        }
    }
    let mut starts: Vec<usize> = next.keys().copied().collect();
    starts.sort_unstable();
    let mut seen: HashSet<usize> = HashSet::new();
    let mut loops = Vec::new();
    for s in starts {
        if seen.contains(&s) {
            continue;
        }
        let mut l = vec![s];
        seen.insert(s);
        let mut v = next[&s];
        while v != s {
            if !seen.insert(v) {
                return Err(DomainError::Bug("boundary edges do not form loops"));
            }
            l.push(v);
            v = *next
                .get(&v)
                .ok_or(DomainError::Bug("boundary edges do not form loops"))?;
        }
        loops.push(l);
    }
    let area = |l: &Vec<usize>| {
        let p: Vec<Point> = l.iter().map(|&i| mesh.vertices[i]).collect();
        signed_area(&p)
    };
    loops.sort_by(|a, b| area(b).total_cmp(&area(a)));
    Ok(loops)
}
