//! The crate's sparse linear algebra, on faer (sequential, as STACK.md asks): every
//! factorisation of the fit, flexible G¹, the weights, the subdivision rig and the deformation
//! operators goes through this module.
//!
//! | piece | what | used by |
//! |---|---|---|
//! | [`Csc`] | square sparse matrix, compressed columns, sorted rows (full symmetric, or the upper triangle a factorisation takes) | mesh operators, weights, `defop`, `subdiv` |
//! | [`cholesky`] | `A = L Lᵀ` of a symmetric positive definite `A`: symbolic analysis once per pattern ([`CholeskyAnalysis::new`], AMD or a given order, [`amd_order`]), numeric factorisation per set of values, allocation-free solves; [`solve_spd_in_place`] for a system solved once | weights (harmonic, BBW), `defop` (ARAP, SARAP, Laplacian eigenbasis), `subdiv` (rig, bone heat) |
//! | [`ldlt_lu`] | symmetric indefinite (KKT) `[H Cᵀ; C 0]` of fixed pattern: `LDLᵀ` without pivoting in a given elimination order, checked by its residual, a pivoting sparse LU where that fails ([`LdltLu`]) | flexible G¹ (every step) |
//! | [`lu`] | one LU with partial pivoting (dense when small, else sparse), many right-hand sides ([`lu_solve_in_place`]) | the fit's KKT system |
//! | [`residual_within`] | `‖K z − r‖∞ ≤ τ (‖K‖ ‖z‖∞ + ‖r‖∞)` | [`ldlt_lu`] |
//!
//! Errors are [`LinalgError`]: the stage that failed and faer's report; each caller wraps it
//! in its own error type with the path, mesh or handle concerned.

pub mod cholesky;
pub mod csc;
pub mod ldlt_lu;
pub mod lu;

use faer::sparse::SparseColMatRef;

pub use cholesky::{amd_order, solve_spd_in_place, CholeskyAnalysis, Ordering};
pub use csc::Csc;
pub use ldlt_lu::{LdltLu, LdltLuScratch};
pub use lu::lu_solve_in_place;

/// Why a factorisation or solve failed: the stage and faer's report. Each module wraps it in
/// its own error (the fit's `FitError::Solver`, the weights' and `defop`'s `Factorization`).
#[derive(Clone, Debug, PartialEq)]
pub struct LinalgError {
    /// "symbolic analysis", "workspace", "numeric factorisation", "LU factorisation", …, or
    /// [`LinalgError::SINGULAR`].
    pub stage: &'static str,
    /// faer's error, formatted.
    pub detail: String,
}

impl LinalgError {
    /// The stage of a solve that factored but produced non-finite values (a singular matrix).
    pub const SINGULAR: &'static str = "solution";

    /// The failure of `stage`, with `e` (faer's error) as the detail.
    pub fn new(stage: &'static str, e: impl std::fmt::Debug) -> LinalgError {
        LinalgError {
            stage,
            detail: format!("{e:?}"),
        }
    }

    /// A solve that gave non-finite values.
    pub fn singular() -> LinalgError {
        LinalgError {
            stage: LinalgError::SINGULAR,
            detail: "not finite (the matrix is singular)".to_string(),
        }
    }

    /// Whether this is [`LinalgError::singular`].
    pub fn is_singular(&self) -> bool {
        self.stage == LinalgError::SINGULAR
    }
}

impl std::fmt::Display for LinalgError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.stage, self.detail)
    }
}

/// Whether `z` solves `K z = r` to the relative tolerance `tolerance`:
///
/// ```text
/// ‖K z − r‖∞ ≤ tolerance · (‖K‖ ‖z‖∞ + ‖r‖∞),   ‖K‖ = max_j Σ_i |K_ij|
/// ```
///
/// (the largest column sum, `‖K‖∞` for a symmetric `K`): a backward-error test, invariant
/// under a common scaling of `K`, `z` and `r`. A non-finite residual fails.
pub fn residual_within(
    k: SparseColMatRef<'_, usize, f64>,
    z: &[f64],
    r: &[f64],
    tolerance: f64,
) -> bool {
    let mut res = r.to_vec();
    let mut norm_k: f64 = 0.0;
    for j in 0..k.ncols() {
        let mut col = 0.0;
        for (i, v) in k.row_idx_of_col(j).zip(k.val_of_col(j)) {
            res[i] -= v * z[j];
            col += v.abs();
        }
        norm_k = norm_k.max(col);
    }
    let inf = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let scale = norm_k * inf(z) + inf(r);
    res.iter().all(|v| v.is_finite()) && inf(&res) <= tolerance * scale
}
