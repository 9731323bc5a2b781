//! Building a [`Domain`]: validation, boundary choice, vertex placement, constrained Delaunay
//! triangulation and refinement (spade), extraction of the mesh. The rules are stated in the
//! parent module's documentation.

use std::collections::{HashMap, HashSet};

use kurbo::{CubicBez, ParamCurve, ParamCurveArclen, Point, Rect, Shape};
use spade::handles::FixedVertexHandle;
use spade::{
    AngleLimit, ConstrainedDelaunayTriangulation, Point2, RefinementParameters, Triangulation,
};

use super::grid::BucketGrid;
use super::polygon::{
    self, segment_distance, segments_intersect, self_intersection, signed_area, PolygonIndex,
};
use super::{
    art_region, Attachment, Boundary, Domain, DomainError, DomainOptions, DomainShape,
    COINCIDENT_RELATIVE, DEFAULT_SAMPLES_PER_DIAGONAL, MAX_MARGIN, MAX_MIN_ANGLE,
};
use crate::drawing::Drawing;
use crate::mesh::TriMesh;

/// Arc-length accuracy of the per-curve sample counts, relative to the spacing: 1e-2 (the
/// counts are rounded up anyway).
const ARCLEN_ACCURACY: f64 = 1e-2;

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

type Cdt = ConstrainedDelaunayTriangulation<Point2<f64>>;

/// Builds the domain of `drawing` for the handles `points` and `bones` (the steps below, in
/// order): inputs checked, the scale measured, the curves sampled, the boundary chosen
/// ([`Outline`]), the vertices and constraint edges placed, the constrained Delaunay
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

/// Refuses options out of range and handles or curves that are not finite.
fn check_inputs(
    drawing: &Drawing,
    points: &[Point],
    bones: &[[Point; 2]],
    options: &DomainOptions,
) -> Result<(), DomainError> {
    check_options(options)?;
    for (handle, p) in points.iter().enumerate() {
        if !(p.x.is_finite() && p.y.is_finite()) {
            return Err(DomainError::NonFiniteHandle { handle });
        }
    }
    for (bone, b) in bones.iter().enumerate() {
        if !b.iter().all(|p| p.x.is_finite() && p.y.is_finite()) {
            return Err(DomainError::NonFiniteBone { bone });
        }
    }
    for (path, p) in drawing.paths.iter().enumerate() {
        if !p.points.iter().all(|p| p.x.is_finite() && p.y.is_finite()) {
            return Err(DomainError::NonFiniteDrawing { path });
        }
    }
    Ok(())
}

/// The sizes every tolerance of a build is relative to.
#[derive(Clone, Copy)]
struct Scale {
    /// The diagonal of the curves' bounding box (else of everything's).
    drawing_diag: f64,
    /// The bounding box of the curves, handles, bones and cage.
    all_bounds: Rect,
    /// Distance under which two points are one: [`COINCIDENT_RELATIVE`] of the larger
    /// diagonal.
    coincident: f64,
}

/// The [`Scale`] of the curves, handles, bones and cage; an error when there is nothing to
/// mesh or it spans a single point.
fn measure_scale(
    drawing: &Drawing,
    points: &[Point],
    bones: &[[Point; 2]],
    cage: Option<&[Point]>,
) -> Result<Scale, DomainError> {
    let curve_bounds = drawing
        .paths
        .iter()
        .flat_map(|p| (0..p.n_curves()).map(move |j| p.curve(j).bounding_box()))
        .reduce(|a, b| a.union(b));
    let mut all_bounds = curve_bounds;
    let extra = points
        .iter()
        .chain(bones.iter().flatten())
        .chain(cage.into_iter().flatten());
    for &p in extra {
        all_bounds = Some(all_bounds.map_or(Rect::from_points(p, p), |r| r.union_pt(p)));
    }
    if curve_bounds.is_none() && cage.is_none() {
        return Err(DomainError::EmptyDomain {
            reason: "the drawing has no curves and no cage was given",
        });
    }
    let diag = |r: Rect| r.width().hypot(r.height());
    let drawing_diag = curve_bounds
        .map(diag)
        .filter(|d| *d > 0.0)
        .or(all_bounds.map(diag))
        .unwrap_or(0.0);
    let all_bounds = all_bounds.unwrap_or_default();
    if drawing_diag.is_nan() || drawing_diag <= 0.0 {
        return Err(DomainError::EmptyDomain {
            reason: "the drawing, handles and cage span a single point",
        });
    }
    Ok(Scale {
        drawing_diag,
        all_bounds,
        coincident: COINCIDENT_RELATIVE * drawing_diag.max(diag(all_bounds)),
    })
}

/// Samples along each path `spacing` apart (closed paths without the repeated first point).
fn sample_curves(drawing: &Drawing, spacing: f64, options: &DomainOptions) -> Vec<Vec<Point>> {
    drawing
        .paths
        .iter()
        .map(|path| {
            let mut out = Vec::new();
            for j in 0..path.n_curves() {
                let c = path.curve(j);
                let n = curve_intervals(&c, spacing, options);
                out.extend((0..n).map(|k| c.eval(k as f64 / n as f64)));
            }
            if !path.closed {
                out.push(*path.points.last().unwrap_or(&Point::ZERO));
            }
            dedup_consecutive(&mut out, path.closed);
            out
        })
        .collect()
}

/// What is triangulated: the vertices and constraint edges, and where the inputs went.
struct Placed {
    verts: VertexSet,
    constraints: Vec<[usize; 2]>,
    /// Each point handle's vertex.
    handle_vertices: Vec<usize>,
    /// Each boundary loop's vertices.
    loop_vertices: Vec<Vec<usize>>,
    /// Each bone's chain of vertices, from its first end.
    bone_chains: Vec<Vec<usize>>,
    /// Curve samples that became vertices (those of boundary paths counted whole).
    n_curve_samples: usize,
}

/// Places the vertices: the point handles, the boundary loops (with their edges as
/// constraints), the bones' chains, and the curve samples inside the domain that are neither
/// near a boundary or bone segment nor merged with another vertex (within half the spacing).
fn place_vertices(
    loops: &[&[Point]],
    outline: &Outline,
    samples: &[Vec<Point>],
    points: &[Point],
    bones: &[[Point; 2]],
    spacing: f64,
    scale: Scale,
) -> Placed {
    let domain_index = PolygonIndex::new(loops);
    let merge = 0.5 * spacing;
    let mut verts = VertexSet::new(merge, scale.coincident);
    let handle_vertices: Vec<usize> = points.iter().map(|&p| verts.add_fixed(p)).collect();
    let mut constraints: Vec<[usize; 2]> = Vec::new();
    let mut add_loop = |verts: &mut VertexSet, poly: &[Point]| -> Vec<usize> {
        let idx: Vec<usize> = poly.iter().map(|&p| verts.add_fixed(p)).collect();
        for k in 0..idx.len() {
            let (a, b) = (idx[k], idx[(k + 1) % idx.len()]);
            if a != b {
                constraints.push([a, b]);
            }
        }
        idx
    };
    let loop_vertices: Vec<Vec<usize>> = loops.iter().map(|l| add_loop(&mut verts, l)).collect();
    let bone_chains: Vec<Vec<usize>> = bones
        .iter()
        .map(|b| {
            let n = (((b[1] - b[0]).hypot() / spacing).ceil() as usize).max(1);
            (0..=n)
                .map(|k| verts.add_fixed(b[0].lerp(b[1], k as f64 / n as f64)))
                .collect()
        })
        .collect();
    let near_segment = near_segment_test(&domain_index, bones, merge);
    let mut n_curve_samples = 0;
    for (path, s) in samples.iter().enumerate() {
        if Some(path) == outline.boundary_path || outline.hole_paths.contains(&path) {
            n_curve_samples += s.len();
            continue;
        }
        for &p in s {
            if domain_index.contains(p) && !near_segment(p) && verts.add_sample(p) {
                n_curve_samples += 1;
            }
        }
    }
    Placed {
        verts,
        constraints,
        handle_vertices,
        loop_vertices,
        bone_chains,
        n_curve_samples,
    }
}

/// Whether a point lies within `merge` of a segment of the boundary, its holes or a bone
/// (curve samples there are skipped: they would make slivers against the constraint edges).
fn near_segment_test(
    domain_index: &PolygonIndex,
    bones: &[[Point; 2]],
    merge: f64,
) -> impl Fn(Point) -> bool {
    let mut segments: Vec<(Point, Point)> = domain_index.edges().to_vec();
    segments.extend(bones.iter().map(|b| (b[0], b[1])));
    let seg_bounds = segments
        .iter()
        .fold(domain_index.bounds(), |r, s| r.union_pt(s.0).union_pt(s.1));
    let seg_diag = seg_bounds.width().hypot(seg_bounds.height());
    let seg_cell = (4.0 * merge).max(seg_diag / 2048.0);
    let seg_grid = BucketGrid::build(seg_bounds, seg_cell, segments.len(), |k, emit| {
        BucketGrid::segment_pieces(seg_cell, segments[k].0, segments[k].1, emit)
    });
    move |p: Point| {
        let mut near = false;
        seg_grid.for_cells_in(Rect::from_center_size(p, (2.0 * merge, 2.0 * merge)), |b| {
            near = near
                || b.iter().any(|&k| {
                    let (a, c) = segments[k as usize];
                    segment_distance(p, a, c).0 < merge
                });
        });
        near
    }
}

/// The constrained Delaunay triangulation of `placed`, refined to the options' angle, area and
/// vertex cap (spade), with the bones added as constraint edges after refinement (spade's
/// classification of outer faces needs closed constraint loops, and a bone is an open chain).
/// Returns it, its faces outside the domain, and whether refinement met its goals.
fn triangulate_and_refine(
    placed: &Placed,
    options: &DomainOptions,
    area: f64,
) -> Result<(Cdt, HashSet<usize>, bool), DomainError> {
    let n_initial = placed.verts.points.len();
    let mut conflicts = Vec::new();
    let mut cdt = Cdt::try_bulk_load_cdt(
        placed
            .verts
            .points
            .iter()
            .map(|p| Point2::new(p.x, p.y))
            .collect(),
        placed.constraints.clone(),
        |e| conflicts.push(e),
    )
    .map_err(|e| DomainError::Triangulation {
        reason: e.to_string(),
    })?;
    if !conflicts.is_empty() {
        return Err(DomainError::Bug(
            "constraint edges of a validated boundary intersect",
        ));
    }
    if cdt.num_vertices() != n_initial {
        return Err(DomainError::Bug(
            "duplicate vertices reached the triangulator",
        ));
    }
    let params = RefinementParameters::<f64>::new()
        .exclude_outer_faces(true)
        .with_angle_limit(AngleLimit::from_deg(options.min_angle))
        .with_max_allowed_area(options.max_area_fraction * area)
        .with_max_additional_vertices(options.max_vertices.saturating_sub(n_initial));
    let result = cdt.refine(params);
    if !result.refinement_complete {
        tracing::warn!(
            max_vertices = options.max_vertices,
            "domain refinement stopped at the vertex cap before meeting its angle and area goals"
        );
    }
    let excluded: HashSet<usize> = result.excluded_faces.iter().map(|f| f.index()).collect();
    for chain in &placed.bone_chains {
        for w in chain.windows(2) {
            if w[0] == w[1] {
                continue;
            }
            let (a, b) = (
                FixedVertexHandle::from_index(w[0]),
                FixedVertexHandle::from_index(w[1]),
            );
            if !cdt.can_add_constraint(a, b) && !cdt.exists_constraint(a, b) {
                return Err(DomainError::Bug("a bone crosses a constraint edge"));
            }
            cdt.add_constraint(a, b);
        }
    }
    Ok((cdt, excluded, result.refinement_complete))
}

/// The kept triangles of `cdt` (not `excluded`) as a mesh of the vertices they use, and the map
/// from the triangulation's vertex indices to the mesh's (`usize::MAX`: not used).
fn extract_mesh(
    cdt: &Cdt,
    excluded: &HashSet<usize>,
) -> Result<(TriMesh, Vec<usize>), DomainError> {
    let mut remap = vec![usize::MAX; cdt.num_vertices()];
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for face in cdt.inner_faces() {
        if excluded.contains(&face.fix().index()) {
            continue;
        }
        let tri = face.vertices().map(|v| {
            let i = v.fix().index();
            if remap[i] == usize::MAX {
                remap[i] = vertices.len();
                let p = v.position();
                vertices.push(Point::new(p.x, p.y));
            }
            remap[i]
        });
        triangles.push(tri);
    }
    Ok((TriMesh::new(vertices, triangles)?, remap))
}

/// A domain's boundary before triangulation ([`build`]).
struct Outline {
    /// Closed polygons: outer ones counter-clockwise, holes clockwise.
    loops: Vec<Vec<Point>>,
    boundary: Boundary,
    /// With a cage, the position in `loops[0]` of each cage corner.
    corners: Vec<usize>,
    /// Area inside (outer polygons minus holes).
    area: f64,
    /// The drawing's path that is the outer boundary (its samples are on it).
    boundary_path: Option<usize>,
    /// The drawing's paths that are holes.
    hole_paths: HashSet<usize>,
    /// The outlines of the art's parts left out (art-shaped domains).
    unpinned: Vec<Vec<Vec<Point>>>,
}

/// Largest number of point pairs compared to find a part's nearest boundary vertex: 4 Mi (both
/// sides are thinned evenly beyond it).
const MAX_ATTACH_PAIRS: usize = 1 << 22;

/// Each part left out, attached to the boundary vertex of `mesh` nearest to its outline.
fn attach(
    mesh: &TriMesh,
    boundary_loops: &[Vec<usize>],
    unpinned: Vec<Vec<Vec<Point>>>,
) -> Vec<Attachment> {
    let boundary: Vec<usize> = boundary_loops.iter().flatten().copied().collect();
    unpinned
        .into_iter()
        .filter_map(|loops| {
            let outline: Vec<Point> = loops.iter().flatten().copied().collect();
            let pairs = outline.len().saturating_mul(boundary.len()).max(1);
            let thin = ((pairs as f64 / MAX_ATTACH_PAIRS as f64).sqrt().ceil() as usize).max(1);
            let vertex = boundary
                .iter()
                .step_by(thin)
                .map(|&v| {
                    let p = mesh.vertices[v];
                    let d = outline
                        .iter()
                        .step_by(thin)
                        .map(|q| (*q - p).hypot2())
                        .fold(f64::INFINITY, f64::min);
                    (d, v)
                })
                .min_by(|a, b| a.0.total_cmp(&b.0))?
                .1;
            Some(Attachment { loops, vertex })
        })
        .collect()
}

/// A boundary given by the caller: polygons and what they are ([`super::Domain::build_within`]).
#[derive(Clone, Copy)]
pub(super) struct Given<'a> {
    pub loops: &'a [Vec<Point>],
    pub boundary: Boundary,
}

/// The given boundary, checked like the art-shaped one.
fn given_outline(
    given: Given<'_>,
    points: &[Point],
    bones: &[[Point; 2]],
    coincident: f64,
) -> Result<Outline, DomainError> {
    let loops = given.loops.to_vec();
    let area = checked_area(&loops, points, bones, coincident)?;
    Ok(Outline {
        loops,
        boundary: given.boundary,
        corners: Vec::new(),
        area,
        boundary_path: None,
        hole_paths: HashSet::new(),
        unpinned: Vec::new(),
    })
}

/// The area inside `loops` (outer polygons counter-clockwise, holes clockwise), after checking
/// that it is positive and finite and holds every handle and bone.
fn checked_area(
    loops: &[Vec<Point>],
    points: &[Point],
    bones: &[[Point; 2]],
    coincident: f64,
) -> Result<f64, DomainError> {
    let area: f64 = loops.iter().map(|l| signed_area(l)).sum();
    if !area.is_finite() {
        return Err(DomainError::Triangulation {
            reason: "the domain's area overflows f64 (coordinates too large)".into(),
        });
    }
    if loops.is_empty() || area <= 0.0 {
        return Err(DomainError::EmptyDomain {
            reason: "the art paints no area that holds a handle",
        });
    }
    let polygons: Vec<&[Point]> = loops.iter().map(Vec::as_slice).collect();
    check_inside(&polygons, points, bones, coincident)?;
    Ok(area)
}

/// Checks that every handle and both ends of every bone lie inside the closed `polygons` (or
/// within `tolerance` of their boundary), and that no bone crosses a boundary other than at an
/// end lying on it.
fn check_inside(
    polygons: &[&[Point]],
    points: &[Point],
    bones: &[[Point; 2]],
    tolerance: f64,
) -> Result<(), DomainError> {
    let index = PolygonIndex::new(polygons);
    let inside =
        |p: Point| index.contains(p) || polygons.iter().any(|poly| on_polygon(poly, p, tolerance));
    if let Some((handle, p)) = points.iter().enumerate().find(|(_, &p)| !inside(p)) {
        return Err(DomainError::HandleOutsideDomain {
            handle,
            x: p.x,
            y: p.y,
        });
    }
    for (bone, b) in bones.iter().enumerate() {
        let crosses = polygons
            .iter()
            .any(|poly| crosses_polygon(poly, b[0], b[1], tolerance));
        if crosses || !b.iter().all(|&p| inside(p)) {
            return Err(DomainError::BoneOutsideDomain { bone });
        }
    }
    Ok(())
}

/// The art-shaped boundary ([`DomainShape::Art`], [`super::art_region`]).
fn art_outline(
    drawing: &Drawing,
    points: &[Point],
    bones: &[[Point; 2]],
    options: &DomainOptions,
    (spacing, coincident, drawing_diag): (f64, f64, f64),
) -> Result<Outline, DomainError> {
    // Traced at the default sample spacing at most, whatever the level's spacing (a coarse
    // preview keeps the parts of the exact domain), simplified to a quarter of the spacing.
    let cell = spacing.min(drawing_diag / DEFAULT_SAMPLES_PER_DIAGONAL);
    let region = art_region::trace(
        drawing,
        points,
        bones,
        options.margin * drawing_diag,
        (cell, 0.25 * spacing),
    );
    let area = checked_area(&region.loops, points, bones, coincident)?;
    Ok(Outline {
        loops: region.loops,
        boundary: Boundary::Art {
            parts: region.n_parts,
            unpinned: region.n_unpinned,
        },
        corners: Vec::new(),
        area,
        boundary_path: None,
        hole_paths: HashSet::new(),
        unpinned: region.unpinned,
    })
}

/// The cage, or the largest closed curve containing everything, or the padded box; with its
/// holes when asked (rules 1–3 of the module documentation). `scale` is the sample spacing,
/// the coincidence distance, the drawing's diagonal and the bounds of everything.
fn enclosing_outline(
    drawing: &Drawing,
    samples: &[Vec<Point>],
    points: &[Point],
    bones: &[[Point; 2]],
    options: &DomainOptions,
    cage: Option<&[Point]>,
    scale: (f64, f64, f64, Rect),
) -> Result<Outline, DomainError> {
    let (spacing, coincident, drawing_diag, all_bounds) = scale;
    let (outer, boundary) = match cage {
        Some(c) => {
            polygon::check_cage(c, coincident)?;
            (c.to_vec(), Boundary::Cage)
        }
        None => match closed_curve_boundary(drawing, samples, points, bones, spacing) {
            Some((path, poly)) => (poly, Boundary::ClosedCurve { path }),
            None => {
                let r = all_bounds.inflate(
                    options.padding * drawing_diag,
                    options.padding * drawing_diag,
                );
                let poly = vec![
                    Point::new(r.x0, r.y0),
                    Point::new(r.x1, r.y0),
                    Point::new(r.x1, r.y1),
                    Point::new(r.x0, r.y1),
                ];
                (poly, Boundary::Padded)
            }
        },
    };
    // Handles and bone ends on the boundary (within `coincident`) become boundary vertices, so
    // that rounding cannot leave them just outside. `corners[k]` is the position in `outer` of
    // its k-th original vertex.
    let (outer, corners) = insert_on_boundary(
        outer,
        points.iter().chain(bones.iter().flatten()).copied(),
        coincident,
    );
    let outer_area = signed_area(&outer);
    if !outer_area.is_finite() {
        return Err(DomainError::Triangulation {
            reason: "the domain's area overflows f64 (coordinates too large)".into(),
        });
    }
    if outer_area.is_nan() || outer_area <= 0.0 {
        return Err(DomainError::EmptyDomain {
            reason: "the domain's boundary has zero area",
        });
    }
    check_inside(&[&outer], points, bones, coincident)?;
    let outer_index = PolygonIndex::new(&[&outer]);

    // Holes.
    let boundary_path = match boundary {
        Boundary::ClosedCurve { path } => Some(path),
        _ => None,
    };
    let holes: Vec<(usize, Vec<Point>)> = if options.holes {
        find_holes(drawing, samples, boundary_path, &outer_index, points, bones)
    } else {
        Vec::new()
    };
    let hole_area: f64 = holes.iter().map(|(_, h)| -signed_area(h)).sum();
    let area = outer_area - hole_area;
    let hole_paths = holes.iter().map(|(p, _)| *p).collect();
    let mut loops = vec![outer];
    loops.extend(holes.into_iter().map(|(_, h)| h));
    Ok(Outline {
        loops,
        boundary,
        corners,
        area,
        boundary_path,
        hole_paths,
        unpinned: Vec::new(),
    })
}

fn check_options(o: &DomainOptions) -> Result<(), DomainError> {
    let bad = |name, value: f64, expected| {
        Err(DomainError::InvalidOption {
            name,
            value,
            expected,
        })
    };
    if !(0.0..=MAX_MIN_ANGLE).contains(&o.min_angle) {
        return bad("min_angle", o.min_angle, "0 to 34 degrees");
    }
    if !(o.max_area_fraction > 0.0 && o.max_area_fraction <= 1.0) {
        return bad("max_area_fraction", o.max_area_fraction, "(0, 1]");
    }
    if !(o.samples_per_diagonal > 0.0 && o.samples_per_diagonal.is_finite()) {
        return bad(
            "samples_per_diagonal",
            o.samples_per_diagonal,
            "positive and finite",
        );
    }
    if o.max_samples_per_curve == 0 {
        return bad("max_samples_per_curve", 0.0, "at least 1");
    }
    if !(0.0..=MAX_MARGIN).contains(&o.margin) {
        return bad("margin", o.margin, "0 to 1 (a fraction of the diagonal)");
    }
    if !(o.padding > 0.0 && o.padding.is_finite()) {
        return bad("padding", o.padding, "positive and finite");
    }
    if o.max_vertices < 3 {
        return bad("max_vertices", o.max_vertices as f64, "at least 3");
    }
    Ok(())
}

/// The cage without a repeated closing vertex.
fn closed_cage(c: &[Point]) -> Vec<Point> {
    let mut c = c.to_vec();
    if c.len() > 1 && c.first() == c.last() {
        c.pop();
    }
    c
}

fn check_handles(points: &[Point], bones: &[[Point; 2]], tol: f64) -> Result<(), DomainError> {
    for first in 0..points.len() {
        for second in first + 1..points.len() {
            let distance = (points[first] - points[second]).hypot();
            if distance <= tol {
                return Err(DomainError::CoincidentHandles {
                    first,
                    second,
                    distance,
                });
            }
        }
    }
    for (bone, b) in bones.iter().enumerate() {
        if (b[1] - b[0]).hypot() <= tol {
            return Err(DomainError::DegenerateBone { bone });
        }
        for (handle, &p) in points.iter().enumerate() {
            if segment_distance(p, b[0], b[1]).0 <= tol {
                return Err(DomainError::HandleOnBone { handle, bone });
            }
        }
    }
    for first in 0..bones.len() {
        for second in first + 1..bones.len() {
            let (a, b) = (bones[first], bones[second]);
            let shared = a
                .iter()
                .flat_map(|p| b.iter().map(move |q| (*p - *q).hypot() <= tol))
                .filter(|s| *s)
                .count();
            let crosses = if shared == 0 {
                segments_intersect(a[0], a[1], b[0], b[1])
            } else {
                // Sharing an end: a problem only if one bone's free end lies on the other
                // (overlap), or both ends are shared (the same bone twice).
                shared > 1
                    || a.iter().any(|&p| {
                        b.iter().all(|q| (p - *q).hypot() > tol)
                            && segment_distance(p, b[0], b[1]).0 <= tol
                    })
                    || b.iter().any(|&p| {
                        a.iter().all(|q| (p - *q).hypot() > tol)
                            && segment_distance(p, a[0], a[1]).0 <= tol
                    })
            };
            if crosses {
                return Err(DomainError::BonesCross { first, second });
            }
        }
    }
    Ok(())
}

/// The polygon `poly` with every point of `extra` that lies within `tol` of one of its edges
/// (and not within `tol` of a vertex) inserted into that edge, in order along it; and the new
/// positions of the original vertices.
fn insert_on_boundary(
    poly: Vec<Point>,
    extra: impl Iterator<Item = Point>,
    tol: f64,
) -> (Vec<Point>, Vec<usize>) {
    let n = poly.len();
    let mut inserts: Vec<(usize, f64, Point)> = Vec::new();
    for p in extra {
        if poly.iter().any(|v| (*v - p).hypot() <= tol) {
            continue;
        }
        let nearest = (0..n)
            .map(|k| (k, segment_distance(p, poly[k], poly[(k + 1) % n])))
            .min_by(|a, b| a.1 .0.total_cmp(&b.1 .0));
        if let Some((k, (d, s))) = nearest {
            if d <= tol {
                inserts.push((k, s, p));
            }
        }
    }
    if inserts.is_empty() {
        return (poly, (0..n).collect());
    }
    inserts.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut out = Vec::with_capacity(n + inserts.len());
    let mut corners = Vec::with_capacity(n);
    let mut next = inserts.iter().peekable();
    for (k, &v) in poly.iter().enumerate() {
        corners.push(out.len());
        out.push(v);
        while let Some(&(_, _, p)) = next.next_if(|i| i.0 == k) {
            if out.last() != Some(&p) {
                out.push(p);
            }
        }
    }
    (out, corners)
}

/// Whether `p` is within `tol` of the polygon's boundary.
fn on_polygon(poly: &[Point], p: Point, tol: f64) -> bool {
    (0..poly.len()).any(|k| segment_distance(p, poly[k], poly[(k + 1) % poly.len()]).0 <= tol)
}

/// Whether the segment `a b` crosses the polygon's boundary other than at its own end points
/// lying on it.
fn crosses_polygon(poly: &[Point], a: Point, b: Point, tol: f64) -> bool {
    let n = poly.len();
    (0..n).any(|k| {
        let (c, d) = (poly[k], poly[(k + 1) % n]);
        segments_intersect(a, b, c, d)
            && segment_distance(a, c, d).0 > tol
            && segment_distance(b, c, d).0 > tol
    })
}

/// The sample spacing `s` (module documentation): `D / samples_per_diagonal`, enlarged until
/// the total count is within `max_curve_samples` (or every curve has a single interval).
fn sample_spacing(drawing: &Drawing, diag: f64, o: &DomainOptions) -> f64 {
    let lengths: Vec<f64> = drawing
        .paths
        .iter()
        .flat_map(|p| (0..p.n_curves()).map(move |j| p.curve(j)))
        .map(|c| c.arclen(ARCLEN_ACCURACY * diag / o.samples_per_diagonal))
        .collect();
    let mut s = diag / o.samples_per_diagonal;
    for _ in 0..64 {
        let total: usize = lengths
            .iter()
            .map(|&l| intervals_for(l, s, o.max_samples_per_curve))
            .sum();
        if total <= o.max_curve_samples || total <= lengths.len() {
            break;
        }
        s *= (total as f64 / o.max_curve_samples as f64).max(1.01);
    }
    s
}

fn intervals_for(len: f64, s: f64, cap: usize) -> usize {
    let n = (len / s).ceil();
    if n.is_finite() && n >= 1.0 {
        (n as usize).min(cap)
    } else {
        1
    }
}

fn curve_intervals(c: &CubicBez, s: f64, o: &DomainOptions) -> usize {
    intervals_for(c.arclen(ARCLEN_ACCURACY * s), s, o.max_samples_per_curve)
}

/// Removes consecutive exact duplicates (and, if closed, a last point equal to the first).
fn dedup_consecutive(v: &mut Vec<Point>, closed: bool) {
    v.dedup();
    if closed && v.len() > 1 && v.first() == v.last() {
        v.pop();
    }
}

/// Most self-crossing loops cut off a closed path's flattening before it can be a boundary
/// ([`polygon::without_small_loops`]).
const MAX_LOOP_CUTS: usize = 16;
/// Largest area those loops may hold, as a fraction of the path's: 1 %.
const MAX_LOOP_AREA_FRACTION: f64 = 0.01;

/// The largest closed path's flattening, counter-clockwise, with small self-crossing loops cut
/// off, if it then contains all other geometry (see the module documentation).
fn closed_curve_boundary(
    drawing: &Drawing,
    samples: &[Vec<Point>],
    points: &[Point],
    bones: &[[Point; 2]],
    spacing: f64,
) -> Option<(usize, Vec<Point>)> {
    let (path, area) = drawing
        .paths
        .iter()
        .enumerate()
        .filter(|(k, p)| p.closed && samples[*k].len() >= 3)
        .map(|(k, _)| (k, signed_area(&samples[k])))
        .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))?;
    if area == 0.0 {
        return None;
    }
    let mut poly = samples[path].clone();
    if area < 0.0 {
        poly.reverse();
    }
    if self_intersection(&poly).is_some() {
        poly = polygon::without_small_loops(&poly, MAX_LOOP_CUTS, MAX_LOOP_AREA_FRACTION)?;
    }
    let index = PolygonIndex::new(&[&poly]);
    let handles_inside = points
        .iter()
        .chain(bones.iter().flatten())
        .all(|&p| index.contains(p));
    if !handles_inside {
        return None;
    }
    let curves_inside = samples
        .iter()
        .enumerate()
        .filter(|(k, _)| *k != path)
        .flat_map(|(_, s)| s.iter())
        .all(|&p| index.contains(p) || on_polygon(&poly, p, spacing));
    curves_inside.then_some((path, poly))
}

/// Closed paths that become holes (module documentation), clockwise.
fn find_holes(
    drawing: &Drawing,
    samples: &[Vec<Point>],
    boundary_path: Option<usize>,
    outer: &PolygonIndex,
    points: &[Point],
    bones: &[[Point; 2]],
) -> Vec<(usize, Vec<Point>)> {
    let mut holes = Vec::new();
    for (k, path) in drawing.paths.iter().enumerate() {
        if !path.closed || Some(k) == boundary_path || samples[k].len() < 3 {
            continue;
        }
        let mut poly = samples[k].clone();
        let area = signed_area(&poly);
        if area == 0.0 || self_intersection(&poly).is_some() {
            continue;
        }
        if area > 0.0 {
            poly.reverse();
        }
        if !poly.iter().all(|&p| outer.contains(p)) {
            continue;
        }
        let index = PolygonIndex::new(&[&poly]);
        let bounds = index.bounds();
        let inside = |p: Point| bounds.contains(p) && index.contains(p);
        let encloses_handle = points
            .iter()
            .chain(bones.iter().flatten())
            .any(|&p| inside(p));
        let encloses_curve = samples
            .iter()
            .enumerate()
            .filter(|(l, _)| *l != k)
            .any(|(_, s)| s.iter().any(|&p| inside(p)));
        if !encloses_handle && !encloses_curve {
            holes.push((k, poly));
        }
    }
    holes
}

/// The points of the triangulation, with merging of near-duplicates through a hash of cells
/// of side `merge`.
struct VertexSet {
    points: Vec<Point>,
    cells: HashMap<(i64, i64), Vec<usize>>,
    merge: f64,
    coincident: f64,
}

impl VertexSet {
    fn new(merge: f64, coincident: f64) -> VertexSet {
        VertexSet {
            points: Vec::new(),
            cells: HashMap::new(),
            merge,
            coincident,
        }
    }

    fn key(&self, p: Point) -> (i64, i64) {
        (
            (p.x / self.merge).floor() as i64,
            (p.y / self.merge).floor() as i64,
        )
    }

    /// The nearest existing point within `radius` (≤ `merge`).
    fn nearest(&self, p: Point, radius: f64) -> Option<usize> {
        let (kx, ky) = self.key(p);
        let mut best = None;
        let mut best_d = radius;
        for dy in -1..=1 {
            for dx in -1..=1 {
                if let Some(v) = self.cells.get(&(kx + dx, ky + dy)) {
                    for &i in v {
                        let d = (self.points[i] - p).hypot();
                        if d <= best_d {
                            best_d = d;
                            best = Some(i);
                        }
                    }
                }
            }
        }
        best
    }

    fn push(&mut self, p: Point) -> usize {
        let i = self.points.len();
        self.points.push(p);
        let key = self.key(p);
        self.cells.entry(key).or_default().push(i);
        i
    }

    /// A point that must be a vertex: merged only with a coincident one.
    fn add_fixed(&mut self, p: Point) -> usize {
        match self.nearest(p, self.coincident) {
            Some(i) => i,
            None => self.push(p),
        }
    }

    /// A curve sample: skipped (false) when within `merge` of an existing vertex.
    fn add_sample(&mut self, p: Point) -> bool {
        if self.nearest(p, self.merge).is_some() {
            return false;
        }
        self.push(p);
        true
    }
}

/// The mesh vertices within `tol` of the segment `a b`, ordered from `a` to `b`.
fn vertices_on_segment(mesh: &TriMesh, a: Point, b: Point, tol: f64) -> Vec<usize> {
    let mut on: Vec<(f64, usize)> = mesh
        .vertices
        .iter()
        .enumerate()
        .filter_map(|(i, &p)| {
            let (d, s) = segment_distance(p, a, b);
            (d <= tol).then_some((s, i))
        })
        .collect();
    on.sort_by(|x, y| x.0.total_cmp(&y.0));
    on.into_iter().map(|(_, i)| i).collect()
}

/// The boundary of the mesh as closed loops of vertices (each boundary edge oriented with the
/// mesh on its left), the loop of largest signed area first.
fn boundary_loops(mesh: &TriMesh) -> Result<Vec<Vec<usize>>, DomainError> {
    let mut directed: HashSet<(usize, usize)> = HashSet::new();
    for t in &mesh.triangles {
        for k in 0..3 {
            directed.insert((t[k], t[(k + 1) % 3]));
        }
    }
    let mut next: HashMap<usize, usize> = HashMap::new();
    for &(a, b) in &directed {
        if !directed.contains(&(b, a)) && next.insert(a, b).is_some() {
            return Err(DomainError::Bug(
                "a boundary vertex starts two boundary edges (the domain pinches)",
            ));
        }
    }
    let mut starts: Vec<usize> = next.keys().copied().collect();
    starts.sort_unstable();
    let mut seen: HashSet<usize> = HashSet::new();
    let mut loops = Vec::new();
    for s in starts {
        if seen.contains(&s) {
            continue;
        }
        let mut l = vec![s];
        seen.insert(s);
        let mut v = next[&s];
        while v != s {
            if !seen.insert(v) {
                return Err(DomainError::Bug("boundary edges do not form loops"));
            }
            l.push(v);
            v = *next
                .get(&v)
                .ok_or(DomainError::Bug("boundary edges do not form loops"))?;
        }
        loops.push(l);
    }
    let area = |l: &Vec<usize>| {
        let p: Vec<Point> = l.iter().map(|&i| mesh.vertices[i]).collect();
        signed_area(&p)
    };
    loops.sort_by(|a, b| area(b).total_cmp(&area(a)));
    Ok(loops)
}

#[cfg(test)]
mod tests {
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

    #[test]
    fn domain_bad_input_is_a_clear_error() {
        let d = wave();
        let o = DomainOptions::default();
        let h = [Point::new(10.0, 0.0), Point::new(60.0, 0.0)];
        let square = [(0., -50.), (100., -50.), (100., 50.), (0., 50.)].map(Point::from);
        let cage = |c: &[Point]| DomainOptions::default().with_cage(c.to_vec());
        let err = |r: Result<Domain, DomainError>| r.expect_err("must fail");

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
        // Self-intersecting cage (a bow tie).
        let bowtie = [(0., -50.), (100., 50.), (100., -50.), (0., 50.)].map(Point::from);
        let e = err(Domain::build(&d, &h, &[], &cage(&bowtie)));
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
        let e = err(Domain::build(&d, &h, &[], &cage(&cw)));
        assert!(matches!(e, DomainError::CageClockwise { signed_area } if signed_area == -10000.0));
        assert!(e.to_string().contains("reverse"));
        // Fewer than three vertices (also after dropping a repeated closing vertex).
        let e = err(Domain::build(&d, &h, &[], &cage(&square[..2])));
        assert_eq!(e, DomainError::CageTooFewVertices { n_vertices: 2 });
        let e = err(Domain::build(
            &d,
            &h,
            &[],
            &cage(&[square[0], square[1], square[0]]),
        ));
        assert_eq!(e, DomainError::CageTooFewVertices { n_vertices: 2 });
        // A zero-length cage edge and a non-finite vertex.
        let dup = [square[0], square[1], square[1], square[2], square[3]];
        assert_eq!(
            err(Domain::build(&d, &h, &[], &cage(&dup))),
            DomainError::CageDegenerateEdge { edge: 1 }
        );
        let nan = [square[0], Point::new(f64::NAN, 0.0), square[2]];
        assert_eq!(
            err(Domain::build(&d, &h, &[], &cage(&nan))),
            DomainError::CageNonFinite { vertex: 1 }
        );
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
}
