//! Harmonic weights solved on the triangulated domain of the bundled fish, evaluated in the
//! fit through `MeshWeights`: the whole mesh-weights path, domain to deformed curves.

#[path = "common/measure.rs"]
mod measure;

use std::time::Instant;

use kurbo::{Affine, Point};
use splineskin::domain::{Domain, DomainOptions, MeshWeights};
use splineskin::drawing::{read_svg, ImportOptions};
use splineskin::examples::{demo_scene, DEMO_SVG};
use splineskin::spline_fit::{FitOptions, SplineRig};
use splineskin::weights::harmonic::harmonic_weights;
use splineskin::weights::WeightField;

#[test]
fn domain_fish_harmonic_rig_reproduces_identity_and_affine_maps() {
    let d = read_svg(DEMO_SVG, &ImportOptions::default()).expect("demo svg");
    let h = demo_scene().handles;
    let domain = Domain::build(&d, &h, &[], &DomainOptions::default()).expect("domain");
    let t = Instant::now();
    let w = harmonic_weights(&domain.mesh, &domain.handle_vertices, 1).expect("harmonic");
    eprintln!(
        "fish: harmonic weights on {} vertices in {:.3} s",
        domain.mesh.n_vertices(),
        t.elapsed().as_secs_f64()
    );
    let field = MeshWeights::new(&domain.mesh, w.into_values(), h.len()).expect("mesh weights");

    // Interpolation at the handles and partition of unity at curve points.
    let mut out = vec![0.0; h.len()];
    for (i, &p) in h.iter().enumerate() {
        field.eval(p, &mut out);
        for (k, &x) in out.iter().enumerate() {
            assert!(
                (x - (i == k) as u8 as f64).abs() < 1e-12,
                "handle {i}: {out:?}"
            );
        }
    }
    for path in &d.paths {
        for j in 0..path.n_curves() {
            field.eval(path.curve(j).p0, &mut out);
            assert!((out.iter().sum::<f64>() - 1.0).abs() < 1e-12);
            assert!(
                out.iter().all(|&x| (-1e-12..=1.0 + 1e-12).contains(&x)),
                "{out:?}"
            );
        }
    }

    let rig = SplineRig::precompute(&d, &field, &FitOptions::default()).expect("rig");
    let a = Affine::translate((-40.0, 25.0)) * Affine::rotate(-0.7) * Affine::scale(1.3);
    measure::assert_affine_reproduction(&rig, &d, h.len(), a, "fish");
    let diag = d.diagonal();
    let input = d.flat_points();
    let mut points = vec![Point::ZERO; rig.n_points()];
    // A real pose moves the fish and keeps every point finite.
    let pose: Vec<Affine> = (0..h.len())
        .map(|i| Affine::rotate_about(0.1 * i as f64, h[i]))
        .collect();
    rig.update(&pose, &mut points).unwrap();
    assert!(points.iter().all(|p| p.x.is_finite() && p.y.is_finite()));
    let moved = measure::max_distance(&points, &input);
    assert!(moved > 1e-3 * diag, "{moved}");
}
