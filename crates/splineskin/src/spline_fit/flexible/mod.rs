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
//! (the squared L² distance to the skinned target, by the fit's quadrature).
//!
//! **Newton** ([`FlexibleRule::Newton`], the default). At a flexible junction with point `P_p`
//! the two neighbours are `P_a = P_p + α R(φ) û`, `P_b = P_p + β R(φ) v̂`: the tangent scalars
//! `α, β > 0` and a common turn `φ` of both tangents (G¹: `û = −v̂`; fixed angle:
//! `û = −R(−θ) v̂`); every other point is free. `E` is quadratic in the points and scalars and
//! smooth in `φ`. A step linearises the turn about the current directions,
//! `P_a ≈ P_p + α û + α₀ δφ û⊥`, and solves one linear KKT system for all points, scalars and
//! turns, with the neighbours' second derivatives `∂²P_a/∂φ² = −α û` and `∂²P_a/∂α∂φ = û⊥`
//! weighted by the energy gradient at the neighbour (the exact Hessian of `E`). Where that
//! step is not a descent direction (its predicted decrease `−gᵀΔx ≤ 0`: the Hessian is
//! indefinite there) they are dropped (Gauss–Newton, always a descent). The scalars are kept positive by an active set: a scalar the step would take below
//! [`MIN_HELD_FRACTION`] of the input's tangent length on that side (or below its current value,
//! if it is already smaller) is held there, its unknown fixed in the KKT system, and the step
//! solved again until no other scalar goes below its bound; a tangent that wants to vanish then
//! reaches its bound in one step and the other unknowns converge as Newton does (shortening the
//! whole step instead made such a path creep, halving the scalar for 17 steps). The step is
//! shortened so that no junction turns by more than [`MAX_TURN`], then halved until `E`
//! decreases; the turn is applied as a rotation, so the new points satisfy every junction
//! exactly. The iteration stops when a step
//! lowers `E` by less than [`FlexibleOptions::tolerance`] relative, or when a whole Newton step
//! lowered it by what its quadratic model predicted, to that tolerance (the model is then
//! accurate, so the step landed at its minimiser). Both tests (and alternation's) add the
//! energy of a [`NOISE_DISTANCE`] deviation along the whole path to the tolerance: below it
//! the energy is rounding (a target the curves can follow exactly has such an energy). From the fixed-ratio fit of the pose it takes
//! one or two solves per path (192 for the 140 flexible paths of the authors' turtles, where
//! the alternation below takes about 1 100).
//!
//! **Alternation** ([`FlexibleRule::Alternating`], the method of the paper). Two linear
//! problems alternate, each the minimiser of `E` over a set that contains the current
//! solution `x⁽ᵏ⁾`:
//!
//! * **ratio step** — the rig's rows `l_u · v' − l_v · R(θ) · u' = 0` ([`super::constraints`])
//!   with the lengths `l_u = ‖P_p − P_a‖`, `l_v = ‖P_b − P_p‖` of `x⁽ᵏ⁾` (`a`, `p`, `b`: the
//!   tangent neighbour before, the junction point, the neighbour after);
//! * **direction step** — at every flexible junction the two neighbours become a scalar
//!   along a fixed direction: `P_a = P_p + α û`, `P_b = P_p + β v̂`, `v̂` the current outgoing
//!   unit tangent and `û = −R(−θ) v̂` (G¹, `θ = 0`: `û = −v̂`); `α`, `β` are new unknowns and
//!   the neighbours leave the system.
//!
//! `x⁽ᵏ⁾` lies in both sets (its tangents are parallel with positive lengths), so no step
//! increases `E`. The scalars are kept positive: when the direction step's minimiser has some
//! `α < MIN_SCALAR_FRACTION · α⁽ᵏ⁾`, the step goes from `x⁽ᵏ⁾` towards the minimiser only as far
//! as the first scalar reaches that floor (`E` is convex along the segment and decreasing
//! towards the minimiser, so the step still does not increase it). A step whose energy comes
//! out larger (rounding) is discarded and the iteration stops. Iterations stop when a round
//! (one step of each kind) lowers `E` by less than [`FlexibleOptions::tolerance`] relative, or
//! after [`FlexibleOptions::max_steps`] steps.
//!
//! **Linear solves.** Each step's KKT matrix has a fixed pattern per path and step kind (every
//! row entry is kept, zero or not): its symbolic factorisations are computed once, in
//! [`FlexibleSolver::new`]; each step refactors numerically, by `LDLᵀ` in chain order with every
//! constraint row after its unknowns, or by a pivoting LU where that fails (`Kkt`). Paths are
//! independent; only those with a flexible junction iterate, in parallel with
//! [`super::FitOptions::parallel`]. Other paths keep the rig's result.
//!
//! **Warm start.** The result depends on the pose, not linearly: [`FlexibleSolver::solve`]
//! starts, per path, from the rig's fixed-ratio result for the pose or, given a previous
//! solution (`warm`, for dragging), from a start made from it where that has the lower energy,
//! so the result is never worse than the rig's. Newton's is the previous solution itself: it
//! wins when the pose barely moved; otherwise the fixed-ratio fit of the new pose is much closer
//! to the new optimum (on the turtles, a Newton step from the previous solution lands further
//! away than the fixed-ratio fit is). Alternation's is a ratio step with the previous solution's
//! tangent ratios.
//!
//! **The authors' rule** ([`FlexibleRule::Authors`], compatibility mode): their solver starts
//! with a direction step along the *input's* tangent directions, then alternates ratio and
//! direction steps (each side's direction its own current one), for at most 10 rounds, and
//! stops when a solution agrees with the previous one of either kind within 1 px absolute or
//! 1e-3 relative per coordinate (numpy's `allclose(atol = 1, rtol = 1e-3)`). No energy check
//! is made. (Their published code can also reset a curve end whose tangent turned by 90° or
//! more to 0.1 units along the previous direction, `clamp_solution`; the reference outputs in
//! `authors-solver-outputs` were made without it: with it the clam scene moves by 1.3e-3 of the
//! diagonal, without it it agrees to 2e-14. So it is not reproduced.)

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::ldlt::factor::LdltRegularization;
use faer::linalg::solvers::Solve;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::SymbolicCholesky;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymmetricOrdering,
};
use faer::sparse::linalg::solvers::{Lu, SymbolicLu};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{Argsort, Pair, SparseColMat, SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par, Side};
use kurbo::{Affine, Point, Vec2};

use super::constraints::{push_pins, tangent_junctions, ConstraintRows, TangentJunction};
use super::quadrature::SampledCurves;
use super::rig::{PoseError, SplineRig};
use super::{ConstraintForm, FitError, FitOptions};
use crate::bezier;
use crate::drawing::{Drawing, JointKind};

/// Default stopping tolerance: a round (a direction and a ratio step) lowering the path's
/// energy by less than this fraction ends the iteration: 1e-4. On the authors' scenes and the
/// bundled drawing, the points then move by less than 1e-4 of the bounding-box diagonal from
/// where a 1e-9 tolerance takes them (tests/flexible_g1.rs), far below what can be seen.
pub const DEFAULT_TOLERANCE: f64 = 1e-5;

/// Default cap on the linear solves (steps) per path: 40 (20 rounds).
pub const DEFAULT_MAX_STEPS: usize = 40;

/// Smallest fraction of its current value a direction step may shrink a tangent scalar `α` to:
/// 0.5. Keeps the scalars positive (a negative one would reverse the tangent, a cusp).
pub const MIN_SCALAR_FRACTION: f64 = 0.5;

/// The least fraction of the input's tangent length a Newton step lets a tangent scalar reach:
/// 1e-3; a step that would take it lower holds it there (module doc).
pub const MIN_HELD_FRACTION: f64 = 1e-3;

/// Largest turn of a junction's tangents in one Gauss–Newton step: π/4 (the linearisation
/// of the turn is poor beyond).
pub const MAX_TURN: f64 = std::f64::consts::FRAC_PI_4;

/// Distances below this fraction of a path's largest target coordinate are taken for
/// rounding: 1e-10 (module doc, stopping).
pub const NOISE_DISTANCE: f64 = 1e-10;

/// Halvings of a Gauss–Newton step tried before the iteration stops: 30.
const MAX_HALVINGS: usize = 30;

/// The authors' cap on rounds (a direction and a ratio step each): 10.
pub const AUTHORS_MAX_ROUNDS: usize = 10;

/// The authors' stopping test: absolute tolerance per coordinate, 1 drawing unit (px).
pub const AUTHORS_ATOL: f64 = 1.0;

/// The authors' stopping test: relative tolerance per coordinate, 1e-3.
pub const AUTHORS_RTOL: f64 = 1e-3;

/// How the iteration is run and stopped.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum FlexibleRule {
    /// Ours, the default: Gauss–Newton steps on the junctions' directions and tangent
    /// lengths together, monotone, stopping on the relative energy decrease of a step (module
    /// doc, "Gauss–Newton").
    #[default]
    Newton,
    /// Ours by alternation: monotone direction and ratio steps, stopping on the relative energy
    /// decrease of a round (module doc). Converges to the same fits as [`FlexibleRule::Newton`],
    /// in more (and cheaper-to-set-up) linear solves.
    Alternating,
    /// The paper authors' schedule, resets and stopping test (module doc), for compatibility
    /// mode.
    Authors,
}

/// Options of the flexible solve.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct FlexibleOptions {
    /// The schedule. Default: [`FlexibleRule::Newton`].
    pub rule: FlexibleRule,
    /// Relative energy decrease per step ([`FlexibleRule::Newton`]) or round
    /// ([`FlexibleRule::Alternating`]) under which the iteration stops (not used by the authors'
    /// rule). Default: [`DEFAULT_TOLERANCE`].
    pub tolerance: f64,
    /// Largest number of steps per path (not the authors' rule, which does at
    /// most `1 + 2 ·` [`AUTHORS_MAX_ROUNDS`]). Default: [`DEFAULT_MAX_STEPS`].
    pub max_steps: usize,
}

impl Default for FlexibleOptions {
    fn default() -> Self {
        FlexibleOptions {
            rule: FlexibleRule::Newton,
            tolerance: DEFAULT_TOLERANCE,
            max_steps: DEFAULT_MAX_STEPS,
        }
    }
}

impl FlexibleOptions {
    /// The authors' rule (compatibility mode `vectorskinning`).
    pub fn vectorskinning() -> Self {
        FlexibleOptions {
            rule: FlexibleRule::Authors,
            ..Default::default()
        }
    }
    /// Sets [`FlexibleOptions::rule`].
    pub fn with_rule(mut self, rule: FlexibleRule) -> Self {
        self.rule = rule;
        self
    }
    /// Sets [`FlexibleOptions::tolerance`].
    pub fn with_tolerance(mut self, tolerance: f64) -> Self {
        self.tolerance = tolerance;
        self
    }
    /// Sets [`FlexibleOptions::max_steps`].
    pub fn with_max_steps(mut self, max_steps: usize) -> Self {
        self.max_steps = max_steps;
        self
    }
}

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
    /// Direction steps shortened to keep a tangent scalar positive.
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

/// The quadrature data of one path, for its target, right-hand side and energy.
#[derive(Clone, Debug)]
struct PathNodes {
    /// First chain point of the path in the drawing's flat layout.
    offset: usize,
    /// Chain points (`3n + 1`).
    n_chain: usize,
    /// Unknown points (`3n` closed, `3n + 1` open).
    m: usize,
    /// The unknown indices of each curve's control points.
    curves: Vec<[usize; 4]>,
    /// Gram matrix of each curve under the fit's rule.
    grams: Vec<[[f64; 4]; 4]>,
    /// Node range of curve `j`: `node_start[j] .. node_start[j + 1]`.
    node_start: Vec<usize>,
    /// Bernstein basis at each node.
    bern: Vec<[f64; 4]>,
    /// Node weight `ω_q` (measure included).
    omega: Vec<f64>,
    /// The input curve's point `B(t_q)`, about `centre`.
    rest: Vec<Point>,
    /// The centre of the bounding box of the path's chain points: the iteration works in
    /// coordinates about it, so that its arithmetic sees numbers of the path's own size
    /// wherever the path lies.
    centre: Vec2,
    /// Handle weights at the nodes, `n_handles` per node.
    weights: Vec<f64>,
}

impl PathNodes {
    /// The point the iteration of `rule` works about: the path's centre, or the origin for
    /// the authors' rule (whose stopping test is relative to drawing coordinates).
    fn frame(&self, rule: FlexibleRule) -> Vec2 {
        match rule {
            FlexibleRule::Authors => Vec2::ZERO,
            _ => self.centre,
        }
    }

    /// The energy of the path's points in the flat buffer `flat`, computed about `o` (as the
    /// iteration computes it, so that both agree to the last bit).
    fn energy_about(&self, pose: &[Affine], o: Vec2, flat: &[Point], s: &mut Vec<Point>) -> f64 {
        self.target_about(pose, o, s);
        let x: Vec<Point> = self.unknowns(flat).iter().map(|p| *p - o).collect();
        self.energy(s, &x)
    }

    /// The skinned target `s_q = Σ_i w_i(q) T_i B(t_q)` about a point `o`, `s_q − o`: with `r_q = B(t_q) − o` and
    /// `L_i = τ(−o) T_i τ(o)` (`τ` a translation), `s_q − o = Σ_i w_i L_i r_q + (Σ_i w_i − 1) o`.
    fn target_about(&self, pose: &[Affine], o: Vec2, s: &mut Vec<Point>) {
        let h = pose.len();
        let shift = self.centre - o;
        let local: Vec<Affine> = pose
            .iter()
            .map(|t| Affine::translate(-o) * *t * Affine::translate(o))
            .collect();
        s.clear();
        s.extend(self.rest.iter().enumerate().map(|(q, &r)| {
            let w = &self.weights[q * h..(q + 1) * h];
            let mut acc = Vec2::ZERO;
            let mut sum = 0.0;
            for (wi, t) in w.iter().zip(&local) {
                if *wi != 0.0 {
                    acc += *wi * (*t * (r + shift)).to_vec2();
                    sum += *wi;
                }
            }
            (acc + (sum - 1.0) * o).to_point()
        }));
    }

    /// The right-hand side `b = Σ_q ω_q b(t_q) s_qᵀ` (`2m` values, coordinate `d` of point `k`
    /// at `2k + d`), equal to the rig's `Σ_i T_i Ŵ_ij` by linearity.
    fn rhs(&self, s: &[Point], b: &mut Vec<f64>) {
        b.clear();
        b.resize(2 * self.m, 0.0);
        for (j, idx) in self.curves.iter().enumerate() {
            for q in self.node_start[j]..self.node_start[j + 1] {
                let (w, bq, sq) = (self.omega[q], self.bern[q], s[q]);
                for (k, &i) in idx.iter().enumerate() {
                    b[2 * i] += w * bq[k] * sq.x;
                    b[2 * i + 1] += w * bq[k] * sq.y;
                }
            }
        }
    }

    /// `E(x) = Σ_q ω_q ‖Σ_k b_k(t_q) x_k − s_q‖²` for the unknown points `x`.
    fn energy(&self, s: &[Point], x: &[Point]) -> f64 {
        let mut e = 0.0;
        for (j, idx) in self.curves.iter().enumerate() {
            let c = idx.map(|i| x[i].to_vec2());
            for q in self.node_start[j]..self.node_start[j + 1] {
                let bq = self.bern[q];
                let p = bq[0] * c[0] + bq[1] * c[1] + bq[2] * c[2] + bq[3] * c[3];
                e += self.omega[q] * (p - s[q].to_vec2()).hypot2();
            }
        }
        e
    }

    /// The energy of a distance of [`NOISE_DISTANCE`] times the target's largest coordinate (about
    /// the path's centre)
    /// all along the path: decreases below it are rounding (a target the curves can follow
    /// exactly, e.g. one affine map for the whole path, has an energy of that order), so the
    /// iteration stops there.
    fn noise_floor(&self, s: &[Point]) -> f64 {
        let size = s
            .iter()
            .fold(0.0f64, |m, p| m.max(p.x.abs()).max(p.y.abs()));
        let measure: f64 = self.omega.iter().sum();
        (NOISE_DISTANCE * size).powi(2) * measure
    }

    /// `H x − b` per unknown point (`H` the Gram matrices, `b` the right-hand side of
    /// [`PathNodes::rhs`]): half the gradient of `E` at `x`.
    fn half_gradient(&self, x: &[Point], b: &[f64]) -> Vec<Vec2> {
        let mut g: Vec<Vec2> = (0..self.m)
            .map(|k| -Vec2::new(b[2 * k], b[2 * k + 1]))
            .collect();
        for (idx, gram) in self.curves.iter().zip(&self.grams) {
            for (k, &pk) in idx.iter().enumerate() {
                for (l, &pl) in idx.iter().enumerate() {
                    g[pk] += gram[k][l] * x[pl].to_vec2();
                }
            }
        }
        g
    }

    /// The path's unknown points read from a flat chain buffer.
    fn unknowns<'a>(&self, flat: &'a [Point]) -> &'a [Point] {
        &flat[self.offset..self.offset + self.m]
    }

    /// Writes the unknown points `x` into a flat chain buffer (a closed path repeats its
    /// first point at the end).
    fn write(&self, x: &[Point], flat: &mut [Point]) {
        let out = &mut flat[self.offset..self.offset + self.n_chain];
        out[..self.m].copy_from_slice(x);
        if self.n_chain > self.m {
            out[self.m] = x[0];
        }
    }
}

/// The place of an unknown point in the direction step's unknowns `z`.
#[derive(Clone, Copy, Debug)]
enum Slot {
    /// A point of its own: `z[2f], z[2f + 1]`.
    Free(usize),
    /// A flexible junction's neighbour `P_p + σ · dir_σ`: free point `f` (the junction point)
    /// and scalar `σ` (`z[2 n_free + σ]`).
    Along { base: usize, scalar: usize },
}

/// A KKT matrix `[H, Cᵀ; C, 0]` of fixed pattern (every entry is kept, zero or not): the
/// symbolic structure, the order of its values, and its symbolic factorisations, computed once.
///
/// Each solve factors `LDLᵀ` without pivoting in an elimination order that puts every
/// constraint row after all the unknowns it involves (the chain order of the points): with `H`
/// positive definite, a row's pivot is then `−c H₁⁻¹ cᵀ < 0` for the part `H₁` already
/// eliminated, so no pivot vanishes unless the rows are dependent. The sparse `LDLᵀ` reuses its
/// elimination tree and is several times cheaper than a pivoting LU. A solve whose `LDLᵀ` fails
/// or leaves a residual above [`KKT_RESIDUAL`] (dependent rows, or growth) is redone with a
/// sparse LU with partial pivoting, whose symbolic analysis is also done once.
#[derive(Clone, Debug)]
struct Kkt {
    n: usize,
    symbolic: SymbolicSparseColMat<usize>,
    argsort: Argsort<usize>,
    ldlt: std::sync::Arc<SymbolicCholesky<usize>>,
    lu: SymbolicLu<usize>,
    /// Workspace needed by the `LDLᵀ` factorisation and solve.
    stack_req: StackReq,
}

/// Largest residual `‖K z − r‖∞` of a KKT solve by `LDLᵀ`, relative to `‖K‖∞ ‖z‖∞ + ‖r‖∞`,
/// accepted before the solve is redone by LU: 1e-11.
const KKT_RESIDUAL: f64 = 1e-11;

/// Reusable buffers of [`Kkt::solve`].
#[derive(Default)]
struct KktScratch {
    values: Vec<f64>,
    l_values: Vec<f64>,
    rhs: Vec<f64>,
    mem: Option<MemBuffer>,
}

impl Kkt {
    /// The pattern of `entries` (both triangles), eliminated in the order of `keys` (one per
    /// row/column; ties keep index order).
    fn new(
        n: usize,
        entries: &[(usize, usize, f64)],
        keys: &[f64],
        path: usize,
    ) -> Result<Kkt, FitError> {
        let pairs: Vec<Pair<usize, usize>> = entries
            .iter()
            .map(|&(row, col, _)| Pair { row, col })
            .collect();
        let (symbolic, argsort) = SymbolicSparseColMat::try_new_from_indices(n, n, &pairs)
            .map_err(|e| solver_error(path, "assembling the pattern", e))?;
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&i, &j| keys[i].total_cmp(&keys[j]).then(i.cmp(&j)));
        let mut inverse = vec![0; n];
        for (new, &old) in order.iter().enumerate() {
            inverse[old] = new;
        }
        let perm = PermRef::new_checked(&order, &inverse, n);
        let ldlt = factorize_symbolic_cholesky(
            symbolic.as_ref(),
            Side::Lower,
            SymmetricOrdering::Custom(perm),
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SIMPLICIAL,
                ..Default::default()
            },
        )
        .map_err(|e| solver_error(path, "symbolic LDLT factorisation", e))?;
        let lu = SymbolicLu::try_new(symbolic.as_ref())
            .map_err(|e| solver_error(path, "symbolic LU factorisation", e))?;
        let stack_req = StackReq::any_of(&[
            ldlt.factorize_numeric_ldlt_scratch::<f64>(Par::Seq, Default::default()),
            ldlt.solve_in_place_scratch::<f64>(1, Par::Seq),
        ]);
        Ok(Kkt {
            n,
            symbolic,
            argsort,
            ldlt: std::sync::Arc::new(ldlt),
            lu,
            stack_req,
        })
    }

    /// Factors the matrix with `entries` (the same entries, in the same order, as given to
    /// [`Kkt::new`]) and solves it for `rhs` in place.
    fn solve(
        &self,
        entries: &[(usize, usize, f64)],
        sc: &mut KktScratch,
        rhs: &mut [f64],
        path: usize,
    ) -> Result<(), FitError> {
        sc.values.clear();
        sc.values.extend(entries.iter().map(|e| e.2));
        let mat = SparseColMat::new_from_argsort(self.symbolic.clone(), &self.argsort, &sc.values)
            .map_err(|e| solver_error(path, "filling the matrix", e))?;
        sc.rhs.clear();
        sc.rhs.extend_from_slice(rhs);
        sc.l_values.resize(self.ldlt.len_val(), 0.0);
        let mem = sc.mem.get_or_insert_with(|| MemBuffer::new(self.stack_req));
        if mem.len() < self.stack_req.unaligned_bytes_required() {
            *mem = MemBuffer::new(self.stack_req);
        }
        let stack = MemStack::new(mem);
        let ok = match self.ldlt.factorize_numeric_ldlt(
            &mut sc.l_values,
            mat.as_ref(),
            Side::Lower,
            LdltRegularization::default(),
            Par::Seq,
            stack,
            Default::default(),
        ) {
            Ok(ldlt) => {
                ldlt.solve_in_place_with_conj(
                    Conj::No,
                    MatMut::from_column_major_slice_mut(rhs, self.n, 1),
                    Par::Seq,
                    stack,
                );
                residual_ok(mat.as_ref(), rhs, &sc.rhs)
            }
            Err(_) => false,
        };
        if !ok {
            rhs.copy_from_slice(&sc.rhs);
            let lu = Lu::try_new_with_symbolic(self.lu.clone(), mat.as_ref())
                .map_err(|e| solver_error(path, "LU factorisation", e))?;
            lu.solve_in_place(MatMut::from_column_major_slice_mut(rhs, self.n, 1));
        }
        if rhs.iter().any(|v| !v.is_finite()) {
            return Err(FitError::Singular { path });
        }
        Ok(())
    }
}

/// Whether `z` solves `K z = r` to [`KKT_RESIDUAL`].
fn residual_ok(k: SparseColMatRef<'_, usize, f64>, z: &[f64], r: &[f64]) -> bool {
    let mut res = r.to_vec();
    let mut norm_k: f64 = 0.0;
    for j in 0..k.ncols() {
        let mut col = 0.0;
        for (i, v) in k.row_idx_of_col(j).zip(k.val_of_col(j)) {
            res[i] -= v * z[j];
            col += v.abs();
        }
        norm_k = norm_k.max(col);
    }
    let inf = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let scale = norm_k * inf(z) + inf(r);
    res.iter().all(|v| v.is_finite()) && inf(&res) <= KKT_RESIDUAL * scale
}

fn solver_error(path: usize, what: &str, e: impl std::fmt::Debug) -> FitError {
    FitError::Solver {
        path,
        detail: format!("flexible G1, {what}: {e:?}"),
    }
}

/// The step-independent description of a path with flexible junctions.
#[derive(Clone, Debug)]
struct Layout {
    /// The flexible junctions (G¹ and fixed angle), whose ratio or directions the steps update.
    flexible: Vec<TangentJunction>,
    /// All other rows: tangent rows with the input lengths, and pins.
    fixed_rows: ConstraintRows,
    /// The input's unknown points (the authors' first direction step uses their tangents).
    input: Vec<Point>,
    /// Per unknown point, its place in the direction step.
    slots: Vec<Slot>,
    /// Points that stay unknowns in the direction step.
    n_free: usize,
}

/// One path with flexible junctions: its layout and the two step systems.
#[derive(Clone, Debug)]
struct FlexPath {
    /// Index of the path in the drawing (and in [`FlexibleSolver::nodes`]).
    path: usize,
    layout: Layout,
    ratio: Kkt,
    direction: Kkt,
    /// The Gauss–Newton step's system: the direction step's plus a turn per junction.
    newton: Kkt,
}

/// Scratch of one path's solve.
#[derive(Default)]
struct Scratch {
    target: Vec<Point>,
    b: Vec<f64>,
    entries: Vec<(usize, usize, f64)>,
    kkt: KktScratch,
    rhs: Vec<f64>,
    /// The energy under which the path counts as converged ([`PathNodes::noise_floor`]).
    floor: f64,
    /// Per tangent scalar, the least value a Newton step holds it at:
    /// [`MIN_HELD_FRACTION`] of the input's tangent length on that side.
    least: Vec<f64>,
}

/// The result of one path's iteration.
struct PathRun {
    x: Vec<Point>,
    energies: Vec<f64>,
    shortened: usize,
    warm: bool,
}

/// The fit with flexible G¹ and fixed-angle junctions (module doc): a [`SplineRig`] for the
/// start and the paths without such junctions, plus the two step systems of every path that
/// has them.
///
/// ```text
/// once:        let solver = FlexibleSolver::new(&drawing, &samples, &fit, FlexibleOptions::default())?;
/// each pose:   let report = solver.solve(&pose, None, &mut points)?;
/// dragging:    solver.solve(&pose, Some(&previous), &mut points)?;   // warm start
/// ```
///
/// ```
/// use kurbo::{Affine, Point};
/// use splineskin::drawing::{Drawing, JointKind, JunctionOptions, Path};
/// use splineskin::spline_fit::quadrature::SampledCurves;
/// use splineskin::spline_fit::{FitOptions, FlexibleOptions, FlexibleSolver};
/// use splineskin::weights::{Shepard, ShepardOptions};
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
        let build = |(pi, path): (usize, &crate::drawing::Path)| {
            if grouped[pi] {
                Ok(None)
            } else {
                flex_path(pi, path, &nodes[pi], fit)
            }
        };
        let built: Vec<Option<FlexPath>> = if fit.parallel {
            use rayon::prelude::*;
            let results: Vec<_> = drawing.paths.par_iter().enumerate().map(build).collect();
            results.into_iter().collect::<Result<_, _>>()?
        } else {
            drawing
                .paths
                .iter()
                .enumerate()
                .map(build)
                .collect::<Result<_, _>>()?
        };
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
            .map(|n| n.energy_about(pose, n.frame(self.options.rule), points, &mut s))
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
        let run = |fp: &FlexPath| self.iterate(fp, pose, out, warm);
        let runs: Vec<Result<PathRun, FitError>> = if self.parallel {
            use rayon::prelude::*;
            self.paths.par_iter().map(run).collect()
        } else {
            self.paths.iter().map(run).collect()
        };
        let runs = runs.into_iter().collect::<Result<Vec<_>, _>>()?;

        // Energies: paths that do not iterate are constant.
        let mut s = Vec::new();
        let mut path_energy: Vec<f64> = self
            .nodes
            .iter()
            .map(|n| n.energy_about(pose, n.frame(self.options.rule), out, &mut s))
            .collect();
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

    /// Iterates one path from the rig's result in `fixed` (or `warm`).
    fn iterate(
        &self,
        fp: &FlexPath,
        pose: &[Affine],
        fixed: &[Point],
        warm: Option<&[Point]>,
    ) -> Result<PathRun, FitError> {
        let nodes = &self.nodes[fp.path];
        let mut sc = Scratch::default();
        // Everything below is about the path's centre (PathNodes::centre); the authors' rule
        // stays in drawing coordinates, since its stopping test is relative to them.
        let o = nodes.frame(self.options.rule);
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
                    self.iterate_newton(fp, nodes, &mut sc, run)
                } else {
                    self.iterate_alternating(fp, nodes, &mut sc, run)
                }
            }
            FlexibleRule::Authors => self.iterate_authors(fp, nodes, &mut sc, e_start, warm),
        }?;
        for p in &mut run.x {
            *p += o;
        }
        Ok(run)
    }

    /// [`FlexibleRule::Newton`] from `run.x` (module doc).
    fn iterate_newton(
        &self,
        fp: &FlexPath,
        nodes: &PathNodes,
        sc: &mut Scratch,
        mut run: PathRun,
    ) -> Result<PathRun, FitError> {
        let input = &fp.layout.input;
        sc.least = fp
            .layout
            .flexible
            .iter()
            .flat_map(|j| {
                let (a, b) = tangent_lengths(j, input);
                [MIN_HELD_FRACTION * a, MIN_HELD_FRACTION * b]
            })
            .collect();
        let mut e = run.energies[run.energies.len() - 1];
        while run.energies.len() <= self.options.max_steps && e > sc.floor {
            // No decrease along the step (rounding, or NaN): converged as far as arithmetic goes.
            let Some(u) = fp.newton_update(nodes, sc, &run.x, e)? else {
                break;
            };
            // Converged when the step gained little, or when a whole Newton step did what its
            // quadratic model said (the model is then accurate, and the step lands at its
            // minimiser).
            let tol = self.options.tolerance * e + sc.floor;
            let done = e - u.energy <= tol || u.model_error.is_some_and(|m| m <= tol);
            run.x = u.x;
            run.shortened += usize::from(u.shortened);
            e = u.energy;
            run.energies.push(e);
            if done {
                break;
            }
        }
        Ok(run)
    }

    /// [`FlexibleRule::Alternating`] from `run.x` (module doc).
    fn iterate_alternating(
        &self,
        fp: &FlexPath,
        nodes: &PathNodes,
        sc: &mut Scratch,
        mut run: PathRun,
    ) -> Result<PathRun, FitError> {
        let layout = &fp.layout;
        let mut e = run.energies[0];
        let mut dirs = vec![Vec2::ZERO; layout.n_scalars()];
        'rounds: while e > sc.floor {
            let e_round = e;
            for direction_step in [true, false] {
                if run.energies.len() > self.options.max_steps {
                    break 'rounds;
                }
                let x = &run.x;
                let x_new = if direction_step {
                    layout.joint_directions(x, Sides::Derived, &mut dirs);
                    let (x_star, scalars) = fp.direction_step(nodes, sc, &dirs)?;
                    // Keep every scalar above a fraction of its current value: stop on the
                    // segment towards the minimiser where the first one reaches its floor.
                    let mut t: f64 = 1.0;
                    for (q, j) in layout.flexible.iter().enumerate() {
                        for (side, n) in [(2 * q, j.a), (2 * q + 1, j.b)] {
                            let current = (x[n] - x[j.p]).dot(dirs[side]);
                            let floor = MIN_SCALAR_FRACTION * current;
                            if scalars[side] < floor {
                                t = t.min(if current > 0.0 {
                                    (current - floor) / (current - scalars[side])
                                } else {
                                    0.0
                                });
                            }
                        }
                    }
                    if t < 1.0 {
                        run.shortened += 1;
                        x.iter().zip(&x_star).map(|(a, b)| a.lerp(*b, t)).collect()
                    } else {
                        x_star
                    }
                } else {
                    fp.ratio_step(nodes, sc, x)?
                };
                let e_new = nodes.energy(&sc.target, &x_new);
                // Not lower (rounding, or NaN): converged as far as arithmetic goes.
                if e_new.is_nan() || e_new > e {
                    break 'rounds;
                }
                run.x = x_new;
                e = e_new;
                run.energies.push(e);
            }
            if e_round - e <= self.options.tolerance * e_round + sc.floor {
                break;
            }
        }
        Ok(run)
    }

    /// [`FlexibleRule::Authors`] (module doc): their preparation step (or `warm`), then at
    /// most [`AUTHORS_MAX_ROUNDS`] rounds.
    fn iterate_authors(
        &self,
        fp: &FlexPath,
        nodes: &PathNodes,
        sc: &mut Scratch,
        e_start: f64,
        warm: Option<Vec<Point>>,
    ) -> Result<PathRun, FitError> {
        let layout = &fp.layout;
        let mut dirs = vec![Vec2::ZERO; layout.n_scalars()];
        let mut energies = vec![e_start];
        let mut step = |x_ref: &[Point], direction: bool, energies: &mut Vec<f64>| {
            let x = if direction {
                layout.joint_directions(x_ref, Sides::Own, &mut dirs);
                fp.direction_step(nodes, sc, &dirs)?.0
            } else {
                fp.ratio_step(nodes, sc, x_ref)?
            };
            energies.push(nodes.energy(&sc.target, &x));
            Ok::<_, FitError>(x)
        };
        let warm_used = warm.is_some();
        // Their preparation: a direction step along the input's tangents.
        let first = match warm {
            Some(w) => w,
            None => step(&layout.input, true, &mut energies)?,
        };
        let mut last_odd = step(&first, false, &mut energies)?;
        let mut last_even: Option<Vec<Point>> = None;
        let mut x = last_odd.clone();
        for _ in 0..AUTHORS_MAX_ROUNDS {
            let even = step(&x, true, &mut energies)?;
            let done = allclose(&last_odd, &even)
                || last_even.as_ref().is_some_and(|l| allclose(l, &even));
            x = even;
            if done {
                break;
            }
            last_even = Some(x.clone());
            let odd = step(&x, false, &mut energies)?;
            let done =
                last_even.as_ref().is_some_and(|l| allclose(l, &odd)) || allclose(&last_odd, &odd);
            x = odd;
            if done {
                break;
            }
            last_odd = x.clone();
        }
        Ok(PathRun {
            x,
            energies,
            shortened: 0,
            warm: warm_used,
        })
    }
}

/// numpy's `allclose(a, b, atol, rtol)` with the authors' tolerances, per coordinate:
/// `|a − b| ≤ atol + rtol · |b|`.
fn allclose(a: &[Point], b: &[Point]) -> bool {
    a.iter().zip(b).all(|(p, q)| {
        (p.x - q.x).abs() <= AUTHORS_ATOL + AUTHORS_RTOL * q.x.abs()
            && (p.y - q.y).abs() <= AUTHORS_ATOL + AUTHORS_RTOL * q.y.abs()
    })
}

/// Where the direction step takes each side's direction from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Sides {
    /// `v̂` the current outgoing direction, `û = −R(−θ) v̂` (exactly consistent).
    Derived,
    /// Each side its own current direction (the authors).
    Own,
}

impl Layout {
    /// The unit directions of the direction step for the current points `x`: `dirs[2q]` for
    /// the side before flexible junction `q` (from `P_p` towards `P_a`), `dirs[2q + 1]` after
    /// it. A vanished tangent takes its direction from the other side (turned by `θ`), or from
    /// the input if both vanished.
    fn joint_directions(&self, x: &[Point], sides: Sides, dirs: &mut [Vec2]) {
        for (q, j) in self.flexible.iter().enumerate() {
            let from_input =
                || unit(self.input[j.b] - self.input[j.p]).unwrap_or(Vec2::new(1.0, 0.0));
            // The outgoing direction is R(θ) times the incoming one, P_p − P_a.
            let out_dir = unit(x[j.b] - x[j.p])
                .or_else(|| unit(x[j.p] - x[j.a]).map(|u| rotate(u, j.theta)))
                .unwrap_or_else(from_input);
            let derived_in = -rotate(out_dir, -j.theta);
            let before = match sides {
                Sides::Derived => derived_in,
                Sides::Own => unit(x[j.a] - x[j.p]).unwrap_or(derived_in),
            };
            dirs[2 * q] = before;
            dirs[2 * q + 1] = out_dir;
        }
    }

    /// The unknowns `z` that coordinate `d` of point `k` is made of, with their coefficients
    /// (`x = S z`): one for a free point, two for a neighbour along a direction.
    fn terms(&self, k: usize, d: usize, dirs: &[Vec2]) -> impl Iterator<Item = (usize, f64)> {
        self.terms_turning(k, d, dirs, None)
    }

    /// [`Layout::terms`], and with `sigma` (the current scalars) the linearised turn of the
    /// junction too: `P_a = P_p + α û + σ_a δφ û⊥` (Gauss–Newton step, module doc), `δφ` of
    /// junction `q` at `z[2 n_free + n_scalars + q]`.
    fn terms_turning(
        &self,
        k: usize,
        d: usize,
        dirs: &[Vec2],
        sigma: Option<&[f64]>,
    ) -> impl Iterator<Item = (usize, f64)> {
        let coord = |v: Vec2| if d == 0 { v.x } else { v.y };
        let terms = match self.slots[k] {
            Slot::Free(f) => [Some((2 * f + d, 1.0)), None, None],
            Slot::Along { base, scalar } => {
                let dir = dirs[scalar];
                [
                    Some((2 * base + d, 1.0)),
                    Some((2 * self.n_free + scalar, coord(dir))),
                    sigma.map(|s| {
                        (
                            2 * self.n_free + self.n_scalars() + scalar / 2,
                            s[scalar] * coord(dir.turn_90()),
                        )
                    }),
                ]
            }
        };
        terms.into_iter().flatten()
    }

    /// Number of direction-step scalars (two per flexible junction).
    fn n_scalars(&self) -> usize {
        2 * self.flexible.len()
    }

    /// The direction step's KKT entries `[SᵀHS, (CS)ᵀ; CS, 0]` in a fixed order (`S` the
    /// substitution `x = S z`, `C` the fixed rows).
    ///
    /// With `turning` (the current scalars `σ` and the energy gradients `g` at the neighbours,
    /// per side), the Newton step's entries: `S` then also maps each junction's turn `δφ` (see
    /// [`Layout::terms_turning`]), and the second derivatives of the neighbours,
    /// `∂²P/∂φ² = −σ d` and `∂²P/∂σ∂φ = d⊥`, add `−σ g·d` at `(δφ, δφ)` and `g·d⊥` at
    /// `(σ, δφ)` (zero `g`: Gauss–Newton).
    fn direction_entries(
        &self,
        nodes: &PathNodes,
        dirs: &[Vec2],
        turning: Option<(&[f64], &[Vec2])>,
        out: &mut Vec<(usize, usize, f64)>,
    ) {
        let sigma = turning.map(|t| t.0);
        out.clear();
        for (idx, g) in nodes.curves.iter().zip(&nodes.grams) {
            for (k, &pk) in idx.iter().enumerate() {
                for (l, &pl) in idx.iter().enumerate() {
                    for d in 0..2 {
                        for (zi, ci) in self.terms_turning(pk, d, dirs, sigma) {
                            for (zj, cj) in self.terms_turning(pl, d, dirs, sigma) {
                                out.push((zi, zj, g[k][l] * ci * cj));
                            }
                        }
                    }
                }
            }
        }
        let mut turns = 0;
        if let Some((sigma, grad)) = turning {
            turns = self.flexible.len();
            let first_turn = 2 * self.n_free + self.n_scalars();
            for side in 0..self.n_scalars() {
                let (d, g) = (dirs[side], grad[side]);
                let (zs, zt) = (2 * self.n_free + side, first_turn + side / 2);
                out.push((zs, zt, g.dot(d.turn_90())));
                out.push((zt, zs, g.dot(d.turn_90())));
                out.push((zt, zt, -sigma[side] * g.dot(d)));
            }
        }
        let base = 2 * self.n_free + self.n_scalars() + turns;
        // By construction (`flex_path`) the fixed rows involve free points only.
        let push = |row: usize, col: usize, v: f64, out: &mut Vec<(usize, usize, f64)>| {
            for (zi, c) in self.terms(col / 2, col % 2, dirs) {
                out.push((row, zi, v * c));
                out.push((zi, row, v * c));
            }
        };
        for &(r, col, v) in &self.fixed_rows.entries {
            push(base + r, col, v, out);
        }
    }
}

impl FlexPath {
    /// The ratio step: the rows of the flexible junctions with the tangent lengths of `x`.
    fn ratio_step(
        &self,
        nodes: &PathNodes,
        sc: &mut Scratch,
        x: &[Point],
    ) -> Result<Vec<Point>, FitError> {
        let layout = &self.layout;
        ratio_entries(
            nodes,
            &layout.fixed_rows,
            &layout.flexible,
            |j| tangent_lengths(j, x),
            &mut sc.entries,
        );
        sc.rhs.clear();
        sc.rhs.extend_from_slice(&sc.b);
        sc.rhs.resize(self.ratio.n, 0.0);
        self.ratio
            .solve(&sc.entries, &mut sc.kkt, &mut sc.rhs, self.path)?;
        Ok((0..nodes.m)
            .map(|k| Point::new(sc.rhs[2 * k], sc.rhs[2 * k + 1]))
            .collect())
    }

    /// The direction step along `dirs` ([`Layout::joint_directions`]): the points and the
    /// scalars (side `σ` at index `σ`).
    fn direction_step(
        &self,
        nodes: &PathNodes,
        sc: &mut Scratch,
        dirs: &[Vec2],
    ) -> Result<(Vec<Point>, Vec<f64>), FitError> {
        let layout = &self.layout;
        layout.direction_entries(nodes, dirs, None, &mut sc.entries);
        // z right-hand side: Sᵀ b.
        sc.rhs.clear();
        sc.rhs.resize(self.direction.n, 0.0);
        for k in 0..nodes.m {
            for d in 0..2 {
                for (zi, c) in layout.terms(k, d, dirs) {
                    sc.rhs[zi] += c * sc.b[2 * k + d];
                }
            }
        }
        self.direction
            .solve(&sc.entries, &mut sc.kkt, &mut sc.rhs, self.path)?;
        let z = &sc.rhs;
        let point = |f: usize| Point::new(z[2 * f], z[2 * f + 1]);
        let scalars: Vec<f64> = (0..dirs.len()).map(|s| z[2 * layout.n_free + s]).collect();
        let x = layout
            .slots
            .iter()
            .map(|slot| match *slot {
                Slot::Free(f) => point(f),
                Slot::Along { base, scalar } => point(base) + scalars[scalar] * dirs[scalar],
            })
            .collect();
        Ok((x, scalars))
    }
}

/// The result of [`FlexPath::newton_update`].
struct NewtonUpdate {
    /// The new points.
    x: Vec<Point>,
    /// Their energy.
    energy: f64,
    /// Whether the step was shortened to keep a scalar positive or a turn small.
    shortened: bool,
    /// For a whole Newton step, how far its energy decrease was from the quadratic model's.
    model_error: Option<f64>,
}

/// The minimiser of the linearised Gauss–Newton problem ([`FlexPath::newton_step`]).
struct NewtonStep {
    /// The unknown points that stay free (direction-step numbering).
    free: Vec<Point>,
    /// The scalars, side `σ` at index `σ`.
    scalars: Vec<f64>,
    /// The turn `δφ` of each junction, radians counter-clockwise.
    turns: Vec<f64>,
}

impl FlexPath {
    /// One Newton step from `x` (on the constraint set, energy `e`), or a Gauss–Newton step
    /// where Newton's is not a descent direction; shortened to keep every scalar above its floor
    /// and every turn below [`MAX_TURN`], then halved until the energy is below `e` (module doc).
    /// `None` if no length lowers the energy.
    fn newton_update(
        &self,
        nodes: &PathNodes,
        sc: &mut Scratch,
        x: &[Point],
        e: f64,
    ) -> Result<Option<NewtonUpdate>, FitError> {
        let layout = &self.layout;
        let mut dirs = vec![Vec2::ZERO; layout.n_scalars()];
        layout.joint_directions(x, Sides::Derived, &mut dirs);
        let sigma: Vec<f64> = layout
            .flexible
            .iter()
            .enumerate()
            .flat_map(|(q, j)| {
                [
                    (x[j.a] - x[j.p]).dot(dirs[2 * q]),
                    (x[j.b] - x[j.p]).dot(dirs[2 * q + 1]),
                ]
            })
            .collect();
        // g = H x − b (half the gradient of E) at every unknown point.
        let g = nodes.half_gradient(x, &sc.b);
        let grad: Vec<Vec2> = layout
            .flexible
            .iter()
            .flat_map(|j| [g[j.a], g[j.b]])
            .collect();
        // The least value each scalar may take in this step: its bound, or its current value
        // if it is already below (module doc).
        let floors: Vec<f64> = sigma
            .iter()
            .zip(&sc.least)
            .map(|(s, l)| l.min(*s))
            .collect();
        let mut exact = true;
        let mut held: Vec<(usize, f64)> = Vec::new();
        let (step, predicted) = loop {
            let zero = vec![Vec2::ZERO; grad.len()];
            let gradient = if exact { &grad } else { &zero };
            // Active set: a scalar the step takes below its floor is held at the floor and the
            // step solved again, until none is.
            let step = loop {
                let step = self.newton_step(nodes, sc, &dirs, &sigma, gradient, &held)?;
                let before = held.len();
                for (side, (&s1, &floor)) in step.scalars.iter().zip(&floors).enumerate() {
                    if s1 < floor && !held.iter().any(|h| h.0 == side) {
                        held.push((side, floor));
                    }
                }
                if held.len() == before {
                    break step;
                }
            };
            // The model's decrease of E over the whole step: −gᵀ Δx (module doc).
            let predicted = -layout
                .linear_change(x, &step, &dirs, &sigma)
                .iter()
                .zip(&g)
                .map(|(dx, gk)| dx.dot(*gk))
                .sum::<f64>();
            if predicted > 0.0 || !exact {
                break (step, predicted);
            }
            exact = false;
            held.clear();
        };
        let mut t: f64 = 1.0;
        for side in 0..sigma.len() {
            let turn = step.turns[side / 2].abs();
            if turn * t > MAX_TURN {
                t = MAX_TURN / turn;
            }
        }
        let shortened = t < 1.0 || !held.is_empty();
        for _ in 0..MAX_HALVINGS {
            if t <= 0.0 {
                break;
            }
            let x_t = layout.newton_point(x, &step, &dirs, &sigma, t);
            let e_t = nodes.energy(&sc.target, &x_t);
            if e_t < e {
                let model_error = (exact && t == 1.0).then(|| ((e - e_t) - predicted).abs());
                return Ok(Some(NewtonUpdate {
                    x: x_t,
                    energy: e_t,
                    shortened,
                    model_error,
                }));
            }
            t *= 0.5;
        }
        Ok(None)
    }

    /// The Gauss–Newton step at the current directions `dirs` and scalars `sigma`: the
    /// direction step with each junction's turn `δφ` as one more unknown, linearised
    /// (module doc); each `(side, value)` of `held` fixes that scalar at that value.
    fn newton_step(
        &self,
        nodes: &PathNodes,
        sc: &mut Scratch,
        dirs: &[Vec2],
        sigma: &[f64],
        grad: &[Vec2],
        held: &[(usize, f64)],
    ) -> Result<NewtonStep, FitError> {
        let layout = &self.layout;
        layout.direction_entries(nodes, dirs, Some((sigma, grad)), &mut sc.entries);
        sc.rhs.clear();
        sc.rhs.resize(self.newton.n, 0.0);
        for k in 0..nodes.m {
            for d in 0..2 {
                for (zi, c) in layout.terms_turning(k, d, dirs, Some(sigma)) {
                    sc.rhs[zi] += c * sc.b[2 * k + d];
                }
            }
        }
        // Newton: K w = Jᵀb + M w₀, M the second-derivative part; w₀ has σ₀ and no turn.
        let first_turn = 2 * layout.n_free + layout.n_scalars();
        for side in 0..layout.n_scalars() {
            sc.rhs[first_turn + side / 2] += grad[side].dot(dirs[side].turn_90()) * sigma[side];
        }
        // Held scalars: their row and column replaced by the diagonal alone, the column's
        // terms moved to the right-hand side (the matrix keeps its pattern).
        for &(side, value) in held {
            let zs = 2 * layout.n_free + side;
            let mut diagonal = 0.0;
            for (r, c, v) in &mut sc.entries {
                if *r == zs && *c == zs {
                    diagonal += *v;
                } else if *c == zs {
                    sc.rhs[*r] -= *v * value;
                    *v = 0.0;
                } else if *r == zs {
                    *v = 0.0;
                }
            }
            sc.rhs[zs] = diagonal * value;
        }
        self.newton
            .solve(&sc.entries, &mut sc.kkt, &mut sc.rhs, self.path)?;
        let z = &sc.rhs;
        let (nf, ns) = (layout.n_free, layout.n_scalars());
        Ok(NewtonStep {
            free: (0..nf)
                .map(|f| Point::new(z[2 * f], z[2 * f + 1]))
                .collect(),
            scalars: z[2 * nf..2 * nf + ns].to_vec(),
            turns: z[2 * nf + ns..2 * nf + ns + layout.flexible.len()].to_vec(),
        })
    }
}

impl Layout {
    /// The linearised change `Δx = J Δw` of every unknown point over the step: free points
    /// move to their solution, a neighbour by `Δp + Δσ d + σ δφ d⊥`.
    fn linear_change(
        &self,
        x: &[Point],
        step: &NewtonStep,
        dirs: &[Vec2],
        sigma: &[f64],
    ) -> Vec<Vec2> {
        let mut free = vec![Vec2::ZERO; self.n_free];
        for (k, slot) in self.slots.iter().enumerate() {
            if let Slot::Free(f) = *slot {
                free[f] = step.free[f] - x[k];
            }
        }
        self.slots
            .iter()
            .map(|slot| match *slot {
                Slot::Free(f) => free[f],
                Slot::Along { base, scalar } => {
                    let d = dirs[scalar];
                    free[base]
                        + (step.scalars[scalar] - sigma[scalar]) * d
                        + sigma[scalar] * step.turns[scalar / 2] * d.turn_90()
                }
            })
            .collect()
    }

    /// The point a fraction `t` of the way along the Gauss–Newton step from `x` (directions
    /// `dirs`, scalars `sigma`): free points and scalars interpolated linearly, each junction
    /// turned by `t δφ`. It satisfies every junction exactly (its tangents are parallel, or at
    /// the input's angle).
    fn newton_point(
        &self,
        x: &[Point],
        step: &NewtonStep,
        dirs: &[Vec2],
        sigma: &[f64],
        t: f64,
    ) -> Vec<Point> {
        let mut free = vec![Point::ZERO; self.n_free];
        for (k, slot) in self.slots.iter().enumerate() {
            if let Slot::Free(f) = *slot {
                free[f] = x[k].lerp(step.free[f], t);
            }
        }
        self.slots
            .iter()
            .map(|slot| match *slot {
                Slot::Free(f) => free[f],
                Slot::Along { base, scalar } => {
                    let s = sigma[scalar] + t * (step.scalars[scalar] - sigma[scalar]);
                    free[base] + s * rotate(dirs[scalar], t * step.turns[scalar / 2])
                }
            })
            .collect()
    }
}

/// The tangent lengths `(‖P_p − P_a‖, ‖P_b − P_p‖)` of junction `j` in the points `x`.
fn tangent_lengths(j: &TangentJunction, x: &[Point]) -> (f64, f64) {
    ((x[j.p] - x[j.a]).hypot(), (x[j.b] - x[j.p]).hypot())
}

/// `v / ‖v‖`, or `None` for a zero (or non-finite) vector.
fn unit(v: Vec2) -> Option<Vec2> {
    let l = v.hypot();
    (l > 0.0 && l.is_finite()).then(|| v / l)
}

/// `R(θ) v`, counter-clockwise.
fn rotate(v: Vec2, theta: f64) -> Vec2 {
    let (s, c) = theta.sin_cos();
    Vec2::new(c * v.x - s * v.y, s * v.x + c * v.y)
}

/// The ratio step's KKT entries `[H, Cᵀ; C, 0]` in a fixed order: the curves' Gram blocks,
/// the fixed rows, then two rows per junction of `varying` with `lengths(junction)`.
fn ratio_entries(
    nodes: &PathNodes,
    fixed_rows: &ConstraintRows,
    varying: &[TangentJunction],
    lengths: impl Fn(&TangentJunction) -> (f64, f64),
    out: &mut Vec<(usize, usize, f64)>,
) {
    out.clear();
    for (idx, g) in nodes.curves.iter().zip(&nodes.grams) {
        for (k, &pk) in idx.iter().enumerate() {
            for (l, &pl) in idx.iter().enumerate() {
                for d in 0..2 {
                    out.push((2 * pk + d, 2 * pl + d, g[k][l]));
                }
            }
        }
    }
    let n_x = 2 * nodes.m;
    for &(r, col, v) in &fixed_rows.entries {
        out.push((n_x + r, col, v));
        out.push((col, n_x + r, v));
    }
    let mut row = n_x + fixed_rows.n_rows;
    for j in varying {
        for r in j.rows(lengths(j)) {
            for (col, v) in r {
                out.push((row, col, v));
                out.push((col, row, v));
            }
            row += 1;
        }
    }
}

/// Elimination keys of a KKT matrix of `n` rows whose first `n_unknowns` are unknowns (key
/// `unknown_key(i)`) and the rest constraint rows: a row's key is half a place after the
/// largest key of the unknowns in it (`entries`), so it is eliminated after all of them.
fn elimination_keys(
    n: usize,
    n_unknowns: usize,
    unknown_key: impl Fn(usize) -> f64,
    entries: &[(usize, usize, f64)],
) -> Vec<f64> {
    let mut keys: Vec<f64> = (0..n)
        .map(|i| {
            if i < n_unknowns {
                unknown_key(i)
            } else {
                f64::MIN
            }
        })
        .collect();
    for &(row, col, _) in entries {
        if row >= n_unknowns && col < n_unknowns {
            keys[row] = keys[row].max(keys[col] + 0.5);
        }
    }
    keys
}

/// The quadrature data of `path` (whose first curve is curve `first_curve` of `samples` and
/// first chain point `offset` in the flat layout).
fn path_nodes(
    path: &crate::drawing::Path,
    samples: &SampledCurves,
    first_curve: usize,
    offset: usize,
) -> PathNodes {
    let m = path.n_unknown_points();
    let unknown = |i: usize| if i >= m { i - m } else { i };
    let h = samples.n_handles();
    let mut n = PathNodes {
        offset,
        n_chain: path.points.len(),
        m,
        curves: Vec::with_capacity(path.n_curves()),
        grams: Vec::with_capacity(path.n_curves()),
        node_start: vec![0],
        bern: Vec::new(),
        omega: Vec::new(),
        rest: Vec::new(),
        centre: super::system::centre(path.points.iter().copied()),
        weights: Vec::new(),
    };
    for j in 0..path.n_curves() {
        let c = path.curve_points(j);
        let curve = samples.curve(first_curve + j);
        n.curves.push([0, 1, 2, 3].map(|k| unknown(3 * j + k)));
        n.grams.push(curve.gram());
        for (&t, &w) in curve.t.iter().zip(curve.omega) {
            n.bern.push(bezier::bernstein(t));
            n.omega.push(w);
            n.rest.push(bezier::eval(&c, t) - n.centre);
        }
        n.weights
            .extend_from_slice(&curve.weights[..curve.t.len() * h]);
        n.node_start.push(n.bern.len());
    }
    n
}

/// The flexible systems of path `pi`, or `None` if it has no flexible junction.
///
/// A G¹ or fixed-angle junction is flexible unless its tangents vanish or one of its
/// neighbours `a`, `b` is an on-curve point or appears in another junction's rows (then it
/// could not be replaced by a scalar; it keeps the input's ratio, as in the rig).
fn flex_path(
    pi: usize,
    path: &crate::drawing::Path,
    nodes: &PathNodes,
    fit: &FitOptions,
) -> Result<Option<FlexPath>, FitError> {
    let all = tangent_junctions(
        &path.points,
        path.closed,
        &path.joints,
        fit.constraint_form,
        &fit.junctions,
    );
    let m = nodes.m;
    let mut uses = vec![0usize; m];
    for j in &all {
        for &i in [j.a, j.p, j.b].iter().chain(&j.pins) {
            uses[i] += 1;
        }
    }
    let is_flexible = |j: &TangentJunction| {
        matches!(j.kind, JointKind::G1 | JointKind::FixedAngle)
            && !j.vanishes()
            && [j.a, j.b].iter().all(|&n| n % 3 != 0 && uses[n] == 1)
    };
    if !all.iter().any(is_flexible) {
        return Ok(None);
    }
    let mut flexible = Vec::new();
    let mut fixed_rows = ConstraintRows::default();
    for j in &all {
        if is_flexible(j) {
            flexible.push(j.clone());
        } else if !j.vanishes() {
            for row in j.rows(j.lengths) {
                fixed_rows.push_row(&row);
            }
        }
    }
    for j in all.iter().filter(|j| !j.vanishes()) {
        push_pins(&mut fixed_rows, j);
    }
    if fit.constraint_form == ConstraintForm::Ours {
        // As the rig's rows: those that follow from the others are left out. A flexible
        // junction's neighbours appear in no other row, so its rows never depend on these.
        fixed_rows = fixed_rows.independent().0;
    }
    // Direction step unknowns: every point but the flexible neighbours, then two scalars per
    // flexible junction.
    let mut along = vec![None; m];
    for (q, j) in flexible.iter().enumerate() {
        along[j.a] = Some((j.p, 2 * q));
        along[j.b] = Some((j.p, 2 * q + 1));
    }
    let mut free_index = vec![usize::MAX; m];
    let mut n_free = 0;
    for (k, a) in along.iter().enumerate() {
        if a.is_none() {
            free_index[k] = n_free;
            n_free += 1;
        }
    }
    let slots = along
        .iter()
        .enumerate()
        .map(|(k, a)| match *a {
            None => Slot::Free(free_index[k]),
            Some((p, scalar)) => Slot::Along {
                base: free_index[p],
                scalar,
            },
        })
        .collect();
    let layout = Layout {
        flexible,
        fixed_rows,
        input: path.points[..m].to_vec(),
        slots,
        n_free,
    };
    // Patterns (every entry is present whatever its value).
    let mut entries = Vec::new();
    ratio_entries(
        nodes,
        &layout.fixed_rows,
        &layout.flexible,
        |j| j.lengths,
        &mut entries,
    );
    let n_rows = layout.fixed_rows.n_rows + 2 * layout.flexible.len();
    let n = 2 * m + n_rows;
    let keys = elimination_keys(n, 2 * m, |i| (i / 2) as f64, &entries);
    let ratio = Kkt::new(n, &entries, &keys, pi)?;
    let dirs = vec![Vec2::new(1.0, 1.0); layout.n_scalars()];
    // Direction and Gauss–Newton unknowns in chain order too: a free point at its own place,
    // a scalar at its neighbour's, a turn at its junction point's.
    let mut chain_of_free = vec![0.0; n_free];
    for (k, &f) in free_index.iter().enumerate() {
        if f != usize::MAX {
            chain_of_free[f] = k as f64;
        }
    }
    let z_key = |i: usize| {
        let (nf, ns) = (2 * n_free, layout.n_scalars());
        if i < nf {
            chain_of_free[i / 2]
        } else if i < nf + ns {
            let j = &layout.flexible[(i - nf) / 2];
            (if (i - nf) % 2 == 0 { j.a } else { j.b }) as f64
        } else {
            layout.flexible[i - nf - ns].p as f64
        }
    };
    layout.direction_entries(nodes, &dirs, None, &mut entries);
    let n_z = 2 * n_free + layout.n_scalars();
    let n = n_z + layout.fixed_rows.n_rows;
    let keys = elimination_keys(n, n_z, z_key, &entries);
    let direction = Kkt::new(n, &entries, &keys, pi)?;
    let sigma = vec![1.0; layout.n_scalars()];
    let grad = vec![Vec2::new(1.0, 1.0); layout.n_scalars()];
    layout.direction_entries(nodes, &dirs, Some((&sigma, &grad)), &mut entries);
    let n_z = n_z + layout.flexible.len();
    let n = n_z + layout.fixed_rows.n_rows;
    let keys = elimination_keys(n, n_z, z_key, &entries);
    let newton = Kkt::new(n, &entries, &keys, pi)?;
    Ok(Some(FlexPath {
        path: pi,
        layout,
        ratio,
        direction,
        newton,
    }))
}
