//! Input checks of a domain build: options in range, finite handles, bones and curves,
//! handles and bones apart from each other and inside the boundary.

use kurbo::Point;

use super::super::polygon::{segment_distance, segments_intersect, PolygonIndex};
use super::super::{DomainError, DomainOptions, MAX_MARGIN, MAX_MIN_ANGLE};
use crate::drawing::Drawing;

/// Refuses options out of range and handles or curves that are not finite.
pub(super) fn check_inputs(
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

pub(super) fn check_options(o: &DomainOptions) -> Result<(), DomainError> {
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

pub(super) fn check_handles(
    points: &[Point],
    bones: &[[Point; 2]],
    tol: f64,
) -> Result<(), DomainError> {
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

/// Checks that every handle and both ends of every bone lie inside the closed `polygons` (or
/// within `tolerance` of their boundary), and that no bone crosses a boundary other than at an
/// end lying on it.
pub(super) fn check_inside(
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

/// Whether `p` is within `tol` of the polygon's boundary.
pub(super) fn on_polygon(poly: &[Point], p: Point, tol: f64) -> bool {
    (0..poly.len()).any(|k| segment_distance(p, poly[k], poly[(k + 1) % poly.len()]).0 <= tol)
}

/// Whether the segment `a b` crosses the polygon's boundary other than at its own end points
/// lying on it.
pub(super) fn crosses_polygon(poly: &[Point], a: Point, b: Point, tol: f64) -> bool {
    let n = poly.len();
    (0..n).any(|k| {
        let (c, d) = (poly[k], poly[(k + 1) % n]);
        segments_intersect(a, b, c, d)
            && segment_distance(a, c, d).0 > tol
            && segment_distance(b, c, d).0 > tol
    })
}
