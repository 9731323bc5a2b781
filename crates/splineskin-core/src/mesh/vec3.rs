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
