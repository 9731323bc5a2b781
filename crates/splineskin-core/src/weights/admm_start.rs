//! A few steps of ADMM on the bounded biharmonic program, to improve a guess before the active
//! set (`super::bbw`) takes over.
//!
//! The active set started from coarser weights (`super::coarse_to_fine`) moves the edge of a
//! bound region a ring or two per re-solve, and a plateau at the upper bound that the coarse
//! level made too large shrinks slowly: on OpenMoji's dog (1F415, 12 347 vertices) one column
//! took 50 re-solves where the others took 12 to 21. ADMM (Boyd et al. 2011, *Distributed
//! optimization and statistical learning via the alternating direction method of multipliers*,
//! §5.2, with over-relaxation §3.4.3) splits the program into the unconstrained quadratic and
//! the box, and each step costs one solve with a matrix factored once for every column:
//!
//! ```text
//! w  ← (Q + ρD)⁻¹ (ρD (z − u))        (free vertices; fixed ones keep their data)
//! ŵ  ← α w + (1 − α) z
//! z  ← clamp(ŵ + u, 0, 1)
//! u  ← u + ŵ − z
//! ```
//!
//! with `D = diag Q` (so `ρ` is in the same units on graded and uniform meshes), started from
//! `z` = the guess and `u = 0`. Two steps are far from converged (ADMM is slow on a matrix
//! whose condition number is about 1e8), but they put `z`'s bound regions nearer the
//! minimiser's: the active set then starts from `z`. The result is the same minimiser (the
//! active set stops at the same KKT tolerances), only reached in fewer re-solves: setup
//! (domain and weights, release, 2 cores) of OpenMoji's dog 0.56 → 0.35 s, giraffe 0.31 →
//! 0.25 s, horse 0.38 → 0.34 s, turtle 1F422 0.70 → 0.26 s, four more animals 5–30 % faster,
//! the bundled octopus unchanged (0.51 s).

use super::reduced_cholesky::{EnergySystem, ReducedCholesky};
use super::{DirichletData, WeightsError};
use crate::stop::StopSignal;

/// Steps run before the active set: 2 (see [`RHO`]).
pub const STEPS: usize = 2;
/// `ρ` relative to `Q`'s diagonal: 3e-2. Measured with [`STEPS`] (setup, release, 2 cores, on
/// the bundled octopus and OpenMoji's dog, horse and giraffe): 10 steps at 1e-3 took the dog
/// from 0.56 to 0.44 s but the octopus from 0.51 to 0.77 s (nine columns: the steps are serial
/// and the free sets they leave larger); 5 at 1e-2: 0.36 s and 0.54 s; 2 at 3e-2: 0.35 s and
/// 0.51 s, the horse 0.38 → 0.34 s and the giraffe 0.31 → 0.25 s.
const RHO: f64 = 3e-2;
/// Values within this of a bound after the steps start at the bound (the active set frees
/// those whose multiplier says so): 1e-6. Left free, the many vertices ADMM leaves at tiny
/// positive weights far from their handle make every re-solve larger (the octopus took 0.77 s
/// instead of 0.63 s at 10 steps); snapped at 1e-4 or more, too many start at a bound.
const SNAP: f64 = 1e-6;
/// Over-relaxation `α`: 1.6 (Boyd et al. suggest 1.5 to 1.8).
const RELAXATION: f64 = 1.6;

/// Runs [`STEPS`] ADMM steps on every column of `columns` (`n × h`, column-major; on entry
/// the guess, clamped to `[lower, upper]`, with the Dirichlet values at the fixed vertices of
/// `data`), leaving `z` (inside the box, snapped onto a bound within [`SNAP`]) in the free
/// entries.
pub(crate) fn improve_guess(
    system: &EnergySystem,
    data: &DirichletData,
    columns: &mut [f64],
    (lower, upper): (f64, f64),
    stop: Option<&StopSignal>,
) -> Result<(), WeightsError> {
    let n = system.n();
    let mut free = vec![true; n];
    for &v in data.vertices() {
        free[v] = false;
    }
    let rho_d: Vec<f64> = system.diagonal().iter().map(|d| RHO * d).collect();
    let shifted = system.shifted(&rho_d);
    let mut factor = ReducedCholesky::analyse(&shifted, &free)?;
    factor.refactor(&shifted, &free)?;
    let mut z = columns.to_vec();
    let mut u = vec![0.0; columns.len()];
    let mut rhs = vec![0.0; columns.len()];
    for _ in 0..STEPS {
        if stop.is_some_and(StopSignal::is_raised) {
            return Err(WeightsError::Stopped);
        }
        for (k, r) in rhs.iter_mut().enumerate() {
            *r = rho_d[k % n] * (z[k] - u[k]);
        }
        factor.solve_free_with(&shifted, columns, Some(&rhs));
        for (k, w) in columns.iter().enumerate() {
            if !free[k % n] {
                continue;
            }
            let relaxed = RELAXATION * w + (1.0 - RELAXATION) * z[k];
            let next = (relaxed + u[k]).clamp(lower, upper);
            u[k] += relaxed - next;
            z[k] = next;
        }
    }
    for (k, w) in columns.iter_mut().enumerate() {
        if free[k % n] {
            *w = match z[k] {
                x if x < lower + SNAP => lower,
                x if x > upper - SNAP => upper,
                x => x,
            };
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::operators::polyharmonic_csc;
    use crate::mesh::TriMesh;
    use crate::weights::bbw::{bounded_biharmonic, BbwOptions};
    use kurbo::Rect;

    #[test]
    fn steps_keep_the_data_and_the_box_and_move_a_poor_guess_toward_the_minimiser() {
        let mesh = TriMesh::grid(Rect::new(0.0, 0.0, 2.0, 1.0), 24, 12).unwrap();
        let handles = [3 * 25 + 3, 9 * 25 + 4, 6 * 25 + 12, 6 * 25 + 21];
        let data = DirichletData::handles(&handles).unwrap();
        let exact = bounded_biharmonic(&mesh, &data, &BbwOptions::default()).unwrap();
        let system = EnergySystem::new(polyharmonic_csc(&mesh, 2)).unwrap();
        let n = mesh.n_vertices();
        let h = handles.len();
        // A poor guess: every free value 0.5 (the data at the handles).
        let mut columns = vec![0.5; n * h];
        for (row, &v) in handles.iter().enumerate() {
            for j in 0..h {
                columns[j * n + v] = data.values_at(row)[j];
            }
        }
        let error = |c: &[f64]| {
            (0..n * h)
                .map(|k| (c[k] - exact.get(k % n, k / n)).abs())
                .sum::<f64>()
        };
        let before = error(&columns);
        improve_guess(&system, &data, &mut columns, (0.0, 1.0), None).unwrap();
        for (row, &v) in handles.iter().enumerate() {
            for j in 0..h {
                assert_eq!(columns[j * n + v], data.values_at(row)[j]);
            }
        }
        assert!(columns.iter().all(|x| (0.0..=1.0).contains(x)));
        let after = error(&columns);
        assert!(after < 0.8 * before, "{before} → {after}");
        // From the minimiser itself, the steps stay near it (its bound regions kept).
        let mut from_exact: Vec<f64> = (0..n * h).map(|k| exact.get(k % n, k / n)).collect();
        improve_guess(&system, &data, &mut from_exact, (0.0, 1.0), None).unwrap();
        let drift = (0..n * h)
            .map(|k| (from_exact[k] - exact.get(k % n, k / n)).abs())
            .fold(0.0, f64::max);
        assert!(drift < 0.03, "{drift}");
        // A raised stop signal ends the steps.
        let stop = StopSignal::new();
        stop.raise();
        assert_eq!(
            improve_guess(&system, &data, &mut columns, (0.0, 1.0), Some(&stop)),
            Err(WeightsError::Stopped)
        );
    }
}
