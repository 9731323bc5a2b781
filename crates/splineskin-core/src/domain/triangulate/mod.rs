//! Building a [`Domain`]: validation, boundary choice, vertex placement, constrained Delaunay
//! triangulation and refinement (spade), extraction of the mesh. The rules are stated in the
//! parent module's documentation. One module per step: [`validate`] (input checks), [`sampling`]
//! (scale and curve samples), [`outline`] (the boundary), [`placement`] (vertices and
//! constraint edges), [`cdt`] (triangulation and refinement), [`mesh_features`] (boundary loops,
//! bone vertices, attachments).

mod cdt;
mod mesh_features;
mod outline;
mod placement;
mod sampling;
mod validate;

use kurbo::Point;

use super::{Domain, DomainError, DomainOptions, DomainShape};
use crate::drawing::Drawing;
use crate::mesh::TriMesh;
use cdt::{extract_mesh, triangulate_and_refine};
use mesh_features::{attach, boundary_loops, vertices_on_segment};
pub(super) use outline::Given;
use outline::{art_outline, closed_cage, enclosing_outline, given_outline};
use placement::place_vertices;
use sampling::{measure_scale, sample_curves, sample_spacing};
use validate::{check_handles, check_inputs};

/// Relative tolerance of the check that the kept triangles tile the domain: 1e-9 of its area,
/// plus the rounding of the coordinates along the boundary ([`area_tolerance`]). The polygon
/// and the triangles share their vertices, so only rounding separates the sums.
const AREA_CHECK: f64 = 1e-9;

/// How far the triangles' areas may sum from the polygons' `area`: [`AREA_CHECK`] of it, plus
/// 64 ulps of the largest coordinate times the boundary's length (a drawing far from the
/// origin for its size has vertices rounded by ulps of their distance to it).
fn area_tolerance(loops: &[&[Point]], mesh: &TriMesh, area: f64) -> f64 {
    let largest = mesh
        .vertices
        .iter()
        .fold(0.0f64, |m, p| m.max(p.x.abs()).max(p.y.abs()));
    let perimeter: f64 = loops
        .iter()
        .map(|l| {
            (0..l.len())
                .map(|k| (l[(k + 1) % l.len()] - l[k]).hypot())
                .sum::<f64>()
        })
        .sum();
    AREA_CHECK * area + 64.0 * f64::EPSILON * largest * perimeter
}

/// Builds the domain of `drawing` for the handles `points` and `bones` (the steps below, in
/// order): inputs checked, the scale measured, the curves sampled, the boundary chosen
/// ([`outline::Outline`]), the vertices and constraint edges placed, the constrained Delaunay
/// triangulation made and refined, the kept triangles extracted and checked to tile the
/// boundary, and the handles, cage corners, bones, boundary loops and attachments found in it.
pub(super) fn build(
    drawing: &Drawing,
    points: &[Point],
    bones: &[[Point; 2]],
    options: &DomainOptions,
    given: Option<Given<'_>>,
) -> Result<Domain, DomainError> {
    check_inputs(drawing, points, bones, options)?;
    let cage = options.cage.as_ref().map(|c| closed_cage(c));
    let scale = measure_scale(drawing, points, bones, cage.as_deref())?;
    check_handles(points, bones, scale.coincident)?;
    let spacing = sample_spacing(drawing, scale.drawing_diag, options);
    let samples = sample_curves(drawing, spacing, options);
    let outline = if let Some(given) = given {
        given_outline(given, points, bones, scale.coincident)?
    } else if cage.is_none() && options.shape == DomainShape::Art {
        art_outline(
            drawing,
            points,
            bones,
            options,
            (spacing, scale.coincident, scale.drawing_diag),
        )?
    } else {
        enclosing_outline(
            drawing,
            &samples,
            points,
            bones,
            options,
            cage.as_deref(),
            (
                spacing,
                scale.coincident,
                scale.drawing_diag,
                scale.all_bounds,
            ),
        )?
    };
    let loops: Vec<&[Point]> = outline.loops.iter().map(Vec::as_slice).collect();
    let placed = place_vertices(&loops, &outline, &samples, points, bones, spacing, scale);
    let (cdt, excluded, refinement_complete) =
        triangulate_and_refine(&placed, options, outline.area)?;
    let (mesh, remap) = extract_mesh(&cdt, &excluded)?;
    let mesh_area: f64 = (0..mesh.n_triangles()).map(|t| mesh.signed_area(t)).sum();
    if (mesh_area - outline.area).abs() > area_tolerance(&loops, &mesh, outline.area) {
        return Err(DomainError::Bug(
            "the kept triangles do not tile the domain",
        ));
    }
    let mapped = |i: usize| {
        let m = remap[i];
        (m != usize::MAX)
            .then_some(m)
            .ok_or(DomainError::Bug("an input vertex is not in the mesh"))
    };
    let handle_vertices = placed
        .handle_vertices
        .iter()
        .map(|&i| mapped(i))
        .collect::<Result<Vec<_>, _>>()?;
    let cage_vertices = match cage {
        Some(_) => outline
            .corners
            .iter()
            .map(|&k| mapped(placed.loop_vertices[0][k]))
            .collect::<Result<Vec<_>, _>>()?,
        None => Vec::new(),
    };
    let bone_vertices = bones
        .iter()
        .map(|b| vertices_on_segment(&mesh, b[0], b[1], scale.coincident))
        .collect();
    let boundary_loops = boundary_loops(&mesh)?;
    let attachments = attach(&mesh, &boundary_loops, outline.unpinned);
    tracing::debug!(
        n_vertices = mesh.n_vertices(),
        n_triangles = mesh.n_triangles(),
        n_curve_samples = placed.n_curve_samples,
        spacing,
        boundary = ?outline.boundary,
        refinement_complete,
        "domain triangulated"
    );
    Ok(Domain {
        mesh,
        handle_vertices,
        bone_vertices,
        cage_vertices,
        boundary_loops,
        boundary: outline.boundary,
        area: outline.area,
        sample_spacing: spacing,
        n_curve_samples: placed.n_curve_samples,
        refinement_complete,
        attachments,
    })
}

#[cfg(test)]
mod tests {
    use std::collections::HashSet;

    use kurbo::{ParamCurve, Shape};

    use super::super::polygon::{self_intersection, signed_area, PolygonIndex};
    use super::super::Boundary;
    use super::sampling::curve_intervals;
    use super::validate::on_polygon;
    use super::*;
    use crate::domain::triangle_min_angle;
    use crate::drawing::{JunctionOptions, Path};

    /// A drawing of one path through the given cubics' control points.
    fn path(points: &[(f64, f64)], closed: bool) -> Path {
        let pts: Vec<Point> = points.iter().map(|&p| Point::from(p)).collect();
        Path::new(pts, closed, &JunctionOptions::default()).expect("chain")
    }

    fn drawing(paths: Vec<Path>) -> Drawing {
        Drawing {
            paths,
            ..Default::default()
        }
    }

    /// A wave: two cubics from (0, 0) to (100, 0).
    fn wave() -> Drawing {
        drawing(vec![path(
            &[
                (0., 0.),
                (20., 40.),
                (30., 40.),
                (50., 0.),
                (70., -40.),
                (80., -40.),
                (100., 0.),
            ],
            false,
        )])
    }

    /// A closed blob around (50, 50), radius about 50, as four cubics (circle approximation).
    fn blob(cx: f64, cy: f64, r: f64) -> Path {
        let k = 0.5523 * r;
        path(
            &[
                (cx + r, cy),
                (cx + r, cy + k),
                (cx + k, cy + r),
                (cx, cy + r),
                (cx - k, cy + r),
                (cx - r, cy + k),
                (cx - r, cy),
                (cx - r, cy - k),
                (cx - k, cy - r),
                (cx, cy - r),
                (cx + k, cy - r),
                (cx + r, cy - k),
                (cx + r, cy),
            ],
            true,
        )
    }

    /// The checks every domain must pass: valid CCW mesh, handles are vertices at their exact
    /// position, the triangle areas sum to the domain's area, the boundary loops enclose that
    /// area, and every triangle's smallest angle reaches the option unless it touches a
    /// boundary vertex (where constraint corners can force smaller angles).
    fn check_domain(domain: &Domain, handles: &[Point], options: &DomainOptions) {
        let mesh = &domain.mesh;
        mesh.check().expect("valid mesh");
        assert_eq!(domain.handle_vertices.len(), handles.len());
        for (i, &v) in domain.handle_vertices.iter().enumerate() {
            assert_eq!(mesh.vertices[v], handles[i], "handle {i}");
        }
        let sum: f64 = (0..mesh.n_triangles()).map(|t| mesh.signed_area(t)).sum();
        assert!(
            (sum - domain.area).abs() <= 1e-9 * domain.area,
            "{sum} vs {}",
            domain.area
        );
        let loop_area: f64 = domain
            .boundary_loops
            .iter()
            .map(|l| signed_area(&l.iter().map(|&i| mesh.vertices[i]).collect::<Vec<_>>()))
            .sum();
        assert!((loop_area - domain.area).abs() <= 1e-9 * domain.area);
        let on_boundary: HashSet<usize> = domain.boundary_loops.iter().flatten().copied().collect();
        let mut n_small = 0;
        for t in 0..mesh.n_triangles() {
            let a = triangle_min_angle(mesh, t);
            if a < options.min_angle - 1e-6 {
                n_small += 1;
                assert!(
                    mesh.triangles[t].iter().any(|v| on_boundary.contains(v)),
                    "triangle {t} has angle {a}° away from the boundary"
                );
            }
        }
        assert!(n_small <= 8, "{n_small} triangles below the angle limit");
        assert!(domain.refinement_complete);
    }

    #[test]
    fn domain_padded_box_holds_handles_and_samples() {
        let d = wave();
        let handles = [Point::new(0.0, 0.0), Point::new(50.0, 10.0)];
        let o = DomainOptions::default();
        let domain = Domain::build(&d, &handles, &[], &o).unwrap();
        assert_eq!(domain.boundary, Boundary::Padded);
        check_domain(&domain, &handles, &o);
        // The box: curve bounds (exact cubic extrema, y in ±30) with 5 % of the diagonal.
        let bounds = d.paths[0]
            .curve(0)
            .bounding_box()
            .union(d.paths[0].curve(1).bounding_box());
        let pad = 0.05 * bounds.width().hypot(bounds.height());
        let expected = (bounds.width() + 2.0 * pad) * (bounds.height() + 2.0 * pad);
        assert!((domain.area - expected).abs() < 1e-9 * expected);
        // Every curve sample is a vertex, or was skipped for one within s/2.
        let s = domain.sample_spacing;
        assert!((s - bounds.width().hypot(bounds.height()) / 500.0).abs() < 1e-12);
        let mut exact = 0;
        for j in 0..2 {
            let c = d.paths[0].curve(j);
            let n = curve_intervals(&c, s, &o);
            assert!(n > 50 && n <= 100, "{n}");
            for k in 0..n {
                let p = c.eval(k as f64 / n as f64);
                let nearest = domain
                    .mesh
                    .vertices
                    .iter()
                    .map(|v| (*v - p).hypot())
                    .fold(f64::INFINITY, f64::min);
                assert!(nearest <= 0.5 * s, "sample {j}/{k} at {nearest}");
                exact += (nearest == 0.0) as usize;
            }
        }
        assert!(exact >= 150, "{exact} samples are vertices");
        assert!(domain.n_curve_samples >= exact);
    }

    #[test]
    fn domain_options_change_density() {
        let d = wave();
        let h = [Point::new(10.0, 0.0)];
        let coarse = DomainOptions::default()
            .with_max_area_fraction(0.01)
            .with_samples_per_diagonal(50.0);
        let fine = DomainOptions::default();
        let a = Domain::build(&d, &h, &[], &coarse).unwrap();
        let b = Domain::build(&d, &h, &[], &fine).unwrap();
        check_domain(&a, &h, &coarse);
        assert!(a.mesh.n_vertices() * 4 < b.mesh.n_vertices());
        // A cap on the curve samples enlarges the spacing.
        let capped = DomainOptions::default().with_max_curve_samples(20);
        let c = Domain::build(&d, &h, &[], &capped).unwrap();
        assert!(c.n_curve_samples <= 20 + 1, "{}", c.n_curve_samples);
        assert!(c.sample_spacing > b.sample_spacing * 5.0);
        // A vertex cap stops refinement and says so.
        let stopped = DomainOptions::default().with_max_vertices(500);
        let e = Domain::build(&d, &h, &[], &stopped).unwrap();
        assert!(!e.refinement_complete);
        assert!(e.mesh.n_vertices() <= 500);
    }

    #[test]
    fn domain_cage_bounds_the_mesh() {
        // An L-shaped cage (not convex) cutting the wave: parts of the drawing are outside.
        let cage: Vec<Point> = [
            (-5., -35.),
            (60., -35.),
            (60., 10.),
            (30., 10.),
            (30., 45.),
            (-5., 45.),
        ]
        .map(Point::from)
        .to_vec();
        let handles = [
            Point::new(0.0, 0.0),
            Point::new(45.0, -20.0),
            Point::new(30.0, 45.0),
        ];
        let o = DomainOptions::default().with_cage(cage.clone());
        let domain = Domain::build(&wave(), &handles, &[], &o).unwrap();
        assert_eq!(domain.boundary, Boundary::Cage);
        check_domain(&domain, &handles, &o);
        assert!((domain.area - signed_area(&cage)).abs() < 1e-9 * domain.area);
        assert_eq!(domain.cage_vertices.len(), 6);
        for (k, &v) in domain.cage_vertices.iter().enumerate() {
            assert_eq!(domain.mesh.vertices[v], cage[k]);
        }
        // No vertex outside the cage.
        let index = PolygonIndex::new(&[&cage]);
        for &p in &domain.mesh.vertices {
            assert!(index.contains(p) || on_polygon(&cage, p, 1e-9), "{p:?}");
        }
        // The cage given with its first vertex repeated is the same cage.
        let mut closed = cage.clone();
        closed.push(cage[0]);
        let again = Domain::build(
            &wave(),
            &handles,
            &[],
            &DomainOptions::default().with_cage(closed),
        )
        .unwrap();
        assert_eq!(again.cage_vertices.len(), 6);
    }

    #[test]
    fn domain_acute_cage_corners_only_spoil_angles_next_to_them() {
        // A five-pointed star: tips of 36°, and a sliver notch of about 6°.
        let mut cage = Vec::new();
        for k in 0..10 {
            let r = if k % 2 == 0 { 50.0 } else { 19.1 };
            let a = std::f64::consts::PI * (0.5 + k as f64 / 5.0);
            cage.push(Point::new(50.0 + r * a.cos(), 50.0 + r * a.sin()));
        }
        cage.insert(3, Point::new(50.0, 50.0 + 2.0));
        let handles = [Point::new(50.0, 40.0)];
        let o = DomainOptions::default().with_cage(cage.clone());
        let domain = Domain::build(&wave(), &handles, &[], &o).unwrap();
        check_domain(&domain, &handles, &o);
        assert!((domain.area - signed_area(&cage)).abs() < 1e-9 * domain.area);
    }

    #[test]
    fn domain_closed_curve_with_a_small_overshoot_loop_is_the_boundary() {
        // The closed 100 × 100 square whose last curve, from (0, 100) back to the origin, has
        // the inner control points `c1` and `c2`.
        let square_closed_by = |c1: (f64, f64), c2: (f64, f64)| {
            let mut points = vec![
                (0., 0.),
                (33., 0.),
                (67., 0.),
                (100., 0.),
                (100., 33.),
                (100., 67.),
                (100., 100.),
                (67., 100.),
                (33., 100.),
                (0., 100.),
            ];
            points.extend([c1, c2, (0., 0.)]);
            path(&points, true)
        };
        // A closed square whose closing curve overshoots its start and crosses back: a loop of
        // about 0.2 % of the area (as drawn outlines often have).
        let outline = square_closed_by((-6., 30.), (6., -8.));
        let inner = path(&[(40., 50.), (45., 60.), (55., 60.), (60., 50.)], false);
        let d = drawing(vec![inner.clone(), outline]);
        assert!(self_intersection(&{
            let mut p = Vec::new();
            for j in 0..d.paths[1].n_curves() {
                let c = d.paths[1].curve(j);
                p.extend((0..50).map(|k| c.eval(k as f64 / 50.0)));
            }
            p
        })
        .is_some());
        let handles = [Point::new(50.0, 50.0), Point::new(20.0, 40.0)];
        let o = DomainOptions::default();
        let domain = Domain::build(&d, &handles, &[], &o).unwrap();
        assert_eq!(domain.boundary, Boundary::ClosedCurve { path: 1 });
        assert!(
            (domain.area / 10_000.0 - 1.0).abs() < 0.01,
            "{}",
            domain.area
        );
        // Control: a loop holding about 2 % of the area is the shape, not a blemish.
        let big = square_closed_by((-20., 60.), (80., -40.));
        let d = drawing(vec![inner, big]);
        let padded = Domain::build(&d, &handles, &[], &o).unwrap();
        assert_eq!(padded.boundary, Boundary::Padded);
    }

    #[test]
    fn domain_largest_closed_curve_is_the_boundary() {
        let d = drawing(vec![
            path(&[(40., 50.), (45., 60.), (55., 60.), (60., 50.)], false),
            blob(50.0, 50.0, 50.0),
            blob(50.0, 50.0, 10.0),
        ]);
        let handles = [Point::new(50.0, 50.0), Point::new(20.0, 40.0)];
        let o = DomainOptions::default();
        let domain = Domain::build(&d, &handles, &[], &o).unwrap();
        assert_eq!(domain.boundary, Boundary::ClosedCurve { path: 1 });
        check_domain(&domain, &handles, &o);
        // The flattened blob: area within 0.1 % of the curve's (the circle approximation's
        // area is π r² to 0.03 %), boundary vertices on the curve.
        let circle = std::f64::consts::PI * 2500.0;
        assert!((domain.area / circle - 1.0).abs() < 2e-3, "{}", domain.area);
        assert_eq!(domain.boundary_loops.len(), 1);
        for &v in &domain.boundary_loops[0] {
            let r = (domain.mesh.vertices[v] - Point::new(50.0, 50.0)).hypot();
            assert!((r - 50.0).abs() < 0.05, "{r}");
        }
        // A handle outside the blob: the padded box instead.
        let outside = [Point::new(50.0, 50.0), Point::new(120.0, 50.0)];
        let padded = Domain::build(&d, &outside, &[], &o).unwrap();
        assert_eq!(padded.boundary, Boundary::Padded);
    }

    #[test]
    fn domain_holes_only_when_asked() {
        let square = |x0: f64, y0: f64, w: f64| {
            path(
                &[
                    (x0, y0),
                    (x0 + w / 3., y0),
                    (x0 + 2. * w / 3., y0),
                    (x0 + w, y0),
                    (x0 + w, y0 + w / 3.),
                    (x0 + w, y0 + 2. * w / 3.),
                    (x0 + w, y0 + w),
                    (x0 + 2. * w / 3., y0 + w),
                    (x0 + w / 3., y0 + w),
                    (x0, y0 + w),
                    (x0, y0 + 2. * w / 3.),
                    (x0, y0 + w / 3.),
                    (x0, y0),
                ],
                true,
            )
        };
        // An outer square, an empty inner square (a hole), and an inner square holding a
        // curve (not a hole).
        let d = drawing(vec![
            square(0.0, 0.0, 100.0),
            square(10.0, 10.0, 30.0),
            square(60.0, 60.0, 30.0),
            path(&[(70., 70.), (75., 80.), (80., 80.), (85., 70.)], false),
        ]);
        let handles = [Point::new(50.0, 50.0), Point::new(5.0, 95.0)];
        let with = DomainOptions::default().with_holes(true);
        let domain = Domain::build(&d, &handles, &[], &with).unwrap();
        assert_eq!(domain.boundary, Boundary::ClosedCurve { path: 0 });
        check_domain(&domain, &handles, &with);
        assert_eq!(domain.boundary_loops.len(), 2);
        assert!((domain.area - (10000.0 - 900.0)).abs() < 1e-6);
        // No triangle inside the hole.
        for t in &domain.mesh.triangles {
            let c = t.iter().fold(Point::ZERO, |acc, &v| {
                acc + domain.mesh.vertices[v].to_vec2() / 3.0
            });
            assert!(
                !(c.x > 10.0 && c.x < 40.0 && c.y > 10.0 && c.y < 40.0),
                "{c:?}"
            );
        }
        let without = Domain::build(&d, &handles, &[], &DomainOptions::default()).unwrap();
        assert_eq!(without.boundary_loops.len(), 1);
        assert!((without.area - 10000.0).abs() < 1e-6);
        // A handle inside the would-be hole keeps it filled.
        let inside = [Point::new(25.0, 25.0)];
        let kept = Domain::build(&d, &inside, &[], &with).unwrap();
        assert_eq!(kept.boundary_loops.len(), 1);
    }

    #[test]
    fn domain_bones_are_edge_chains() {
        let bones = [
            [Point::new(10.0, 0.0), Point::new(40.0, 5.0)],
            [Point::new(40.0, 5.0), Point::new(90.0, -5.0)],
        ];
        let handles = [Point::new(50.0, 30.0)];
        let o = DomainOptions::default();
        let domain = Domain::build(&wave(), &handles, &bones, &o).unwrap();
        check_domain(&domain, &handles, &o);
        let mut edges: HashSet<(usize, usize)> = HashSet::new();
        for t in &domain.mesh.triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                edges.insert((a.min(b), a.max(b)));
            }
        }
        for (b, chain) in bones.iter().zip(&domain.bone_vertices) {
            assert!(chain.len() >= 3, "{}", chain.len());
            assert_eq!(domain.mesh.vertices[chain[0]], b[0]);
            assert_eq!(domain.mesh.vertices[*chain.last().unwrap()], b[1]);
            for w in chain.windows(2) {
                assert!(edges.contains(&(w[0].min(w[1]), w[0].max(w[1]))), "{w:?}");
            }
        }
        // The shared joint is one vertex.
        assert_eq!(
            domain.bone_vertices[0].last(),
            domain.bone_vertices[1].first()
        );
    }

    /// The default options with the cage `c`.
    fn cage(c: &[Point]) -> DomainOptions {
        DomainOptions::default().with_cage(c.to_vec())
    }

    /// The error of a build that must fail.
    fn err(r: Result<Domain, DomainError>) -> DomainError {
        r.expect_err("must fail")
    }

    #[test]
    fn domain_bad_input_is_a_clear_error() {
        let d = wave();
        let o = DomainOptions::default();
        let h = [Point::new(10.0, 0.0), Point::new(60.0, 0.0)];
        let square = [(0., -50.), (100., -50.), (100., 50.), (0., 50.)].map(Point::from);

        // A handle outside the cage.
        let e = err(Domain::build(
            &d,
            &[Point::new(150.0, 0.0)],
            &[],
            &cage(&square),
        ));
        assert!(
            matches!(e, DomainError::HandleOutsideDomain { handle: 0, .. }),
            "{e}"
        );
        assert!(e.to_string().contains("outside the domain"));
        // Two coincident handles.
        let e = err(Domain::build(&d, &[h[0], h[1], h[0]], &[], &o));
        assert_eq!(
            e,
            DomainError::CoincidentHandles {
                first: 0,
                second: 2,
                distance: 0.0
            }
        );
        bad_cages_are_clear_errors(&d, &h, square);
        // Empty domains: nothing at all, or a drawing that is a single point.
        let e = err(Domain::build(&Drawing::default(), &h, &[], &o));
        assert!(matches!(e, DomainError::EmptyDomain { .. }), "{e}");
        let dot = drawing(vec![path(&[(5., 5.); 4], false)]);
        let e = err(Domain::build(&dot, &[Point::new(5.0, 5.0)], &[], &o));
        assert!(matches!(e, DomainError::EmptyDomain { .. }), "{e}");
        // Handles and bones.
        assert_eq!(
            err(Domain::build(
                &d,
                &[Point::new(f64::INFINITY, 0.0)],
                &[],
                &o
            )),
            DomainError::NonFiniteHandle { handle: 0 }
        );
        let bone = [Point::new(10.0, 10.0), Point::new(90.0, 10.0)];
        assert_eq!(
            err(Domain::build(&d, &[Point::new(50.0, 10.0)], &[bone], &o)),
            DomainError::HandleOnBone { handle: 0, bone: 0 }
        );
        assert_eq!(
            err(Domain::build(&d, &[], &[[bone[0], bone[0]]], &o)),
            DomainError::DegenerateBone { bone: 0 }
        );
        let crossing = [Point::new(50.0, 0.0), Point::new(50.0, 20.0)];
        assert_eq!(
            err(Domain::build(&d, &[], &[bone, crossing], &o)),
            DomainError::BonesCross {
                first: 0,
                second: 1
            }
        );
        let leaving = [Point::new(50.0, 0.0), Point::new(150.0, 0.0)];
        assert_eq!(
            err(Domain::build(&d, &[], &[leaving], &cage(&square))),
            DomainError::BoneOutsideDomain { bone: 0 }
        );
        // Handles on the cage, exactly or within the coincidence tolerance on either side,
        // become boundary vertices; farther outside is an error.
        for dy in [0.0, -1e-12, 1e-12] {
            let on = [Point::new(50.0, -50.0 + dy), Point::new(100.0 + dy, 10.0)];
            let domain = Domain::build(&d, &on, &[], &cage(&square)).unwrap();
            assert_eq!(domain.mesh.vertices[domain.handle_vertices[0]], on[0]);
            assert_eq!(domain.cage_vertices.len(), 4);
            for (k, &v) in domain.cage_vertices.iter().enumerate() {
                assert_eq!(domain.mesh.vertices[v], square[k]);
            }
            assert!((domain.area - 10000.0).abs() < 1e-6);
        }
        let e = err(Domain::build(
            &d,
            &[Point::new(50.0, -50.001)],
            &[],
            &cage(&square),
        ));
        assert!(matches!(e, DomainError::HandleOutsideDomain { .. }), "{e}");
        // Coordinates too large for the domain's area.
        let huge = drawing(vec![path(
            &[(0., 0.), (1e200, 1e200), (2e200, 0.), (3e200, 1e200)],
            false,
        )]);
        let e = err(Domain::build(&huge, &[], &[], &o));
        assert!(matches!(e, DomainError::Triangulation { .. }), "{e}");
        // Options out of range.
        let e = err(Domain::build(&d, &h, &[], &o.clone().with_min_angle(40.0)));
        assert!(
            matches!(
                e,
                DomainError::InvalidOption {
                    name: "min_angle",
                    ..
                }
            ),
            "{e}"
        );
        let e = err(Domain::build(
            &d,
            &h,
            &[],
            &o.clone().with_max_area_fraction(0.0),
        ));
        assert!(matches!(
            e,
            DomainError::InvalidOption {
                name: "max_area_fraction",
                ..
            }
        ));
    }

    /// The cage checks of [`domain_bad_input_is_a_clear_error`]: a bow tie, a clockwise cage,
    /// too few vertices, a zero-length edge and a non-finite vertex, around the `square`.
    fn bad_cages_are_clear_errors(d: &Drawing, h: &[Point], square: [Point; 4]) {
        // Self-intersecting cage (a bow tie).
        let bowtie = [(0., -50.), (100., 50.), (100., -50.), (0., 50.)].map(Point::from);
        let e = err(Domain::build(d, h, &[], &cage(&bowtie)));
        assert_eq!(
            e,
            DomainError::CageSelfIntersecting {
                first: 0,
                second: 2
            }
        );
        // Clockwise cage.
        let mut cw = square.to_vec();
        cw.reverse();
        let e = err(Domain::build(d, h, &[], &cage(&cw)));
        assert!(matches!(e, DomainError::CageClockwise { signed_area } if signed_area == -10000.0));
        assert!(e.to_string().contains("reverse"));
        // Fewer than three vertices (also after dropping a repeated closing vertex).
        let e = err(Domain::build(d, h, &[], &cage(&square[..2])));
        assert_eq!(e, DomainError::CageTooFewVertices { n_vertices: 2 });
        let e = err(Domain::build(
            d,
            h,
            &[],
            &cage(&[square[0], square[1], square[0]]),
        ));
        assert_eq!(e, DomainError::CageTooFewVertices { n_vertices: 2 });
        // A zero-length cage edge and a non-finite vertex.
        let dup = [square[0], square[1], square[1], square[2], square[3]];
        assert_eq!(
            err(Domain::build(d, h, &[], &cage(&dup))),
            DomainError::CageDegenerateEdge { edge: 1 }
        );
        let nan = [square[0], Point::new(f64::NAN, 0.0), square[2]];
        assert_eq!(
            err(Domain::build(d, h, &[], &cage(&nan))),
            DomainError::CageNonFinite { vertex: 1 }
        );
    }
}
