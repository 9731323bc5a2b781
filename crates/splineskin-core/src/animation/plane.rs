//! Maps of the plane split into parts for interpolation.
//!
//! **Decomposition** (translate · rotate · scale · shear about the handle's pivot `c`). A map
//! `T(x) = A x + t` with invertible linear part `A` (SVG coefficients `a b c d e f`, columns
//! `(a, b)` and `(c, d)`) is written
//!
//! ```text
//! T(x) = q + R(θ) · diag(s_x, s_y) · [[1, k], [0, 1]] · (x − c)
//!
//! q   = T(c)                                  where the pivot goes
//! s_x = |(a, b)| > 0,  θ = atan2(b, a)        length and angle of the first column
//! s_y = det A / s_x                           negative iff A reflects
//! k   = ((a, b) · (c, d)) / s_x²              shear
//! ```
//!
//! It is exact (a QR factorisation of `A`): `compose(decompose(T)) = T` up to rounding.
//! **Reflections** are carried by the sign of `s_y` (a flip across the rotated first axis);
//! `s_x` and `θ` are those of the first column as for any map.
//!
//! **Interpolation** between keyframes `(t₀, T₀)` and `(t₁, T₁)` at `u = e((t − t₀)/(t₁ − t₀))`,
//! `e` the first keyframe's [`Easing`](super::Easing):
//!
//! ```text
//! q(u)   = (1 − u) q₀ + u q₁                          linear
//! θ(u)   = θ₀ + u Δ,  Δ = θ₁ − θ₀ wrapped to (−π, π]   shortest arc (a half turn goes +π)
//! s_x(u) = s_x₀ (s_x₁ / s_x₀)^u                        geometric
//! s_y(u) = s_y₀ (s_y₁ / s_y₀)^u  if s_y₀ s_y₁ > 0      geometric;
//!          (1 − u) s_y₀ + u s_y₁ otherwise             linear through 0 when a reflection
//!                                                      starts or ends (the drawing turns over)
//! k(u)   = (1 − u) k₀ + u k₁                          linear
//! ```

use kurbo::{Affine, Point, Vec2};

/// An affine map split about a pivot `c`: `T(x) = q + R(θ) · diag(s_x, s_y) · [[1, k], [0, 1]] ·
/// (x − c)` (module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AffineParts {
    /// `q = T(c)`: where the pivot goes.
    pub pivot_image: Point,
    /// `θ`, radians in `(−π, π]`: the angle of the first column (SVG's y-down frame: positive
    /// turns x towards y, clockwise on screen).
    pub angle: f64,
    /// `(s_x, s_y)`: `s_x > 0`; `s_y < 0` for a reflection.
    pub scale: Vec2,
    /// `k`: the shear of the second axis along the first, applied before scaling.
    pub shear: f64,
}

impl AffineParts {
    /// Splits `map` about `pivot`; `None` if `map` is not finite or its linear part is
    /// singular.
    ///
    /// ```
    /// use kurbo::{Affine, Point, Vec2};
    /// use splineskin_core::animation::AffineParts;
    /// let c = Point::new(3.0, 4.0);
    /// // Scale by (2, −1) (a reflection), turn by 0.5 rad about c, then move by (1, 0).
    /// let map = Affine::translate(c.to_vec2() + Vec2::new(1.0, 0.0))
    ///     * Affine::rotate(0.5)
    ///     * Affine::scale_non_uniform(2.0, -1.0)
    ///     * Affine::translate(-c.to_vec2());
    /// let parts = AffineParts::decompose(map, c).unwrap();
    /// assert!((parts.angle - 0.5).abs() < 1e-15);
    /// assert!((parts.scale - Vec2::new(2.0, -1.0)).hypot() < 1e-15);
    /// assert!(parts.shear.abs() < 1e-15);
    /// assert!((parts.pivot_image - Point::new(4.0, 4.0)).hypot() < 1e-14);
    /// let back = parts.compose(c);
    /// for (g, w) in back.as_coeffs().iter().zip(map.as_coeffs()) {
    ///     assert!((g - w).abs() < 1e-14);
    /// }
    /// assert!(AffineParts::decompose(Affine::scale_non_uniform(1.0, 0.0), c).is_none());
    /// ```
    pub fn decompose(map: Affine, pivot: Point) -> Option<AffineParts> {
        let coeffs = map.as_coeffs();
        if !coeffs.iter().all(|v| v.is_finite()) {
            return None;
        }
        let [a, b, c, d, _, _] = coeffs;
        let det = a * d - b * c;
        let sx = a.hypot(b);
        if !(det != 0.0 && det.is_finite() && sx > 0.0) {
            return None;
        }
        let (cos, sin) = (a / sx, b / sx);
        // Rᵀ · (c, d) = (s_x k, s_y).
        let along = cos * c + sin * d;
        let across = -sin * c + cos * d;
        Some(AffineParts {
            pivot_image: map * pivot,
            angle: b.atan2(a),
            scale: Vec2::new(sx, across),
            shear: along / sx,
        })
    }

    /// The map `x ↦ q + R(θ) · diag(s_x, s_y) · [[1, k], [0, 1]] · (x − pivot)`.
    pub fn compose(&self, pivot: Point) -> Affine {
        let (sin, cos) = self.angle.sin_cos();
        let (sx, sy, k) = (self.scale.x, self.scale.y, self.shear);
        // Columns of R · [[s_x, s_x k], [0, s_y]].
        let (a, b) = (cos * sx, sin * sx);
        let (c, d) = (cos * sx * k - sin * sy, sin * sx * k + cos * sy);
        let linear = Affine::new([a, b, c, d, 0.0, 0.0]);
        let moved = linear * pivot;
        Affine::new([
            a,
            b,
            c,
            d,
            self.pivot_image.x - moved.x,
            self.pivot_image.y - moved.y,
        ])
    }

    /// The parts at fraction `u` from `self` (`u = 0`) to `other` (`u = 1`), by the module
    /// doc's rules: pivot image and shear linear, angle along the shortest arc, scales
    /// geometric (`s_y` linear when its sign changes). `u = 0` and `u = 1` return `self` and
    /// `other` exactly.
    pub fn interpolate(&self, other: &AffineParts, u: f64) -> AffineParts {
        if u == 0.0 {
            return *self;
        }
        if u == 1.0 {
            return *other;
        }
        let lerp = |x: f64, y: f64| x + u * (y - x);
        let geometric = |x: f64, y: f64| x * (y / x).powf(u);
        AffineParts {
            pivot_image: self.pivot_image.lerp(other.pivot_image, u),
            angle: self.angle + u * shortest_turn(self.angle, other.angle),
            scale: Vec2::new(
                geometric(self.scale.x, other.scale.x),
                if self.scale.y * other.scale.y > 0.0 {
                    geometric(self.scale.y, other.scale.y)
                } else {
                    lerp(self.scale.y, other.scale.y)
                },
            ),
            shear: lerp(self.shear, other.shear),
        }
    }
}

/// `to − from` wrapped to `(−π, π]`, radians: the shortest turn, a half turn counted positive.
///
/// ```
/// use std::f64::consts::PI;
/// use splineskin_core::animation::shortest_turn;
/// assert!((shortest_turn(0.9 * PI, -0.9 * PI) - 0.2 * PI).abs() < 1e-15);
/// assert_eq!(shortest_turn(0.0, PI), PI);
/// assert_eq!(shortest_turn(0.0, -PI), PI);
/// ```
pub fn shortest_turn(from: f64, to: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    PI - (PI - (to - from)).rem_euclid(TAU)
}

/// Interpolates one map: [`AffineParts::decompose`] both about `pivot`, interpolate at `u`,
/// compose. `None` if either map is singular. Exact at `u = 0` and `u = 1`.
pub fn interpolate_map(from: Affine, to: Affine, pivot: Point, u: f64) -> Option<Affine> {
    if u == 0.0 {
        return Some(from);
    }
    if u == 1.0 {
        return Some(to);
    }
    let p0 = AffineParts::decompose(from, pivot)?;
    let p1 = AffineParts::decompose(to, pivot)?;
    Some(p0.interpolate(&p1, u).compose(pivot))
}

impl super::KeyMap for Affine {
    type Point = Point;
    type Parts = AffineParts;
    const IDENTITY: Affine = Affine::IDENTITY;

    fn split(self, pivot: Point) -> Option<AffineParts> {
        AffineParts::decompose(self, pivot)
    }

    fn join(parts: &AffineParts, pivot: Point) -> Affine {
        parts.compose(pivot)
    }

    fn blend(from: &AffineParts, to: &AffineParts, u: f64) -> AffineParts {
        from.interpolate(to, u)
    }

    fn coefficients(&self) -> Vec<f64> {
        self.as_coeffs().to_vec()
    }
}
