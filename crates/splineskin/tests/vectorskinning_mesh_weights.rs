//! The paper authors' scenes with bounded biharmonic weights, deformed in default mode (our
//! domain triangulation, our BBW solve, our fit), against their solver's output, curve against
//! curve. Their 2014 BBW weights came from Triangle on integer-rounded samples and an older
//! QP, so they are not reproducible exactly: the requirement is 2 % of the bounding-box
//! diagonal.
//!
//! Where the authors' BBW solve failed, their code silently used Shepard weights instead
//! (`bbw_fell_back_to_shepard` in the case file), so that reference is a Shepard deformation
//! whatever the scene says. For those cases the test also deforms the scene with the weights
//! their solver did use (Shepard, `1/d²`): in compatibility mode it must reproduce their
//! output exactly (which shows the reference is Shepard), in default mode within the
//! tolerance. Why their solve failed is in [`OPEN_CASES`].

mod common;

use common::authors_outputs::{self, AuthorsCase};
use common::scene_compare::{default_mode_distance, deform, deform_flexible, scene_of};
use splineskin::scene::{Compat, Scene, WeightSpec};

/// Agreement required, as a fraction of the bounding-box diagonal.
const TOLERANCE: f64 = 2e-2;

/// Agreement required in compatibility mode with the weights the authors' solver used, as a
/// fraction of the diagonal: 1e-9 (measured 2.5e-13 and 7.7e-13).
const EXACT: f64 = 1e-9;

fn mesh_weight_cases(root: &std::path::Path) -> Vec<AuthorsCase> {
    authors_outputs::cases_where(root, |c| {
        (c.weight_function == "bbw" || c.weight_function == "harmonic") && c.engine_type == "ours"
    })
}

/// Cases not within [`TOLERANCE`], with the figure measured when they were listed (they must
/// not get worse, and must leave the list when they pass). Cases with the authors' flexible
/// G¹/angle joints (solved by their nonlinear iteration) are compared with our flexible solve
/// (`spline_fit::flexible`, default mode); the fixed-ratio figure is reported beside it.
///
/// The two cases listed cannot pass by any change of ours: their reference is not a BBW
/// deformation. The authors' BBW solve failed on their own domain and their code fell back to
/// Shepard weights; with Shepard weights our default mode is within 5.8e-5 and 3.6e-4 of the
/// diagonal of their output (asserted below), and our BBW weights, on a valid domain, are what
/// the scenes ask for. Why their solve failed, replayed outside the repository with their
/// domain construction (100 samples per curve, samples and handles rounded to integers and
/// de-duplicated, the boundary loop of one closed path, Triangle `-pqa100`) and libigl 2.6.3's
/// `bbw`:
///
/// * `clam-songrun/reflexed-lookdown`: the boundary is path 0, the outline. Path 5 (the lower
///   jaw) runs along it up to 0.22 px outside it, and 121 of its de-duplicated samples fall
///   outside the rounded boundary loop. Triangle leaves them in no triangle, those vertices
///   have empty rows in the biharmonic system, and `bbw` fails. The same replay succeeds on
///   `clam-Ours-BBW`, whose path 5 lies exactly on its outline; none of the other 18 BBW cases
///   has a sample outside its loop. Our domain is the same outline (samples within one sample
///   spacing of it count as on it).
/// * `turtle-seven-stack/wobble 2`: their editor takes the boundary as the position of the
///   largest bounding box among the *closed* paths (`argmax([bbox_area for closed paths])`),
///   then uses that position as an index into *all* paths. The seven open paths before the
///   outline (path 140) shift it to path 133, a small closed path (16 triangles): all three
///   handles and 12 600 of 12 614 vertices are outside it and `bbw` fails (with path 140 it
///   succeeds). Their 2014 overlay agrees with the Shepard output within 6.3e-5 px
///   (`comparison_with_stored_output`), so their editor fell back then too. Our domain is the
///   outline.
///
/// The two caterpillar cases were listed here at 2.67e-2 and 2.02e-2 while our domain was the
/// padded bounding box: the outline (path 4) was refused as a boundary because its closing
/// curve crosses itself in a tiny loop, so the body's weights leaked across the gaps between
/// its legs. With such loops cut off (`domain::polygon::without_small_loops`) the outline is
/// the domain, as for the authors, and the cases pass (1.49e-2 and 3.65e-3).
const OPEN_CASES: &[(&str, f64)] = &[
    ("clam-songrun__reflexed-lookdown", 1.73e-1),
    ("turtle-seven-stack__wobble__2", 3.06e-2),
];

/// The scene with the weights the authors' code falls back to: Shepard, `1/d²`.
fn with_shepard_weights(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    s.weights = WeightSpec::Shepard { exponent: 2.0 };
    s
}

/// What one case measured: name, default mode against the reference (fixed ratio, and flexible
/// for cases with flexible joints), and for
/// a reference that fell back to Shepard the distances with Shepard weights (default mode,
/// compatibility mode).
struct Measured {
    name: String,
    default_mode: f64,
    /// Flexible cases: default mode with our flexible solve.
    flexible_mode: Option<f64>,
    shepard: Option<(f64, f64)>,
}

#[test]
fn authors_bbw_scenes_deform_as_their_solver() {
    let Some(root) = common::data_root() else {
        return;
    };
    let cases = mesh_weight_cases(&root);
    assert_eq!(cases.len(), 20, "the authors' BBW cases");
    // Two threads: each case triangulates its domain and solves BBW.
    let (even, odd): (Vec<_>, Vec<_>) = cases.iter().enumerate().partition(|(i, _)| i % 2 == 0);
    let run = |part: Vec<(usize, &AuthorsCase)>| -> Vec<Measured> {
        part.into_iter()
            .map(|(_, case)| {
                let scene = scene_of(&root, case);
                let (theirs, _, singular) = deform(&scene, Compat::VectorSkinning);
                let diag = theirs.diagonal();
                let distance = |scene: &Scene, compat: Compat| {
                    let (ours, points, _) = deform(scene, compat);
                    default_mode_distance(case, &theirs, &ours, &points, &singular, diag)
                };
                let shepard = (case.bbw_fell_back_to_shepard == Some(true)).then(|| {
                    let s = with_shepard_weights(&scene);
                    (
                        distance(&s, Compat::None),
                        distance(&s, Compat::VectorSkinning),
                    )
                });
                let flexible = case.has_flexible_joints();
                let flexible_mode = flexible.then(|| {
                    let (ours, points, _, _) = deform_flexible(&scene, Compat::None, None);
                    default_mode_distance(case, &theirs, &ours, &points, &singular, diag)
                });
                Measured {
                    name: case.case.clone(),
                    default_mode: distance(&scene, Compat::None),
                    flexible_mode,
                    shepard,
                }
            })
            .collect()
    };
    let report: Vec<Measured> = std::thread::scope(|s| {
        let a = s.spawn(|| run(even));
        let b = run(odd);
        let mut all = a.join().expect("worker");
        all.extend(b);
        all
    });
    for m in &report {
        match m.flexible_mode {
            Some(f) => eprintln!(
                "{}: default mode {f:.2e} of the diagonal with flexible joints ({:.2e} with the \
                 fixed-ratio fit)",
                m.name, m.default_mode
            ),
            None => eprintln!(
                "{}: default mode {:.2e} of the diagonal",
                m.name, m.default_mode
            ),
        }
        if let Some((default_mode, compat)) = m.shepard {
            eprintln!(
                "  their BBW fell back to Shepard; with Shepard weights: default mode {default_mode:.2e}, compatibility mode {compat:.2e}"
            );
        }
    }
    for m in &report {
        let name = &m.name;
        if let Some((default_mode, compat)) = m.shepard {
            assert!(
                compat <= EXACT,
                "{name}: Shepard, compatibility mode {compat:e}"
            );
            assert!(
                default_mode <= TOLERANCE,
                "{name}: Shepard, default mode {default_mode:e}"
            );
        }
    }
    for m in &report {
        let (name, d) = (&m.name, m.flexible_mode.unwrap_or(m.default_mode));
        let listed = |open: &str| name == open || name.starts_with(&format!("{open}__"));
        match OPEN_CASES.iter().find(|(open, _)| listed(open)) {
            // Still open: must not get worse (and must be removed from the list when fixed).
            Some((_, measured)) => {
                assert!(
                    d > TOLERANCE,
                    "{name}: now {d:e}, remove it from OPEN_CASES"
                );
                assert!(d <= measured * 1.05, "{name}: {d:e} (was {measured:e})");
            }
            None => assert!(d <= TOLERANCE, "{name}: {d:e}"),
        }
    }
}
