//! [`Arap`]: the as-rigid-as-possible deformation of a triangle mesh with point handles at
//! vertices, minimised by local–global iteration (Sorkine & Alexa 2007; Liu et al. 2008 for
//! triangles), the ground truth the deformation operators approximate (Poranne & Lipman 2016,
//! Eq. (10); DESIGN.md §4).
//!
//! ```text
//! minimise  E(u) = Σ_t A_t ‖J_t(u) − R_t‖²_F   over u and R_t ∈ SO(2),   subject to u_ℓ = q_ℓ at the handles
//!
//! once:            −L_ff = Σ_t A_t ∇φ_i·∇φ_j restricted to the free vertices f; Cholesky factor
//! each iteration:  1. u_ℓ ← q_ℓ                                   (handles)
//!                  2. R_t ← closest rotation to J_t(u)             (local step, closed form)
//!                  3. −L_ff u_f = b_f + L_fc q,   b_i = Σ_{t ∋ i} A_t R_t ∇φ_i   (global step, x and y)
//! stop:            when no coordinate moved by more than step_tolerance × bounding-box diagonal
//! ```
//!
//! This is exactly libigl 2.6.3's `arap_solve` with its default energy for triangles
//! (`ARAP_ENERGY_TYPE_ELEMENTS`: one rotation per triangle, cotangent weights
//! `½ cot θ_ij` on its edges) and the order of its steps (targets set before the local step),
//! which `../shared/data/reference-igl/README.md` documents; its `b` is the same as libigl's
//! edge form `Σ ½ cot θ_ij R_t (p_i − p_j)` because `A_t ∇φ_i·∇φ_j = −½ cot θ_ij`. Each
//! iteration cannot increase `E`: the local step minimises over the rotations with `u` fixed,
//! the global step over `u` with the rotations fixed.
//!
//! | here | libigl / paper | meaning |
//! |---|---|---|
//! | `targets[ℓ]` | `bc`, `q_ℓ` | handle ℓ's target |
//! | `handles[ℓ]` | `b` | handle ℓ's vertex |
//! | `positions` | `U`, `f(x)` | deformed vertices (initial guess in, result out) |

use kurbo::{Point, Vec2};

use super::arap_energy::arap_energy_of;
use super::deformation_gradient::TriangleGradients;
use super::error::check_count_option;
use super::error::DefOpError;
use super::handles::{bounding_box_diagonal, HandleSet, NOT_FREE};
use splineskin_core::linalg::{CholeskyAnalysis, Ordering};
use splineskin_core::mesh::cotangent::laplacian_csc;
use splineskin_core::mesh::TriMesh;

/// Default [`ArapOptions::max_iterations`]: 10 000 local–global iterations. libigl's
/// reference solutions converged in 135–610 iterations on meshes of 575 and 1091 vertices
/// (`reference-igl/README.md`); the cap only stops a solve that cannot reach its tolerance.
pub const DEFAULT_ARAP_MAX_ITERATIONS: usize = 10_000;

/// Default [`ArapOptions::step_tolerance`]: `2.5e-14`, a fraction of the mesh's bounding-box
/// diagonal. The reference solutions stopped when no coordinate moved by `1e-13` or more in an
/// iteration, on shapes whose diagonal is about 4 (so `2.5e-14` of it); the iteration then
/// sits within about `1e-12` of its fixed point (it contracts by about 0.95 per iteration).
pub const DEFAULT_ARAP_STEP_TOLERANCE: f64 = 2.5e-14;

/// [`ArapOptions::anderson_depth`] used for training deformation operators: Anderson
/// acceleration over the last 5 iterates. Measured, iterations to the default tolerance from
/// the rest pose: 45–80 instead of 135–610 on the ten reference-igl cases, and 102–501 instead
/// of 798–3 686 on ten configurations of the benchmark octopus (1 991 vertices, 9 handles),
/// about 7 times fewer at a slightly higher cost per iteration; depths 3 and 10 gave within
/// 10 % of depth 5.
pub const TRAINING_ANDERSON_DEPTH: usize = 5;

/// Relative ridge added to the Anderson least-squares normal equations' diagonal, so nearly
/// dependent residual differences do not blow the mixing coefficients up (dimensionless).
const ANDERSON_RIDGE: f64 = 1e-10;

/// Options of [`Arap`].
///
/// ```
/// use splineskin_defop::ArapOptions;
/// let options = ArapOptions::default().with_max_iterations(10).with_step_tolerance(0.0);
/// assert_eq!(options.max_iterations, 10);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct ArapOptions {
    /// Local–global iterations allowed per solve. Default: [`DEFAULT_ARAP_MAX_ITERATIONS`].
    pub max_iterations: usize,
    /// Stop once an iteration moves no coordinate by more than this fraction of the rest
    /// mesh's bounding-box diagonal (dimensionless; `0` runs exactly `max_iterations`).
    /// Default: [`DEFAULT_ARAP_STEP_TOLERANCE`].
    pub step_tolerance: f64,
    /// Anderson acceleration of the local–global map over this many previous iterates (Walker
    /// & Ni 2011), with Peng et al.'s 2018 energy safeguard; `0` runs the plain iteration,
    /// libigl's. Both stop on the same test (one plain local–global step from the iterate
    /// moves nothing more than the tolerance) and return that step's result, so they end at
    /// the same fixed point to the tolerance. Default: `0`; training uses
    /// [`TRAINING_ANDERSON_DEPTH`].
    pub anderson_depth: usize,
}

impl Default for ArapOptions {
    fn default() -> Self {
        ArapOptions {
            max_iterations: DEFAULT_ARAP_MAX_ITERATIONS,
            step_tolerance: DEFAULT_ARAP_STEP_TOLERANCE,
            anderson_depth: 0,
        }
    }
}

impl ArapOptions {
    /// Sets [`ArapOptions::max_iterations`].
    pub fn with_max_iterations(mut self, n: usize) -> Self {
        self.max_iterations = n;
        self
    }
    /// Sets [`ArapOptions::step_tolerance`].
    pub fn with_step_tolerance(mut self, tolerance: f64) -> Self {
        self.step_tolerance = tolerance;
        self
    }
    /// Sets [`ArapOptions::anderson_depth`].
    pub fn with_anderson_depth(mut self, depth: usize) -> Self {
        self.anderson_depth = depth;
        self
    }

    fn check(&self) -> Result<(), DefOpError> {
        check_iteration_options(self.max_iterations, self.step_tolerance)
    }
}

/// How an ARAP solve ended.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct ArapReport {
    /// Local–global iterations run.
    pub iterations: usize,
    /// Whether the last iteration moved no coordinate by more than the step tolerance;
    /// `false` when the iteration cap stopped the solve.
    pub converged: bool,
    /// The largest coordinate change of the last iteration, in drawing units.
    pub last_step: f64,
    /// `E_ARAP` at the result ([`super::arap_energy`]).
    pub energy: f64,
}

impl ArapReport {
    /// The report before the first iteration: none run, not converged, no step or energy yet.
    const NOT_STARTED: ArapReport = ArapReport {
        iterations: 0,
        converged: false,
        last_step: f64::INFINITY,
        energy: f64::NAN,
    };
}

/// ARAP deformation with point handles at mesh vertices, factored for one set of handles.
///
/// Build once per mesh and handle set ([`Arap::new`]: the Cholesky factor of the Laplacian on
/// the free vertices); then [`Arap::solve`] for any number of target configurations, warm
/// started from any initial guess. `solve` takes `&self`, so one `Arap` serves many threads.
///
/// A vertex in no triangle has no energy: it is not moved (it keeps its initial position).
///
/// ```
/// use kurbo::{Point, Rect};
/// use splineskin_defop::{Arap, ArapOptions};
/// use splineskin_core::mesh::TriMesh;
/// let mesh = TriMesh::grid(Rect::new(0., 0., 4., 1.), 8, 2)?;
/// // Handles at the two ends of the bar's mid-line (vertices 9 and 17).
/// let arap = Arap::new(&mesh, &[9, 17], ArapOptions::default())?;
/// // Pull the right end 1 unit further right: the bar stretches.
/// let mut positions = mesh.vertices.clone();
/// let report = arap.solve(&[Point::new(0., 0.5), Point::new(5., 0.5)], &mut positions)?;
/// assert!(report.converged);
/// assert_eq!(positions[17], Point::new(5., 0.5)); // handles are met exactly
/// assert!(positions[8].x > 4.0 && report.energy > 0.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct Arap {
    rest: TriangleGradients,
    /// `A_t ∇φ_k` per triangle corner.
    weighted_gradient: Vec<[Vec2; 3]>,
    handles: HandleSet,
    /// `(free row r, handle ℓ, (−L)_{r, handles[ℓ]})`: the free rows' coupling to handles.
    coupling: Vec<(usize, usize, f64)>,
    analysis: CholeskyAnalysis,
    /// The Cholesky factor of `−L_ff`.
    factor: Vec<f64>,
    /// The rest mesh's bounding-box diagonal.
    diagonal: f64,
    options: ArapOptions,
}

impl Arap {
    /// Precomputes the solver for `mesh` with handles at the vertices `handles` (distinct, at
    /// least one in every connected part of the mesh): checks the inputs and factors the
    /// cotangent Laplacian restricted to the free vertices.
    pub fn new(
        mesh: &TriMesh,
        handles: &[usize],
        options: ArapOptions,
    ) -> Result<Arap, DefOpError> {
        options.check()?;
        let handles = HandleSet::new(mesh, handles)?;
        let rest = TriangleGradients::new(mesh);
        let weighted_gradient = (0..rest.n_triangles())
            .map(|t| rest.gradient[t].map(|g| rest.area[t] * g))
            .collect();
        let laplacian = laplacian_csc(mesh);
        let mut handle_of = vec![usize::MAX; mesh.n_vertices()];
        for (l, &v) in handles.vertices.iter().enumerate() {
            handle_of[v] = l;
        }
        let m = handles.n_free();
        let mut col_ptr = Vec::with_capacity(m + 1);
        let mut row_idx = Vec::new();
        let mut values = Vec::new();
        let mut coupling = Vec::new();
        col_ptr.push(0);
        for (c, &v) in handles.free.iter().enumerate() {
            let (rows, vals) = laplacian.column(v);
            for (&u, &x) in rows.iter().zip(vals) {
                let r = handles.free_index[u];
                if r != NOT_FREE && r <= c {
                    row_idx.push(r);
                    values.push(-x);
                }
                if handle_of[u] != usize::MAX {
                    // −L is symmetric: (−L)_{v,u} = (−L)_{u,v}.
                    coupling.push((c, handle_of[u], -x));
                }
            }
            col_ptr.push(row_idx.len());
        }
        let analysis = CholeskyAnalysis::new(m, col_ptr, row_idx, Ordering::Amd)?;
        let mut factor = vec![0.0; analysis.factor_len()];
        if m > 0 {
            let mut workspace = analysis.workspace(0)?;
            analysis.factor(&values, &mut factor, &mut workspace)?;
        }
        Ok(Arap {
            rest,
            weighted_gradient,
            handles,
            coupling,
            analysis,
            factor,
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
    pub fn options(&self) -> ArapOptions {
        self.options
    }

    /// Deforms to the handle `targets` (one per handle, in [`Arap::handles`]' order).
    /// `positions` (one per vertex) holds the initial guess on entry — the rest pose
    /// `mesh.vertices` for a cold start, a previous solution for a warm start — and the
    /// result on return. The handles are set to their targets exactly.
    ///
    /// Errors (before any work) on a target or position count that does not match, or a
    /// value that is not finite. A solve stopped by the iteration cap is not an error: the
    /// report says `converged: false`.
    pub fn solve(
        &self,
        targets: &[Point],
        positions: &mut [Point],
    ) -> Result<ArapReport, DefOpError> {
        self.handles.check_inputs(targets, positions)?;
        if self.options.anderson_depth > 0 {
            return self.solve_anderson(targets, positions);
        }
        let m = self.handles.n_free();
        let mut rhs = vec![0.0; 2 * m];
        let mut workspace = self.analysis.workspace(2)?;
        let tolerance = self.options.step_tolerance * self.diagonal;
        let mut report = ArapReport::NOT_STARTED;
        for iteration in 1..=self.options.max_iterations {
            let mut step: f64 = 0.0;
            for (&v, &q) in self.handles.vertices.iter().zip(targets) {
                step = step.max(max_coordinate_change(positions[v], q));
                positions[v] = q;
            }
            self.global_right_hand_side(positions, targets, &mut rhs);
            self.analysis.solve(&self.factor, &mut rhs, &mut workspace);
            for (r, &v) in self.handles.free.iter().enumerate() {
                let new = Point::new(rhs[r], rhs[m + r]);
                step = step.max(max_coordinate_change(positions[v], new));
                positions[v] = new;
            }
            report.iterations = iteration;
            report.last_step = step;
            if step <= tolerance {
                report.converged = true;
                break;
            }
        }
        report.energy = arap_energy_of(&self.rest, positions);
        Ok(report)
    }

    /// The global step's right-hand side `b_f + L_fc q` (x column then y column) for the
    /// rotations closest to the current `J_t` (the local step). Returns `E_ARAP(u)`, which
    /// those rotations attain.
    fn global_right_hand_side(&self, u: &[Point], targets: &[Point], rhs: &mut [f64]) -> f64 {
        let m = self.handles.n_free();
        rhs.fill(0.0);
        let mut energy = 0.0;
        for t in 0..self.rest.n_triangles() {
            let split = self.rest.jacobian(t, u).split();
            energy += self.rest.area[t] * split.arap_density();
            let (cos, sin) = split.closest_rotation();
            let tri = self.rest.triangles[t];
            for k in 0..3 {
                let r = self.handles.free_index[tri[k]];
                if r != NOT_FREE {
                    let w = self.weighted_gradient[t][k];
                    rhs[r] += cos * w.x - sin * w.y;
                    rhs[m + r] += sin * w.x + cos * w.y;
                }
            }
        }
        for &(r, l, x) in &self.coupling {
            rhs[r] -= x * targets[l].x;
            rhs[m + r] -= x * targets[l].y;
        }
        energy
    }

    /// [`Arap::solve`] with Anderson acceleration (type II, Walker & Ni 2011) of the fixed
    /// point map `g` = local step then global step, on the free coordinates `x`:
    ///
    /// ```text
    /// f_k = g(x_k) − x_k;   γ = argmin ‖f_k − ΔF γ‖   (ΔF, ΔG: the last differences of f, g)
    /// x_{k+1} = g(x_k) − ΔG γ
    /// ```
    ///
    /// Safeguard (Peng, Deng, Zhang & Zhang 2018, *Anderson acceleration for geometry
    /// optimization and physics simulation*, §4): an accelerated iterate whose energy exceeds
    /// the previous iterate's is replaced by the plain step `g(x_k)` (which never raises it)
    /// and the history is cleared, so the energy decreases monotonically as in the plain
    /// iteration. Stop when `max |f_k| ≤ tolerance`, returning `g(x_k)`.
    fn solve_anderson(
        &self,
        targets: &[Point],
        positions: &mut [Point],
    ) -> Result<ArapReport, DefOpError> {
        let m = self.handles.n_free();
        let dim = 2 * m;
        let depth = self.options.anderson_depth;
        let mut workspace = self.analysis.workspace(2)?;
        let tolerance = self.options.step_tolerance * self.diagonal;
        let mut report = ArapReport::NOT_STARTED;
        let mut handle_step: f64 = 0.0;
        for (&v, &q) in self.handles.vertices.iter().zip(targets) {
            handle_step = handle_step.max(max_coordinate_change(positions[v], q));
            positions[v] = q;
        }
        let free = &self.handles.free;
        let write = |x: &[f64], positions: &mut [Point]| {
            for (r, &v) in free.iter().enumerate() {
                positions[v] = Point::new(x[r], x[m + r]);
            }
        };
        let mut x: Vec<f64> = free.iter().map(|&v| positions[v].x).collect();
        x.extend(free.iter().map(|&v| positions[v].y));
        let mut g = vec![0.0; dim];
        let mut f = vec![0.0; dim];
        // The previous f and g, and the differences (ring buffers of `depth` vectors).
        let mut previous: Option<(Vec<f64>, Vec<f64>)> = None;
        let mut delta_f: Vec<Vec<f64>> = Vec::with_capacity(depth);
        let mut delta_g: Vec<Vec<f64>> = Vec::with_capacity(depth);
        let mut oldest = 0;
        // The plain step of the last accepted iterate, to fall back on.
        let mut fallback: Option<Vec<f64>> = None;
        let mut accepted_energy = f64::INFINITY;
        let mut gram = vec![0.0; depth * depth];
        let mut gamma = vec![0.0; depth];
        for iteration in 1..=self.options.max_iterations {
            write(&x, positions);
            let mut energy = self.global_right_hand_side(positions, targets, &mut g);
            if let Some(plain) = fallback.take() {
                if energy > accepted_energy {
                    x.copy_from_slice(&plain);
                    write(&x, positions);
                    delta_f.clear();
                    delta_g.clear();
                    oldest = 0;
                    previous = None;
                    energy = self.global_right_hand_side(positions, targets, &mut g);
                }
            }
            accepted_energy = energy;
            self.analysis.solve(&self.factor, &mut g, &mut workspace);
            let mut step = if iteration == 1 { handle_step } else { 0.0 };
            for ((fi, gi), xi) in f.iter_mut().zip(&g).zip(&x) {
                *fi = gi - xi;
                step = step.max(fi.abs());
            }
            report.iterations = iteration;
            report.last_step = step;
            if step <= tolerance || iteration == self.options.max_iterations {
                write(&g, positions);
                report.converged = step <= tolerance;
                break;
            }
            if let Some((pf, pg)) = previous.as_mut() {
                let df: Vec<f64> = f.iter().zip(pf.iter()).map(|(a, b)| a - b).collect();
                let dg: Vec<f64> = g.iter().zip(pg.iter()).map(|(a, b)| a - b).collect();
                if delta_f.len() < depth {
                    delta_f.push(df);
                    delta_g.push(dg);
                } else {
                    delta_f[oldest] = df;
                    delta_g[oldest] = dg;
                    oldest = (oldest + 1) % depth;
                }
                pf.copy_from_slice(&f);
                pg.copy_from_slice(&g);
            } else {
                previous = Some((f.clone(), g.clone()));
            }
            let k = delta_f.len();
            let mixed = k > 0 && anderson_coefficients(&delta_f, &f, &mut gram, &mut gamma);
            if mixed {
                fallback = Some(g.clone());
                x.copy_from_slice(&g);
                for (j, dg) in delta_g.iter().enumerate() {
                    x.iter_mut().zip(dg).for_each(|(xi, d)| *xi -= gamma[j] * d);
                }
            } else {
                x.copy_from_slice(&g);
            }
        }
        report.energy = arap_energy_of(&self.rest, positions);
        Ok(report)
    }
}

/// Solves the Anderson least squares `min ‖f − ΔF γ‖` by its normal equations
/// `(ΔFᵀΔF + ridge) γ = ΔFᵀ f` (Cholesky of the `k × k` Gram matrix, `k = delta_f.len()`),
/// writing `γ` into `gamma[..k]`. Returns `false` if the system is not positive definite.
fn anderson_coefficients(
    delta_f: &[Vec<f64>],
    f: &[f64],
    gram: &mut [f64],
    gamma: &mut [f64],
) -> bool {
    let k = delta_f.len();
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    for i in 0..k {
        for j in 0..=i {
            gram[i * k + j] = dot(&delta_f[i], &delta_f[j]);
        }
        gamma[i] = dot(&delta_f[i], f);
    }
    let largest = (0..k).map(|i| gram[i * k + i]).fold(0.0, f64::max);
    if !(largest > 0.0 && largest.is_finite()) {
        return false;
    }
    for i in 0..k {
        gram[i * k + i] += ANDERSON_RIDGE * largest;
    }
    // In-place Cholesky of the lower triangle, then the two triangular solves.
    for j in 0..k {
        let mut d = gram[j * k + j];
        for p in 0..j {
            d -= gram[j * k + p] * gram[j * k + p];
        }
        if d.is_nan() || d <= 0.0 {
            return false;
        }
        let d = d.sqrt();
        gram[j * k + j] = d;
        for i in j + 1..k {
            let mut v = gram[i * k + j];
            for p in 0..j {
                v -= gram[i * k + p] * gram[j * k + p];
            }
            gram[i * k + j] = v / d;
        }
    }
    for i in 0..k {
        let mut v = gamma[i];
        for p in 0..i {
            v -= gram[i * k + p] * gamma[p];
        }
        gamma[i] = v / gram[i * k + i];
    }
    for i in (0..k).rev() {
        let mut v = gamma[i];
        for p in i + 1..k {
            v -= gram[p * k + i] * gamma[p];
        }
        gamma[i] = v / gram[i * k + i];
    }
    true
}

/// `max(|Δx|, |Δy|)` between two points.
fn max_coordinate_change(a: Point, b: Point) -> f64 {
    (a.x - b.x).abs().max((a.y - b.y).abs())
}

/// The checks both solvers' options share: at least one iteration, and a step tolerance that
/// is a finite fraction ≥ 0 of the bounding-box diagonal.
pub(super) fn check_iteration_options(
    max_iterations: usize,
    step_tolerance: f64,
) -> Result<(), DefOpError> {
    check_count_option("max_iterations", max_iterations)?;
    if !(step_tolerance.is_finite() && step_tolerance >= 0.0) {
        return Err(DefOpError::InvalidOption {
            name: "step_tolerance",
            value: step_tolerance.to_string(),
            expected: "a finite fraction ≥ 0 of the bounding-box diagonal",
        });
    }
    Ok(())
}
