//! Skinning a Catmull–Clark cage so that its **limit surface** follows the skinned limit
//! surface (Liu, Jacobson & Gingold 2014 §3, Table 2; DESIGN.md §3).
//!
//! The limit surface is `G(p) = C m_p` (`C` the 3 × N cage positions, `m_p` the limit stencil).
//! Skinning it with handle weights `w_i` and affine maps `T_i` (3 × 4) gives
//! `s(p) = Σ_i w_i(G(p)) T_i Ḡ(p)`, `Ḡ = (G, 1)`, which is no subdivision surface. The new cage
//! `C'` minimises `∫ ‖C' m_p − s(p)‖² dp`:
//!
//! ```text
//! C' Â = Σ_i T_i Ŵ_i,   Â = ∫ m_p m_pᵀ dp  (N × N),   Ŵ_i = C̄ ∫ w_i(G(p)) m_p m_pᵀ dp  (4 × N)
//! ```
//!
//! so `C'ᵀ = Σ_i B_i T_iᵀ` with `B_i = Â⁻¹ Ŵ_iᵀ` (N × 4), and `Ŵ_iᵀ = ∫ w_i m_p Ḡ(p)ᵀ dp` is
//! accumulated directly from the quadrature nodes (no N × N matrix per handle).
//!
//! ```text
//! once:        cage + LimitQuadrature + node weights ──► SubdivRig::precompute (one sparse
//!              Cholesky of Â, 4h solves) ──► B = [B_1 … B_h]  (N × 4h)
//! each frame:  transforms T_i ──► rig.update(&T, &mut cage_positions)   (C'ᵀ = Σ_i B_i T_iᵀ)
//! ```
//!
//! # `Â` can be singular
//!
//! Catmull–Clark limit functions are not always linearly independent: on a cube (all vertices
//! of valence 3) the alternating pattern `±1` has zero face points, edge points and vertex
//! points after one step, so its limit function is zero and `Â` has a zero eigenvalue; larger
//! cages have near-dependences around extraordinary vertices. The fit then does not determine
//! the cage. It is completed by a small pull towards the cage skinned directly,
//! `C_ref,v = Σ_i w_iv T_i P̄_v`, with the *projected* vertex weights
//! `w_iv = ∫ w_i m_v dp / ∫ m_v dp` (which sum to one when the `w_i` do):
//!
//! ```text
//! minimise  ∫ ‖C' m_p − s(p)‖² dp + ε Σ_v Â_vv ‖C'_v − C_ref,v‖²,   ε = RIG_REGULARIZATION
//! ```
//!
//! still linear in the `T_i`. Where `Â` is regular the pull changes the fit by a fraction of
//! order `ε`; in its null space it picks the skinned cage.
//!
//! `Â`, every `Ŵ_i` and the projected weights use the same nodes ([`LimitQuadrature`]): when
//! the weights sum to one at every node, `Σ_i Ŵ_i = C̄ Â` and `C_ref` is the cage under the
//! identity (its affine image under one common map), so the identity pose gives back the cage
//! and one affine map on every handle gives that map of the cage. The solve leaves a defect in
//! `Σ_i B_i = P̄` of order `1e-16/ε` where `Â` is nearly singular; when the weights form a
//! partition of unity, precompute hands it back to the handles by their projected weights, so
//! both invariants hold to rounding.

use super::affine3::Affine3;
use super::cage::{Cage, Point3};
use super::error::SubdivError;
use super::quadrature::LimitQuadrature;
use splineskin_core::linalg::{solve_spd_in_place, Csc};

/// Weight `ε` of the regularisation, relative to the diagonal of `Â` (module documentation):
/// small enough that the fit to the skinned surface changes by about that fraction, large
/// enough that the solve loses at most about 6 of f64's 16 digits where `Â` is singular.
pub const RIG_REGULARIZATION: f64 = 1e-6;

/// How far from one the handle weights at a node may sum for [`SubdivRig::precompute`] to treat
/// them as a partition of unity (and make the identity pose exact to rounding): a few ulps of
/// a normalised sum.
const PARTITION_TOLERANCE: f64 = 1e-12;

/// A precomputed subdivision-surface rig (module documentation): `update` is `h` products of
/// `N × 4` by `4 × 3` and allocates nothing.
///
/// ```
/// use splineskin_subdiv::{parse_obj, LimitOptions, LimitQuadrature, LimitSurface, SubdivRig, AFFINE3_IDENTITY};
///
/// let cube = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
///             f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
/// let cage = parse_obj(cube, "cube.obj")?;
/// let surface = LimitSurface::new(&cage, &LimitOptions::default())?;
/// let quadrature = LimitQuadrature::new(&surface, 4)?;
/// // Two handles: weight of the first falls linearly from z = 0 to z = 1.
/// let mut g = vec![[0.0; 3]; quadrature.n_nodes()];
/// quadrature.positions(cage.positions(), &mut g);
/// let weights: Vec<f64> = g.iter().flat_map(|p| [1.0 - p[2], p[2]]).collect();
/// let rig = SubdivRig::precompute(&cage, &quadrature, &weights, 2)?;
///
/// // Move the second handle up by 1: the top of the cage follows, the bottom less so.
/// let mut up = AFFINE3_IDENTITY;
/// up[2][3] = 1.0;
/// let mut deformed = vec![[0.0; 3]; cage.n_vertices()];
/// rig.update(&[AFFINE3_IDENTITY, up], &mut deformed)?;
/// assert!(deformed[6][2] > 1.5 && deformed[0][2] < 0.5);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct SubdivRig {
    n_vertices: usize,
    n_handles: usize,
    /// `B`, vertex-major: `b[v·4h + 4i + c]` is row `v`, column `c` of `B_i`.
    b: Vec<f64>,
}

impl SubdivRig {
    /// Precomputes the rig of `cage` for `n_handles` handles. `node_weights` holds
    /// `w_i(G(p_k))` for every node `k` of `quadrature` (in its order) and handle `i`,
    /// node-major (`n_nodes · n_handles` values, `[k · n_handles + i]`); evaluate them at the
    /// node positions of [`LimitQuadrature::positions`].
    ///
    /// Errors: sizes that do not match, non-finite weights, and a cage vertex that no limit
    /// stencil uses (a vertex of no face: `Â` is then singular and the fit cannot place it).
    pub fn precompute(
        cage: &Cage,
        quadrature: &LimitQuadrature,
        node_weights: &[f64],
        n_handles: usize,
    ) -> Result<Self, SubdivError> {
        let n = cage.n_vertices();
        let n_nodes = quadrature.n_nodes();
        let bad = |what: String| SubdivError::BadRig { what };
        if quadrature.n_control() != n {
            return Err(bad(format!(
                "the quadrature is for {} vertices, the cage has {n}",
                quadrature.n_control()
            )));
        }
        if n_handles == 0 {
            return Err(bad("no handle; expected at least one".into()));
        }
        if node_weights.len() != n_nodes * n_handles {
            return Err(bad(format!(
                "{} node weights; expected n_nodes · n_handles = {n_nodes} · {n_handles}",
                node_weights.len()
            )));
        }
        if let Some(k) = node_weights.iter().position(|w| !w.is_finite()) {
            return Err(bad(format!(
                "weight of handle {} at node {} is {}; expected a finite number",
                k % n_handles,
                k / n_handles,
                node_weights[k]
            )));
        }
        let gram = quadrature.gram();
        let mut diagonal = vec![0.0; n];
        for (v, d) in diagonal.iter_mut().enumerate() {
            let col = gram.col_range(v);
            let rows = &gram.symbolic().row_idx()[col.clone()];
            *d = rows
                .iter()
                .position(|&r| r == v)
                .map_or(0.0, |k| gram.val()[col.start + k]);
        }
        // Ŵ_iᵀ = Σ_k ω_k w_ik m_k Ḡ_kᵀ, stored column-major as the right-hand sides (N × 4h);
        // alongside, the numerator and denominator of the projected vertex weights.
        let width = 4 * n_handles;
        let mut rhs = vec![0.0; n * width];
        let mut projected = vec![0.0; n * n_handles];
        let mut support = vec![0.0; n];
        let mut g = vec![[0.0; 3]; n_nodes];
        quadrature.positions(cage.positions(), &mut g);
        for (k, node) in quadrature.nodes().iter().enumerate() {
            let st = quadrature.stencil(k);
            let gbar = [g[k][0], g[k][1], g[k][2], 1.0];
            for (&v, &m) in st.indices.iter().zip(&st.weights) {
                support[v as usize] += node.weight * m;
            }
            for i in 0..n_handles {
                let scale = node.weight * node_weights[k * n_handles + i];
                if scale == 0.0 {
                    continue;
                }
                for (&v, &m) in st.indices.iter().zip(&st.weights) {
                    projected[v as usize * n_handles + i] += scale * m;
                    for (c, &gc) in gbar.iter().enumerate() {
                        rhs[(4 * i + c) * n + v as usize] += scale * m * gc;
                    }
                }
            }
        }
        // The regularisation towards the cage skinned with the projected weights (module
        // documentation): ε·diag(Â) on the left, ε·diag(Â)·w_iv·P̄_v on the right.
        for v in 0..n {
            if diagonal[v] <= 0.0 || support[v] <= 0.0 {
                return Err(bad(format!(
                    "cage vertex {v} has no influence on the limit surface (no face, or only \
                     hole faces around it); the fit cannot place it"
                )));
            }
            let pbar = {
                let p = cage.positions()[v];
                [p[0], p[1], p[2], 1.0]
            };
            let pull = RIG_REGULARIZATION * diagonal[v];
            for i in 0..n_handles {
                let w = projected[v * n_handles + i] / support[v];
                for (c, &pc) in pbar.iter().enumerate() {
                    rhs[(4 * i + c) * n + v] += pull * w * pc;
                }
            }
        }
        solve_gram(&gram, &diagonal, &mut rhs)?;
        // Where the weights are a partition of unity, Σ_i B_i = P̄ holds mathematically but
        // only to about 1e-16/ε after the solve: hand the defect back to the handles in
        // proportion to the projected weights, so that it holds to rounding.
        let partition = (0..n_nodes).all(|k| {
            let sum: f64 = node_weights[k * n_handles..][..n_handles].iter().sum();
            (sum - 1.0).abs() <= PARTITION_TOLERANCE
        });
        if partition {
            for v in 0..n {
                let p = cage.positions()[v];
                let pbar = [p[0], p[1], p[2], 1.0];
                for (c, &pc) in pbar.iter().enumerate() {
                    let sum: f64 = (0..n_handles).map(|i| rhs[(4 * i + c) * n + v]).sum();
                    let defect = pc - sum;
                    for i in 0..n_handles {
                        let w = projected[v * n_handles + i] / support[v];
                        rhs[(4 * i + c) * n + v] += w * defect;
                    }
                }
            }
        }
        // Vertex-major for the update.
        let mut b = vec![0.0; n * width];
        for col in 0..width {
            for v in 0..n {
                b[v * width + col] = rhs[col * n + v];
            }
        }
        Ok(SubdivRig {
            n_vertices: n,
            n_handles,
            b,
        })
    }

    /// Number of cage vertices `N`.
    pub fn n_vertices(&self) -> usize {
        self.n_vertices
    }

    /// Number of handles `h`.
    pub fn n_handles(&self) -> usize {
        self.n_handles
    }

    /// `B_i` row `v`: the factors of `T_i`'s four columns in vertex `v`'s new position
    /// (`C'_v = Σ_i T_i · B_i[v]`).
    pub fn coefficients(&self, v: usize, i: usize) -> [f64; 4] {
        let row = &self.b[v * 4 * self.n_handles + 4 * i..][..4];
        [row[0], row[1], row[2], row[3]]
    }

    /// Writes the fitted cage positions `C'ᵀ = Σ_i B_i T_iᵀ` for the handle transforms
    /// `transforms` (`n_handles` long) into `out` (`n_vertices` long). Allocates nothing, also
    /// when it refuses lengths that do not match.
    pub fn update(&self, transforms: &[Affine3], out: &mut [Point3]) -> Result<(), SubdivError> {
        if transforms.len() != self.n_handles {
            return Err(SubdivError::SizeMismatch {
                what: "transforms (one per handle)",
                expected: self.n_handles,
                found: transforms.len(),
            });
        }
        if out.len() != self.n_vertices {
            return Err(SubdivError::SizeMismatch {
                what: "output points (one per cage vertex)",
                expected: self.n_vertices,
                found: out.len(),
            });
        }
        let width = 4 * self.n_handles;
        for (o, row) in out.iter_mut().zip(self.b.chunks_exact(width)) {
            let mut p = [0.0; 3];
            for (t, bi) in transforms.iter().zip(row.chunks_exact(4)) {
                for r in 0..3 {
                    p[r] += t[r][0] * bi[0] + t[r][1] * bi[1] + t[r][2] * bi[2] + t[r][3] * bi[3];
                }
            }
            *o = p;
        }
        Ok(())
    }
}

/// Solves `(Â + ε·diag(Â)) X = R` in place for the columns of `rhs` (column-major, `N` rows)
/// with one sparse Cholesky factorisation.
fn solve_gram(
    gram: &faer::sparse::SparseColMat<usize, f64>,
    diagonal: &[f64],
    rhs: &mut [f64],
) -> Result<(), SubdivError> {
    let shift: Vec<f64> = diagonal.iter().map(|d| RIG_REGULARIZATION * d).collect();
    let upper = Csc::upper_from_symmetric(gram, &shift);
    solve_spd_in_place(&upper, rhs).map_err(|e| SubdivError::BadRig {
        what: format!("the Gram matrix Â: {e}; expected it positive definite"),
    })
}
