//! Timings of the subdivision rig (issue 6's benchmark: a cage of about 4 000 vertices with
//! 4 handles, precompute ≤ 0.5 s, update ≤ 50 µs), phase by phase:
//!
//! * `limit_surface`: [`LimitSurface::new`] at the default isolation (level 10), for
//!   comparison: the rig does not need it;
//! * `for_cage`: [`LimitQuadrature::for_cage`] (the limit surface refined as deep as the 4 × 4
//!   Gauss nodes per ptex face need, and their limit stencils);
//! * `node_weights`: Shepard weights of 4 farthest-point handles at the nodes;
//! * `rig`: [`SubdivRig::precompute`] (`Â` and `Ŵ_i` assembled, one sparse Cholesky, 16
//!   solves);
//! * `precompute`: `for_cage`, `node_weights` and `rig`, what `splineskin subdiv bench`
//!   reports as `precompute_s`;
//! * `update`: [`SubdivRig::update`] for one pose.
//!
//! on OpenSubdiv's `catmark_bishop` refined once (3 767 vertices, 3 740 quads) and
//! `catmark_car` (1 642 vertices), read from `../shared/data` (skipped, with a note, when
//! missing). Run with `cargo bench -p splineskin --bench subdiv`; divan prints the fastest and
//! the median of each.

use std::path::PathBuf;
use std::sync::OnceLock;

use splineskin::subdiv::{
    farthest_point_sample, node_weights, read_obj, refine_uniform, Cage, Handles3, LimitOptions,
    LimitQuadrature, LimitSurface, Shepard3, SubdivRig, AFFINE3_IDENTITY, DEFAULT_GAUSS_POINTS,
};
use splineskin::weights::ShepardOptions;

/// Handles of every benchmark.
const N_HANDLES: usize = 4;

fn main() {
    if cages().is_empty() {
        eprintln!("note: ../shared/data not found: the subdivision benchmarks are skipped");
    }
    divan::main();
}

/// The benchmark cages: `bishop1` and `car`, or none without the data.
fn cages() -> &'static [(&'static str, Cage)] {
    static CAGES: OnceLock<Vec<(&'static str, Cage)>> = OnceLock::new();
    CAGES.get_or_init(|| {
        let root = PathBuf::from(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../../shared/data/subdiv/shapes"
        ));
        let (Ok(bishop), Ok(car)) = (
            read_obj(&root.join("catmark_bishop.obj")),
            read_obj(&root.join("catmark_car.obj")),
        ) else {
            return Vec::new();
        };
        let bishop1 = refine_uniform(&bishop, 1)
            .expect("refine the bishop")
            .levels()[0]
            .to_cage()
            .expect("the refined bishop");
        vec![("bishop1", bishop1), ("car", car)]
    })
}

const NAMES: &[&str] = &["bishop1", "car"];

fn cage(name: &str) -> Option<&'static Cage> {
    cages().iter().find(|(n, _)| *n == name).map(|(_, c)| c)
}

fn shepard(cage: &Cage) -> Shepard3 {
    let points = farthest_point_sample(cage.positions(), N_HANDLES)
        .into_iter()
        .map(|v| cage.positions()[v])
        .collect();
    Shepard3::new(
        Handles3::new(points, vec![]).expect("handles"),
        ShepardOptions::default(),
    )
    .expect("Shepard weights")
}

#[divan::bench(args = NAMES)]
fn limit_surface(bencher: divan::Bencher, name: &str) {
    let Some(cage) = cage(name) else { return };
    bencher.bench(|| LimitSurface::new(cage, &LimitOptions::default()).expect("surface"));
}

#[divan::bench(args = NAMES)]
fn for_cage(bencher: divan::Bencher, name: &str) {
    let Some(cage) = cage(name) else { return };
    bencher.bench(|| LimitQuadrature::for_cage(cage, DEFAULT_GAUSS_POINTS).expect("quadrature"));
}

/// The rig's quadrature and its surface.
fn quadrature(cage: &Cage) -> LimitQuadrature {
    LimitQuadrature::for_cage(cage, DEFAULT_GAUSS_POINTS)
        .expect("quadrature")
        .1
}

#[divan::bench(args = NAMES)]
fn node_weights_shepard(bencher: divan::Bencher, name: &str) {
    let Some(cage) = cage(name) else { return };
    let q = quadrature(cage);
    let w = shepard(cage);
    bencher.bench(|| node_weights(&w, cage, &q).expect("weights"));
}

#[divan::bench(args = NAMES)]
fn rig(bencher: divan::Bencher, name: &str) {
    let Some(cage) = cage(name) else { return };
    let q = quadrature(cage);
    let w = node_weights(&shepard(cage), cage, &q).expect("weights");
    bencher.bench(|| SubdivRig::precompute(cage, &q, &w, N_HANDLES).expect("rig"));
}

#[divan::bench(args = NAMES, sample_count = 20)]
fn precompute(bencher: divan::Bencher, name: &str) {
    let Some(cage) = cage(name) else { return };
    let field = shepard(cage);
    bencher.bench(|| {
        let q = quadrature(cage);
        let w = node_weights(&field, cage, &q).expect("weights");
        SubdivRig::precompute(cage, &q, &w, N_HANDLES).expect("rig")
    });
}

#[divan::bench(args = NAMES)]
fn update(bencher: divan::Bencher, name: &str) {
    let Some(cage) = cage(name) else { return };
    let q = quadrature(cage);
    let w = node_weights(&shepard(cage), cage, &q).expect("weights");
    let rig = SubdivRig::precompute(cage, &q, &w, N_HANDLES).expect("rig");
    let mut pose = [AFFINE3_IDENTITY; N_HANDLES];
    pose[1][1][3] = 0.1;
    let mut out = vec![[0.0; 3]; cage.n_vertices()];
    bencher.bench_local(|| rig.update(&pose, &mut out).expect("update"));
}
