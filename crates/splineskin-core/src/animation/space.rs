//! Maps of space split into parts for interpolation.
//!
//! A map is a 3 × 4 matrix `[[a, b, c, d], [e, f, g, h], [i, j, k, l]]` sending `x` to
//! `A x + t` (rows of `A` then `t`), as Catmull–Clark scenes write handle poses.
//!
//! **Decomposition** about the handle's pivot `c`, by the polar decomposition of `A`
//! (Shoemake & Duff 1992, "Matrix animation and polar decomposition"):
//!
//! ```text
//! T(x) = q + R · S · (x − c)
//!
//! q = T(c)                     where the pivot goes
//! A = U P                      U orthogonal, P symmetric positive definite (Newton's iteration
//!                              U ← (γ U + γ⁻¹ U⁻ᵀ) / 2, γ = (‖U⁻¹‖ / ‖U‖)^½, Higham 1986)
//! R = σ U,  σ = sign(det A)    a proper rotation (det R = +1), kept as a unit quaternion
//! S = Rᵀ A                     the stretch: P, negated when A reflects (σ = −1)
//! ```
//!
//! `compose(decompose(T)) = T` up to rounding. **Interpolation** at fraction `u`:
//!
//! ```text
//! q(u) = (1 − u) q₀ + u q₁      linear
//! R(u) = slerp(R₀, R₁, u)       along the shortest arc (the quaternions' sign chosen so)
//! S(u) = (1 − u) S₀ + u S₁      linear, entry by entry (through 0 when a reflection starts or
//!                               ends: the shape turns inside out)
//! ```
//!
//! A rigid map stays rigid (`S = I` at both ends), a rotation about the pivot stays one, a
//! translation stays a translation. At `u = 0` and `u = 1` the ends are returned exactly.

use crate::mesh::vec3::{cross, dot, quaternion_rotation, Point3};

/// A 3 × 4 map of space: `[[a, b, c, d], [e, f, g, h], [i, j, k, l]]`, `x ↦ A x + t`.
type Map3 = [[f64; 4]; 3];
/// A 3 × 3 matrix, rows.
type Mat3 = [[f64; 3]; 3];

/// Most Newton steps of the polar decomposition: it converges quadratically, in well under 20
/// steps for any condition number `f64` can hold.
const POLAR_MAX_STEPS: usize = 40;

/// A map of space split about a pivot `c`: `T(x) = q + R · S · (x − c)` (module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpaceParts {
    /// `q = T(c)`: where the pivot goes.
    pub pivot_image: Point3,
    /// `R` as a unit quaternion `[w, x, y, z]`.
    pub rotation: [f64; 4],
    /// `S = Rᵀ A`, rows: symmetric up to rounding; negative definite for a reflection.
    pub stretch: Mat3,
}

impl SpaceParts {
    /// Splits `map` about `pivot`; `None` if `map` is not finite or its linear part is
    /// singular.
    ///
    /// ```
    /// use splineskin_core::animation::SpaceParts;
    /// // A quarter turn about z, scaled by 2, about the pivot (1, 0, 0).
    /// let map = [[0.0, -2.0, 0.0, 1.0], [2.0, 0.0, 0.0, -2.0], [0.0, 0.0, 2.0, 0.0]];
    /// let parts = SpaceParts::decompose(&map, [1.0, 0.0, 0.0]).unwrap();
    /// let h = std::f64::consts::FRAC_1_SQRT_2;
    /// assert!(parts.rotation.iter().zip([h, 0.0, 0.0, h]).all(|(a, b)| (a - b).abs() < 1e-15));
    /// assert!((parts.stretch[1][1] - 2.0).abs() < 1e-15);
    /// assert_eq!(parts.pivot_image, [1.0, 0.0, 0.0]);
    /// let back = parts.compose([1.0, 0.0, 0.0]);
    /// assert!(back.iter().flatten().zip(map.iter().flatten()).all(|(a, b)| (a - b).abs() < 1e-14));
    /// ```
    pub fn decompose(map: &Map3, pivot: Point3) -> Option<SpaceParts> {
        if !map.iter().flatten().all(|v| v.is_finite()) {
            return None;
        }
        let a = linear_part(map);
        let det = det3(&a);
        if !(det != 0.0 && det.is_finite()) {
            return None;
        }
        let mut r = polar_orthogonal(&a)?;
        if det < 0.0 {
            r = r.map(|row| row.map(|v| -v));
        }
        let stretch = mul3(&transpose3(&r), &a);
        Some(SpaceParts {
            pivot_image: apply(map, pivot),
            rotation: quaternion_of(&r),
            stretch,
        })
    }

    /// The map `x ↦ q + R · S · (x − pivot)`.
    pub fn compose(&self, pivot: Point3) -> Map3 {
        let a = mul3(&quaternion_rotation(self.rotation), &self.stretch);
        let mut map = [[0.0; 4]; 3];
        for i in 0..3 {
            map[i][..3].copy_from_slice(&a[i]);
            map[i][3] = self.pivot_image[i] - dot(a[i], pivot);
        }
        map
    }

    /// The parts at fraction `u` from `self` (`u = 0`) to `other` (`u = 1`), by the module
    /// doc's rules. `u = 0` and `u = 1` return `self` and `other` exactly.
    pub fn interpolate(&self, other: &SpaceParts, u: f64) -> SpaceParts {
        if u == 0.0 {
            return *self;
        }
        if u == 1.0 {
            return *other;
        }
        let lerp = |x: f64, y: f64| x + u * (y - x);
        let mut stretch = [[0.0; 3]; 3];
        for (i, row) in stretch.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = lerp(self.stretch[i][j], other.stretch[i][j]);
            }
        }
        SpaceParts {
            pivot_image: std::array::from_fn(|i| lerp(self.pivot_image[i], other.pivot_image[i])),
            rotation: slerp(self.rotation, other.rotation, u),
            stretch,
        }
    }
}

impl super::KeyMap for Map3 {
    type Point = Point3;
    type Parts = SpaceParts;
    const IDENTITY: Map3 = [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
    ];

    fn split(self, pivot: Point3) -> Option<SpaceParts> {
        SpaceParts::decompose(&self, pivot)
    }

    fn join(parts: &SpaceParts, pivot: Point3) -> Map3 {
        parts.compose(pivot)
    }

    fn blend(from: &SpaceParts, to: &SpaceParts, u: f64) -> SpaceParts {
        from.interpolate(to, u)
    }

    fn coefficients(&self) -> Vec<f64> {
        self.iter().flatten().copied().collect()
    }
}

fn linear_part(map: &Map3) -> Mat3 {
    map.map(|row| [row[0], row[1], row[2]])
}

fn apply(map: &Map3, p: Point3) -> Point3 {
    map.map(|row| row[0] * p[0] + row[1] * p[1] + row[2] * p[2] + row[3])
}

fn det3(a: &Mat3) -> f64 {
    dot(a[0], cross(a[1], a[2]))
}

fn transpose3(a: &Mat3) -> Mat3 {
    std::array::from_fn(|i| std::array::from_fn(|j| a[j][i]))
}

fn mul3(a: &Mat3, b: &Mat3) -> Mat3 {
    std::array::from_fn(|i| std::array::from_fn(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

fn frobenius(a: &Mat3) -> f64 {
    a.iter().flatten().map(|v| v * v).sum::<f64>().sqrt()
}

/// `U` of the polar decomposition `A = U P` by scaled Newton steps (module doc); `None` if a
/// step meets a singular or non-finite matrix.
fn polar_orthogonal(a: &Mat3) -> Option<Mat3> {
    let mut u = *a;
    for _ in 0..POLAR_MAX_STEPS {
        let det = det3(&u);
        if !(det != 0.0 && det.is_finite()) {
            return None;
        }
        // U⁻ᵀ = cofactor(U) / det U; the cofactor rows are the cross products of U's rows.
        let inv_t = [
            cross(u[1], u[2]).map(|v| v / det),
            cross(u[2], u[0]).map(|v| v / det),
            cross(u[0], u[1]).map(|v| v / det),
        ];
        let gamma = (frobenius(&inv_t) / frobenius(&u)).sqrt();
        let next: Mat3 = std::array::from_fn(|i| {
            std::array::from_fn(|j| 0.5 * (gamma * u[i][j] + inv_t[i][j] / gamma))
        });
        let step: f64 = (0..3)
            .flat_map(|i| (0..3).map(move |j| (i, j)))
            .map(|(i, j)| (next[i][j] - u[i][j]).abs())
            .fold(0.0, f64::max);
        u = next;
        if step <= 4.0 * f64::EPSILON {
            break;
        }
    }
    Some(u)
}

/// The unit quaternion `[w, x, y, z]` of a rotation matrix (Shepperd's method: the largest of
/// `w², x², y², z²` is taken from the diagonal, the rest from off-diagonal sums).
fn quaternion_of(r: &Mat3) -> [f64; 4] {
    let trace = r[0][0] + r[1][1] + r[2][2];
    let q = if trace >= r[0][0].max(r[1][1]).max(r[2][2]) {
        let w = 0.5 * (1.0 + trace).sqrt();
        let f = 0.25 / w;
        [
            w,
            (r[2][1] - r[1][2]) * f,
            (r[0][2] - r[2][0]) * f,
            (r[1][0] - r[0][1]) * f,
        ]
    } else if r[0][0] >= r[1][1] && r[0][0] >= r[2][2] {
        let x = 0.5 * (1.0 + r[0][0] - r[1][1] - r[2][2]).sqrt();
        let f = 0.25 / x;
        [
            (r[2][1] - r[1][2]) * f,
            x,
            (r[0][1] + r[1][0]) * f,
            (r[0][2] + r[2][0]) * f,
        ]
    } else if r[1][1] >= r[2][2] {
        let y = 0.5 * (1.0 - r[0][0] + r[1][1] - r[2][2]).sqrt();
        let f = 0.25 / y;
        [
            (r[0][2] - r[2][0]) * f,
            (r[0][1] + r[1][0]) * f,
            y,
            (r[1][2] + r[2][1]) * f,
        ]
    } else {
        let z = 0.5 * (1.0 - r[0][0] - r[1][1] + r[2][2]).sqrt();
        let f = 0.25 / z;
        [
            (r[1][0] - r[0][1]) * f,
            (r[0][2] + r[2][0]) * f,
            (r[1][2] + r[2][1]) * f,
            z,
        ]
    };
    let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    q.map(|v| v / n)
}

/// Spherical interpolation of unit quaternions along the shorter arc.
fn slerp(a: [f64; 4], b: [f64; 4], u: f64) -> [f64; 4] {
    let mut cos = a.iter().zip(&b).map(|(x, y)| x * y).sum::<f64>();
    let b = if cos < 0.0 {
        cos = -cos;
        b.map(|v| -v)
    } else {
        b
    };
    let (wa, wb) = if cos > 1.0 - 1e-12 {
        // Nearly the same rotation: the chord is the arc to rounding.
        (1.0 - u, u)
    } else {
        let angle = cos.min(1.0).acos();
        let sin = angle.sin();
        (((1.0 - u) * angle).sin() / sin, (u * angle).sin() / sin)
    };
    let q: [f64; 4] = std::array::from_fn(|i| wa * a[i] + wb * b[i]);
    let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    q.map(|v| v / n)
}

#[cfg(test)]
mod tests {
    use super::super::KeyMap;
    use super::*;

    fn axis_angle(axis: Point3, angle: f64) -> Mat3 {
        let n = dot(axis, axis).sqrt();
        let (s, c) = (angle * 0.5).sin_cos();
        quaternion_rotation([c, s * axis[0] / n, s * axis[1] / n, s * axis[2] / n])
    }

    fn about(pivot: Point3, a: &Mat3, shift: Point3) -> Map3 {
        std::array::from_fn(|i| {
            let mut row = [a[i][0], a[i][1], a[i][2], 0.0];
            row[3] = pivot[i] + shift[i] - dot(a[i], pivot);
            row
        })
    }

    fn close(a: &Map3, b: &Map3, tol: f64) -> bool {
        a.iter()
            .flatten()
            .zip(b.iter().flatten())
            .all(|(x, y)| (x - y).abs() <= tol)
    }

    #[test]
    fn decompose_compose_round_trips_rotations_scales_shears_and_reflections() {
        let c = [0.3, -1.2, 2.5];
        let r = axis_angle([1.0, 2.0, -0.5], 2.4);
        let shear = [[1.5, 0.4, 0.0], [0.0, 0.7, -0.3], [0.2, 0.0, 2.0]];
        let mirror = [[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        for a in [r, mul3(&r, &shear), mul3(&mirror, &mul3(&r, &shear))] {
            let map = about(c, &a, [4.0, 5.0, -6.0]);
            let parts = SpaceParts::decompose(&map, c).unwrap();
            let back = parts.compose(c);
            assert!(close(&back, &map, 1e-13), "{back:?} vs {map:?}");
            let rot = quaternion_rotation(parts.rotation);
            assert!((det3(&rot) - 1.0).abs() < 1e-14);
            // The stretch is symmetric: R is the polar factor, not any orthogonal one.
            let s = parts.stretch;
            assert!((s[0][1] - s[1][0]).abs() < 1e-13 && (s[0][2] - s[2][0]).abs() < 1e-13);
        }
        let flat = [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 0.0, 0.0],
        ];
        assert!(SpaceParts::decompose(&flat, c).is_none());
        let nan = [
            [f64::NAN, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
        ];
        assert!(SpaceParts::decompose(&nan, c).is_none());
    }

    #[test]
    fn halfway_between_rotations_about_the_pivot_is_the_half_rotation() {
        let c = [1.0, 2.0, 3.0];
        let axis = [0.0, 1.0, 1.0];
        let from = about(c, &axis_angle(axis, 0.2), [0.0; 3]);
        let to = about(c, &axis_angle(axis, 2.6), [2.0, 0.0, 0.0]);
        let (p0, p1) = (from.split(c).unwrap(), to.split(c).unwrap());
        let mid = Map3::join(&Map3::blend(&p0, &p1, 0.5), c);
        let want = about(c, &axis_angle(axis, 1.4), [1.0, 0.0, 0.0]);
        assert!(close(&mid, &want, 1e-14), "{mid:?}");
        // The ends exactly.
        assert_eq!(Map3::blend(&p0, &p1, 0.0), p0);
        assert_eq!(Map3::blend(&p0, &p1, 1.0), p1);
    }

    #[test]
    fn the_shorter_arc_is_taken() {
        let c = [0.0; 3];
        let z = [0.0, 0.0, 1.0];
        let from = about(c, &axis_angle(z, 3.0), [0.0; 3]);
        let to = about(c, &axis_angle(z, -3.0), [0.0; 3]);
        let (p0, p1) = (from.split(c).unwrap(), to.split(c).unwrap());
        let mid = Map3::join(&Map3::blend(&p0, &p1, 0.5), c);
        // Halfway from +3 rad to −3 rad the short way round is π.
        let want = about(c, &axis_angle(z, std::f64::consts::PI), [0.0; 3]);
        assert!(close(&mid, &want, 1e-14), "{mid:?}");
    }
}
