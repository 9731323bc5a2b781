//! Minimising a quadratic energy with some vertices fixed: the linear algebra shared by the
//! harmonic and bounded biharmonic solves.
//!
//! With `Q` symmetric positive semidefinite (`n × n`), the free vertices `f` and the fixed ones
//! `c`, the minimiser of `wᵀ Q w` over `w_f` with `w_c` given solves
//!
//! ```text
//! Q_ff w_f = −Q_fc w_c
//! ```
//!
//! (libigl's `min_quad_with_fixed` without linear term or equality rows). `Q_ff` is positive
//! definite when every connected part of the mesh holds a fixed vertex, and is factored by the
//! crate's sparse Cholesky (`crate::linalg::cholesky`: faer, supernodal or simplicial as faer
//! chooses, sequential) in the order described next.
//!
//! **Orderings.** The fill-reducing ordering is computed once, by AMD on the pattern of the
//! whole `Q` ([`EnergySystem::new`]), and every `Q_ff` is factored in the order it induces on
//! `f`. The fill of a principal submatrix in an induced order is contained in the fill of the
//! whole matrix (a fill edge `(i, j)` is a path from `i` to `j` through vertices eliminated
//! before both — George & Liu's path lemma — and the paths of a subgraph are paths of the
//! graph), so factoring `Q_ff` costs at most what factoring `Q` does, and shrinks with `f`;
//! the bounded solve, which factors a new `Q_ff` per active-set iteration, needs no ordering
//! pass per iteration. It does not redo the symbolic analysis per iteration either: a
//! [`ReducedCholesky`] is analysed for a set of vertices covering the free ones with a margin,
//! and refactored numerically while the free set stays inside it.

use faer::dyn_stack::MemBuffer;

use super::WeightsError;
use crate::linalg::{amd_order, CholeskyAnalysis, Csc, LinalgError, Ordering};

/// Right-hand sides solved together: the workspace is sized for this many columns.
const SOLVE_BLOCK: usize = 8;

/// A symmetric positive semidefinite energy `Q` on the vertices with its fill-reducing
/// elimination order.
#[derive(Clone, Debug)]
pub(crate) struct EnergySystem {
    /// `Q`, full symmetric storage, sorted rows.
    pub q: Csc,
    /// `order[k]` is the vertex eliminated `k`-th.
    order: Vec<usize>,
    /// The upper triangle of `Q` renumbered in elimination order (`P Q Pᵀ`), sorted rows:
    /// restricting it to free vertices keeps rows sorted, so each factorisation only filters.
    permuted: Csc,
}

impl EnergySystem {
    /// Wraps `q` and orders it by AMD (faer's, default parameters).
    pub fn new(q: Csc) -> Result<EnergySystem, WeightsError> {
        let n = q.n;
        let nnz = q.row_idx.len();
        let (order, inverse) = amd_order(&q)?;
        // Column k of P Q Pᵀ's upper triangle: vertex order[k]'s entries, renumbered.
        let permuted = Csc::from_columns(n, nnz / 2 + n, |k, column| {
            let (rows, vals) = q.column(order[k]);
            column.extend(
                rows.iter()
                    .zip(vals)
                    .map(|(&u, &x)| (inverse[u], x))
                    .filter(|&(r, _)| r <= k),
            );
            column.sort_unstable_by_key(|&(r, _)| r);
        });
        Ok(EnergySystem { q, order, permuted })
    }

    /// `Q + diag(shift)`, in the same elimination order (its pattern is `Q`'s: no new
    /// ordering pass).
    pub fn shifted(&self, shift: &[f64]) -> EnergySystem {
        let mut shifted = self.clone();
        for (v, &s) in shift.iter().enumerate() {
            let start = shifted.q.col_ptr[v];
            let (rows, _) = shifted.q.column(v);
            if let Ok(k) = rows.binary_search(&v) {
                shifted.q.values[start + k] += s;
            }
        }
        // Column k of the permuted upper triangle ends with its diagonal (rows sorted, r ≤ k).
        for (k, &v) in self.order.iter().enumerate() {
            let end = shifted.permuted.col_ptr[k + 1];
            if end > shifted.permuted.col_ptr[k] && shifted.permuted.row_idx[end - 1] == k {
                shifted.permuted.values[end - 1] += shift[v];
            }
        }
        shifted
    }

    /// Number of vertices.
    pub fn n(&self) -> usize {
        self.q.n
    }

    /// The diagonal `Q_vv` of every vertex.
    pub fn diagonal(&self) -> Vec<f64> {
        (0..self.n())
            .map(|v| {
                let (rows, vals) = self.q.column(v);
                rows.binary_search(&v).map_or(0.0, |k| vals[k])
            })
            .collect()
    }

    /// `out = Q w`.
    pub fn apply(&self, w: &[f64], out: &mut [f64]) {
        // Q is symmetric: row v of Q·w is column v's entries against w.
        for (v, o) in out.iter_mut().enumerate() {
            let (rows, values) = self.q.column(v);
            *o = rows.iter().zip(values).map(|(&u, &q)| q * w[u]).sum();
        }
    }

    /// Factors `Q_ff` for the vertices with `free[v]`.
    pub fn factor(&self, free: &[bool]) -> Result<ReducedCholesky, WeightsError> {
        let mut factor = ReducedCholesky::analyse(self, free)?;
        factor.refactor(self, free)?;
        Ok(factor)
    }

    /// The neighbours of vertex `v` in `Q`'s pattern (its two-ring on a mesh), `v` included.
    pub fn neighbours(&self, v: usize) -> &[usize] {
        self.q.column(v).0
    }
}

/// Marks a vertex that is not covered in [`ReducedCholesky`]'s position map.
const NOT_COVERED: usize = usize::MAX;

impl From<LinalgError> for WeightsError {
    fn from(e: LinalgError) -> Self {
        WeightsError::Factorization {
            detail: e.to_string(),
        }
    }
}

/// The Cholesky factor of `Q_ff` for one set of free vertices `f`, analysed for a larger
/// *covered* set `c ⊇ f`: what the active-set iterations refactor as `f` changes.
///
/// The matrix factored is `Q_cc` with every covered vertex that is not free decoupled (its row
/// and column zero, 1 on the diagonal): block diagonal, `Q_ff` and an identity, so its factor
/// is `Q_ff`'s with identity rows between, and the free values it solves for are exactly
/// those of `Q_ff w_f = −Q_fc w_c`. Its pattern is that of `Q_cc` whatever `f ⊆ c` is, so the
/// symbolic analysis (about a quarter of a factorisation's time at 7 000 free vertices) is done
/// once per covered set, and each change of `f` inside it costs only a numeric factorisation.
pub(crate) struct ReducedCholesky {
    /// `vertices[r]`: the covered vertex of reduced index `r` (in elimination order).
    vertices: Vec<usize>,
    /// Reduced index of each vertex, [`NOT_COVERED`] for those not covered.
    position: Vec<usize>,
    /// Which covered vertices are free in the current factor.
    free: Vec<bool>,
    /// For each stored entry of `Q_cc`'s upper triangle: its index in `permuted`'s values,
    /// and its reduced row and column.
    entries: Vec<(usize, usize, usize)>,
    /// The values of the matrix factored (`Q_ff` and the identity, see above).
    values: Vec<f64>,
    analysis: CholeskyAnalysis,
    /// The Cholesky factor's values.
    factor: Vec<f64>,
    /// Workspace of the factorisation and the solves.
    memory: MemBuffer,
    /// Right-hand sides of the solves.
    rhs: Vec<f64>,
}

impl ReducedCholesky {
    /// The symbolic analysis of `Q_cc` for the vertices with `covered[v]` (not yet factored:
    /// call [`ReducedCholesky::refactor`]).
    pub fn analyse(system: &EnergySystem, covered: &[bool]) -> Result<Self, WeightsError> {
        let n = system.n();
        // Reduced index of each elimination position, and of each vertex.
        let mut reduced = vec![NOT_COVERED; n];
        let mut position = vec![NOT_COVERED; n];
        let mut vertices = Vec::new();
        for (k, &v) in system.order.iter().enumerate() {
            if covered[v] {
                reduced[k] = vertices.len();
                position[v] = vertices.len();
                vertices.push(v);
            }
        }
        let m = vertices.len();
        // Upper triangle of Q_cc in the induced order: the covered rows of the covered columns
        // of `permuted`, renumbered (monotonically, so rows stay sorted).
        let mut col_ptr = Vec::with_capacity(m + 1);
        let mut row_idx = Vec::new();
        let mut entries = Vec::new();
        col_ptr.push(0);
        for k in 0..n {
            if reduced[k] == NOT_COVERED {
                continue;
            }
            let start = system.permuted.col_ptr[k];
            let (rows, _) = system.permuted.column(k);
            for (offset, &r) in rows.iter().enumerate() {
                if reduced[r] != NOT_COVERED {
                    row_idx.push(reduced[r]);
                    entries.push((start + offset, reduced[r], reduced[k]));
                }
            }
            col_ptr.push(row_idx.len());
        }
        let analysis = CholeskyAnalysis::new(m, col_ptr, row_idx, Ordering::Identity)?;
        let memory = analysis.workspace(SOLVE_BLOCK)?;
        Ok(ReducedCholesky {
            free: vec![false; m],
            values: vec![0.0; entries.len()],
            factor: vec![0.0; analysis.factor_len()],
            rhs: Vec::new(),
            vertices,
            position,
            entries,
            analysis,
            memory,
        })
    }

    /// Whether every vertex with `free[v]` is covered: [`ReducedCholesky::refactor`] accepts
    /// `free`.
    pub fn covers(&self, free: &[bool]) -> bool {
        free.iter()
            .zip(&self.position)
            .all(|(&f, &p)| !f || p != NOT_COVERED)
    }

    /// Factors `Q_ff` for the vertices with `free[v]`, reusing the analysis. Every free vertex
    /// must be covered ([`ReducedCholesky::covers`], which the callers check or hold by
    /// construction).
    pub fn refactor(&mut self, system: &EnergySystem, free: &[bool]) -> Result<(), WeightsError> {
        debug_assert!(self.covers(free), "a free vertex outside the analysed set");
        for (f, &v) in self.free.iter_mut().zip(&self.vertices) {
            *f = free[v];
        }
        let values = &system.permuted.values;
        for (x, &(source, r, c)) in self.values.iter_mut().zip(&self.entries) {
            *x = match (self.free[r] && self.free[c], r == c) {
                (true, _) => values[source],
                (false, true) => 1.0,
                (false, false) => 0.0,
            };
        }
        self.analysis
            .factor(&self.values, &mut self.factor, &mut self.memory)?;
        Ok(())
    }

    /// For each column `w` of `columns` (vertex-indexed, `n_vertices` each, contiguous),
    /// overwrites the free entries with the minimiser of `wᵀQw` given the fixed ones:
    /// `w_f = −Q_ff⁻¹ Q_fc w_c`.
    pub fn solve_free(&mut self, system: &EnergySystem, columns: &mut [f64]) {
        self.solve_free_with(system, columns, None);
    }

    /// [`ReducedCholesky::solve_free`] with `extra` (laid out as `columns`) added to the
    /// right-hand sides: `w_f = Q_ff⁻¹ (extra_f − Q_fc w_c)`, the minimiser of
    /// `½ wᵀQw − extraᵀw` given the fixed entries.
    pub fn solve_free_with(
        &mut self,
        system: &EnergySystem,
        columns: &mut [f64],
        extra: Option<&[f64]>,
    ) {
        let n = system.n();
        let m = self.vertices.len();
        if m == 0 || n == 0 {
            return;
        }
        for (b, block) in columns.chunks_mut(n * SOLVE_BLOCK).enumerate() {
            let k = block.len() / n;
            let extra = extra.map(|e| &e[b * n * SOLVE_BLOCK..b * n * SOLVE_BLOCK + k * n]);
            self.rhs.clear();
            self.rhs.resize(m * k, 0.0);
            let is_free = |u: usize| self.position[u] != NOT_COVERED && self.free[self.position[u]];
            for (j, w) in block.chunks(n).enumerate() {
                let b = &mut self.rhs[j * m..(j + 1) * m];
                for (r, &v) in self.vertices.iter().enumerate() {
                    if !self.free[r] {
                        continue;
                    }
                    let (rows, vals) = system.q.column(v);
                    let given = extra.map_or(0.0, |e| e[j * n + v]);
                    b[r] = given
                        - rows
                            .iter()
                            .zip(vals)
                            .filter(|(&u, _)| !is_free(u))
                            .map(|(&u, &q)| q * w[u])
                            .sum::<f64>();
                }
            }
            self.analysis
                .solve(&self.factor, &mut self.rhs, &mut self.memory);
            for (j, w) in block.chunks_mut(n).enumerate() {
                for (r, &v) in self.vertices.iter().enumerate() {
                    if self.free[r] {
                        w[v] = self.rhs[j * m + r];
                    }
                }
            }
        }
    }
}
