//! Linear junction constraints of one path, as sparse rows over its unknowns.
//!
//! Unknowns are the path's distinct chain points (C⁰ is built in: neighbouring curves share
//! their junction point), two coordinates each: unknown `2·k + d` is coordinate `d` of point `k`.
//!
//! At a smooth or fixed-angle junction `p`, with `a` the tangent neighbour before it and `b` the
//! one after it (see [`JunctionRule`]), `u = P_p − P_a` and `v = P_b − P_p` in the input with
//! lengths `l_u`, `l_v`, the deformed tangents must satisfy
//!
//! ```text
//! l_u · v' − l_v · R(θ) · u' = 0          (two rows, one per coordinate)
//! ```
//!
//! i.e. `v'` is `u'` turned by `θ` and scaled by the input ratio `l_v/l_u` (Liu et al. 2014 §4,
//! Table 1; DESIGN.md §1):
//!
//! | kind | `θ` | lengths |
//! |---|---|---|
//! | C¹ (ours: strict, when the input is C¹) | 0 | `l_u = l_v = 1` |
//! | G¹, and C¹ whose input is not C¹ (ours), tangents within the smooth angle | the input's angle | input |
//! | fixed angle | the input's angle | input |
//! | C¹, G¹ ([`ConstraintForm::Authors`]) | 0 | input |
//!
//! In our form a C¹ or G¹ junction whose input tangents are farther apart than the smooth
//! angle has no rows (C⁰), and every row holds on the input whatever kind a scene saved, so
//! the rest pose reproduces the drawing ([`crate::drawing::junction`] explains the choice).
//!
//! A fixed angle whose tangent neighbour on a side is that side's far end (a straight side
//! drawn with its control points on its ends, as the import writes lines between corners)
//! has no rows in our form: there the rows would tie the corner to the far corner, keeping
//! the two sides' length ratio, and around a polygon of such corners lock it to a
//! similarity of itself (a rectangle could not follow a bend; shared sides spread that
//! stiffness to every path along them). The authors' rows vanish there too (both tangents
//! have zero length). The corner keeps its position (C⁰), its sides bend freely.
//!
//! Rows are divided by `max(l_u, l_v)` for conditioning. With [`JunctionRule::NextDistinct`]
//! control points lying on the junction point (between `a` and `p`, or `p` and `b`) are also
//! pinned to it (`P_k' = P_p'`), so a degenerate tangent stays degenerate and the curve's real
//! tangent (towards the next distinct point) carries the continuity.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use kurbo::Point;

use crate::drawing::junction::{
    coincidence_distance, rest_relation, tangent_neighbours, turn_angle,
};
use crate::drawing::{JointKind, JunctionOptions};

/// How constraints are written.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ConstraintForm {
    /// Ours: tangent neighbours are the next distinct points ([`JunctionRule::NextDistinct`]),
    /// C¹ is strict where the input is C¹, G¹ keeps the input's angle, so that the rest pose
    /// is exact ([`crate::drawing::junction::rest_relation`]).
    #[default]
    Ours,
    /// The paper authors' rows (compatibility mode): immediate neighbours, C¹ rows identical to
    /// G¹ rows with the input ratio, G¹ with `θ = 0`, rows that vanish (two zero-length tangents)
    /// dropped.
    Authors,
}

/// Which points define a junction's tangents.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JunctionRule {
    /// `c2` and `d1`, whatever their position.
    Immediate,
    /// The first control point distinct from the junction point on each side.
    NextDistinct,
}

/// Sparse linear constraint rows `Σ coef · x_col = 0`.
#[derive(Clone, Debug, Default)]
pub struct ConstraintRows {
    /// `(row, column, coefficient)` entries; rows are numbered from 0.
    pub entries: Vec<(usize, usize, f64)>,
    /// Number of rows.
    pub n_rows: usize,
}

/// Size below which a constraint row, reduced by the rows kept before it, counts as their
/// linear combination, relative to the largest coefficient met while reducing it: 1e-9
/// ([`ConstraintRows::independent`]).
pub const DEPENDENT_ROW_TOLERANCE: f64 = 1e-9;

impl ConstraintRows {
    /// The rows with every row that is a linear combination of the rows kept before it left
    /// out, and the number left out.
    ///
    /// Junction rows are independent as long as each junction's tangent neighbours are its
    /// own control points. They stop being so when the neighbours are other junctions' points:
    /// a closed polygon whose straight sides have their control points on their ends and whose
    /// corners are all fixed angles (or G¹) gives each corner's rows over the corner and its
    /// two neighbouring corners, and around the loop two pairs of rows follow from the others
    /// (the polygon keeps a translation and a similarity: `2n` unknowns, `2n − 4` independent
    /// rows); a zero-length curve between two junctions pins its points twice. The input
    /// satisfies every row, so the dependent ones are consistent, but kept they make the KKT
    /// matrix singular up to rounding and the solve returns whatever the rounding decides
    /// (collapsed or exploded shapes, at any scale). Leaving them out changes nothing else:
    /// they hold wherever the kept rows hold.
    ///
    /// Gaussian elimination row by row, in the order pushed: a row is reduced by the kept rows
    /// whose pivot columns it touches; if what remains is below [`DEPENDENT_ROW_TOLERANCE`]
    /// times the largest coefficient met during its reduction, it is dependent, otherwise it
    /// is kept with the furthest column among those within half of its largest remaining
    /// coefficient as pivot (columns follow the chain, so a chain of junctions keeps its
    /// stored rows short). Rows are kept exactly as given; elimination only decides which.
    ///
    /// ```
    /// use splineskin_core::spline_fit::constraints::ConstraintRows;
    /// let mut rows = ConstraintRows::default();
    /// rows.push_row(&[(0, 1.0), (1, -1.0)]);
    /// rows.push_row(&[(1, 1.0), (2, -1.0)]);
    /// rows.push_row(&[(0, 2.0), (2, -2.0)]); // twice the sum of the first two
    /// let (kept, dropped) = rows.independent();
    /// assert_eq!((kept.n_rows, dropped), (2, 1));
    /// ```
    pub fn independent(&self) -> (ConstraintRows, usize) {
        let n_cols = self.entries.iter().map(|e| e.1 + 1).max().unwrap_or(0);
        let mut by_row: Vec<Vec<(usize, f64)>> = vec![Vec::new(); self.n_rows];
        for &(r, c, v) in &self.entries {
            by_row[r].push((c, v));
        }
        // Kept rows, reduced and scaled so that their pivot coefficient is 1.
        let mut basis: Vec<Vec<(usize, f64)>> = Vec::new();
        let mut pivot_of = vec![usize::MAX; n_cols];
        let mut work = vec![0.0f64; n_cols];
        let mut touched: Vec<usize> = Vec::new();
        let mut is_touched = vec![false; n_cols];
        let mut out = ConstraintRows::default();
        let mut dropped = 0;
        for row in &by_row {
            let mut largest = 0.0f64;
            for &(c, v) in row {
                if !is_touched[c] {
                    is_touched[c] = true;
                    touched.push(c);
                }
                work[c] += v;
                largest = largest.max(work[c].abs());
            }
            // Eliminate pivot columns, oldest kept row first: a kept row was reduced by the
            // pivots before its own, so it only brings in younger pivots and each is met once.
            let mut heap: BinaryHeap<Reverse<(usize, usize)>> = touched
                .iter()
                .filter(|&&c| pivot_of[c] != usize::MAX)
                .map(|&c| Reverse((pivot_of[c], c)))
                .collect();
            while let Some(Reverse((_, c))) = heap.pop() {
                let f = work[c];
                if f == 0.0 {
                    continue;
                }
                for &(cc, v) in &basis[pivot_of[c]] {
                    if !is_touched[cc] {
                        is_touched[cc] = true;
                        touched.push(cc);
                    }
                    work[cc] -= f * v;
                    largest = largest.max(work[cc].abs());
                    if cc != c && pivot_of[cc] != usize::MAX {
                        heap.push(Reverse((pivot_of[cc], cc)));
                    }
                }
                work[c] = 0.0;
            }
            let remaining = touched.iter().map(|&c| work[c].abs()).fold(0.0, f64::max);
            if remaining > DEPENDENT_ROW_TOLERANCE * largest {
                let pivot = touched
                    .iter()
                    .copied()
                    .filter(|&c| work[c].abs() >= 0.5 * remaining)
                    .max()
                    .expect("a coefficient reaches the largest");
                let scale = 1.0 / work[pivot];
                let mut reduced: Vec<(usize, f64)> = touched
                    .iter()
                    .filter(|&&c| work[c] != 0.0)
                    .map(|&c| (c, work[c] * scale))
                    .collect();
                reduced.sort_by_key(|e| e.0);
                pivot_of[pivot] = basis.len();
                basis.push(reduced);
                out.push_row(row);
            } else {
                dropped += 1;
            }
            for &c in &touched {
                work[c] = 0.0;
                is_touched[c] = false;
            }
            touched.clear();
        }
        (out, dropped)
    }

    /// Appends the row `Σ coef · x_col = 0` given as `(col, coef)` pairs; zero coefficients
    /// are left out, and a row with none is not added.
    pub fn push_row(&mut self, entries: &[(usize, f64)]) {
        let mut any = false;
        for &(col, v) in entries {
            if v != 0.0 {
                self.entries.push((self.n_rows, col, v));
                any = true;
            }
        }
        if any {
            self.n_rows += 1;
        }
    }
}

/// The tangent geometry of one junction that has tangent rows (C¹, G¹ or fixed angle): the
/// unknowns `a`, `p`, `b` of the rows `l_u · v' − l_v · R(θ) · u' = 0` (module doc), `u = P_p −
/// P_a`, `v = P_b − P_p`.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct TangentJunction {
    /// The joint index `k` (chain point `3k`).
    pub joint: usize,
    /// Its kind.
    pub kind: JointKind,
    /// Unknown index of the tangent neighbour before the junction point.
    pub a: usize,
    /// Unknown index of the junction point.
    pub p: usize,
    /// Unknown index of the tangent neighbour after it.
    pub b: usize,
    /// The angle `θ` taking the incoming direction `u` to the outgoing one `v` (radians).
    pub theta: f64,
    /// The lengths the rows keep the ratio of: the input's `‖u‖`, `‖v‖` (1, 1 for strict C¹).
    pub lengths: (f64, f64),
    /// Unknowns pinned to `p` (control points lying on the junction point, our form only).
    pub pins: Vec<usize>,
}

impl TangentJunction {
    /// Whether both kept lengths are zero: the authors' rows vanish and are dropped.
    pub fn vanishes(&self) -> bool {
        self.lengths.0.max(self.lengths.1) == 0.0
    }

    /// The two rows for tangent lengths `(l_u, l_v)`, as `(column, coefficient)` lists with
    /// every entry present (zero coefficients included, so that the pattern does not depend on
    /// the lengths or the angle). Rows are divided by `max(l_u, l_v)`; when both are zero the
    /// rows are written for equal lengths.
    pub fn rows(&self, lengths: (f64, f64)) -> [[(usize, f64); 5]; 2] {
        let scale = lengths.0.max(lengths.1);
        let (lu, lv) = if scale > 0.0 {
            (lengths.0 / scale, lengths.1 / scale)
        } else {
            (1.0, 1.0)
        };
        let (s, c) = self.theta.sin_cos();
        let (ia, ip, ib) = (self.a, self.p, self.b);
        let x = |i: usize| 2 * i;
        let y = |i: usize| 2 * i + 1;
        // x row: lu (xb − xp) − lv [c (xp − xa) − s (yp − ya)] = 0
        // y row: lu (yb − yp) − lv [s (xp − xa) + c (yp − ya)] = 0
        [
            [
                (x(ib), lu),
                (x(ip), -lu - lv * c),
                (x(ia), lv * c),
                (y(ip), lv * s),
                (y(ia), -lv * s),
            ],
            [
                (y(ib), lu),
                (y(ip), -lu - lv * c),
                (y(ia), lv * c),
                (x(ip), -lv * s),
                (x(ia), lv * s),
            ],
        ]
    }
}

/// The tangent junctions of a chain with joint kinds `joints`, in joint order (see
/// [`junction_rows`]): every C¹, G¹ and fixed-angle joint that has a direction on both sides.
pub(crate) fn tangent_junctions(
    points: &[Point],
    closed: bool,
    joints: &[JointKind],
    form: ConstraintForm,
    options: &JunctionOptions,
) -> Vec<TangentJunction> {
    let m = points.len() - 1; // 3n
    let n_unknown = if closed { m } else { m + 1 };
    let wrap = |i: usize| if i >= n_unknown { i - n_unknown } else { i };
    let eps = coincidence_distance(points, options.coincidence);
    let mut out = Vec::new();
    for (k, &kind) in joints.iter().enumerate() {
        if matches!(kind, JointKind::End | JointKind::C0) {
            continue;
        }
        let p = 3 * k;
        let (a, b) = match form {
            ConstraintForm::Ours => match tangent_neighbours(points, closed, p, eps) {
                (Some(a), Some(b)) => (a, b),
                // No direction on one side: nothing to keep but position.
                _ => continue,
            },
            ConstraintForm::Authors => {
                let a = if p == 0 { m - 1 } else { p - 1 };
                (a, p + 1)
            }
        };
        if form == ConstraintForm::Ours && kind == JointKind::FixedAngle {
            // A side whose tangent neighbour is its far end (a straight side with its
            // control points on its ends) has no drawn tangent: see the module doc.
            let far_before = points[if p == 0 { m } else { p } - 3];
            let far_after = points[if p == m { 0 } else { p } + 3];
            if (points[a] - far_before).hypot() <= eps || (points[b] - far_after).hypot() <= eps {
                continue;
            }
        }
        let pp = points[p];
        let u = pp - points[a];
        let v = points[b] - pp;
        let (mut lu, mut lv) = (u.hypot(), v.hypot());
        let theta = match form {
            ConstraintForm::Ours => {
                // A saved kind the input does not have: what it has (a corner saved smooth
                // keeps only its position).
                let Some(relation) = rest_relation(kind, u, v, options) else {
                    continue;
                };
                if relation.equal_lengths {
                    (lu, lv) = (1.0, 1.0);
                }
                relation.theta
            }
            ConstraintForm::Authors if kind == JointKind::FixedAngle => turn_angle(u, v),
            ConstraintForm::Authors => 0.0,
        };
        let mut pins = Vec::new();
        if form == ConstraintForm::Ours {
            // Control points lying on the junction point between a and p, and p and b.
            let end = if p == 0 { m } else { p };
            pins.extend((1..end - a).map(|d| wrap(end - d)));
            pins.extend((1..(b - p)).map(|d| wrap(p + d)));
        }
        out.push(TangentJunction {
            joint: k,
            kind,
            a: wrap(a),
            p: wrap(p),
            b: wrap(b),
            theta,
            lengths: (lu, lv),
            pins,
        });
    }
    out
}

/// Builds the constraint rows of a chain with joint kinds `joints` (see
/// [`crate::drawing::Path`] for the layouts). `options` holds the C¹ tolerance and the
/// coincidence distance ([`crate::drawing::junction::rest_relation`]).
///
/// Per junction: its two tangent rows with the input's lengths (`TangentJunction::rows`, zero
/// coefficients left out), then its pins `P_q' − P_p' = 0`. Junctions whose two tangents
/// vanish (the authors' form) have no rows. In our form, rows that are linear combinations of
/// earlier ones are left out ([`ConstraintRows::independent`]); the authors' form keeps them.
pub fn junction_rows(
    points: &[Point],
    closed: bool,
    joints: &[JointKind],
    form: ConstraintForm,
    options: &JunctionOptions,
) -> ConstraintRows {
    let mut rows = ConstraintRows::default();
    for t in tangent_junctions(points, closed, joints, form, options) {
        if t.vanishes() {
            continue; // both tangents vanish: the authors' rows are all zero and dropped
        }
        for row in t.rows(t.lengths) {
            rows.push_row(&row);
        }
        push_pins(&mut rows, &t);
    }
    match form {
        // Rows that follow from the others are left out (see ConstraintRows::independent).
        ConstraintForm::Ours => rows.independent().0,
        // Compatibility mode keeps the authors' rows as they are, dependent or not.
        ConstraintForm::Authors => rows,
    }
}

/// Pushes the pin rows `P_q' − P_p' = 0` of junction `t` (two per pinned point).
pub(crate) fn push_pins(rows: &mut ConstraintRows, t: &TangentJunction) {
    for &q in &t.pins {
        rows.push_row(&[(2 * q, 1.0), (2 * t.p, -1.0)]);
        rows.push_row(&[(2 * q + 1, 1.0), (2 * t.p + 1, -1.0)]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support::{self, CLOSED_TWO_CURVES, SMOOTH_RATIO_2, STACKED_HANDLES};

    /// The constraint rows of the chain `pts` (joint kinds `joints`, default options) in
    /// `form`, and their residuals `A x` at the chain itself.
    fn rows_and_residuals(
        pts: &[Point],
        closed: bool,
        joints: &[JointKind],
        form: ConstraintForm,
    ) -> (ConstraintRows, Vec<f64>) {
        let rows = junction_rows(pts, closed, joints, form, &JunctionOptions::default());
        let n_unknown = if closed { pts.len() - 1 } else { pts.len() };
        let x: Vec<f64> = pts[..n_unknown].iter().flat_map(|p| [p.x, p.y]).collect();
        let mut r = vec![0.0; rows.n_rows];
        for &(i, j, v) in &rows.entries {
            r[i] += v * x[j];
        }
        (rows, r)
    }

    #[test]
    fn constraints_hold_on_the_input() {
        // A corner at 60°, kept as a fixed angle, and a smooth G1 junction with ratio 2.
        let pts: Vec<Point> = [
            (0.0, 0.0),
            (1.0, 0.0),
            (2.0, 0.0),
            (3.0, 0.0),
            (3.5, 0.866_025_403_784_438_6),
            (4.0, 2.0),
            (5.0, 2.0),
            (7.0, 2.0),
            (8.0, 3.0),
            (9.0, 2.0),
        ]
        .map(Point::from)
        .to_vec();
        let joints = [
            JointKind::End,
            JointKind::FixedAngle,
            JointKind::G1,
            JointKind::End,
        ];
        for form in [ConstraintForm::Ours, ConstraintForm::Authors] {
            let (rows, residuals) = rows_and_residuals(&pts, false, &joints, form);
            assert_eq!(rows.n_rows, 4);
            for r in residuals {
                assert!(r.abs() < 1e-14, "{form:?}: {r}");
            }
        }
    }

    #[test]
    fn constraints_c1_is_strict_where_the_input_is_c1() {
        // A C1 input: ours writes equal lengths, so a configuration whose outgoing tangent is
        // parallel but twice as long violates the rows.
        let c1 = test_support::pts(&test_support::SMOOTH_C1);
        let joints = [JointKind::End, JointKind::C1, JointKind::End];
        let rows = junction_rows(
            &c1,
            false,
            &joints,
            ConstraintForm::Ours,
            &JunctionOptions::default(),
        );
        let mut stretched = c1.clone();
        stretched[4] = Point::new(5.0, 0.0);
        let x: Vec<f64> = stretched.iter().flat_map(|p| [p.x, p.y]).collect();
        let mut r = vec![0.0; rows.n_rows];
        for &(i, j, v) in &rows.entries {
            r[i] += v * x[j];
        }
        assert!(r[0].abs() > 0.1, "{r:?}");
        // Saved C1 on an input with ratio 2: both forms keep the input (the rest pose).
        let pts = test_support::pts(&SMOOTH_RATIO_2);
        for form in [ConstraintForm::Ours, ConstraintForm::Authors] {
            let (_, residuals) = rows_and_residuals(&pts, false, &joints, form);
            assert!(
                residuals.iter().all(|r| r.abs() < 1e-15),
                "{form:?}: {residuals:?}"
            );
        }
    }

    #[test]
    fn constraints_saved_g1_keeps_what_the_input_has() {
        // Saved G1, tangents `deg` degrees apart.
        let chain = |deg: f64| {
            let d = kurbo::Vec2::from_angle(deg.to_radians());
            let q = Point::new(3.0, 0.0);
            vec![
                Point::ZERO,
                Point::new(1.0, 0.0),
                Point::new(2.0, 0.0),
                q,
                q + d,
                q + 2.0 * d,
                q + 3.0 * d,
            ]
        };
        let joints = [JointKind::End, JointKind::G1, JointKind::End];
        // 0.5°: within the smooth angle, two rows keeping the input's turn (they hold at rest).
        let (rows, ours) = rows_and_residuals(&chain(0.5), false, &joints, ConstraintForm::Ours);
        assert_eq!(rows.n_rows, 2);
        assert!(ours.iter().all(|r| r.abs() < 1e-15), "{ours:?}");
        // 10°: a corner in the input, C0 in ours (no rows); the authors' form imposes parallel
        // tangents, which the input violates.
        let (rows, _) = rows_and_residuals(&chain(10.0), false, &joints, ConstraintForm::Ours);
        assert_eq!(rows.n_rows, 0);
        let (_, theirs) = rows_and_residuals(&chain(10.0), false, &joints, ConstraintForm::Authors);
        assert!(theirs.iter().any(|r| r.abs() > 0.1), "{theirs:?}");
    }

    #[test]
    fn constraints_pin_degenerate_handles() {
        // c2 on c3 and d1 on d0: pins for both, tangent row between c1 and d2.
        let pts = test_support::pts(&STACKED_HANDLES);
        let joints = [JointKind::End, JointKind::G1, JointKind::End];
        let (rows, residuals) = rows_and_residuals(&pts, false, &joints, ConstraintForm::Ours);
        assert_eq!(rows.n_rows, 2 + 4);
        for r in residuals {
            assert!(r.abs() < 1e-15);
        }
    }

    #[test]
    fn constraints_closed_path_wraps() {
        let pts = test_support::pts(&CLOSED_TWO_CURVES);
        let joints = [JointKind::C1, JointKind::C1];
        let (rows, residuals) = rows_and_residuals(&pts, true, &joints, ConstraintForm::Ours);
        assert_eq!(rows.n_rows, 4);
        assert!(rows.entries.iter().all(|&(_, c, _)| c < 12));
        for r in residuals {
            assert!(r.abs() < 1e-15);
        }
    }
}
