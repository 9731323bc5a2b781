//! The linearly precise squared-Laplacian energy of Wang, Jacobson, Barbič & Kavan 2015
//! (*Linear Subspace Design for Real-Time Shape Deformation*, §3), discretised with
//! Crouzeix–Raviart (edge-midpoint) elements as libigl's `biharmonic_coordinates` does.
//!
//! The paper's vertex-based `K = L + N` (Laplacian plus boundary normal derivative) is not used:
//! its erratum (linked from the paper's page) and a comment in libigl's source call it wrong,
//! and libigl 2.6.3 builds instead, for a mesh with edges `E`:
//!
//! ```text
//! L_CR   #E × #E   Crouzeix–Raviart stiffness: for the edges e_a, e_b of a triangle meeting at
//!                  its corner c, L_CR[e_a, e_b] += 2 cot θ_c; L_CR[e, e] = −Σ off-diagonal
//! M_CR   #E        Crouzeix–Raviart mass, exact and diagonal: Σ_{t ∋ e} A_t / 3
//! Avg    #E × #V   edge ← vertex averaging: Avg[e, v] = ½ for the two ends v of e
//! K      = L_CR · Avg                          (#E × #V)
//! W      = M_CR⁻¹ on interior edges, 0 on boundary edges
//! A      = Kᵀ W K                              (#V × #V, symmetric positive semidefinite)
//! ```
//!
//! A Crouzeix–Raviart basis function is `ψ_a = 1 − 2 φ_a` on a triangle (`φ_a` the hat of the
//! corner opposite edge `e_a`), so `∫ ∇ψ_a·∇ψ_b = 4 ∫ ∇φ_a·∇φ_b = −2 cot θ_c`: `L_CR` is the
//! stiffness matrix in libigl's sign convention (negative semidefinite). For a linear function
//! `w`, `(K w)_e = −∫ ∇ψ_e·∇w` vanishes on every interior edge (`ψ_e` has zero mean on the
//! patch's other edges), so `A` kills the linear functions: the minimisers of `wᵀ A w` with
//! prescribed values reproduce linear data exactly (linear precision). Boundary edges get no
//! weight: there the energy would impose a natural boundary condition that linear functions
//! do not meet. Scaling `M_CR` (libigl divides it by its largest entry) scales `A` and does not
//! change any minimiser; it is not done here.

use super::TriMesh;
use crate::linalg::Csc;

/// The edges of a mesh and, per triangle corner, the edge opposite it.
#[derive(Clone, Debug, PartialEq)]
pub struct Edges {
    /// Each undirected edge once, as `[smaller vertex, larger vertex]`, sorted.
    pub ends: Vec<[usize; 2]>,
    /// `opposite[t][c]`: the edge of triangle `t` opposite its corner `c`.
    pub opposite: Vec<[usize; 3]>,
    /// Number of triangles holding each edge (1 on the boundary, 2 inside).
    pub n_triangles: Vec<u8>,
}

impl Edges {
    /// Enumerates the edges of `mesh` (a valid mesh: every edge in one or two triangles).
    pub fn new(mesh: &TriMesh) -> Edges {
        let mut corners: Vec<([usize; 2], usize, usize)> =
            Vec::with_capacity(3 * mesh.n_triangles());
        for (t, tri) in mesh.triangles.iter().enumerate() {
            for c in 0..3 {
                let (a, b) = (tri[(c + 1) % 3], tri[(c + 2) % 3]);
                corners.push(([a.min(b), a.max(b)], t, c));
            }
        }
        corners.sort_unstable();
        let mut ends: Vec<[usize; 2]> = Vec::new();
        let mut n_triangles: Vec<u8> = Vec::new();
        let mut opposite = vec![[0usize; 3]; mesh.n_triangles()];
        for (key, t, c) in corners {
            if ends.last() != Some(&key) {
                ends.push(key);
                n_triangles.push(0);
            }
            let e = ends.len() - 1;
            n_triangles[e] = n_triangles[e].saturating_add(1);
            opposite[t][c] = e;
        }
        Edges {
            ends,
            opposite,
            n_triangles,
        }
    }

    /// Number of edges.
    pub fn n_edges(&self) -> usize {
        self.ends.len()
    }
}

/// The linearly precise energy `A = Kᵀ W K` of the module doc (`n_vertices × n_vertices`,
/// full symmetric storage, sorted rows). A vertex in no triangle gets an empty row and column.
/// The mesh must be valid ([`TriMesh::check`]).
pub fn linearly_precise_energy_csc(mesh: &TriMesh) -> Csc {
    let edges = Edges::new(mesh);
    let n_edges = edges.n_edges();
    // M_CR: a third of each triangle's area to each of its edges.
    let mut mass = vec![0.0; n_edges];
    // L_CR, row by row: up to four off-diagonal entries per edge (the other edges of its one
    // or two triangles) and the diagonal.
    let mut stiffness: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n_edges];
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let p = tri.map(|i| mesh.vertices[i]);
        let double_area = (p[1] - p[0]).cross(p[2] - p[0]);
        for c in 0..3 {
            mass[edges.opposite[t][c]] += double_area / 6.0;
            // The edges opposite corners c + 1 and c + 2 meet at corner c.
            let o = p[c];
            let (u, v) = (p[(c + 1) % 3] - o, p[(c + 2) % 3] - o);
            let weight = 2.0 * u.dot(v) / double_area; // 2 cot θ_c
            let (ea, eb) = (
                edges.opposite[t][(c + 1) % 3],
                edges.opposite[t][(c + 2) % 3],
            );
            stiffness[ea].push((eb, weight));
            stiffness[eb].push((ea, weight));
            stiffness[ea].push((ea, -weight));
            stiffness[eb].push((eb, -weight));
        }
    }
    // Each interior edge's row of K = L_CR · Avg, then its outer product into A.
    let mut triplets: Vec<(usize, usize, f64)> = Vec::new();
    let mut row: Vec<(usize, f64)> = Vec::new();
    for e in 0..n_edges {
        if edges.n_triangles[e] != 2 {
            continue; // boundary edge: W = 0
        }
        row.clear();
        for &(f, l) in &stiffness[e] {
            for v in edges.ends[f] {
                row.push((v, 0.5 * l));
            }
        }
        row.sort_unstable_by_key(|&(v, _)| v);
        let mut merged: Vec<(usize, f64)> = Vec::with_capacity(row.len());
        for &(v, x) in &row {
            match merged.last_mut() {
                Some((last, sum)) if *last == v => *sum += x,
                _ => merged.push((v, x)),
            }
        }
        let w = 1.0 / mass[e];
        for &(v, kv) in &merged {
            for &(u, ku) in &merged {
                triplets.push((u, v, kv * w * ku));
            }
        }
    }
    Csc::from_triplets(mesh.n_vertices(), triplets)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support::pts;
    use kurbo::{Point, Rect};

    #[test]
    fn edges_of_two_triangles() {
        let v = pts(&[(0., 0.), (1., 0.), (1., 1.), (0., 1.)]);
        let mesh = TriMesh::new(v, vec![[0, 1, 2], [0, 2, 3]]).unwrap();
        let edges = Edges::new(&mesh);
        assert_eq!(edges.ends, vec![[0, 1], [0, 2], [0, 3], [1, 2], [2, 3]]);
        assert_eq!(edges.n_triangles, vec![1, 2, 1, 1, 1]);
        // Triangle 0 = (0, 1, 2): corner 0 faces edge (1, 2), corner 1 faces (0, 2).
        assert_eq!(edges.opposite[0], [3, 1, 0]);
    }

    #[test]
    fn linearly_precise_energy_kills_linear_functions_only() {
        let mut mesh = TriMesh::grid(Rect::new(0., 0., 2., 1.), 8, 4).unwrap();
        // Jitter the interior so no two triangles are alike.
        for (i, p) in mesh.vertices.iter_mut().enumerate() {
            if p.x > 0.0 && p.x < 2.0 && p.y > 0.0 && p.y < 1.0 {
                p.x += 0.03 * ((i * 37 % 11) as f64 / 11.0 - 0.5);
                p.y += 0.03 * ((i * 53 % 7) as f64 / 7.0 - 0.5);
            }
        }
        mesh.check().unwrap();
        let a = linearly_precise_energy_csc(&mesh).into_faer().to_dense();
        let n = mesh.n_vertices();
        let apply = |w: &[f64]| -> Vec<f64> {
            (0..n)
                .map(|i| (0..n).map(|j| a[(i, j)] * w[j]).sum())
                .collect()
        };
        let scale = (0..n).map(|i| a[(i, i)]).fold(0.0, f64::max);
        for f in [
            |p: Point| 1.0 + 0.0 * p.x,
            |p: Point| p.x,
            |p: Point| 2.0 * p.y - p.x,
        ] {
            let w: Vec<f64> = mesh.vertices.iter().map(|&p| f(p)).collect();
            let aw = apply(&w);
            let worst = aw.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            assert!(worst < 1e-12 * scale, "A w = {worst:e} for a linear w");
        }
        // A quadratic is not in the null space; A is symmetric.
        let w: Vec<f64> = mesh.vertices.iter().map(|p| p.x * p.x).collect();
        let energy: f64 = w.iter().zip(apply(&w)).map(|(a, b)| a * b).sum();
        assert!(energy > 1e-3 * scale);
        for i in 0..n {
            for j in 0..n {
                assert!((a[(i, j)] - a[(j, i)]).abs() <= 1e-12 * scale);
            }
        }
    }
}
