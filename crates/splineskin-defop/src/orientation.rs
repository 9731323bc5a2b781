//! Triangle orientation under a deformation: which triangles a configuration flips, and how
//! far a configuration may move along a direction before the first triangle flips.

use kurbo::{Point, Vec2};

use super::error::DefOpError;
use splineskin_core::mesh::TriMesh;

/// The triangles of `mesh` that `positions` (one per vertex) flip or collapse: signed area
/// `≤ 0` where the rest triangle is counter-clockwise. Sorted.
///
/// ```
/// use kurbo::Point;
/// use splineskin_defop::flipped_triangles;
/// use splineskin_core::mesh::TriMesh;
/// let v = vec![Point::new(0., 0.), Point::new(1., 0.), Point::new(0., 1.), Point::new(1., 1.)];
/// let mesh = TriMesh::new(v.clone(), vec![[0, 1, 2], [1, 3, 2]])?;
/// assert!(flipped_triangles(&mesh, &v)?.is_empty());
/// // Pull vertex 3 across the diagonal: triangle 1 turns clockwise.
/// let mut u = v.clone();
/// u[3] = Point::new(0.2, 0.2);
/// assert_eq!(flipped_triangles(&mesh, &u)?, vec![1]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn flipped_triangles(mesh: &TriMesh, positions: &[Point]) -> Result<Vec<usize>, DefOpError> {
    if positions.len() != mesh.n_vertices() {
        return Err(DefOpError::PositionCount {
            given: positions.len(),
            n_vertices: mesh.n_vertices(),
        });
    }
    Ok((0..mesh.n_triangles())
        .filter(|&t| {
            let double = double_area(mesh.triangles[t], positions);
            double.is_nan() || double <= 0.0
        })
        .collect())
}

/// Twice the signed area of triangle `tri` at `u`.
pub(crate) fn double_area(tri: [usize; 3], u: &[Point]) -> f64 {
    let [a, b, c] = tri.map(|i| u[i]);
    (b - a).cross(c - a)
}

/// The largest `α_max` such that moving every vertex `v` to `u_v + α d_v` keeps every
/// triangle's signed area positive for all `α ∈ [0, α_max)`: the smallest positive root over
/// the triangles of
///
/// ```text
/// 2A_t(α) = (e₁ + α f₁) × (e₂ + α f₂) = D₀ + D₁ α + D₂ α²,
/// e_k = u_{i_k} − u_{i_0},  f_k = d_{i_k} − d_{i_0},  D₀ = e₁×e₂,  D₁ = e₁×f₂ + f₁×e₂,  D₂ = f₁×f₂
/// ```
///
/// (`+∞` when no triangle ever flips). Every triangle must have positive area at `u`.
/// The roots use the cancellation-free form `q = −½(D₁ + sign(D₁)√Δ)`, roots `q/D₂`, `D₀/q`.
pub(crate) fn max_orientation_preserving_step(
    triangles: &[[usize; 3]],
    u: &[Point],
    d: &[Vec2],
) -> f64 {
    let mut alpha = f64::INFINITY;
    for tri in triangles {
        let [a, b, c] = tri.map(|i| u[i]);
        let [da, db, dc] = tri.map(|i| d[i]);
        let (e1, e2) = (b - a, c - a);
        let (f1, f2) = (db - da, dc - da);
        let d0 = e1.cross(e2);
        let d1 = e1.cross(f2) + f1.cross(e2);
        let d2 = f1.cross(f2);
        alpha = alpha.min(smallest_positive_root(d0, d1, d2));
    }
    alpha
}

/// The smallest positive root of `d0 + d1 α + d2 α²` with `d0 > 0`, or `+∞`.
fn smallest_positive_root(d0: f64, d1: f64, d2: f64) -> f64 {
    if d2 == 0.0 {
        return if d1 < 0.0 { -d0 / d1 } else { f64::INFINITY };
    }
    let discriminant = d1 * d1 - 4.0 * d2 * d0;
    if discriminant < 0.0 {
        return f64::INFINITY;
    }
    let q = -0.5 * (d1 + discriminant.sqrt().copysign(d1));
    let mut best = f64::INFINITY;
    for root in [q / d2, d0 / q] {
        if root > 0.0 && root < best {
            best = root;
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn max_step_stops_at_the_first_collapse() {
        // Unit right triangle; move the apex (0, 1) straight down by 1 per unit α: the area
        // vanishes at α = 1.
        let u = [Point::new(0., 0.), Point::new(1., 0.), Point::new(0., 1.)];
        let d = [Vec2::ZERO, Vec2::ZERO, Vec2::new(0.0, -1.0)];
        assert_eq!(max_orientation_preserving_step(&[[0, 1, 2]], &u, &d), 1.0);
        // Moving it up never flips.
        let up = [Vec2::ZERO, Vec2::ZERO, Vec2::new(0.0, 1.0)];
        assert_eq!(
            max_orientation_preserving_step(&[[0, 1, 2]], &u, &up),
            f64::INFINITY
        );
        // f₁ = (−1, 1), f₂ = (−1, −1) (a linearised quarter turn of the edges about corner 0):
        // 2A(α) = 1 − 2α + 2α², which has no real root, so the triangle never collapses.
        let spin = [Vec2::ZERO, Vec2::new(-1.0, 1.0), Vec2::new(-1.0, -1.0)];
        assert_eq!(
            max_orientation_preserving_step(&[[0, 1, 2]], &u, &spin),
            f64::INFINITY
        );
        // A quadratic with two positive roots: the smaller one is returned.
        assert!((smallest_positive_root(2.0, -3.0, 1.0) - 1.0).abs() < 1e-15);
        assert!((smallest_positive_root(1.0, 0.0, -4.0) - 0.5).abs() < 1e-15);
    }
}
