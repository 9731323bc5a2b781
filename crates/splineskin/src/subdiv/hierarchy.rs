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

use super::cage::Cage;
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

/// The Sdc options of every refinement here (module documentation of [`crate::subdiv`]).
pub(crate) fn sdc_options() -> sdc::Options {
    sdc::Options::default()
        .with_vtx_boundary_interpolation(sdc::VtxBoundaryInterpolation::EdgeAndCorner)
        .with_creasing_method(sdc::CreasingMethod::Uniform)
        .with_triangle_subdivision(sdc::TriangleSubdivision::Catmark)
}

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
        let creases: Vec<[u32; 2]> = cage.tags().creases.iter().map(|c| c.vertices).collect();
        let crease_weights: Vec<f32> = cage
            .tags()
            .creases
            .iter()
            .map(|c| c.sharpness as f32)
            .collect();
        let corners: Vec<u32> = cage.tags().corners.iter().map(|c| c.vertex).collect();
        let corner_weights: Vec<f32> = cage
            .tags()
            .corners
            .iter()
            .map(|c| c.sharpness as f32)
            .collect();
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

fn set_origin(origin: &mut [Origin], child: u32, o: Origin) {
    if child != INDEX_INVALID {
        origin[child as usize] = o;
    }
}
