//! Timings of the deformation operators' ground truth (issue 7, part 1) on an octopus-like
//! domain of about 3 000 triangles with 9 point handles (the body's centre and the eight arm
//! tips), the size the training benchmark names:
//!
//! * `precompute_arap`: [`Arap::new`] (the Laplacian on the free vertices, AMD, Cholesky);
//! * `precompute_sarap`: [`SymmetricArap::new`] (Hessian pattern, AMD, symbolic analysis);
//! * `arap`: one configuration solved from the rest pose to the default tolerance;
//! * `sarap_from_arap`: SARAP from that configuration's ARAP solution (from the rest pose if
//!   it flips a triangle: the printout says);
//! * `sarap_from_rest`: SARAP from the rest pose (the handles pulled on target first).
//!
//! Configurations move every handle uniformly in a disc of radius 0.4 (the arms are 2.2
//! long), as the paper samples them; four fixed ones. The iteration counts of each are printed
//! before the timings. Run with `cargo bench -p splineskin --bench defop`.

use std::sync::OnceLock;

use kurbo::{Point, Vec2};
use splineskin::defop::{flipped_triangles, Arap, ArapOptions, SarapOptions, SymmetricArap};
use splineskin::examples::{octopus_domain, octopus_handles};
use splineskin::mesh::TriMesh;

/// Largest triangle of the octopus mesh, as a fraction of its bounding box: 1 991 vertices and
/// 3 377 triangles ([`octopus_domain`]).
const OCTOPUS_AREA_FRACTION: f64 = 1.0 / 1800.0;
/// Radius of the disc each handle's target is drawn from.
const REACH: f64 = 0.4;
/// Configurations benchmarked.
const N_CONFIGURATIONS: usize = 4;

struct Setup {
    mesh: TriMesh,
    handles: Vec<usize>,
    arap: Arap,
    sarap: SymmetricArap,
    configurations: Vec<Vec<Point>>,
    /// The ARAP solution of each configuration (the rest pose where it flips a triangle).
    sarap_starts: Vec<Vec<Point>>,
}

fn setup() -> &'static Setup {
    static SETUP: OnceLock<Setup> = OnceLock::new();
    SETUP.get_or_init(|| {
        let points = octopus_handles();
        let domain = octopus_domain(OCTOPUS_AREA_FRACTION).expect("octopus domain");
        let (mesh, handles) = (domain.mesh, domain.handle_vertices);
        let arap = Arap::new(&mesh, &handles, ArapOptions::default()).expect("ARAP");
        let sarap = SymmetricArap::new(&mesh, &handles, SarapOptions::default()).expect("SARAP");
        let mut seed = 0x5eed_u64;
        let mut uniform = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let configurations: Vec<Vec<Point>> = (0..N_CONFIGURATIONS)
            .map(|_| {
                points
                    .iter()
                    .map(|&p| {
                        let (r, a) = (REACH * uniform().sqrt(), std::f64::consts::TAU * uniform());
                        p + Vec2::new(r * a.cos(), r * a.sin())
                    })
                    .collect()
            })
            .collect();
        eprintln!(
            "octopus: {} vertices, {} triangles, {} handles",
            mesh.n_vertices(),
            mesh.n_triangles(),
            handles.len()
        );
        let mut sarap_starts = Vec::new();
        for (k, targets) in configurations.iter().enumerate() {
            let mut u = mesh.vertices.clone();
            let report = arap.solve(targets, &mut u).expect("ARAP solve");
            let flips = flipped_triangles(&mesh, &u).expect("flips").len();
            let start = if flips == 0 { u } else { mesh.vertices.clone() };
            let mut s = start.clone();
            let from_arap = sarap.solve(targets, &mut s).expect("SARAP solve");
            let mut r = mesh.vertices.clone();
            let from_rest = sarap.solve(targets, &mut r).expect("SARAP solve");
            eprintln!(
                "configuration {k}: ARAP {} iterations ({} flipped), SARAP {} from ARAP ({:?}), {} from rest ({:?})",
                report.iterations,
                flips,
                from_arap.iterations,
                from_arap.stop,
                from_rest.iterations,
                from_rest.stop
            );
            sarap_starts.push(start);
        }
        Setup {
            mesh,
            handles,
            arap,
            sarap,
            configurations,
            sarap_starts,
        }
    })
}

fn main() {
    setup();
    divan::main();
}

const CONFIGURATIONS: [usize; N_CONFIGURATIONS] = [0, 1, 2, 3];

#[divan::bench(sample_count = 10)]
fn precompute_arap(bencher: divan::Bencher) {
    let s = setup();
    bencher.bench_local(|| Arap::new(&s.mesh, &s.handles, ArapOptions::default()).expect("ARAP"));
}

#[divan::bench(sample_count = 10)]
fn precompute_sarap(bencher: divan::Bencher) {
    let s = setup();
    bencher.bench_local(|| {
        SymmetricArap::new(&s.mesh, &s.handles, SarapOptions::default()).expect("SARAP")
    });
}

/// Times `solve` on a fresh copy of `start` per run (the copy is not timed).
fn bench_from<T>(bencher: divan::Bencher, start: &[Point], solve: impl Fn(&mut Vec<Point>) -> T) {
    bencher
        .with_inputs(|| start.to_vec())
        .bench_local_refs(solve);
}

#[divan::bench(args = CONFIGURATIONS, sample_count = 5)]
fn arap(bencher: divan::Bencher, k: usize) {
    let s = setup();
    let solve = |u: &mut Vec<Point>| s.arap.solve(&s.configurations[k], u).expect("ARAP");
    bench_from(bencher, &s.mesh.vertices, solve);
}

#[divan::bench(args = CONFIGURATIONS, sample_count = 5)]
fn sarap_from_arap(bencher: divan::Bencher, k: usize) {
    let s = setup();
    let solve = |u: &mut Vec<Point>| s.sarap.solve(&s.configurations[k], u).expect("SARAP");
    bench_from(bencher, &s.sarap_starts[k], solve);
}

#[divan::bench(args = CONFIGURATIONS, sample_count = 5)]
fn sarap_from_rest(bencher: divan::Bencher, k: usize) {
    let s = setup();
    let solve = |u: &mut Vec<Point>| s.sarap.solve(&s.configurations[k], u).expect("SARAP");
    bench_from(bencher, &s.mesh.vertices, solve);
}
