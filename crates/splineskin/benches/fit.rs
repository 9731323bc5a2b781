//! Timings of the three phases of the spline fit, each on its own:
//!
//! * `sample`: evaluating the weights at the quadrature nodes ([`SampledCurves::sample`]);
//! * `precompute`: integrating, factoring and solving every path's system
//!   ([`SplineRig::from_samples`]);
//! * `update`: one pose, the per-frame dense mat-vec ([`SplineRig::update`]), cycling through
//!   16 different poses so that no two consecutive frames are the same.
//!
//! on two drawings:
//!
//! * `demo_tiled`: the bundled demo fish ([`DEMO_SVG`]) tiled to at least [`TILED_CURVES`]
//!   curves by [`examples::tile`], with 5 Shepard handles spread over the tiling;
//! * `turtles`: the paper authors' "turtles-seven" drawing (1324 curves, 3 handles) as parsed
//!   by their code, read from `../shared/data` (skipped, with a note, when that folder is
//!   missing).
//!
//! Run with `cargo bench -p splineskin`; divan prints the median of each.

use std::f64::consts::TAU;
use std::path::PathBuf;
use std::sync::OnceLock;

use divan::Bencher;
use kurbo::{Affine, Point};
use serde::Deserialize;
use splineskin::drawing::svg_in::{read_svg, ImportOptions};
use splineskin::drawing::{Drawing, JunctionOptions, Path};
use splineskin::examples::{self, DEMO_SCENE, DEMO_SVG};
use splineskin::scene::Scene;
use splineskin::spline_fit::quadrature::SampledCurves;
use splineskin::spline_fit::{FitOptions, SplineRig};
use splineskin::weights::{Shepard, ShepardOptions};

/// Curves of the tiled demo drawing, at least: 10 000.
const TILED_CURVES: usize = 10_000;

/// Poses cycled through by the `update` benchmark: 16.
const N_POSES: usize = 16;

/// Largest handle rotation of the tiled demo's poses: 25°.
const MAX_ROTATION_DEGREES: f64 = 25.0;

/// The authors' parsed turtles, relative to `../shared/data`.
const TURTLES: &str = "vectorskinning/authors-solver-outputs/\
turtle-seven-stack__comparison__shepard__ours__turtles-seven.json";

fn main() {
    // Build the cases before timing, and say what they are.
    for case in cases() {
        let r = case.get();
        eprintln!(
            "{case}: {} paths, {} curves, {} handles",
            r.drawing.paths.len(),
            r.drawing.n_curves(),
            r.rig.n_handles()
        );
    }
    if !turtles_file().is_file() {
        eprintln!(
            "note: {} not found: the turtles benchmarks are skipped",
            turtles_file().display()
        );
    }
    divan::main();
}

/// A drawing to time.
#[derive(Clone, Copy, Debug)]
enum Case {
    DemoTiled,
    Turtles,
}

impl std::fmt::Display for Case {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Case::DemoTiled => "demo_tiled",
            Case::Turtles => "turtles",
        })
    }
}

/// Everything a benchmark needs, built once per case.
struct Rigged {
    drawing: Drawing,
    field: Shepard,
    options: FitOptions,
    samples: SampledCurves,
    rig: SplineRig,
    poses: Vec<Vec<Affine>>,
}

impl Rigged {
    fn new(drawing: Drawing, handles: &[Point], poses: Vec<Vec<Affine>>) -> Rigged {
        let field = Shepard::new(handles, ShepardOptions::default());
        let options = FitOptions::default();
        let samples = SampledCurves::sample(&drawing, &field, &options);
        let rig = SplineRig::from_samples(&drawing, &samples, &options).expect("fit");
        Rigged {
            drawing,
            field,
            options,
            samples,
            rig,
            poses,
        }
    }
}

impl Case {
    fn get(self) -> &'static Rigged {
        static DEMO_TILED: OnceLock<Rigged> = OnceLock::new();
        static TURTLES: OnceLock<Rigged> = OnceLock::new();
        match self {
            Case::DemoTiled => DEMO_TILED.get_or_init(demo_tiled),
            Case::Turtles => TURTLES.get_or_init(turtles),
        }
    }
}

/// The cases whose data is available.
fn cases() -> Vec<Case> {
    if turtles_file().is_file() {
        vec![Case::DemoTiled, Case::Turtles]
    } else {
        vec![Case::DemoTiled]
    }
}

fn demo_tiled() -> Rigged {
    let drawing = read_svg(DEMO_SVG, &ImportOptions::default()).expect("demo SVG");
    let assets = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/assets"));
    let scene = Scene::from_json(DEMO_SCENE, "demo-scene.json", Some(&assets)).expect("scene");
    let (tiled, handles) = examples::tile(&drawing, &scene.handles, TILED_CURVES);
    // Pose k rotates handle i about itself by MAX_ROTATION · sin(2π k / N_POSES + i).
    let poses = (0..N_POSES)
        .map(|k| {
            handles
                .iter()
                .enumerate()
                .map(|(i, &h)| {
                    let phase = TAU * k as f64 / N_POSES as f64 + i as f64;
                    Affine::rotate_about(MAX_ROTATION_DEGREES.to_radians() * phase.sin(), h)
                })
                .collect()
        })
        .collect();
    Rigged::new(tiled, &handles, poses)
}

fn turtles_file() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data")).join(TURTLES)
}

/// The fields of an `authors-solver-outputs` case used here.
#[derive(Deserialize)]
struct AuthorsCase {
    input_paths: Vec<InputPath>,
    handle_positions: Vec<[f64; 2]>,
    /// Per handle `[[a, c, e], [b, d, f]]`.
    handle_transforms_2x3: Vec<[[f64; 3]; 2]>,
}

#[derive(Deserialize)]
struct InputPath {
    closed: bool,
    cubic_bezier_chain: Vec<[f64; 2]>,
}

fn turtles() -> Rigged {
    let file = turtles_file();
    let text = std::fs::read_to_string(&file).expect("read the turtles case");
    let case: AuthorsCase = serde_json::from_str(&text).expect("parse the turtles case");
    let paths = case
        .input_paths
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let points = p.cubic_bezier_chain.iter().map(|q| Point::new(q[0], q[1]));
            Path::new(points.collect(), p.closed, &JunctionOptions::default())
                .unwrap_or_else(|| panic!("{}: input_paths[{i}] is not a chain", file.display()))
        })
        .collect();
    let drawing = Drawing {
        paths,
        ..Default::default()
    };
    let handles: Vec<Point> = case
        .handle_positions
        .iter()
        .map(|p| Point::new(p[0], p[1]))
        .collect();
    let target: Vec<Affine> = case
        .handle_transforms_2x3
        .iter()
        .map(|[[a, c, e], [b, d, f]]| Affine::new([*a, *b, *c, *d, *e, *f]))
        .collect();
    // Pose k blends linearly from the identity to the authors' pose.
    let poses = (0..N_POSES)
        .map(|k| {
            let s = (k + 1) as f64 / N_POSES as f64;
            target
                .iter()
                .map(|t| {
                    let (m, i) = (t.as_coeffs(), Affine::IDENTITY.as_coeffs());
                    Affine::new(std::array::from_fn(|c| i[c] + s * (m[c] - i[c])))
                })
                .collect()
        })
        .collect();
    Rigged::new(drawing, &handles, poses)
}

#[divan::bench(args = cases(), sample_count = 10, sample_size = 1)]
fn sample(bencher: Bencher, case: Case) {
    let r = case.get();
    bencher.bench_local(|| SampledCurves::sample(&r.drawing, &r.field, &r.options));
}

#[divan::bench(args = cases(), sample_count = 10, sample_size = 1)]
fn precompute(bencher: Bencher, case: Case) {
    let r = case.get();
    bencher.bench_local(|| SplineRig::from_samples(&r.drawing, &r.samples, &r.options));
}

#[divan::bench(args = cases(), sample_count = 100)]
fn update(bencher: Bencher, case: Case) {
    let r = case.get();
    let mut out = vec![Point::ZERO; r.rig.n_points()];
    let mut k = 0;
    bencher.bench_local(|| {
        k = (k + 1) % r.poses.len();
        r.rig.update(&r.poses[k], &mut out).expect("pose");
        divan::black_box(&out);
    });
}
