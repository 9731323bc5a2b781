//! The paper authors' scenes with bounded biharmonic weights, deformed in default mode (our
//! domain triangulation, our BBW solve, our fit), against their solver's output, curve against
//! curve. Their 2014 BBW weights came from Triangle on integer-rounded samples and an older
//! QP, so they are not reproducible exactly: the requirement is 2 % of the bounding-box
//! diagonal.

mod common;

use common::authors_outputs::AuthorsCase;
use common::scene_compare::{default_mode_distance, deform, scene_of};
use splineskin::scene::Compat;

/// Agreement required, as a fraction of the bounding-box diagonal.
const TOLERANCE: f64 = 2e-2;

fn mesh_weight_cases(root: &std::path::Path) -> Vec<AuthorsCase> {
    let dir = root.join("vectorskinning/authors-solver-outputs");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("authors-solver-outputs")
        .map(|e| e.expect("dir entry").path())
        .filter(|f| f.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    files
        .iter()
        .map(|f| AuthorsCase::load(f))
        .filter(|c| {
            (c.weight_function == "bbw" || c.weight_function == "harmonic")
                && c.engine_type == "ours"
        })
        .collect()
}

/// Cases not yet within [`TOLERANCE`], with the figure measured when they were listed: issue 4
/// is open until this list is empty. Cases with the authors' flexible G¹/angle joints (solved
/// by their nonlinear iteration, issue 5) are reported, not asserted.
const OPEN_CASES: &[(&str, f64)] = &[
    ("clam-songrun__reflexed-lookdown", 1.74e-1),
    ("turtle-seven-stack__wobble__2", 3.07e-2),
];

#[test]
fn authors_bbw_scenes_deform_as_their_solver() {
    let Some(root) = common::data_root() else {
        return;
    };
    let cases = mesh_weight_cases(&root);
    assert_eq!(cases.len(), 20, "the authors' BBW cases");
    // Two threads: each case triangulates its domain and solves BBW.
    let (even, odd): (Vec<_>, Vec<_>) = cases.iter().enumerate().partition(|(i, _)| i % 2 == 0);
    let run = |part: Vec<(usize, &AuthorsCase)>| -> Vec<(String, f64, bool)> {
        part.into_iter()
            .map(|(_, case)| {
                let scene = scene_of(&root, case);
                let (theirs, _, singular) = deform(&scene, Compat::VectorSkinning);
                let diag = theirs.diagonal();
                let (ours, points, _) = deform(&scene, Compat::None);
                let d = default_mode_distance(case, &theirs, &ours, &points, &singular, diag);
                (case.case.clone(), d, case.has_flexible_joints())
            })
            .collect()
    };
    let report: Vec<(String, f64, bool)> = std::thread::scope(|s| {
        let a = s.spawn(|| run(even));
        let b = run(odd);
        let mut all = a.join().expect("worker");
        all.extend(b);
        all
    });
    for (name, d, flexible) in &report {
        eprintln!("{name}: default mode {d:.2e} of the diagonal (flexible joints: {flexible})");
    }
    for (name, d, flexible) in &report {
        if *flexible {
            continue;
        }
        match OPEN_CASES.iter().find(|(open, _)| name.starts_with(open)) {
            // Still open: must not get worse (and must be removed from the list when fixed).
            Some((_, measured)) => {
                assert!(
                    *d > TOLERANCE,
                    "{name}: now {d:e}, remove it from OPEN_CASES"
                );
                assert!(*d <= measured * 1.05, "{name}: {d:e} (was {measured:e})");
            }
            None => assert!(*d <= TOLERANCE, "{name}: {d:e}"),
        }
    }
}
