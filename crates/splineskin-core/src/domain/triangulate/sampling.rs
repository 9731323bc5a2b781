//! The scale of a domain build and the curve samples: the sizes every tolerance is relative
//! to, the sample spacing and the samples along each path.

use kurbo::{CubicBez, ParamCurve, ParamCurveArclen, Point, Rect, Shape};

use super::super::{DomainError, DomainOptions, COINCIDENT_RELATIVE};
use crate::drawing::Drawing;

/// Arc-length accuracy of the per-curve sample counts, relative to the spacing: 1e-2 (the
/// counts are rounded up anyway).
pub(super) const ARCLEN_ACCURACY: f64 = 1e-2;

/// The sizes every tolerance of a build is relative to.
#[derive(Clone, Copy)]
pub(super) struct Scale {
    /// The diagonal of the curves' bounding box (else of everything's).
    pub(super) drawing_diag: f64,
    /// The bounding box of the curves, handles, bones and cage.
    pub(super) all_bounds: Rect,
    /// Distance under which two points are one: [`COINCIDENT_RELATIVE`] of the larger
    /// diagonal.
    pub(super) coincident: f64,
}

/// The [`Scale`] of the curves, handles, bones and cage; an error when there is nothing to
/// mesh or it spans a single point.
pub(super) fn measure_scale(
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
pub(super) fn sample_curves(
    drawing: &Drawing,
    spacing: f64,
    options: &DomainOptions,
) -> Vec<Vec<Point>> {
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

/// The sample spacing `s` (module documentation): `D / samples_per_diagonal`, enlarged until
/// the total count is within `max_curve_samples` (or every curve has a single interval).
pub(super) fn sample_spacing(drawing: &Drawing, diag: f64, o: &DomainOptions) -> f64 {
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

pub(super) fn intervals_for(len: f64, s: f64, cap: usize) -> usize {
    let n = (len / s).ceil();
    if n.is_finite() && n >= 1.0 {
        (n as usize).min(cap)
    } else {
        1
    }
}

pub(super) fn curve_intervals(c: &CubicBez, s: f64, o: &DomainOptions) -> usize {
    intervals_for(c.arclen(ARCLEN_ACCURACY * s), s, o.max_samples_per_curve)
}

/// Removes consecutive exact duplicates (and, if closed, a last point equal to the first).
pub(super) fn dedup_consecutive(v: &mut Vec<Point>, closed: bool) {
    v.dedup();
    if closed && v.len() > 1 && v.first() == v.last() {
        v.pop();
    }
}
