//! The paper's spline fit: the cubic closest (in L²) to each skinned curve, under the drawing's
//! junction constraints, as a linear operator of the handle transforms.
//!
//! | paper (Liu et al. 2014 §4) | here |
//! |---|---|
//! | `Â` (Gram matrix of the Bernstein basis) | [`quadrature::CurveNodes::gram`] |
//! | `Ŵ_i` (weighted Gram times `C̄`) | [`weighted_integrals`] ([`quadrature::CurveNodes::weighted_grams`] times `C̄`) |
//! | continuity constraints (Table 1) | [`constraints`] |
//! | per-handle operators `O_i` | [`SplineRig`] rows |
//!
//! See [`SplineRig`] for the precompute / update recipe.

pub mod constraints;
pub mod flexible;
mod frame_product;
pub mod quadrature;
mod rig;
pub mod shared_curves;
pub mod system;
pub mod weighted_integrals;

pub use constraints::ConstraintForm;
pub use flexible::{FlexibleError, FlexibleOptions, FlexibleReport, FlexibleRule, FlexibleSolver};
pub use frame_product::{update_threads, BYTES_PER_THREAD, PARALLEL_MIN_BYTES};
pub use quadrature::{Measure, Quadrature};
pub use rig::validate;
pub use rig::{PoseError, SplineRig};

use crate::drawing::JunctionOptions;

/// Options of the fit.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct FitOptions {
    /// The integration rule. Default: [`Quadrature::default`] (composite Gauss–Legendre).
    pub quadrature: Quadrature,
    /// The measure along curves. Default: [`Measure::LengthWeighted`].
    pub measure: Measure,
    /// How junction constraints are written. Default: [`ConstraintForm::Ours`].
    pub constraint_form: ConstraintForm,
    /// Tolerances used when writing constraints (the smooth angle under which G¹ keeps the
    /// input's own angle, the coincidence distance). Default: [`JunctionOptions::default`].
    pub junctions: JunctionOptions,
    /// Solve paths (and sample their weights) on several threads (rayon's global pool).
    /// Default: `false` (sequential), so that the library never spawns threads unasked.
    pub parallel: bool,
    /// Check every path's system for rank deficiency with a dense SVD (slow; compatibility
    /// mode uses it to report the paths where the authors' solver is ill-posed). Default: false.
    pub check_rank: bool,
    /// Fit curves shared by several paths once, so that every path along them gets the same
    /// deformed curve ([`shared_curves`]; our constraint form only), so that fills and their
    /// outlines, and regions that touch, stay watertight. Default: true (false in the
    /// compatibility mode, whose solver fits every path alone). A path of such a group is not
    /// iterated by the flexible G¹ solver ([`flexible`]): it keeps the group's fixed-ratio
    /// result, since iterated alone it would part from its neighbours at the shared curves.
    pub share_curves: bool,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            quadrature: Quadrature::default(),
            measure: Measure::LengthWeighted,
            constraint_form: ConstraintForm::Ours,
            junctions: JunctionOptions::default(),
            parallel: false,
            check_rank: false,
            share_curves: true,
        }
    }
}

impl FitOptions {
    /// The paper authors' discretisation (compatibility mode `vectorskinning`): their 100-sample
    /// midpoint rule for both sides, polyline-length weighting, their constraint rows, and the
    /// rank check. `arc_length` selects their arc-length measure.
    pub fn vectorskinning(arc_length: bool) -> FitOptions {
        FitOptions {
            quadrature: Quadrature::AuthorsMidpoint {
                samples: quadrature::AUTHORS_SAMPLES,
            },
            measure: Measure::from_arc_length(arc_length),
            constraint_form: ConstraintForm::Authors,
            junctions: JunctionOptions::default(),
            parallel: false,
            check_rank: true,
            share_curves: false,
        }
    }

    /// Sets [`FitOptions::measure`].
    pub fn with_measure(mut self, measure: Measure) -> Self {
        self.measure = measure;
        self
    }
    /// Sets [`FitOptions::quadrature`].
    pub fn with_quadrature(mut self, quadrature: Quadrature) -> Self {
        self.quadrature = quadrature;
        self
    }
    /// Sets [`FitOptions::parallel`].
    pub fn with_parallel(mut self, parallel: bool) -> Self {
        self.parallel = parallel;
        self
    }
    /// Sets [`FitOptions::share_curves`].
    pub fn with_share_curves(mut self, share: bool) -> Self {
        self.share_curves = share;
        self
    }
    /// Sets [`FitOptions::check_rank`].
    pub fn with_check_rank(mut self, check: bool) -> Self {
        self.check_rank = check;
        self
    }
}

/// Why a rig could not be built.
#[derive(Debug, thiserror::Error, PartialEq)]
#[non_exhaustive]
pub enum FitError {
    /// The weight field has no handles.
    #[error("no handles: a rig needs at least one handle")]
    NoHandles,
    /// The drawing has no paths.
    #[error("the drawing has no paths to fit (expected at least one path with a curve)")]
    NoPaths,
    /// A control point is NaN or infinite.
    #[error("path {path}, point {point}: coordinate is not finite ({x}, {y})")]
    NonFinite {
        /// Path index.
        path: usize,
        /// Chain point index.
        point: usize,
        /// x coordinate.
        x: f64,
        /// y coordinate.
        y: f64,
    },
    /// A path's joint list does not match its curves.
    #[error("path {path}: {got} joint kinds, expected {expected} for {n_curves} curves")]
    JointCount {
        /// Path index.
        path: usize,
        /// Number given.
        got: usize,
        /// Number expected.
        expected: usize,
        /// Curves in the path.
        n_curves: usize,
    },
    /// A path has a malformed chain.
    #[error("path {path}: {n_points} chain points is not 3n+1 with n ≥ 1 (or a closed path does not end at its start)")]
    BadChain {
        /// Path index.
        path: usize,
        /// Points in the chain.
        n_points: usize,
    },
    /// The sampled weights were computed for another drawing.
    #[error("weights were sampled on {sampled} curves but the drawing has {curves}")]
    SamplesMismatch {
        /// Curves in the samples.
        sampled: usize,
        /// Curves in the drawing.
        curves: usize,
    },
    /// The system of a path is singular although it should not be (a bug).
    #[error(
        "path {path}: the fit system is singular; this is a bug, please report it with the drawing"
    )]
    Singular {
        /// Path index.
        path: usize,
    },
    /// The sparse solver failed.
    #[error("path {path}: sparse solver failed: {detail}")]
    Solver {
        /// Path index.
        path: usize,
        /// The solver's message.
        detail: String,
    },
}
