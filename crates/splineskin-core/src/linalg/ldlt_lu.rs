//! A symmetric indefinite solve of fixed pattern: the KKT system of every flexible G¹ step,
//!
//! ```text
//! [ H  Cᵀ ] [ z ]   [ r ]
//! [ C  0  ] [ λ ] = [ c ]
//! ```
//!
//! (`H` positive definite on the null space of `C`, the constraint rows `C` independent),
//! factored symbolically once and numerically per step: `LDLᵀ` without pivoting in an
//! elimination order that puts every constraint row after its unknowns, and a sparse LU with
//! partial pivoting where that fails or leaves a residual above [`KKT_RESIDUAL`] ([`LdltLu`];
//! the residual check is [`super::residual_within`]).

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::ldlt::factor::LdltRegularization;
use faer::linalg::solvers::Solve;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::SymbolicCholesky;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymmetricOrdering,
};
use faer::sparse::linalg::solvers::{Lu, SymbolicLu};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{Argsort, Pair, SparseColMat, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par, Side};

use super::{residual_within, LinalgError};

/// A KKT matrix `[H, Cᵀ; C, 0]` of fixed pattern (every entry is kept, zero or not): the
/// symbolic structure, the order of its values, and its symbolic factorisations, computed once.
///
/// Each solve factors `LDLᵀ` without pivoting in an elimination order that puts every
/// constraint row after all the unknowns it involves (the chain order of the points): with `H`
/// positive definite, a row's pivot is then `−c H₁⁻¹ cᵀ < 0` for the part `H₁` already
/// eliminated, so no pivot vanishes unless the rows are dependent. The sparse `LDLᵀ` reuses its
/// elimination tree and is several times cheaper than a pivoting LU. A solve whose `LDLᵀ` fails
/// or leaves a residual above [`KKT_RESIDUAL`] (dependent rows, or growth) is redone with a
/// sparse LU with partial pivoting, whose symbolic analysis is also done once.
#[derive(Clone, Debug)]
pub struct LdltLu {
    /// Rows (and columns).
    pub n: usize,
    symbolic: SymbolicSparseColMat<usize>,
    argsort: Argsort<usize>,
    ldlt: std::sync::Arc<SymbolicCholesky<usize>>,
    lu: SymbolicLu<usize>,
    /// Workspace needed by the `LDLᵀ` factorisation and solve.
    stack_req: StackReq,
}

/// Largest residual `‖K z − r‖∞` of a KKT solve by `LDLᵀ`, relative to `‖K‖∞ ‖z‖∞ + ‖r‖∞`,
/// accepted before the solve is redone by LU: 1e-11.
pub const KKT_RESIDUAL: f64 = 1e-11;

/// Reusable buffers of [`LdltLu::solve`].
#[derive(Default)]
pub struct LdltLuScratch {
    values: Vec<f64>,
    l_values: Vec<f64>,
    rhs: Vec<f64>,
    mem: Option<MemBuffer>,
}

impl LdltLu {
    /// The pattern of `entries` (both triangles), eliminated in the order of `keys` (one per
    /// row/column; ties keep index order).
    pub fn new(
        n: usize,
        entries: &[(usize, usize, f64)],
        keys: &[f64],
    ) -> Result<LdltLu, LinalgError> {
        let pairs: Vec<Pair<usize, usize>> = entries
            .iter()
            .map(|&(row, col, _)| Pair { row, col })
            .collect();
        let (symbolic, argsort) = SymbolicSparseColMat::try_new_from_indices(n, n, &pairs)
            .map_err(|e| LinalgError::new("assembling the pattern", e))?;
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&i, &j| keys[i].total_cmp(&keys[j]).then(i.cmp(&j)));
        let mut inverse = vec![0; n];
        for (new, &old) in order.iter().enumerate() {
            inverse[old] = new;
        }
        let perm = PermRef::new_checked(&order, &inverse, n);
        let ldlt = factorize_symbolic_cholesky(
            symbolic.as_ref(),
            Side::Lower,
            SymmetricOrdering::Custom(perm),
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SIMPLICIAL,
                ..Default::default()
            },
        )
        .map_err(|e| LinalgError::new("symbolic LDLT factorisation", e))?;
        let lu = SymbolicLu::try_new(symbolic.as_ref())
            .map_err(|e| LinalgError::new("symbolic LU factorisation", e))?;
        let stack_req = StackReq::any_of(&[
            ldlt.factorize_numeric_ldlt_scratch::<f64>(Par::Seq, Default::default()),
            ldlt.solve_in_place_scratch::<f64>(1, Par::Seq),
        ]);
        Ok(LdltLu {
            n,
            symbolic,
            argsort,
            ldlt: std::sync::Arc::new(ldlt),
            lu,
            stack_req,
        })
    }

    /// Factors the matrix with `entries` (the same entries, in the same order, as given to
    /// [`LdltLu::new`]) and solves it for `rhs` in place.
    pub fn solve(
        &self,
        entries: &[(usize, usize, f64)],
        sc: &mut LdltLuScratch,
        rhs: &mut [f64],
    ) -> Result<(), LinalgError> {
        sc.values.clear();
        sc.values.extend(entries.iter().map(|e| e.2));
        let mat = SparseColMat::new_from_argsort(self.symbolic.clone(), &self.argsort, &sc.values)
            .map_err(|e| LinalgError::new("filling the matrix", e))?;
        sc.rhs.clear();
        sc.rhs.extend_from_slice(rhs);
        sc.l_values.resize(self.ldlt.len_val(), 0.0);
        let mem = sc.mem.get_or_insert_with(|| MemBuffer::new(self.stack_req));
        if mem.len() < self.stack_req.unaligned_bytes_required() {
            *mem = MemBuffer::new(self.stack_req);
        }
        let stack = MemStack::new(mem);
        let ok = match self.ldlt.factorize_numeric_ldlt(
            &mut sc.l_values,
            mat.as_ref(),
            Side::Lower,
            LdltRegularization::default(),
            Par::Seq,
            stack,
            Default::default(),
        ) {
            Ok(ldlt) => {
                ldlt.solve_in_place_with_conj(
                    Conj::No,
                    MatMut::from_column_major_slice_mut(rhs, self.n, 1),
                    Par::Seq,
                    stack,
                );
                residual_within(mat.as_ref(), rhs, &sc.rhs, KKT_RESIDUAL)
            }
            Err(_) => false,
        };
        if !ok {
            rhs.copy_from_slice(&sc.rhs);
            let lu = Lu::try_new_with_symbolic(self.lu.clone(), mat.as_ref())
                .map_err(|e| LinalgError::new("LU factorisation", e))?;
            lu.solve_in_place(MatMut::from_column_major_slice_mut(rhs, self.n, 1));
        }
        if rhs.iter().any(|v| !v.is_finite()) {
            return Err(LinalgError::singular());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `min ½ xᵀ diag(1, 2, 4) x` subject to `x₀ + x₁ + x₂ = 1`: `x = (4, 2, 1) / 7`, `λ = −4/7`.
    fn equality_qp() -> Vec<(usize, usize, f64)> {
        let mut e = vec![(0, 0, 1.0), (1, 1, 2.0), (2, 2, 4.0)];
        for i in 0..3 {
            e.push((3, i, 1.0));
            e.push((i, 3, 1.0));
        }
        e
    }

    fn solve(keys: &[f64], entries: &[(usize, usize, f64)]) -> Result<Vec<f64>, LinalgError> {
        let kkt = LdltLu::new(4, entries, keys)?;
        let mut rhs = vec![0.0, 0.0, 0.0, 1.0];
        kkt.solve(entries, &mut LdltLuScratch::default(), &mut rhs)?;
        Ok(rhs)
    }

    const EXPECTED: [f64; 4] = [4.0 / 7.0, 2.0 / 7.0, 1.0 / 7.0, -4.0 / 7.0];

    #[test]
    fn kkt_solves_an_equality_qp() {
        let z = solve(&[0.0, 1.0, 2.0, 2.5], &equality_qp()).unwrap();
        for (a, b) in z.iter().zip(EXPECTED) {
            assert!((a - b).abs() <= 1e-15, "{z:?}");
        }
    }

    #[test]
    fn kkt_constraint_row_first_still_solves() {
        // The row eliminated first has a zero pivot: LDLᵀ cannot, the LU fallback does.
        let z = solve(&[1.0, 2.0, 3.0, 0.0], &equality_qp()).unwrap();
        for (a, b) in z.iter().zip(EXPECTED) {
            assert!((a - b).abs() <= 1e-15, "{z:?}");
        }
    }

    #[test]
    fn kkt_refactors_new_values_on_the_same_pattern() {
        // diag(2, 2, 2): x = (1, 1, 1) / 3, λ = −2/3.
        let mut e = equality_qp();
        for v in &mut e[..3] {
            v.2 = 2.0;
        }
        let kkt = LdltLu::new(4, &equality_qp(), &[0.0, 1.0, 2.0, 2.5]).unwrap();
        let mut rhs = vec![0.0, 0.0, 0.0, 1.0];
        kkt.solve(&e, &mut LdltLuScratch::default(), &mut rhs)
            .unwrap();
        let expected = [1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0, -2.0 / 3.0];
        for (a, b) in rhs.iter().zip(expected) {
            assert!((a - b).abs() <= 1e-15, "{rhs:?}");
        }
    }

    #[test]
    fn residual_within_accepts_the_solution_and_rejects_a_perturbed_one() {
        let e = equality_qp();
        let pairs: Vec<Pair<usize, usize>> =
            e.iter().map(|&(row, col, _)| Pair { row, col }).collect();
        let (symbolic, argsort) = SymbolicSparseColMat::try_new_from_indices(4, 4, &pairs).unwrap();
        let values: Vec<f64> = e.iter().map(|v| v.2).collect();
        let k = SparseColMat::new_from_argsort(symbolic, &argsort, &values).unwrap();
        let r = [0.0, 0.0, 0.0, 1.0];
        assert!(residual_within(k.as_ref(), &EXPECTED, &r, KKT_RESIDUAL));
        let mut z = EXPECTED;
        z[1] += 1e-9;
        assert!(!residual_within(k.as_ref(), &z, &r, KKT_RESIDUAL));
    }
}
