//! Where a cubic Bézier curve crosses a line segment: the parameters `t` at which piecewise
//! linear (mesh) weights stop being smooth along the curve.
//!
//! The signed distance of `B(t)` to the line through `a, b`, scaled by `‖b − a‖`,
//!
//! ```text
//! d(t) = (B(t) − a) × (b − a) = Σ_k d_k b_k(t),   d_k = (c_k − a) × (b − a),
//! ```
//!
//! is a cubic in Bernstein form with coefficients `d_k` (the cross product is linear and the
//! Bernstein basis sums to one). Its roots in `[0, 1]` are isolated by subdivision: by the
//! variation-diminishing property, no sign change among the `d_k` of an interval means no root
//! there, exactly one means exactly one root, and the root is then bracketed by the interval's
//! ends and found by safeguarded Newton iteration (bisection when Newton leaves the bracket).
//! More changes split the interval at its middle (de Casteljau). A root is a crossing of the
//! *segment* when the nearest point parameter `s = (B(t) − a)·(b − a) / ‖b − a‖²` lies in
//! `[0, 1]` (with a tolerance: extra cuts are harmless, missed ones are not). Tangential
//! touches (double roots) are reported when the subdivision reaches [`MIN_INTERVAL`] with the
//! ends of different sign only; at a touch the weights are smooth anyway.

use kurbo::Point;

/// Smallest parameter interval that root isolation subdivides: `2⁻³⁰ ≈ 1e-9`. Below it the
/// coefficients can no longer separate roots in double precision (near-tangency), and the
/// interval's midpoint is taken as the root if its ends differ in sign.
pub const MIN_INTERVAL: f64 = 1.0 / (1u64 << 30) as f64;

/// Accuracy of a crossing parameter: `1e-14` (in `t`), the bracket width at which the iteration
/// stops.
pub const T_ACCURACY: f64 = 1e-14;

/// Slack on the segment parameter `s` when deciding whether a root of the line crossing lies on
/// the segment: `1e-9`. Crossings through a segment's end points are found from the other
/// segments meeting there too; the slack only makes sure none is lost to rounding.
pub const S_SLACK: f64 = 1e-9;

/// The Bernstein coefficients of the cubic `c` split at `t = ½`: left and right halves.
#[inline]
fn split_half(d: [f64; 4]) -> ([f64; 4], [f64; 4]) {
    let d01 = 0.5 * (d[0] + d[1]);
    let d12 = 0.5 * (d[1] + d[2]);
    let d23 = 0.5 * (d[2] + d[3]);
    let d012 = 0.5 * (d01 + d12);
    let d123 = 0.5 * (d12 + d23);
    let m = 0.5 * (d012 + d123);
    ([d[0], d01, d012, m], [m, d123, d23, d[3]])
}

/// Value and derivative of the Bernstein cubic `d` at `t`.
#[inline]
fn eval_bernstein(d: &[f64; 4], t: f64) -> (f64, f64) {
    let s = 1.0 - t;
    let v = s * s * s * d[0] + 3.0 * s * s * t * d[1] + 3.0 * s * t * t * d[2] + t * t * t * d[3];
    let dv = 3.0 * (s * s * (d[1] - d[0]) + 2.0 * s * t * (d[2] - d[1]) + t * t * (d[3] - d[2]));
    (v, dv)
}

/// Number of sign changes in `d`, zeros skipped.
#[inline]
fn sign_changes(d: &[f64; 4]) -> usize {
    let mut last = 0.0;
    let mut n = 0;
    for &x in d {
        if x != 0.0 {
            if last != 0.0 && (x > 0.0) != (last > 0.0) {
                n += 1;
            }
            last = x;
        }
    }
    n
}

/// Appends to `out` the roots in the open interval `(0, 1)` of the cubic with Bernstein
/// coefficients `d` (see the module documentation), in increasing order. A cubic whose
/// coefficients are all zero (the curve lies on the line) has no isolated root and adds
/// nothing.
pub(crate) fn bernstein_roots(d: [f64; 4], out: &mut Vec<f64>) {
    if d.iter().all(|&x| x == 0.0) {
        return;
    }
    let start = out.len();
    // Depth-first over (coefficients of the sub-interval, its start, its width).
    let mut stack: Vec<([f64; 4], f64, f64)> = vec![(d, 0.0, 1.0)];
    while let Some((c, t0, w)) = stack.pop() {
        let n = sign_changes(&c);
        if n == 0 {
            continue;
        }
        if n == 1 && c[0] != 0.0 && c[3] != 0.0 {
            out.push(bracketed_root(&d, t0, t0 + w, c[0] > 0.0));
            continue;
        }
        if w <= MIN_INTERVAL {
            if (c[0] > 0.0) != (c[3] > 0.0) && c[0] != 0.0 && c[3] != 0.0 {
                out.push(t0 + 0.5 * w);
            }
            continue;
        }
        let (l, r) = split_half(c);
        // The shared middle value is a root exactly when it is zero.
        if l[3] == 0.0 {
            out.push(t0 + 0.5 * w);
        }
        // Right first so that the left half is popped first (increasing order).
        stack.push((r, t0 + 0.5 * w, 0.5 * w));
        stack.push((l, t0, 0.5 * w));
    }
    let mut keep = start;
    for k in start..out.len() {
        if out[k] > 0.0 && out[k] < 1.0 {
            out[keep] = out[k];
            keep += 1;
        }
    }
    out.truncate(keep);
}

/// The root of the Bernstein cubic `d` in `[lo, hi]`, where `d(lo)` has the sign
/// `positive_at_lo` and `d(hi)` the other: Newton steps kept inside a shrinking bracket.
fn bracketed_root(d: &[f64; 4], mut lo: f64, mut hi: f64, positive_at_lo: bool) -> f64 {
    let mut t = 0.5 * (lo + hi);
    for _ in 0..100 {
        let (v, dv) = eval_bernstein(d, t);
        if v == 0.0 {
            return t;
        }
        if (v > 0.0) == positive_at_lo {
            lo = t;
        } else {
            hi = t;
        }
        if hi - lo <= T_ACCURACY {
            break;
        }
        let step = v / dv;
        let newton = t - step;
        if newton > lo && newton < hi {
            t = newton;
            if step.abs() <= T_ACCURACY {
                return t;
            }
        } else {
            t = 0.5 * (lo + hi);
        }
    }
    t
}

/// Appends to `out` the parameters `t ∈ (0, 1)` where the cubic with control points `c`
/// crosses (or touches) the closed segment `a b`.
pub(crate) fn cubic_segment_crossings(c: &[Point; 4], a: Point, b: Point, out: &mut Vec<f64>) {
    let ab = b - a;
    let len2 = ab.hypot2();
    if len2 == 0.0 {
        return;
    }
    let d = c.map(|p| (p - a).cross(ab));
    let start = out.len();
    bernstein_roots(d, out);
    let mut keep = start;
    for k in start..out.len() {
        let t = out[k];
        let p = crate::bezier::eval(c, t);
        let s = (p - a).dot(ab) / len2;
        if (-S_SLACK..=1.0 + S_SLACK).contains(&s) {
            out[keep] = t;
            keep += 1;
        }
    }
    out.truncate(keep);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bernstein coefficients of the cubic with the given roots (monic up to sign).
    fn from_roots(r: [f64; 3]) -> [f64; 4] {
        // Power basis coefficients of (t−r0)(t−r1)(t−r2) = t³ + p2 t² + p1 t + p0.
        let p2 = -(r[0] + r[1] + r[2]);
        let p1 = r[0] * r[1] + r[0] * r[2] + r[1] * r[2];
        let p0 = -r[0] * r[1] * r[2];
        // Power to Bernstein: d0 = p0, d1 = p0 + p1/3, d2 = p0 + 2p1/3 + p2/3, d3 = Σ.
        [
            p0,
            p0 + p1 / 3.0,
            p0 + 2.0 * p1 / 3.0 + p2 / 3.0,
            p0 + p1 + p2 + 1.0,
        ]
    }

    #[test]
    fn crossings_three_close_roots_found_exactly() {
        for roots in [
            [0.1, 0.5, 0.9],
            [0.3, 0.3001, 0.7],
            [0.25, 0.5, 0.75],
            [-0.5, 0.4, 1.5],
        ] {
            let mut out = Vec::new();
            bernstein_roots(from_roots(roots), &mut out);
            let expected: Vec<f64> = roots
                .iter()
                .copied()
                .filter(|r| *r > 0.0 && *r < 1.0)
                .collect();
            assert_eq!(out.len(), expected.len(), "{roots:?}: {out:?}");
            // Each root moves by about ε / |p'(r)| when the coefficients are rounded:
            // p'(0.3) = 4e-5 for the close pair, so 1e-11 is that conditioning, not slack.
            for (a, b) in out.iter().zip(&expected) {
                assert!((a - b).abs() < 1e-11, "{roots:?}: {out:?}");
            }
        }
    }

    #[test]
    fn crossings_of_line_with_segment() {
        // The straight cubic from (0,0) to (4,0), parametrised uniformly, crosses x = 1 at 1/4.
        let c = [(0., 0.), (4. / 3., 0.), (8. / 3., 0.), (4., 0.)].map(Point::from);
        let mut out = vec![7.0]; // appended to, earlier content kept
        cubic_segment_crossings(&c, Point::new(1.0, -1.0), Point::new(1.0, 1.0), &mut out);
        assert_eq!(out.len(), 2);
        assert_eq!(out.remove(0), 7.0);
        assert!((out[0] - 0.25).abs() <= 2.0 * T_ACCURACY, "{}", out[0]);
        // A segment beside the line's crossing point is not crossed.
        out.clear();
        cubic_segment_crossings(&c, Point::new(1.0, 0.5), Point::new(1.0, 1.0), &mut out);
        assert!(out.is_empty());
        // Collinear: no isolated crossing.
        cubic_segment_crossings(&c, Point::new(-1.0, 0.0), Point::new(5.0, 0.0), &mut out);
        assert!(out.is_empty());
    }
}
