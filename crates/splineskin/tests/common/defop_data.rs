//! Training data for the deformation-operator tests: configurations sampled about the rest
//! pose, and their ARAP solutions (the ground truth an operator is fitted to).
#![allow(dead_code)]

use kurbo::Point;
use splineskin::defop::{Arap, DefOp, DefOpOptions, SampleRegion, Sampler, SpatialBasis};
use splineskin::mesh::TriMesh;

/// `rest` followed by `count` configurations sampled (seed `seed`) with every handle in a
/// disc of `radius` about its rest position.
pub fn rest_and_disc_samples(
    rest: &[Point],
    radius: f64,
    seed: u64,
    count: usize,
) -> Vec<Vec<Point>> {
    let mut sampler = Sampler::new(rest, &[(SampleRegion::Disc { radius }, 1.0)], seed).unwrap();
    let mut configurations = vec![rest.to_vec()];
    configurations.extend(sampler.configurations(count));
    configurations
}

/// The ARAP solution of `mesh` for each configuration of the handles, each solve starting
/// from the rest mesh.
pub fn arap_solutions(
    arap: &Arap,
    mesh: &TriMesh,
    configurations: &[Vec<Point>],
) -> Vec<Vec<Point>> {
    configurations
        .iter()
        .map(|q| {
            let mut u = mesh.vertices.clone();
            arap.solve(q, &mut u).unwrap();
            u
        })
        .collect()
}

/// The operator on the hat basis of `mesh` with the default options, fitted to the
/// `solutions` at the `configurations` of the `handles`.
pub fn fit_on_hats(
    mesh: &TriMesh,
    handles: &[usize],
    configurations: &[Vec<Point>],
    solutions: &[Vec<Point>],
) -> DefOp {
    let hats = SpatialBasis::hats(mesh).unwrap();
    DefOp::fit(
        mesh,
        handles,
        &hats,
        configurations,
        solutions,
        &DefOpOptions::default(),
    )
    .unwrap()
}
