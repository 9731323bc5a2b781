//! The ground-truth solves of a training: one sample's ARAP or symmetric ARAP solve from its
//! starts, and the held-out truths solved from the rest pose.

use std::sync::atomic::{AtomicUsize, Ordering};

use kurbo::Point;
use rayon::prelude::*;

use super::super::arap::Arap;
use super::super::error::DefOpError;
use super::super::operator::DefOp;
use super::super::orientation::flipped_triangles;
use super::super::sarap::SymmetricArap;
use super::options::{check_stop, Energy, TrainOptions};
use splineskin_core::mesh::TriMesh;

/// The ground-truth solvers of a training: ARAP, and symmetric ARAP when that is the energy
/// (ARAP then gives it starts).
pub(super) struct Solver {
    pub(super) arap: Arap,
    pub(super) sarap: Option<SymmetricArap>,
}

impl Solver {
    /// The solvers for `handles` on `mesh` with the options' energy and solver options.
    pub(super) fn new(
        mesh: &TriMesh,
        handles: &[usize],
        options: &TrainOptions,
    ) -> Result<Solver, DefOpError> {
        Ok(Solver {
            arap: Arap::new(mesh, handles, options.arap)?,
            sarap: match options.energy {
                Energy::Arap => None,
                Energy::SymmetricArap => Some(SymmetricArap::new(mesh, handles, options.sarap)?),
            },
        })
    }
}

/// One sample's solve: its solution, iterations (of the solve that succeeded), which start
/// succeeded, whether it converged.
pub(super) struct Solved {
    pub(super) solution: Vec<Point>,
    pub(super) iterations: usize,
    pub(super) start: Start,
    pub(super) converged: bool,
}

/// The start a sample's solve succeeded from.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Start {
    /// The operator's prediction, or the rest pose when there is none (ARAP; stage 0).
    First,
    /// Symmetric ARAP: the sample's ARAP solution.
    Arap,
    /// Symmetric ARAP: the rest pose, after the others were refused or failed.
    Rest,
}

/// The ground truths at `configurations` solved from the rest pose, independently of any
/// operator: the held-out truth of the convergence study ([`crate::study()`]), deterministic
/// for a given mesh and configuration. `options` gives the energy, the solver options and
/// [`TrainOptions::parallel`] (rayon); its samples and fit are ignored. Symmetric ARAP tries
/// the rest pose's ARAP solution first (if flip-free), then the rest pose, as [`super::train()`] does
/// when it has no prediction. `progress(done)` is called after every solve.
///
/// Both energies have several local minima for large handle displacements, so the solution
/// depends on the start; starting every held-out configuration from rest makes the truth one
/// fixed function of the configuration, the same for every operator it measures.
///
/// ```
/// use kurbo::{Point, Rect};
/// use splineskin_defop::{ground_truths_from_rest, Energy, TrainOptions};
/// use splineskin_core::mesh::TriMesh;
/// let mesh = TriMesh::grid(Rect::new(0., 0., 4., 1.), 8, 2)?;
/// let q = vec![Point::new(0., 0.5), Point::new(4.5, 0.5)];
/// let options = TrainOptions::default().with_energy(Energy::Arap);
/// let truths = ground_truths_from_rest(&mesh, &[9, 17], &options, &[q], &|_| {})?;
/// assert_eq!(truths[0][17], Point::new(4.5, 0.5));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn ground_truths_from_rest(
    mesh: &TriMesh,
    handles: &[usize],
    options: &TrainOptions,
    configurations: &[Vec<Point>],
    progress: &(dyn Fn(usize) + Sync),
) -> Result<Vec<Vec<Point>>, DefOpError> {
    let solver = Solver::new(mesh, handles, options)?;
    let solved = AtomicUsize::new(0);
    let solve_one = |k: usize| -> Result<Vec<Point>, DefOpError> {
        check_stop(&options.stop)?;
        let result = solve_sample(mesh, handles, &solver, None, k, &configurations[k]);
        progress(solved.fetch_add(1, Ordering::Relaxed) + 1);
        result.map(|s| s.solution)
    };
    if options.parallel {
        (0..configurations.len())
            .into_par_iter()
            .map(solve_one)
            .collect()
    } else {
        (0..configurations.len()).map(solve_one).collect()
    }
}

/// The ground truth at `q` (sample `sample`), started from `predictor`'s prediction when
/// there is one.
pub(super) fn solve_sample(
    mesh: &TriMesh,
    handles: &[usize],
    solver: &Solver,
    predictor: Option<&DefOp>,
    sample: usize,
    q: &[Point],
) -> Result<Solved, DefOpError> {
    let mut u = match predictor {
        Some(op) => {
            let mut u = op.eval(q)?;
            for (&h, &target) in handles.iter().zip(q) {
                u[h] = target;
            }
            u
        }
        None => mesh.vertices.clone(),
    };
    let arap = &solver.arap;
    match &solver.sarap {
        None => {
            let report = arap.solve(q, &mut u)?;
            Ok(Solved {
                solution: u,
                iterations: report.iterations,
                start: Start::First,
                converged: report.converged,
            })
        }
        Some(sarap) => {
            // Starts in order: the prediction (if flip-free), the ARAP solution (if
            // flip-free), the rest pose; the first that converges wins.
            let mut last = None;
            for start in [Start::First, Start::Arap, Start::Rest] {
                match start {
                    Start::First if predictor.is_none() => continue,
                    Start::First => {}
                    Start::Arap => {
                        u.copy_from_slice(&mesh.vertices);
                        arap.solve(q, &mut u)?;
                    }
                    Start::Rest => u.copy_from_slice(&mesh.vertices),
                }
                if start != Start::Rest && !flipped_triangles(mesh, &u)?.is_empty() {
                    continue;
                }
                let report = sarap.solve(q, &mut u)?;
                if report.converged() {
                    return Ok(Solved {
                        solution: u,
                        iterations: report.iterations,
                        start,
                        converged: true,
                    });
                }
                last = Some(report);
            }
            let detail = last.map_or_else(String::new, |r| {
                format!(" ({:?} after {} iterations)", r.stop, r.iterations)
            });
            Err(DefOpError::BadSample {
                sample,
                reason: format!(
                    "symmetric ARAP converged from none of its starts (prediction, ARAP solution, rest pose){detail}"
                ),
            })
        }
    }
}
