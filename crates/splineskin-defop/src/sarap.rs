//! [`SymmetricArap`]: the symmetric ARAP deformation of a triangle mesh with point handles at
//! vertices (Poranne & Lipman 2016, Eq. (11); DESIGN.md §4), minimised by Newton's method with
//! a projected Hessian and a line search that never flips a triangle.
//!
//! ```text
//! minimise  E(u) = Σ_t A_t ((Σ_t − 1)² + (1/σ_t − 1)²)   subject to u_ℓ = q_ℓ at the handles
//!
//! once:            sparsity of the Hessian on the free vertices (2×2 blocks), its ordering and
//!                  symbolic Cholesky analysis; where each triangle's 6×6 block lands
//! each iteration:  1. H = Σ_t A_t Wᵀ(∇²ψ)₊W, g = ∇E        (projected Hessian, sarap_energy)
//!                  2. d_c = q − u_c at the handles;  H_ff d_f = −g_f − H_fc d_c
//!                  3. α_max: the first α at which some triangle of u + α d collapses;
//!                     α = min(1, 0.9 α_max)
//!                  4. while the handles are off target: take α (they move that fraction of
//!                     the way; α = 1 puts them on target exactly);
//!                     then: halve α until E(u + α d) ≤ E(u) + 10⁻⁴ α gᵀd (Armijo)
//! stop:            handles on target and the Newton step moves no coordinate by more than
//!                  step_tolerance × bounding-box diagonal, or the decrease it promises
//!                  (−gᵀd) is below the energy's rounding (then it is kept if E does not rise)
//! ```
//!
//! With the handles on target the exact Hessian is tried first and used when its Cholesky
//! factorisation succeeds (then the step is Newton's own and converges quadratically); the
//! projected one otherwise. On the reference shapes a solve from a flip-free ARAP solution
//! takes 5–10 iterations.
//!
//! Every iterate is flip-free (the start must be: the energy is infinite on a flip), so the
//! result is. Once the handles are on their targets the energy decreases at every step. The
//! first phase is Newton's method from an infeasible start (Boyd & Vandenberghe 2004, §10.3):
//! starting from the rest pose, it pulls the handles to their targets in as few flip-free
//! steps as the mesh allows. A flip-free solution that already meets the targets (a flip-free
//! ARAP solution, or the previous frame's) is the better start.
//!
//! The projected Hessian is positive semidefinite and, with the handles fixed, positive
//! definite in practice; when the factorisation meets a non-positive pivot (for instance one
//! handle and a rigid rotation about it at the rest pose), a multiple of the identity is added
//! and grown by factors of 100 until it succeeds.

use kurbo::{Point, Vec2};

use super::deformation_gradient::TriangleGradients;
use super::error::DefOpError;
use super::handles::{bounding_box_diagonal, HandleSet, NOT_FREE};
use super::orientation::{double_area, max_orientation_preserving_step};
use super::sarap_energy::{sarap_energy_of, triangle_derivatives};
use splineskin_core::linalg::{CholeskyAnalysis, Ordering};
use splineskin_core::mesh::cotangent::laplacian_csc;
use splineskin_core::mesh::TriMesh;

/// Default [`SarapOptions::max_iterations`]: 1 000 Newton iterations. Solves from the rest
/// pose take the most: up to 20 on the reference shapes and the benchmark's octopus (rigid
/// half turns included); from a flip-free ARAP solution 4–10. The cap only stops a solve that
/// cannot progress.
pub const DEFAULT_SARAP_MAX_ITERATIONS: usize = 1000;

/// Default [`SarapOptions::step_tolerance`]: `1e-12` of the bounding-box diagonal. Near the
/// minimiser a Newton step is the distance to it to first order, so the result is within about
/// that of the minimiser; Newton converges quadratically there, so a tighter tolerance costs
/// about one more iteration.
pub const DEFAULT_SARAP_STEP_TOLERANCE: f64 = 1e-12;

/// Armijo's sufficient-decrease constant: accept a step that achieves at least this fraction of
/// the decrease the gradient predicts (Nocedal & Wright 2006, §3.1, suggest 10⁻⁴).
const ARMIJO: f64 = 1e-4;

/// Fraction of the largest flip-free step taken at most, so no triangle comes near collapse
/// in one step (Smith & Schaefer 2015 use 0.9 too).
const FLIP_MARGIN: f64 = 0.9;

/// Halvings of the step before the line search gives up (`2⁻⁶⁰ ≈ 1e-18`).
const MAX_BACKTRACKS: usize = 60;

/// Relative size of the energy's rounding: when even the decrease the gradient predicts,
/// `−gᵀd`, is below this fraction of the energy, a step cannot be told from rounding and the
/// solve has converged as far as f64 allows (energies are sums of `n_triangles` positive terms,
/// each with a relative rounding of a few ulps).
const ENERGY_ROUNDING: f64 = 1e-14;

/// Steps after which a solve whose energy has not fallen by more than [`ENERGY_ROUNDING`] in
/// total stops at the rounding floor. Measured on the benchmark octopus: 2 of 19 random
/// configurations had Newton steps of 1e-5 (a soft mode) that changed the energy by nothing
/// f64 resolves, for all of the 1 000 iterations allowed.
const STALL_ITERATIONS: usize = 20;

/// Regularisation added to the Hessian's diagonal when its factorisation fails: first this
/// fraction of the largest diagonal entry, then 100 times more at each retry, at most
/// [`MAX_REGULARISATIONS`] times.
const FIRST_REGULARISATION: f64 = 1e-12;
const MAX_REGULARISATIONS: usize = 8;

/// Marks a Hessian entry that is not stored (a handle's coordinate, or the lower triangle).
const NOT_STORED: usize = usize::MAX;

/// Options of [`SymmetricArap`].
///
/// ```
/// use splineskin_defop::SarapOptions;
/// let options = SarapOptions::default().with_step_tolerance(1e-10);
/// assert_eq!(options.step_tolerance, 1e-10);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct SarapOptions {
    /// Newton iterations allowed per solve. Default: [`DEFAULT_SARAP_MAX_ITERATIONS`].
    pub max_iterations: usize,
    /// Stop once the handles are on target and the Newton step moves no coordinate by more
    /// than this fraction of the rest mesh's bounding-box diagonal (dimensionless). Default:
    /// [`DEFAULT_SARAP_STEP_TOLERANCE`].
    pub step_tolerance: f64,
}

impl Default for SarapOptions {
    fn default() -> Self {
        SarapOptions {
            max_iterations: DEFAULT_SARAP_MAX_ITERATIONS,
            step_tolerance: DEFAULT_SARAP_STEP_TOLERANCE,
        }
    }
}

impl SarapOptions {
    /// Sets [`SarapOptions::max_iterations`].
    pub fn with_max_iterations(mut self, n: usize) -> Self {
        self.max_iterations = n;
        self
    }
    /// Sets [`SarapOptions::step_tolerance`].
    pub fn with_step_tolerance(mut self, tolerance: f64) -> Self {
        self.step_tolerance = tolerance;
        self
    }

    fn check(&self) -> Result<(), DefOpError> {
        super::arap::check_iteration_options(self.max_iterations, self.step_tolerance)
    }
}

/// Why a SARAP solve stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum SarapStop {
    /// Handles on target and the Newton step below the step tolerance.
    Converged,
    /// Handles on target and the decrease the Newton step promised is below the energy's
    /// rounding (relative `1e-14`), or twenty steps together lowered the energy by less than
    /// that: as converged as f64 allows. The last step is kept if it did not raise the energy.
    /// Newton steps this close to the minimiser are typically `1e-10` of the diagonal or less;
    /// along a soft mode (a direction of nearly zero curvature) they can stay near `1e-5`.
    RoundingFloor,
    /// The iteration cap was reached.
    IterationCap,
    /// The line search found no decrease although one was predicted above rounding (a bug, or
    /// an extremely ill-conditioned mesh).
    LineSearchFailed,
}

/// How a SARAP solve ended.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct SarapReport {
    /// Newton iterations run (steps computed, whether or not taken).
    pub iterations: usize,
    /// Why the solve stopped.
    pub stop: SarapStop,
    /// `E_SARAP` of every iterate, the initial guess first, so `energies.len()` is one more
    /// than the steps taken.
    pub energies: Vec<f64>,
    /// Index in `energies` of the first iterate with every handle on its target; from there
    /// on the energies do not increase. `None` if the handles never reached their targets.
    pub constrained_from: Option<usize>,
    /// The largest coordinate of the last Newton step computed, in drawing units.
    pub last_step: f64,
}

impl SarapReport {
    /// Whether the solve reached its tolerance (or the rounding floor) with the handles on
    /// target.
    pub fn converged(&self) -> bool {
        matches!(self.stop, SarapStop::Converged | SarapStop::RoundingFloor)
    }

    /// `E_SARAP` at the result.
    pub fn energy(&self) -> f64 {
        self.energies.last().copied().unwrap_or(f64::NAN)
    }
}

/// Symmetric ARAP deformation with point handles at mesh vertices, analysed for one set of
/// handles.
///
/// Build once per mesh and handle set ([`SymmetricArap::new`]: the Hessian's pattern and its
/// symbolic factorisation); then [`SymmetricArap::solve`] for any number of target
/// configurations from any flip-free initial guess. `solve` takes `&self`.
///
/// A vertex in no triangle has no energy: it is not moved.
///
/// ```
/// use kurbo::{Point, Rect};
/// use splineskin_defop::{flipped_triangles, SarapOptions, SymmetricArap};
/// use splineskin_core::mesh::TriMesh;
/// let mesh = TriMesh::grid(Rect::new(0., 0., 4., 1.), 8, 2)?;
/// let sarap = SymmetricArap::new(&mesh, &[9, 17], SarapOptions::default())?;
/// // Push the right end of the bar 1 unit to the left, starting from the rest pose.
/// let mut positions = mesh.vertices.clone();
/// let report = sarap.solve(&[Point::new(0., 0.5), Point::new(3., 0.5)], &mut positions)?;
/// assert!(report.converged());
/// assert_eq!(positions[17], Point::new(3., 0.5));
/// assert!(flipped_triangles(&mesh, &positions)?.is_empty());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct SymmetricArap {
    rest: TriangleGradients,
    handles: HandleSet,
    /// Pattern of the Hessian on the free coordinates: free vertex `r` has coordinates `2r`
    /// (x) and `2r + 1` (y).
    analysis: CholeskyAnalysis,
    /// For triangle `t` and local coordinates `(i, j)` (`i = 2k + axis` of corner `k`), the
    /// position of `H[i][j]` among the stored upper-triangle values, or [`NOT_STORED`].
    scatter: Vec<[usize; 36]>,
    /// Position of each free coordinate's diagonal entry.
    diagonal_entries: Vec<usize>,
    /// The rest mesh's bounding-box diagonal.
    diagonal: f64,
    options: SarapOptions,
}

/// The per-solve buffers of [`SymmetricArap::solve`].
struct Workspace {
    /// The projected Hessian's stored values.
    values: Vec<f64>,
    /// The exact Hessian's stored values.
    exact_values: Vec<f64>,
    factor: Vec<f64>,
    /// `−g_f`, the free coordinates' negative gradient.
    minus_gradient: Vec<f64>,
    rhs: Vec<f64>,
    direction: Vec<Vec2>,
    trial: Vec<Point>,
    memory: faer::dyn_stack::MemBuffer,
}

impl SymmetricArap {
    /// Precomputes the solver for `mesh` with handles at the vertices `handles` (distinct, at
    /// least one in every connected part of the mesh): the Hessian's sparsity pattern on the
    /// free vertices and its symbolic Cholesky analysis.
    pub fn new(
        mesh: &TriMesh,
        handles: &[usize],
        options: SarapOptions,
    ) -> Result<SymmetricArap, DefOpError> {
        options.check()?;
        let handles = HandleSet::new(mesh, handles)?;
        let rest = TriangleGradients::new(mesh);
        // The Hessian couples the coordinates of vertices that share a triangle: the
        // Laplacian's pattern, each entry a 2×2 block.
        let laplacian = laplacian_csc(mesh);
        let m = handles.n_free();
        let mut col_ptr = Vec::with_capacity(2 * m + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for (c, &v) in handles.free.iter().enumerate() {
            let (rows, _) = laplacian.column(v);
            for axis_col in 0..2 {
                let col = 2 * c + axis_col;
                for &u in rows {
                    let r = handles.free_index[u];
                    if r == NOT_FREE || r > c {
                        continue;
                    }
                    for axis_row in 0..2 {
                        if 2 * r + axis_row <= col {
                            row_idx.push(2 * r + axis_row);
                        }
                    }
                }
                col_ptr.push(row_idx.len());
            }
        }
        let analysis = CholeskyAnalysis::new(2 * m, col_ptr, row_idx, Ordering::Amd)?;
        let mut scatter = Vec::with_capacity(rest.n_triangles());
        for tri in &rest.triangles {
            let mut slots = [NOT_STORED; 36];
            for i in 0..6 {
                for j in 0..6 {
                    let (ri, rj) = (
                        handles.free_index[tri[i / 2]],
                        handles.free_index[tri[j / 2]],
                    );
                    if ri == NOT_FREE || rj == NOT_FREE {
                        continue;
                    }
                    let (row, col) = (2 * ri + i % 2, 2 * rj + j % 2);
                    if row <= col {
                        slots[6 * i + j] = analysis.entry(row, col).ok_or_else(|| {
                            DefOpError::Factorization {
                                detail: format!("bug: Hessian entry ({row}, {col}) of triangle corners {tri:?} missing from the pattern"),
                            }
                        })?;
                    }
                }
            }
            scatter.push(slots);
        }
        let diagonal_entries = (0..2 * m)
            .map(|k| {
                analysis
                    .entry(k, k)
                    .ok_or_else(|| DefOpError::Factorization {
                        detail: format!("bug: diagonal entry {k} missing from the Hessian pattern"),
                    })
            })
            .collect::<Result<_, _>>()?;
        Ok(SymmetricArap {
            rest,
            handles,
            analysis,
            scatter,
            diagonal_entries,
            diagonal: bounding_box_diagonal(mesh),
            options,
        })
    }

    /// Number of handles.
    pub fn n_handles(&self) -> usize {
        self.handles.n_handles()
    }

    /// The handle vertices, in the order targets are given.
    pub fn handles(&self) -> &[usize] {
        &self.handles.vertices
    }

    /// The options the solver was built with.
    pub fn options(&self) -> SarapOptions {
        self.options
    }

    /// Deforms to the handle `targets` (one per handle, in [`SymmetricArap::handles`]'
    /// order). `positions` (one per vertex) holds the initial guess on entry and the result on
    /// return. The guess must flip no triangle; its handles need not be on their targets
    /// (the rest pose `mesh.vertices` is always a valid start). The handles end on their
    /// targets exactly when the report says converged.
    ///
    /// Errors (before any work) on a target or position count that does not match, a value
    /// that is not finite, or a flipped or collapsed triangle in the initial guess.
    pub fn solve(
        &self,
        targets: &[Point],
        positions: &mut [Point],
    ) -> Result<SarapReport, DefOpError> {
        self.handles.check_inputs(targets, positions)?;
        for (t, &tri) in self.rest.triangles.iter().enumerate() {
            let double = double_area(tri, positions);
            if double.is_nan() || double <= 0.0 {
                return Err(DefOpError::FlippedStart {
                    triangle: t,
                    area: 0.5 * double,
                });
            }
        }
        let n_coords = 2 * self.handles.n_free();
        let mut work = Workspace {
            values: vec![0.0; self.analysis.n_entries()],
            exact_values: vec![0.0; self.analysis.n_entries()],
            factor: vec![0.0; self.analysis.factor_len()],
            minus_gradient: vec![0.0; n_coords],
            rhs: vec![0.0; n_coords],
            direction: vec![Vec2::ZERO; positions.len()],
            trial: positions.to_vec(),
            memory: self.analysis.workspace(1)?,
        };
        let tolerance = self.options.step_tolerance * self.diagonal;
        let mut energy = sarap_energy_of(&self.rest, positions);
        let mut report = SarapReport {
            iterations: 0,
            stop: SarapStop::IterationCap,
            energies: vec![energy],
            constrained_from: None,
            last_step: f64::INFINITY,
        };
        let on_target = |u: &[Point]| {
            self.handles
                .vertices
                .iter()
                .zip(targets)
                .all(|(&v, &q)| u[v] == q)
        };
        if on_target(positions) {
            report.constrained_from = Some(0);
        }
        for iteration in 1..=self.options.max_iterations {
            report.iterations = iteration;
            let feasible = report.constrained_from.is_some();
            // d_c: what remains of the handles' way to their targets.
            for (&v, &q) in self.handles.vertices.iter().zip(targets) {
                work.direction[v] = q - positions[v];
            }
            let slope = self.newton_direction(positions, feasible, &mut work)?;
            let step = work
                .direction
                .iter()
                .map(|d| d.x.abs().max(d.y.abs()))
                .fold(0.0, f64::max);
            report.last_step = step;
            tracing::trace!(
                iteration,
                feasible,
                energy,
                step,
                slope,
                "SARAP Newton step"
            );
            if feasible && step <= tolerance {
                report.stop = SarapStop::Converged;
                break;
            }
            // Below the floor the energy cannot tell a good step from a bad one: the step is
            // tried once, kept if the energy does not rise, and the solve stops.
            let at_floor = feasible && -slope <= ENERGY_ROUNDING * energy;
            let alpha_max =
                max_orientation_preserving_step(&self.rest.triangles, positions, &work.direction);
            let mut alpha = (FLIP_MARGIN * alpha_max).min(1.0);
            let mut accepted = false;
            let tries = if at_floor { 1 } else { MAX_BACKTRACKS };
            for _ in 0..tries {
                for (t, (&p, &d)) in work
                    .trial
                    .iter_mut()
                    .zip(positions.iter().zip(&work.direction))
                {
                    *t = p + alpha * d;
                }
                if alpha == 1.0 {
                    // A full step lands the handles on their targets exactly.
                    for (&v, &q) in self.handles.vertices.iter().zip(targets) {
                        work.trial[v] = q;
                    }
                }
                let trial_energy = sarap_energy_of(&self.rest, &work.trial);
                let acceptable = if at_floor {
                    trial_energy <= energy
                } else if feasible {
                    trial_energy <= energy + ARMIJO * alpha * slope
                } else {
                    trial_energy.is_finite()
                };
                if acceptable {
                    positions.copy_from_slice(&work.trial);
                    energy = trial_energy;
                    accepted = true;
                    break;
                }
                alpha *= 0.5;
            }
            if accepted {
                report.energies.push(energy);
                if !feasible && on_target(positions) {
                    report.constrained_from = Some(report.energies.len() - 1);
                }
            }
            // Stalled: with the handles on target, the last STALL_ITERATIONS steps together
            // lowered the energy by less than its rounding.
            let n = report.energies.len();
            let stalled = feasible
                && report
                    .constrained_from
                    .is_some_and(|c| n > c + STALL_ITERATIONS)
                && report.energies[n - 1 - STALL_ITERATIONS] - energy <= ENERGY_ROUNDING * energy;
            if at_floor || stalled {
                report.stop = SarapStop::RoundingFloor;
                break;
            }
            if !accepted {
                report.stop = SarapStop::LineSearchFailed;
                break;
            }
        }
        Ok(report)
    }

    /// Assembles the gradient and the Hessians at `u`, factors, and solves for the Newton
    /// direction of the free vertices into `work.direction` (whose handle entries hold `d_c`
    /// on entry). Returns the slope `gᵀd` over all coordinates.
    ///
    /// With the handles on target, the exact Hessian is used when it is positive definite
    /// (its Cholesky factorisation succeeds): the step is then a true Newton step and
    /// converges quadratically near the minimiser, which the projected Hessian does not where
    /// it clamps (every compressed triangle has a negative twist eigenvalue). Otherwise, and
    /// while the handles are being pulled on target, the projected Hessian.
    fn newton_direction(
        &self,
        u: &[Point],
        feasible: bool,
        work: &mut Workspace,
    ) -> Result<f64, DefOpError> {
        work.values.fill(0.0);
        work.exact_values.fill(0.0);
        work.minus_gradient.fill(0.0);
        work.rhs.fill(0.0);
        let mut slope = 0.0;
        for t in 0..self.rest.n_triangles() {
            let tri = self.rest.triangles[t];
            let Some(local) = triangle_derivatives(&self.rest, t, u) else {
                return Err(DefOpError::Factorization {
                    detail: format!("bug: triangle {t} flipped inside the solve"),
                });
            };
            for i in 0..6 {
                let r = self.handles.free_index[tri[i / 2]];
                if r == NOT_FREE {
                    // A handle coordinate: its part of gᵀd (zero once on target).
                    slope += local.gradient[i] * component(work.direction[tri[i / 2]], i % 2);
                    continue;
                }
                let row = 2 * r + i % 2;
                work.minus_gradient[row] -= local.gradient[i];
                for j in 0..6 {
                    let slot = self.scatter[t][6 * i + j];
                    if slot != NOT_STORED {
                        work.values[slot] += local.hessian[i][j];
                        work.exact_values[slot] += local.exact_hessian[i][j];
                    }
                    if !feasible && self.handles.free_index[tri[j / 2]] == NOT_FREE {
                        work.rhs[row] -=
                            local.hessian[i][j] * component(work.direction[tri[j / 2]], j % 2);
                    }
                }
            }
        }
        // H_ff d_f = −g_f − H_fc d_c (rhs holds −H_fc d_c so far).
        for (r, g) in work.rhs.iter_mut().zip(&work.minus_gradient) {
            *r += g;
        }
        let exact = feasible
            && self
                .analysis
                .factor(&work.exact_values, &mut work.factor, &mut work.memory)
                .is_ok();
        if !exact {
            self.factor_regularised(work)?;
        }
        self.analysis
            .solve(&work.factor, &mut work.rhs, &mut work.memory);
        for (r, &v) in self.handles.free.iter().enumerate() {
            let d = Vec2::new(work.rhs[2 * r], work.rhs[2 * r + 1]);
            work.direction[v] = d;
            slope -= work.minus_gradient[2 * r] * d.x + work.minus_gradient[2 * r + 1] * d.y;
        }
        Ok(slope)
    }

    /// Factors `work.values`, adding a growing multiple of the identity if a pivot is not
    /// positive.
    fn factor_regularised(&self, work: &mut Workspace) -> Result<(), DefOpError> {
        if self.analysis.n() == 0 {
            return Ok(());
        }
        let largest = self
            .diagonal_entries
            .iter()
            .map(|&k| work.values[k])
            .fold(f64::MIN_POSITIVE, f64::max);
        let mut shift = 0.0;
        let mut attempt = 0;
        loop {
            match self
                .analysis
                .factor(&work.values, &mut work.factor, &mut work.memory)
            {
                Ok(()) => return Ok(()),
                Err(e) if attempt == MAX_REGULARISATIONS => return Err(e.into()),
                Err(_) => {
                    let next = if shift == 0.0 {
                        FIRST_REGULARISATION * largest
                    } else {
                        100.0 * shift
                    };
                    for &k in &self.diagonal_entries {
                        work.values[k] += next - shift;
                    }
                    shift = next;
                    attempt += 1;
                    tracing::debug!(attempt, shift, "SARAP Hessian regularised");
                }
            }
        }
    }
}

/// Coordinate `axis` (0: x, 1: y) of `v`.
fn component(v: Vec2, axis: usize) -> f64 {
    if axis == 0 {
        v.x
    } else {
        v.y
    }
}
