//! The fold check an interactive tool runs after every frame
//! ([`splineskin::folds::FoldCheck::new_crossings_into`]) allocates nothing once its scratch and
//! output have grown to the drawing's size (STYLE.md: no allocation per frame), and finds what
//! the allocating form finds, on the bundled fish in every pose of its scene and on a pose that
//! folds it.
//!
//! Its own test binary: its global allocator, which counts the requests of a thread while it
//! is inside `counting_alloc::count`, applies to the whole binary.

#[path = "common/alloc_checks.rs"]
mod alloc_checks;

use alloc_checks::{assert_counter_counts, demo_posed};
use counting_alloc::{count, Counts};
use kurbo::{Affine, Point};
use splineskin::folds::{FoldCheck, FoldScratch};
use std::hint::black_box;

#[test]
fn fold_check_alloc_none_with_warm_scratch() {
    assert_counter_counts();
    let (scene, posed) = demo_posed();
    let drawing = posed.drawing();
    let rest = drawing.flat_points();
    let check = FoldCheck::new(drawing, &rest);
    let n = posed.n_handles();
    let mut poses: Vec<Vec<Affine>> = scene.poses.iter().map(|p| p.transforms.clone()).collect();
    // The first handle swung far round: the outline folds over itself.
    let mut folding = vec![Affine::IDENTITY; n];
    folding[0] = Affine::rotate_about(2.6, rest[0]);
    poses.push(folding);
    let mut deformed: Vec<Vec<Point>> = Vec::new();
    for pose in &poses {
        let mut out = vec![Point::ZERO; posed.n_points()];
        posed.update(pose, &mut out).unwrap();
        deformed.push(out);
    }
    let (mut scratch, mut out) = (FoldScratch::default(), Vec::new());
    // Warm-up: every buffer grows to its largest size.
    for points in &deformed {
        check.new_crossings_into(drawing, points, &mut scratch, &mut out);
    }
    let mut folds_seen = 0;
    for points in &deformed {
        let ((), counts) =
            count(|| check.new_crossings_into(drawing, black_box(points), &mut scratch, &mut out));
        assert_eq!(counts, Counts::default());
        assert_eq!(
            out,
            check.new_crossings(drawing, points),
            "the allocating form's answer"
        );
        folds_seen += out.len();
    }
    assert!(folds_seen > 0, "the folding pose should fold the fish");
}
