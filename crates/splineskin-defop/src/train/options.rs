//! [`TrainOptions`]: the energy, sample counts and regions, bootstrapping and solver options
//! of a training, with their defaults.

use kurbo::Point;
pub use splineskin_core::stop::StopSignal;

use super::super::arap::{ArapOptions, TRAINING_ANDERSON_DEPTH};
use super::super::error::DefOpError;
use super::super::fit::DefOpOptions;
use super::super::handle_basis::HandleBasisKind;
use super::super::handles::bounding_box_diagonal;
use super::super::sample::SampleRegion;
use super::super::sarap::SarapOptions;
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
    /// As-rigid-as-possible, Eq. (10) ([`crate::Arap`]).
    Arap,
    /// Symmetric ARAP, Eq. (11) ([`crate::SymmetricArap`]).
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

/// Options of [`super::train()`].
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
    /// Where configurations are drawn ([`crate::Sampler`]); empty means one disc of
    /// [`DEFAULT_DISC_FRACTION`] of the bounding-box diagonal. Default: empty.
    pub regions: Vec<(SampleRegion, f64)>,
    /// Configurations to cover besides the rest (one point per handle each: a scene's poses,
    /// its animation's frames), sampled along the way to them ([`crate::Sampler::with_cover`]); the
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
pub(super) fn check_stop(stop: &StopSignal) -> Result<(), DefOpError> {
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
    /// radius of "the region an operator was trained on" ([`super::trained_distance`]).
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
    /// Sets [`TrainOptions::stop`]: a running [`super::train()`], [`super::extend()`] or
    /// [`super::ground_truths_from_rest`] skips each solve not started once it is raised and returns
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
