//! Quadrature of the limit surface: Gauss nodes on every face with their limit stencils `m_p`,
//! and the Gram matrices of the subdivision-surface fit (DESIGN.md §3; Liu et al. 2014 §3):
//!
//! ```text
//! Â  = ∫ m_p m_pᵀ dp            ≈ Σ_k ω_k m_k m_kᵀ            (N × N, sparse, SPD)
//! Â_f = ∫ f(p) m_p m_pᵀ dp      ≈ Σ_k ω_k f(p_k) m_k m_kᵀ      (f = w_i ∘ G for Ŵ_i = C̄ Â_f)
//! ```
//!
//! `N` is the number of cage vertices, `m_k` the limit stencil at node `k`. Both use the same
//! nodes ([`LimitQuadrature::weighted_gram`] with `f ≡ 1` *is* [`LimitQuadrature::gram`]), so
//! when the handle weights sum to one, `Σ_i Ŵ_i = C̄ Â` holds to rounding and the identity pose
//! reproduces the cage exactly, whatever the quadrature error.
//!
//! # The measure `dp`
//!
//! Parametric, as in the paper (uniform samples per face): each ptex face (a quad face, or
//! each of an n-gon's `n` sub-faces) is the unit square with area 1, and gets the tensor
//! `n × n` Gauss–Legendre rule on it. On a regular face `m_p` is bicubic, so `m_p m_pᵀ` has
//! degree 6 per axis and 4 nodes per axis integrate it exactly
//! ([`DEFAULT_GAUSS_POINTS`]); on faces next to extraordinary vertices the rule converges as
//! the number of nodes grows. Gauss nodes are interior (the nearest is `0.069` from a corner
//! for 4 nodes), so every node lies on a regular patch after a few levels of refinement:
//! [`LimitQuadrature::for_cage`] refines only that deep (isolation 4 or 5 on all of
//! OpenSubdiv's regression shapes, against 10 by default), which makes the rig's
//! precomputation several times cheaper on cages with semi-sharp creases. Hole faces have no
//! surface and no nodes.

use faer::sparse::{SparseColMat, SymbolicSparseColMat};

use super::cage::{Cage, Point3};
use super::error::SubdivError;
use super::limit::{LimitOptions, LimitSurface, SurfaceLocation, DEFAULT_ISOLATION_LEVEL};
use super::stencil::LimitStencil;
use splineskin_core::bezier::gauss_legendre;

/// Gauss–Legendre nodes per axis per ptex face by default: 4, the fewest that integrate the
/// product of two bicubic B-spline bases (degree 6 per axis) exactly on regular faces.
pub const DEFAULT_GAUSS_POINTS: usize = 4;

/// A quadrature node: a location on the surface and its weight (parametric area).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadratureNode {
    /// Where.
    pub location: SurfaceLocation,
    /// The weight `ω_k`; the weights of one ptex face sum to 1.
    pub weight: f64,
}

/// Gauss nodes on every non-hole ptex face of a cage with their limit stencils. Built once per
/// topology (the stencils do not depend on positions).
///
/// ```
/// use splineskin_subdiv::{parse_obj, LimitOptions, LimitQuadrature, LimitSurface};
///
/// let cube = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
///             f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
/// let cage = parse_obj(cube, "cube.obj")?;
/// let surface = LimitSurface::new(&cage, &LimitOptions::default())?;
/// let q = LimitQuadrature::new(&surface, 4)?;
/// assert_eq!(q.n_nodes(), 6 * 16);
/// let a = q.gram();
/// // Σ_ij Â_ij = ∫ (Σ_j m_j)² dp = the total parametric area: 6 faces of area 1.
/// let total: f64 = a.val().iter().sum();
/// assert!((total - 6.0).abs() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct LimitQuadrature {
    n_control: usize,
    nodes: Vec<QuadratureNode>,
    stencils: Vec<LimitStencil>,
}

impl LimitQuadrature {
    /// Places `n_per_axis × n_per_axis` Gauss–Legendre nodes on every non-hole ptex face of
    /// `surface`'s cage, face by face (sub-faces in order, `v` slower than `u`), and computes
    /// their limit stencils.
    pub fn new(surface: &LimitSurface, n_per_axis: usize) -> Result<Self, SubdivError> {
        if n_per_axis == 0 {
            return Err(SubdivError::BadQuadrature {
                what: "0 nodes per axis; expected at least 1".into(),
            });
        }
        let (t, w) = gauss_legendre(n_per_axis);
        let mut nodes = Vec::new();
        for face in 0..surface.n_faces() as u32 {
            if surface.is_hole(face) {
                continue;
            }
            for subface in 0..surface.n_subfaces(face) {
                for (v, wv) in t.iter().zip(&w) {
                    for (u, wu) in t.iter().zip(&w) {
                        nodes.push(QuadratureNode {
                            location: SurfaceLocation {
                                face,
                                subface,
                                u: *u,
                                v: *v,
                            },
                            weight: wu * wv,
                        });
                    }
                }
            }
        }
        let locations: Vec<SurfaceLocation> = nodes.iter().map(|n| n.location).collect();
        let stencils = surface.stencils(&locations)?;
        Ok(LimitQuadrature {
            n_control: surface.n_control(),
            nodes,
            stencils,
        })
    }

    /// The quadrature of `cage` with `n_per_axis²` nodes per ptex face, on a limit surface
    /// refined only as deep as the nodes need (returned with it): the shallowest isolation
    /// level at which every node lies on a regular patch, so that every stencil is exact
    /// (module documentation) — the same stencils as at [`DEFAULT_ISOLATION_LEVEL`], at a
    /// fraction of the refinement (a rook refined once: isolation 4 instead of 10, its
    /// surface built 15 times faster).
    ///
    /// The search starts at `⌈log₂(1/t₀)⌉`, `t₀` the rule's node nearest a ptex corner (4 for
    /// 4 nodes per axis: a level-4 face next to an irregular corner no longer holds a node),
    /// and goes one level deeper while a node nearest a corner of some ptex face
    /// ([`LimitSurface::is_exact_at`]) is not on a regular patch. Should a node farther in
    /// still not be exact, the surface is refined to [`DEFAULT_ISOLATION_LEVEL`] after all.
    /// Shapes whose nodes are not all exact even there (none of OpenSubdiv's regression shapes)
    /// keep the default's corner approximation.
    ///
    /// Grid samples on ptex edges (a [`LimitMesh`](super::LimitMesh)) may need deeper
    /// isolation than nodes do: sample those on a surface at the default level.
    ///
    /// ```
    /// use splineskin_subdiv::{parse_obj, LimitQuadrature, DEFAULT_GAUSS_POINTS};
    /// let cube = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
    ///             f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
    /// let cage = parse_obj(cube, "cube.obj")?;
    /// let (surface, q) = LimitQuadrature::for_cage(&cage, DEFAULT_GAUSS_POINTS)?;
    /// assert_eq!(surface.isolation_level(), 4);
    /// assert!((0..q.n_nodes()).all(|k| q.stencil(k).exact));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn for_cage(
        cage: &Cage,
        n_per_axis: usize,
    ) -> Result<(LimitSurface, LimitQuadrature), SubdivError> {
        if n_per_axis == 0 {
            return Err(SubdivError::BadQuadrature {
                what: "0 nodes per axis; expected at least 1".into(),
            });
        }
        let (t, _) = gauss_legendre(n_per_axis);
        let (first, last) = (t[0], t[n_per_axis - 1]);
        let start = ((1.0 / first).log2().ceil() as usize).clamp(1, DEFAULT_ISOLATION_LEVEL);
        let mut chosen = None;
        for isolation in start..=DEFAULT_ISOLATION_LEVEL {
            let surface = LimitSurface::new(
                cage,
                &LimitOptions::default().with_isolation_level(isolation),
            )?;
            if isolation == DEFAULT_ISOLATION_LEVEL || corners_exact(&surface, first, last)? {
                chosen = Some(surface);
                break;
            }
        }
        let surface = chosen.ok_or_else(|| SubdivError::Internal {
            what: "no isolation level was tried".into(),
        })?;
        let quadrature = LimitQuadrature::new(&surface, n_per_axis)?;
        if surface.isolation_level() < DEFAULT_ISOLATION_LEVEL
            && (0..quadrature.n_nodes()).any(|k| !quadrature.stencil(k).exact)
        {
            let surface = LimitSurface::new(cage, &LimitOptions::default())?;
            let quadrature = LimitQuadrature::new(&surface, n_per_axis)?;
            return Ok((surface, quadrature));
        }
        Ok((surface, quadrature))
    }

    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.nodes.len()
    }

    /// Number of cage vertices the stencils refer to (`N`).
    pub fn n_control(&self) -> usize {
        self.n_control
    }

    /// The nodes, in the order of [`LimitQuadrature::new`].
    pub fn nodes(&self) -> &[QuadratureNode] {
        &self.nodes
    }

    /// The limit stencil `m_k` of node `k`.
    pub fn stencil(&self, k: usize) -> &LimitStencil {
        &self.stencils[k]
    }

    /// The limit positions `G(p_k)` of all nodes for the cage positions `control`, into `out`
    /// (`n_nodes` long): where handle weights are evaluated for [`Self::weighted_gram`].
    ///
    /// # Panics
    /// If `control.len() != n_control()` or `out.len() != n_nodes()`.
    pub fn positions(&self, control: &[Point3], out: &mut [Point3]) {
        assert_eq!(
            control.len(),
            self.n_control,
            "control: expected n_control() points"
        );
        assert_eq!(out.len(), self.n_nodes(), "out: expected n_nodes() points");
        for (o, st) in out.iter_mut().zip(&self.stencils) {
            *o = st.position(control);
        }
    }

    /// `Â = Σ_k ω_k m_k m_kᵀ` (N × N, symmetric).
    pub fn gram(&self) -> SparseColMat<usize, f64> {
        self.assemble(|_| 1.0)
    }

    /// `Σ_k ω_k f_k m_k m_kᵀ` with one value `f_k` per node (for `Ŵ_i`, `f_k = w_i(G(p_k))`).
    ///
    /// # Panics
    /// If `f.len() != n_nodes()`.
    pub fn weighted_gram(&self, f: &[f64]) -> SparseColMat<usize, f64> {
        assert_eq!(f.len(), self.n_nodes(), "f: expected one value per node");
        self.assemble(|k| f[k])
    }

    /// Sums the nodes' outer products ptex face by ptex face in a small dense block over the
    /// face's support (upper triangle, mirrored), then assembles the sparse matrix column by
    /// column: column `j` is the sum of the rows of `j` in every block holding `j`, blocks in
    /// face order, so that entries `(i, j)` and `(j, i)` are the same sums in the same order
    /// and the matrix is exactly symmetric.
    fn assemble(&self, f: impl Fn(usize) -> f64) -> SparseColMat<usize, f64> {
        let n = self.n_control;
        // The blocks: supports (sorted vertices) and dense symmetric values, one per ptex face.
        let mut supports: Vec<u32> = Vec::new();
        let mut support_offsets = vec![0usize];
        let mut values: Vec<f64> = Vec::new();
        let mut value_offsets = vec![0usize];
        let mut local: Vec<usize> = Vec::new();
        let mut start = 0;
        while start < self.nodes.len() {
            let here = (
                self.nodes[start].location.face,
                self.nodes[start].location.subface,
            );
            let end = start
                + self.nodes[start..]
                    .iter()
                    .take_while(|n| (n.location.face, n.location.subface) == here)
                    .count();
            let first = supports.len();
            for st in &self.stencils[start..end] {
                supports.extend_from_slice(&st.indices);
            }
            supports[first..].sort_unstable();
            let m = {
                let mut tail = supports.split_off(first);
                tail.dedup();
                let m = tail.len();
                supports.append(&mut tail);
                m
            };
            let support = &supports[first..];
            let block_start = values.len();
            values.resize(block_start + m * m, 0.0);
            let block = &mut values[block_start..];
            for k in start..end {
                let st = &self.stencils[k];
                let scale = self.nodes[k].weight * f(k);
                local.clear();
                local.extend(
                    st.indices
                        .iter()
                        .map(|i| support.binary_search(i).unwrap_or(0)),
                );
                for (a, &ia) in local.iter().enumerate() {
                    let wa = scale * st.weights[a];
                    for (b, &ib) in local.iter().enumerate() {
                        if ia <= ib {
                            block[ia * m + ib] += wa * st.weights[b];
                        }
                    }
                }
            }
            for a in 0..m {
                for b in 0..a {
                    block[a * m + b] = block[b * m + a];
                }
            }
            support_offsets.push(supports.len());
            value_offsets.push(values.len());
            start = end;
        }
        let n_blocks = support_offsets.len() - 1;
        // Blocks holding each vertex, with its local index there, in block order.
        let mut count = vec![0usize; n + 1];
        for &v in &supports {
            count[v as usize + 1] += 1;
        }
        for v in 0..n {
            count[v + 1] += count[v];
        }
        let mut at = count.clone();
        let mut incidence = vec![(0u32, 0u32); supports.len()];
        for b in 0..n_blocks {
            for (a, &v) in supports[support_offsets[b]..support_offsets[b + 1]]
                .iter()
                .enumerate()
            {
                incidence[at[v as usize]] = (b as u32, a as u32);
                at[v as usize] += 1;
            }
        }
        let mut accumulator = vec![0.0; n];
        let mut marker = vec![usize::MAX; n];
        let mut touched: Vec<usize> = Vec::new();
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        let mut entries = Vec::new();
        col_ptr.push(0);
        for j in 0..n {
            for &(b, a) in &incidence[count[j]..count[j + 1]] {
                let (b, a) = (b as usize, a as usize);
                let support = &supports[support_offsets[b]..support_offsets[b + 1]];
                let m = support.len();
                let row = &values[value_offsets[b] + a * m..][..m];
                for (&i, &x) in support.iter().zip(row) {
                    let i = i as usize;
                    if marker[i] != j {
                        marker[i] = j;
                        touched.push(i);
                    }
                    accumulator[i] += x;
                }
            }
            touched.sort_unstable();
            for &i in &touched {
                if accumulator[i] != 0.0 {
                    row_idx.push(i);
                    entries.push(accumulator[i]);
                }
                accumulator[i] = 0.0;
            }
            touched.clear();
            col_ptr.push(row_idx.len());
        }
        let symbolic = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        SparseColMat::new(symbolic, entries)
    }
}

/// Are the nodes nearest the four corners of every ptex face (at `first`, `last` per axis) on
/// regular patches of `surface`?
fn corners_exact(surface: &LimitSurface, first: f64, last: f64) -> Result<bool, SubdivError> {
    for face in 0..surface.n_faces() as u32 {
        if surface.is_hole(face) {
            continue;
        }
        for subface in 0..surface.n_subfaces(face) {
            for (u, v) in [(first, first), (last, first), (first, last), (last, last)] {
                if !surface.is_exact_at(SurfaceLocation {
                    face,
                    subface,
                    u,
                    v,
                })? {
                    return Ok(false);
                }
            }
        }
    }
    Ok(true)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{parse_obj, LimitOptions};

    /// An `n × n` torus of unit quads in the plane-wrapped grid: every vertex has valence 4,
    /// every face is a regular B-spline patch.
    fn torus(n: usize) -> crate::Cage {
        let mut text = String::new();
        for j in 0..n {
            for i in 0..n {
                let (a, b) = (
                    std::f64::consts::TAU * i as f64 / n as f64,
                    std::f64::consts::TAU * j as f64 / n as f64,
                );
                let r = 3.0 + b.cos();
                text += &format!("v {} {} {}\n", r * a.cos(), r * a.sin(), b.sin());
            }
        }
        let id = |i: usize, j: usize| (j % n) * n + (i % n) + 1;
        for j in 0..n {
            for i in 0..n {
                text += &format!(
                    "f {} {} {} {}\n",
                    id(i, j),
                    id(i + 1, j),
                    id(i + 1, j + 1),
                    id(i, j + 1)
                );
            }
        }
        parse_obj(&text, "torus.obj").unwrap()
    }

    fn dense(m: &SparseColMat<usize, f64>) -> faer::Mat<f64> {
        m.to_dense()
    }

    #[test]
    fn quadrature_four_points_exact_on_regular_faces() {
        let cage = torus(6);
        let surface = LimitSurface::new(&cage, &LimitOptions::default()).unwrap();
        let a4 = dense(&LimitQuadrature::new(&surface, 4).unwrap().gram());
        let a7 = dense(&LimitQuadrature::new(&surface, 7).unwrap().gram());
        let a3 = dense(&LimitQuadrature::new(&surface, 3).unwrap().gram());
        let diff = |x: &faer::Mat<f64>, y: &faer::Mat<f64>| {
            let mut m = 0.0f64;
            for j in 0..x.ncols() {
                for i in 0..x.nrows() {
                    m = m.max((x[(i, j)] - y[(i, j)]).abs());
                }
            }
            m
        };
        // Degree 6 per axis: 4 nodes are exact, 3 are not.
        assert!(diff(&a4, &a7) < 1e-15, "{}", diff(&a4, &a7));
        assert!(diff(&a3, &a7) > 1e-6, "{}", diff(&a3, &a7));
        // On the regular torus every Â row is the same bicubic B-spline stencil:
        // ∫ N(s) N(s − k) over the line for k = 0..3 is 151/315, 397/1680, 1/42, 1/5040.
        let row0: f64 = 151.0 / 315.0;
        assert!((a4[(0, 0)] - row0 * row0).abs() < 1e-14, "{}", a4[(0, 0)]);
    }

    #[test]
    fn quadrature_gram_spd_and_partition_of_unity() {
        let cube = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
                    f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
        let cage = parse_obj(cube, "cube.obj").unwrap();
        let surface = LimitSurface::new(&cage, &LimitOptions::default()).unwrap();
        let q = LimitQuadrature::new(&surface, DEFAULT_GAUSS_POINTS).unwrap();
        let a = dense(&q.gram());
        // Σ_j m_j = 1 at every node: every row of Â sums to ∫ m_i dp, and those to the area.
        let total: f64 = (0..8)
            .flat_map(|i| (0..8).map(move |j| (i, j)))
            .map(|(i, j)| a[(i, j)])
            .sum();
        assert!((total - 6.0).abs() < 1e-13, "{total}");
        // By symmetry of the cube every vertex gets the same share.
        for i in 0..8 {
            let row: f64 = (0..8).map(|j| a[(i, j)]).sum();
            assert!((row - 0.75).abs() < 1e-13, "{row}");
            for j in 0..8 {
                assert_eq!(a[(i, j)], a[(j, i)]);
            }
        }
        assert!(a.llt(faer::Side::Lower).is_ok(), "Â is positive definite");
        // The weighted Gram with f ≡ 1 is Â, bit for bit.
        let ones = vec![1.0; q.n_nodes()];
        assert_eq!(dense(&q.weighted_gram(&ones)), a);
        // ∫ G(p) dp = Pᵀ Â 1: the centroid of the cube's limit surface is its centre.
        let mut g = vec![[0.0; 3]; q.n_nodes()];
        q.positions(cage.positions(), &mut g);
        let mut centre = [0.0; 3];
        for (node, p) in q.nodes().iter().zip(&g) {
            for k in 0..3 {
                centre[k] += node.weight * p[k] / 6.0;
            }
        }
        for c in centre {
            assert!((c - 0.5).abs() < 1e-14, "{centre:?}");
        }
    }
}
