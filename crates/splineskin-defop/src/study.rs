//! [`study()`]: the convergence experiment of Poranne & Lipman 2016, Fig. 8 (DESIGN.md §4):
//! for each handle basis, the error of the fitted operator against the ground truth on
//! held-out handle configurations as the number of training samples grows.
//!
//! ```text
//! 1. train once with the largest sample count m_max (train(): bootstrapped ground truths)
//! 2. draw n_held_out configurations from the same regions with another seed, and solve
//!    their ground truth from the rest pose (ground_truths_from_rest)
//! 3. for each basis Ψ and each count m: fit DefOp on the rest configuration and the first m
//!    training samples, and measure
//!        error(Ψ, m) = mean_k  l2_distance(D(·, Q_k), U_k) / diagonal
//!    (RMS distance over the shape, as a fraction of the rest mesh's bounding-box diagonal)
//! ```
//!
//! Prefixes of one sample set make the counts nested, as in the paper; every basis and count is
//! measured against the same held-out truth. That truth is solved from the rest pose, not from
//! an operator's prediction: both energies have several local minima for large displacements,
//! and a truth started from the operator under test would depend on that operator.

use std::time::Instant;

use kurbo::Point;

use super::distance::l2_distance;
use super::error::check_count_option;
use super::error::DefOpError;
use super::handle_basis::HandleBasisKind;
use super::handles::bounding_box_diagonal;
use super::operator::DefOp;
use super::sample::{SampleRegion, Sampler};
use super::spatial_basis::SpatialBasis;
use super::train::{
    ground_truths_from_rest, train, Progress, TrainOptions, Training, DEFAULT_DISC_FRACTION,
};
use splineskin_core::mesh::TriMesh;

/// Default [`StudyOptions::n_held_out`]: 20 held-out configurations.
pub const DEFAULT_HELD_OUT: usize = 20;

/// Default [`StudyOptions::held_out_seed`] (any seed other than the training's).
pub const DEFAULT_HELD_OUT_SEED: u64 = 424_242;

/// The four handle bases of the paper's Fig. 8, in the order the study reports them.
pub const STUDY_BASES: [HandleBasisKind; 4] = [
    HandleBasisKind::Linear,
    HandleBasisKind::Quadratic,
    HandleBasisKind::Cubic,
    HandleBasisKind::ThinPlateSpline,
];

/// Options of [`study()`].
///
/// ```
/// use splineskin_defop::{StudyOptions, TrainOptions};
/// let options = StudyOptions::new(TrainOptions::default(), vec![20, 40, 80]);
/// assert_eq!(options.n_held_out, 20);
/// ```
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct StudyOptions {
    /// Energy, sampling regions, seed, solvers and parallelism of the training and of the
    /// held-out solves; its `n_samples` and handle basis are replaced (the largest count, and
    /// thin-plate splines for bootstrapping).
    pub train: TrainOptions,
    /// The sample counts (each ≥ 1), increasing.
    pub sample_counts: Vec<usize>,
    /// Held-out configurations. Default: [`DEFAULT_HELD_OUT`].
    pub n_held_out: usize,
    /// Seed of the held-out sampler. Default: [`DEFAULT_HELD_OUT_SEED`].
    pub held_out_seed: u64,
    /// Handle bases measured. Default: [`STUDY_BASES`].
    pub bases: Vec<HandleBasisKind>,
}

impl StudyOptions {
    /// The study of `sample_counts` with the training options `train` and the defaults.
    pub fn new(train: TrainOptions, sample_counts: Vec<usize>) -> StudyOptions {
        StudyOptions {
            train,
            sample_counts,
            n_held_out: DEFAULT_HELD_OUT,
            held_out_seed: DEFAULT_HELD_OUT_SEED,
            bases: STUDY_BASES.to_vec(),
        }
    }
}

/// `count` sample counts from `first` to `last` in a geometric sequence (rounded, distinct,
/// increasing; `first` and `last` included).
///
/// ```
/// use splineskin_defop::geometric_sample_counts;
/// assert_eq!(geometric_sample_counts(25, 800, 6), vec![25, 50, 100, 200, 400, 800]);
/// ```
pub fn geometric_sample_counts(first: usize, last: usize, count: usize) -> Vec<usize> {
    let (first, last) = (first.max(1), last.max(first.max(1)));
    let ratio = (last as f64 / first as f64).powf(1.0 / (count.max(2) - 1) as f64);
    let mut counts: Vec<usize> = (0..count.max(2))
        .map(|k| (first as f64 * ratio.powi(k as i32)).round() as usize)
        .collect();
    counts.dedup();
    counts
}

/// Where a study is: training (as [`train`] reports it), then the held-out solves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StudyProgress {
    /// A training solve finished.
    Training(Progress),
    /// `done` of `total` held-out ground truths solved.
    HeldOut {
        /// Solved so far.
        done: usize,
        /// To solve.
        total: usize,
    },
}

/// One measurement of a [`Study`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StudyRow {
    /// The handle basis.
    pub basis: HandleBasisKind,
    /// Training samples besides the rest configuration.
    pub samples: usize,
    /// Mean over the held-out configurations of the RMS distance over the shape
    /// ([`l2_distance`]) to the ground truth, as a fraction of the bounding-box diagonal.
    pub error: f64,
    /// The largest of those distances, same unit.
    pub max_error: f64,
    /// Seconds of the fit.
    pub fit_seconds: f64,
}

/// The result of [`study()`].
#[derive(Clone, Debug)]
pub struct Study {
    /// One row per basis and count, bases in [`StudyOptions::bases`] order; thin-plate
    /// splines skip counts below `2n` (their side conditions need the rest configuration and
    /// `2n` more samples).
    pub rows: Vec<StudyRow>,
    /// The rest mesh's bounding-box diagonal (drawing units): the errors' unit.
    pub diagonal: f64,
    /// Held-out configurations measured.
    pub n_held_out: usize,
    /// The training (its largest count).
    pub training: Training,
    /// Seconds of the training.
    pub training_seconds: f64,
    /// Seconds of the held-out solves.
    pub held_out_seconds: f64,
}

/// Runs the convergence study (module documentation) on `mesh` with handles at `handles` and
/// spatial basis `spatial`. Errors as [`train`] and [`DefOp::fit`], or on empty or zero
/// sample counts or no held-out configuration.
///
/// ```
/// use kurbo::Rect;
/// use splineskin_defop::{study, SpatialBasis, StudyOptions, TrainOptions};
/// use splineskin_core::mesh::TriMesh;
/// let mesh = TriMesh::grid(Rect::new(0., 0., 4., 1.), 8, 2)?;
/// let spatial = SpatialBasis::hats(&mesh)?;
/// let mut options = StudyOptions::new(TrainOptions::default(), vec![5, 10]);
/// options.n_held_out = 3;
/// let result = study(&mesh, &[9, 17], &spatial, &options, &|_| {})?;
/// assert_eq!(result.rows.len(), 4 * 2);
/// assert!(result.rows.iter().all(|r| r.error.is_finite()));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn study(
    mesh: &TriMesh,
    handles: &[usize],
    spatial: &SpatialBasis,
    options: &StudyOptions,
    progress: &(dyn Fn(StudyProgress) + Sync),
) -> Result<Study, DefOpError> {
    let counts = &options.sample_counts;
    let largest = counts.iter().copied().max().unwrap_or(0);
    if counts.is_empty() || counts.contains(&0) {
        return Err(DefOpError::InvalidOption {
            name: "sample_counts",
            value: format!("{counts:?}"),
            expected: "at least one count, each at least 1",
        });
    }
    check_count_option("n_held_out", options.n_held_out)?;
    let train_options = options
        .train
        .clone()
        .with_n_samples(largest)
        .with_handle_basis(HandleBasisKind::ThinPlateSpline);
    let clock = Instant::now();
    let training = train(mesh, handles, spatial, &train_options, &|p| {
        progress(StudyProgress::Training(p));
    })?;
    let training_seconds = clock.elapsed().as_secs_f64();

    let diagonal = bounding_box_diagonal(mesh);
    let regions = if options.train.regions.is_empty() {
        vec![(
            SampleRegion::Disc {
                radius: DEFAULT_DISC_FRACTION * diagonal,
            },
            1.0,
        )]
    } else {
        options.train.regions.clone()
    };
    let rest: Vec<Point> = handles.iter().map(|&h| mesh.vertices[h]).collect();
    let held_out =
        Sampler::new(&rest, &regions, options.held_out_seed)?.configurations(options.n_held_out);
    let clock = Instant::now();
    let total = held_out.len();
    let truths = ground_truths_from_rest(mesh, handles, &options.train, &held_out, &|done| {
        progress(StudyProgress::HeldOut { done, total });
    })?;
    let held_out_seconds = clock.elapsed().as_secs_f64();

    let mut rows = Vec::with_capacity(options.bases.len() * counts.len());
    for &basis in &options.bases {
        for &m in counts {
            // Thin-plate interpolation needs the rest and 2n samples not on one hyperplane.
            if basis == HandleBasisKind::ThinPlateSpline && m < 2 * handles.len() {
                continue;
            }
            let clock = Instant::now();
            let op = DefOp::fit(
                mesh,
                handles,
                spatial,
                &training.configurations[..=m],
                &training.solutions[..=m],
                &train_options.fit.with_handle_basis(basis),
            )?;
            let fit_seconds = clock.elapsed().as_secs_f64();
            let mut evaluator = op.evaluator();
            let mut positions = vec![Point::ZERO; mesh.n_vertices()];
            let mut sum = 0.0;
            let mut max: f64 = 0.0;
            for (q, truth) in held_out.iter().zip(&truths) {
                evaluator.eval(q, &mut positions)?;
                let d = l2_distance(mesh, &positions, truth)? / diagonal;
                sum += d;
                max = max.max(d);
            }
            rows.push(StudyRow {
                basis,
                samples: m,
                error: sum / total as f64,
                max_error: max,
                fit_seconds,
            });
        }
    }
    Ok(Study {
        rows,
        diagonal,
        n_held_out: total,
        training,
        training_seconds,
        held_out_seconds,
    })
}
