//! Checks shared by the allocation tests (each its own test binary; they include this file by
//! `#[path]`, which installs the counting global allocator for the binary).
#![allow(dead_code)]

use counting_alloc::{count, CountingAlloc, Counts};
use splineskin::examples::demo_scene;
use splineskin::scene::{Compat, PosedDrawing, Scene};
use std::hint::black_box;

#[global_allocator]
static ALLOCATOR: CountingAlloc = CountingAlloc;

/// The bundled demo scene and its drawing posed by the scene's own engine (no compatibility
/// mode, fixed ratios).
pub fn demo_posed() -> (Scene, PosedDrawing) {
    let scene = demo_scene();
    let posed = PosedDrawing::from_scene(&scene, Compat::None, false).unwrap();
    (scene, posed)
}

/// Asserts that the counter sees an allocation made on purpose (a counter that never counts,
/// e.g. because the allocator is not installed, would pass every other check).
pub fn assert_counter_counts() {
    let (_, counts) = count(|| black_box(vec![0u8; 16]));
    assert_eq!(counts.allocations, 1, "the counter counts");
}

/// Asserts that `update` refuses a pose one map short of `pose` and an output one element
/// short of `out` (both right for it), and allocates nothing to do so.
pub fn assert_refusals_allocate_nothing<P, O, T, E>(
    mut update: impl FnMut(&[P], &mut [O]) -> Result<T, E>,
    pose: &[P],
    out: &mut [O],
) {
    let (result, counts) = count(|| update(black_box(&pose[1..]), black_box(&mut *out)));
    assert!(result.is_err());
    assert_eq!(counts, Counts::default(), "rejected pose");
    let (result, counts) = count(|| update(black_box(pose), black_box(&mut out[1..])));
    assert!(result.is_err());
    assert_eq!(counts, Counts::default(), "rejected buffer");
}
