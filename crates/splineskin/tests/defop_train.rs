//! Training deformation operators (issue 7, part 3): bootstrapping stages of the paper's sizes,
//! parallel solves equal to sequential ones, progress reported for every solve, rest-pose
//! starts equal to independent cold solves, and the trained operator keeps the interpolation
//! properties. On a 4 × 1 bar with three handles.

#[path = "common/measure.rs"]
mod measure;

use measure::max_distance;
use std::sync::Mutex;

use kurbo::Rect;
use splineskin::defop::{
    flipped_triangles, train, Arap, ArapOptions, DefOpError, Energy, HandleBasisKind, Progress,
    SampleRegion, Sampler, SarapOptions, SpatialBasis, SymmetricArap, TrainOptions, WarmStart,
    TRAINING_ANDERSON_DEPTH,
};
use splineskin::mesh::TriMesh;

const HANDLES: [usize; 3] = [34, 50, 76];

/// Solutions computed in another order or on another thread: the same arithmetic, so equal;
/// 1e-12 of the diagonal allows for a different summation order should rayon split sums.
const SAME: f64 = 1e-12;

fn bar() -> TriMesh {
    TriMesh::grid(Rect::new(0., 0., 4., 1.), 16, 4).unwrap()
}

fn options(energy: Energy) -> TrainOptions {
    TrainOptions::default()
        .with_energy(energy)
        .with_n_samples(60)
        .with_regions(vec![(SampleRegion::Disc { radius: 0.5 }, 1.0)])
        .with_seed(5)
}

#[test]
fn training_stages_parallel_and_progress() {
    let mesh = bar();
    let spatial = SpatialBasis::hats(&mesh).unwrap();
    for energy in [Energy::Arap, Energy::SymmetricArap] {
        let seen = Mutex::new(Vec::new());
        let record = |p: Progress| seen.lock().unwrap().push(p.solved);
        let sequential = train(&mesh, &HANDLES, &spatial, &options(energy), &record).unwrap();
        let mut counts = seen.lock().unwrap().clone();
        assert_eq!(counts, (1..=60).collect::<Vec<_>>(), "{energy:?}");
        // 2n + 1 = 7, then ×4: 28, then the rest: 60; fitted counts include the rest pose.
        let fitted: Vec<usize> = sequential.stages.iter().map(|s| s.n_fitted).collect();
        assert_eq!(fitted, vec![8, 29, 61], "{energy:?}");
        assert_eq!(
            sequential.stages[0].handle_basis,
            HandleBasisKind::ThinPlateSpline
        );
        for s in &sequential.stages {
            eprintln!(
                "{energy:?}: {} new, iterations {:?}, {} rest starts, {:.3} s solve, {:.3} s fit",
                s.n_new, s.iterations, s.rest_starts, s.solve_seconds, s.fit_seconds
            );
            assert_eq!(s.not_converged, 0);
        }
        seen.lock().unwrap().clear();
        let parallel = train(
            &mesh,
            &HANDLES,
            &spatial,
            &options(energy).with_parallel(true),
            &record,
        )
        .unwrap();
        counts = seen.lock().unwrap().clone();
        counts.sort_unstable();
        assert_eq!(counts, (1..=60).collect::<Vec<_>>(), "{energy:?}: parallel");
        assert_eq!(parallel.configurations, sequential.configurations);
        let apart = parallel
            .solutions
            .iter()
            .zip(&sequential.solutions)
            .map(|(a, b)| max_distance(a, b))
            .fold(0.0, f64::max);
        assert!(apart <= SAME * 17f64.sqrt(), "{energy:?}: {apart:e}");
        // The trained operator reproduces the rest pose and every sample (thin-plate splines
        // on the hats), and follows the handles anywhere.
        let op = &sequential.op;
        for (q, u) in sequential.configurations.iter().zip(&sequential.solutions) {
            assert!(max_distance(&op.eval(q).unwrap(), u) < 1e-9, "{energy:?}");
        }
        let mut far = Sampler::new(
            sequential.configurations[0].as_slice(),
            &[(SampleRegion::Disc { radius: 1.0 }, 1.0)],
            77,
        )
        .unwrap();
        for q in far.configurations(10) {
            let u = op.eval(&q).unwrap();
            for (&h, &target) in HANDLES.iter().zip(&q) {
                assert!((u[h] - target).hypot() < 1e-9);
            }
        }
    }
}

#[test]
fn rest_starts_give_the_cold_ground_truth() {
    let mesh = bar();
    let spatial = SpatialBasis::hats(&mesh).unwrap();
    let arap = Arap::new(
        &mesh,
        &HANDLES,
        ArapOptions::default().with_anderson_depth(TRAINING_ANDERSON_DEPTH),
    )
    .unwrap();
    let sarap = SymmetricArap::new(&mesh, &HANDLES, SarapOptions::default()).unwrap();
    for energy in [Energy::Arap, Energy::SymmetricArap] {
        let training = train(
            &mesh,
            &HANDLES,
            &spatial,
            &options(energy).with_warm_start(WarmStart::Rest),
            &|_| {},
        )
        .unwrap();
        for (q, u) in training
            .configurations
            .iter()
            .zip(&training.solutions)
            .skip(1)
        {
            // ARAP from the rest pose; symmetric ARAP from that ARAP solution when it flips
            // nothing, else from the rest pose.
            let mut cold = mesh.vertices.clone();
            arap.solve(q, &mut cold).unwrap();
            if energy == Energy::SymmetricArap {
                if !flipped_triangles(&mesh, &cold).unwrap().is_empty() {
                    cold = mesh.vertices.clone();
                }
                assert!(sarap.solve(q, &mut cold).unwrap().converged());
            }
            assert!(max_distance(&cold, u) <= SAME, "{energy:?}");
        }
    }
}

#[test]
fn training_refuses_bad_options() {
    let mesh = bar();
    let spatial = SpatialBasis::hats(&mesh).unwrap();
    let run = |o: &TrainOptions| train(&mesh, &HANDLES, &spatial, o, &|_| {});
    assert!(matches!(
        run(&options(Energy::Arap).with_growth(1)),
        Err(DefOpError::InvalidOption { name: "growth", .. })
    ));
    assert!(matches!(
        run(&options(Energy::Arap).with_n_samples(0)),
        Err(DefOpError::InvalidOption {
            name: "n_samples",
            ..
        })
    ));
    assert!(matches!(
        run(&options(Energy::Arap).with_regions(vec![(SampleRegion::Circle { radius: -1.0 }, 1.0)])),
        Err(DefOpError::InvalidOption { .. })
    ));
    assert!(matches!(
        train(&mesh, &[34, 34], &spatial, &options(Energy::Arap), &|_| {}),
        Err(DefOpError::DuplicateHandle { .. })
    ));
    // Thin-plate splines need 2n samples besides the rest; linear operators take fewer.
    let n = HANDLES.len();
    let tps = |k: usize| {
        options(Energy::Arap)
            .with_n_samples(k)
            .with_handle_basis(HandleBasisKind::ThinPlateSpline)
    };
    let err = run(&tps(2 * n - 1)).unwrap_err();
    assert_eq!(
        err,
        DefOpError::TooFewSamples {
            handles: n,
            needed: 2 * n,
            given: 2 * n - 1
        }
    );
    assert!(err.to_string().starts_with(&format!(
        "{n} handles need at least {} training samples",
        2 * n
    )));
    assert!(run(&tps(2 * n)).is_ok());
    assert!(run(&tps(2 * n - 1).with_handle_basis(HandleBasisKind::Linear)).is_ok());
}

/// Training that covers a configuration far outside the sampling discs (the right handle lifted
/// by 1.5 on a 4 × 1 bar, discs of 0.5): the operator follows the handles there much more
/// closely than one trained on the discs alone, and still interpolates the handles.
#[test]
fn training_with_cover_follows_a_far_configuration() {
    let mesh = bar();
    let spatial = SpatialBasis::hats(&mesh).unwrap();
    let rest: Vec<_> = HANDLES.iter().map(|&h| mesh.vertices[h]).collect();
    let mut far = rest.clone();
    far[2] += kurbo::Vec2::new(0.3, 1.5);
    let base = options(Energy::SymmetricArap);
    let plain = train(&mesh, &HANDLES, &spatial, &base, &|_| {}).unwrap();
    let covered = train(
        &mesh,
        &HANDLES,
        &spatial,
        &base.clone().with_cover(vec![far.clone()]),
        &|_| {},
    )
    .unwrap();
    let truth = splineskin::defop::ground_truths_from_rest(
        &mesh,
        &HANDLES,
        &base,
        std::slice::from_ref(&far),
        &|_| {},
    )
    .unwrap()
    .remove(0);
    let error = |op: &splineskin::defop::DefOp| {
        let v = op.eval(&far).unwrap();
        max_distance(&v, &truth)
    };
    let (e_plain, e_covered) = (error(&plain.op), error(&covered.op));
    eprintln!("far configuration: largest vertex error {e_plain:.3e} (discs only), {e_covered:.3e} (covered)");
    assert!(e_covered < 0.5 * e_plain, "{e_covered:e} vs {e_plain:e}");
    let v = covered.op.eval(&far).unwrap();
    for (k, &h) in HANDLES.iter().enumerate() {
        assert!((v[h] - far[k]).hypot() < 1e-9, "handle {k}");
    }
    // The target is a sample itself, the last: the operator reproduces its ground truth there.
    let last = covered.configurations.len() - 1;
    assert_eq!(covered.configurations[last], far);
    let own = max_distance(&v, &covered.solutions[last]);
    assert!(own < 1e-8, "the covered target's own ground truth: {own:e}");
}

/// Following the user (`extend`): a configuration added to a training is reproduced by the
/// refitted operator, the handles stay interpolated at others, and the samples trained before
/// are still reproduced.
#[test]
fn extend_adds_a_configuration_the_operator_then_reproduces() {
    let mesh = bar();
    let spatial = SpatialBasis::hats(&mesh).unwrap();
    let rest: Vec<_> = HANDLES.iter().map(|&h| mesh.vertices[h]).collect();
    let base = options(Energy::SymmetricArap);
    let mut training = train(&mesh, &HANDLES, &spatial, &base, &|_| {}).unwrap();
    let n_before = training.configurations.len();
    let reach = base.reach(&mesh);
    let mut far = rest.clone();
    far[2] += kurbo::Vec2::new(0.3, 1.5);
    // Far outside the trained region; after the extension, on a sample.
    let before = splineskin::defop::trained_distance(&training.configurations, &far);
    assert!(before > reach, "{before} vs the reach {reach}");
    let solved = std::sync::atomic::AtomicUsize::new(0);
    let report = splineskin::defop::extend(&mesh, &base, &mut training, &[far.clone()], &|_| {
        solved.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    })
    .unwrap();
    assert_eq!(solved.into_inner(), 1);
    assert_eq!((report.n_new, report.n_fitted), (1, n_before + 1));
    assert_eq!(
        splineskin::defop::trained_distance(&training.configurations, &far),
        0.0
    );
    let at = training.op.eval(&far).unwrap();
    let own = max_distance(&at, &training.solutions[n_before]);
    assert!(own < 1e-8, "{own:e}");
    for k in [0, n_before / 2, n_before - 1] {
        let v = training.op.eval(&training.configurations[k]).unwrap();
        let e = max_distance(&v, &training.solutions[k]);
        assert!(e < 1e-8, "sample {k}: {e:e}");
    }
    let mut elsewhere = far.clone();
    elsewhere[0] += kurbo::Vec2::new(-0.2, 0.4);
    let v = training.op.eval(&elsewhere).unwrap();
    for (k, &h) in HANDLES.iter().enumerate() {
        assert!((v[h] - elsewhere[k]).hypot() < 1e-9, "handle {k}");
    }
}
