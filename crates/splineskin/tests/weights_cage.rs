//! Cage weight families: mean value coordinates (closed form, `weights::mvc`) and harmonic
//! coordinates (on a caged domain, `weights::cage`). Properties every cage coordinate must have
//! — partition of unity, linear precision, Lagrange at the corners, linear along the edges,
//! bounds — on convex and non-convex cages, and closed forms where they are known (barycentric
//! coordinates in a triangle, symmetry at the centre of a regular polygon, bilinear coordinates
//! in a rectangle).

mod common;

use common::Rng;
use kurbo::Point;
use splineskin::domain::{Boundary, Domain, DomainError, DomainOptions};
use splineskin::drawing::{read_svg, Drawing, ImportOptions};
use splineskin::weights::{
    cage_boundary_data, harmonic_coordinates, MeanValue, VertexWeights, WeightField, WeightsError,
};

fn pts(v: &[(f64, f64)]) -> Vec<Point> {
    v.iter().map(|&p| Point::from(p)).collect()
}

fn square() -> Vec<Point> {
    pts(&[(0., 0.), (1., 0.), (1., 1.), (0., 1.)])
}

fn l_shape() -> Vec<Point> {
    pts(&[(0., 0.), (4., 0.), (4., 2.), (2., 2.), (2., 4.), (0., 4.)])
}

/// A five-pointed star (10 vertices, reflex ones at radius 0.4), centred at `(cx, cy)`.
fn star(cx: f64, cy: f64) -> Vec<Point> {
    (0..10)
        .map(|k| {
            let a = std::f64::consts::FRAC_PI_2 + k as f64 * std::f64::consts::PI / 5.0;
            let r = if k % 2 == 0 { 1.0 } else { 0.4 };
            Point::new(cx + r * a.cos(), cy + r * a.sin())
        })
        .collect()
}

/// A comb (three teeth), far from the origin so that translation is exercised.
fn comb() -> Vec<Point> {
    pts(&[
        (0., 0.),
        (5., 0.),
        (5., 3.),
        (4., 3.),
        (4., 1.),
        (3., 1.),
        (3., 3.),
        (2., 3.),
        (2., 1.),
        (1., 1.),
        (1., 3.),
        (0., 3.),
    ])
    .into_iter()
    .map(|p| Point::new(p.x + 1000.0, p.y - 2000.0))
    .collect()
}

fn regular(n: usize, phase: f64) -> Vec<Point> {
    (0..n)
        .map(|k| {
            let a = phase + 2.0 * std::f64::consts::PI * k as f64 / n as f64;
            Point::new(3.0 + 2.0 * a.cos(), -1.0 + 2.0 * a.sin())
        })
        .collect()
}

/// Even–odd containment (points exactly on the polygon are not drawn by the tests).
fn inside(poly: &[Point], p: Point) -> bool {
    let n = poly.len();
    let mut c = false;
    for k in 0..n {
        let (a, b) = (poly[k], poly[(k + 1) % n]);
        if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x) {
            c = !c;
        }
    }
    c
}

/// Bounding box `(min, max)` and diagonal of a polygon.
fn bounds(poly: &[Point]) -> (Point, Point, f64) {
    let lo = poly
        .iter()
        .fold(Point::new(f64::INFINITY, f64::INFINITY), |a, p| {
            Point::new(a.x.min(p.x), a.y.min(p.y))
        });
    let hi = poly
        .iter()
        .fold(Point::new(f64::NEG_INFINITY, f64::NEG_INFINITY), |a, p| {
            Point::new(a.x.max(p.x), a.y.max(p.y))
        });
    (lo, hi, (hi - lo).hypot())
}

/// `Σ_i w_i (c_i − p)`, the linear-precision residual computed without the cancellation of
/// `Σ w_i c_i − p` far from the origin.
fn residual(cage: &[Point], w: &[f64], p: Point) -> f64 {
    cage.iter()
        .zip(w)
        .fold(kurbo::Vec2::ZERO, |acc, (c, wi)| acc + (*c - p) * *wi)
        .hypot()
}

// ---------------------------------------------------------------------------------------------
// Mean value coordinates
// ---------------------------------------------------------------------------------------------

/// The weight of corner `i` of an `n`-corner cage at the point `s` of the way along edge `k`
/// (from corner `k` to corner `k + 1`): coordinates linear on the edge, `1 − s` and `s` on its
/// ends, 0 on every other corner.
fn on_edge_weight(n: usize, k: usize, s: f64, i: usize) -> f64 {
    if i == k {
        1.0 - s
    } else if i == (k + 1) % n {
        s
    } else {
        0.0
    }
}

/// Partition of unity and linear precision: rounding of `n`-term sums of weights of order 1,
/// measured worst 1.6e-15 (sum) and 3.5e-15 (residual over the diagonal) over the cages and
/// points below. 1e-12, the issue's figure, leaves room for other platforms' libm; a wrong
/// formula (say, unsigned angles outside) is off by order 1.
const MVC_IDENTITY_TOLERANCE: f64 = 1e-12;

#[test]
fn mvc_partition_of_unity_and_linear_precision() {
    let mut rng = Rng(7);
    let mut worst_sum: f64 = 0.0;
    let mut worst_linear: f64 = 0.0;
    for cage in [
        square(),
        l_shape(),
        star(0.3, -0.2),
        comb(),
        regular(7, 0.3),
    ] {
        let mvc = MeanValue::new(&cage).unwrap();
        let (lo, hi, diag) = bounds(&cage);
        let mut w = vec![0.0; cage.len()];
        let (mut n_in, mut n_out) = (0, 0);
        for _ in 0..4000 {
            // The bounding box grown by its size on every side: about 8 of 9 points outside.
            let p = Point::new(
                lo.x + (hi.x - lo.x) * (3.0 * rng.next_f64() - 1.0),
                lo.y + (hi.y - lo.y) * (3.0 * rng.next_f64() - 1.0),
            );
            if inside(&cage, p) {
                n_in += 1;
            } else {
                n_out += 1;
            }
            mvc.eval(p, &mut w);
            let sum: f64 = w.iter().sum();
            worst_sum = worst_sum.max((sum - 1.0).abs());
            worst_linear = worst_linear.max(residual(&cage, &w, p) / diag);
        }
        assert!(n_in > 100 && n_out > 100, "{n_in} inside, {n_out} outside");
    }
    eprintln!(
        "mvc: worst |Σw − 1| = {worst_sum:e}, worst |Σ w_i (c_i − p)| / diag = {worst_linear:e}"
    );
    assert!(worst_sum < MVC_IDENTITY_TOLERANCE, "{worst_sum:e}");
    assert!(worst_linear < MVC_IDENTITY_TOLERANCE, "{worst_linear:e}");
}

#[test]
fn mvc_far_away_loses_accuracy_gradually() {
    // Far outside, the signed angles nearly cancel in Σ w̃: the relative error grows like the
    // distance d over the cage's size. Measured (L shape, d in sizes): 3.7e-15 at d = 10,
    // 2.3e-14 at 100, 2.9e-13 at 1000, i.e. about 3e-16 d. Computing A_i as s_i × s_{i+1}
    // instead of s_i × e_i would add a factor d (measured 1.6e-10 at d = 1000), which the
    // bound 1e-15 d rejects.
    let cage = l_shape();
    let mvc = MeanValue::new(&cage).unwrap();
    let mut w = [0.0; 6];
    for d in [1e1, 1e2, 1e3] {
        for a in [0.3f64, 2.0, 4.0] {
            let p = Point::new(2.0 + 4.0 * d * a.cos(), 2.0 + 4.0 * d * a.sin());
            mvc.eval(p, &mut w);
            let sum: f64 = w.iter().sum();
            let err = (sum - 1.0).abs().max(residual(&cage, &w, p) / (4.0 * d));
            eprintln!("mvc far: d = {d:e} sizes, angle {a}: error {err:e}");
            assert!(err < 1e-15 * d, "d = {d}: {err:e}");
        }
    }
}

#[test]
fn mvc_lagrange_at_vertices_and_linear_on_edges() {
    let mut rng = Rng(11);
    for cage in [square(), l_shape(), star(0.0, 0.0), comb()] {
        let n = cage.len();
        let mvc = MeanValue::new(&cage).unwrap();
        let mut w = vec![0.0; n];
        for (k, &v) in cage.iter().enumerate() {
            mvc.eval(v, &mut w);
            for i in 0..n {
                assert_eq!(w[i], if i == k { 1.0 } else { 0.0 }, "vertex {k}");
            }
        }
        for k in 0..n {
            let (a, b) = (cage[k], cage[(k + 1) % n]);
            for _ in 0..20 {
                let s = rng.next_f64();
                let p = a.lerp(b, s);
                mvc.eval(p, &mut w);
                // p is a + s(b − a) rounded: off the edge's line by ~1e-16 of the coordinates
                // (1e-13 for the comb, 2000 from the origin), which moves the weights as much
                // relative to the edge length.
                for i in 0..n {
                    let expected = on_edge_weight(n, k, s, i);
                    assert!(
                        (w[i] - expected).abs() < 1e-12,
                        "edge {k}, s = {s}, weight {i}: {} vs {expected}",
                        w[i]
                    );
                }
            }
        }
    }
}

#[test]
fn mvc_positive_inside_convex_cages() {
    let mut rng = Rng(3);
    let irregular = pts(&[(0., 0.), (5., -1.), (7., 2.), (6., 5.), (2., 6.), (-1., 3.)]);
    for cage in [square(), regular(5, 0.1), regular(12, 0.0), irregular] {
        let mvc = MeanValue::new(&cage).unwrap();
        let (lo, hi, _) = bounds(&cage);
        let mut w = vec![0.0; cage.len()];
        let mut n_in = 0;
        while n_in < 2000 {
            let p = Point::new(
                lo.x + (hi.x - lo.x) * rng.next_f64(),
                lo.y + (hi.y - lo.y) * rng.next_f64(),
            );
            if !inside(&cage, p) {
                continue;
            }
            n_in += 1;
            mvc.eval(p, &mut w);
            assert!(w.iter().all(|&wi| wi > 0.0), "{p:?}: {w:?}");
        }
    }
    // Control: inside a non-convex cage some weights are negative (so the check can fail).
    let mvc = MeanValue::new(&l_shape()).unwrap();
    let mut w = [0.0; 6];
    mvc.eval(Point::new(3.9, 1.9), &mut w);
    assert!(w.iter().any(|&wi| wi < 0.0), "{w:?}");
}

#[test]
fn mvc_symmetric_at_the_centre() {
    let mvc = MeanValue::new(&square()).unwrap();
    let mut w = [0.0; 4];
    mvc.eval(Point::new(0.5, 0.5), &mut w);
    for wi in w {
        assert!((wi - 0.25).abs() < 1e-15, "{w:?}");
    }
    for n in 3..=16 {
        let cage = regular(n, 0.37);
        let mvc = MeanValue::new(&cage).unwrap();
        let mut w = vec![0.0; n];
        mvc.eval(Point::new(3.0, -1.0), &mut w);
        for &wi in &w {
            assert!((wi - 1.0 / n as f64).abs() < 1e-14, "n = {n}: {w:?}");
        }
    }
}

#[test]
fn mvc_in_a_triangle_are_barycentric_coordinates() {
    // For a triangle the coordinates are fixed by the two properties every MVC have:
    // Σ w_i = 1 and Σ w_i v_i = x are three linear equations in (w_0, w_1, w_2) whose matrix
    // [v_0 v_1 v_2; 1 1 1] is invertible (twice the triangle's area is its determinant), so
    // the only solution is the barycentric one, w_i = area(x, v_{i+1}, v_{i+2}) / area(triangle)
    // — inside and outside alike.
    let t = pts(&[(1., 1.), (6., 2.), (2., 5.)]);
    let mvc = MeanValue::new(&t).unwrap();
    let area = |a: Point, b: Point, c: Point| 0.5 * (b - a).cross(c - a);
    let total = area(t[0], t[1], t[2]);
    let mut w = [0.0; 3];
    // By hand for x = (3, 2.5): areas (x, v1, v2) = ½·(3·2.5 − (−0.5)(−1)) = ½·(7.5 − 0.5) = 3.5,
    // total = ½·(5·4 − 1·1) = 9.5, so w_0 = 7/19.
    mvc.eval(Point::new(3.0, 2.5), &mut w);
    assert!((w[0] - 7.0 / 19.0).abs() < 1e-15, "{w:?}");
    for x in [
        (3.0, 2.5),
        (2.0, 2.0),
        (5.0, 2.2),
        (0.0, 0.0),
        (8.0, 8.0),
        (4.0, -3.0),
    ] {
        let x = Point::from(x);
        mvc.eval(x, &mut w);
        for i in 0..3 {
            let b = area(x, t[(i + 1) % 3], t[(i + 2) % 3]) / total;
            assert!(
                (w[i] - b).abs() < 1e-14,
                "{x:?}: {w:?}, barycentric {i} = {b}"
            );
        }
    }
}

/// The largest jump, over the weights, between the one-sided slopes of `w_i(p + s d)` in `s`
/// at `s = 0` (forward differences of step `h` on either side).
fn slope_jump(mvc: &MeanValue, p: Point, d: kurbo::Vec2) -> f64 {
    let h = 1e-6;
    let n = mvc.n_handles();
    let mut w = vec![vec![0.0; n]; 3];
    for (k, wk) in w.iter_mut().enumerate() {
        mvc.eval(p + d * ((k as f64 - 1.0) * h), wk);
    }
    (0..n)
        .map(|i| ((w[2][i] - w[1][i]) / h - (w[1][i] - w[0][i]) / h).abs())
        .fold(0.0, f64::max)
}

#[test]
fn mvc_smooth_across_edges_kinked_at_vertices() {
    // Only the vertices are kinks (module documentation of `weights::mvc`): crossing an edge,
    // the one-sided slopes agree to the differences' own error (O(h |w''|) = O(1e-6));
    // through a vertex they differ by O(1).
    let dx = kurbo::Vec2::new(1.0, 0.0);
    let diagonal = kurbo::Vec2::new(1.0, 1.0).normalize();
    for cage in [square(), l_shape(), star(0.0, 0.0)] {
        let mvc = MeanValue::new(&cage).unwrap();
        let n = cage.len();
        for k in 0..n {
            let (a, b) = (cage[k], cage[(k + 1) % n]);
            let normal = (b - a).turn_90().normalize();
            for s in [0.17, 0.5, 0.81] {
                let jump = slope_jump(&mvc, a.lerp(b, s), normal);
                assert!(jump < 1e-4, "edge {k} at s = {s}: slope jump {jump:e}");
            }
            // Through the vertex, along the bisector of its edges' directions or across it.
            let d = ((b - a).normalize() - (a - cage[(k + n - 1) % n]).normalize()).normalize();
            let d = if d.is_finite() { d } else { dx };
            let jump = slope_jump(&mvc, a, d).max(slope_jump(&mvc, a, d.turn_90()));
            assert!(jump > 0.1, "vertex {k}: slope jump {jump:e}");
        }
    }
    let mvc = MeanValue::new(&square()).unwrap();
    eprintln!(
        "mvc slope jumps: across the edge x = 0 at y = 0.3: {:e}; through vertex (0, 0) along \
         the diagonal: {:e}",
        slope_jump(&mvc, Point::new(0.0, 0.3), dx),
        slope_jump(&mvc, Point::ZERO, diagonal)
    );
}

#[test]
fn mvc_kinks_where_a_cubic_passes_a_vertex() {
    let mvc = MeanValue::new(&square()).unwrap();
    // The straight cubic y = 0.3 from x = −0.5 to 1.5 crosses two edges: no kink (smooth).
    let line = [-0.5, 1.0 / 6.0, 5.0 / 6.0, 1.5].map(|x| Point::new(x, 0.3));
    let mut kinks = vec![9.0]; // appended to: earlier content stays
    mvc.kinks(&line, &mut kinks);
    assert_eq!(kinks, [9.0]);
    // On the line y = x, with x(t) = −0.5 (1 − t)³ + 3 t² (1 − t) + 1.5 t³: it passes the cage
    // vertices (0, 0) and (1, 1), each on two edges at once — one kink each, not two.
    let diagonal = [-0.5, 0.0, 1.0, 1.5].map(|x| Point::new(x, x));
    kinks.clear();
    mvc.kinks(&diagonal, &mut kinks);
    assert_eq!(kinks.len(), 2, "{kinks:?}");
    for (&t, target) in kinks.iter().zip([0.0, 1.0]) {
        let x = -0.5 * (1.0 - t).powi(3) + 3.0 * t * t * (1.0 - t) + 1.5 * t.powi(3);
        assert!((x - target).abs() < 1e-13, "t = {t}: x = {x}");
    }
    // A curved cubic through vertex (1, 0) at t = ½: B(½) = (P0 + 3 P1 + 3 P2 + P3) / 8, so
    // P2 = (8 v − P0 − P3) / 3 − P1.
    let v = Point::new(1.0, 0.0);
    let (p0, p1, p3) = (
        Point::new(0.4, -0.6),
        Point::new(0.9, 0.5),
        Point::new(1.7, 0.3),
    );
    let p2 = ((v.to_vec2() * 8.0 - p0.to_vec2() - p3.to_vec2()) / 3.0 - p1.to_vec2()).to_point();
    kinks.clear();
    mvc.kinks(&[p0, p1, p2, p3], &mut kinks);
    assert_eq!(kinks.len(), 1, "{kinks:?}");
    assert!((kinks[0] - 0.5).abs() < 1e-13, "{kinks:?}");
    // The same curve moved 1e-3 off the vertex: smooth, no kink.
    let off = kurbo::Vec2::new(1e-3, 0.0);
    kinks.clear();
    mvc.kinks(&[p0 + off, p1 + off, p2 + off, p3 + off], &mut kinks);
    assert!(kinks.is_empty(), "{kinks:?}");
    // A curve inside, and one far away, cross nothing.
    let arc = pts(&[(0.2, 0.2), (0.2, 0.9), (0.9, 0.9), (0.8, 0.3)]);
    mvc.kinks(&[arc[0], arc[1], arc[2], arc[3]], &mut kinks);
    mvc.kinks(
        &[(5., 5.), (6., 7.), (7., 5.), (8., 6.)].map(Point::from),
        &mut kinks,
    );
    assert!(kinks.is_empty(), "{kinks:?}");
}

#[test]
fn mvc_rejects_bad_cages() {
    let cage_error = |c: &[Point]| match MeanValue::new(c) {
        Err(WeightsError::Cage(e)) => e,
        other => panic!("{other:?}"),
    };
    let mut clockwise = square();
    clockwise.reverse();
    assert!(matches!(
        cage_error(&clockwise),
        DomainError::CageClockwise { signed_area } if signed_area == -1.0
    ));
    assert_eq!(
        cage_error(&square()[..2]),
        DomainError::CageTooFewVertices { n_vertices: 2 }
    );
    // A closing vertex repeating the first does not count.
    let s = square();
    assert_eq!(
        cage_error(&[s[0], s[1], s[0]]),
        DomainError::CageTooFewVertices { n_vertices: 2 }
    );
    let mut nan = square();
    nan[2].y = f64::NAN;
    assert_eq!(cage_error(&nan), DomainError::CageNonFinite { vertex: 2 });
    let mut inf = square();
    inf[1].x = f64::INFINITY;
    assert_eq!(cage_error(&inf), DomainError::CageNonFinite { vertex: 1 });
    let mut duplicate = square();
    duplicate.insert(2, duplicate[1]);
    assert_eq!(
        cage_error(&duplicate),
        DomainError::CageDegenerateEdge { edge: 1 }
    );
    let bowtie = pts(&[(0., 0.), (1., 1.), (1., 0.), (0., 1.)]);
    assert_eq!(
        cage_error(&bowtie),
        DomainError::CageSelfIntersecting {
            first: 0,
            second: 2
        }
    );
    // The messages name the problem.
    let message = MeanValue::new(&clockwise).unwrap_err().to_string();
    assert!(message.contains("clockwise"), "{message}");
    // The same cages are refused by the domain with the same variant.
    let domain_error = |c: &[Point]| {
        Domain::build(
            &Drawing::default(),
            &[],
            &[],
            &DomainOptions::default().with_cage(c.to_vec()),
        )
        .unwrap_err()
    };
    for bad in [&clockwise, &nan, &duplicate, &bowtie] {
        assert_eq!(cage_error(bad), domain_error(bad));
    }
}

// ---------------------------------------------------------------------------------------------
// Harmonic coordinates
// ---------------------------------------------------------------------------------------------

fn caged_domain(cage: &[Point], max_area_fraction: f64) -> Domain {
    let options = DomainOptions::default()
        .with_cage(cage.to_vec())
        .with_max_area_fraction(max_area_fraction);
    Domain::build(&Drawing::default(), &[], &[], &options).unwrap()
}

/// Rounding of the sparse solve on meshes of a few thousand vertices with values of order 1:
/// measured at most 5.1e-15 off the partition of unity, and no bound violated at all (the
/// refined Delaunay meshes' cotangent weights are non-negative).
const SOLVE_ROUNDING: f64 = 1e-12;

/// Linear precision holds exactly in exact arithmetic; what is left is the solve's rounding
/// times the Laplacian's conditioning: measured at most 6.1e-16 of the cage's diagonal (on
/// meshes of about 1600 vertices). The issue asks 1e-10; 1e-12 still leaves a wide margin.
const LINEAR_PRECISION: f64 = 1e-12;

#[test]
fn harmonic_coordinates_boundary_values_are_piecewise_linear() {
    for cage in [square(), l_shape(), star(0.0, 0.0)] {
        let domain = caged_domain(&cage, 1.0 / 2000.0);
        let w = harmonic_coordinates(&domain).unwrap();
        let n = cage.len();
        let diag = bounds(&cage).2;
        let outer = &domain.boundary_loops[0];
        assert!(outer.len() > 2 * n, "Steiner points on the edges");
        for &v in outer {
            let p = domain.mesh.vertices[v];
            let row = w.row(v);
            if let Some(k) = cage.iter().position(|&c| c == p) {
                for i in 0..n {
                    assert_eq!(row[i], if i == k { 1.0 } else { 0.0 });
                }
                continue;
            }
            // The edge holding p, found geometrically (independently of the loop walk).
            let k = (0..n)
                .find(|&k| {
                    let (a, b) = (cage[k], cage[(k + 1) % n]);
                    let ab = b - a;
                    let s = (p - a).dot(ab) / ab.hypot2();
                    (p - a).cross(ab).abs() / ab.hypot() < 1e-12 * diag && s > 0.0 && s < 1.0
                })
                .expect("boundary vertex on a cage edge");
            let (a, b) = (cage[k], cage[(k + 1) % n]);
            let s = (p - a).hypot() / (b - a).hypot();
            for i in 0..n {
                let expected = on_edge_weight(n, k, s, i);
                // Exactly 0 off the edge's two corners; on them s by projection vs by
                // distance, equal to rounding.
                if expected == 0.0 {
                    assert_eq!(row[i], 0.0);
                } else {
                    assert!((row[i] - expected).abs() < 1e-14, "{p:?} {i}: {row:?}");
                }
            }
        }
        // The data give exactly these boundary rows.
        let data = cage_boundary_data(&domain).unwrap();
        for (r, &v) in data.vertices().iter().enumerate() {
            assert_eq!(data.values_at(r), w.row(v));
        }
    }
}

/// Worst partition-of-unity error, bound violation and linear precision residual (relative to
/// the cage's diagonal) over all vertices.
fn harmonic_properties(cage: &[Point], domain: &Domain, w: &VertexWeights) -> (f64, f64, f64) {
    let diag = bounds(cage).2;
    let (mut sum_err, mut bound_err, mut linear_err): (f64, f64, f64) = (0.0, 0.0, 0.0);
    for v in 0..w.n_vertices() {
        let row = w.row(v);
        sum_err = sum_err.max((row.iter().sum::<f64>() - 1.0).abs());
        for &wi in row {
            bound_err = bound_err.max(-wi).max(wi - 1.0);
        }
        linear_err = linear_err.max(residual(cage, row, domain.mesh.vertices[v]) / diag);
    }
    (sum_err, bound_err, linear_err)
}

#[test]
fn harmonic_coordinates_partition_bounds_and_linear_precision() {
    for (name, cage) in [
        ("square", square()),
        ("L", l_shape()),
        ("star", star(0.3, -0.2)),
        ("comb", comb()),
    ] {
        let domain = caged_domain(&cage, 1.0 / 2000.0);
        let w = harmonic_coordinates(&domain).unwrap();
        assert_eq!(
            (w.n_vertices(), w.n_handles()),
            (domain.mesh.n_vertices(), cage.len())
        );
        let (sum_err, bound_err, linear_err) = harmonic_properties(&cage, &domain, &w);
        eprintln!(
            "harmonic {name}: {} vertices, min angle {:.1}°: |Σw − 1| ≤ {sum_err:e}, \
             bounds violated by ≤ {bound_err:e}, linear residual ≤ {linear_err:e}",
            domain.mesh.n_vertices(),
            Domain::min_angle_of(&domain.mesh)
        );
        assert!(sum_err < SOLVE_ROUNDING, "{name}: {sum_err:e}");
        assert!(bound_err < SOLVE_ROUNDING, "{name}: {bound_err:e}");
        assert!(linear_err < LINEAR_PRECISION, "{name}: {linear_err:e}");
    }
    // Control: harmonic coordinates are not mean value coordinates (the L's reflex corner
    // pulls them apart), so the two families are really different functions.
    let cage = l_shape();
    let domain = caged_domain(&cage, 1.0 / 2000.0);
    let w = harmonic_coordinates(&domain).unwrap();
    let mvc = MeanValue::new(&cage).unwrap();
    let mut m = [0.0; 6];
    let mut worst: f64 = 0.0;
    for v in 0..w.n_vertices() {
        mvc.eval(domain.mesh.vertices[v], &mut m);
        for i in 0..6 {
            worst = worst.max((m[i] - w.get(v, i)).abs());
        }
    }
    assert!(worst > 0.01, "{worst:e}");
}

#[test]
fn harmonic_coordinates_with_a_drawing_and_point_handles_in_the_cage() {
    // A wave partly outside an L-shaped cage (its samples inside become vertices, those
    // outside are dropped) and a point handle (ignored: one column per cage corner).
    let svg = r#"<svg xmlns="http://www.w3.org/2000/svg">
        <path d="M-20 50 C20 -10 60 110 120 50"/></svg>"#;
    let drawing = read_svg(svg, &ImportOptions::default()).unwrap();
    let cage = pts(&[
        (0., 0.),
        (100., 0.),
        (100., 40.),
        (40., 40.),
        (40., 100.),
        (0., 100.),
    ]);
    let options = DomainOptions::default().with_cage(cage.clone());
    let domain = Domain::build(&drawing, &[Point::new(20.0, 20.0)], &[], &options).unwrap();
    assert!(domain.n_curve_samples > 10, "{}", domain.n_curve_samples);
    let w = harmonic_coordinates(&domain).unwrap();
    assert_eq!(w.n_handles(), 6);
    let (sum_err, bound_err, linear_err) = harmonic_properties(&cage, &domain, &w);
    eprintln!(
        "harmonic, L cage with a wave: {} vertices: |Σw − 1| ≤ {sum_err:e}, bounds violated by \
         ≤ {bound_err:e}, linear residual ≤ {linear_err:e}",
        domain.mesh.n_vertices()
    );
    assert!(sum_err < SOLVE_ROUNDING, "{sum_err:e}");
    assert!(bound_err < SOLVE_ROUNDING, "{bound_err:e}");
    assert!(linear_err < LINEAR_PRECISION, "{linear_err:e}");
}

/// Largest difference at the vertices between the harmonic coordinates of the rectangle
/// `[0, 2] × [0, 1]` and its bilinear coordinates — which are harmonic (`∂²/∂x² + ∂²/∂y²` of
/// `x y` is 0) and linear along the edges, so they are the exact harmonic coordinates.
fn bilinear_error(max_area_fraction: f64) -> (usize, f64) {
    let cage = pts(&[(0., 0.), (2., 0.), (2., 1.), (0., 1.)]);
    let domain = caged_domain(&cage, max_area_fraction);
    let w = harmonic_coordinates(&domain).unwrap();
    let mut worst: f64 = 0.0;
    for (v, p) in domain.mesh.vertices.iter().enumerate() {
        let (u, t) = (p.x / 2.0, p.y);
        let bilinear = [(1.0 - u) * (1.0 - t), u * (1.0 - t), u * t, (1.0 - u) * t];
        for i in 0..4 {
            worst = worst.max((w.get(v, i) - bilinear[i]).abs());
        }
    }
    (domain.mesh.n_vertices(), worst)
}

/// Harmonic coordinates of a rectangle against bilinear coordinates at the default resolution
/// (largest triangle 1/5000 of the area, 4004 vertices): measured 3.3e-5 (P1 elements converge
/// at O(h²) at the vertices). At 1/500 of the area the error is larger, at 1/50 (46 vertices)
/// 1.5e-3.
const BILINEAR_TOLERANCE: f64 = 4e-5;

#[test]
fn harmonic_coordinates_converge_to_bilinear_on_a_rectangle() {
    let (n_default, default) = bilinear_error(DomainOptions::default().max_area_fraction);
    let (n_medium, medium) = bilinear_error(1.0 / 500.0);
    let (n_coarse, coarse) = bilinear_error(1.0 / 50.0);
    eprintln!(
        "harmonic vs bilinear: {default:e} at {n_default} vertices (default), {medium:e} at \
         {n_medium} vertices, {coarse:e} at {n_coarse} vertices"
    );
    assert!(default < BILINEAR_TOLERANCE, "{default:e}");
    // Control: the bound is not met trivially — coarser meshes are further off, in order.
    assert!(
        medium > BILINEAR_TOLERANCE && coarse > medium,
        "{medium:e} {coarse:e}"
    );
}

#[test]
fn harmonic_coordinates_need_a_cage() {
    // A drawing's padded box as the domain: no cage.
    let svg =
        r#"<svg xmlns="http://www.w3.org/2000/svg"><path d="M0 0 C30 40 70 40 100 0"/></svg>"#;
    let drawing = read_svg(svg, &ImportOptions::default()).unwrap();
    let domain = Domain::build(&drawing, &[], &[], &DomainOptions::default()).unwrap();
    assert_eq!(domain.boundary, Boundary::Padded);
    assert_eq!(harmonic_coordinates(&domain), Err(WeightsError::NoCage));
    assert_eq!(cage_boundary_data(&domain), Err(WeightsError::NoCage));
}
