//! Trains a deformation operator on the octopus (1 991 vertices, 3 377 triangles, 9 handles:
//! [`splineskin::examples::octopus_domain`]) and measures it: training time per stage against
//! the issue's budget (1 000 samples in 2 minutes on 2 cores), evaluations per second, and the
//! error against the ground truth on held-out configurations (solved from the rest pose, and
//! from the operator's prediction). The error of every handle basis for growing sample counts
//! (the paper's Fig. 8) is `splineskin defop study` ([`splineskin::defop::study()`]).
//!
//! ```text
//! cargo run --release -p splineskin --example defop_train -- [arap|sarap] [SAMPLES] [hats|eigen:K|biharmonic:K] [linear|quadratic|cubic|tps] [bootstrap|rest]
//! ```
//!
//! Defaults: `sarap 1000 hats tps bootstrap`. Samples are drawn uniformly in discs of radius
//! 0.4 around the handles (the arms are 2.2 long); solves run on rayon's pool. A progress bar
//! is drawn on stderr when it is a terminal.

use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};
use kurbo::Point;
use splineskin::defop::{
    ground_truths_from_rest, l2_distance, train, Arap, ArapOptions, DefOp, EigenOperator, Energy,
    HandleBasisKind, SampleRegion, Sampler, SarapOptions, SpatialBasis, SymmetricArap,
    TrainOptions, WarmStart, TRAINING_ANDERSON_DEPTH,
};
use splineskin::examples::octopus_domain;

/// Largest triangle, as a fraction of the bounding box: the benchmark octopus.
const AREA_FRACTION: f64 = 1.0 / 1800.0;
/// Disc radius of the samples (drawing units).
const RADIUS: f64 = 0.4;
/// Held-out configurations for the error.
const N_HELD_OUT: usize = 20;
/// Evaluations timed.
const N_EVALUATIONS: usize = 2000;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let has = |word: &str| args.iter().any(|a| a == word);
    let energy = if has("arap") {
        Energy::Arap
    } else {
        Energy::SymmetricArap
    };
    let n_samples: usize = args.iter().find_map(|a| a.parse().ok()).unwrap_or(1000);
    let basis = [
        ("linear", HandleBasisKind::Linear),
        ("quadratic", HandleBasisKind::Quadratic),
        ("cubic", HandleBasisKind::Cubic),
        ("tps", HandleBasisKind::ThinPlateSpline),
    ]
    .into_iter()
    .find(|(name, _)| has(name))
    .map_or(HandleBasisKind::ThinPlateSpline, |(_, k)| k);
    let warm_start = if has("rest") {
        WarmStart::Rest
    } else {
        WarmStart::Bootstrap
    };
    let domain = octopus_domain(AREA_FRACTION).expect("octopus");
    let (mesh, handles) = (domain.mesh, domain.handle_vertices);
    let spatial_arg = args
        .iter()
        .find(|a| a.starts_with("eigen") || a.starts_with("biharmonic") || *a == "hats")
        .cloned()
        .unwrap_or_else(|| "hats".into());
    let clock = Instant::now();
    let spatial = match spatial_arg.split_once(':') {
        Some(("eigen", k)) => SpatialBasis::laplacian_eigenfunctions(
            &mesh,
            k.parse().expect("eigen:K"),
            EigenOperator::LinearlyPrecise,
        ),
        Some(("biharmonic", k)) => SpatialBasis::biharmonic_coordinates_sampled(
            &mesh,
            &handles,
            k.parse().expect("biharmonic:K"),
        ),
        _ => SpatialBasis::hats(&mesh),
    }
    .expect("spatial basis");
    eprintln!(
        "octopus: {} vertices, {} triangles, {} handles; {energy:?}, {n_samples} samples, {spatial_arg} ({} functions, {:.2} s), {}, {warm_start:?}, {} threads",
        mesh.n_vertices(),
        mesh.n_triangles(),
        handles.len(),
        spatial.n_functions(),
        clock.elapsed().as_secs_f64(),
        basis.name(),
        rayon::current_num_threads()
    );
    let options = TrainOptions::default()
        .with_energy(energy)
        .with_n_samples(n_samples)
        .with_regions(vec![(SampleRegion::Disc { radius: RADIUS }, 1.0)])
        .with_handle_basis(basis)
        .with_warm_start(warm_start)
        .with_parallel(true);
    let bar = ProgressBar::new(n_samples as u64);
    bar.set_style(
        ProgressStyle::with_template(
            "{elapsed_precise} [{bar:40}] {pos}/{len} ground truths {msg}",
        )
        .expect("template"),
    );
    let clock = Instant::now();
    let training = train(&mesh, &handles, &spatial, &options, &|p| {
        bar.set_position(p.solved as u64);
        bar.set_message(format!("stage {}/{}", p.stage + 1, p.n_stages));
    })
    .expect("training");
    bar.finish_and_clear();
    let seconds = clock.elapsed().as_secs_f64();
    for (i, s) in training.stages.iter().enumerate() {
        eprintln!(
            "stage {i}: {:>4} new samples, {:>4} fitted ({}), iterations min {} mean {:.1} max {}, {} ARAP starts, {} rest starts, {} not converged, solve {:.2} s, fit {:.2} s",
            s.n_new,
            s.n_fitted,
            s.handle_basis.name(),
            s.iterations.0,
            s.iterations.1,
            s.iterations.2,
            s.arap_starts,
            s.rest_starts,
            s.not_converged,
            s.solve_seconds,
            s.fit_seconds
        );
    }
    eprintln!("training: {seconds:.1} s (budget 120 s)");

    // Evaluation speed.
    let op = &training.op;
    let rest: Vec<Point> = handles.iter().map(|&h| mesh.vertices[h]).collect();
    let mut held_out_sampler = Sampler::new(
        &rest,
        &[(SampleRegion::Disc { radius: RADIUS }, 1.0)],
        424242,
    )
    .unwrap();
    let held_out = held_out_sampler.configurations(N_HELD_OUT);
    let mut evaluator = op.evaluator();
    let mut positions = vec![Point::ZERO; mesh.n_vertices()];
    let clock = Instant::now();
    for k in 0..N_EVALUATIONS {
        evaluator
            .eval(&held_out[k % N_HELD_OUT], &mut positions)
            .unwrap();
    }
    let per_second = N_EVALUATIONS as f64 / clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    for k in 0..N_EVALUATIONS {
        std::hint::black_box(
            evaluator
                .spatial_coefficients(&held_out[k % N_HELD_OUT])
                .unwrap(),
        );
    }
    let coefficients_per_second = N_EVALUATIONS as f64 / clock.elapsed().as_secs_f64();
    eprintln!(
        "evaluation: {per_second:.0} per second (all {} vertices), {coefficients_per_second:.0} per second (the {} spatial coefficients)",
        mesh.n_vertices(),
        spatial.n_functions(),
    );

    // Held-out error against the ground truth from the rest pose and from the operator.
    let truths_rest =
        ground_truths_from_rest(&mesh, &handles, &options, &held_out, &|_| {}).unwrap();
    let truths_op = truths_from_operator(&mesh, &handles, energy, &held_out, op);
    let error = |op: &DefOp, truths: &[Vec<Point>]| -> f64 {
        held_out
            .iter()
            .zip(truths)
            .map(|(q, u)| l2_distance(&mesh, &op.eval(q).unwrap(), u).unwrap())
            .sum::<f64>()
            / N_HELD_OUT as f64
    };
    let (lo, hi) = mesh.vertices.iter().fold(
        (
            Point::new(f64::MAX, f64::MAX),
            Point::new(f64::MIN, f64::MIN),
        ),
        |(lo, hi), p| {
            (
                Point::new(lo.x.min(p.x), lo.y.min(p.y)),
                Point::new(hi.x.max(p.x), hi.y.max(p.y)),
            )
        },
    );
    let diagonal = (hi - lo).hypot();
    let differ = truths_rest
        .iter()
        .zip(&truths_op)
        .filter(|(a, b)| {
            a.iter()
                .zip(b.iter())
                .map(|(p, q)| (*p - *q).hypot())
                .fold(0.0, f64::max)
                > 1e-6
        })
        .count();
    eprintln!(
        "held-out error (RMS over the shape, drawing units; bounding-box diagonal {:.2}): {:.4} against the ground truth from rest, {:.4} against the one started from the operator ({differ} of {N_HELD_OUT} held-out ground truths differ between the two starts)",
        diagonal,
        error(op, &truths_rest),
        error(op, &truths_op)
    );
}

/// The ground truths at `configurations` started from `op`'s prediction (as the training's
/// bootstrapping starts them; [`ground_truths_from_rest`] starts from the rest pose).
fn truths_from_operator(
    mesh: &splineskin::mesh::TriMesh,
    handles: &[usize],
    energy: Energy,
    configurations: &[Vec<Point>],
    op: &DefOp,
) -> Vec<Vec<Point>> {
    let arap = Arap::new(
        mesh,
        handles,
        ArapOptions::default().with_anderson_depth(TRAINING_ANDERSON_DEPTH),
    )
    .unwrap();
    let sarap = SymmetricArap::new(mesh, handles, SarapOptions::default()).unwrap();
    configurations
        .iter()
        .map(|q| {
            let mut u = op.eval(q).unwrap();
            for (&h, &t) in handles.iter().zip(q) {
                u[h] = t;
            }
            match energy {
                Energy::Arap => {
                    arap.solve(q, &mut u).unwrap();
                }
                Energy::SymmetricArap => {
                    // As training does: the start given, else the ARAP solution, else rest.
                    let flip_free = |u: &[Point]| {
                        splineskin::defop::flipped_triangles(mesh, u)
                            .unwrap()
                            .is_empty()
                    };
                    let from_start = flip_free(&u) && sarap.solve(q, &mut u).unwrap().converged();
                    if !from_start {
                        u = mesh.vertices.clone();
                        arap.solve(q, &mut u).unwrap();
                        if !flip_free(&u) || !sarap.solve(q, &mut u).unwrap().converged() {
                            u = mesh.vertices.clone();
                            sarap.solve(q, &mut u).unwrap();
                        }
                    }
                }
            }
            u
        })
        .collect()
}
