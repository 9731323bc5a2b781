//! Adaptive control points ([`splineskin::adaptive`]) against the refit at equal structure:
//!
//! * on the bundled fish (its three poses) and the authors' clam and turtles Shepard scenes
//!   (`../shared/data`), `ours-adaptive` (refined to 0.1 % of the diagonal) is within 0.1 % of
//!   the diagonal by closest point, and below the Schneider refit given the same curve count per
//!   path (`schneider-adaptive-count`) on max and RMS;
//! * every input anchor is kept, in order, with its position and kind, and the refined drawing
//!   traces the input's curves exactly at rest (the identity pose gives the input back);
//! * the anchors inserted are exactly the ones marked.
//!
//! The table is printed (`cargo test --test adaptive_control_points -- --nocapture`).

#[path = "common/external_data.rs"]
mod external_data;

use kurbo::{Affine, ParamCurve, Point};
use splineskin::adaptive::{refine, AdaptiveOptions};
use splineskin::compare::{compare_posed, CompareOptions, Method};
use splineskin::drawing::Drawing;
use splineskin::examples::demo_scene;
use splineskin::scene::{Compat, PosedDrawing, Scene};

/// The tolerance asked for and reached: 0.1 % of the diagonal.
const TOLERANCE: f64 = 1e-3;

/// Checks that `refined` keeps every anchor of `input` in order (position and kind) with the
/// others marked inserted, and traces the input's curves exactly.
fn assert_anchors_kept(label: &str, input: &Drawing, refined: &Drawing, inserted: &[Vec<bool>]) {
    let diag = input.diagonal();
    assert_eq!(input.paths.len(), refined.paths.len(), "{label}");
    for (p, (a, b)) in input.paths.iter().zip(&refined.paths).enumerate() {
        let kept: Vec<usize> = (0..b.joints.len()).filter(|&k| !inserted[p][k]).collect();
        assert_eq!(kept.len(), a.joints.len(), "{label}: path {p}");
        for (k, &k2) in kept.iter().enumerate() {
            assert_eq!(
                b.points[3 * k2],
                a.points[3 * k],
                "{label}: path {p} anchor {k}"
            );
            assert_eq!(b.joints[k2], a.joints[k], "{label}: path {p} joint {k}");
        }
        // Each input curve is traced by the refined curves between its anchors.
        for c in 0..a.n_curves() {
            let (first, last) = (kept[c], kept.get(c + 1).copied().unwrap_or(b.n_curves()));
            let pieces = last - first;
            let original = a.curve(c);
            // Splits are at halves: piece i of 2^m covers [i / 2^m, (i + 1) / 2^m] when all
            // pieces are at one depth; check points of each piece lie on the original.
            for i in first..last {
                let piece = b.curve(i);
                for s in [0.0, 0.3, 0.7, 1.0] {
                    let q = piece.eval(s);
                    let near = kurbo::ParamCurveNearest::nearest(&original, q, 1e-12);
                    assert!(
                        near.distance_sq.sqrt() <= 1e-9 * diag,
                        "{label}: path {p} curve {c} piece {i}/{pieces}"
                    );
                }
            }
        }
    }
}

/// Compares with the adaptive methods for `pose`, checks the claims, returns the table row.
fn check(label: &str, posed: &PosedDrawing, pose: &[Affine]) {
    let options = CompareOptions::default()
        .with_adaptive(AdaptiveOptions::default().with_tolerance(TOLERANCE));
    let c = compare_posed(posed, pose, &options).unwrap();
    let row = |m: Method| {
        let r = c.get(m).unwrap();
        (
            r.closest.overall.max,
            r.closest.overall.rms,
            r.result.n_curves(),
        )
    };
    let (ours, same, fixed) = (
        row(Method::OursAdaptive),
        row(Method::SchneiderAdaptiveCount),
        row(Method::Ours),
    );
    eprintln!(
        "{label}: ours {:.3}/{:.4} % ({} curves); ours-adaptive {:.3}/{:.4} % ({} curves); schneider-adaptive-count {:.3}/{:.4} % ({} curves)",
        100.0 * fixed.0, 100.0 * fixed.1, fixed.2,
        100.0 * ours.0, 100.0 * ours.1, ours.2,
        100.0 * same.0, 100.0 * same.1, same.2
    );
    assert!(ours.0 <= TOLERANCE, "{label}: {ours:?}");
    assert!(
        ours.0 < same.0 && ours.1 < same.1,
        "{label}: {ours:?} vs {same:?}"
    );
    assert!(same.2 <= ours.2, "{label}: the refit got more curves");

    // The refinement itself: anchors kept, insertions marked, the rest pose exact.
    let drawing = posed.drawing();
    let refined = refine(
        drawing,
        posed.weights(),
        posed.fit_options(),
        &[pose.to_vec()],
        &AdaptiveOptions::default().with_tolerance(TOLERANCE),
    )
    .unwrap();
    assert!(refined.met, "{label}");
    assert_eq!(refined.drawing.n_curves(), ours.2, "{label}");
    assert_eq!(
        refined.n_inserted(),
        refined.drawing.n_curves() - drawing.n_curves(),
        "{label}"
    );
    assert_anchors_kept(label, drawing, &refined.drawing, &refined.inserted);
    let mut out = vec![Point::ZERO; refined.drawing.n_points()];
    refined
        .rig
        .update(&vec![Affine::IDENTITY; posed.n_handles()], &mut out)
        .unwrap();
    let diag = drawing.diagonal();
    let identity = refined
        .drawing
        .flat_points()
        .iter()
        .zip(&out)
        .map(|(a, b)| (*a - *b).hypot() / diag)
        .fold(0.0, f64::max);
    assert!(identity <= 1e-9, "{label}: identity {identity:e}");
}

#[test]
fn adaptive_bundled_fish_reaches_the_tolerance_and_beats_the_refit() {
    let scene = demo_scene();
    let posed = PosedDrawing::from_scene(&scene, Compat::None, false).unwrap();
    for pose in &scene.poses {
        let label = format!("fish {:?}", pose.name.as_deref().unwrap_or(""));
        check(&label, &posed, &pose.transforms);
    }
}

#[test]
fn adaptive_authors_clam_and_turtles() {
    let Some(root) = external_data::shared_data() else {
        return;
    };
    for source in [
        "clam-songrun/clam-Our-shepard/clam-songrun-deformation.json",
        "clam-songrun/clam-Ours2-Shepard/clam-songrun-deformation.json",
        "turtle-seven-stack/comparison/shepard ours/turtles-seven-deformation.json",
    ] {
        let file = root.join("vectorskinning").join(source);
        let scene = Scene::load(&file).unwrap();
        let posed = PosedDrawing::from_scene(&scene, Compat::None, false).unwrap();
        let pose = scene.pose(0).unwrap().transforms;
        check(source, &posed, &pose);
    }
}

#[test]
fn adaptive_refuses_bad_options() {
    let scene = demo_scene();
    let posed = PosedDrawing::from_scene(&scene, Compat::None, false).unwrap();
    let pose = vec![Affine::IDENTITY; posed.n_handles()];
    let refine_with = |tolerance: f64, poses: &[Vec<Affine>]| {
        refine(
            posed.drawing(),
            posed.weights(),
            posed.fit_options(),
            poses,
            &AdaptiveOptions::default().with_tolerance(tolerance),
        )
        .err()
        .map(|e| e.to_string())
    };
    assert!(refine_with(0.0, std::slice::from_ref(&pose))
        .unwrap()
        .contains("tolerance"));
    assert!(refine_with(f64::NAN, std::slice::from_ref(&pose))
        .unwrap()
        .contains("tolerance"));
    assert!(refine_with(1e-3, &[]).unwrap().contains("no poses"));
    let short = vec![Affine::IDENTITY; 2];
    assert!(refine_with(1e-3, &[short]).unwrap().contains("pose 0"));
    // The identity needs nothing: no split.
    let refined = refine(
        posed.drawing(),
        posed.weights(),
        posed.fit_options(),
        &[pose],
        &AdaptiveOptions::default(),
    )
    .unwrap();
    assert!(refined.met && refined.n_inserted() == 0 && refined.rounds == 0);
}
