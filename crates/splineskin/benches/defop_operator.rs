//! Evaluation speed of deformation operators on the octopus (1 991 vertices, 3 377 triangles,
//! 9 handles; [`octopus_domain`]) with 1 000 thin-plate centres (`|Ψ| = 1 019`, the paper's
//! octopus), for three spatial bases: the hats (`|Φ| = 1 991`), 100 Laplacian eigenfunctions
//! of the linearly precise operator and 100 biharmonic coordinates. `eval` gives every
//! vertex, `coefficients` only `G ψ(Q)` (what the spline join will need). The issue asks
//! ≥ 5 000 evaluations per second: the reciprocal of the medians printed.
//!
//! Speed does not depend on the training data's values, so the operators are fitted to made-up
//! deformations (the rest mesh moved smoothly with the body handle, handles on target);
//! `examples/defop_train.rs` trains on the real ground truth and measures the same way.
//! Run with `cargo bench -p splineskin --bench defop_operator`.

use std::sync::OnceLock;

use kurbo::{Point, Vec2};
use splineskin::defop::{DefOp, DefOpOptions, EigenOperator, SampleRegion, Sampler, SpatialBasis};
use splineskin::examples::octopus_domain;

/// Largest triangle of the octopus, as a fraction of its bounding box.
const OCTOPUS_AREA_FRACTION: f64 = 1.0 / 1800.0;
/// Training samples besides the rest configuration: 1 000 thin-plate centres.
const N_SAMPLES: usize = 1000;
/// Functions of the reduced bases.
const N_REDUCED: usize = 100;

struct Setup {
    /// `(name, operator)`.
    ops: Vec<(&'static str, DefOp)>,
    configurations: Vec<Vec<Point>>,
}

fn setup() -> &'static Setup {
    static SETUP: OnceLock<Setup> = OnceLock::new();
    SETUP.get_or_init(|| {
        let domain = octopus_domain(OCTOPUS_AREA_FRACTION).expect("octopus");
        let (mesh, handles) = (domain.mesh, domain.handle_vertices);
        let rest: Vec<Point> = handles.iter().map(|&h| mesh.vertices[h]).collect();
        let mut sampler =
            Sampler::new(&rest, &[(SampleRegion::Disc { radius: 0.4 }, 1.0)], 3).expect("sampler");
        let mut configurations = vec![rest.clone()];
        configurations.extend(sampler.configurations(N_SAMPLES));
        let solutions: Vec<Vec<Point>> = configurations
            .iter()
            .map(|q| {
                let shift = q[0] - rest[0];
                let mut u: Vec<Point> = mesh
                    .vertices
                    .iter()
                    .map(|&p| {
                        p + shift + 0.1 * Vec2::new((p.y * shift.x).sin(), (p.x * shift.y).sin())
                    })
                    .collect();
                for (&h, &target) in handles.iter().zip(q) {
                    u[h] = target;
                }
                u
            })
            .collect();
        let bases = [
            ("hats", SpatialBasis::hats(&mesh)),
            (
                "eigen100",
                SpatialBasis::laplacian_eigenfunctions(
                    &mesh,
                    N_REDUCED,
                    EigenOperator::LinearlyPrecise,
                ),
            ),
            (
                "biharmonic100",
                SpatialBasis::biharmonic_coordinates_sampled(&mesh, &handles, N_REDUCED),
            ),
        ];
        let ops = bases
            .into_iter()
            .map(|(name, basis)| {
                let basis = basis.expect("spatial basis");
                let op = DefOp::fit(
                    &mesh,
                    &handles,
                    &basis,
                    &configurations,
                    &solutions,
                    &DefOpOptions::default(),
                )
                .expect("fit");
                (name, op)
            })
            .collect();
        let mut held_out =
            Sampler::new(&rest, &[(SampleRegion::Disc { radius: 0.4 }, 1.0)], 4).expect("sampler");
        Setup {
            ops,
            configurations: held_out.configurations(16),
        }
    })
}

fn main() {
    setup();
    divan::main();
}

/// Indices into `Setup::ops`: 0 hats, 1 eigen100, 2 biharmonic100.
const BASES: [usize; 3] = [0, 1, 2];

#[divan::bench(args = BASES)]
fn eval(bencher: divan::Bencher, basis: usize) {
    let s = setup();
    let op = &s.ops[basis].1;
    let mut evaluator = op.evaluator();
    let mut positions = vec![Point::ZERO; op.n_vertices()];
    let mut k = 0;
    bencher.bench_local(|| {
        k = (k + 1) % s.configurations.len();
        evaluator
            .eval(divan::black_box(&s.configurations[k]), &mut positions)
            .expect("eval");
    });
}

#[divan::bench(args = BASES)]
fn coefficients(bencher: divan::Bencher, basis: usize) {
    let s = setup();
    let op = &s.ops[basis].1;
    let mut evaluator = op.evaluator();
    let mut k = 0;
    bencher.bench_local(|| {
        k = (k + 1) % s.configurations.len();
        divan::black_box(
            evaluator
                .spatial_coefficients(divan::black_box(&s.configurations[k]))
                .expect("coefficients")
                .len(),
        );
    });
}
