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
//! **Starts.** ARAP (local–global with [`TRAINING_ANDERSON_DEPTH`] Anderson acceleration)
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

use std::sync::atomic::{AtomicUsize, Ordering};

pub use splineskin_core::stop::StopSignal;

use kurbo::Point;
use rayon::prelude::*;

use super::arap::{Arap, ArapOptions, TRAINING_ANDERSON_DEPTH};
use super::error::check_count_option;
use super::error::DefOpError;
use super::fit::DefOpOptions;
use super::handle_basis::HandleBasisKind;
use super::handles::bounding_box_diagonal;
use super::operator::DefOp;
use super::orientation::flipped_triangles;
use super::sample::{SampleRegion, Sampler};
use super::sarap::{SarapOptions, SymmetricArap};
use super::spatial_basis::SpatialBasis;
use splineskin_core::mesh::TriMesh;

/// Default [`TrainOptions::n_samples`]: 1 000, the paper's octopus (Fig. 1).
pub const DEFAULT_TRAINING_SAMPLES: usize = 1000;

/// Default share of the samples drawn along the way to [`TrainOptions::cover`]: one half (the
/// other half stays around the rest, where small edits happen).
pub const DEFAULT_COVER_SHARE: f64 = 0.5;

/// Default disc radius of the samples when [`TrainOptions::regions`] is empty, as a fraction
/// of the mesh's bounding-box diagonal: 0.05 (0.4 drawing units on the 8.3-wide octopus,
/// where its arms are 2.2 long).
pub const DEFAULT_DISC_FRACTION: f64 = 0.05;

/// Default [`TrainOptions::growth`]: each bootstrapping stage has 4 times the samples of the
/// previous one (19, 76, 304, 1 000 for nine handles).
pub const DEFAULT_GROWTH: usize = 4;

/// The variational deformation a training samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Energy {
    /// As-rigid-as-possible, Eq. (10) ([`Arap`]).
    Arap,
    /// Symmetric ARAP, Eq. (11) ([`SymmetricArap`]).
    SymmetricArap,
}

/// Where the ground-truth solves of later stages start.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum WarmStart {
    /// From the current operator's prediction (the paper's bootstrapping).
    Bootstrap,
    /// From the rest pose, every sample.
    Rest,
}

/// Options of [`train`].
///
/// ```
/// use splineskin_defop::{Energy, TrainOptions};
/// let options = TrainOptions::default().with_energy(Energy::Arap).with_n_samples(200);
/// assert_eq!((options.energy, options.n_samples), (Energy::Arap, 200));
/// ```
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct TrainOptions {
    /// The ground truth. Default: [`Energy::SymmetricArap`] (the paper's main choice: no
    /// flips, no cusps).
    pub energy: Energy,
    /// Samples besides the rest configuration. Default: [`DEFAULT_TRAINING_SAMPLES`].
    pub n_samples: usize,
    /// Where configurations are drawn ([`Sampler`]); empty means one disc of
    /// [`DEFAULT_DISC_FRACTION`] of the bounding-box diagonal. Default: empty.
    pub regions: Vec<(SampleRegion, f64)>,
    /// Configurations to cover besides the rest (one point per handle each: a scene's poses,
    /// its animation's frames), sampled along the way to them ([`Sampler::with_cover`]); the
    /// distinct targets are samples themselves (at most the cover's share of the samples,
    /// spread evenly over the list). Default: none.
    pub cover: Vec<Vec<Point>>,
    /// The share of samples drawn along the way to [`TrainOptions::cover`]. Default:
    /// [`DEFAULT_COVER_SHARE`].
    pub cover_share: f64,
    /// Seed of the sampler. Default: 1.
    pub seed: u64,
    /// The fit, its handle basis included. Default: [`DefOpOptions::default`] (thin-plate
    /// splines).
    pub fit: DefOpOptions,
    /// Starts of the ground-truth solves. Default: [`WarmStart::Bootstrap`].
    pub warm_start: WarmStart,
    /// Factor between the sample counts of successive stages (≥ 2). Default:
    /// [`DEFAULT_GROWTH`].
    pub growth: usize,
    /// ARAP solver options. Default: [`ArapOptions::default`] with
    /// [`TRAINING_ANDERSON_DEPTH`].
    pub arap: ArapOptions,
    /// Symmetric ARAP solver options. Default: [`SarapOptions::default`].
    pub sarap: SarapOptions,
    /// Solve a stage's samples on rayon's thread pool. Default: `false` (STYLE.md:
    /// sequential unless asked).
    pub parallel: bool,
    /// Stops the training between solves when raised ([`StopSignal`]). Default: a signal
    /// nobody else holds, never raised.
    pub stop: StopSignal,
}

/// [`DefOpError::Stopped`] once `stop` is raised.
fn check_stop(stop: &StopSignal) -> Result<(), DefOpError> {
    if stop.is_raised() {
        Err(DefOpError::Stopped)
    } else {
        Ok(())
    }
}

impl Default for TrainOptions {
    fn default() -> Self {
        TrainOptions {
            energy: Energy::SymmetricArap,
            n_samples: DEFAULT_TRAINING_SAMPLES,
            regions: Vec::new(),
            cover: Vec::new(),
            cover_share: DEFAULT_COVER_SHARE,
            seed: 1,
            fit: DefOpOptions::default(),
            warm_start: WarmStart::Bootstrap,
            growth: DEFAULT_GROWTH,
            arap: ArapOptions::default().with_anderson_depth(TRAINING_ANDERSON_DEPTH),
            sarap: SarapOptions::default(),
            parallel: false,
            stop: StopSignal::new(),
        }
    }
}

impl TrainOptions {
    /// How far from its centre the sampling moves a handle, drawing units: the largest
    /// radius of the disc and circle regions, two standard deviations of a Gaussian one, and
    /// [`DEFAULT_DISC_FRACTION`] of `mesh`'s bounding-box diagonal for a Voronoi cell (whose
    /// size varies per handle) or when there are no regions (the default disc's). The
    /// radius of "the region an operator was trained on" ([`trained_distance`]).
    ///
    /// ```
    /// use kurbo::Rect;
    /// use splineskin_defop::{SampleRegion, TrainOptions};
    /// use splineskin_core::mesh::TriMesh;
    /// let mesh = TriMesh::grid(Rect::new(0., 0., 4., 3.), 4, 3)?;
    /// assert!((TrainOptions::default().reach(&mesh) - 0.25).abs() < 1e-12); // 5 % of 5
    /// let disc = TrainOptions::default().with_regions(vec![(SampleRegion::Disc { radius: 0.7 }, 1.0)]);
    /// assert_eq!(disc.reach(&mesh), 0.7);
    /// # Ok::<(), splineskin_core::mesh::MeshError>(())
    /// ```
    pub fn reach(&self, mesh: &TriMesh) -> f64 {
        let default = DEFAULT_DISC_FRACTION * bounding_box_diagonal(mesh);
        self.regions
            .iter()
            .map(|(region, _)| match *region {
                SampleRegion::Disc { radius } | SampleRegion::Circle { radius } => radius,
                SampleRegion::Gaussian { sigma } => 2.0 * sigma,
                SampleRegion::VoronoiCell { .. } => default,
            })
            .reduce(f64::max)
            .unwrap_or(default)
    }

    /// Sets [`TrainOptions::energy`].
    pub fn with_energy(mut self, energy: Energy) -> Self {
        self.energy = energy;
        self
    }
    /// Sets [`TrainOptions::n_samples`].
    pub fn with_n_samples(mut self, n: usize) -> Self {
        self.n_samples = n;
        self
    }
    /// Sets [`TrainOptions::regions`].
    pub fn with_regions(mut self, regions: Vec<(SampleRegion, f64)>) -> Self {
        self.regions = regions;
        self
    }
    /// Sets [`TrainOptions::cover`].
    pub fn with_cover(mut self, configurations: Vec<Vec<Point>>) -> Self {
        self.cover = configurations;
        self
    }
    /// Sets [`TrainOptions::seed`].
    pub fn with_seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }
    /// Sets [`TrainOptions::fit`].
    pub fn with_fit(mut self, fit: DefOpOptions) -> Self {
        self.fit = fit;
        self
    }
    /// Sets the fit's handle basis ([`DefOpOptions::handle_basis`]).
    pub fn with_handle_basis(mut self, kind: HandleBasisKind) -> Self {
        self.fit.handle_basis = kind;
        self
    }
    /// Sets [`TrainOptions::warm_start`].
    pub fn with_warm_start(mut self, start: WarmStart) -> Self {
        self.warm_start = start;
        self
    }
    /// Sets [`TrainOptions::growth`].
    pub fn with_growth(mut self, growth: usize) -> Self {
        self.growth = growth;
        self
    }
    /// Sets [`TrainOptions::arap`].
    pub fn with_arap(mut self, arap: ArapOptions) -> Self {
        self.arap = arap;
        self
    }
    /// Sets [`TrainOptions::sarap`].
    pub fn with_sarap(mut self, sarap: SarapOptions) -> Self {
        self.sarap = sarap;
        self
    }
    /// Sets [`TrainOptions::parallel`].
    pub fn with_parallel(mut self, parallel: bool) -> Self {
        self.parallel = parallel;
        self
    }
    /// Sets [`TrainOptions::stop`]: a running [`train`], [`extend`] or
    /// [`ground_truths_from_rest`] skips each solve not started once it is raised and returns
    /// [`DefOpError::Stopped`]; a solve under way finishes first (its cost is one ground truth).
    ///
    /// ```
    /// use kurbo::Rect;
    /// use splineskin_defop::{train, DefOpError, Energy, SpatialBasis, StopSignal, TrainOptions};
    /// use splineskin_core::mesh::TriMesh;
    /// let mesh = TriMesh::grid(Rect::new(0., 0., 4., 1.), 8, 2)?;
    /// let stop = StopSignal::new();
    /// let options = TrainOptions::default().with_energy(Energy::Arap).with_n_samples(40).with_stop(stop.clone());
    /// let solved = std::sync::atomic::AtomicUsize::new(0);
    /// // The callback stops the training after its fifth solve.
    /// let result = train(&mesh, &[9, 17], &SpatialBasis::hats(&mesh)?, &options, &|p| {
    ///     solved.store(p.solved, std::sync::atomic::Ordering::Relaxed);
    ///     if p.solved == 5 {
    ///         stop.raise();
    ///     }
    /// });
    /// assert!(matches!(result, Err(DefOpError::Stopped)));
    /// assert!(stop.is_raised());
    /// assert_eq!(solved.into_inner(), 5);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn with_stop(mut self, stop: StopSignal) -> Self {
        self.stop = stop;
        self
    }
}

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

/// The ground-truth solvers of a training: ARAP, and symmetric ARAP when that is the energy
/// (ARAP then gives it starts).
struct Solver {
    arap: Arap,
    sarap: Option<SymmetricArap>,
}

/// One sample's solve: its solution, iterations (of the solve that succeeded), which start
/// succeeded, whether it converged.
struct Solved {
    solution: Vec<Point>,
    iterations: usize,
    start: Start,
    converged: bool,
}

/// The start a sample's solve succeeded from.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Start {
    /// The operator's prediction, or the rest pose when there is none (ARAP; stage 0).
    First,
    /// Symmetric ARAP: the sample's ARAP solution.
    Arap,
    /// Symmetric ARAP: the rest pose, after the others were refused or failed.
    Rest,
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
    let solver = Solver {
        arap: Arap::new(mesh, handles, options.arap)?,
        sarap: match options.energy {
            Energy::Arap => None,
            Energy::SymmetricArap => Some(SymmetricArap::new(mesh, handles, options.sarap)?),
        },
    };
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

/// The ground truths at `configurations` solved from the rest pose, independently of any
/// operator: the held-out truth of the convergence study ([`super::study()`]), deterministic
/// for a given mesh and configuration. `options` gives the energy, the solver options and
/// [`TrainOptions::parallel`] (rayon); its samples and fit are ignored. Symmetric ARAP tries
/// the rest pose's ARAP solution first (if flip-free), then the rest pose, as [`train`] does
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
    let solver = Solver {
        arap: Arap::new(mesh, handles, options.arap)?,
        sarap: match options.energy {
            Energy::Arap => None,
            Energy::SymmetricArap => Some(SymmetricArap::new(mesh, handles, options.sarap)?),
        },
    };
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
fn solve_sample(
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
    /// Samples whose solver stopped before converging (ARAP; kept, as [`train`] keeps them).
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
/// current operator's prediction (symmetric ARAP falls back as in [`train`]); the refit is
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
    let solver = Solver {
        arap: Arap::new(mesh, &handles, options.arap)?,
        sarap: match options.energy {
            Energy::Arap => None,
            Energy::SymmetricArap => Some(SymmetricArap::new(mesh, &handles, options.sarap)?),
        },
    };
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
