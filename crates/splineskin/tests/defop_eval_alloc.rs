//! `DefOpEvaluator::eval` and `spatial_coefficients` allocate nothing (STYLE.md: no allocation
//! per frame), for the hat basis and a reduced one, polynomial and thin-plate handle bases, and
//! when they reject a configuration or buffer of the wrong size.
//!
//! Its own test binary: the counting global allocator applies to the whole binary.

#[path = "common/alloc_checks.rs"]
mod alloc_checks;
#[path = "common/defop_data.rs"]
mod defop_data;

use alloc_checks::assert_counter_counts;
use counting_alloc::{count, Counts};
use defop_data::{arap_solutions, fit_on_hats, rest_and_disc_samples};
use kurbo::{Point, Rect, Vec2};
use splineskin::defop::{
    Arap, ArapOptions, DefOp, DefOpOptions, EigenOperator, HandleBasisKind, SpatialBasis,
};
use splineskin::mesh::TriMesh;
use std::hint::black_box;

#[test]
fn defop_evaluation_allocates_nothing() {
    assert_counter_counts();

    let mesh = TriMesh::grid(Rect::new(0., 0., 4., 1.), 16, 4).unwrap();
    let handles = [34, 50, 76];
    let rest: Vec<Point> = handles.iter().map(|&h| mesh.vertices[h]).collect();
    let arap = Arap::new(&mesh, &handles, ArapOptions::default()).unwrap();
    let configurations = rest_and_disc_samples(&rest, 0.5, 5, 20);
    let solutions = arap_solutions(&arap, &mesh, &configurations);
    let bases = [
        SpatialBasis::hats(&mesh).unwrap(),
        SpatialBasis::laplacian_eigenfunctions(&mesh, 12, EigenOperator::LinearlyPrecise).unwrap(),
    ];
    let q: Vec<Point> = rest.iter().map(|&p| p + Vec2::new(0.2, -0.1)).collect();
    let fit = |spatial: &SpatialBasis, options: &DefOpOptions| {
        DefOp::fit(
            &mesh,
            &handles,
            spatial,
            &configurations,
            &solutions,
            options,
        )
        .unwrap()
    };
    for spatial in &bases {
        for kind in [HandleBasisKind::Cubic, HandleBasisKind::ThinPlateSpline] {
            let options = DefOpOptions::default().with_handle_basis(kind);
            let op = fit(spatial, &options);
            let mut evaluator = op.evaluator();
            let mut positions = vec![Point::ZERO; mesh.n_vertices()];
            evaluator.eval(&q, &mut positions).unwrap(); // warm-up
            positions.fill(Point::new(f64::NAN, f64::NAN));
            let (result, counts) =
                count(|| evaluator.eval(black_box(&q), black_box(&mut positions)));
            result.unwrap();
            assert_eq!(counts, Counts::default(), "{:?}/{kind:?}", spatial.kind());
            assert!(positions.iter().all(|p| p.is_finite()));
            let (result, counts) = count(|| {
                evaluator
                    .spatial_coefficients(black_box(&q))
                    .map(|c| c.len())
            });
            assert_eq!(result.unwrap(), 2 * spatial.n_functions());
            assert_eq!(counts, Counts::default());
            let (result, counts) =
                count(|| evaluator.eval(black_box(&q[1..]), black_box(&mut positions)));
            assert!(result.is_err());
            assert_eq!(counts, Counts::default(), "rejected configuration");
            let (result, counts) =
                count(|| evaluator.eval(black_box(&q), black_box(&mut positions[1..])));
            assert!(result.is_err());
            assert_eq!(counts, Counts::default(), "rejected buffer");
        }
    }
}

/// A large operator (3 721 vertices, 9 handles, 400 thin-plate centres: `G` is 7 442 × 419),
/// where faer's matrix product takes its blocked path, allocates nothing either. Its training
/// data are made up (any deformation that puts the handles on their targets fits).
#[test]
fn defop_evaluation_of_a_large_operator_allocates_nothing() {
    let mesh = TriMesh::grid(Rect::new(0., 0., 6., 6.), 60, 60).unwrap();
    let handles: Vec<usize> = (0..9)
        .map(|k| 61 * (10 + 20 * (k / 3)) + 10 + 20 * (k % 3))
        .collect();
    let rest: Vec<Point> = handles.iter().map(|&h| mesh.vertices[h]).collect();
    let configurations = rest_and_disc_samples(&rest, 0.5, 8, 399);
    // Made up: a smooth wave following handle 4's shift, then the handles on their targets.
    let made_up = |q: &[Point]| {
        let shift = q[4] - rest[4];
        let wave =
            |p: Point| p + shift + Vec2::new((p.y * shift.x).sin(), (p.x * shift.y).cos() - 1.0);
        let mut u: Vec<Point> = mesh.vertices.iter().map(|&p| wave(p)).collect();
        for (&h, &target) in handles.iter().zip(q) {
            u[h] = target;
        }
        u
    };
    let solutions: Vec<Vec<Point>> = configurations.iter().map(|q| made_up(q)).collect();
    let op = fit_on_hats(&mesh, &handles, &configurations, &solutions);
    let mut evaluator = op.evaluator();
    let mut positions = vec![Point::ZERO; mesh.n_vertices()];
    let q: Vec<Point> = rest.iter().map(|&p| p + Vec2::new(0.2, -0.1)).collect();
    evaluator.eval(&q, &mut positions).unwrap(); // warm-up
    let (result, counts) = count(|| evaluator.eval(black_box(&q), black_box(&mut positions)));
    result.unwrap();
    assert_eq!(counts, Counts::default());
    for (&h, &target) in handles.iter().zip(&q) {
        assert!((positions[h] - target).hypot() < 1e-9);
    }
}
