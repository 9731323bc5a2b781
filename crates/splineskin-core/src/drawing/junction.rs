//! Classification of the on-curve points of a chain into continuity kinds.
//!
//! At a junction between curve `C` (ending at `c3`) and curve `D` (starting at `d0 = c3`) the
//! incoming tangent is `u = c3 − a` and the outgoing one `v = b − d0`, where `a` is the first of
//! `c2, c1, c0` and `b` the first of `d1, d2, d3` farther than [`JunctionOptions::coincidence`]
//! from the junction point (a control point on top of its end point has no direction; the next
//! distinct point gives it). If either has no distinct point the junction is C⁰. Otherwise,
//! with `θ` the angle between `u` and `v`:
//!
//! | condition | kind |
//! |---|---|
//! | `θ ≤ smooth_angle` and `‖u‖ = ‖v‖` within `c1_ratio` (relative) | [`JointKind::C1`] |
//! | `θ ≤ smooth_angle` | [`JointKind::G1`] |
//! | `|θ − 90°| ≤ right_angle` (if `keep_right_angles`) | [`JointKind::FixedAngle`] |
//! | otherwise | [`JointKind::C0`] |
//!
//! The constraint each kind imposes is in [`crate::spline_fit`]. Every kind is satisfied by the
//! input itself (G¹ and fixed angle use the input's own angle and length ratio), so the rest
//! pose reproduces the drawing exactly.
//!
//! **Saved kinds the input does not satisfy.** A scene can mark a junction with a kind its
//! drawing does not have: editors save "smooth" for points whose handles were moved apart
//! afterwards, and hand-digitised script is full of junctions marked G¹ whose tangents are a
//! few degrees apart (or whose handle lies on its anchor). Imposing the saved kind exactly
//! there would move the drawing at rest and pull every curve near it away from the target.
//! Our constraint form imposes instead what the input has ([`rest_relation`]):
//!
//! | saved kind | the input's tangents | imposed |
//! |---|---|---|
//! | C¹ | C¹: `|θ| ≤ c1_ratio`, `|‖u‖/‖v‖ − 1| ≤ c1_ratio` | strict C¹ |
//! | C¹ or G¹ | `|θ| ≤ smooth_angle` | G¹: the input's turn `θ` and ratio |
//! | C¹ or G¹ | `|θ| > smooth_angle` | C⁰: position only |
//! | fixed angle | any | the input's angle and ratio |
//!
//! Why C⁰ for a "smooth" junction whose tangents are more than `smooth_angle` apart: a tangent
//! relation that the input satisfies must then turn `u` by `θ` into `v`, and no fixed linear
//! relation between two non-parallel tangents survives a non-uniform local map (a shear or a
//! stretch of the skinning turns them by different angles), so the fit would be held away from
//! the skinned target around every such junction. On a line of hand-digitised script of
//! ours (`tools/make_script.py`: 368 curves, 352 junctions saved G¹, 64 of them 1–13.4° off,
//! Shepard handles outside), keeping the input's turn there gave the fit twice the energy of
//! the naive Jacobian baseline (2.3e-3 against 1.07e-3); C⁰ gives it a fifth of it (2.4e-4),
//! and a smaller max and RMS distance. Free, the fit follows the target, in which the kink is
//! carried by the deformation. Parallel tangents (`|θ| ≤ smooth_angle`) keep their
//! relation: it survives every affine map up to that small angle. A junction with no distinct
//! point on one side has no tangent to keep and is C⁰ whatever its saved kind. These
//! junctions are listed by [`joint_mismatches`] so that a tool can say how many a drawing had.

use kurbo::{Point, Vec2};
use serde::{Deserialize, Serialize};

/// The continuity imposed at an on-curve point of a chain.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum JointKind {
    /// An end of an open path: no constraint.
    #[serde(rename = "end")]
    End,
    /// Position continuity only: the two curves share the point.
    C0,
    /// Strict C¹: `c3' − c2' = d1' − d0'` (equal tangents), where the input is C¹; saved on
    /// an input that is not, what the input has ([`rest_relation`]).
    C1,
    /// G¹ with the input's tangent-length ratio: `c3' − c2' = r (d1' − d0')`, turned by the
    /// input's own small angle; saved on a corner, C⁰ ([`rest_relation`]).
    G1,
    /// The input's angle between the tangents and their length ratio are kept.
    #[serde(rename = "angle")]
    FixedAngle,
}

impl JointKind {
    /// Short name as used in scenes and the CLI: `end`, `C0`, `C1`, `G1`, `angle`.
    pub fn name(self) -> &'static str {
        match self {
            JointKind::End => "end",
            JointKind::C0 => "C0",
            JointKind::C1 => "C1",
            JointKind::G1 => "G1",
            JointKind::FixedAngle => "angle",
        }
    }
}

/// Default largest angle between incoming and outgoing tangents of a smooth junction:
/// 1° (0.01745 rad). Drawings exported with three decimals put smooth points within ≈0.1° of
/// parallel for handles longer than one unit; 1° leaves room for shorter handles while still
/// being an angle nobody draws as a corner.
pub const DEFAULT_SMOOTH_ANGLE: f64 = 1.0 * std::f64::consts::PI / 180.0;

/// Default tolerance on `|θ − 90°|` for a right-angle corner kept at a fixed angle: 1°.
pub const DEFAULT_RIGHT_ANGLE: f64 = 1.0 * std::f64::consts::PI / 180.0;

/// Default relative tolerance on `|‖u‖/‖v‖ − 1|` for labelling a smooth junction C¹ rather than
/// G¹: 1e-9. Strict C¹ moves the rest pose unless the input is C¹ to this precision; anything
/// less exact is G¹, which keeps the input's ratio.
pub const DEFAULT_C1_RATIO: f64 = 1e-9;

/// Default distance (in drawing units, relative to the path's size) below which a control point
/// counts as lying on its end point: 1e-9 of the path's bounding-box diagonal.
pub const DEFAULT_COINCIDENCE: f64 = 1e-9;

/// Tolerances of junction classification. See the module doc for how they are used.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct JunctionOptions {
    /// Largest tangent angle (radians) of a smooth junction. Default: [`DEFAULT_SMOOTH_ANGLE`].
    pub smooth_angle: f64,
    /// Whether right-angle corners keep their angle ([`JointKind::FixedAngle`]) rather than
    /// being C⁰. Default: `true` (as the paper's authors do).
    pub keep_right_angles: bool,
    /// Tolerance (radians) on a right angle. Default: [`DEFAULT_RIGHT_ANGLE`].
    pub right_angle: f64,
    /// Relative tolerance on equal tangent lengths for C¹. Default: [`DEFAULT_C1_RATIO`].
    pub c1_ratio: f64,
    /// Coincidence distance relative to the path's control-point bounding-box diagonal.
    /// Default: [`DEFAULT_COINCIDENCE`].
    pub coincidence: f64,
}

impl Default for JunctionOptions {
    fn default() -> Self {
        JunctionOptions {
            smooth_angle: DEFAULT_SMOOTH_ANGLE,
            keep_right_angles: true,
            right_angle: DEFAULT_RIGHT_ANGLE,
            c1_ratio: DEFAULT_C1_RATIO,
            coincidence: DEFAULT_COINCIDENCE,
        }
    }
}

impl JunctionOptions {
    /// Sets [`JunctionOptions::smooth_angle`].
    pub fn with_smooth_angle(mut self, radians: f64) -> Self {
        self.smooth_angle = radians;
        self
    }
    /// Sets [`JunctionOptions::keep_right_angles`].
    pub fn with_keep_right_angles(mut self, keep: bool) -> Self {
        self.keep_right_angles = keep;
        self
    }
}

/// The tangent geometry at on-curve point `p` of a chain: the index of the first distinct point
/// before it (within the previous curve) and after it (within the next curve).
///
/// `prev` and `next` are chain indices; for closed chains they wrap (index `3n` is index 0).
/// `eps` is the coincidence distance.
pub fn tangent_neighbours(
    points: &[Point],
    closed: bool,
    p: usize,
    eps: f64,
) -> (Option<usize>, Option<usize>) {
    let m = points.len() - 1; // 3n
    let centre = points[p];
    let prev = if p == 0 && !closed {
        None
    } else {
        let base = if p == 0 { m } else { p };
        (1..=3)
            .map(|k| base - k)
            .find(|&i| (points[i] - centre).hypot() > eps)
    };
    let next = if p == m && !closed {
        None
    } else {
        let base = if p == m { 0 } else { p };
        (1..=3)
            .map(|k| base + k)
            .find(|&i| (points[i] - centre).hypot() > eps)
    };
    (prev, next)
}

/// The coincidence distance for a chain: `relative` times its control-point diagonal (at
/// least the smallest positive normal `f64`, so that exact duplicates always coincide).
pub fn coincidence_distance(points: &[Point], relative: f64) -> f64 {
    let (mut lo, mut hi) = (points[0], points[0]);
    for p in points {
        lo = Point::new(lo.x.min(p.x), lo.y.min(p.y));
        hi = Point::new(hi.x.max(p.x), hi.y.max(p.y));
    }
    ((hi - lo).hypot() * relative).max(f64::MIN_POSITIVE)
}

/// Angle in `[0, π]` between two non-zero vectors.
pub fn angle_between(u: Vec2, v: Vec2) -> f64 {
    u.cross(v).atan2(u.dot(v)).abs()
}

/// What the fit keeps at a junction with tangents: the turn `θ` from the incoming tangent `u`
/// to the outgoing one `v` (radians, signed), and whether the two lengths are made equal
/// (strict C¹) or keep the input's ratio `‖v‖/‖u‖`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TangentRelation {
    /// The imposed turn angle (radians, counter-clockwise positive).
    pub theta: f64,
    /// `true`: `‖u'‖ = ‖v'‖` (strict C¹); `false`: the input's ratio is kept.
    pub equal_lengths: bool,
}

/// Signed angle (radians, in `(−π, π]`) turning `u` to `v`; 0 if either is zero.
pub fn turn_angle(u: Vec2, v: Vec2) -> f64 {
    if u.hypot() > 0.0 && v.hypot() > 0.0 {
        u.cross(v).atan2(u.dot(v))
    } else {
        0.0
    }
}

/// Whether input tangents `u` (incoming) and `v` (outgoing) have the continuity `kind`
/// within the tolerances of `options` (table in the module doc). `End`, `C0` and fixed
/// angles are always satisfied.
///
/// ```
/// use kurbo::Vec2;
/// use splineskin_core::drawing::junction::input_satisfies;
/// use splineskin_core::drawing::{JointKind, JunctionOptions};
/// let o = JunctionOptions::default();
/// let u = Vec2::new(1.0, 0.0);
/// let v = Vec2::from_angle(5f64.to_radians()) * 2.0; // 5° off, twice as long
/// assert!(!input_satisfies(JointKind::G1, u, v, &o));
/// assert!(input_satisfies(JointKind::G1, u, Vec2::new(2.0, 0.0), &o));
/// assert!(!input_satisfies(JointKind::C1, u, Vec2::new(2.0, 0.0), &o));
/// ```
pub fn input_satisfies(kind: JointKind, u: Vec2, v: Vec2, options: &JunctionOptions) -> bool {
    let theta = turn_angle(u, v).abs();
    match kind {
        JointKind::C1 => {
            theta <= options.c1_ratio && (u.hypot() / v.hypot() - 1.0).abs() <= options.c1_ratio
        }
        JointKind::G1 => theta <= options.smooth_angle,
        JointKind::End | JointKind::C0 | JointKind::FixedAngle => true,
    }
}

/// The relation our constraint form imposes at a C¹, G¹ or fixed-angle junction with input
/// tangents `u`, `v` (table in the module doc): strict C¹ (`θ = 0`, equal lengths) for a C¹
/// junction whose input is C¹; the input's own turn angle and ratio for a fixed angle and for
/// C¹ or G¹ within `smooth_angle`; `None` (C⁰, no tangent relation) for C¹ or G¹ whose
/// tangents are farther apart. The input satisfies every relation returned, so the rest pose
/// is reproduced whatever kind was saved.
///
/// ```
/// use kurbo::Vec2;
/// use splineskin_core::drawing::junction::rest_relation;
/// use splineskin_core::drawing::{JointKind, JunctionOptions};
/// let o = JunctionOptions::default();
/// let u = Vec2::new(1.0, 0.0);
/// let slight = Vec2::from_angle(0.5f64.to_radians()) * 3.0;
/// let r = rest_relation(JointKind::G1, u, slight, &o).unwrap();
/// assert!((r.theta - 0.5f64.to_radians()).abs() < 1e-15 && !r.equal_lengths);
/// let c1 = rest_relation(JointKind::C1, u, u, &o).unwrap();
/// assert!(c1.theta == 0.0 && c1.equal_lengths);
/// // Saved G1 with tangents 10° apart: a corner in the input, kept C0.
/// assert!(rest_relation(JointKind::G1, u, Vec2::from_angle(0.17), &o).is_none());
/// ```
pub fn rest_relation(
    kind: JointKind,
    u: Vec2,
    v: Vec2,
    options: &JunctionOptions,
) -> Option<TangentRelation> {
    let theta = turn_angle(u, v);
    match kind {
        JointKind::C1 if input_satisfies(kind, u, v, options) => Some(TangentRelation {
            theta: 0.0,
            equal_lengths: true,
        }),
        JointKind::C1 | JointKind::G1 if theta.abs() > options.smooth_angle => None,
        JointKind::C1 | JointKind::G1 | JointKind::FixedAngle => Some(TangentRelation {
            theta,
            equal_lengths: false,
        }),
        JointKind::End | JointKind::C0 => None,
    }
}

/// A junction whose saved kind its input does not have (module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointMismatch {
    /// The joint index `k` (chain point `3k`).
    pub joint: usize,
    /// Its saved kind (C¹ or G¹).
    pub kind: JointKind,
    /// The input's turn angle between the tangents (radians, absolute); `None` when a side
    /// has no distinct point (no tangent: the junction is C⁰).
    pub angle: Option<f64>,
    /// The input's tangent-length ratio `‖v‖/‖u‖` (`None` with `angle`).
    pub ratio: Option<f64>,
}

/// The joints of a chain whose saved kinds (`joints`, the layout of
/// [`crate::drawing::Path::joints`]) the input does not satisfy within `options`
/// ([`input_satisfies`]), or which have no tangent on a side although saved as C¹ or G¹.
/// Our constraint form imposes what the input has there ([`rest_relation`]).
///
/// ```
/// use kurbo::Point;
/// use splineskin_core::drawing::junction::joint_mismatches;
/// use splineskin_core::drawing::{JointKind, JunctionOptions};
/// // Two curves meeting at (3, 0) with a 10° kink, saved as G¹.
/// let d = kurbo::Vec2::from_angle(10f64.to_radians());
/// let q = Point::new(3.0, 0.0);
/// let pts = [Point::ZERO, Point::new(1.0, 0.0), Point::new(2.0, 0.0), q, q + d, q + 2.0 * d, q + 3.0 * d];
/// let kinds = [JointKind::End, JointKind::G1, JointKind::End];
/// let m = joint_mismatches(&pts, false, &kinds, &JunctionOptions::default());
/// assert_eq!(m.len(), 1);
/// assert!((m[0].angle.unwrap().to_degrees() - 10.0).abs() < 1e-9);
/// ```
pub fn joint_mismatches(
    points: &[Point],
    closed: bool,
    joints: &[JointKind],
    options: &JunctionOptions,
) -> Vec<JointMismatch> {
    let eps = coincidence_distance(points, options.coincidence);
    let mut out = Vec::new();
    for (k, &kind) in joints.iter().enumerate() {
        if !matches!(kind, JointKind::C1 | JointKind::G1) {
            continue;
        }
        let p = 3 * k;
        match tangent_neighbours(points, closed, p, eps) {
            (Some(a), Some(b)) => {
                let (u, v) = (points[p] - points[a], points[b] - points[p]);
                if !input_satisfies(kind, u, v, options) {
                    out.push(JointMismatch {
                        joint: k,
                        kind,
                        angle: Some(turn_angle(u, v).abs()),
                        ratio: Some(v.hypot() / u.hypot()),
                    });
                }
            }
            _ => out.push(JointMismatch {
                joint: k,
                kind,
                angle: None,
                ratio: None,
            }),
        }
    }
    out
}

/// Classifies every on-curve point of the chain `points` (`3n + 1` points; closed chains repeat
/// the first point at the end). Returns `n + 1` kinds for an open chain, `n` for a closed one.
///
/// ```
/// use kurbo::Point;
/// use splineskin_core::drawing::{classify_joints, JointKind, JunctionOptions};
/// // Two curves meeting smoothly (collinear tangents of different lengths) at (3, 0).
/// let pts = [(0.0, 0.0), (1.0, 1.0), (2.0, 0.0), (3.0, 0.0), (5.0, 0.0), (6.0, 1.0), (7.0, 0.0)]
///     .map(Point::from);
/// let kinds = classify_joints(&pts, false, &JunctionOptions::default());
/// assert_eq!(kinds, vec![JointKind::End, JointKind::G1, JointKind::End]);
/// ```
pub fn classify_joints(
    points: &[Point],
    closed: bool,
    options: &JunctionOptions,
) -> Vec<JointKind> {
    let n = (points.len() - 1) / 3;
    let eps = coincidence_distance(points, options.coincidence);
    let count = if closed { n } else { n + 1 };
    (0..count)
        .map(|k| {
            let p = 3 * k;
            if !closed && (k == 0 || k == n) {
                return JointKind::End;
            }
            let (prev, next) = tangent_neighbours(points, closed, p, eps);
            let (Some(a), Some(b)) = (prev, next) else {
                return JointKind::C0;
            };
            let u = points[p] - points[a];
            let v = points[b] - points[p];
            let theta = angle_between(u, v);
            if input_satisfies(JointKind::C1, u, v, options) {
                JointKind::C1
            } else if input_satisfies(JointKind::G1, u, v, options) {
                JointKind::G1
            } else if options.keep_right_angles
                && (theta - std::f64::consts::FRAC_PI_2).abs() <= options.right_angle
            {
                JointKind::FixedAngle
            } else {
                JointKind::C0
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support::{pts, CLOSED_TWO_CURVES, STACKED_HANDLES};

    /// The kind of the junction (point 3) of two open curves with control points `p`
    /// (points 0–3 and 3–6), under the default options.
    fn middle_joint(p: &[(f64, f64)]) -> JointKind {
        classify_joints(&pts(p), false, &JunctionOptions::default())[1]
    }

    #[test]
    fn junction_corner_is_c0() {
        let corner = [
            (0., 0.),
            (1., 0.),
            (2., 0.),
            (3., 0.),
            (4., 1.),
            (5., 2.),
            (6., 3.),
        ];
        assert_eq!(middle_joint(&corner), JointKind::C0);
    }

    #[test]
    fn junction_equal_collinear_tangents_are_c1() {
        let smooth = crate::test_support::SMOOTH_C1;
        assert_eq!(middle_joint(&smooth), JointKind::C1);
    }

    #[test]
    fn junction_right_angle_is_fixed_unless_disabled() {
        let p = pts(&[
            (0., 0.),
            (1., 0.),
            (2., 0.),
            (3., 0.),
            (3., 1.),
            (3., 2.),
            (3., 3.),
        ]);
        let k = classify_joints(&p, false, &JunctionOptions::default());
        assert_eq!(k[1], JointKind::FixedAngle);
        let o = JunctionOptions::default().with_keep_right_angles(false);
        assert_eq!(classify_joints(&p, false, &o)[1], JointKind::C0);
    }

    #[test]
    fn junction_degenerate_tangent_uses_next_distinct_point() {
        // c2 on top of c3, d1 on top of d0: directions come from c1 and d2.
        assert_eq!(middle_joint(&STACKED_HANDLES), JointKind::G1);
    }

    #[test]
    fn junction_without_any_direction_is_c0() {
        // The second curve is a single point.
        let collapsed = [
            (0., 0.),
            (1., 0.),
            (2., 0.),
            (3., 0.),
            (3., 0.),
            (3., 0.),
            (3., 0.),
        ];
        assert_eq!(middle_joint(&collapsed), JointKind::C0);
    }

    #[test]
    fn junction_closed_chain_classifies_the_closing_point() {
        // A circle-like closed chain of two curves, smooth everywhere.
        let k = classify_joints(&pts(&CLOSED_TWO_CURVES), true, &JunctionOptions::default());
        assert_eq!(k, vec![JointKind::C1, JointKind::C1]);
    }
}
