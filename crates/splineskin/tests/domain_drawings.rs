//! The triangulated domain and mesh weights on real drawings: the bundled fish (five handles
//! of the demo scene) and the authors' "Seven Turtles" (1327 curves, the five handles of their
//! "wobble 4" scene). Sizes and times are printed (`--nocapture`), never asserted.

mod common;

use std::collections::HashSet;
use std::time::Instant;

use kurbo::{Affine, Point};
use splineskin::bezier::{bernstein, bernstein_gram, gauss_legendre};
use splineskin::domain::{Boundary, Domain, DomainOptions, MeshWeights};
use splineskin::drawing::{read_svg, read_svg_file, Drawing, ImportOptions};
use splineskin::examples::{demo_scene, DEMO_SVG};
use splineskin::scene::Scene;
use splineskin::spline_fit::quadrature::SampledCurves;
use splineskin::spline_fit::{FitOptions, SplineRig};
use splineskin::weights::{Shepard, ShepardOptions, WeightField};

fn fish() -> (Drawing, Vec<Point>) {
    let d = read_svg(DEMO_SVG, &ImportOptions::default()).expect("demo svg");
    (d, demo_scene().handles)
}

fn turtles() -> Option<(Drawing, Vec<Point>)> {
    let root = common::data_root()?;
    let folder = root.join("vectorskinning/turtle-seven-stack/wobble 4");
    let d = read_svg_file(&folder.join("turtles-seven.svg"), &ImportOptions::default())
        .expect("turtles svg");
    // The five handles of the authors' "wobble 4" turtles scene.
    let scene = Scene::load(&folder.join("turtles-seven-deformation.json")).expect("scene");
    Some((d, scene.handles))
}

fn build(name: &str, d: &Drawing, h: &[Point]) -> Domain {
    let t = Instant::now();
    let domain = Domain::build(d, h, &[], &DomainOptions::default()).expect("domain");
    eprintln!(
        "{name}: {} curves, {:?}, {} vertices, {} triangles, {} curve samples (spacing {:.3}), \
         min angle {:.2}°, built in {:.3} s",
        d.n_curves(),
        domain.boundary,
        domain.mesh.n_vertices(),
        domain.mesh.n_triangles(),
        domain.n_curve_samples,
        domain.sample_spacing,
        Domain::min_angle_of(&domain.mesh),
        t.elapsed().as_secs_f64()
    );
    domain
}

/// The invariants of a default domain of a drawing: valid counter-clockwise mesh, handles as
/// vertices at their exact positions, triangle areas summing to the padded box's area, every
/// triangle's smallest angle at least the default 25° (the padded box has right-angled
/// corners only, so refinement meets it everywhere), every curve's end points as vertices or
/// within half a sample spacing of one.
fn check_default_domain(d: &Drawing, h: &[Point], domain: &Domain) {
    let mesh = &domain.mesh;
    mesh.check().expect("valid mesh");
    assert_eq!(domain.boundary, Boundary::Padded);
    assert!(domain.refinement_complete);
    for (i, &v) in domain.handle_vertices.iter().enumerate() {
        assert_eq!(mesh.vertices[v], h[i]);
    }
    let distinct: HashSet<usize> = domain.handle_vertices.iter().copied().collect();
    assert_eq!(distinct.len(), h.len());
    let sum: f64 = (0..mesh.n_triangles()).map(|t| mesh.signed_area(t)).sum();
    let r = d
        .paths
        .iter()
        .flat_map(|p| (0..p.n_curves()).map(|j| kurbo::Shape::bounding_box(&p.curve(j))))
        .reduce(|a, b| a.union(b))
        .unwrap()
        .union_pt(h[0]);
    let r = h.iter().fold(r, |r, &p| r.union_pt(p));
    assert!((sum - domain.area).abs() < 1e-9 * domain.area);
    assert!(domain.area >= r.area(), "{} < {}", domain.area, r.area());
    let min_angle = Domain::min_angle_of(mesh);
    assert!(min_angle >= 25.0 - 1e-9, "min angle {min_angle}");
    // Curve end points: vertices, or skipped for a vertex within s/2.
    let mut exact = 0;
    let mut total = 0;
    for p in &d.paths {
        for &q in p.points.iter().step_by(3) {
            let nearest = mesh
                .vertices
                .iter()
                .map(|v| (*v - q).hypot())
                .fold(f64::INFINITY, f64::min);
            assert!(
                nearest <= 0.5 * domain.sample_spacing + 1e-12,
                "{q:?}: {nearest}"
            );
            exact += (nearest == 0.0) as usize;
            total += 1;
        }
    }
    assert!(
        exact * 2 > total,
        "{exact} of {total} junction points are vertices"
    );
}

#[test]
fn domain_fish_is_a_quality_mesh_through_handles_and_samples() {
    let (d, h) = fish();
    let domain = build("fish", &d, &h);
    check_default_domain(&d, &h, &domain);
    assert!(domain.mesh.n_vertices() > 5000);
}

#[test]
fn domain_turtles_has_20k_vertices() {
    let Some((d, h)) = turtles() else { return };
    let domain = build("turtles", &d, &h);
    check_default_domain(&d, &h, &domain);
    assert!(
        domain.mesh.n_vertices() >= 20_000,
        "{}",
        domain.mesh.n_vertices()
    );
}

/// Shepard weights sampled at the vertices: a partition of unity, interpolated linearly.
fn vertex_shepard(domain: &Domain, h: &[Point]) -> MeshWeights {
    let s = Shepard::new(h, ShepardOptions::default());
    let mut w = vec![0.0; domain.mesh.n_vertices() * h.len()];
    for (v, row) in w.chunks_mut(h.len()).enumerate() {
        s.eval(domain.mesh.vertices[v], row);
    }
    MeshWeights::new(&domain.mesh, w, h.len()).expect("mesh weights")
}

/// Reference weighted Gram matrices of curve `c` (without its length factor): the pieces
/// between consecutive `cuts`, each split into `sub` equal parts of 8 Gauss–Legendre nodes.
/// With the cuts at every kink, any `sub` gives the exact integral; a kink missing from the
/// cuts shows as a change with `sub` (the rule is then only O(h²) on that piece).
fn refined_grams(
    w: &dyn WeightField,
    c: &[Point; 4],
    cuts: &[f64],
    sub: usize,
) -> Vec<[[f64; 4]; 4]> {
    let (gt, gw) = gauss_legendre(8);
    let h = w.n_handles();
    let mut m = vec![[[0.0; 4]; 4]; h];
    let mut wv = vec![0.0; h];
    for piece in cuts.windows(2) {
        for q in 0..sub {
            let a = piece[0] + (piece[1] - piece[0]) * q as f64 / sub as f64;
            let b = piece[0] + (piece[1] - piece[0]) * (q + 1) as f64 / sub as f64;
            for (&s, &g) in gt.iter().zip(&gw) {
                let t = a + (b - a) * s;
                w.eval(splineskin::bezier::eval(c, t), &mut wv);
                let bt = bernstein(t);
                for i in 0..h {
                    for k in 0..4 {
                        for l in 0..4 {
                            m[i][k][l] += (b - a) * g * wv[i] * bt[k] * bt[l];
                        }
                    }
                }
            }
        }
    }
    m
}

/// Largest entry of `|a − b|` relative to `Â₀₀` (the scale of a unit-length curve's Gram).
fn gram_difference(a: &[[[f64; 4]; 4]], b: &[[[f64; 4]; 4]]) -> f64 {
    let a00 = bernstein_gram()[0][0];
    a.iter()
        .zip(b)
        .flat_map(|(x, y)| (0..16).map(move |k| (x[k / 4][k % 4] - y[k / 4][k % 4]).abs() / a00))
        .fold(0.0, f64::max)
}

/// The integration error of the fit's quadrature on mesh weights, over every `stride`-th
/// curve: the library's weighted Gram matrices (`SampledCurves`, kinks from
/// `MeshWeights::kinks`, divided by the curve's length) against the same cuts refined 16
/// times. Returns it with the same figure for the default rule without kinks (4 equal
/// pieces against 64), which shows the check detects missing kinks.
fn integration_error(d: &Drawing, w: &MeshWeights, stride: usize) -> (f64, f64) {
    let t = Instant::now();
    let samples = SampledCurves::sample(d, w, &FitOptions::default());
    let n_nodes: usize = (0..samples.n_curves())
        .map(|j| samples.curve(j).t.len())
        .sum();
    eprintln!(
        "  sampling {} curves with kinks: {} nodes in {:.3} s",
        samples.n_curves(),
        n_nodes,
        t.elapsed().as_secs_f64()
    );
    let a00 = bernstein_gram()[0][0];
    let quarters = [0.0, 0.25, 0.5, 0.75, 1.0];
    let (mut with, mut without): (f64, f64) = (0.0, 0.0);
    let mut j = 0;
    let mut m = Vec::new();
    for p in &d.paths {
        for k in 0..p.n_curves() {
            if j % stride == 0 {
                let c = p.curve_points(k);
                let nodes = samples.curve(j);
                let len = nodes.gram()[0][0] / a00;
                nodes.weighted_grams(&mut m);
                for mi in &mut m {
                    for row in mi.iter_mut() {
                        for x in row.iter_mut() {
                            *x /= len;
                        }
                    }
                }
                let mut cuts = quarters.to_vec();
                w.kinks(&c, &mut cuts);
                cuts.sort_by(f64::total_cmp);
                cuts.dedup();
                with = with.max(gram_difference(&m, &refined_grams(w, &c, &cuts, 16)));
                let coarse = refined_grams(w, &c, &quarters, 1);
                without = without.max(gram_difference(
                    &coarse,
                    &refined_grams(w, &c, &quarters, 16),
                ));
            }
            j += 1;
        }
    }
    (with, without)
}

/// The integration error accepted for mesh weights in the fit: 1e-12 relative to `ℓ Â₀₀`.
/// With kinks the rule is exact on each piece (module doc of `domain::locate`), so only
/// rounding over the ~50 pieces of a curve remains (measured 6.4e-14 on the fish, 1.4e-14 on
/// the turtles, printed); without kinks the same figure is 6.5e-6 and 1.6e-5.
const ACCEPTED_INTEGRATION_ERROR: f64 = 1e-12;

/// Smallest error the check must see without kinks for it to count as able to fail: 1e-7.
const NO_KINKS_DETECTED: f64 = 1e-7;

/// Builds the domain of `d` named `name` with vertex Shepard weights of the handles `h`, and
/// checks that the quadrature with kinks integrates them exactly (every `stride`-th curve;
/// [`ACCEPTED_INTEGRATION_ERROR`]) while the one without kinks does not
/// ([`NO_KINKS_DETECTED`]). Returns the weights.
fn check_exact_integration(name: &str, d: &Drawing, h: &[Point], stride: usize) -> MeshWeights {
    let domain = build(name, d, h);
    let w = vertex_shepard(&domain, h);
    let (err, control) = integration_error(d, &w, stride);
    eprintln!(
        "  {name}: weighted Gram error with kinks {err:e}, without {control:e} (relative to \
         ℓ Â00, every curve in {stride})"
    );
    assert!(err < ACCEPTED_INTEGRATION_ERROR, "{err:e}");
    assert!(control > NO_KINKS_DETECTED, "{control:e}");
    w
}

#[test]
fn mesh_weights_fish_integrate_exactly_and_reproduce_identity() {
    let (d, h) = fish();
    let w = check_exact_integration("fish", &d, &h, 1);

    // The rig on mesh weights: identity transforms reproduce the drawing, and one affine map
    // on every handle maps it (weights sum to one at every node, DESIGN.md §1).
    let rig = SplineRig::precompute(&d, &w, &FitOptions::default()).expect("rig");
    let a = Affine::translate((30.0, -12.0)) * Affine::rotate(0.4);
    common::measure::assert_affine_reproduction(&rig, &d, h.len(), a, "  fish");
}

#[test]
fn mesh_weights_turtles_integrate_exactly() {
    let Some((d, h)) = turtles() else { return };
    check_exact_integration("turtles", &d, &h, 3);
}

#[test]
fn mesh_weights_fish_reproduce_affine_functions_at_nodes() {
    let (d, h) = fish();
    let domain = build("fish", &d, &h);
    let f = |p: Point| {
        [
            2.0 - 0.01 * p.x + 0.03 * p.y,
            0.5 + 0.002 * p.x * 1.0 - 0.004 * p.y,
        ]
    };
    let w: Vec<f64> = domain.mesh.vertices.iter().flat_map(|&p| f(p)).collect();
    let w = MeshWeights::new(&domain.mesh, w, 2).unwrap();
    let mut out = [0.0; 2];
    let mut n = 0;
    for p in &d.paths {
        for j in 0..p.n_curves() {
            let c = p.curve_points(j);
            for k in 0..=16 {
                let q = splineskin::bezier::eval(&c, k as f64 / 16.0);
                w.eval(q, &mut out);
                let e = f(q);
                assert!((out[0] - e[0]).abs() < 1e-12 && (out[1] - e[1]).abs() < 1e-12);
                n += 1;
            }
        }
    }
    assert_eq!(n, 17 * d.n_curves());
}
