//! Folds: where a deformation turns a drawing over onto itself — a closed outline that crosses
//! itself, or a triangle of the domain whose orientation flips.
//!
//! An outline is checked on a polyline of each cubic: curve `j` is cut into `k_j` pieces of
//! equal parameter length, `k_j = ⌈√(¾ · M_j / ε)⌉` with `M_j = max(|P0 − 2P1 + P2|,
//! |P1 − 2P2 + P3|)`, which keeps every piece within `ε` of its curve (Wang's bound for a cubic:
//! the chord of a parameter interval `h` is within `n(n − 1)/8 · M · h²` of the curve, `n = 3`).
//! `ε` is [`FLATNESS`] times the diagonal of the outline's control points, so the answer does
//! not change when the drawing is scaled or moved. The pieces are bucketed in a uniform grid
//! over the outline's box (about one piece per cell), and only pieces sharing a cell are
//! intersected: proper crossings of two pieces that are not neighbours along the outline.
//!
//! A crossing that the rest drawing already has (an artist's figure eight, a ribbon drawn over
//! itself) is not a fold: [`new_self_crossings`] keeps the crossings of curve pairs that do not
//! cross at rest. [`inverted_triangles`] compares signed areas at rest and deformed.

use std::collections::HashSet;

use kurbo::Point;

use crate::drawing::Drawing;

/// The flatness of the polyline an outline is checked on, relative to the diagonal of its
/// control points: 1e-4.
pub const FLATNESS: f64 = 1e-4;

/// Distance from a piece's line, relative to the outline's diagonal, within which a point
/// counts as on it (not across): 1e-9.
pub const NEAR_LINE: f64 = 1e-9;

/// Most pieces a single cubic is cut into: 64.
pub const MAX_PIECES: usize = 64;

/// A point where a closed outline crosses itself.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    /// The path (index in the drawing).
    pub path: usize,
    /// The two curves of the path that cross, the smaller index first.
    pub curves: (usize, usize),
    /// Where they cross (the crossing of their polylines, within the flatness of the curves).
    pub at: Point,
}

/// Every point where a closed path of `drawing` crosses itself when its chain points are
/// `points` (all paths' chain points concatenated in path order, [`Drawing::n_points`] long).
/// Open paths are not checked. In path order, then curve pair order.
///
/// ```
/// use kurbo::Point;
/// use splineskin_core::drawing::{Drawing, JunctionOptions, Path};
/// use splineskin_core::folds::self_crossings;
/// // A bow tie: the closed outline (0,0) → (10,10) → (10,0) → (0,10) → (0,0) crosses at (5,5).
/// let corners = [(0.0, 0.0), (10.0, 10.0), (10.0, 0.0), (0.0, 10.0), (0.0, 0.0)];
/// let mut points = vec![Point::from(corners[0])];
/// for w in corners.windows(2) {
///     let (a, b) = (Point::from(w[0]), Point::from(w[1]));
///     points.extend([a.lerp(b, 1.0 / 3.0), a.lerp(b, 2.0 / 3.0), b]);
/// }
/// let path = Path::new(points.clone(), true, &JunctionOptions::default()).unwrap();
/// let drawing = Drawing { paths: vec![path], ..Default::default() };
/// let crossings = self_crossings(&drawing, &points);
/// assert_eq!(crossings.len(), 1);
/// assert_eq!(crossings[0].curves, (0, 2));
/// assert!((crossings[0].at - Point::new(5.0, 5.0)).hypot() < 1e-9);
/// ```
pub fn self_crossings(drawing: &Drawing, points: &[Point]) -> Vec<Crossing> {
    let mut out = Vec::new();
    self_crossings_into(drawing, points, &mut FoldScratch::default(), &mut out);
    out
}

/// [`self_crossings`] written into `out` (cleared first), with the working buffers in
/// `scratch`: once both have grown to the drawing's size, a call allocates nothing.
pub fn self_crossings_into(
    drawing: &Drawing,
    points: &[Point],
    scratch: &mut FoldScratch,
    out: &mut Vec<Crossing>,
) {
    out.clear();
    if points.len() != drawing.n_points() {
        return;
    }
    for (path_index, (path, range)) in drawing.paths.iter().zip(drawing.path_ranges()).enumerate() {
        if path.closed {
            outline_crossings(path_index, &points[range], scratch, out);
        }
    }
}

/// The working buffers of a fold check ([`self_crossings_into`],
/// [`FoldCheck::new_crossings_into`]): the outline's pieces, its grid and the candidate
/// crossings, kept between calls so that an interactive tool's check after every frame
/// allocates nothing.
#[derive(Clone, Debug, Default)]
pub struct FoldScratch {
    pieces: Vec<Piece>,
    /// Each piece's range of grid cells: first column, first row, last column, last row.
    ranges: Vec<(usize, usize, usize, usize)>,
    /// Where each cell's members start in `members` (one more entry than cells).
    start: Vec<usize>,
    fill: Vec<usize>,
    members: Vec<usize>,
    candidates: Vec<(usize, usize, Point)>,
    /// Crossings found in one outline, with the pieces that found them (the sort key).
    found: Vec<(usize, usize, Crossing)>,
}

/// The crossings of `deformed` ([`self_crossings`]) between curves that do not cross at
/// `rest`: the folds the deformation made.
///
/// ```
/// use kurbo::Point;
/// use splineskin_core::drawing::{Drawing, JunctionOptions, Path};
/// use splineskin_core::folds::new_self_crossings;
/// // A square; its corner (10, 10) dragged to (−5, 5), across the opposite side.
/// let square = [(0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0), (0.0, 0.0)];
/// let chain = |c: &[(f64, f64)]| {
///     let mut p = vec![Point::from(c[0])];
///     for w in c.windows(2) {
///         let (a, b) = (Point::from(w[0]), Point::from(w[1]));
///         p.extend([a.lerp(b, 1.0 / 3.0), a.lerp(b, 2.0 / 3.0), b]);
///     }
///     p
/// };
/// let rest = chain(&square);
/// let path = Path::new(rest.clone(), true, &JunctionOptions::default()).unwrap();
/// let drawing = Drawing { paths: vec![path], ..Default::default() };
/// let folded = chain(&[(0.0, 0.0), (10.0, 0.0), (-5.0, 5.0), (0.0, 10.0), (0.0, 0.0)]);
/// assert_eq!(new_self_crossings(&drawing, &rest, &rest), vec![]);
/// let folds = new_self_crossings(&drawing, &rest, &folded);
/// // The side from (10, 0) to (−5, 5) crosses the left side x = 0 at y = 10/3.
/// assert_eq!(folds.len(), 1, "{folds:?}");
/// assert_eq!(folds[0].curves, (1, 3));
/// assert!((folds[0].at - Point::new(0.0, 10.0 / 3.0)).hypot() < 1e-9);
/// ```
pub fn new_self_crossings(drawing: &Drawing, rest: &[Point], deformed: &[Point]) -> Vec<Crossing> {
    FoldCheck::new(drawing, rest).new_crossings(drawing, deformed)
}

/// [`new_self_crossings`] for many deformations of one drawing: the rest pose's crossings are
/// found once, so each check costs one [`self_crossings`] of the deformed drawing (what an
/// interactive tool runs after every frame).
///
/// ```
/// use kurbo::Point;
/// use splineskin_core::drawing::{Drawing, JunctionOptions, Path};
/// use splineskin_core::folds::FoldCheck;
/// let rest = [(0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 0.0)].map(Point::from).to_vec();
/// let path = Path::new(rest.clone(), true, &JunctionOptions::default()).unwrap();
/// let drawing = Drawing { paths: vec![path], ..Default::default() };
/// let check = FoldCheck::new(&drawing, &rest);
/// assert!(check.new_crossings(&drawing, &rest).is_empty());
/// ```
#[derive(Clone, Debug, Default)]
pub struct FoldCheck {
    at_rest: HashSet<(usize, usize, usize)>,
}

impl FoldCheck {
    /// Finds the crossings of `drawing` at `rest` (its chain points).
    pub fn new(drawing: &Drawing, rest: &[Point]) -> FoldCheck {
        FoldCheck {
            at_rest: self_crossings(drawing, rest)
                .iter()
                .map(|c| (c.path, c.curves.0, c.curves.1))
                .collect(),
        }
    }

    /// The crossings of `deformed` between curves that do not cross at rest
    /// ([`new_self_crossings`]).
    pub fn new_crossings(&self, drawing: &Drawing, deformed: &[Point]) -> Vec<Crossing> {
        let mut out = Vec::new();
        self.new_crossings_into(drawing, deformed, &mut FoldScratch::default(), &mut out);
        out
    }

    /// [`FoldCheck::new_crossings`] written into `out` (cleared first), with the working
    /// buffers in `scratch`: once both have grown to the drawing's size, a check allocates
    /// nothing.
    ///
    /// ```
    /// use kurbo::Point;
    /// use splineskin_core::drawing::{Drawing, JunctionOptions, Path};
    /// use splineskin_core::folds::{FoldCheck, FoldScratch};
    /// let square = [(0., 0.), (10., 0.), (10., 10.), (0., 10.), (0., 0.)];
    /// let chain = |c: &[(f64, f64)]| {
    ///     let mut p = vec![Point::from(c[0])];
    ///     for w in c.windows(2) {
    ///         let (a, b) = (Point::from(w[0]), Point::from(w[1]));
    ///         p.extend([a.lerp(b, 1. / 3.), a.lerp(b, 2. / 3.), b]);
    ///     }
    ///     p
    /// };
    /// let rest = chain(&square);
    /// let drawing = Drawing { paths: vec![Path::new(rest.clone(), true, &JunctionOptions::default()).unwrap()], ..Default::default() };
    /// let check = FoldCheck::new(&drawing, &rest);
    /// let (mut scratch, mut out) = (FoldScratch::default(), Vec::new());
    /// // A corner dragged across the opposite side, then back: the same scratch each time.
    /// let folded = chain(&[(0., 0.), (10., 0.), (-5., 5.), (0., 10.), (0., 0.)]);
    /// check.new_crossings_into(&drawing, &folded, &mut scratch, &mut out);
    /// assert_eq!(out, check.new_crossings(&drawing, &folded));
    /// assert_eq!(out.len(), 1);
    /// check.new_crossings_into(&drawing, &rest, &mut scratch, &mut out);
    /// assert!(out.is_empty());
    /// ```
    pub fn new_crossings_into(
        &self,
        drawing: &Drawing,
        deformed: &[Point],
        scratch: &mut FoldScratch,
        out: &mut Vec<Crossing>,
    ) {
        self_crossings_into(drawing, deformed, scratch, out);
        out.retain(|c| !self.at_rest.contains(&(c.path, c.curves.0, c.curves.1)));
    }
}

/// The triangles (indices into `triangles`) whose orientation at `deformed` is the opposite of
/// their orientation at `rest` (signed areas of opposite signs): the domain folded over
/// itself there. Triangles degenerate at rest are not reported.
///
/// ```
/// use kurbo::Point;
/// use splineskin_core::folds::inverted_triangles;
/// let rest = [Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(0.0, 1.0), Point::new(1.0, 1.0)];
/// let triangles = [[0, 1, 2], [1, 3, 2]];
/// // Vertex 3 pulled across the edge 1–2.
/// let mut moved = rest;
/// moved[3] = Point::new(0.2, 0.2);
/// assert_eq!(inverted_triangles(&triangles, &rest, &moved), vec![1]);
/// assert!(inverted_triangles(&triangles, &rest, &rest).is_empty());
/// ```
pub fn inverted_triangles(
    triangles: &[[usize; 3]],
    rest: &[Point],
    deformed: &[Point],
) -> Vec<usize> {
    let area = |p: &[Point], [a, b, c]: [usize; 3]| (p[b] - p[a]).cross(p[c] - p[a]);
    triangles
        .iter()
        .enumerate()
        .filter(|&(_, &t)| {
            t.iter().all(|&v| v < rest.len() && v < deformed.len())
                && area(rest, t) * area(deformed, t) < 0.0
        })
        .map(|(k, _)| k)
        .collect()
}

/// One piece of an outline's polyline: its ends and the curve it belongs to.
#[derive(Clone, Copy, Debug)]
struct Piece {
    a: Point,
    b: Point,
    curve: usize,
}

/// The crossings of the closed outline with chain points `chain` (path `path`), appended to
/// `out`, with the working buffers in `scratch`.
fn outline_crossings(
    path: usize,
    chain: &[Point],
    scratch: &mut FoldScratch,
    out: &mut Vec<Crossing>,
) {
    let FoldScratch {
        pieces,
        ranges,
        start,
        fill,
        members,
        candidates,
        found,
    } = scratch;
    if chain.len() < 4 || !chain.iter().all(|p| p.is_finite()) {
        return;
    }
    let (mut lo, mut hi) = (chain[0], chain[0]);
    for p in chain {
        lo = Point::new(lo.x.min(p.x), lo.y.min(p.y));
        hi = Point::new(hi.x.max(p.x), hi.y.max(p.y));
    }
    let diagonal = (hi - lo).hypot();
    if diagonal == 0.0 {
        return;
    }
    let flatness = FLATNESS * diagonal;
    polyline(chain, flatness, pieces);
    let n = pieces.len();
    // A uniform grid of about one piece per cell.
    let side = ((n as f64).sqrt().ceil() as usize).clamp(1, 1024);
    let (w, h) = (
        (hi.x - lo.x).max(diagonal * 1e-12),
        (hi.y - lo.y).max(diagonal * 1e-12),
    );
    let cell = |p: Point| {
        let cx = (((p.x - lo.x) / w) * side as f64).floor() as isize;
        let cy = (((p.y - lo.y) / h) * side as f64).floor() as isize;
        (
            cx.clamp(0, side as isize - 1) as usize,
            cy.clamp(0, side as isize - 1) as usize,
        )
    };
    // The cells' members in one array (counted, then placed): no allocation per cell.
    ranges.clear();
    ranges.extend(pieces.iter().map(|piece| {
        let (c0, r0) = cell(Point::new(
            piece.a.x.min(piece.b.x),
            piece.a.y.min(piece.b.y),
        ));
        let (c1, r1) = cell(Point::new(
            piece.a.x.max(piece.b.x),
            piece.a.y.max(piece.b.y),
        ));
        (c0, r0, c1, r1)
    }));
    start.clear();
    start.resize(side * side + 1, 0);
    for &(c0, r0, c1, r1) in ranges.iter() {
        for r in r0..=r1 {
            for c in c0..=c1 {
                start[r * side + c + 1] += 1;
            }
        }
    }
    for k in 1..start.len() {
        start[k] += start[k - 1];
    }
    fill.clear();
    fill.extend_from_slice(start);
    members.clear();
    members.resize(start[side * side], 0);
    for (k, &(c0, r0, c1, r1)) in ranges.iter().enumerate() {
        for r in r0..=r1 {
            for c in c0..=c1 {
                members[fill[r * side + c]] = k;
                fill[r * side + c] += 1;
            }
        }
    }
    // Each pair of pieces is tested once, in the first cell both cover (the lowest column and
    // row of the overlap of their cell ranges): no list of pairs to sort and deduplicate.
    let near = NEAR_LINE * diagonal;
    candidates.clear();
    for r in 0..side {
        for c in 0..side {
            let cell_index = r * side + c;
            let members = &members[start[cell_index]..start[cell_index + 1]];
            for (x, &i) in members.iter().enumerate() {
                for &j in &members[x + 1..] {
                    let (i, j) = (i.min(j), i.max(j));
                    // Neighbours along the closed outline share an end: not a crossing.
                    if j - i <= 1 || (i == 0 && j == n - 1) {
                        continue;
                    }
                    let (a, b) = (ranges[i], ranges[j]);
                    if (a.0.max(b.0), a.1.max(b.1)) != (c, r) {
                        continue;
                    }
                    let (p, q) = (&pieces[i], &pieces[j]);
                    if let Some(at) = crossing(p.a, p.b, q.a, q.b, near) {
                        candidates.push((i, j, at));
                    }
                }
            }
        }
    }
    candidates.sort_unstable_by_key(|&(i, j, _)| (i, j));
    found.clear();
    for &(i, j, at) in candidates.iter() {
        let (p, q) = (&pieces[i], &pieces[j]);
        let curves = (p.curve.min(q.curve), p.curve.max(q.curve));
        // One crossing counted once, also when it falls where two pieces meet.
        let duplicate = found
            .iter()
            .any(|(_, _, c)| c.curves == curves && (c.at - at).hypot() <= 2.0 * flatness);
        if !duplicate {
            found.push((i, j, Crossing { path, curves, at }));
        }
    }
    // By curves, then in the order found (the pieces' order): an unstable sort on that key
    // needs no buffer.
    found.sort_unstable_by_key(|&(i, j, c)| (c.curves, i, j));
    out.extend(found.iter().map(|&(_, _, c)| c));
}

/// The polyline of the chain's cubics, each cut into pieces within `flatness` of it, written
/// into `pieces` (cleared first).
fn polyline(chain: &[Point], flatness: f64, pieces: &mut Vec<Piece>) {
    pieces.clear();
    for (curve, c) in chain.windows(4).step_by(3).enumerate() {
        let m = ((c[0] - c[1]) - (c[1] - c[2]))
            .hypot()
            .max(((c[1] - c[2]) - (c[2] - c[3])).hypot());
        let k = ((0.75 * m / flatness).sqrt().ceil() as usize).clamp(1, MAX_PIECES);
        let cubic = [c[0], c[1], c[2], c[3]];
        let mut a = c[0];
        for s in 1..=k {
            let b = if s == k {
                c[3]
            } else {
                crate::bezier::eval(&cubic, s as f64 / k as f64)
            };
            pieces.push(Piece { a, b, curve });
            a = b;
        }
    }
}

/// Where segments `a0 a1` and `b0 b1` cross (each one's ends on either side of the other's
/// line), if they do. An end within `near` (a distance) of the other line counts as on its
/// negative side, so that a crossing through the point where two pieces meet is found once,
/// by one of them, an outline touching a line there without crossing it is mostly not
/// reported, and collinear pieces (a straight side drawn with its handles on its ends, whose
/// pieces rounding puts a hair off each other's line) never cross.
fn crossing(a0: Point, a1: Point, b0: Point, b1: Point, near: f64) -> Option<Point> {
    let (da, db) = (a1 - a0, b1 - b0);
    let side = |o: Point, d: kurbo::Vec2, p: Point| d.cross(p - o);
    let (s0, s1) = (side(a0, da, b0), side(a0, da, b1));
    let (t0, t1) = (side(b0, db, a0), side(b0, db, a1));
    let (na, nb) = (near * da.hypot(), near * db.hypot());
    if (s0 > na) != (s1 > na) && (t0 > nb) != (t1 > nb) && t0 != t1 {
        let t = t0 / (t0 - t1);
        Some(a0 + da * t)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::{JunctionOptions, Path};
    use kurbo::{Affine, Vec2};

    /// A circle of four cubics about `centre` of radius `r`, as a closed chain.
    fn circle(centre: Point, r: f64) -> Vec<Point> {
        let k = 0.552_284_749_831 * r;
        let (x, y) = (centre.x, centre.y);
        vec![
            Point::new(x + r, y),
            Point::new(x + r, y + k),
            Point::new(x + k, y + r),
            Point::new(x, y + r),
            Point::new(x - k, y + r),
            Point::new(x - r, y + k),
            Point::new(x - r, y),
            Point::new(x - r, y - k),
            Point::new(x - k, y - r),
            Point::new(x, y - r),
            Point::new(x + k, y - r),
            Point::new(x + r, y - k),
            Point::new(x + r, y),
        ]
    }

    fn drawing_of(chains: &[Vec<Point>]) -> Drawing {
        Drawing {
            paths: chains
                .iter()
                .map(|c| Path::new(c.clone(), true, &JunctionOptions::default()).unwrap())
                .collect(),
            ..Default::default()
        }
    }

    #[test]
    fn folds_straight_sides_with_handles_on_their_ends_never_cross() {
        // A square's sides drawn as lines (handles on the ends), one corner moved and a
        // coordinate off by rounding (1e-19): collinear pieces a hair apart are not a fold.
        let p = |x: f64, y: f64| Point::new(x, y);
        let (a, b, c, d) = (p(0.0, 0.0), p(20.0, 0.0), p(23.0, 18.0), p(1e-19, 20.0));
        let chain = vec![a, a, b, b, b, c, c, c, d, d, d, a, a];
        let path = Path::new(chain.clone(), true, &JunctionOptions::default()).unwrap();
        let drawing = Drawing {
            paths: vec![path],
            ..Default::default()
        };
        assert_eq!(self_crossings(&drawing, &chain), vec![]);
    }

    #[test]
    fn folds_none_under_large_rigid_and_smooth_deformations() {
        let rest = circle(Point::new(3.0, -2.0), 5.0);
        let drawing = drawing_of(std::slice::from_ref(&rest));
        assert!(self_crossings(&drawing, &rest).is_empty());
        // Turned, scaled, sheared, moved far: no fold.
        let maps = [
            Affine::rotate(2.5),
            Affine::scale_non_uniform(40.0, 0.02),
            Affine::new([1.0, 0.0, 3.0, 1.0, 0.0, 0.0]),
            Affine::translate(Vec2::new(1e7, -3e6)) * Affine::scale(1e-6),
        ];
        for m in maps {
            let moved: Vec<Point> = rest.iter().map(|&p| m * p).collect();
            assert!(
                new_self_crossings(&drawing, &rest, &moved).is_empty(),
                "{m:?}"
            );
        }
        // A smooth non-affine bend (y += 0.3 x²): none either.
        let bent: Vec<Point> = rest
            .iter()
            .map(|p| Point::new(p.x, p.y + 0.3 * (p.x - 3.0).powi(2)))
            .collect();
        assert!(new_self_crossings(&drawing, &rest, &bent).is_empty());
    }

    #[test]
    fn folds_a_pulled_control_point_crosses_the_outline_where_computed() {
        // The circle's top handle pulled far down through the bottom: curves 0–1 swing across
        // curves 2–3. The crossings are where the deformed curves meet (checked on the curves
        // themselves by bisection on the found positions).
        let rest = circle(Point::ZERO, 10.0);
        let drawing = drawing_of(std::slice::from_ref(&rest));
        let mut folded = rest.clone();
        folded[3] = Point::new(0.0, -25.0); // the top on-curve point, below the bottom
        let folds = new_self_crossings(&drawing, &rest, &folded);
        assert!(!folds.is_empty());
        let path = Path::new(folded.clone(), true, &JunctionOptions::default()).unwrap();
        let size = 50.0;
        for c in &folds {
            // Each reported position lies on both curves, within the flatness.
            for j in [c.curves.0, c.curves.1] {
                let cubic = path.curve_points(j);
                let nearest = (0..=4000)
                    .map(|s| (crate::bezier::eval(&cubic, s as f64 / 4000.0) - c.at).hypot())
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    nearest <= 4.0 * FLATNESS * size,
                    "{c:?}: {nearest} from curve {j}"
                );
            }
        }
        // Scaled by 1e6 and moved far: the same folds, scaled and moved.
        let m = Affine::translate(Vec2::new(-4e9, 7e8)) * Affine::scale(1e6);
        let big: Vec<Point> = folded.iter().map(|&p| m * p).collect();
        let big_rest: Vec<Point> = rest.iter().map(|&p| m * p).collect();
        let big_folds = new_self_crossings(&drawing, &big_rest, &big);
        assert_eq!(big_folds.len(), folds.len());
        for (a, b) in folds.iter().zip(&big_folds) {
            assert_eq!(a.curves, b.curves);
            assert!((m * a.at - b.at).hypot() <= 1e-6 * 1e6 * size);
        }
    }

    #[test]
    fn folds_crossings_drawn_at_rest_are_not_folds_and_open_paths_are_not_checked() {
        // A bow tie drawn as such (its sides cross at rest): none new under a translation.
        let corners = [
            (0.0, 0.0),
            (10.0, 10.0),
            (10.0, 0.0),
            (0.0, 10.0),
            (0.0, 0.0),
        ];
        let mut eight = vec![Point::from(corners[0])];
        for w in corners.windows(2) {
            let (a, b) = (Point::from(w[0]), Point::from(w[1]));
            eight.extend([a.lerp(b, 0.25), a.lerp(b, 0.75), b]);
        }
        let drawing = drawing_of(std::slice::from_ref(&eight));
        assert_eq!(self_crossings(&drawing, &eight).len(), 1);
        let moved: Vec<Point> = eight.iter().map(|&p| p + Vec2::new(5.0, 5.0)).collect();
        assert_eq!(self_crossings(&drawing, &moved).len(), 1);
        assert!(new_self_crossings(&drawing, &eight, &moved).is_empty());
        // Open: never checked.
        let zigzag = vec![
            Point::new(0.0, 0.0),
            Point::new(10.0, 10.0),
            Point::new(10.0, -10.0),
            Point::new(0.0, 0.0),
            Point::new(-10.0, 10.0),
            Point::new(20.0, 5.0),
            Point::new(0.0, -3.0),
        ];
        let open = Drawing {
            paths: vec![Path::new(zigzag.clone(), false, &JunctionOptions::default()).unwrap()],
            ..Default::default()
        };
        assert!(self_crossings(&open, &zigzag).is_empty());
        // A wrong number of points, or a NaN: nothing reported, nothing panics.
        assert!(self_crossings(&drawing, &eight[..4]).is_empty());
        let mut nan = eight.clone();
        nan[2].x = f64::NAN;
        assert!(self_crossings(&drawing, &nan).is_empty());
    }
}
