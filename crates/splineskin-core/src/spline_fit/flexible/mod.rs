//! Flexible G¹ and flexible fixed-angle junctions: the fit with the tangent-length ratio at G¹
//! and fixed-angle junctions left free (DESIGN.md §1, "Flexible G¹"; Liu et al. 2014 §4).
//!
//! The rig ([`super::SplineRig`]) keeps the input's ratio `r = l_v / l_u` at every G¹ and
//! fixed-angle junction, a linear row. Flexible, such a junction only asks the deformed tangents
//! to be parallel (fixed angle: the outgoing one is the incoming one turned by the input's angle
//! `θ`), which is not linear. The energy is the fit's own (per path, over its unknown points
//! `x`, as in the rig's `system` module):
//!
//! ```text
//! E(x) = Σ_j ∫ ‖Σ_k x_jk b_k(t) − s_j(t)‖² dμ_j,     s_j(t) = Σ_i w_i(B_j(t)) T_i B̄_j(t)
//! ```
//!
//! (the squared L² distance to the skinned target, by the fit's quadrature). Three rules
//! minimise it ([`FlexibleRule`]):
//!
//! * **Newton** ([`FlexibleRule::Newton`], the default): at a flexible junction with point
//!   `P_p` the neighbours are `P_a = P_p + α R(φ) û`, `P_b = P_p + β R(φ) v̂`, tangent scalars
//!   `α, β > 0` and a common turn `φ`; each step solves one linear KKT system for all points,
//!   scalars and turns (Newton, or Gauss–Newton where Newton's step is not a descent), the
//!   scalars kept above [`MIN_HELD_FRACTION`] of the input's tangent lengths by an active set,
//!   the turns below [`MAX_TURN`], halved until `E` decreases. From the fixed-ratio fit of the
//!   pose it takes one or two solves per path (192 for the 140 flexible paths of the authors'
//!   turtles, where the alternation takes about 1 100).
//! * **Alternation** ([`FlexibleRule::Alternating`], the method of the paper): a *ratio step*
//!   (the rig's rows with the current tangent lengths) and a *direction step* (the neighbours
//!   as scalars along the current tangent directions) in turn, each the minimiser of `E` over a
//!   set that contains the current solution, so `E` never increases; a direction step is
//!   shortened to keep every scalar above [`MIN_SCALAR_FRACTION`] of its current value.
//! * **The authors' rule** ([`FlexibleRule::Authors`], compatibility mode): their schedule
//!   (a direction step along the input's tangents, then at most [`AUTHORS_MAX_ROUNDS`] rounds)
//!   and their stopping test (numpy's `allclose` with [`AUTHORS_ATOL`], [`AUTHORS_RTOL`]); no
//!   energy check.
//!
//! Newton and alternation stop when a step (a round) lowers `E` by less than
//! [`FlexibleOptions::tolerance`] relative plus the energy of a [`NOISE_DISTANCE`] deviation
//! along the whole path (below it the energy is rounding), or after
//! [`FlexibleOptions::max_steps`] steps.
//!
//! **Where each part is.** Each file states what it computes and its formulas:
//!
//! | file | computes |
//! |---|---|
//! | `options.rs` | [`FlexibleRule`], [`FlexibleOptions`] and their defaults |
//! | `energy.rs` | one path's `E`, skinned target, right-hand side, half-gradient and noise floor |
//! | `layout.rs` | which junctions are flexible, the steps' unknowns and KKT patterns (solved by `crate::linalg::LdltLu`: `LDLᵀ` in chain order, a pivoting LU where that fails), the ratio and direction steps |
//! | `newton.rs` | [`FlexibleRule::Newton`]: the (Gauss–)Newton step, its active set and line search |
//! | `alternation.rs` | [`FlexibleRule::Alternating`]: direction and ratio steps in turn |
//! | `authors.rs` | [`FlexibleRule::Authors`]: the authors' schedule and stopping test |
//! | `mod.rs` | [`FlexibleSolver`]: building the paths' systems, the warm start, the dispatch to a rule, the report |
//!
//! Arrows go one way: `mod.rs` → the three rules → `layout.rs` → `energy.rs`, `crate::linalg` (the
//! rules read `energy.rs` and `options.rs` too); no file reads `mod.rs` outside tests.
//!
//! **Paths.** Paths are independent; only those with a flexible junction iterate, in parallel
//! with [`super::FitOptions::parallel`]. Other paths keep the rig's result, and so do paths that
//! share curves with others (the rig solves them as one group; iterated alone they would part).
//! Each step's KKT matrix has a fixed pattern per path and step kind: its symbolic
//! factorisations are computed once, in [`FlexibleSolver::new`]; each step refactors
//! numerically.
//!
//! **Warm start.** The result depends on the pose, not linearly: [`FlexibleSolver::solve`]
//! starts, per path, from the rig's fixed-ratio result for the pose or, given a previous
//! solution (`warm`, for dragging), from a start made from it where that has the lower energy,
//! so the result is never worse than the rig's. Newton's is the previous solution itself: it
//! wins when the pose barely moved; otherwise the fixed-ratio fit of the new pose is much closer
//! to the new optimum (on the turtles, a Newton step from the previous solution lands further
//! away than the fixed-ratio fit is). Alternation's is a ratio step with the previous solution's
//! tangent ratios. The authors' rule uses it in place of its first direction step.

mod alternation;
mod authors;
mod energy;
mod layout;
mod newton;
mod options;

use kurbo::{Affine, Point, Vec2};

use super::quadrature::SampledCurves;
use super::rig::{PoseError, SplineRig};
use super::{ConstraintForm, FitError, FitOptions};
use crate::drawing::Drawing;
use energy::{path_nodes, PathNodes};
use layout::{flex_path, FlexPath, PathRun, Scratch};

pub use alternation::MIN_SCALAR_FRACTION;
pub use authors::{AUTHORS_ATOL, AUTHORS_MAX_ROUNDS, AUTHORS_RTOL};
pub use energy::NOISE_DISTANCE;
pub use newton::{MAX_TURN, MIN_HELD_FRACTION};
pub use options::{FlexibleOptions, FlexibleRule, DEFAULT_MAX_STEPS, DEFAULT_TOLERANCE};

/// What a flexible solve did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FlexibleReport {
    /// Paths iterated (those with a flexible junction).
    pub paths: usize,
    /// Steps of the path that took the most: its linear solves, plus one for a warm start taken
    /// (module doc).
    pub steps: usize,
    /// Steps over all paths.
    pub total_steps: usize,
    /// The energy `E` of the whole drawing at the start (index 0) and after each step (a path
    /// that stopped counts with its final energy).
    pub energies: Vec<f64>,
    /// The energy of the rig's fixed-ratio result for this pose.
    pub fixed_ratio_energy: f64,
    /// Steps shortened to keep every tangent scalar positive (and, for Newton, every
    /// junction's turn below [`MAX_TURN`]).
    pub shortened_steps: usize,
    /// Paths started from the `warm` solution's ratios (that had the lower energy).
    pub warm_started_paths: usize,
    /// `(path, steps)` for every path iterated, in drawing order.
    pub path_steps: Vec<(usize, usize)>,
}

impl FlexibleReport {
    /// The energy of the result.
    pub fn energy(&self) -> f64 {
        self.energies
            .last()
            .copied()
            .unwrap_or(self.fixed_ratio_energy)
    }
}

/// Why a flexible solve failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FlexibleError {
    /// A pose, output or warm-start buffer of the wrong size.
    #[error(transparent)]
    Pose(#[from] PoseError),
    /// A linear solve failed.
    #[error(transparent)]
    Fit(#[from] FitError),
}

/// The fit with flexible G¹ and fixed-angle junctions (module doc): a [`SplineRig`] for the
/// start and the paths without such junctions, plus the step systems (ratio, direction and
/// Gauss–Newton) of every path that has them.
///
/// ```text
/// once:        let solver = FlexibleSolver::new(&drawing, &samples, &fit, FlexibleOptions::default())?;
/// each pose:   let report = solver.solve(&pose, None, &mut points)?;
/// dragging:    solver.solve(&pose, Some(&previous), &mut points)?;   // warm start
/// ```
///
/// ```
/// use kurbo::{Affine, Point};
/// use splineskin_core::drawing::{Drawing, JointKind, JunctionOptions, Path};
/// use splineskin_core::spline_fit::quadrature::SampledCurves;
/// use splineskin_core::spline_fit::{FitOptions, FlexibleOptions, FlexibleSolver};
/// use splineskin_core::weights::{Shepard, ShepardOptions};
///
/// // Two curves meeting smoothly at (3, 0), tangent lengths 1 and 2 (a G¹ junction).
/// let pts = [(0., 0.), (1., 1.), (2., 0.), (3., 0.), (5., 0.), (6., 1.), (7., 0.)]
///     .map(Point::from)
///     .to_vec();
/// let path = Path::new(pts, false, &JunctionOptions::default()).unwrap();
/// assert_eq!(path.joints[1], JointKind::G1);
/// let drawing = Drawing { paths: vec![path], ..Default::default() };
/// let weights = Shepard::new(&[Point::new(0., 0.), Point::new(7., 0.)], ShepardOptions::default());
/// let fit = FitOptions::default();
/// let samples = SampledCurves::sample(&drawing, &weights, &fit);
/// let solver = FlexibleSolver::new(&drawing, &samples, &fit, FlexibleOptions::default()).unwrap();
///
/// let pose = [Affine::IDENTITY, Affine::rotate_about(0.5, Point::new(7., 0.))];
/// let mut out = vec![Point::ZERO; solver.rig().n_points()];
/// let report = solver.solve(&pose, None, &mut out).unwrap();
/// // Never worse than the fixed-ratio fit, and the energy never goes up.
/// assert!(report.energy() <= report.fixed_ratio_energy);
/// assert!(report.energies.windows(2).all(|e| e[1] <= e[0]));
/// // The junction stays G¹: parallel tangents.
/// let (u, v) = (out[3] - out[2], out[4] - out[3]);
/// assert!(u.cross(v).abs() <= 1e-9 * u.hypot() * v.hypot() && u.dot(v) > 0.0);
/// ```
#[derive(Clone, Debug)]
pub struct FlexibleSolver {
    rig: SplineRig,
    nodes: Vec<PathNodes>,
    paths: Vec<FlexPath>,
    options: FlexibleOptions,
    parallel: bool,
}

impl FlexibleSolver {
    /// Builds the rig ([`SplineRig::from_samples`]) and the flexible paths' systems.
    pub fn new(
        drawing: &Drawing,
        samples: &SampledCurves,
        fit: &FitOptions,
        options: FlexibleOptions,
    ) -> Result<FlexibleSolver, FitError> {
        let rig = SplineRig::from_samples(drawing, samples, fit)?;
        FlexibleSolver::from_rig(rig, drawing, samples, fit, options)
    }

    /// Builds the flexible paths' systems around a rig already built from the same drawing,
    /// samples and fit options.
    pub fn from_rig(
        rig: SplineRig,
        drawing: &Drawing,
        samples: &SampledCurves,
        fit: &FitOptions,
        options: FlexibleOptions,
    ) -> Result<FlexibleSolver, FitError> {
        if samples.n_curves() != drawing.n_curves() {
            return Err(FitError::SamplesMismatch {
                sampled: samples.n_curves(),
                curves: drawing.n_curves(),
            });
        }
        let mut nodes = Vec::with_capacity(drawing.paths.len());
        let (mut offset, mut first_curve) = (0, 0);
        for path in &drawing.paths {
            nodes.push(path_nodes(path, samples, first_curve, offset));
            offset += path.points.len();
            first_curve += path.n_curves();
        }
        // Paths that share curves with others are solved as one group by the rig; iterated
        // alone they would part at the shared curves, so they keep the rig's result.
        let grouped = if fit.share_curves && fit.constraint_form == ConstraintForm::Ours {
            let shared = super::shared_curves::SharedCurves::find(drawing);
            let mut grouped = vec![false; drawing.paths.len()];
            for p in shared.groups.iter().flatten() {
                grouped[*p] = true;
            }
            grouped
        } else {
            vec![false; drawing.paths.len()]
        };
        let built: Vec<Option<FlexPath>> =
            crate::parallel::try_map(&drawing.paths, fit.parallel, |pi, path| {
                if grouped[pi] {
                    Ok(None)
                } else {
                    flex_path(pi, path, &nodes[pi], fit)
                }
            })?;
        Ok(FlexibleSolver {
            rig,
            nodes,
            paths: built.into_iter().flatten().collect(),
            options,
            parallel: fit.parallel,
        })
    }

    /// The fixed-ratio rig (the start of every solve, and the result of paths without flexible
    /// junctions).
    pub fn rig(&self) -> &SplineRig {
        &self.rig
    }

    /// The options.
    pub fn options(&self) -> &FlexibleOptions {
        &self.options
    }

    /// Indices of the paths that iterate (those with a flexible junction).
    pub fn flexible_paths(&self) -> impl Iterator<Item = usize> + '_ {
        self.paths.iter().map(|p| p.path)
    }

    /// Number of flexible junctions over all paths.
    pub fn n_flexible_junctions(&self) -> usize {
        self.paths.iter().map(|p| p.layout.flexible.len()).sum()
    }

    /// The fit energy `E` (module doc) of the control points `points` (layout of
    /// [`Drawing::flat_points`]) for the handle maps `pose`: the squared L² distance to the
    /// skinned target over the whole drawing, by the fit's quadrature.
    pub fn energy(&self, pose: &[Affine], points: &[Point]) -> Result<f64, PoseError> {
        self.check(pose, points.len())?;
        let mut s = Vec::new();
        Ok(self
            .nodes
            .iter()
            .map(|n| n.energy_about(pose, self.frame(n), points, &mut s))
            .sum())
    }

    /// Deforms with flexible junctions: writes the control points for the handle maps `pose`
    /// into `out` (length [`SplineRig::n_points`], layout of [`Drawing::flat_points`]).
    ///
    /// Paths without flexible junctions get the rig's result. The others start from the rig's
    /// result or, if `warm` (a previous solution, same layout) is given, from a ratio step with
    /// its tangent lengths, whichever has the lower energy for `pose`, and iterate (module
    /// doc). With [`FlexibleRule::Authors`] `warm` replaces the authors' first direction step.
    ///
    /// Allocates (each step refactors a sparse matrix); not for the allocation-free per-frame
    /// path of [`SplineRig::update`].
    pub fn solve(
        &self,
        pose: &[Affine],
        warm: Option<&[Point]>,
        out: &mut [Point],
    ) -> Result<FlexibleReport, FlexibleError> {
        self.check(pose, out.len())?;
        if let Some(w) = warm {
            if w.len() != out.len() {
                return Err(PoseError::Output {
                    got: w.len(),
                    expected: out.len(),
                }
                .into());
            }
        }
        self.rig.update(pose, out)?;
        let runs = crate::parallel::try_map(&self.paths, self.parallel, |_, fp| {
            self.iterate(fp, pose, out, warm)
        })?;

        // Energies of the rig's result, path by path: the iterating paths computed theirs,
        // the others' are computed here (in parallel: on a drawing of 100 000 curves this pass
        // took a third of a solve).
        let mut iterated = vec![None; self.nodes.len()];
        for (fp, (_, e)) in self.paths.iter().zip(&runs) {
            iterated[fp.path] = Some(*e);
        }
        let energy = |k: usize, n: &PathNodes| {
            Ok::<f64, std::convert::Infallible>(
                iterated[k]
                    .unwrap_or_else(|| n.energy_about(pose, self.frame(n), out, &mut Vec::new())),
            )
        };
        let Ok(mut path_energy) = crate::parallel::try_map(&self.nodes, self.parallel, energy);
        let runs: Vec<PathRun> = runs.into_iter().map(|(run, _)| run).collect();
        let fixed_ratio_energy = path_energy.iter().sum();
        let steps = runs.iter().map(|r| r.energies.len() - 1).max().unwrap_or(0);
        let mut energies = vec![0.0; steps + 1];
        for (fp, r) in self.paths.iter().zip(&runs) {
            path_energy[fp.path] = 0.0;
            for (k, e) in energies.iter_mut().enumerate() {
                *e += r.energies[k.min(r.energies.len() - 1)];
            }
        }
        let rest: f64 = path_energy.iter().sum();
        energies.iter_mut().for_each(|e| *e += rest);
        for (fp, r) in self.paths.iter().zip(&runs) {
            self.nodes[fp.path].write(&r.x, out);
        }
        Ok(FlexibleReport {
            paths: self.paths.len(),
            steps,
            total_steps: runs.iter().map(|r| r.energies.len() - 1).sum(),
            energies,
            fixed_ratio_energy,
            shortened_steps: runs.iter().map(|r| r.shortened).sum(),
            warm_started_paths: runs.iter().filter(|r| r.warm).count(),
            path_steps: self
                .paths
                .iter()
                .zip(&runs)
                .map(|(fp, r)| (fp.path, r.energies.len() - 1))
                .collect(),
        })
    }

    fn check(&self, pose: &[Affine], n_points: usize) -> Result<(), PoseError> {
        if pose.len() != self.rig.n_handles() {
            return Err(PoseError::Transforms {
                got: pose.len(),
                expected: self.rig.n_handles(),
            });
        }
        if n_points != self.rig.n_points() {
            return Err(PoseError::Output {
                got: n_points,
                expected: self.rig.n_points(),
            });
        }
        Ok(())
    }

    /// Iterates one path from the rig's result in `fixed` (or `warm`); returns the run and
    /// the energy of the rig's result.
    fn iterate(
        &self,
        fp: &FlexPath,
        pose: &[Affine],
        fixed: &[Point],
        warm: Option<&[Point]>,
    ) -> Result<(PathRun, f64), FitError> {
        let nodes = &self.nodes[fp.path];
        let mut sc = Scratch::default();
        // Everything below is about the path's centre (PathNodes::centre); the authors' rule
        // stays in drawing coordinates, since its stopping test is relative to them.
        let o = self.frame(nodes);
        let about_centre = |x: &[Point]| x.iter().map(|p| *p - o).collect::<Vec<_>>();
        nodes.target_about(pose, o, &mut sc.target);
        nodes.rhs(&sc.target, &mut sc.b);
        sc.floor = nodes.noise_floor(&sc.target);
        let start = about_centre(nodes.unknowns(fixed));
        let e_start = nodes.energy(&sc.target, &start);
        let warm = warm.map(|w| about_centre(nodes.unknowns(w)));
        let mut run = match self.options.rule {
            FlexibleRule::Newton | FlexibleRule::Alternating => {
                let mut run = PathRun {
                    x: start,
                    energies: vec![e_start],
                    shortened: 0,
                    warm: false,
                };
                if let Some(w) = warm {
                    // Newton: the previous solution itself, if it fits this pose better than
                    // the fixed-ratio fit (a pose that barely moved); alternating: one ratio
                    // step with its tangent ratios.
                    let candidate = if self.options.rule == FlexibleRule::Newton {
                        let e_w = nodes.energy(&sc.target, &w);
                        (w, e_w)
                    } else {
                        let x = fp.ratio_step(nodes, &mut sc, &w)?;
                        let e = nodes.energy(&sc.target, &x);
                        (x, e)
                    };
                    if candidate.1 < e_start {
                        run.x = candidate.0;
                        run.energies.push(candidate.1);
                        run.warm = true;
                    }
                }
                if self.options.rule == FlexibleRule::Newton {
                    newton::iterate_newton(&self.options, fp, nodes, &mut sc, run)
                } else {
                    alternation::iterate_alternating(&self.options, fp, nodes, &mut sc, run)
                }
            }
            FlexibleRule::Authors => authors::iterate_authors(fp, nodes, &mut sc, e_start, warm),
        }?;
        for p in &mut run.x {
            *p += o;
        }
        Ok((run, e_start))
    }

    /// The point the iteration of the solver's rule works about, for path `nodes`: the path's
    /// centre ([`PathNodes::centre`]), or the origin for the authors' rule (whose stopping test
    /// is relative to drawing coordinates).
    fn frame(&self, nodes: &PathNodes) -> Vec2 {
        match self.options.rule {
            FlexibleRule::Authors => Vec2::ZERO,
            _ => nodes.centre,
        }
    }
}

/// The fixture of the files' unit tests: one open path of two curves meeting G¹ at point 3
/// (tangent lengths 1 and 2), two Shepard handles at its ends, and the state the iteration of
/// one path starts from (as [`FlexibleSolver::iterate`] prepares it).
#[cfg(test)]
pub(super) mod fixture {
    use kurbo::{Affine, Point};

    use super::layout::Scratch;
    use super::{FlexibleOptions, FlexibleRule, FlexibleSolver};
    use crate::drawing::{Drawing, JointKind, JunctionOptions, Path};
    use crate::spline_fit::quadrature::SampledCurves;
    use crate::spline_fit::FitOptions;
    use crate::weights::{Shepard, ShepardOptions};

    /// The input's control points (one open path, curves 0–3 and 3–6).
    pub(super) const INPUT: [(f64, f64); 7] = crate::test_support::SMOOTH_RATIO_2;

    /// One path's iteration state for a pose.
    pub(super) struct Case {
        pub(super) solver: FlexibleSolver,
        pub(super) sc: Scratch,
        /// The rig's fixed-ratio result, about the frame of the rule.
        pub(super) start: Vec<Point>,
        /// Its energy.
        pub(super) e_start: f64,
        /// The input's points, about the frame of the rule.
        pub(super) input: Vec<Point>,
    }

    /// The handle maps: identity at the start handle, a turn by `angle` about the end handle.
    pub(super) fn pose(angle: f64) -> [Affine; 2] {
        [
            Affine::IDENTITY,
            Affine::rotate_about(angle, Point::new(7., 0.)),
        ]
    }

    /// The case for `pose` under `rule` with stopping tolerance `tolerance`.
    pub(super) fn case(rule: FlexibleRule, tolerance: f64, pose: &[Affine]) -> Case {
        let pts = INPUT.map(Point::from).to_vec();
        let path = Path::new(pts, false, &JunctionOptions::default()).unwrap();
        assert_eq!(path.joints[1], JointKind::G1);
        let drawing = Drawing {
            paths: vec![path],
            ..Default::default()
        };
        let handles = [Point::new(0., 0.), Point::new(7., 0.)];
        let weights = Shepard::new(&handles, ShepardOptions::default());
        let fit = FitOptions::default();
        let samples = SampledCurves::sample(&drawing, &weights, &fit);
        let options = FlexibleOptions::default()
            .with_rule(rule)
            .with_tolerance(tolerance);
        let solver = FlexibleSolver::new(&drawing, &samples, &fit, options).unwrap();
        let mut out = vec![Point::ZERO; solver.rig().n_points()];
        solver.rig().update(pose, &mut out).unwrap();
        let nodes = &solver.nodes[0];
        let o = solver.frame(nodes);
        let mut sc = Scratch::default();
        nodes.target_about(pose, o, &mut sc.target);
        nodes.rhs(&sc.target, &mut sc.b);
        sc.floor = nodes.noise_floor(&sc.target);
        let start: Vec<Point> = nodes.unknowns(&out).iter().map(|p| *p - o).collect();
        let e_start = nodes.energy(&sc.target, &start);
        let input = INPUT.map(|p| Point::from(p) - o).to_vec();
        Case {
            solver,
            sc,
            start,
            e_start,
            input,
        }
    }

    /// The sine of the angle between the junction's tangents `x[3] − x[2]` and `x[4] − x[3]`
    /// (zero: G¹), or infinity if they point apart (a cusp).
    pub(super) fn g1_sine(x: &[Point]) -> f64 {
        let (u, v) = (x[3] - x[2], x[4] - x[3]);
        if u.dot(v) <= 0.0 {
            return f64::INFINITY;
        }
        u.cross(v).abs() / (u.hypot() * v.hypot())
    }

    /// The tangent-length ratio `‖x[4] − x[3]‖ / ‖x[3] − x[2]‖` (the input's: 2).
    pub(super) fn ratio(x: &[Point]) -> f64 {
        (x[4] - x[3]).hypot() / (x[3] - x[2]).hypot()
    }
}
