//! SMIL animation of what follows the deformation in an animated SVG
//! ([`crate::svg_animate::write_animated_svg_following`]): an affine map per frame written as
//! `animateTransform` elements, and a number per frame (a marker's `orient`, a stroke width) as
//! an `animate`.
//!
//! # An affine map as parts SMIL can animate
//!
//! `animateTransform` has `translate`, `scale`, `rotate`, `skewX` and `skewY` types but no
//! `matrix`, so each frame's map is decomposed ([`AffineParts::of`]):
//!
//! ```text
//! A = T(tx, ty) · R(θ) · SkewX(φ) · S(sx, sy)
//!
//!     ⎡a c e⎤   ⎡1 0 tx⎤ ⎡cos θ −sin θ 0⎤ ⎡1 tan φ 0⎤ ⎡sx 0  0⎤
//!     ⎢b d f⎥ = ⎢0 1 ty⎥ ⎢sin θ  cos θ 0⎥ ⎢0   1   0⎥ ⎢0  sy 0⎥
//!     ⎣0 0 1⎦   ⎣0 0  1⎦ ⎣  0      0   1⎦ ⎣0   0   1⎦ ⎣0  0  1⎦
//! ```
//!
//! (`a b c d e f` as in SVG's `matrix(a b c d e f)` and kurbo's `Affine`). The linear part is
//! `R·SkewX·S`, whose first column is `sx (cos θ, sin θ)` and whose second is
//! `sy (tan φ (cos θ, sin θ) + (−sin θ, cos θ))`; hence, with `det = ad − bc`:
//!
//! ```text
//! tx = e,  ty = f,  sx = √(a² + b²),  θ = atan2(b, a),
//! sy = det / sx,  tan φ = (ac + bd) / det
//! ```
//!
//! (the QR factorisation of the linear part: `R` its orthogonal factor, `SkewX·S` its upper
//! triangular one). `sx > 0`; a reflection (`det < 0`) gives `sy < 0`. A singular map
//! (`det = 0`: the element collapsed onto a line) is written with `sy = 0` and `φ = 0`, and a
//! map whose first column is zero with `sx = 0`, `φ = 0`, `θ` turning `(0, 1)` onto its second
//! column: either way a non-invertible transform, which SVG does not render, as it does not
//! render the element under the singular map itself.
//!
//! **Continuity.** Browsers interpolate each `animateTransform`'s values linearly between
//! key times, so `θ` must not jump by `2π` between frames (a jump from 179° to −179° would
//! spin the element through a full turn in between): each frame's angle is the one of
//! `θ + 2πk` nearest the previous frame's ([`unwrap_angle`]). The other parts are continuous
//! wherever the map is (and `φ` wherever `det ≠ 0`).
//!
//! # How the elements compose
//!
//! An `animateTransform` with `additive="sum"` multiplies its value onto the right of what is
//! below it; one with `additive="replace"` discards the underlying value. The four elements
//! are written in the order `translate` (replace), `rotate`, `skewX`, `scale` (each sum), so
//! the animated value is exactly `T·R·SkewX·S = A_f`, whatever the attribute holds. The
//! attribute itself keeps the first frame's `matrix(A₀)` (so a renderer without SMIL, such as
//! resvg, shows the first frame, as for the paths' `d`), and any transform that was on the
//! element before is part of each `A_f` (the caller composes it in: a text's own `transform`
//! on the right, a gradient's `gradientTransform` on the right), not left on the attribute to
//! be summed onto, since a sum would put it on the wrong side.

use std::fmt::Write as _;

use kurbo::{Affine, Vec2};

/// A map `T(translate) · R(rotate) · SkewX(skew_x) · S(scale)` (module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AffineParts {
    /// `(tx, ty)`.
    pub translate: Vec2,
    /// `θ`, radians, counter-clockwise in a y-up frame (clockwise on screen, as SVG's
    /// `rotate`).
    pub rotate: f64,
    /// `φ`, radians, in `(−π/2, π/2)`.
    pub skew_x: f64,
    /// `(sx, sy)`: `sx ≥ 0`, `sy` negative for a reflection.
    pub scale: Vec2,
}

impl AffineParts {
    /// The decomposition of `a` (module doc: formula, singular maps). `θ` in `(−π, π]`.
    ///
    /// ```
    /// use kurbo::Affine;
    /// use splineskin_svg::smil::AffineParts;
    /// let a = Affine::new([0.5, 1.2, -0.7, 0.9, 3.0, -4.0]);
    /// let parts = AffineParts::of(a);
    /// let back = parts.to_affine();
    /// for (x, y) in back.as_coeffs().iter().zip(a.as_coeffs()) {
    ///     assert!((x - y).abs() < 1e-14);
    /// }
    /// ```
    pub fn of(a: Affine) -> AffineParts {
        let [a, b, c, d, e, f] = a.as_coeffs();
        let translate = Vec2::new(e, f);
        let sx = a.hypot(b);
        if sx == 0.0 {
            // First column zero: (0, 1) turned onto the second column, sy its length.
            let sy = c.hypot(d);
            let rotate = if sy == 0.0 { 0.0 } else { (-c).atan2(d) };
            return AffineParts {
                translate,
                rotate,
                skew_x: 0.0,
                scale: Vec2::new(0.0, sy),
            };
        }
        let det = a * d - b * c;
        let rotate = b.atan2(a);
        let (sy, skew_x) = if det == 0.0 {
            (0.0, 0.0)
        } else {
            (det / sx, ((a * c + b * d) / det).atan())
        };
        AffineParts {
            translate,
            rotate,
            skew_x,
            scale: Vec2::new(sx, sy),
        }
    }

    /// The map `T·R·SkewX·S` of these parts.
    pub fn to_affine(&self) -> Affine {
        Affine::translate(self.translate)
            * Affine::rotate(self.rotate)
            * Affine::skew(self.skew_x.tan(), 0.0)
            * Affine::scale_non_uniform(self.scale.x, self.scale.y)
    }
}

/// The angle `angle + 2πk` (radians, `k` an integer) nearest `previous`: consecutive angles of
/// an animation made continuous (module doc).
///
/// ```
/// use splineskin_svg::smil::unwrap_angle;
/// let (a, b) = (179f64.to_radians(), -179f64.to_radians());
/// assert!((unwrap_angle(a, b) - 181f64.to_radians()).abs() < 1e-12);
/// assert_eq!(unwrap_angle(0.0, 0.25), 0.25);
/// ```
pub fn unwrap_angle(previous: f64, angle: f64) -> f64 {
    let tau = std::f64::consts::TAU;
    let step = angle - previous;
    previous + (step - tau * (step / tau).round())
}

/// `angles` (radians) each replaced by [`unwrap_angle`] of the previous result.
pub fn unwrap_angles(angles: &mut [f64]) {
    for f in 1..angles.len() {
        angles[f] = unwrap_angle(angles[f - 1], angles[f]);
    }
}

/// The attributes every animation element of one animated document shares: its duration, loop
/// and key times (`keyTimes` one per frame, as the paths' `d` animation).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Timing {
    /// ` dur="…s" repeatCount="indefinite" calcMode="linear" keyTimes="…"`.
    pub(crate) attributes: String,
    /// Number of frames.
    pub(crate) n_frames: usize,
}

/// Appends `<animateTransform …/>` elements animating attribute `attribute` through `maps`
/// (one per frame) as `translate` (replace), `rotate`, `skewX`, `scale` (sum) (module doc).
/// `target`: the id of the element animated when the elements are not its children (`href`).
pub(crate) fn push_animate_transform(
    out: &mut String,
    attribute: &str,
    maps: &[Affine],
    timing: &Timing,
    target: Option<&str>,
) {
    let mut parts: Vec<AffineParts> = maps.iter().map(|&m| AffineParts::of(m)).collect();
    let mut angles: Vec<f64> = parts.iter().map(|p| p.rotate).collect();
    unwrap_angles(&mut angles);
    for (p, a) in parts.iter_mut().zip(angles) {
        p.rotate = a;
    }
    // (type, additive, the frame's value: one number, or two).
    type Part = fn(&AffineParts) -> (f64, Option<f64>);
    let kinds: [(&str, &str, Part); 4] = [
        ("translate", "replace", |p| {
            (p.translate.x, Some(p.translate.y))
        }),
        ("rotate", "sum", |p| (p.rotate.to_degrees(), None)),
        ("skewX", "sum", |p| (p.skew_x.to_degrees(), None)),
        ("scale", "sum", |p| (p.scale.x, Some(p.scale.y))),
    ];
    for (kind, additive, value) in kinds {
        out.push_str("<animateTransform");
        if let Some(id) = target {
            let _ = write!(out, " href=\"#{id}\"");
        }
        let _ = write!(
            out,
            " attributeName=\"{attribute}\" type=\"{kind}\" additive=\"{additive}\"{} values=\"",
            timing.attributes
        );
        for (f, p) in parts.iter().enumerate() {
            if f > 0 {
                out.push(';');
            }
            let (x, y) = value(p);
            crate::document::push_number(out, x);
            if let Some(y) = y {
                out.push(' ');
                crate::document::push_number(out, y);
            }
        }
        out.push_str("\"/>");
    }
}

/// Appends `<animate attributeName="attribute" … values="v₀;v₁;…"/>` (one value per frame).
pub(crate) fn push_animate(out: &mut String, attribute: &str, values: &[f64], timing: &Timing) {
    let _ = write!(
        out,
        "<animate attributeName=\"{attribute}\"{} values=\"",
        timing.attributes
    );
    for (f, &v) in values.iter().enumerate() {
        if f > 0 {
            out.push(';');
        }
        crate::document::push_number(out, v);
    }
    out.push_str("\"/>");
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Affine, b: Affine, tolerance: f64) -> bool {
        let scale = b.as_coeffs().iter().fold(1.0f64, |m, v| m.max(v.abs()));
        a.as_coeffs()
            .iter()
            .zip(b.as_coeffs())
            .all(|(x, y)| (x - y).abs() <= tolerance * scale)
    }

    #[test]
    fn affine_parts_recompose_every_kind_of_map() {
        let maps = [
            Affine::IDENTITY,
            Affine::rotate(3.0),
            Affine::rotate(-3.1) * Affine::scale_non_uniform(2.0, 0.5),
            Affine::new([0.5, 1.2, -0.7, 0.9, 3.0, -4.0]),
            // A reflection, a shear, a tiny and a huge scale far from the origin.
            Affine::new([1.0, 0.0, 0.0, -1.0, 0.0, 0.0]),
            Affine::skew(0.8, 0.3),
            Affine::translate((1e6, -2e6)) * Affine::rotate(1.0) * Affine::scale(1e-6),
            Affine::translate((1e-3, 5.0)) * Affine::rotate(-2.0) * Affine::scale(1e6),
        ];
        for a in maps {
            let p = AffineParts::of(a);
            assert!(close(p.to_affine(), a, 1e-14), "{a:?}: {p:?}");
            assert!(p.scale.x >= 0.0 && p.skew_x.abs() < std::f64::consts::FRAC_PI_2);
        }
        // Known parts come back.
        let p = AffineParts {
            translate: Vec2::new(2.0, -1.0),
            rotate: 0.7,
            skew_x: -0.4,
            scale: Vec2::new(1.5, -0.25),
        };
        let q = AffineParts::of(p.to_affine());
        assert!((q.translate - p.translate).hypot() < 1e-15);
        for (x, y) in [
            (q.rotate, p.rotate),
            (q.skew_x, p.skew_x),
            (q.scale.x, p.scale.x),
            (q.scale.y, p.scale.y),
        ] {
            assert!((x - y).abs() < 1e-14, "{q:?} vs {p:?}");
        }
    }

    #[test]
    fn affine_parts_of_singular_maps_are_singular() {
        // Collapsed onto a line: the second column along the first.
        let line = Affine::new([2.0, 1.0, 4.0, 2.0, 1.0, 1.0]);
        let p = AffineParts::of(line);
        assert_eq!(p.scale.y, 0.0);
        assert_eq!(p.to_affine().determinant(), 0.0);
        // First column zero: exact.
        let a = Affine::new([0.0, 0.0, -3.0, 4.0, 0.0, 0.0]);
        assert!(close(AffineParts::of(a).to_affine(), a, 1e-15));
        let zero = Affine::new([0.0; 6]);
        assert_eq!(AffineParts::of(zero).to_affine().as_coeffs()[..4], [0.0; 4]);
    }

    #[test]
    fn unwrap_angles_turns_continuously_past_a_full_turn() {
        // 0°, 50°, …, 500°: atan2 gives them in (−180°, 180°]; unwrapped they come back.
        let truth: Vec<f64> = (0..11).map(|k| (50.0 * k as f64).to_radians()).collect();
        let mut wrapped: Vec<f64> = truth.iter().map(|&t| t.sin().atan2(t.cos())).collect();
        assert!(wrapped.iter().any(|&w| w < 0.0));
        unwrap_angles(&mut wrapped);
        for (u, t) in wrapped.iter().zip(&truth) {
            assert!((u - t).abs() < 1e-12, "{u} vs {t}");
        }
    }
}
