//! Side-by-side comparison of the spline fit with the naive baselines (paper §5 and its
//! Figs. 1, 3, 7): every method deforms the same drawing by the same pose, and each result is
//! measured against the same target, the exactly skinned input curves
//! `s_j(t) = Σ_i w_i(B_j(t)) T_i B̄_j(t)` ([`crate::metrics`]).
//!
//! | [`Method`] | result | distance to the target |
//! |---|---|---|
//! | `ours` | [`SplineRig`](crate::spline_fit::SplineRig): fixed tangent-length ratios | parametric |
//! | `ours-flexible` | [`FlexibleSolver`](crate::spline_fit::FlexibleSolver): G¹ and fixed-angle ratios free | parametric |
//! | `fourcontrols` | [`naive::skin_control_points`](crate::naive::skin_control_points) | parametric |
//! | `twoendpoints` | [`naive::skin_on_curve_points`](crate::naive::skin_on_curve_points) | parametric |
//! | `jacobian` | [`naive::skin_with_jacobian`](crate::naive::skin_with_jacobian) | parametric |
//! | `schneider` | [`naive::schneider_refit`](crate::naive::schneider_refit) (more curves) | closest point |
//! | `schneider-same-count` | [`naive::schneider_refit_same_count`](crate::naive::schneider_refit_same_count) (at most the input's curves per path) | closest point |
//! | `ours-adaptive` (when asked) | the fit of the drawing refined by [`crate::adaptive::refine`] for the pose: more curves, every input anchor kept | closest point |
//! | `schneider-adaptive-count` (when asked) | [`naive::schneider_refit_within`](crate::naive::schneider_refit_within) with `ours-adaptive`'s curve count per path | closest point |
//!
//! "Parametric" is `‖R_j(t) − s_j(t)‖` at equal `t` ([`metrics::chain_metrics`](crate::metrics::chain_metrics)); "closest
//! point" is the distance from `s_j(t)` to the nearest point of the refitted path
//! ([`metrics::refit_metrics`](crate::metrics::refit_metrics)): a refit has its own curves and parametrisation. The distances
//! along the target ([`MethodResult::distances`]) are exactly those the metrics' max and RMS
//! are taken over (uniform `t_k = k / (S − 1)`, `S` = [`MetricsOptions::samples_per_curve`](crate::metrics::MetricsOptions::samples_per_curve)),
//! so the picture ([`render_comparison`](crate::figure::comparison::render_comparison), drawn by [`crate::figure::comparison`]) and the table show the same numbers.
//!
//! ```text
//! once per comparison:  drawing + weights + pose ──► compare_methods ──► Comparison
//!                       (or a PosedDrawing + pose ──► compare_posed: its rig is reused)
//!                       Comparison + posed handle markers ──► render_comparison ──► PNG
//! ```

pub(crate) mod methods;

pub use methods::{
    compare_methods, compare_posed, posed_markers, CompareError, CompareInputs, CompareOptions,
    Comparison, Method, MethodResult, DEFAULT_REFIT_TOLERANCE_FRACTION,
};
