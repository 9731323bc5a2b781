//! 3D affine maps `T_i` of the subdivision rig's handles, as 3 × 4 matrices.
//!
//! ```text
//!         ⎡ T[0][0] T[0][1] T[0][2] T[0][3] ⎤ ⎡x⎤
//! T·p̄  =  ⎢ T[1][0] T[1][1] T[1][2] T[1][3] ⎥ ⎢y⎥     p̄ = (x, y, z, 1)
//!         ⎣ T[2][0] T[2][1] T[2][2] T[2][3] ⎦ ⎢z⎥
//!                                             ⎣1⎦
//! ```
//!
//! The last column is the translation. [`affine3_about`] builds the usual "scale, then
//! rotate, about a pivot, then translate" map of a handle; rotations come from an axis and
//! an angle ([`rotation_axis_angle`]) or a unit quaternion ([`rotation_quaternion`]).

use super::cage::Point3;
use splineskin_core::mesh::vec3::quaternion_rotation;
pub(crate) use splineskin_core::mesh::vec3::{cross, dot, norm, sub};

/// A 3D affine map as 3 rows of 4: `x' = T[0][0] x + T[0][1] y + T[0][2] z + T[0][3]`, and so
/// on for `y'`, `z'` (the 3 × 4 matrix `T_i` acting on `(x, y, z, 1)`; module documentation).
pub type Affine3 = [[f64; 4]; 3];

/// A 3 × 3 linear map, rows first.
pub type Linear3 = [[f64; 3]; 3];

/// The identity map.
pub const AFFINE3_IDENTITY: Affine3 = [
    [1.0, 0.0, 0.0, 0.0],
    [0.0, 1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
];

/// The 3 × 3 identity.
pub const LINEAR3_IDENTITY: Linear3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// `T·p̄`.
///
/// ```
/// use splineskin_subdiv::{affine3_apply, AFFINE3_IDENTITY};
/// let mut t = AFFINE3_IDENTITY;
/// t[0][3] = 2.0;
/// assert_eq!(affine3_apply(&t, [1.0, 1.0, 1.0]), [3.0, 1.0, 1.0]);
/// ```
pub fn affine3_apply(t: &Affine3, p: Point3) -> Point3 {
    std::array::from_fn(|r| t[r][0] * p[0] + t[r][1] * p[1] + t[r][2] * p[2] + t[r][3])
}

/// The composition `a ∘ b` (first `b`, then `a`).
///
/// ```
/// use splineskin_subdiv::{affine3_apply, affine3_compose, affine3_translation};
/// let ab = affine3_compose(&affine3_translation([1.0, 0.0, 0.0]), &affine3_translation([0.0, 2.0, 0.0]));
/// assert_eq!(affine3_apply(&ab, [0.0; 3]), [1.0, 2.0, 0.0]);
/// ```
pub fn affine3_compose(a: &Affine3, b: &Affine3) -> Affine3 {
    std::array::from_fn(|r| {
        std::array::from_fn(|c| {
            let linear = a[r][0] * b[0][c] + a[r][1] * b[1][c] + a[r][2] * b[2][c];
            if c == 3 {
                linear + a[r][3]
            } else {
                linear
            }
        })
    })
}

/// The translation by `d`.
pub fn affine3_translation(d: Point3) -> Affine3 {
    let mut t = AFFINE3_IDENTITY;
    for r in 0..3 {
        t[r][3] = d[r];
    }
    t
}

/// `x ↦ A (x − c) + c + d`: the linear map `a` about the pivot `c`, then the translation `d`.
///
/// ```
/// use splineskin_subdiv::{affine3_about, affine3_apply, rotation_axis_angle};
/// // A quarter turn about the z axis through (1, 0, 0): the pivot stays, (2, 0, 0) goes to (1, 1, 0).
/// let r = rotation_axis_angle([0.0, 0.0, 1.0], std::f64::consts::FRAC_PI_2).unwrap();
/// let t = affine3_about([1.0, 0.0, 0.0], &r, [0.0; 3]);
/// let p = affine3_apply(&t, [2.0, 0.0, 0.0]);
/// assert!((p[0] - 1.0).abs() < 1e-15 && (p[1] - 1.0).abs() < 1e-15);
/// ```
pub fn affine3_about(c: Point3, a: &Linear3, d: Point3) -> Affine3 {
    std::array::from_fn(|r| {
        let ac = a[r][0] * c[0] + a[r][1] * c[1] + a[r][2] * c[2];
        [a[r][0], a[r][1], a[r][2], c[r] - ac + d[r]]
    })
}

/// The product `a · b` of two 3 × 3 maps.
pub fn linear3_mul(a: &Linear3, b: &Linear3) -> Linear3 {
    std::array::from_fn(|r| std::array::from_fn(|c| (0..3).map(|k| a[r][k] * b[k][c]).sum()))
}

/// The rotation by `angle` radians about `axis` (right-handed: counter-clockwise looking down
/// the axis), by Rodrigues' formula `R = cos θ I + sin θ [k]ₓ + (1 − cos θ) k kᵀ` with
/// `k = axis/‖axis‖`. `None` if the axis is zero or anything is not finite.
pub fn rotation_axis_angle(axis: Point3, angle: f64) -> Option<Linear3> {
    let len = norm(axis);
    if !(len > 0.0 && len.is_finite() && angle.is_finite()) {
        return None;
    }
    let [x, y, z] = axis.map(|a| a / len);
    let (s, c) = angle.sin_cos();
    let t = 1.0 - c;
    Some([
        [c + x * x * t, x * y * t - z * s, x * z * t + y * s],
        [y * x * t + z * s, c + y * y * t, y * z * t - x * s],
        [z * x * t - y * s, z * y * t + x * s, c + z * z * t],
    ])
}

/// The rotation of the quaternion `q = [w, x, y, z]` (scalar first), normalised first.
/// `None` if `q` is zero or not finite.
///
/// ```
/// use splineskin_subdiv::{rotation_axis_angle, rotation_quaternion};
/// // [cos θ/2, sin θ/2 · k] is the rotation by θ about k.
/// let h = std::f64::consts::FRAC_PI_8;
/// let q = rotation_quaternion([h.cos(), 0.0, h.sin(), 0.0]).unwrap();
/// let r = rotation_axis_angle([0.0, 1.0, 0.0], 2.0 * h).unwrap();
/// for i in 0..3 { for j in 0..3 { assert!((q[i][j] - r[i][j]).abs() < 1e-15); } }
/// ```
pub fn rotation_quaternion(q: [f64; 4]) -> Option<Linear3> {
    let len = q.iter().map(|a| a * a).sum::<f64>().sqrt();
    if !(len > 0.0 && len.is_finite()) {
        return None;
    }
    Some(quaternion_rotation(q.map(|a| a / len)))
}

/// Are all twelve entries finite?
pub fn affine3_is_finite(t: &Affine3) -> bool {
    t.iter().flatten().all(|x| x.is_finite())
}

/// `‖a − b‖²`.
pub(crate) fn distance2(a: Point3, b: Point3) -> f64 {
    let d = sub(a, b);
    dot(d, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn affine3_rotations_are_orthonormal_and_compose() {
        let r = rotation_axis_angle([1.0, 2.0, -0.5], 0.7).unwrap();
        let rt_r = linear3_mul(
            &std::array::from_fn(|i| std::array::from_fn(|j| r[j][i])),
            &r,
        );
        for i in 0..3 {
            for j in 0..3 {
                let e = if i == j { 1.0 } else { 0.0 };
                assert!((rt_r[i][j] - e).abs() < 1e-15);
            }
        }
        // The axis is fixed.
        let t = affine3_about([0.0; 3], &r, [0.0; 3]);
        let a = affine3_apply(&t, [1.0, 2.0, -0.5]);
        assert!(distance2(a, [1.0, 2.0, -0.5]) < 1e-28);
        // Composition applies right to left.
        let s = affine3_translation([0.0, 0.0, 3.0]);
        let p = [0.3, -0.2, 0.9];
        let both = affine3_apply(&affine3_compose(&s, &t), p);
        let step = affine3_apply(&s, affine3_apply(&t, p));
        assert!(distance2(both, step) < 1e-28);
        assert!(rotation_axis_angle([0.0; 3], 1.0).is_none());
        assert!(rotation_quaternion([0.0; 4]).is_none());
        assert!(rotation_quaternion([f64::NAN, 0.0, 0.0, 1.0]).is_none());
    }
}
