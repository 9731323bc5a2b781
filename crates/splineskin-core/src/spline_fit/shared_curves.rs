//! Curves that several paths share, and the groups of paths they tie together.
//!
//! Real drawings draw a fill and its outline, or two regions that touch, as separate paths
//! that run along the same curves. Fitted path by path, each copy of a shared curve is fitted
//! with its own neighbours and lands somewhere slightly different, so gaps and slivers open
//! between regions that touched. Here a shared curve is fitted once: every path that runs
//! along it gets exactly the same deformed curve.
//!
//! **Which curves are shared.** Two curves of different paths (or of the same path, at
//! different places) are the same curve when their four control points coincide, in the same
//! order or reversed, within [`SHARED_CURVE_TOLERANCE`] of the larger of the two curves'
//! control-polygon lengths. Curves of zero length are never shared (a dot is not an edge).
//!
//! **How they enter the systems.** Paths connected through shared curves form a *group*,
//! solved as one system (the rig's per-path solve, extended to several paths): its unknowns are the paths' unknown points with
//! the control points of every shared curve identified (one unknown for all the copies of a
//! point), its energy is the sum of the members' energies, each relative to the member's own
//! size: `Σ_p (D / d_p)² E_p`, `d_p` the diagonal of member `p`'s control-point box and `D`
//! the group's largest (a shared curve counted once per member along it, so that a small piece
//! beside long bars is fitted as well as it would be alone, not sacrificed to them), and
//! its constraint rows are every path's junction rows written over the group's unknowns,
//! rows that follow from others left out
//! ([`super::constraints::ConstraintRows::independent`]: a shared curve's end junction seen
//! from two paths gives the same rows twice when both paths continue the same way). The
//! result is linear in the handles' maps as before; each path reads its points from the
//! group's solution.

use std::collections::HashMap;

use kurbo::Point;

use crate::drawing::{Drawing, Path};
use crate::union_find;

/// Largest distance between corresponding control points of two curves taken as one shared
/// curve, relative to the larger control-polygon length of the two: 1e-7.
pub const SHARED_CURVE_TOLERANCE: f64 = 1e-7;

/// A cell of the grid on which curve ends are matched.
type Cell = (i64, i64);

/// One curve of a path.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct CurveRef {
    /// Path index in the drawing.
    pub path: usize,
    /// Curve index in the path.
    pub curve: usize,
}

/// A copy of a shared curve: `copy` runs along `original` (an earlier curve), reversed or not.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SharedCopy {
    /// The later curve.
    pub copy: CurveRef,
    /// The first curve (in document order) it coincides with.
    pub original: CurveRef,
    /// Whether `copy` runs the other way (`copy`'s `c_k` is `original`'s `c_{3−k}`).
    pub reversed: bool,
}

/// The shared curves of a drawing and the groups of paths they connect.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SharedCurves {
    /// Every copy of a shared curve, in document order of the copies.
    pub copies: Vec<SharedCopy>,
    /// Groups of paths connected by shared curves (a path may be alone in its group when it
    /// runs twice along one curve), each sorted, in order of their first path. Paths in no
    /// group are solved alone.
    pub groups: Vec<Vec<usize>>,
}

impl SharedCurves {
    /// Finds the shared curves of `drawing`.
    ///
    /// ```
    /// use kurbo::Point;
    /// use splineskin_core::drawing::{Drawing, JunctionOptions, Path};
    /// use splineskin_core::spline_fit::shared_curves::SharedCurves;
    /// let o = JunctionOptions::default();
    /// let pt = |x: f64, y: f64| Point::new(x, y);
    /// // Two squares side by side; the right one runs along the left one's right side, reversed.
    /// let left = vec![pt(0., 0.), pt(1., 0.), pt(1., 0.), pt(1., 0.), pt(1., 1.), pt(1., 1.),
    ///     pt(1., 1.), pt(0., 1.), pt(0., 1.), pt(0., 1.), pt(0., 0.), pt(0., 0.), pt(0., 0.)];
    /// let right = vec![pt(1., 0.), pt(2., 0.), pt(2., 0.), pt(2., 0.), pt(2., 1.), pt(2., 1.),
    ///     pt(2., 1.), pt(1., 1.), pt(1., 1.), pt(1., 1.), pt(1., 1.), pt(1., 1.), pt(1., 0.)];
    /// let drawing = Drawing {
    ///     paths: vec![Path::new(left, true, &o).unwrap(), Path::new(right, true, &o).unwrap()],
    ///     ..Default::default()
    /// };
    /// let shared = SharedCurves::find(&drawing);
    /// assert_eq!(shared.copies.len(), 1);
    /// assert!(shared.copies[0].reversed);
    /// assert_eq!(shared.groups, vec![vec![0, 1]]);
    /// ```
    pub fn find(drawing: &Drawing) -> SharedCurves {
        let diag = drawing.diagonal();
        // Candidates by their unordered end points on a grid far finer than any drawing's
        // detail; a pair straddling a cell boundary is missed, which only costs a gap that
        // was there before.
        let cell = (diag * SHARED_CURVE_TOLERANCE).max(f64::MIN_POSITIVE);
        let key = |p: Point| ((p.x / cell).round() as i64, (p.y / cell).round() as i64);
        let mut by_ends: HashMap<(Cell, Cell), Vec<CurveRef>> = HashMap::new();
        let mut copies = Vec::new();
        for (pi, path) in drawing.paths.iter().enumerate() {
            for j in 0..path.n_curves() {
                let c = path.curve_points(j);
                let length = polygon_length(&c);
                if length == 0.0 {
                    continue;
                }
                let (a, b) = (key(c[0]), key(c[3]));
                let ends = if a <= b { (a, b) } else { (b, a) };
                let here = CurveRef { path: pi, curve: j };
                let entry = by_ends.entry(ends).or_default();
                let found = entry.iter().find_map(|&o| {
                    let d = drawing.paths[o.path].curve_points(o.curve);
                    let tol = SHARED_CURVE_TOLERANCE * length.max(polygon_length(&d));
                    let close = |rev: bool| {
                        (0..4).all(|k| (c[k] - d[if rev { 3 - k } else { k }]).hypot() <= tol)
                    };
                    if close(false) {
                        Some((o, false))
                    } else if close(true) {
                        Some((o, true))
                    } else {
                        None
                    }
                });
                match found {
                    Some((original, reversed)) => copies.push(SharedCopy {
                        copy: here,
                        original,
                        reversed,
                    }),
                    None => entry.push(here),
                }
            }
        }
        // Groups: paths connected by copies.
        let mut parent = union_find::singletons(drawing.paths.len());
        for c in &copies {
            union_find::union(&mut parent, c.copy.path, c.original.path);
        }
        let mut members: HashMap<usize, Vec<usize>> = HashMap::new();
        for c in &copies {
            for p in [c.copy.path, c.original.path] {
                members
                    .entry(union_find::root(&mut parent, p))
                    .or_default()
                    .push(p);
            }
        }
        let mut groups: Vec<Vec<usize>> = members
            .into_values()
            .map(|mut g| {
                g.sort_unstable();
                g.dedup();
                g
            })
            .collect();
        groups.sort_unstable();
        SharedCurves { copies, groups }
    }

    /// The group path `path` belongs to, if any (an index into [`SharedCurves::groups`]).
    pub fn group_of(&self, path: usize) -> Option<usize> {
        self.groups
            .iter()
            .position(|g| g.binary_search(&path).is_ok())
    }
}

/// The length of a curve's control polygon.
fn polygon_length(c: &[Point; 4]) -> f64 {
    (c[1] - c[0]).hypot() + (c[2] - c[1]).hypot() + (c[3] - c[2]).hypot()
}

/// Unknown indices of a group's paths: for each path (in group order) the group unknown of each
/// of its own unknown points (`Path::n_unknown_points` of them), and the number of group
/// unknowns. Copies of shared curves take their original's unknowns.
pub(crate) fn group_unknowns(
    paths: &[&Path],
    group: &[usize],
    copies: &[SharedCopy],
) -> (Vec<Vec<usize>>, usize) {
    let offsets: Vec<usize> = paths
        .iter()
        .scan(0, |acc, p| {
            let o = *acc;
            *acc += p.n_unknown_points();
            Some(o)
        })
        .collect();
    let total: usize = paths.iter().map(|p| p.n_unknown_points()).sum();
    let slot = |path: usize, chain: usize| {
        let g = group.binary_search(&path).expect("a copy of this group");
        offsets[g] + paths[g].unknown_index(chain)
    };
    let mut parent = union_find::singletons(total);
    for c in copies {
        if group.binary_search(&c.copy.path).is_err() {
            continue;
        }
        for k in 0..4 {
            let ko = if c.reversed { 3 - k } else { k };
            union_find::union(
                &mut parent,
                slot(c.copy.path, 3 * c.copy.curve + k),
                slot(c.original.path, 3 * c.original.curve + ko),
            );
        }
    }
    let (index, n) = union_find::labels(&mut parent);
    let maps = paths
        .iter()
        .enumerate()
        .map(|(g, p)| index[offsets[g]..offsets[g] + p.n_unknown_points()].to_vec())
        .collect();
    (maps, n)
}
