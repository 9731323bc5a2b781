//! Deforms the bundled fish through a deformation operator joined with the spline fit
//! ([`splineskin::defop::DefOpRig`]) and draws it next to the ground truth: trains symmetric
//! ARAP (hats + thin-plate splines) on the fish's domain, moves the handles to held-out
//! configurations and writes, per configuration, `join-K.png` (the deformed drawing, its own
//! styles) and `overlay-K.png` (the joined curves in black over the ground-truth mesh
//! interpolated along the input curves in red, the deformed handles as dots), with the
//! distances printed.
//!
//! ```text
//! cargo run --release -p splineskin --example defop_join -- [SAMPLES] [OUT_DIR]
//! ```
//!
//! Defaults: 300 samples, `target/defop-join`.

use std::fmt::Write;
use std::time::Instant;

use kurbo::{Affine, Point};
use splineskin::defop::{
    flipped_triangles, training_domain_options, Arap, ArapOptions, DrawingDefOp, SampleRegion,
    Sampler, SarapOptions, SymmetricArap, TrainOptions, DEFAULT_DISC_FRACTION,
};
use splineskin::domain::MeshWeights;
use splineskin::drawing::svg_out::write_svg;
use splineskin::drawing::{read_svg, ImportOptions};
use splineskin::examples::{demo_scene, DEMO_SVG};
use splineskin::metrics::{chain_metrics, target_samples, MetricsOptions};
use splineskin::render::render_png;
use splineskin::spline_fit::FitOptions;

/// Held-out configurations drawn.
const N_CONFIGURATIONS: usize = 3;
/// Size of the pictures (pixels, larger side).
const PICTURE_SIZE: u32 = 900;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n_samples: usize = args.iter().find_map(|a| a.parse().ok()).unwrap_or(300);
    let out_dir = args
        .iter()
        .find(|a| a.parse::<usize>().is_err())
        .cloned()
        .unwrap_or_else(|| "target/defop-join".into());
    std::fs::create_dir_all(&out_dir).expect("output folder");
    let drawing = read_svg(DEMO_SVG, &ImportOptions::default()).expect("demo svg");
    let handles = demo_scene().handles;
    let clock = Instant::now();
    let joined = DrawingDefOp::train(
        &drawing,
        &handles,
        &training_domain_options(),
        &TrainOptions::default()
            .with_n_samples(n_samples)
            .with_parallel(true),
        &FitOptions::default(),
        &|_| {},
    )
    .expect("training");
    let mesh = &joined.domain.mesh;
    eprintln!(
        "fish: {} vertices, {} triangles; symmetric ARAP, {n_samples} samples, hats + TPS: domain, training and join in {:.1} s",
        mesh.n_vertices(),
        mesh.n_triangles(),
        clock.elapsed().as_secs_f64()
    );
    let r = mesh.vertices.iter().fold(
        kurbo::Rect::from_points(mesh.vertices[0], mesh.vertices[0]),
        |r, &p| r.union_pt(p),
    );
    let radius = DEFAULT_DISC_FRACTION * r.width().hypot(r.height());
    let configurations = Sampler::new(&handles, &[(SampleRegion::Circle { radius }, 1.0)], 77)
        .expect("sampler")
        .configurations(N_CONFIGURATIONS);
    let hv = &joined.domain.handle_vertices;
    let arap = Arap::new(mesh, hv, ArapOptions::default()).expect("arap");
    let sarap = SymmetricArap::new(mesh, hv, SarapOptions::default()).expect("sarap");
    let mut evaluator = joined.rig.evaluator();
    let mut points = vec![Point::ZERO; joined.rig.n_points()];
    for (k, q) in configurations.iter().enumerate() {
        let clock = Instant::now();
        evaluator.update(q, &mut points).expect("update");
        let update = clock.elapsed().as_secs_f64();
        let mut truth = mesh.vertices.clone();
        arap.solve(q, &mut truth).expect("arap");
        if !flipped_triangles(mesh, &truth).expect("mesh").is_empty() {
            truth = mesh.vertices.clone();
        }
        sarap.solve(q, &mut truth).expect("symmetric arap");
        let w: Vec<f64> = truth.iter().flat_map(|p| [p.x, p.y]).collect();
        let field = MeshWeights::new(mesh, w, 2).expect("field");
        let pose = [
            Affine::new([0.0, 0.0, 0.0, 0.0, 1.0, 0.0]),
            Affine::new([0.0, 0.0, 0.0, 0.0, 0.0, 1.0]),
        ];
        let m = chain_metrics(&drawing, &field, &pose, &points, &MetricsOptions::default())
            .expect("metrics");
        eprintln!(
            "configuration {k} (handles on circles of {radius:.1}): update {:.0} us, distance to the ground truth: max {:.2e}, RMS {:.2e} of the diagonal",
            update * 1e6,
            m.overall.max,
            m.overall.rms
        );
        let svg = write_svg(&drawing, &points).expect("svg");
        let png = render_png(&svg, PICTURE_SIZE).expect("render");
        std::fs::write(format!("{out_dir}/join-{k}.png"), png).expect("write");

        // Overlay: truth polylines (red, wide) under the joined cubics (black, thin).
        let samples = 101;
        let target = target_samples(&drawing, &field, &pose, samples);
        let mut body = String::new();
        for curve in target.chunks(samples) {
            let mut d = format!("M{} {}", curve[0].x, curve[0].y);
            for p in &curve[1..] {
                let _ = write!(d, " L{} {}", p.x, p.y);
            }
            let _ = write!(
                body,
                r#"<path d="{d}" fill="none" stroke="red" stroke-width="4" stroke-opacity="0.5"/>"#
            );
        }
        for range in drawing.path_ranges() {
            let o = &points[range];
            let mut d = format!("M{} {}", o[0].x, o[0].y);
            for c in o[1..].chunks(3) {
                let _ = write!(
                    d,
                    " C{} {} {} {} {} {}",
                    c[0].x, c[0].y, c[1].x, c[1].y, c[2].x, c[2].y
                );
            }
            let _ = write!(
                body,
                r#"<path d="{d}" fill="none" stroke="black" stroke-width="1"/>"#
            );
        }
        for p in q {
            let _ = write!(
                body,
                r#"<circle cx="{}" cy="{}" r="5" fill="blue"/>"#,
                p.x, p.y
            );
        }
        let view = r.inflate(10.0, 10.0);
        let svg = format!(
            r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="{} {} {} {}" width="{}" height="{}"><rect x="{}" y="{}" width="{}" height="{}" fill="white"/>{body}</svg>"#,
            view.x0,
            view.y0,
            view.width(),
            view.height(),
            view.width(),
            view.height(),
            view.x0,
            view.y0,
            view.width(),
            view.height()
        );
        let png = render_png(&svg, PICTURE_SIZE).expect("render overlay");
        std::fs::write(format!("{out_dir}/overlay-{k}.png"), png).expect("write");
    }
    eprintln!("pictures in {out_dir}");
}
