//! Discrete operators on a [`TriMesh`]: the cotangent Laplacian, the lumped mass matrices and
//! the polyharmonic energies built from them.
//!
//! Conventions are libigl's (`cotmatrix`, `massmatrix`), which the reference data in
//! `../shared/data/reference-igl` were computed with:
//!
//! | quantity | formula | size |
//! |---|---|---|
//! | [`cotangent_laplacian`] `L` | `L_ij = ½ (cot α_ij + cot β_ij)` over the edge `ij`'s one or two opposite angles, `L_ii = −Σ_{j≠i} L_ij` | `n_vertices × n_vertices`, symmetric, negative semidefinite |
//! | [`lumped_mass`] `M` (Voronoi) | Meyer et al. 2003 hybrid Voronoi areas, per corner: see [`MassKind::Voronoi`] | diagonal, `n_vertices` |
//! | [`lumped_mass`] `M` (barycentric) | a third of each triangle's area to each corner | diagonal, `n_vertices` |
//! | [`consistent_mass`] `M` | `M_ij = Σ_t ∫_t φ_i φ_j = Σ_t A_t (1 + δ_ij) / 12` over the triangles holding `i` and `j` | `n_vertices × n_vertices`, symmetric positive semidefinite |
//! | [`polyharmonic_energy`] `Q_k` | `Q_1 = −L`, `Q_k = Q_{k−1} M⁻¹ (−L)` (Voronoi `M`) | `n_vertices × n_vertices`, symmetric positive semidefinite |
//!
//! `−L` discretises `∫ ‖∇w‖²` for piecewise linear `w` (`wᵀ(−L)w` is exactly that integral;
//! Pinkall & Polthier 1993), and `Q_2 = L M⁻¹ L` the squared Laplacian energy `∫ (Δw)²` with
//! natural boundary conditions (Jacobson et al. 2011, *Bounded biharmonic weights*, §3).

use faer::sparse::SparseColMat;

pub use super::cotangent::cotangent_laplacian;
use super::cotangent::laplacian_csc;
use super::TriMesh;
pub use crate::linalg::Csc;

/// How a triangle's area is shared among its corners for a lumped (diagonal) mass matrix.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MassKind {
    /// Meyer, Desbrun, Schröder & Barr 2003 (*Discrete differential-geometry operators for
    /// triangulated 2-manifolds*, §3.3, the "mixed" area): in a triangle with no obtuse angle,
    /// corner `i` (other corners `j`, `l`, angles `θ_j`, `θ_l`) gets its Voronoi area
    /// `⅛ (‖e_ij‖² cot θ_l + ‖e_il‖² cot θ_j)`; in an obtuse triangle the obtuse corner gets
    /// `A/2` and the other two `A/4`. libigl's `MASSMATRIX_TYPE_VORONOI`, its default for
    /// triangles.
    Voronoi,
    /// `A/3` to each corner (libigl's `MASSMATRIX_TYPE_BARYCENTRIC`).
    Barycentric,
}

/// The diagonal of the lumped mass matrix of `mesh` (length `n_vertices`): each vertex's share
/// of the area of its triangles, shared as [`MassKind`] says. The entries sum to the mesh's
/// area; a vertex in no triangle gets 0.
///
/// ```
/// use kurbo::Point;
/// use splineskin_core::mesh::{operators::{lumped_mass, MassKind}, TriMesh};
/// // Right isosceles triangle (area ½): the circumcentre is the hypotenuse's midpoint, so the
/// // right-angle corner gets half of the area and the others a quarter each.
/// let v = vec![Point::new(0., 0.), Point::new(1., 0.), Point::new(0., 1.)];
/// let mesh = TriMesh::new(v, vec![[0, 1, 2]])?;
/// let m = lumped_mass(&mesh, MassKind::Voronoi);
/// assert!((m[0] - 0.25).abs() < 1e-16 && (m[1] - 0.125).abs() < 1e-16);
/// assert_eq!(lumped_mass(&mesh, MassKind::Barycentric), vec![0.5 / 3.0; 3]);
/// # Ok::<(), splineskin_core::mesh::MeshError>(())
/// ```
pub fn lumped_mass(mesh: &TriMesh, kind: MassKind) -> Vec<f64> {
    let mut mass = vec![0.0; mesh.n_vertices()];
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let shares = match kind {
            MassKind::Barycentric => [mesh.signed_area(t) / 3.0; 3],
            MassKind::Voronoi => voronoi_shares(tri.map(|i| mesh.vertices[i])),
        };
        for k in 0..3 {
            mass[tri[k]] += shares[k];
        }
    }
    mass
}

/// The consistent (finite-element) mass matrix of `mesh` (`n_vertices × n_vertices`, full
/// symmetric storage, sorted rows): `M_ij = ∫ φ_i φ_j` for the hat functions, so `uᵀ M v` is
/// exactly `∫ u v` for the piecewise linear functions with vertex values `u` and `v`. On a
/// triangle of area `A` it is `A/6` on the diagonal and `A/12` off it. A vertex in no triangle
/// gets an empty row and column.
///
/// ```
/// use kurbo::Point;
/// use splineskin_core::mesh::{operators::consistent_mass, TriMesh};
/// let v = vec![Point::new(0., 0.), Point::new(1., 0.), Point::new(0., 1.)];
/// let m = consistent_mass(&TriMesh::new(v, vec![[0, 1, 2]])?).to_dense();
/// // ∫ φ_0² = A/6 and ∫ φ_0 φ_1 = A/12 with A = ½.
/// assert!((m[(0, 0)] - 1.0 / 12.0).abs() < 1e-16 && (m[(0, 1)] - 1.0 / 24.0).abs() < 1e-16);
/// # Ok::<(), splineskin_core::mesh::MeshError>(())
/// ```
pub fn consistent_mass(mesh: &TriMesh) -> SparseColMat<usize, f64> {
    consistent_mass_csc(mesh).into_faer()
}

/// [`consistent_mass`] in our working form.
pub fn consistent_mass_csc(mesh: &TriMesh) -> Csc {
    let mut triplets = Vec::with_capacity(9 * mesh.n_triangles());
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let area = mesh.signed_area(t);
        for &i in tri {
            for &j in tri {
                let share = if i == j { area / 6.0 } else { area / 12.0 };
                triplets.push((i, j, share));
            }
        }
    }
    Csc::from_triplets(mesh.n_vertices(), triplets)
}

/// The three corners' shares of triangle `p`'s area under [`MassKind::Voronoi`].
fn voronoi_shares(p: [kurbo::Point; 3]) -> [f64; 3] {
    let double_area = (p[1] - p[0]).cross(p[2] - p[0]);
    let area = 0.5 * double_area;
    // dots[k] = (p_{k+1} − p_k)·(p_{k+2} − p_k): negative at an obtuse corner.
    let dots: [f64; 3] = std::array::from_fn(|k| {
        let o = p[k];
        (p[(k + 1) % 3] - o).dot(p[(k + 2) % 3] - o)
    });
    if let Some(obtuse) = dots.iter().position(|&d| d < 0.0) {
        return std::array::from_fn(|k| if k == obtuse { 0.5 * area } else { 0.25 * area });
    }
    // ⅛ (‖e_ij‖² cot θ_l + ‖e_il‖² cot θ_j) with cot θ = dot / (2A).
    std::array::from_fn(|i| {
        let (j, l) = ((i + 1) % 3, (i + 2) % 3);
        let eij = (p[j] - p[i]).hypot2();
        let eil = (p[l] - p[i]).hypot2();
        (eij * dots[l] + eil * dots[j]) / (8.0 * double_area)
    })
}

/// The polyharmonic energy matrix of order `k ≥ 1` (`n_vertices × n_vertices`, symmetric
/// positive semidefinite, full storage):
///
/// ```text
/// Q_1 = −L,    Q_k = Q_{k−1} · M⁻¹ · (−L)      (so Q_2 = L M⁻¹ L)
/// ```
///
/// with `L` the [`cotangent_laplacian`] and `M` the Voronoi [`lumped_mass`] (libigl's
/// `harmonic(V, F, b, bc, k, W)`). `wᵀ Q_k w` discretises `∫ ‖∇^k w‖²` with natural boundary
/// conditions; its null space is the constants on each connected component. A vertex in no
/// triangle (zero mass) gets an empty row and column. `k = 0` gives an empty (all-zero)
/// matrix.
///
/// ```
/// use kurbo::Point;
/// use splineskin_core::mesh::{operators::polyharmonic_energy, TriMesh};
/// let v = vec![Point::new(0., 0.), Point::new(1., 0.), Point::new(1., 1.), Point::new(0., 1.)];
/// let mesh = TriMesh::new(v, vec![[0, 1, 2], [0, 2, 3]])?;
/// let q = polyharmonic_energy(&mesh, 2).to_dense();
/// // Constants are in the null space: every row sums to zero.
/// for i in 0..4 {
///     assert!((0..4).map(|j| q[(i, j)]).sum::<f64>().abs() < 1e-12);
/// }
/// # Ok::<(), splineskin_core::mesh::MeshError>(())
/// ```
pub fn polyharmonic_energy(mesh: &TriMesh, k: usize) -> SparseColMat<usize, f64> {
    polyharmonic_csc(mesh, k).into_faer()
}

/// [`polyharmonic_energy`] in our working form.
pub fn polyharmonic_csc(mesh: &TriMesh, k: usize) -> Csc {
    let n = mesh.n_vertices();
    if k == 0 {
        return Csc {
            n,
            col_ptr: vec![0; n + 1],
            row_idx: Vec::new(),
            values: Vec::new(),
        };
    }
    let minus_l = laplacian_csc(mesh).scaled(-1.0);
    let mass = lumped_mass(mesh, MassKind::Voronoi);
    let inverse_mass: Vec<f64> = mass
        .iter()
        .map(|&m| if m > 0.0 { 1.0 / m } else { 0.0 })
        .collect();
    let mut q = minus_l.clone();
    for _ in 1..k {
        q = q.times_diagonal_times(&inverse_mass, &minus_l);
    }
    q
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support::pts;
    use kurbo::Point;

    /// A regular `n × n` grid of unit squares, each cut along alternating diagonals.
    fn grid(n: usize) -> TriMesh {
        let mut v = Vec::new();
        for y in 0..=n {
            for x in 0..=n {
                v.push(Point::new(x as f64, y as f64 * 0.7));
            }
        }
        let id = |x: usize, y: usize| y * (n + 1) + x;
        let mut t = Vec::new();
        for y in 0..n {
            for x in 0..n {
                let (a, b, c, d) = (id(x, y), id(x + 1, y), id(x + 1, y + 1), id(x, y + 1));
                if (x + y) % 2 == 0 {
                    t.push([a, b, c]);
                    t.push([a, c, d]);
                } else {
                    t.push([a, b, d]);
                    t.push([b, c, d]);
                }
            }
        }
        TriMesh::new(v, t).unwrap()
    }

    /// Rounding allowance for sums of a few O(1) terms.
    const ROUNDING: f64 = 1e-13;

    #[test]
    fn cotangent_laplacian_constant_in_null_space_and_symmetric() {
        let mesh = grid(5);
        let l = cotangent_laplacian(&mesh).to_dense();
        for i in 0..mesh.n_vertices() {
            let row: f64 = (0..mesh.n_vertices()).map(|j| l[(i, j)]).sum();
            assert!(row.abs() < ROUNDING, "row {i} sums to {row}");
            for j in 0..mesh.n_vertices() {
                assert_eq!(l[(i, j)], l[(j, i)]);
            }
        }
    }

    #[test]
    fn cotangent_laplacian_energy_is_dirichlet_energy_of_linear_function() {
        // For w = a·x + b·y, −wᵀLw = ∫‖∇w‖² = (a² + b²)·area exactly (the cotangent formula is
        // exact on piecewise linear functions).
        let mesh = grid(4);
        let l = Csc::from_faer(&cotangent_laplacian(&mesh));
        let (a, b) = (0.3, -1.7);
        let w: Vec<f64> = mesh.vertices.iter().map(|p| a * p.x + b * p.y).collect();
        let mut energy = 0.0;
        for j in 0..l.n {
            let (is, vs) = l.column(j);
            for (&i, &v) in is.iter().zip(vs) {
                energy -= w[i] * v * w[j];
            }
        }
        let expected = (a * a + b * b) * mesh.total_area();
        assert!(
            (energy - expected).abs() < ROUNDING * expected,
            "{energy} vs {expected}"
        );
    }

    #[test]
    fn lumped_mass_sums_to_area_and_matches_circumcentre_split() {
        let mesh = grid(3);
        for kind in [MassKind::Voronoi, MassKind::Barycentric] {
            let total: f64 = lumped_mass(&mesh, kind).iter().sum();
            assert!((total - mesh.total_area()).abs() < ROUNDING);
        }
        // Equilateral triangle: every corner gets a third.
        let h = 3f64.sqrt() / 2.0;
        let v = vec![Point::new(0., 0.), Point::new(1., 0.), Point::new(0.5, h)];
        let m = lumped_mass(
            &TriMesh::new(v, vec![[0, 1, 2]]).unwrap(),
            MassKind::Voronoi,
        );
        for mi in m {
            assert!((mi - h / 6.0).abs() < 1e-16);
        }
        // Obtuse triangle (angle at 2 is obtuse): A/4, A/4, A/2.
        let v = vec![Point::new(0., 0.), Point::new(4., 0.), Point::new(2., 0.5)];
        let m = lumped_mass(
            &TriMesh::new(v, vec![[0, 1, 2]]).unwrap(),
            MassKind::Voronoi,
        );
        assert_eq!(m, vec![0.25, 0.25, 0.5]);
    }

    #[test]
    fn polyharmonic_energy_matches_dense_product() {
        let mesh = grid(3);
        let n = mesh.n_vertices();
        let l = cotangent_laplacian(&mesh).to_dense();
        let m = lumped_mass(&mesh, MassKind::Voronoi);
        let q2 = polyharmonic_energy(&mesh, 2).to_dense();
        let q3 = polyharmonic_energy(&mesh, 3).to_dense();
        let q1 = polyharmonic_energy(&mesh, 1).to_dense();
        for i in 0..n {
            for j in 0..n {
                let p2: f64 = (0..n).map(|k| l[(i, k)] * l[(k, j)] / m[k]).sum();
                assert!((q2[(i, j)] - p2).abs() < 1e-12 * (1.0 + p2.abs()));
                let p3: f64 = (0..n).map(|k| -q2[(i, k)] * l[(k, j)] / m[k]).sum();
                assert!((q3[(i, j)] - p3).abs() < 1e-11 * (1.0 + p3.abs()));
                assert_eq!(q1[(i, j)], -l[(i, j)]);
            }
        }
    }

    #[test]
    fn consistent_mass_integrates_products_of_linear_functions() {
        // The consistent mass integrates products of piecewise linear functions exactly: over
        // the grid's [0, 5] × [0, 3.5], ∫ 1 = 17.5, ∫ x = 12.5 · 3.5, ∫ x² = (125/3) · 3.5.
        let mesh = grid(5);
        let m = Csc::from_faer(&consistent_mass(&mesh));
        let n = mesh.n_vertices();
        let apply = |u: &[f64], v: &[f64]| -> f64 {
            (0..n)
                .map(|j| {
                    let (is, vs) = m.column(j);
                    is.iter()
                        .zip(vs)
                        .map(|(&i, &x)| u[i] * x * v[j])
                        .sum::<f64>()
                })
                .sum()
        };
        let one = vec![1.0; n];
        let x: Vec<f64> = mesh.vertices.iter().map(|p| p.x).collect();
        assert!((apply(&one, &one) - mesh.total_area()).abs() < ROUNDING);
        // ∫ x = 12.5 · 3.5 (x ranges over [0, 5], y over [0, 3.5]).
        assert!((apply(&one, &x) - 12.5 * 3.5).abs() < ROUNDING * 100.0);
        // ∫ x² = (125 / 3) · 3.5: exact for the linear x on each triangle.
        assert!((apply(&x, &x) - 125.0 / 3.0 * 3.5).abs() < ROUNDING * 100.0);
    }

    #[test]
    fn unreferenced_vertex_has_empty_row() {
        let v = pts(&[(0., 0.), (1., 0.), (0., 1.), (9., 9.)]);
        let mesh = TriMesh::new(v, vec![[0, 1, 2]]).unwrap();
        let q = Csc::from_faer(&polyharmonic_energy(&mesh, 2));
        assert!(q.column(3).0.is_empty());
        assert_eq!(lumped_mass(&mesh, MassKind::Voronoi)[3], 0.0);
    }
}
