//! A refinement hierarchy: `opensubdiv-rs`'s topology levels (uniform or feature-adaptive)
//! plus, for every refined vertex, where it comes from and whether its value is the true
//! subdivision value (fringe vertices of sparse levels are not).
//!
//! Weights are never stored per level: the mask of a child vertex is recomputed from the
//! parent level's topology when needed ([`masks::child_mask`]), which keeps memory at a few
//! bytes per refined vertex however deep the isolation goes.

use opensubdiv_rs::far::TopologyLevel;
use opensubdiv_rs::far::{
    AdaptiveOptions, TopologyDescriptor, TopologyRefiner, TopologyRefinerFactory, UniformOptions,
};
use opensubdiv_rs::sdc::{self, Crease};
use opensubdiv_rs::INDEX_INVALID;

use std::collections::HashMap;

use super::cage::{face_edges, Cage};
use super::error::SubdivError;
use super::masks::{self, Origin, Weights};

/// How to refine.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Refine {
    /// Every face, this many levels.
    Uniform(usize),
    /// Feature-adaptive isolation to this level.
    Adaptive(usize),
}

/// The Sdc options of every refinement here (module documentation of [`crate`]).
pub(crate) fn sdc_options() -> sdc::Options {
    sdc::Options::default()
        .with_vtx_boundary_interpolation(sdc::VtxBoundaryInterpolation::EdgeAndCorner)
        .with_creasing_method(sdc::CreasingMethod::Uniform)
        .with_triangle_subdivision(sdc::TriangleSubdivision::Catmark)
}

#[derive(Clone)]
pub(crate) struct Hierarchy {
    pub(crate) refiner: TopologyRefiner,
    pub(crate) crease: Crease,
    /// Per level ≥ 1 (index `level - 1`): the origin of each vertex.
    origins: Vec<Vec<Origin>>,
    /// Per level (index `level`): is each vertex's value the subdivision value?
    valid: Vec<Vec<bool>>,
}

impl Hierarchy {
    pub(crate) fn new(cage: &Cage, refine: Refine) -> Result<Self, SubdivError> {
        let sizes: Vec<usize> = cage.face_sizes().collect();
        let tags = cage.tags();
        let (mut creases, mut crease_weights): (Vec<[u32; 2]>, Vec<f32>) = tags
            .creases
            .iter()
            .map(|c| (c.vertices, c.sharpness as f32))
            .unzip();
        let (mut corners, mut corner_weights): (Vec<u32>, Vec<f32>) = tags
            .corners
            .iter()
            .map(|c| (c.vertex, c.sharpness as f32))
            .unzip();
        // Inconsistently oriented edges: OpenSubdiv's non-manifold sharpening, which
        // opensubdiv-rs applies only to edges with more than two faces.
        let (sharp_edges, sharp_vertices) = orientation_sharpness(cage);
        if !sharp_edges.is_empty() {
            tracing::warn!(
                n_edges = sharp_edges.len(),
                first = ?sharp_edges[0],
                "inconsistently oriented faces: their shared edges are made infinitely sharp, \
                 as OpenSubdiv does (Cage::inconsistent_edges lists them)"
            );
        }
        crease_weights.extend(sharp_edges.iter().map(|_| sdc::SHARPNESS_INFINITE));
        creases.extend(sharp_edges);
        corner_weights.extend(sharp_vertices.iter().map(|_| sdc::SHARPNESS_INFINITE));
        corners.extend(sharp_vertices);
        let descriptor = TopologyDescriptor::new(cage.n_vertices(), &sizes, cage.face_vertices())
            .with_creases(&creases, &crease_weights)
            .with_corners(&corners, &corner_weights)
            .with_holes(&cage.tags().holes);
        let options = sdc_options();
        let mut refiner =
            TopologyRefinerFactory::create(descriptor, sdc::SchemeType::Catmark, options).map_err(
                |e| SubdivError::Topology {
                    what: e.to_string(),
                },
            )?;
        match refine {
            Refine::Uniform(levels) => refiner.refine_uniform(UniformOptions::new(levels)),
            Refine::Adaptive(isolation) => refiner.refine_adaptive(AdaptiveOptions::new(isolation)),
        }
        let crease = Crease::new(options);
        let mut origins = Vec::with_capacity(refiner.max_level());
        let mut valid = vec![vec![true; cage.n_vertices()]];
        let mut mask = Weights::new();
        for level in 1..=refiner.max_level() {
            let parent = refiner.level(level - 1);
            let refinement = refiner.refinement(level);
            let n_child = refiner.level(level).num_vertices();
            let mut origin = vec![Origin::Vertex(u32::MAX); n_child];
            for f in 0..parent.num_faces() {
                set_origin(
                    &mut origin,
                    refinement.face_child_vertex(f),
                    Origin::Face(f as u32),
                );
            }
            for e in 0..parent.num_edges() {
                set_origin(
                    &mut origin,
                    refinement.edge_child_vertex(e),
                    Origin::Edge(e as u32),
                );
            }
            for v in 0..parent.num_vertices() {
                set_origin(
                    &mut origin,
                    refinement.vertex_child_vertex(v),
                    Origin::Vertex(v as u32),
                );
            }
            let parent_valid = &valid[level - 1];
            let mut child_valid = vec![false; n_child];
            for (c, &o) in origin.iter().enumerate() {
                if o == Origin::Vertex(u32::MAX) {
                    return Err(SubdivError::Internal {
                        what: format!("level {level} vertex {c} has no parent component"),
                    });
                }
                let complete = masks::child_mask(&crease, parent, refinement, o, &mut mask);
                child_valid[c] = complete && mask.iter().all(|&(p, _)| parent_valid[p as usize]);
            }
            origins.push(origin);
            valid.push(child_valid);
        }
        Ok(Hierarchy {
            refiner,
            crease,
            origins,
            valid,
        })
    }

    /// The deepest level.
    pub(crate) fn max_level(&self) -> usize {
        self.refiner.max_level()
    }

    /// The topology of `level`.
    pub(crate) fn level(&self, level: usize) -> TopologyLevel<'_> {
        self.refiner.level(level)
    }

    /// Where vertex `v` of `level ≥ 1` comes from.
    pub(crate) fn origin(&self, level: usize, v: u32) -> Origin {
        self.origins[level - 1][v as usize]
    }

    /// Is the value of vertex `v` of `level` the true subdivision value?
    pub(crate) fn is_valid(&self, level: usize, v: u32) -> bool {
        self.valid[level][v as usize]
    }

    /// Rewrites `weights` (over the vertices of `level`) as weights over the base vertices,
    /// merged and sorted by vertex. `scratch` is reused.
    pub(crate) fn to_base(&self, level: usize, weights: &mut Weights, scratch: &mut Weights) {
        let mut mask = Weights::new();
        for l in (1..=level).rev() {
            masks::merge(weights);
            scratch.clear();
            let parent = self.level(l - 1);
            let refinement = self.refiner.refinement(l);
            for &(v, w) in weights.iter() {
                masks::child_mask(
                    &self.crease,
                    parent,
                    refinement,
                    self.origin(l, v),
                    &mut mask,
                );
                scratch.extend(mask.iter().map(|&(p, m)| (p, m * w)));
            }
            std::mem::swap(weights, scratch);
        }
        masks::merge(weights);
    }
}

/// Reusable buffers of [`Hierarchy::to_base_columns`].
#[derive(Default)]
pub(crate) struct ColumnScratch {
    keys: Vec<u64>,
    verts: Vec<u32>,
    vals: Vec<f64>,
    mask: Weights,
}

impl Hierarchy {
    /// [`Hierarchy::to_base`] for `cols` weight lists at once: entry `e` is vertex `verts[e]`
    /// of `level` with the weights `vals[e·cols .. (e+1)·cols]`, one per list. The lists share
    /// every expansion and sort, so carrying 16 patch points costs little more than carrying
    /// their sum. On return the entries are base vertices, increasing, with entries whose
    /// weights are all zero dropped.
    pub(crate) fn to_base_columns(
        &self,
        level: usize,
        verts: &mut Vec<u32>,
        vals: &mut Vec<f64>,
        cols: usize,
        scratch: &mut ColumnScratch,
    ) {
        for l in (1..=level).rev() {
            merge_columns(verts, vals, cols, scratch);
            scratch.verts.clear();
            scratch.vals.clear();
            let parent = self.level(l - 1);
            let refinement = self.refiner.refinement(l);
            for (e, &v) in verts.iter().enumerate() {
                masks::child_mask(
                    &self.crease,
                    parent,
                    refinement,
                    self.origin(l, v),
                    &mut scratch.mask,
                );
                let row = &vals[e * cols..][..cols];
                for &(p, m) in &scratch.mask {
                    scratch.verts.push(p);
                    scratch.vals.extend(row.iter().map(|x| m * x));
                }
            }
            std::mem::swap(verts, &mut scratch.verts);
            std::mem::swap(vals, &mut scratch.vals);
        }
        merge_columns(verts, vals, cols, scratch);
    }
}

/// Sorts the entries of [`Hierarchy::to_base_columns`] by vertex, sums repeated vertices and
/// drops entries whose weights are all exactly zero (summing in entry order within a vertex).
fn merge_columns(
    verts: &mut Vec<u32>,
    vals: &mut Vec<f64>,
    cols: usize,
    scratch: &mut ColumnScratch,
) {
    scratch.keys.clear();
    scratch.keys.extend(
        verts
            .iter()
            .enumerate()
            .map(|(e, &v)| (u64::from(v) << 32) | e as u64),
    );
    scratch.keys.sort_unstable();
    scratch.verts.clear();
    scratch.vals.clear();
    for &key in &scratch.keys {
        let (v, e) = ((key >> 32) as u32, (key & 0xffff_ffff) as usize);
        let row = &vals[e * cols..][..cols];
        if scratch.verts.last() == Some(&v) {
            let start = scratch.vals.len() - cols;
            for (o, x) in scratch.vals[start..].iter_mut().zip(row) {
                *o += x;
            }
        } else {
            scratch.verts.push(v);
            scratch.vals.extend_from_slice(row);
        }
    }
    verts.clear();
    vals.clear();
    for (e, &v) in scratch.verts.iter().enumerate() {
        let row = &scratch.vals[e * cols..][..cols];
        if row.iter().any(|&x| x != 0.0) {
            verts.push(v);
            vals.extend_from_slice(row);
        }
    }
}

/// OpenSubdiv's sharpening of inconsistently oriented edges (two faces running along the edge
/// in the same direction; `Vtr` tags them non-manifold): the edges become infinitely sharp, and
/// so does each of their end vertices unless it lies on a *non-manifold crease* — exactly two
/// non-manifold edges, no boundary edge, and every fan of faces around the vertex (faces joined
/// across its manifold edges) touching both. Returns the edges and the vertices to sharpen.
fn orientation_sharpness(cage: &Cage) -> (Vec<[u32; 2]>, Vec<u32>) {
    let inconsistent = cage.inconsistent_edges();
    if inconsistent.is_empty() {
        return (Vec::new(), Vec::new());
    }
    let key = |a: u32, b: u32| (a.min(b), a.max(b));
    // Edge -> its faces with direction (true: from the smaller vertex).
    let mut faces_of: HashMap<(u32, u32), Vec<(usize, bool)>> = HashMap::new();
    for f in 0..cage.n_faces() {
        for (a, b) in face_edges(cage.face(f)) {
            faces_of.entry(key(a, b)).or_default().push((f, a < b));
        }
    }
    let non_manifold = |e: &(u32, u32)| match faces_of[e][..] {
        [(_, d0), (_, d1)] => d0 == d1,
        ref f => f.len() > 2,
    };
    let mut vertices: Vec<u32> = inconsistent.iter().flat_map(|&(a, b, _)| [a, b]).collect();
    vertices.sort_unstable();
    vertices.dedup();
    let sharp_vertices = vertices
        .into_iter()
        .filter(|&v| {
            // The faces around v and its edges.
            let faces: Vec<usize> = (0..cage.n_faces())
                .filter(|&f| cage.face(f).contains(&v))
                .collect();
            let mut edges: Vec<(u32, u32)> = faces
                .iter()
                .flat_map(|&f| face_edges(cage.face(f)).filter(|&(a, b)| a == v || b == v))
                .map(|(a, b)| key(a, b))
                .collect();
            edges.sort_unstable();
            edges.dedup();
            let crease: Vec<(u32, u32)> = edges.iter().copied().filter(non_manifold).collect();
            if crease.len() != 2 || edges.iter().any(|e| faces_of[e].len() == 1) {
                return true;
            }
            // Fans: union of faces across v's manifold edges.
            let mut fan: Vec<usize> = (0..faces.len()).collect();
            fn root(fan: &mut [usize], mut i: usize) -> usize {
                while fan[i] != i {
                    fan[i] = fan[fan[i]];
                    i = fan[i];
                }
                i
            }
            for e in edges.iter().filter(|e| !non_manifold(e)) {
                if let [(f0, _), (f1, _)] = faces_of[e][..] {
                    let (i, j) = (
                        faces.iter().position(|&f| f == f0).unwrap_or(0),
                        faces.iter().position(|&f| f == f1).unwrap_or(0),
                    );
                    let (ri, rj) = (root(&mut fan, i), root(&mut fan, j));
                    fan[ri] = rj;
                }
            }
            // Every fan must touch both crease edges.
            let mut touches: HashMap<usize, [bool; 2]> = HashMap::new();
            for (i, &f) in faces.iter().enumerate() {
                let r = root(&mut fan, i);
                let t = touches.entry(r).or_default();
                for (a, b) in face_edges(cage.face(f)) {
                    if let Some(k) = crease.iter().position(|&c| c == key(a, b)) {
                        t[k] = true;
                    }
                }
            }
            !touches.values().all(|t| t[0] && t[1])
        })
        .collect();
    let edges = inconsistent.iter().map(|&(a, b, _)| [a, b]).collect();
    (edges, sharp_vertices)
}

fn set_origin(origin: &mut [Origin], child: u32, o: Origin) {
    if child != INDEX_INVALID {
        origin[child as usize] = o;
    }
}
