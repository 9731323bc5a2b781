//! `SplineRig::update` allocates nothing (STYLE.md: no allocation per frame): on the bundled
//! drawing and on a tiling of it to about ten thousand curves, after a warm-up call, every
//! pose (the scene's, the identity, general affine maps) and the rejected ones (wrong number of
//! transforms, wrong buffer length) make no allocator request at all; also when the tiled
//! drawing's update is split over two threads, and when it reads single-precision entries.
//!
//! This file is its own test binary because its global allocator, which counts the requests
//! of a thread while it is inside `counting_alloc::count`, applies to the whole binary.

#[path = "common/alloc_checks.rs"]
mod alloc_checks;

use alloc_checks::assert_refusals_allocate_nothing;
use counting_alloc::{count, Counts};
use kurbo::{Affine, Point};
use splineskin::drawing::{read_svg, Drawing, ImportOptions};
use splineskin::examples::{demo_scene, tile, DEMO_SVG};
use splineskin::spline_fit::{FitOptions, Measure, SplineRig};
use splineskin::weights::{Shepard, ShepardOptions};
use std::hint::black_box;

/// Curves of the tiled drawing: about ten thousand, a large frame.
const TILED_CURVES: usize = 10_000;

/// Asserts that `update` makes no allocator request for any of `poses`, nor when it rejects a
/// pose or buffer of the wrong size.
fn assert_update_allocates_nothing(drawing: &Drawing, handles: &[Point], poses: &[Vec<Affine>]) {
    let weights = Shepard::new(handles, ShepardOptions::default());
    for measure in [Measure::LengthWeighted, Measure::ArcLength] {
        let options = FitOptions::default().with_measure(measure);
        let rig = SplineRig::precompute(drawing, &weights, &options).unwrap();
        let mut out = vec![Point::ZERO; rig.n_points()];
        rig.update(&poses[0], &mut out).unwrap(); // warm-up
        for pose in poses {
            out.fill(Point::new(f64::NAN, f64::NAN));
            let (result, counts) = count(|| rig.update(black_box(pose), black_box(&mut out)));
            result.unwrap();
            assert_eq!(counts, Counts::default(), "{measure:?}, pose {pose:?}");
            // The frame was computed inside the window: every point was written.
            assert!(out.iter().all(|p| p.is_finite()));
        }
        assert_refusals_allocate_nothing(|p, o| rig.update(p, o), &poses[0], &mut out);
    }
}

/// The identity, a similarity and a general affine map on every handle, and a different map
/// per handle.
fn test_poses(handles: &[Point]) -> Vec<Vec<Affine>> {
    let n = handles.len();
    let similarity = Affine::translate((37.0, -21.0)) * Affine::rotate(0.7) * Affine::scale(1.6);
    let general = Affine::new([1.3, 0.4, -0.7, 0.9, 12.0, -5.0]);
    let per_handle = (0..n)
        .map(|i| Affine::rotate(0.1 * i as f64) * Affine::translate((3.0 * i as f64, 0.0)))
        .collect();
    vec![
        vec![Affine::IDENTITY; n],
        vec![similarity; n],
        vec![general; n],
        per_handle,
    ]
}

/// The counter sees what it is meant to: an allocation, a free and a reallocation made on
/// purpose inside the window, and nothing outside it. Without this, a counter that never
/// counts would let every test here pass.
#[test]
fn update_alloc_counter_counts() {
    let (v, counts) = count(|| black_box(vec![0.0f64; 64]));
    assert_eq!(counts.allocations, 1);
    let ((), counts) = count(|| drop(black_box(v)));
    assert_eq!(counts.deallocations, 1);
    let (_, counts) = count(|| {
        let mut v = black_box(Vec::<Point>::with_capacity(1));
        v.extend((0..100).map(|i| Point::new(i as f64, 0.0)));
        black_box(v)
    });
    assert!(counts.allocations >= 2, "{counts:?}");
    // A rig's own allocations are seen too: precomputing allocates.
    let drawing = read_svg(DEMO_SVG, &ImportOptions::default()).unwrap();
    let handles = demo_scene().handles;
    let weights = Shepard::new(&handles, ShepardOptions::default());
    let (rig, counts) = count(|| SplineRig::precompute(&drawing, &weights, &FitOptions::default()));
    assert!(rig.is_ok() && counts.allocations > 0, "{counts:?}");
}

#[test]
fn update_alloc_none_on_the_bundled_drawing() {
    let drawing = read_svg(DEMO_SVG, &ImportOptions::default()).unwrap();
    let scene = demo_scene();
    let mut poses = test_poses(&scene.handles);
    poses.extend(scene.poses.iter().map(|p| p.transforms.clone()));
    assert_update_allocates_nothing(&drawing, &scene.handles, &poses);
}

#[test]
fn update_alloc_none_on_several_threads_and_in_single_precision() {
    let drawing = read_svg(DEMO_SVG, &ImportOptions::default()).unwrap();
    let (tiled, handles) = tile(&drawing, &demo_scene().handles, TILED_CURVES);
    let weights = Shepard::new(&handles, ShepardOptions::default());
    let serial = SplineRig::precompute(&tiled, &weights, &FitOptions::default()).unwrap();
    let options = FitOptions::default().with_parallel(true);
    let split = SplineRig::precompute(&tiled, &weights, &options).unwrap();
    assert!(serial.update_bytes() >= 8 << 20, "large enough to split");
    assert_eq!(serial.update_threads(), 1);
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    assert_eq!(
        split.update_threads(),
        splineskin::spline_fit::update_threads(split.update_bytes(), cores)
    );
    assert!(split.update_threads() >= 2 || cores == 1);
    let single = split.with_single_precision(true);
    let poses = test_poses(&handles);
    let mut expected = vec![Point::ZERO; serial.n_points()];
    let mut out = expected.clone();
    for rig in [&split, &single] {
        rig.update(&poses[0], &mut out).unwrap(); // warm-up
        for pose in &poses {
            out.fill(Point::new(f64::NAN, f64::NAN));
            let (result, counts) = count(|| rig.update(black_box(pose), black_box(&mut out)));
            result.unwrap();
            assert_eq!(counts, Counts::default(), "pose {pose:?}");
            serial.update(pose, &mut expected).unwrap();
            if rig.is_single_precision() {
                // Entries rounded to f32: within 1e-6 of the drawing's diagonal here (the
                // tiling lies within a few thousand units of the origin).
                let gap = out
                    .iter()
                    .zip(&expected)
                    .map(|(a, b)| (*a - *b).hypot())
                    .fold(0.0, f64::max);
                assert!(gap <= 1e-6 * tiled.diagonal(), "{gap}");
            } else {
                assert_eq!(
                    out, expected,
                    "two threads give the one-thread result exactly"
                );
            }
        }
        assert_refusals_allocate_nothing(|p, o| rig.update(p, o), &poses[0], &mut out);
    }
}

#[test]
fn update_alloc_none_on_a_tiled_drawing() {
    let drawing = read_svg(DEMO_SVG, &ImportOptions::default()).unwrap();
    let (tiled, handles) = tile(&drawing, &demo_scene().handles, TILED_CURVES);
    assert!(tiled.n_curves() >= TILED_CURVES);
    assert_update_allocates_nothing(&tiled, &handles, &test_poses(&handles));
}
