//! Shapes the unit tests of several modules share.

use super::cage::Point3;

/// The unit cube `[0, 1]³` as 12 triangles, outward (counter-clockwise seen from outside).
pub(crate) fn unit_cube_triangles() -> (Vec<Point3>, Vec<[u32; 3]>) {
    let p = (0..8)
        .map(|v| [(v & 1) as f64, ((v >> 1) & 1) as f64, ((v >> 2) & 1) as f64])
        .collect();
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let t = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    (p, t)
}
