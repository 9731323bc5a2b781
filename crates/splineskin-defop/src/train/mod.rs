//! [`train`]: sampling, ground truth and fitting in one call, with the paper's bootstrapping
//! (Poranne & Lipman 2016, §3.3; DESIGN.md §4).
//!
//! ```text
//! stage 0:  2n + 1 samples, ground truth from the rest pose        → fit a linear operator
//! stage s:  growth × as many samples (the new ones only), ground truth started from the
//!           current operator's prediction                         → refit (all samples)
//! last:     the requested number                                   → fit the requested basis
//! ```
//!
//! The rest configuration is always sample 0, with the rest mesh as its ground truth (both
//! energies are zero there), so a thin-plate operator reproduces every sample
//! ([`DefOp::fit`]). Intermediate fits use the requested handle basis once there are at least
//! as many samples as it has functions (thin-plate splines: always), the linear one before.
//!
//! **Starts.** ARAP (local–global with [`crate::TRAINING_ANDERSON_DEPTH`] Anderson acceleration)
//! starts from the prediction as it is (from the rest pose in stage 0). Symmetric ARAP needs a
//! flip-free start and its Newton solve from the rest pose can stall (measured: the 1 000-
//! iteration cap on an octopus sample), so it tries, in order, the prediction, the sample's
//! ARAP solution and the rest pose, skipping a start that flips a triangle and keeping the
//! first solve that converges (the report counts the fallbacks). Both energies have several
//! local minima: a start decides which one a sample gets. [`WarmStart::Rest`] starts every
//! sample as in stage 0 (the deterministic ground truth, at the price of the iterations warm
//! starts save).
//!
//! **Parallelism** is an argument ([`TrainOptions::parallel`]): the samples of a stage are
//! solved on rayon's pool (each solver is shared: `solve` takes `&self`). Configurations are
//! drawn up front from one seeded [`Sampler`], so the samples do not depend on it; the
//! solutions do not either, up to the order of floating-point sums, which is the same.
//! Progress is reported through a callback (the library never prints): the CLI draws a bar.
//! A [`StopSignal`] in the options stops a training from elsewhere (a user interface, the
//! callback itself): the solves not yet started are skipped and the call returns
//! [`DefOpError::Stopped`].

mod extend;
mod ground_truth;
mod options;

use std::sync::atomic::{AtomicUsize, Ordering};

use kurbo::Point;
use rayon::prelude::*;

use super::error::check_count_option;
use super::error::DefOpError;
use super::handle_basis::HandleBasisKind;
use super::handles::bounding_box_diagonal;
use super::operator::DefOp;
use super::sample::{SampleRegion, Sampler};
use super::spatial_basis::SpatialBasis;
use splineskin_core::mesh::TriMesh;

pub use extend::{extend, ExtendReport};
pub use ground_truth::ground_truths_from_rest;
use ground_truth::{solve_sample, Solved, Solver, Start};
use options::check_stop;
pub use options::{
    Energy, StopSignal, TrainOptions, WarmStart, DEFAULT_COVER_SHARE, DEFAULT_DISC_FRACTION,
    DEFAULT_GROWTH, DEFAULT_TRAINING_SAMPLES,
};

/// Where a training is, for a progress display.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct Progress {
    /// Current stage, from 0.
    pub stage: usize,
    /// Number of stages.
    pub n_stages: usize,
    /// Ground-truth solves finished so far, all stages.
    pub solved: usize,
    /// Ground-truth solves in all.
    pub to_solve: usize,
}

/// What one bootstrapping stage did.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct StageReport {
    /// Samples solved in this stage.
    pub n_new: usize,
    /// Samples fitted after it, rest configuration included.
    pub n_fitted: usize,
    /// The handle basis fitted after it.
    pub handle_basis: HandleBasisKind,
    /// Solver iterations (local–global or Newton) of its samples: smallest, mean, largest.
    pub iterations: (usize, f64, usize),
    /// Symmetric ARAP samples solved from their ARAP solution (stage 0, or the prediction
    /// flipped a triangle or its solve failed).
    pub arap_starts: usize,
    /// Symmetric ARAP samples solved from the rest pose (the other starts flipped or failed).
    pub rest_starts: usize,
    /// Samples whose solver stopped at its iteration cap (ARAP; kept, the report says).
    pub not_converged: usize,
    /// Wall time of the ground-truth solves, seconds.
    pub solve_seconds: f64,
    /// Wall time of the fit, seconds.
    pub fit_seconds: f64,
}

/// A trained operator with its data.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct Training {
    /// The fitted operator.
    pub op: DefOp,
    /// The configurations, rest first.
    pub configurations: Vec<Vec<Point>>,
    /// Their ground truths.
    pub solutions: Vec<Vec<Point>>,
    /// One report per stage.
    pub stages: Vec<StageReport>,
}

/// Trains a deformation operator on `mesh` with handles at `handles` and spatial basis
/// `spatial`: draws the configurations, solves the ground truth in bootstrapping stages and
/// fits (module documentation). `progress` is called after every solve (from the solving
/// thread).
///
/// Errors: anything [`DefOp::fit`] or the solvers refuse, a bad option, or a symmetric ARAP
/// sample that converges neither from the prediction nor from the rest pose.
///
/// ```
/// use kurbo::Rect;
/// use splineskin_defop::{train, SpatialBasis, TrainOptions};
/// use splineskin_core::mesh::TriMesh;
/// let mesh = TriMesh::grid(Rect::new(0., 0., 4., 1.), 16, 4)?;
/// let handles = [34, 50, 76];
/// let spatial = SpatialBasis::hats(&mesh)?;
/// let training = train(&mesh, &handles, &spatial, &TrainOptions::default().with_n_samples(30), &|_| {})?;
/// assert_eq!(training.configurations.len(), 31); // the rest configuration first
/// assert_eq!(training.stages.iter().map(|s| s.n_fitted).collect::<Vec<_>>(), vec![8, 29, 31]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn train(
    mesh: &TriMesh,
    handles: &[usize],
    spatial: &SpatialBasis,
    options: &TrainOptions,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<Training, DefOpError> {
    check_train_options(options, handles.len())?;
    let solver = Solver::new(mesh, handles, options)?;
    let configurations = training_configurations(mesh, handles, options)?;
    let mut solutions = vec![mesh.vertices.clone()];
    let ends = stage_ends(handles.len(), options);
    let n_stages = ends.len();
    let solved = AtomicUsize::new(0);
    let mut op: Option<DefOp> = None;
    let mut stages = Vec::with_capacity(n_stages);
    let mut start = 0;
    for (stage, &end) in ends.iter().enumerate() {
        let clock = stopwatch();
        let predictor = match options.warm_start {
            WarmStart::Bootstrap => op.as_ref(),
            WarmStart::Rest => None,
        };
        let solve_one = |k: usize| -> Result<Solved, DefOpError> {
            check_stop(&options.stop)?;
            let result = solve_sample(mesh, handles, &solver, predictor, k, &configurations[k]);
            let done = solved.fetch_add(1, Ordering::Relaxed) + 1;
            progress(Progress {
                stage,
                n_stages,
                solved: done,
                to_solve: options.n_samples,
            });
            result
        };
        let batch = 1 + start..1 + end;
        let results: Vec<Solved> = if options.parallel {
            batch
                .into_par_iter()
                .map(solve_one)
                .collect::<Result<_, _>>()?
        } else {
            batch.map(solve_one).collect::<Result<_, _>>()?
        };
        let solve_seconds = clock();
        let iterations: Vec<usize> = results.iter().map(|s| s.iterations).collect();
        let arap_starts = results.iter().filter(|s| s.start == Start::Arap).count();
        let rest_starts = results.iter().filter(|s| s.start == Start::Rest).count();
        let not_converged = results.iter().filter(|s| !s.converged).count();
        solutions.extend(results.into_iter().map(|s| s.solution));
        let handle_basis = stage_basis(options, stage + 1 == n_stages, end, handles.len());
        let clock = stopwatch();
        let fitted = DefOp::fit(
            mesh,
            handles,
            spatial,
            &configurations[..=end],
            &solutions,
            &options.fit.with_handle_basis(handle_basis),
        )?;
        let fit_seconds = clock();
        let n_new = end - start;
        stages.push(StageReport {
            n_new,
            n_fitted: end + 1,
            handle_basis,
            iterations: (
                iterations.iter().copied().min().unwrap_or(0),
                iterations.iter().sum::<usize>() as f64 / n_new.max(1) as f64,
                iterations.iter().copied().max().unwrap_or(0),
            ),
            arap_starts,
            rest_starts,
            not_converged,
            solve_seconds,
            fit_seconds,
        });
        tracing::debug!(stage, ?stages, "training stage done");
        op = Some(fitted);
        start = end;
    }
    let op = op.ok_or(DefOpError::InvalidOption {
        name: "n_samples",
        value: options.n_samples.to_string(),
        expected: "at least 1",
    })?;
    Ok(Training {
        op,
        configurations,
        solutions,
        stages,
    })
}

/// Refuses a growth under 2, no samples, and fewer than `2n` samples for a thin-plate basis
/// (`n` handles).
fn check_train_options(options: &TrainOptions, n: usize) -> Result<(), DefOpError> {
    if options.growth < 2 {
        return Err(DefOpError::InvalidOption {
            name: "growth",
            value: options.growth.to_string(),
            expected: "at least 2",
        });
    }
    check_count_option("n_samples", options.n_samples)?;
    if options.fit.handle_basis == HandleBasisKind::ThinPlateSpline && options.n_samples < 2 * n {
        return Err(DefOpError::TooFewSamples {
            handles: n,
            needed: 2 * n,
            given: options.n_samples,
        });
    }
    Ok(())
}

/// The training's handle configurations: the rest first, then the sampler's (in the options'
/// regions, else a disc of [`DEFAULT_DISC_FRACTION`] of the diagonal), then the targets to
/// cover (last, so that their solves start from the most trained prediction: a thin-plate
/// operator then reproduces their ground truth).
fn training_configurations(
    mesh: &TriMesh,
    handles: &[usize],
    options: &TrainOptions,
) -> Result<Vec<Vec<Point>>, DefOpError> {
    let rest: Vec<Point> = handles.iter().map(|&h| mesh.vertices[h]).collect();
    let regions = if options.regions.is_empty() {
        vec![(
            SampleRegion::Disc {
                radius: DEFAULT_DISC_FRACTION * bounding_box_diagonal(mesh),
            },
            1.0,
        )]
    } else {
        options.regions.clone()
    };
    let mut sampler = Sampler::new(&rest, &regions, options.seed)?;
    if !options.cover.is_empty() {
        sampler = sampler.with_cover(options.cover.clone(), options.cover_share)?;
    }
    let targets = cover_targets(
        &options.cover,
        &rest,
        options.cover_share,
        options.n_samples,
    );
    let mut configurations = vec![rest];
    configurations.extend(sampler.configurations(options.n_samples - targets.len()));
    configurations.extend(targets);
    Ok(configurations)
}

/// Where each stage ends, in samples besides the rest configuration: `2n + 1` (`n` handles),
/// then growing by the options' factor up to all samples.
fn stage_ends(n: usize, options: &TrainOptions) -> Vec<usize> {
    let mut ends = vec![(2 * n + 1).min(options.n_samples)];
    while let Some(&last) = ends.last() {
        if last >= options.n_samples {
            break;
        }
        ends.push((last * options.growth).min(options.n_samples));
    }
    ends
}

/// The handle basis a stage fits (ending at sample `end`, `last` or not, `n` handles): the
/// wanted one, except a polynomial basis with more functions than samples before the last
/// stage, which fits a linear one meanwhile.
fn stage_basis(options: &TrainOptions, last: bool, end: usize, n: usize) -> HandleBasisKind {
    let wanted = options.fit.handle_basis;
    if last || wanted == HandleBasisKind::ThinPlateSpline || wanted.n_functions(n, 0) <= end + 1 {
        wanted
    } else {
        HandleBasisKind::Linear
    }
}

/// The configurations of `cover` trained on as they are: the distinct ones other than the rest
/// (to 1e-12 of the rest's extent plus one unit of its size, so rounding does not count as a
/// new pose), at most `share · n_samples` of them, taken evenly along the list when there are
/// more.
fn cover_targets(
    cover: &[Vec<Point>],
    rest: &[Point],
    share: f64,
    n_samples: usize,
) -> Vec<Vec<Point>> {
    let size = rest
        .iter()
        .fold(0.0f64, |m, p| m.max(p.x.abs()).max(p.y.abs()))
        .max(1e-300);
    let same = |a: &[Point], b: &[Point]| {
        a.iter()
            .zip(b)
            .all(|(p, q)| (*p - *q).hypot() <= 1e-12 * size)
    };
    let mut distinct: Vec<&Vec<Point>> = Vec::new();
    for q in cover {
        if !same(q, rest) && !distinct.iter().any(|d| same(d, q)) {
            distinct.push(q);
        }
    }
    let budget = ((share * n_samples as f64).floor() as usize).min(distinct.len());
    (0..budget)
        .map(|k| distinct[k * distinct.len() / budget].clone())
        .collect()
}

/// How far the configuration `q` is from those trained on: the smallest, over the training
/// configurations `s`, of the largest handle distance `max_ℓ ‖q_ℓ − s_ℓ‖`. A configuration is
/// inside the region an operator was trained on when this is at most the sampling radius:
/// some sample has every handle within a disc's reach of `q`'s. (Every configuration drawn
/// in discs about the rest is inside, through the rest sample; the measure is the ∞-norm over
/// handles because one handle dragged far is what leaves the region, however still the
/// others are.)
///
/// ```
/// use kurbo::Point;
/// use splineskin_defop::trained_distance;
/// let trained = vec![vec![Point::new(0., 0.), Point::new(3., 0.)]];
/// let q = [Point::new(0.5, 0.), Point::new(3., 2.)];
/// assert_eq!(trained_distance(&trained, &q), 2.0);
/// ```
pub fn trained_distance(configurations: &[Vec<Point>], q: &[Point]) -> f64 {
    configurations
        .iter()
        .map(|s| {
            s.iter()
                .zip(q)
                .map(|(a, b)| (*a - *b).hypot2())
                .fold(0.0, f64::max)
        })
        .fold(f64::INFINITY, f64::min)
        .sqrt()
}

/// A stopwatch started now: the seconds since, by `std::time::Instant`. WebAssembly in a page
/// (`wasm32-unknown-unknown`) has no clock (`Instant::now` panics there): its stages are
/// timed as 0 s.
fn stopwatch() -> impl Fn() -> f64 {
    #[cfg(not(all(target_arch = "wasm32", target_os = "unknown")))]
    {
        let start = std::time::Instant::now();
        move || start.elapsed().as_secs_f64()
    }
    #[cfg(all(target_arch = "wasm32", target_os = "unknown"))]
    {
        || 0.0
    }
}
