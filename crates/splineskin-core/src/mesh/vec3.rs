//! Small vector algebra on points of 3D space as `[x, y, z]`: what the 3D cotangent
//! Laplacian ([`super::cotangent`]) and the subdivision code share.

/// A point (or vector) of 3D space.
pub type Point3 = [f64; 3];

/// `‖p‖`.
pub fn norm(p: Point3) -> f64 {
    (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt()
}

/// `a − b`.
pub fn sub(a: Point3, b: Point3) -> Point3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `a · b`.
pub fn dot(a: Point3, b: Point3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `a × b`.
pub fn cross(a: Point3, b: Point3) -> Point3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The rotation matrix (rows) of a unit quaternion `q = [w, x, y, z]`:
///
/// ```text
/// ⎡1 − 2(y² + z²)   2(xy − wz)       2(xz + wy)    ⎤
/// ⎢2(xy + wz)       1 − 2(x² + z²)   2(yz − wx)    ⎥
/// ⎣2(xz − wy)       2(yz + wx)       1 − 2(x² + y²)⎦
/// ```
///
/// ```
/// use splineskin_core::mesh::vec3::quaternion_rotation;
/// let h = std::f64::consts::FRAC_1_SQRT_2;
/// // A quarter turn about z sends x to y.
/// let r = quaternion_rotation([h, 0.0, 0.0, h]);
/// assert!((r[1][0] - 1.0).abs() < 1e-15 && r[0][0].abs() < 1e-15);
/// ```
pub fn quaternion_rotation(q: [f64; 4]) -> [[f64; 3]; 3] {
    let [w, x, y, z] = q;
    [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ]
}
