//! The cotangent Laplacian in both dimensions, on one per-triangle rule: of a planar
//! [`TriMesh`] (the weights' and the deformation operators' `L`) and of a quad mesh in 3D (the
//! surface operators of the subdivision rig's bone-heat weights).
//!
//! Per triangle, with `θ_k` the angle at corner `k` (opposite the edge of the other two
//! corners) and `A` its area (libigl's conventions, `cotmatrix` and `massmatrix`):
//!
//! ```text
//! ½ cot θ_k = ½ (p_{k+1} − p_k)·(p_{k+2} − p_k) / 2A          (half_cotangents_from)
//! L_ij     += ½ cot θ_k   for the edge ij opposite corner k,   L_ii = −Σ_{j≠i} L_ij
//! ```
//!
//! so `L` is symmetric, negative semidefinite, `L·1 = 0`, and `−wᵀLw = ∫ ‖∇w‖²` for the
//! piecewise linear `w` with vertex values `w` (Pinkall & Polthier 1993).
//!
//! | dimension | function | form |
//! |---|---|---|
//! | 2D | [`cotangent_laplacian`] (and `laplacian_csc`) | `L`, full symmetric storage |
//! | 3D | `quad_stiffness_and_mass` | `K = −L` upper-triangle entries and the barycentric lumped mass (`A/3` to each corner), each quad the **average of its two triangulations** (`(0,1,2),(0,2,3)` and `(0,1,3),(1,2,3)`), so that the operators do not depend on a choice of diagonal — a mirror-symmetric mesh has mirror-symmetric operators |
//!
//! In 3D a triangle whose area is below [`DEGENERATE_AREA_FRACTION`] of its longest edge
//! squared has unbounded cotangents and is left out of both operators. In 2D every triangle
//! counts, as in libigl: a [`TriMesh`]'s triangles have positive area (its constructors check
//! it).

use faer::sparse::SparseColMat;
use kurbo::Point;

use super::vec3::{cross, dot, norm, sub, Point3};
use super::TriMesh;
use crate::linalg::Csc;

/// `½ cot θ_k` at the three corners `k` of triangle `p` whose doubled area is `double_area`,
/// with `dot_at(o, a, b) = (a − o)·(b − o)`:
///
/// ```text
/// ½ cot θ_k = ½ (p_{k+1} − p_k)·(p_{k+2} − p_k) / 2A
/// ```
///
/// (`cot θ = cos θ / sin θ = (u·v) / ‖u × v‖`, and `‖u × v‖ = 2A`).
fn half_cotangents_from<P: Copy>(
    p: [P; 3],
    double_area: f64,
    dot_at: impl Fn(P, P, P) -> f64,
) -> [f64; 3] {
    std::array::from_fn(|k| 0.5 * dot_at(p[k], p[(k + 1) % 3], p[(k + 2) % 3]) / double_area)
}

/// Calls `f(k, a, b)` for each corner `k` of triangle `tri` and the edge `(a, b)` its angle
/// faces (the other two corners, in cyclic order).
fn for_each_opposite_edge(tri: [usize; 3], mut f: impl FnMut(usize, usize, usize)) {
    for k in 0..3 {
        f(k, tri[(k + 1) % 3], tri[(k + 2) % 3]);
    }
}

/// Half the cotangents of the planar triangle `[a, b, c]`'s angles at `a`, `b`, `c`
/// ([`half_cotangents_from`] with `2A = (b − a)×(c − a)`, positive for the counter-clockwise
/// triangles a [`TriMesh`] holds).
fn half_cotangents(p: [Point; 3]) -> [f64; 3] {
    let double_area = (p[1] - p[0]).cross(p[2] - p[0]);
    half_cotangents_from(p, double_area, |o, a, b| (a - o).dot(b - o))
}

/// The cotangent Laplacian `L` of `mesh` (`n_vertices × n_vertices`, full symmetric storage,
/// sorted row indices).
///
/// ```text
/// L_ij = ½ (cot α_ij + cot β_ij)    for an edge ij; α_ij, β_ij the angles opposite it
///                                    (one term on a boundary edge)
/// L_ii = −Σ_{j≠i} L_ij
/// ```
///
/// so `L` is symmetric, negative semidefinite, and `L·1 = 0`; `−wᵀLw = ∫ ‖∇w‖²` for the
/// piecewise linear function with vertex values `w` (Pinkall & Polthier 1993). This is libigl's
/// `cotmatrix` convention. A vertex in no triangle gets an empty row and column.
///
/// ```
/// use kurbo::Point;
/// use splineskin_core::mesh::{operators::cotangent_laplacian, TriMesh};
/// // The unit right triangle: cot 90° = 0 and cot 45° = 1.
/// let v = vec![Point::new(0., 0.), Point::new(1., 0.), Point::new(0., 1.)];
/// let l = cotangent_laplacian(&TriMesh::new(v, vec![[0, 1, 2]])?);
/// let dense = l.to_dense();
/// assert!((dense[(0, 1)] - 0.5).abs() < 1e-15); // edge 01 faces the 45° angle at 2
/// assert!(dense[(1, 2)].abs() < 1e-15);          // edge 12 faces the right angle at 0
/// assert!((dense[(0, 0)] + 1.0).abs() < 1e-15);
/// # Ok::<(), splineskin_core::mesh::MeshError>(())
/// ```
pub fn cotangent_laplacian(mesh: &TriMesh) -> SparseColMat<usize, f64> {
    laplacian_csc(mesh).into_faer()
}

/// [`cotangent_laplacian`] in our working form.
pub fn laplacian_csc(mesh: &TriMesh) -> Csc {
    let n = mesh.n_vertices();
    // Each triangle contributes one half-cotangent to each of its three edges, in both
    // directions; every vertex of a triangle also gets a diagonal slot. Bucket the entries by
    // column (counting sort), then sort and merge each short column.
    let mut col_ptr = vec![0usize; n + 1];
    let mut referenced = vec![false; n];
    for tri in &mesh.triangles {
        for &i in tri {
            col_ptr[i + 1] += 2;
            referenced[i] = true;
        }
    }
    for (i, &r) in referenced.iter().enumerate() {
        col_ptr[i + 1] += usize::from(r);
    }
    for i in 0..n {
        col_ptr[i + 1] += col_ptr[i];
    }
    let mut next = col_ptr.clone();
    let mut entries = vec![(0usize, 0.0f64); col_ptr[n]];
    for (i, &r) in referenced.iter().enumerate() {
        if r {
            entries[next[i]] = (i, 0.0); // the diagonal's slot, filled below
            next[i] += 1;
        }
    }
    for tri in &mesh.triangles {
        let c = half_cotangents(tri.map(|i| mesh.vertices[i]));
        for_each_opposite_edge(*tri, |k, i, j| {
            entries[next[i]] = (j, c[k]);
            next[i] += 1;
            entries[next[j]] = (i, c[k]);
            next[j] += 1;
        });
    }
    let mut merged_ptr = Vec::with_capacity(n + 1);
    let mut row_idx = Vec::with_capacity(entries.len());
    let mut values = Vec::with_capacity(entries.len());
    merged_ptr.push(0);
    for i in 0..n {
        let column = &mut entries[col_ptr[i]..col_ptr[i + 1]];
        column.sort_unstable_by_key(|&(j, _)| j);
        let start = row_idx.len();
        let mut diagonal_at = start;
        for &(j, value) in column.iter() {
            match row_idx.last() {
                Some(&last) if row_idx.len() > start && last == j => {
                    if let Some(v) = values.last_mut() {
                        *v += value;
                    }
                }
                _ => {
                    if j == i {
                        diagonal_at = row_idx.len();
                    }
                    row_idx.push(j);
                    values.push(value);
                }
            }
        }
        if row_idx.len() > start {
            // The diagonal slot still holds 0, so this is the sum of the off-diagonal entries.
            let off_diagonal: f64 = values[start..].iter().sum();
            values[diagonal_at] = -off_diagonal;
        }
        merged_ptr.push(row_idx.len());
    }
    Csc {
        n,
        col_ptr: merged_ptr,
        row_idx,
        values,
    }
}

/// A triangle with `2·area < DEGENERATE_AREA_FRACTION · (longest edge)²` is degenerate (its
/// angles are within about `1e-12` radians of 0 or π) and contributes nothing.
pub const DEGENERATE_AREA_FRACTION: f64 = 1e-12;

/// The two triangulations of a quad, as corner indices.
const SPLITS: [[[usize; 3]; 2]; 2] = [[[0, 1, 2], [0, 2, 3]], [[0, 1, 3], [1, 2, 3]]];

/// `(K, M)`: the upper-triangle entries of the stiffness `K = −L` (`(row, column, value)`,
/// `row ≤ column`, repeated entries to be summed) and the lumped mass (`n_vertices` long) of the
/// quads `quads` at `positions` (module documentation).
pub fn quad_stiffness_and_mass(
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
                let Some((half_cot, area)) = half_cotangents_3d(p) else {
                    continue;
                };
                for_each_opposite_edge(v, |k, a, b| {
                    let w = 0.5 * half_cot[k];
                    entries.push((a.min(b), a.max(b), -w));
                    entries.push((a, a, w));
                    entries.push((b, b, w));
                    mass[v[k]] += 0.5 * area / 3.0;
                });
            }
        }
    }
    (entries, mass)
}

/// `½ cot` of the angles at the three corners of triangle `p` and its area, or `None` if it is
/// degenerate.
fn half_cotangents_3d(p: [Point3; 3]) -> Option<([f64; 3], f64)> {
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
    let cot = half_cotangents_from(p, double_area, |o, a, b| dot(sub(a, o), sub(b, o)));
    Some((cot, 0.5 * double_area))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::Csc;

    /// `K x` from upper entries.
    fn apply(n: usize, entries: &[(usize, usize, f64)], x: &[f64]) -> Vec<f64> {
        let k = Csc::upper_from_entries(n, entries.to_vec(), &vec![0.0; n]);
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
        assert!(half_cotangents_3d([[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]).is_none());
    }
}
