//! `PosedDrawing::update` with the fixed-ratio rig allocates nothing (STYLE.md: no allocation
//! per frame): the rig's product, the finiteness check and the report, for every pose of the
//! bundled scene and for rejected poses and buffers; and its result is the rig's, exactly.
//! `Puppet::update` (the editor's layer over it) allocates nothing either once its rig is built.
//!
//! Its own test binary: its global allocator, which counts the requests of a thread while it
//! is inside `counting_alloc::count`, applies to the whole binary.

#[path = "common/alloc_checks.rs"]
mod alloc_checks;

use alloc_checks::{assert_counter_counts, assert_refusals_allocate_nothing, demo_posed};
use counting_alloc::{count, Counts};
use kurbo::{Affine, Point};
use splineskin::scene::{Compat, Puppet};
use std::hint::black_box;

#[test]
fn posed_update_alloc_none_with_the_fixed_rig() {
    assert_counter_counts();

    let (scene, posed) = demo_posed();
    assert!(posed.rig().is_some() && !posed.is_flexible());
    let n = posed.n_handles();
    let mut poses: Vec<Vec<Affine>> = scene.poses.iter().map(|p| p.transforms.clone()).collect();
    poses.push(vec![Affine::IDENTITY; n]);
    poses.push(
        (0..n)
            .map(|i| Affine::rotate(0.1 * i as f64) * Affine::translate((3.0 * i as f64, 0.0)))
            .collect(),
    );
    let mut out = vec![Point::ZERO; posed.n_points()];
    let mut expected = out.clone();
    posed.update(&poses[0], &mut out).unwrap(); // warm-up
    for pose in &poses {
        out.fill(Point::new(f64::NAN, f64::NAN));
        let (result, counts) = count(|| posed.update(black_box(pose), black_box(&mut out)));
        let report = result.unwrap();
        assert_eq!(counts, Counts::default(), "pose {pose:?}");
        assert!(report.flexible.is_none() && report.note().is_none());
        posed.rig().unwrap().update(pose, &mut expected).unwrap();
        assert_eq!(out, expected, "the rig's result");
    }
    assert_refusals_allocate_nothing(|p, o| posed.update(p, o), &poses[0], &mut out);

    // The editor's layer: a pose change and an update, with the rig built, allocate nothing.
    let mut puppet = Puppet::from_scene(&scene, Compat::None).unwrap();
    puppet.update(&mut out).unwrap();
    for pose in &poses {
        let (result, counts) = count(|| {
            puppet.set_pose(black_box(pose))?;
            puppet.update(black_box(&mut out))
        });
        result.unwrap();
        assert_eq!(counts, Counts::default(), "puppet, pose {pose:?}");
    }
}
