//! The cotangent Laplacian and lumped mass of a quad mesh in 3D (the surface operators of
//! bone-heat weights).
//!
//! Each quad counts as the **average of its two triangulations** (`(0,1,2),(0,2,3)` and
//! `(0,1,3),(1,2,3)`), so that the operators do not depend on a choice of diagonal — a mirror-
//! symmetric mesh has mirror-symmetric operators, whichever way ties between diagonals would
//! have been broken. Per triangle, as in [`splineskin_core::mesh::operators`] (libigl's conventions):
//!
//! ```text
//! stiffness  K = −L:   K_ab −= ½ cot θ_c,  K_aa += ½ cot θ_c,  K_bb += ½ cot θ_c   (θ_c opposite edge ab)
//! mass       M:        A/3 to each corner (barycentric lumping)
//! ```
//!
//! `K` is symmetric positive semidefinite (`wᵀKw = ∫ ‖∇w‖²` for the piecewise linear `w` of each
//! triangulation, Pinkall & Polthier 1993) and `K·1 = 0`. A triangle whose area is below
//! [`DEGENERATE_AREA_FRACTION`] of its longest edge squared has unbounded cotangents and is left
//! out of both operators.

use super::affine3::{cross, dot, norm, sub};
use super::cage::Point3;

/// A triangle with `2·area < DEGENERATE_AREA_FRACTION · (longest edge)²` is degenerate (its
/// angles are within about `1e-12` radians of 0 or π) and contributes nothing.
pub const DEGENERATE_AREA_FRACTION: f64 = 1e-12;

/// The two triangulations of a quad, as corner indices.
const SPLITS: [[[usize; 3]; 2]; 2] = [[[0, 1, 2], [0, 2, 3]], [[0, 1, 3], [1, 2, 3]]];

/// `(K, M)`: the upper-triangle entries of the stiffness `K = −L` (`(row, column, value)`,
/// `row ≤ column`, repeated entries to be summed) and the lumped mass (`n_vertices` long) of the
/// quads `quads` at `positions` (module documentation).
pub(crate) fn quad_stiffness_and_mass(
    positions: &[Point3],
    quads: &[[u32; 4]],
) -> (Vec<(usize, usize, f64)>, Vec<f64>) {
    let mut entries = Vec::with_capacity(quads.len() * 2 * 2 * 6);
    let mut mass = vec![0.0; positions.len()];
    for q in quads {
        for split in SPLITS {
            for t in split {
                let v = t.map(|k| q[k] as usize);
                let p = v.map(|i| positions[i]);
                let Some((half_cot, area)) = half_cotangents(p) else {
                    continue;
                };
                for k in 0..3 {
                    // The angle at corner k faces the edge (k+1, k+2).
                    let (a, b) = (v[(k + 1) % 3], v[(k + 2) % 3]);
                    let w = 0.5 * half_cot[k];
                    entries.push((a.min(b), a.max(b), -w));
                    entries.push((a, a, w));
                    entries.push((b, b, w));
                    mass[v[k]] += 0.5 * area / 3.0;
                }
            }
        }
    }
    (entries, mass)
}

/// `½ cot` of the angles at the three corners of triangle `p` and its area, or `None` if it is
/// degenerate.
fn half_cotangents(p: [Point3; 3]) -> Option<([f64; 3], f64)> {
    let n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
    let double_area = norm(n);
    let longest = (0..3)
        .map(|k| {
            let e = sub(p[(k + 1) % 3], p[k]);
            dot(e, e)
        })
        .fold(0.0, f64::max);
    if double_area.is_nan() || double_area <= DEGENERATE_AREA_FRACTION * longest {
        return None;
    }
    let cot = std::array::from_fn(|k| {
        let o = p[k];
        let (u, v) = (sub(p[(k + 1) % 3], o), sub(p[(k + 2) % 3], o));
        0.5 * dot(u, v) / double_area
    });
    Some((cot, 0.5 * double_area))
}

#[cfg(test)]
mod tests {
    use super::*;
    use splineskin_core::sparse_cholesky::UpperCsc;

    /// `K x` from upper entries.
    fn apply(n: usize, entries: &[(usize, usize, f64)], x: &[f64]) -> Vec<f64> {
        let k = UpperCsc::from_entries(n, entries.to_vec(), &vec![0.0; n]);
        let mut out = vec![0.0; n];
        for j in 0..n {
            for p in k.col_ptr[j]..k.col_ptr[j + 1] {
                let (i, v) = (k.row_idx[p], k.values[p]);
                out[i] += v * x[j];
                if i != j {
                    out[j] += v * x[i];
                }
            }
        }
        out
    }

    #[test]
    fn cotangent_laplacian_kills_constants_and_linear_functions_inside() {
        // A 4 × 4 grid of a tilted, sheared plane: linear functions are harmonic at inner
        // vertices, constants everywhere.
        let n = 5;
        let positions: Vec<Point3> = (0..n * n)
            .map(|k| {
                let (i, j) = ((k % n) as f64, (k / n) as f64);
                [i + 0.3 * j, j, 0.5 * i - 0.2 * j]
            })
            .collect();
        let id = |i: usize, j: usize| (j * n + i) as u32;
        let quads: Vec<[u32; 4]> = (0..n - 1)
            .flat_map(|j| {
                (0..n - 1).map(move |i| [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)])
            })
            .collect();
        let (entries, mass) = quad_stiffness_and_mass(&positions, &quads);
        let ones = vec![1.0; n * n];
        assert!(apply(n * n, &entries, &ones)
            .iter()
            .all(|x| x.abs() < 1e-14));
        for c in 0..3 {
            let f: Vec<f64> = positions.iter().map(|p| p[c]).collect();
            let kf = apply(n * n, &entries, &f);
            for j in 1..n - 1 {
                for i in 1..n - 1 {
                    assert!(kf[id(i, j) as usize].abs() < 1e-13, "{c} ({i}, {j})");
                }
            }
        }
        // The mass is the area: each quad is a parallelogram of area ‖(1,0,.5)×(.3,1,−.2)‖.
        let area = norm(cross([1.0, 0.0, 0.5], [0.3, 1.0, -0.2]));
        let total: f64 = mass.iter().sum();
        assert!((total - 16.0 * area).abs() < 1e-12, "{total}");
        // A degenerate triangle is left out rather than giving infinite cotangents.
        assert!(half_cotangents([[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]).is_none());
    }
}
