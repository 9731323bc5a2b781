//! [`extend`]: the bootstrapping continued past a training, new configurations solved from
//! the current operator's prediction and the operator refitted.

use std::sync::atomic::{AtomicUsize, Ordering};

use kurbo::Point;
use rayon::prelude::*;

use super::super::error::DefOpError;
use super::super::operator::DefOp;
use super::ground_truth::{solve_sample, Solved, Solver, Start};
use super::options::{check_stop, TrainOptions};
use super::{stopwatch, Training};
use splineskin_core::mesh::TriMesh;

/// What [`extend`] did.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct ExtendReport {
    /// Configurations solved and added.
    pub n_new: usize,
    /// Samples the operator is fitted to now, the rest included.
    pub n_fitted: usize,
    /// Symmetric ARAP: samples whose solve fell back to the ARAP solution or the rest pose.
    pub fallbacks: usize,
    /// Samples whose solver stopped before converging (ARAP; kept, as [`super::train()`] keeps them).
    pub not_converged: usize,
    /// The most iterations a solve took (of the start that succeeded).
    pub max_iterations: usize,
    /// Wall time of the solves, seconds (0 in WebAssembly in a page).
    pub solve_seconds: f64,
    /// Wall time of the refit, seconds.
    pub fit_seconds: f64,
}

/// Adds the ground truths at `configurations` to `training` and refits its operator: the
/// paper's bootstrapping (§3.3) continued where the user goes. Each solve starts from the
/// current operator's prediction (symmetric ARAP falls back as in [`super::train()`]); the refit is
/// [`DefOp::fit`] over every sample with the options' fit, as the training's last stage.
/// `options` must be the training's own (energy, solvers, fit); its sample counts, regions
/// and seed are ignored. `progress(done)` is called after every solve.
///
/// A thin-plate operator reproduces each added sample exactly, so a configuration added here
/// is deformed as its ground truth, and the handles stay interpolated at every configuration
/// ([`DefOp::fit`]'s constraint (8c′)).
///
/// ```
/// use kurbo::{Point, Rect, Vec2};
/// use splineskin_defop::{extend, train, Energy, SpatialBasis, TrainOptions};
/// use splineskin_core::mesh::TriMesh;
/// let mesh = TriMesh::grid(Rect::new(0., 0., 4., 1.), 16, 4)?;
/// let handles = [34, 50, 76];
/// let spatial = SpatialBasis::hats(&mesh)?;
/// let options = TrainOptions::default().with_energy(Energy::Arap).with_n_samples(20);
/// let mut training = train(&mesh, &handles, &spatial, &options, &|_| {})?;
/// // The last handle lifted far beyond the training discs (5 % of the diagonal).
/// let mut far: Vec<Point> = handles.iter().map(|&h| mesh.vertices[h]).collect();
/// far[2] += Vec2::new(0.0, 1.5);
/// let report = extend(&mesh, &options, &mut training, &[far.clone()], &|_| {})?;
/// assert_eq!((report.n_new, report.n_fitted), (1, 22));
/// // The operator now gives that sample's ground truth.
/// let truth = training.solutions.last().unwrap();
/// let at = training.op.eval(&far)?;
/// assert!(at.iter().zip(truth).all(|(a, t)| (*a - *t).hypot() < 1e-8));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn extend(
    mesh: &TriMesh,
    options: &TrainOptions,
    training: &mut Training,
    configurations: &[Vec<Point>],
    progress: &(dyn Fn(usize) + Sync),
) -> Result<ExtendReport, DefOpError> {
    let handles = training.op.handles().to_vec();
    let solver = Solver::new(mesh, &handles, options)?;
    let clock = stopwatch();
    let solved = AtomicUsize::new(0);
    let n_before = training.configurations.len();
    let op = &training.op;
    let solve_one = |k: usize| -> Result<Solved, DefOpError> {
        check_stop(&options.stop)?;
        let result = solve_sample(
            mesh,
            &handles,
            &solver,
            Some(op),
            n_before + k,
            &configurations[k],
        );
        progress(solved.fetch_add(1, Ordering::Relaxed) + 1);
        result
    };
    let results: Vec<Solved> = if options.parallel {
        (0..configurations.len())
            .into_par_iter()
            .map(solve_one)
            .collect::<Result<_, _>>()?
    } else {
        (0..configurations.len())
            .map(solve_one)
            .collect::<Result<_, _>>()?
    };
    let solve_seconds = clock();
    let fallbacks = results.iter().filter(|s| s.start != Start::First).count();
    let not_converged = results.iter().filter(|s| !s.converged).count();
    let max_iterations = results.iter().map(|s| s.iterations).max().unwrap_or(0);
    let clock = stopwatch();
    let mut all = training.configurations.clone();
    all.extend_from_slice(configurations);
    let mut solutions = training.solutions.clone();
    solutions.extend(results.into_iter().map(|s| s.solution));
    let fitted = DefOp::fit(
        mesh,
        &handles,
        training.op.spatial_basis(),
        &all,
        &solutions,
        &options.fit,
    )?;
    let fit_seconds = clock();
    training.op = fitted;
    training.configurations = all;
    training.solutions = solutions;
    Ok(ExtendReport {
        n_new: configurations.len(),
        n_fitted: training.configurations.len(),
        fallbacks,
        not_converged,
        max_iterations,
        solve_seconds,
        fit_seconds,
    })
}
