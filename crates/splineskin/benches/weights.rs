//! Timings of the mesh weight families (issue 4's benchmark: 5 handles on a domain of at least
//! 20 000 vertices):
//!
//! * `harmonic`: [`harmonic_weights`] with `k = 1` and `k = 2` (build the energy, order,
//!   factor once, solve for the 5 handles);
//! * `bbw`: [`bbw_weights`] with the handles' programs on rayon's pool (2 cores here) — the
//!   sequential time is about 1.6 times longer — started cold, from the unbounded solution;
//! * `bbw_coarse_to_fine` (turtles only): what a scene with `bbw` weights does — the domain
//!   built ([`Domain::build`], included in the time), the program solved on coarser domains
//!   first ([`bbw_coarse_to_fine`]), handles in parallel, rows normalised;
//! * `domain` (turtles only): [`Domain::build`] alone.
//!
//! on two domains:
//!
//! * `grid`: [`TriMesh::grid`] over a 2 × 1 rectangle, 200 × 100 cells (20 301 vertices), with
//!   handles at five vertices spread over it;
//! * `turtles`: the domain [`Domain::build`] makes with default options for the paper
//!   authors' "Seven Turtles" drawing and the five handles of their "wobble 4" scene
//!   (20 437 vertices), read from `../shared/data` (skipped, with a note, when missing).
//!
//! Run with `cargo bench -p splineskin --bench weights`; divan prints the median of each.

use std::path::PathBuf;
use std::sync::OnceLock;

use kurbo::{Point, Rect};
use splineskin::domain::{Domain, DomainOptions};
use splineskin::drawing::Drawing;
use splineskin::drawing::{svg_in::read_svg_file, ImportOptions};
use splineskin::mesh::TriMesh;
use splineskin::weights::coarse_to_fine::bbw_coarse_to_fine;
use splineskin::weights::{bbw_weights, harmonic_weights, BbwOptions, DirichletData};

/// Cells along x of the grid (the rectangle is 2 × 1, cells are square).
const NX: usize = 200;
/// Cells along y.
const NY: usize = 100;

/// The turtles drawing, relative to `../shared/data`.
const TURTLES_SVG: &str = "vectorskinning/turtle-seven-stack/wobble 4/turtles-seven.svg";

/// The five handles of the authors' "wobble 4" turtles scene.
const TURTLE_HANDLES: [(f64, f64); 5] = [
    (363.0, 547.0),
    (347.0, 138.0),
    (378.0, 231.0),
    (264.0, 624.0),
    (464.0, 641.0),
];

fn main() {
    if !turtles_svg().is_file() {
        eprintln!(
            "note: {} not found: the turtles benchmarks are skipped",
            turtles_svg().display()
        );
    }
    divan::main();
}

fn turtles_svg() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data")).join(TURTLES_SVG)
}

#[derive(Clone, Copy, Debug)]
enum Case {
    Grid,
    Turtles,
}

impl std::fmt::Display for Case {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Case::Grid => "grid",
            Case::Turtles => "turtles",
        })
    }
}

impl Case {
    /// The mesh and its five handle vertices, built once; `None` when the data are missing.
    fn get(self) -> Option<&'static (TriMesh, Vec<usize>)> {
        static GRID: OnceLock<(TriMesh, Vec<usize>)> = OnceLock::new();
        static TURTLES: OnceLock<Option<(TriMesh, Vec<usize>)>> = OnceLock::new();
        match self {
            Case::Grid => Some(GRID.get_or_init(grid)),
            Case::Turtles => TURTLES.get_or_init(turtles).as_ref(),
        }
    }
}

fn grid() -> (TriMesh, Vec<usize>) {
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

fn turtles() -> Option<(TriMesh, Vec<usize>)> {
    let path = turtles_svg();
    if !path.is_file() {
        return None;
    }
    let drawing = read_svg_file(&path, &ImportOptions::default()).expect("turtles SVG");
    let handles = TURTLE_HANDLES.map(Point::from);
    let domain =
        Domain::build(&drawing, &handles, &[], &DomainOptions::default()).expect("turtles domain");
    Some((domain.mesh, domain.handle_vertices))
}

const CASES: [Case; 2] = [Case::Grid, Case::Turtles];

#[divan::bench(args = CASES, consts = [1, 2], sample_count = 10)]
fn harmonic<const K: usize>(bencher: divan::Bencher, case: Case) {
    let Some((mesh, handles)) = case.get() else {
        return;
    };
    bencher.bench_local(|| harmonic_weights(mesh, handles, K).expect("harmonic weights"));
}

#[divan::bench(args = CASES, sample_count = 3)]
fn bbw(bencher: divan::Bencher, case: Case) {
    let Some((mesh, handles)) = case.get() else {
        return;
    };
    let options = BbwOptions::default().with_parallel(true);
    bencher.bench_local(|| bbw_weights(mesh, handles, &options).expect("bbw weights"));
}

/// The turtles drawing, read once (`None` without ../shared/data).
fn turtles_drawing() -> Option<&'static Drawing> {
    static DRAWING: OnceLock<Option<Drawing>> = OnceLock::new();
    DRAWING
        .get_or_init(|| {
            let path = turtles_svg();
            path.is_file()
                .then(|| read_svg_file(&path, &ImportOptions::default()).expect("turtles SVG"))
        })
        .as_ref()
}

#[divan::bench(sample_count = 10)]
fn domain(bencher: divan::Bencher) {
    let Some(drawing) = turtles_drawing() else {
        return;
    };
    let handles = TURTLE_HANDLES.map(Point::from);
    bencher.bench_local(|| {
        Domain::build(drawing, &handles, &[], &DomainOptions::default()).expect("turtles domain")
    });
}

#[divan::bench(sample_count = 5)]
fn bbw_coarse_to_fine_turtles(bencher: divan::Bencher) {
    let Some(drawing) = turtles_drawing() else {
        return;
    };
    let handles = TURTLE_HANDLES.map(Point::from);
    let options = DomainOptions::default();
    let bbw = BbwOptions::default().with_parallel(true);
    bencher.bench_local(|| {
        let fine = Domain::build(drawing, &handles, &[], &options).expect("turtles domain");
        let data = |d: &Domain| DirichletData::handles(&d.handle_vertices).ok();
        let fine_data = data(&fine).expect("handle data");
        let mut w = bbw_coarse_to_fine(
            drawing,
            &handles,
            &[],
            &options,
            &fine,
            &fine_data,
            data,
            &bbw,
        )
        .expect("bbw weights");
        w.normalize_rows().expect("normalised");
        w
    });
}
