//! Timings of the mesh weight families on a synthetic domain of about 20 000 vertices (the
//! size issue 4 asks for the turtles drawing's domain) with 5 point handles:
//!
//! * `harmonic_k1`, `harmonic_k2`: [`harmonic_weights`] (build the energy, order, factor once,
//!   solve for the 5 handles);
//! * `bbw_sequential`, `bbw_parallel`: [`bbw_weights`] with the handles' programs one after the
//!   other or on rayon's pool (2 cores here).
//!
//! The domain is [`TriMesh::grid`] over a 2 × 1 rectangle, 200 × 100 cells (20 301 vertices),
//! with handles at five vertices spread over it. Run with
//! `cargo bench -p splineskin --bench weights`; divan prints the median of each.

use kurbo::{Point, Rect};
use splineskin::mesh::TriMesh;
use splineskin::weights::{bbw_weights, harmonic_weights, BbwOptions};

/// Cells along x (the rectangle is 2 × 1, cells are square).
const NX: usize = 200;
/// Cells along y.
const NY: usize = 100;

fn main() {
    divan::main();
}

/// The grid and its five handle vertices.
fn domain() -> (TriMesh, Vec<usize>) {
    let mesh = TriMesh::grid(Rect::new(0.0, 0.0, 2.0, 1.0), NX, NY).expect("valid grid");
    let targets = [
        (0.3, 0.25),
        (0.3, 0.75),
        (1.0, 0.5),
        (1.7, 0.25),
        (1.7, 0.75),
    ];
    let handles = targets
        .iter()
        .map(|&(x, y)| nearest_vertex(&mesh, Point::new(x, y)))
        .collect();
    (mesh, handles)
}

fn nearest_vertex(mesh: &TriMesh, p: Point) -> usize {
    (0..mesh.n_vertices())
        .min_by(|&a, &b| {
            let (da, db) = (mesh.vertices[a].distance(p), mesh.vertices[b].distance(p));
            da.total_cmp(&db)
        })
        .unwrap_or(0)
}

#[divan::bench(args = [1, 2], sample_count = 10)]
fn harmonic(bencher: divan::Bencher, k: usize) {
    let (mesh, handles) = domain();
    bencher.bench_local(|| harmonic_weights(&mesh, &handles, k).expect("harmonic weights"));
}

#[divan::bench(args = [false, true], sample_count = 5)]
fn bbw(bencher: divan::Bencher, parallel: bool) {
    let (mesh, handles) = domain();
    let options = BbwOptions::default().with_parallel(parallel);
    bencher.bench_local(|| bbw_weights(&mesh, &handles, &options).expect("bbw weights"));
}
