//! The join of a deformation operator with the spline fit ([`DefOpRig`]) on the bundled fish
//! (58 curves, 190 chain points, 5 point handles) and its training domain
//! ([`training_domain_options`]: 1 917 vertices, 3 714 triangles): `precompute` (the fit `F`
//! per path and `F Dᵀ G`) and the per-frame `update` (`ψ(Q)` and one dense product with
//! `G_spline`, `2 · 190 × |Ψ|`). The issue asks ≤ 1 ms per frame.
//!
//! The operator has the size of a real one: hats (`|Φ| = 1 917`) and thin-plate splines on
//! 1 000 samples (`|Ψ| = 1 + 2·5 + 1 001 = 1 012`). Training it (1 000 symmetric ARAP solves)
//! in a benchmark's setup is too slow, and neither time depends on the training data's values,
//! so it is fitted to made-up deformations (the rest mesh moved smoothly with the body handle,
//! handles on target), as in `benches/defop_operator.rs`; `tests/defop_spline_join.rs` and
//! `examples/defop_join.rs` use trained operators. Run with
//! `cargo bench -p splineskin --bench defop_join`.

use std::sync::OnceLock;

use kurbo::{Point, Vec2};
use splineskin::defop::{
    training_domain_options, DefOp, DefOpOptions, DefOpRig, SampleRegion, Sampler, SpatialBasis,
    DEFAULT_DISC_FRACTION,
};
use splineskin::domain::Domain;
use splineskin::drawing::{read_svg, Drawing, ImportOptions};
use splineskin::examples::{demo_scene, DEMO_SVG};
use splineskin::spline_fit::FitOptions;

/// Samples besides the rest configuration: 1 000 thin-plate centres.
const N_SAMPLES: usize = 1000;

struct Setup {
    drawing: Drawing,
    domain: Domain,
    op: DefOp,
    rig: DefOpRig,
    configurations: Vec<Vec<Point>>,
}

fn setup() -> &'static Setup {
    static SETUP: OnceLock<Setup> = OnceLock::new();
    SETUP.get_or_init(|| {
        let drawing = read_svg(DEMO_SVG, &ImportOptions::default()).expect("demo svg");
        let rest = demo_scene().handles;
        let domain =
            Domain::build(&drawing, &rest, &[], &training_domain_options()).expect("domain");
        let mesh = &domain.mesh;
        let handles = &domain.handle_vertices;
        let bounds = drawing.control_bounds().expect("bounds");
        let radius = DEFAULT_DISC_FRACTION * bounds.width().hypot(bounds.height());
        let region = [(SampleRegion::Disc { radius }, 1.0)];
        let mut configurations = vec![rest.clone()];
        configurations.extend(
            Sampler::new(&rest, &region, 3)
                .expect("sampler")
                .configurations(N_SAMPLES),
        );
        let scale = 1.0 / bounds.width().max(bounds.height());
        let solutions: Vec<Vec<Point>> = configurations
            .iter()
            .map(|q| {
                let shift = q[1] - rest[1];
                let mut u: Vec<Point> = mesh
                    .vertices
                    .iter()
                    .map(|&p| {
                        let wave =
                            Vec2::new((p.y * scale * shift.x).sin(), (p.x * scale * shift.y).sin());
                        p + shift + wave
                    })
                    .collect();
                for (&h, &target) in handles.iter().zip(q) {
                    u[h] = target;
                }
                u
            })
            .collect();
        let spatial = SpatialBasis::hats(mesh).expect("hats");
        let op = DefOp::fit(
            mesh,
            handles,
            &spatial,
            &configurations,
            &solutions,
            &DefOpOptions::default(),
        )
        .expect("fit");
        let rig =
            DefOpRig::from_domain(&drawing, &domain, &op, &FitOptions::default()).expect("rig");
        let configurations = Sampler::new(&rest, &region, 4)
            .expect("sampler")
            .configurations(16);
        Setup {
            drawing,
            domain,
            op,
            rig,
            configurations,
        }
    })
}

fn main() {
    let s = setup();
    eprintln!(
        "fish: {} chain points, {} vertices, |Phi| = {}, |Psi| = {}",
        s.rig.n_points(),
        s.domain.mesh.n_vertices(),
        s.op.spatial_basis().n_functions(),
        s.rig.handle_basis().n_functions()
    );
    divan::main();
}

/// `parallel`: paths joined on rayon's pool ([`FitOptions::parallel`]).
#[divan::bench(sample_count = 20, args = [false, true])]
fn precompute(bencher: divan::Bencher, parallel: bool) {
    let s = setup();
    let options = FitOptions::default().with_parallel(parallel);
    bencher.bench_local(|| {
        DefOpRig::from_domain(divan::black_box(&s.drawing), &s.domain, &s.op, &options)
            .expect("rig")
    });
}

#[divan::bench]
fn update(bencher: divan::Bencher) {
    let s = setup();
    let mut evaluator = s.rig.evaluator();
    let mut points = vec![Point::ZERO; s.rig.n_points()];
    let mut k = 0;
    bencher.bench_local(|| {
        k = (k + 1) % s.configurations.len();
        evaluator
            .update(divan::black_box(&s.configurations[k]), &mut points)
            .expect("update");
    });
}
