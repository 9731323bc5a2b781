//! From usvg's path data to chains of cubic curves: the segments of a subpath ([`Segment`]),
//! cross-checked against the element's own `d` (usvg stores `f32`), turned into the `3n + 1`
//! chain points of a [`Path`] with its closing line and corner lines placed.

use kurbo::{Affine, Point, Rect};
use splineskin_core::drawing::{JointKind, Path};

use super::{ImportOptions, CLOSE_SNAP, MAX_COORDINATE};
use crate::document::SvgError;

/// A segment of path data in local coordinates (`f64`), as tiny-skia's path builder stores
/// it: absolute, arcs already cubics, `H`/`V`/`S`/`T` resolved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Segment {
    Move(Point),
    Line(Point),
    Quad(Point, Point),
    Cubic(Point, Point, Point),
    Close,
}

/// usvg's (`f32`) path data as segments.
pub(super) fn segments_of_usvg(data: &usvg::tiny_skia_path::Path) -> Vec<Segment> {
    use usvg::tiny_skia_path::PathSegment as S;
    let pt = |p: usvg::tiny_skia_path::Point| Point::new(f64::from(p.x), f64::from(p.y));
    data.segments()
        .map(|s| match s {
            S::MoveTo(p) => Segment::Move(pt(p)),
            S::LineTo(p) => Segment::Line(pt(p)),
            S::QuadTo(q, p) => Segment::Quad(pt(q), pt(p)),
            S::CubicTo(c1, c2, p) => Segment::Cubic(pt(c1), pt(c2), pt(p)),
            S::Close => Segment::Close,
        })
        .collect()
}

/// A validated `d` attribute as segments, in `f64`: the same svgtypes simplification usvg
/// uses (arcs become cubics with kurbo at tolerance 0.1), with tiny-skia's path-builder rules
/// (consecutive moves collapse, repeated closes collapse, drawing after a close starts at the
/// subpath's start), but without usvg's rounding to `f32`.
pub(super) fn segments_of_path_data(d: &str) -> Vec<Segment> {
    use svgtypes::SimplePathSegment as S;
    let mut out: Vec<Segment> = Vec::new();
    let mut last_move = Point::ORIGIN;
    let mut move_required = true;
    let move_to = |out: &mut Vec<Segment>, p: Point, last_move: &mut Point| {
        match out.last_mut() {
            Some(Segment::Move(q)) => *q = p,
            _ => out.push(Segment::Move(p)),
        }
        *last_move = p;
    };
    for segment in svgtypes::SimplifyingPathParser::from(d) {
        let Ok(segment) = segment else {
            break; // as usvg does; validation has already refused such data
        };
        if !matches!(segment, S::MoveTo { .. } | S::ClosePath) && move_required {
            move_to(&mut out, last_move, &mut last_move);
            move_required = false;
        }
        match segment {
            S::MoveTo { x, y } => {
                move_to(&mut out, Point::new(x, y), &mut last_move);
                move_required = false;
            }
            S::LineTo { x, y } => out.push(Segment::Line(Point::new(x, y))),
            S::Quadratic { x1, y1, x, y } => {
                out.push(Segment::Quad(Point::new(x1, y1), Point::new(x, y)))
            }
            S::CurveTo {
                x1,
                y1,
                x2,
                y2,
                x,
                y,
            } => out.push(Segment::Cubic(
                Point::new(x1, y1),
                Point::new(x2, y2),
                Point::new(x, y),
            )),
            S::ClosePath => {
                if !matches!(out.last(), None | Some(Segment::Close)) {
                    out.push(Segment::Close);
                }
                move_required = true;
            }
        }
    }
    out
}

/// Relative tolerance of the cross-check between our `f64` path data and usvg's `f32` one:
/// 1e-6, a dozen `f32` ulps.
pub(super) const F32_CROSS_CHECK: f64 = 1e-6;

/// Whether two segment lists have the same commands and points equal within `f32` rounding.
pub(super) fn same_structure(a: &[Segment], b: &[Segment]) -> bool {
    let close = |p: &Point, q: &Point| {
        (*p - *q).hypot() <= F32_CROSS_CHECK * (1.0 + p.x.abs().max(p.y.abs()))
    };
    a.len() == b.len()
        && a.iter().zip(b).all(|pair| match pair {
            (Segment::Move(p), Segment::Move(q)) | (Segment::Line(p), Segment::Line(q)) => {
                close(p, q)
            }
            (Segment::Quad(p1, p), Segment::Quad(q1, q)) => close(p1, q1) && close(p, q),
            (Segment::Cubic(p1, p2, p), Segment::Cubic(q1, q2, q)) => {
                close(p1, q1) && close(p2, q2) && close(p, q)
            }
            (Segment::Close, Segment::Close) => true,
            _ => false,
        })
}

/// Appends the subpaths of `segments` (local coordinates) as [`Path`]s in root user space,
/// and for each whether it is closed without a `Z` (to `closed_without_z`).
pub(super) fn convert_segments(
    segments: &[Segment],
    local_to_root: Affine,
    options: &ImportOptions,
    origin: &str,
    label: &str,
    out: &mut Vec<Path>,
    closed_without_z: &mut Vec<bool>,
) -> Result<(), SvgError> {
    let mut current: Vec<Point> = Vec::new();
    // Curves of the current subpath that are straight segments (`L`, `H`, `V`, closing lines).
    let mut lines: Vec<usize> = Vec::new();
    let mut finish = |points: &mut Vec<Point>,
                      lines: &mut Vec<usize>,
                      has_z: bool|
     -> Result<(), SvgError> {
        let mut points = std::mem::take(points);
        let mut lines = std::mem::take(lines);
        if points.is_empty() {
            return Ok(());
        }
        if has_z {
            let before = points.len();
            close_subpath(&mut points);
            if points.len() > before {
                lines.push((before - 1) / 3);
            }
        }
        let returns_to_start = !has_z && points.len() >= 4 && points[0] == points[points.len() - 1];
        let closed = has_z || returns_to_start;
        if points.len() < 4 {
            tracing::warn!(
                file = origin,
                element = label,
                x = points[0].x,
                y = points[0].y,
                "a subpath of a single point has no curve; skipped (it is not written back)"
            );
            return Ok(());
        }
        for p in &mut points {
            *p = local_to_root * *p;
            for v in [p.x, p.y] {
                if v.is_nan() || v.abs() > MAX_COORDINATE {
                    return Err(SvgError::CoordinateOutOfRange {
                        file: origin.to_string(),
                        element: label.to_string(),
                        value: v,
                        limit: MAX_COORDINATE,
                    });
                }
            }
        }
        let mut path =
            Path::new(points, closed, &options.junctions).ok_or_else(|| SvgError::Internal {
                file: origin.to_string(),
                what: format!("{label}: a subpath is not a 3n+1 chain"),
            })?;
        if options.corner_lines_at_ends {
            place_corner_lines(&mut path, &lines);
        }
        out.push(path);
        closed_without_z.push(returns_to_start);
        Ok(())
    };
    for &segment in segments {
        match segment {
            Segment::Move(p) => {
                finish(&mut current, &mut lines, false)?;
                current.push(p);
            }
            Segment::Line(p3) => {
                let p0 = start_point(&mut current);
                lines.push((current.len() - 1) / 3);
                current.extend([p0.lerp(p3, 1.0 / 3.0), p0.lerp(p3, 2.0 / 3.0), p3]);
            }
            Segment::Quad(q, p3) => {
                let p0 = start_point(&mut current);
                current.extend([p0.lerp(q, 2.0 / 3.0), p3.lerp(q, 2.0 / 3.0), p3]);
            }
            Segment::Cubic(c1, c2, p3) => {
                start_point(&mut current);
                current.extend([c1, c2, p3]);
            }
            Segment::Close => finish(&mut current, &mut lines, true)?,
        }
    }
    finish(&mut current, &mut lines, false)
}

/// Moves the inner control points of the straight segments `lines` (curve indices) onto their
/// ends when neither end is a smooth junction (see the module doc).
pub(super) fn place_corner_lines(path: &mut Path, lines: &[usize]) {
    let n = path.n_curves();
    let smooth = |k: usize| {
        let joint = if path.closed { k % n } else { k };
        matches!(path.joints.get(joint), Some(JointKind::C1 | JointKind::G1))
    };
    let corner_lines: Vec<usize> = lines
        .iter()
        .copied()
        .filter(|&k| k < n && !smooth(k) && !smooth(k + 1))
        .collect();
    for k in corner_lines {
        path.points[3 * k + 1] = path.points[3 * k];
        path.points[3 * k + 2] = path.points[3 * k + 3];
    }
}

/// The current point of a subpath being built; starts the subpath at the origin if it has
/// none (tiny-skia always starts with a move, so this is only a guard).
pub(super) fn start_point(points: &mut Vec<Point>) -> Point {
    match points.last() {
        Some(&p) => p,
        None => {
            points.push(Point::ORIGIN);
            Point::ORIGIN
        }
    }
}

/// Closes a subpath's chain (`≥ 1` point): snaps its last point onto the first when within
/// [`CLOSE_SNAP`], otherwise appends the closing line as a cubic. A single point stays single.
pub(super) fn close_subpath(points: &mut Vec<Point>) {
    let first = points[0];
    let last = points[points.len() - 1];
    if points.len() < 4 {
        return;
    }
    let bounds = points
        .iter()
        .fold(Rect::from_points(first, first), |r, &p| r.union_pt(p));
    let magnitude = points
        .iter()
        .fold(0.0f64, |m, p| m.max(p.x.abs()).max(p.y.abs()));
    let scale = (bounds.width().hypot(bounds.height())).max(magnitude);
    if (last - first).hypot() <= CLOSE_SNAP * scale {
        let n = points.len();
        points[n - 1] = first;
    } else {
        points.extend([
            last.lerp(first, 1.0 / 3.0),
            last.lerp(first, 2.0 / 3.0),
            first,
        ]);
    }
}
