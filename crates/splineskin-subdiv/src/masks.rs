//! Catmull–Clark refinement and limit masks in `f64`, with OpenSubdiv's rules
//! (`Sdc::Scheme<SCHEME_CATMARK>`, `Sdc::Crease`; reference README "What a reimplementation
//! must match").
//!
//! A *mask* gives a child vertex (or a limit point) as weights over the vertices of the parent
//! level. Face points are expanded into their face's vertices, so every mask here refers to
//! parent vertices only.
//!
//! | child of | mask |
//! |---|---|
//! | face with n vertices | centroid: `1/n` each |
//! | edge, sharpness `s ≥ 1` (or no face) | midpoint `(a + b)/2` |
//! | edge, `0 ≤ s < 1` | `s·(a + b)/2 + (1 − s)·((a + b)/4 + ½·mean of the adjacent face points)` |
//! | vertex, smooth or dart rule, valence n | `(n − 2)/n·v + 1/n²·Σ edge neighbours + 1/n²·Σ adjacent face points` (`n − nF` extra edges at a non-manifold vertex are weighted the same) |
//! | vertex, crease rule | `3/4·v + 1/8·(a + b)`, `a`, `b` across its two sharp edges |
//! | vertex, corner rule | `v` |
//! | vertex whose rule changes this step | `w·(parent-rule mask) + (1 − w)·(child-rule mask)`, `w` from `Sdc::Crease::ComputeFractionalWeightAtVertex` |
//!
//! Sharpness values and the rule decisions come from `opensubdiv-rs` in `f32`, as in
//! OpenSubdiv itself ("sharpness arithmetic is float32"); all weights are computed in `f64`.

use opensubdiv_rs::far::TopologyLevel as Level;
use opensubdiv_rs::sdc::{Crease, Rule};
use opensubdiv_rs::vtr::Refinement;
use opensubdiv_rs::{Index, INDEX_INVALID};

/// Sparse weights over the vertices of one level: `(vertex, weight)`, possibly repeated.
pub(crate) type Weights = Vec<(u32, f64)>;

/// Where a child vertex comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Origin {
    /// The face point of a parent face.
    Face(u32),
    /// The edge point of a parent edge.
    Edge(u32),
    /// The child of a parent vertex.
    Vertex(u32),
}

/// Adds the centroid of `face` with total weight `w`.
fn add_face_point(parent: Level<'_>, face: usize, w: f64, out: &mut Weights) {
    let fv = parent.face_vertices(face);
    let each = w / fv.len() as f64;
    out.extend(fv.iter().map(|&v| (v, each)));
}

/// Is every face a mask would read refined at this step? Fringe components of a sparse
/// refinement are not: their child values only support the region and are never evaluated.
fn faces_refined(refinement: &Refinement, faces: &[Index]) -> bool {
    faces
        .iter()
        .all(|&f| refinement.face_child_vertex(f as usize) != INDEX_INVALID)
}

/// The mask of the child vertex with origin `origin`, appended to `out` (cleared first).
/// Returns `false` when the mask's neighbourhood is incomplete (a fringe vertex of a sparse
/// level); `out` then holds a stand-in (the edge midpoint or the parent vertex) that keeps
/// values finite but is not the subdivision rule.
pub(crate) fn child_mask(
    crease: &Crease,
    parent: Level<'_>,
    refinement: &Refinement,
    origin: Origin,
    out: &mut Weights,
) -> bool {
    out.clear();
    match origin {
        Origin::Face(f) => {
            add_face_point(parent, f as usize, 1.0, out);
            true
        }
        Origin::Edge(e) => edge_mask(parent, refinement, e as usize, out),
        Origin::Vertex(v) => vertex_mask(crease, parent, refinement, v as usize, out),
    }
}

fn edge_mask(parent: Level<'_>, refinement: &Refinement, e: usize, out: &mut Weights) -> bool {
    let [a, b] = parent.edge_vertices(e);
    let faces = parent.edge_faces(e);
    let complete = faces_refined(refinement, faces);
    // Crease weight: the edge's sharpness clamped to [0, 1] (Sdc: transitional edges blend).
    let crease_weight = f64::from(parent.edge_sharpness(e)).clamp(0.0, 1.0);
    if crease_weight >= 1.0 || faces.is_empty() || !complete {
        out.push((a, 0.5));
        out.push((b, 0.5));
        return complete;
    }
    let smooth = 1.0 - crease_weight;
    let end = crease_weight * 0.5 + smooth * 0.25;
    out.push((a, end));
    out.push((b, end));
    let per_face = smooth * 0.5 / faces.len() as f64;
    for &f in faces {
        add_face_point(parent, f as usize, per_face, out);
    }
    true
}

/// Which mask to take of a rule that blends.
#[derive(Clone, Copy)]
enum Side {
    Parent,
    Child,
}

fn vertex_mask(
    crease: &Crease,
    parent: Level<'_>,
    refinement: &Refinement,
    v: usize,
    out: &mut Weights,
) -> bool {
    let faces = parent.vertex_faces(v);
    if !faces_refined(refinement, faces) {
        out.push((v as u32, 1.0));
        return false;
    }
    let edges = parent.vertex_edges(v);
    let sharpness: Vec<f32> = edges
        .iter()
        .map(|&e| parent.edge_sharpness(e as usize))
        .collect();
    let vertex_sharpness = parent.vertex_sharpness(v);
    let parent_rule =
        crease.determine_vertex_vertex_rule(vertex_sharpness, count_sharp(&sharpness));
    if matches!(parent_rule, Rule::Smooth | Rule::Dart) {
        smooth_vertex_mask(parent, v, 1.0, out);
        return true;
    }
    let child_sharpness: Vec<f32> = sharpness
        .iter()
        .map(|&s| {
            if Crease::is_sharp(s) {
                crease.subdivide_edge_sharpness_at_vertex(s, &sharpness)
            } else {
                0.0
            }
        })
        .collect();
    let child_vertex_sharpness = crease.subdivide_vertex_sharpness(vertex_sharpness);
    let child_rule =
        crease.determine_vertex_vertex_rule(child_vertex_sharpness, count_sharp(&child_sharpness));
    let rule_mask = |rule: Rule, side: Side, scale: f64, out: &mut Weights| match rule {
        Rule::Smooth | Rule::Dart | Rule::Unknown => smooth_vertex_mask(parent, v, scale, out),
        Rule::Crease => {
            let s = match side {
                Side::Parent => &sharpness,
                Side::Child => &child_sharpness,
            };
            crease_vertex_mask(parent, v, s, scale, out)
        }
        Rule::Corner => out.push((v as u32, scale)),
    };
    if parent_rule == child_rule {
        rule_mask(parent_rule, Side::Parent, 1.0, out);
    } else {
        let w = f64::from(crease.compute_fractional_weight_at_vertex(
            vertex_sharpness,
            child_vertex_sharpness,
            &sharpness,
            &child_sharpness,
        ));
        rule_mask(parent_rule, Side::Parent, w, out);
        rule_mask(child_rule, Side::Child, 1.0 - w, out);
    }
    true
}

fn count_sharp(sharpness: &[f32]) -> usize {
    sharpness.iter().filter(|&&s| Crease::is_sharp(s)).count()
}

/// Smooth rule: `(n − 2)/n·v + 1/n²·Σ edge neighbours + 1/n²·Σ face points`, written as
/// `1 − n·(1/n²) − nF·(1/n²)` on `v` so that it also holds where `nF ≠ n`.
fn smooth_vertex_mask(parent: Level<'_>, v: usize, scale: f64, out: &mut Weights) {
    let edges = parent.vertex_edges(v);
    let faces = parent.vertex_faces(v);
    let n = edges.len() as f64;
    if edges.is_empty() {
        out.push((v as u32, scale));
        return;
    }
    let w = 1.0 / (n * n);
    out.push((v as u32, scale * (1.0 - n * w - faces.len() as f64 * w)));
    for &e in edges {
        out.push((opposite(parent, e, v), scale * w));
    }
    for &f in faces {
        add_face_point(parent, f as usize, scale * w, out);
    }
}

/// Crease rule: `3/4·v + 1/8·(a + b)` over the first two sharp edges (as Sdc takes them).
fn crease_vertex_mask(
    parent: Level<'_>,
    v: usize,
    sharpness: &[f32],
    scale: f64,
    out: &mut Weights,
) {
    out.push((v as u32, scale * 0.75));
    let edges = parent.vertex_edges(v);
    for (&e, _) in edges
        .iter()
        .zip(sharpness)
        .filter(|(_, &s)| Crease::is_sharp(s))
        .take(2)
    {
        out.push((opposite(parent, e, v), scale * 0.125));
    }
}

/// How exact a vertex limit mask is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum LimitExactness {
    /// The true limit point (smooth, crease or corner rule, quads all around, no semi-sharp
    /// feature left).
    Exact,
    /// Sdc's mask where it is known not to be the limit: darts (smooth mask) and interior
    /// vertices of valence 2.
    Approximate,
}

/// The limit mask of vertex `v` of `level` over that level's vertices, into `out`
/// (`Sdc::Scheme::ComputeVertexLimitMask`):
///
/// * smooth, valence n, all faces quads: `(n²·v + 4·Σ eᵢ + Σ dᵢ) / (n(n + 5))`, `eᵢ` edge
///   neighbours, `dᵢ` the vertices diagonally opposite `v` in its faces;
/// * crease: `(a + 4v + b)/6` along its two sharp edges;
/// * corner: `v`.
///
/// Returns `None` when the mask is not defined here: a face around `v` is not a quad, or an
/// incident edge or `v` itself is semi-sharp (the rule would still change), or `v` has no face.
pub(crate) fn limit_mask(
    crease: &Crease,
    level: Level<'_>,
    v: usize,
    out: &mut Weights,
) -> Option<LimitExactness> {
    out.clear();
    let faces = level.vertex_faces(v);
    let edges = level.vertex_edges(v);
    if faces.is_empty() {
        return None;
    }
    if faces
        .iter()
        .any(|&f| level.face_vertices(f as usize).len() != 4)
    {
        return None;
    }
    let sharpness: Vec<f32> = edges
        .iter()
        .map(|&e| level.edge_sharpness(e as usize))
        .collect();
    let vs = level.vertex_sharpness(v);
    if Crease::is_semi_sharp(vs) || sharpness.iter().any(|&s| Crease::is_semi_sharp(s)) {
        return None;
    }
    let rule = crease.determine_vertex_vertex_rule(vs, count_sharp(&sharpness));
    let mut exactness = LimitExactness::Exact;
    match rule {
        Rule::Smooth | Rule::Dart | Rule::Unknown => {
            if rule != Rule::Smooth || edges.len() == 2 {
                exactness = LimitExactness::Approximate;
            }
            let n = edges.len() as f64;
            let fw = 1.0 / (n * (n + 5.0));
            let ew = 4.0 * fw;
            out.push((v as u32, 1.0 - n * ew - faces.len() as f64 * fw));
            for &e in edges {
                out.push((opposite(level, e, v), ew));
            }
            for &f in faces {
                let fv = level.face_vertices(f as usize);
                let i = fv.iter().position(|&x| x as usize == v)?;
                out.push((fv[(i + 2) % 4], fw));
            }
        }
        Rule::Crease => {
            out.push((v as u32, 2.0 / 3.0));
            for (&e, _) in edges
                .iter()
                .zip(&sharpness)
                .filter(|(_, &s)| Crease::is_sharp(s))
                .take(2)
            {
                out.push((opposite(level, e, v), 1.0 / 6.0));
            }
        }
        Rule::Corner => out.push((v as u32, 1.0)),
    }
    Some(exactness)
}

/// Sorts `w` by vertex and sums repeated entries, dropping exact zeros.
pub(crate) fn merge(w: &mut Weights) {
    w.sort_unstable_by_key(|&(v, _)| v);
    let mut out = 0;
    for i in 0..w.len() {
        if out > 0 && w[out - 1].0 == w[i].0 {
            w[out - 1].1 += w[i].1;
        } else {
            w[out] = w[i];
            out += 1;
        }
    }
    w.truncate(out);
    w.retain(|&(_, x)| x != 0.0);
}

/// The other end of edge `e` from vertex `v`.
fn opposite(level: Level<'_>, e: Index, v: usize) -> u32 {
    let [a, b] = level.edge_vertices(e as usize);
    if a as usize == v {
        b
    } else {
        a
    }
}
