//! `SubdivRig::update` allocates nothing (STYLE.md: no allocation per frame), for accepted
//! poses and for the ones it refuses (wrong number of transforms, wrong buffer length).
//!
//! Its own test binary: its global allocator, which counts the requests of a thread while it
//! is inside `counting_alloc::count`, applies to the whole binary.

#[path = "common/alloc_checks.rs"]
mod alloc_checks;

use alloc_checks::assert_refusals_allocate_nothing;
use counting_alloc::{count, Counts};
use splineskin::subdiv::{
    parse_obj, Affine3, LimitOptions, LimitQuadrature, LimitSurface, SubdivRig, AFFINE3_IDENTITY,
};
use std::hint::black_box;

/// A 4 × 4 grid of quads folded into a tube: 20 vertices, boundaries at both ends.
fn tube_obj() -> String {
    let mut text = String::new();
    for j in 0..5 {
        for i in 0..4 {
            let a = std::f64::consts::FRAC_PI_2 * i as f64;
            text += &format!("v {} {} {}\n", a.cos(), a.sin(), j as f64);
        }
    }
    for j in 0..4 {
        for i in 0..4 {
            let id = |i: usize, j: usize| j * 4 + (i % 4) + 1;
            text += &format!(
                "f {} {} {} {}\n",
                id(i, j),
                id(i + 1, j),
                id(i + 1, j + 1),
                id(i, j + 1)
            );
        }
    }
    text
}

#[test]
fn subdiv_update_alloc_none() {
    // The counter counts (a counter that never counts would pass everything below).
    let (v, counts) = count(|| black_box(vec![0.0f64; 64]));
    assert_eq!(counts.allocations, 1);
    drop(v);

    let cage = parse_obj(&tube_obj(), "tube.obj").unwrap();
    let surface = LimitSurface::new(&cage, &LimitOptions::default()).unwrap();
    let q = LimitQuadrature::new(&surface, 4).unwrap();
    let mut g = vec![[0.0; 3]; q.n_nodes()];
    q.positions(cage.positions(), &mut g);
    // Three handles along the tube, weights linear in z, normalised.
    let weights: Vec<f64> = g
        .iter()
        .flat_map(|p| {
            let t = p[2] / 4.0;
            [(1.0 - t) * (1.0 - t), 2.0 * t * (1.0 - t), t * t]
        })
        .collect();
    let (rig, counts) = count(|| SubdivRig::precompute(&cage, &q, &weights, 3));
    let rig = rig.unwrap();
    assert!(counts.allocations > 0, "precompute is seen allocating");

    let mut bend = AFFINE3_IDENTITY;
    bend[0][3] = 0.8;
    let mut turn = AFFINE3_IDENTITY;
    (turn[0][0], turn[0][1], turn[1][0], turn[1][1]) = (0.0, -1.0, 1.0, 0.0);
    let poses: [[Affine3; 3]; 3] = [
        [AFFINE3_IDENTITY; 3],
        [AFFINE3_IDENTITY, bend, turn],
        [turn, turn, bend],
    ];
    let mut out = vec![[0.0; 3]; cage.n_vertices()];
    rig.update(&poses[0], &mut out).unwrap(); // warm-up
    for pose in &poses {
        out.fill([f64::NAN; 3]);
        let (result, counts) = count(|| rig.update(black_box(pose), black_box(&mut out)));
        result.unwrap();
        assert_eq!(counts, Counts::default(), "pose {pose:?}");
        assert!(
            out.iter().flatten().all(|c| c.is_finite()),
            "every point written"
        );
    }
    assert_refusals_allocate_nothing(|p, o| rig.update(p, o), &poses[1], &mut out);
}
