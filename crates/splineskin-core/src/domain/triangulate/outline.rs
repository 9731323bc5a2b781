//! The domain's boundary before triangulation: a given boundary, the art's shape, or the
//! cage, the largest closed curve or the padded box, with the holes when asked.

use std::collections::HashSet;

use kurbo::{Point, Rect};

use super::super::polygon::{self, segment_distance, self_intersection, signed_area, PolygonIndex};
use super::super::{
    art_region, Boundary, DomainError, DomainOptions, DEFAULT_SAMPLES_PER_DIAGONAL,
};
use super::validate::{check_inside, on_polygon};
use crate::drawing::Drawing;

/// A domain's boundary before triangulation ([`super::build`]).
pub(super) struct Outline {
    /// Closed polygons: outer ones counter-clockwise, holes clockwise.
    pub(super) loops: Vec<Vec<Point>>,
    pub(super) boundary: Boundary,
    /// With a cage, the position in `loops[0]` of each cage corner.
    pub(super) corners: Vec<usize>,
    /// Area inside (outer polygons minus holes).
    pub(super) area: f64,
    /// The drawing's path that is the outer boundary (its samples are on it).
    pub(super) boundary_path: Option<usize>,
    /// The drawing's paths that are holes.
    pub(super) hole_paths: HashSet<usize>,
    /// The outlines of the art's parts left out (art-shaped domains).
    pub(super) unpinned: Vec<Vec<Vec<Point>>>,
}

/// A boundary given by the caller: polygons and what they are ([`super::Domain::build_within`]).
#[derive(Clone, Copy)]
pub(in crate::domain) struct Given<'a> {
    pub loops: &'a [Vec<Point>],
    pub boundary: Boundary,
}

/// The given boundary, checked like the art-shaped one.
pub(super) fn given_outline(
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
pub(super) fn checked_area(
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

/// The art-shaped boundary ([`crate::domain::DomainShape::Art`], [`crate::domain::art_region`]).
pub(super) fn art_outline(
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
pub(super) fn enclosing_outline(
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

/// The cage without a repeated closing vertex.
pub(super) fn closed_cage(c: &[Point]) -> Vec<Point> {
    let mut c = c.to_vec();
    if c.len() > 1 && c.first() == c.last() {
        c.pop();
    }
    c
}

/// The polygon `poly` with every point of `extra` that lies within `tol` of one of its edges
/// (and not within `tol` of a vertex) inserted into that edge, in order along it; and the new
/// positions of the original vertices.
pub(super) fn insert_on_boundary(
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

/// Most self-crossing loops cut off a closed path's flattening before it can be a boundary
/// ([`polygon::without_small_loops`]).
pub(super) const MAX_LOOP_CUTS: usize = 16;
/// Largest area those loops may hold, as a fraction of the path's: 1 %.
pub(super) const MAX_LOOP_AREA_FRACTION: f64 = 0.01;

/// The largest closed path's flattening, counter-clockwise, with small self-crossing loops cut
/// off, if it then contains all other geometry (see the module documentation).
pub(super) fn closed_curve_boundary(
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
pub(super) fn find_holes(
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
