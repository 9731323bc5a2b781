//! Bounded biharmonic weights (Jacobson, Baran, Popović & Sorkine 2011, *Bounded biharmonic
//! weights for real-time deformation*, §3; DESIGN.md §2; libigl's `bbw`).
//!
//! Each column `w` (one per handle) solves the strictly convex quadratic program
//!
//! ```text
//! minimise  ½ wᵀ Q w   subject to  w[b] = bc,   0 ≤ w ≤ 1,      Q = L M⁻¹ L
//! ```
//!
//! (`Q` the biharmonic energy of [`crate::mesh::operators::polyharmonic_energy`] with `k = 2`),
//! separately per handle; the rows are then normalised to sum to 1 ([`bbw_weights`]).
//! Like libigl, no partition-of-unity constraint couples the columns: the raw rows
//! ([`bounded_biharmonic`]) sum to slightly more than 1 (up to 1.08 on libigl's test shapes).
//!
//! # Solver
//!
//! A primal–dual active-set method (Hintermüller, Ito & Kunisch 2002), the method of libigl's
//! `active_set`, specialised to bounds. Every vertex is *fixed* (Dirichlet), *free*, or held
//! at its *lower* or *upper* bound. Starting from the unconstrained biharmonic solution (one
//! factorisation shared by all handles), each iteration
//!
//! 1. computes the gradient `g = Q w`;
//! 2. moves every free vertex outside `[0, 1]` (by more than the feasibility tolerance) to the
//!    bound it crossed, and frees every bound vertex whose multiplier has the wrong sign: at
//!    the lower bound `g_v < 0` (raising `w_v` would lower the energy), at the upper bound
//!    `g_v > 0` — measured as `−g_v / Q_vv`, the move of `w_v` that would zero its gradient
//!    with its neighbours held, against the optimality tolerance (both tolerances are in
//!    weight units, so they mean the same on graded and uniform meshes);
//! 3. if nothing changed, stops: `w` satisfies the KKT conditions (free vertices inside the box
//!    with `g = 0`, `g ≥ 0` at lower and `g ≤ 0` at upper bounds, to the tolerances);
//! 4. else solves `Q_ff w_f = −Q_fc w_c` with the bound vertices at their bounds as extra
//!    Dirichlet data.
//!
//! Each step 4 factors the new `Q_ff` in the elimination order computed once for the whole
//! `Q` (see `reduced_cholesky`): no ordering pass per iteration, and the factorisation gets
//! cheaper as vertices reach their bounds. Its symbolic analysis covers the free vertices and
//! two rings of `Q`'s pattern around them, and is redone only when a vertex outside that is
//! freed (the factor's workspace is kept between iterations): on the bundled octopus and
//! OpenMoji animals with 4 pins this took 3–7 % off the setup (0.53 → 0.52 s octopus, 0.63 →
//! 0.59 s dog 1F415, 0.34 → 0.31 s giraffe 1F992; release, 2 cores). The free values that end
//! within the feasibility tolerance outside the box are then clamped onto it, so the output
//! respects `0 ≤ w ≤ 1` exactly. The program being strictly convex, its minimiser is unique
//! and the result does not depend on the path (nor on [`BbwOptions::parallel`]): libigl's weights are matched to its
//! own stopping tolerance.
//!
//! **Cost.** One sparse factorisation per iteration and handle. The number of iterations grows
//! with the mesh's resolution: the gradient at a bound vertex only sees `Q`'s stencil (two
//! rings), so the active set's edge moves a ring or two per iteration, and the problem is
//! massively degenerate (most bound vertices have zero multipliers). Measured (re-solves per
//! handle): 7–46 on libigl's 575- and 1 091-vertex test shapes, about 40 on a regular
//! 5 000-vertex grid, 75–115 on the 20 437-vertex turtles domain. Started from a guess
//! ([`bounded_biharmonic_from`]: coarser weights, `super::coarse_to_fine`), far fewer; the
//! guess is first improved by two ADMM steps (`admm_start`), which cut the slowest column of
//! OpenMoji's dog from 50 re-solves to under 10.
//!
//! **Tried and not kept** (setup, release, 2 cores; octopus, OpenMoji dog 1F415, giraffe
//! 1F992, horse 1F40E): looser stopping tolerances (1e-6 halves the octopus, 0.47 → 0.25 s, but
//! not the dog, and 1e-5 errs by 3.9e-3 on the dog, more than the 1e-3 allowed); faer's parallel
//! numeric factorisation inside a column (no gain on 2 cores: the columns already fill them);
//! freeing the degenerate neighbours of a freed bound vertex at once (no gain, 0.47 → 0.56 s on
//! the octopus); a warm start from the previous pins' weights (3–6 times slower); ten ADMM
//! steps instead of two (the octopus 0.51 → 0.77 s).

use rayon::prelude::*;

use super::admm_start;
use super::harmonic::{prepare, solve_unbounded};
use super::reduced_cholesky::{EnergySystem, ReducedCholesky};
use super::{DirichletData, VertexWeights, WeightsError};
use crate::linalg::csc::Csc;
use crate::mesh::TriMesh;
use crate::stop::StopSignal;

/// Lower bound of bounded biharmonic weights.
pub const LOWER: f64 = 0.0;
/// Upper bound of bounded biharmonic weights.
pub const UPPER: f64 = 1.0;

/// Default [`BbwOptions::max_iterations`]: 1 000 active-set iterations per handle. libigl
/// allows 100, of which its test shapes need up to 46; a 20 000-vertex domain needs up to about
/// 115 (see the module documentation), so the limit only stops a cycling active set.
pub const DEFAULT_MAX_ITERATIONS: usize = 1000;
/// Default [`BbwOptions::feasibility_tolerance`]: `1e-10` in weight units (weights are
/// dimensionless, in `[0, 1]`). A free value this close outside the box is accepted (then
/// clamped). The solve's forward error grows with `Q`'s condition number (about `1e8` at
/// 20 000 vertices), so degenerate vertices, whose exact value is 0, come out at up to about
/// `1e-12`; far below any visible effect.
pub const DEFAULT_FEASIBILITY_TOLERANCE: f64 = 1e-10;
/// Default [`BbwOptions::optimality_tolerance`]: `1e-12` in weight units (`−g_v / Q_vv`, see
/// the module documentation). A bound vertex whose multiplier has the wrong sign by less than
/// this stays bound; `g_v` is a sum of about twenty terms `Q_vu w_u`, so its rounding is about
/// `1e-15 · Q_vv`.
pub const DEFAULT_OPTIMALITY_TOLERANCE: f64 = 1e-12;

/// Options of [`bounded_biharmonic`] and [`bbw_weights`].
///
/// ```
/// use splineskin_core::weights::bbw::BbwOptions;
/// let options = BbwOptions::default().with_parallel(true).with_max_iterations(50);
/// assert_eq!(options.max_iterations, 50);
/// ```
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct BbwOptions {
    /// Active-set iterations (re-solves) allowed per handle before giving up with
    /// [`WeightsError::NotConverged`]. Default: [`DEFAULT_MAX_ITERATIONS`].
    pub max_iterations: usize,
    /// How far outside `[0, 1]` a free value may end, in weight units. Default:
    /// [`DEFAULT_FEASIBILITY_TOLERANCE`].
    pub feasibility_tolerance: f64,
    /// How wrong a bound vertex's multiplier may be, as the move `−g_v / Q_vv` it asks for, in
    /// weight units. Default: [`DEFAULT_OPTIMALITY_TOLERANCE`].
    pub optimality_tolerance: f64,
    /// Solve the handles' programs in parallel (rayon's global pool). Default: `false`.
    pub parallel: bool,
    /// Stops the solve between active-set iterations when raised, with
    /// [`WeightsError::Stopped`] (an editor whose user asked for other weights meanwhile).
    /// Default: `None`.
    pub stop: Option<StopSignal>,
}

impl Default for BbwOptions {
    fn default() -> Self {
        BbwOptions {
            max_iterations: DEFAULT_MAX_ITERATIONS,
            feasibility_tolerance: DEFAULT_FEASIBILITY_TOLERANCE,
            optimality_tolerance: DEFAULT_OPTIMALITY_TOLERANCE,
            parallel: false,
            stop: None,
        }
    }
}

impl BbwOptions {
    /// Sets [`BbwOptions::max_iterations`].
    pub fn with_max_iterations(mut self, n: usize) -> Self {
        self.max_iterations = n;
        self
    }
    /// Sets [`BbwOptions::feasibility_tolerance`].
    pub fn with_feasibility_tolerance(mut self, tolerance: f64) -> Self {
        self.feasibility_tolerance = tolerance;
        self
    }
    /// Sets [`BbwOptions::optimality_tolerance`].
    pub fn with_optimality_tolerance(mut self, tolerance: f64) -> Self {
        self.optimality_tolerance = tolerance;
        self
    }
    /// Sets [`BbwOptions::parallel`].
    pub fn with_parallel(mut self, parallel: bool) -> Self {
        self.parallel = parallel;
        self
    }
    /// Sets [`BbwOptions::stop`].
    ///
    /// ```
    /// use kurbo::Rect;
    /// use splineskin_core::mesh::TriMesh;
    /// use splineskin_core::stop::StopSignal;
    /// use splineskin_core::weights::{bbw::{bbw_weights, BbwOptions}, WeightsError};
    /// let mesh = TriMesh::grid(Rect::new(0.0, 0.0, 2.0, 1.0), 16, 8)?;
    /// let stop = StopSignal::new();
    /// stop.raise();
    /// let options = BbwOptions::default().with_stop(Some(stop));
    /// assert_eq!(bbw_weights(&mesh, &[20, 60, 100], &options), Err(WeightsError::Stopped));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn with_stop(mut self, stop: Option<StopSignal>) -> Self {
        self.stop = stop;
        self
    }

    fn check(&self) -> Result<(), WeightsError> {
        if self.max_iterations == 0 {
            return Err(WeightsError::InvalidOption {
                name: "max_iterations",
                value: "0".into(),
                expected: "at least 1",
            });
        }
        for (name, value) in [
            ("feasibility_tolerance", self.feasibility_tolerance),
            ("optimality_tolerance", self.optimality_tolerance),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(WeightsError::InvalidOption {
                    name,
                    value: value.to_string(),
                    expected: "a positive finite number",
                });
            }
        }
        Ok(())
    }
}

/// Bounded biharmonic weights of point handles at vertices `handles`, rows normalised to sum
/// to 1: what skinning uses. `n_vertices × handles.len()`.
///
/// Errors: those of [`crate::weights::harmonic::harmonic_weights`], invalid options, or an
/// active set that does not settle within [`BbwOptions::max_iterations`].
///
/// ```
/// use kurbo::Point;
/// use splineskin_core::mesh::TriMesh;
/// use splineskin_core::weights::bbw::{bbw_weights, BbwOptions};
/// // A 4 × 1 strip of squares, handles at the two ends.
/// let mut v = Vec::new();
/// for y in 0..2 { for x in 0..5 { v.push(Point::new(x as f64, y as f64)); } }
/// let t = (0..4).flat_map(|x| [[x, x + 1, x + 6], [x, x + 6, x + 5]]).collect();
/// let mesh = TriMesh::new(v, t)?;
/// let w = bbw_weights(&mesh, &[0, 4], &BbwOptions::default())?;
/// for v in 0..10 {
///     let row = w.row(v);
///     assert!(row.iter().all(|&x| (0.0..=1.0).contains(&x)));
///     assert!((row[0] + row[1] - 1.0).abs() < 1e-12);
/// }
/// assert_eq!(w.row(4), &[0.0, 1.0]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn bbw_weights(
    mesh: &TriMesh,
    handles: &[usize],
    options: &BbwOptions,
) -> Result<VertexWeights, WeightsError> {
    let mut weights = bounded_biharmonic(mesh, &DirichletData::handles(handles)?, options)?;
    weights.normalize_rows()?;
    Ok(weights)
}

/// The bounded biharmonic function of each column of `data` (values in `[0, 1]` required),
/// **not normalised** (libigl's `bbw` output): `n_vertices × data.n_columns()`.
///
/// ```
/// use kurbo::Point;
/// use splineskin_core::mesh::TriMesh;
/// use splineskin_core::weights::{bbw::{bounded_biharmonic, BbwOptions}, DirichletData};
/// let v = [(0., 0.), (1., 0.), (1., 1.), (0., 1.)].map(Point::from);
/// let mesh = TriMesh::new(v.to_vec(), vec![[0, 1, 2], [0, 2, 3]])?;
/// let data = DirichletData::handles(&[0, 2])?;
/// let w = bounded_biharmonic(&mesh, &data, &BbwOptions::default())?;
/// assert_eq!(w.row(0), &[1.0, 0.0]);
/// // Out-of-box data has no feasible point.
/// let bad = DirichletData::new(vec![0], vec![1.5], 1)?;
/// assert!(bounded_biharmonic(&mesh, &bad, &BbwOptions::default()).is_err());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn bounded_biharmonic(
    mesh: &TriMesh,
    data: &DirichletData,
    options: &BbwOptions,
) -> Result<VertexWeights, WeightsError> {
    options.check()?;
    check_data_bounds(data)?;
    solve_bounded(&prepare(mesh, data, 2)?, data, options)
}

/// The bounded minimiser of each column of `data` for any energy `Q` (symmetric positive
/// semidefinite, full storage, its null space the constants on each connected part of its
/// pattern): `minimise ½ wᵀ Q w subject to w[b] = bc, 0 ≤ w ≤ 1`, by the active-set method of
/// [`bounded_biharmonic`], which is this with `Q = L M⁻¹ L` of a triangle mesh. For example the
/// biharmonic energy of a volume's grid (Catmull–Clark cages' volumetric weights).
///
/// Errors: a fixed vertex out of range, a connected part of `Q`'s pattern with no fixed vertex
/// ([`WeightsError::UnconstrainedComponent`]), and those of [`bounded_biharmonic`].
///
/// ```
/// use splineskin_core::linalg::csc::Csc;
/// use splineskin_core::weights::{bbw::{bounded_minimiser, BbwOptions}, DirichletData};
/// // The path graph 0 – 1 – 2 – 3 – 4: its Laplacian L, and Q = L L (unit masses).
/// let mut t = Vec::new();
/// for i in 0..4 {
///     t.extend([(i, i, 1.0), (i + 1, i + 1, 1.0), (i, i + 1, -1.0), (i + 1, i, -1.0)]);
/// }
/// let l = Csc::from_triplets(5, t);
/// let q = l.times_diagonal_times(&[1.0; 5], &l);
/// let w = bounded_minimiser(q, &DirichletData::handles(&[0, 4])?, &BbwOptions::default())?;
/// assert_eq!(w.row(0), &[1.0, 0.0]);
/// assert!((w.row(2)[0] - 0.5).abs() < 1e-12, "halfway along the path: {:?}", w.row(2));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn bounded_minimiser(
    q: Csc,
    data: &DirichletData,
    options: &BbwOptions,
) -> Result<VertexWeights, WeightsError> {
    options.check()?;
    check_data_bounds(data)?;
    data.check_range(q.n)?;
    check_pattern_components(&q, data)?;
    solve_bounded(&EnergySystem::new(q)?, data, options)
}

/// Every connected part of `q`'s pattern (as a graph) holds a fixed vertex of `data`.
fn check_pattern_components(q: &Csc, data: &DirichletData) -> Result<(), WeightsError> {
    use crate::union_find::{labels, singletons, union};
    let mut parent = singletons(q.n);
    for j in 0..q.n {
        for &i in q.column(j).0 {
            union(&mut parent, i, j);
        }
    }
    let (component, n_components) = labels(&mut parent);
    let mut held = vec![false; n_components];
    for &v in data.vertices() {
        held[component[v]] = true;
    }
    match (0..q.n).find(|&v| !held[component[v]]) {
        Some(vertex) => Err(WeightsError::UnconstrainedComponent { vertex }),
        None => Ok(()),
    }
}

/// The active-set solve of every column from the unbounded minimisers.
fn solve_bounded(
    system: &EnergySystem,
    data: &DirichletData,
    options: &BbwOptions,
) -> Result<VertexWeights, WeightsError> {
    let (n, h) = (system.n(), data.n_columns());
    let columns = solve_unbounded(system, data)?;
    solve_columns(columns, n, h, options, |j, column| {
        let status = initial_status(n, data, None);
        solve_column(system, j, column, status, false, options)
    })
}

/// [`bounded_biharmonic`] started from a guess of the solution (`n_vertices × data.n_columns()`,
/// for example coarser weights interpolated onto this mesh), improved by two ADMM steps
/// (`admm_start`): the vertices where it is then at a bound start at that bound, the others
/// free. The result is the same minimiser
/// (the program is strictly convex); only the number of active-set iterations changes, from
/// about one per ring the active set's edge has to travel to about one per ring the guess has it
/// wrong.
///
/// ```
/// use kurbo::{Point, Rect};
/// use splineskin_core::mesh::TriMesh;
/// use splineskin_core::weights::{bbw::{bounded_biharmonic, bounded_biharmonic_from, BbwOptions}, DirichletData};
/// let mesh = TriMesh::grid(Rect::new(0.0, 0.0, 2.0, 1.0), 16, 8)?;
/// let data = DirichletData::handles(&[20, 60, 100])?;
/// let options = BbwOptions::default();
/// let cold = bounded_biharmonic(&mesh, &data, &options)?;
/// let warm = bounded_biharmonic_from(&mesh, &data, &options, &cold)?;
/// let gap = cold.as_slice().iter().zip(warm.as_slice()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
/// assert!(gap < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn bounded_biharmonic_from(
    mesh: &TriMesh,
    data: &DirichletData,
    options: &BbwOptions,
    guess: &VertexWeights,
) -> Result<VertexWeights, WeightsError> {
    options.check()?;
    check_data_bounds(data)?;
    let h = data.n_columns();
    let n = mesh.n_vertices();
    if guess.n_vertices() != n || guess.n_handles() != h {
        return Err(WeightsError::WeightsShape {
            len: guess.as_slice().len(),
            n_vertices: n,
            n_handles: h,
        });
    }
    let system = prepare(mesh, data, 2)?;
    let mut columns = vec![0.0; n * h];
    for (j, column) in columns.chunks_mut(n).enumerate() {
        for (v, x) in column.iter_mut().enumerate() {
            let g = guess.row(v)[j];
            *x = if g.is_finite() {
                g.clamp(LOWER, UPPER)
            } else {
                LOWER
            };
        }
        for (row, &v) in data.vertices().iter().enumerate() {
            column[v] = data.values_at(row)[j];
        }
    }
    let bounds = (LOWER, UPPER);
    admm_start::improve_guess(&system, data, &mut columns, bounds, options.stop.as_ref())?;
    solve_columns(columns, n, h, options, |j, column| {
        let status = initial_status(n, data, Some(&*column));
        solve_column(&system, j, column, status, true, options)
    })
}

/// Runs `solve(j, column)` on each of the `h` columns (length `n`, column-major in
/// `columns`), in parallel when [`BbwOptions::parallel`] is set, and gathers the solved
/// columns as weights.
fn solve_columns(
    mut columns: Vec<f64>,
    n: usize,
    h: usize,
    options: &BbwOptions,
    solve: impl Fn(usize, &mut [f64]) -> Result<(), WeightsError> + Sync + Send,
) -> Result<VertexWeights, WeightsError> {
    let solve = |(j, column): (usize, &mut [f64])| solve(j, column);
    if options.parallel {
        columns.par_chunks_mut(n).enumerate().try_for_each(solve)?;
    } else {
        columns.chunks_mut(n).enumerate().try_for_each(solve)?;
    }
    Ok(VertexWeights::from_columns(n, h, &columns))
}

/// Dirichlet values outside `[LOWER, UPPER]` leave the program without a feasible point.
fn check_data_bounds(data: &DirichletData) -> Result<(), WeightsError> {
    for (row, &vertex) in data.vertices().iter().enumerate() {
        for (column, &value) in data.values_at(row).iter().enumerate() {
            if !(LOWER..=UPPER).contains(&value) {
                return Err(WeightsError::ValueOutOfBounds {
                    vertex,
                    column,
                    value,
                    lower: LOWER,
                    upper: UPPER,
                });
            }
        }
    }
    Ok(())
}

/// The starting status of every vertex: fixed at the Dirichlet vertices; elsewhere free, or,
/// given a (clamped) guess, at the bound the guess sits on.
fn initial_status(n: usize, data: &DirichletData, guess: Option<&[f64]>) -> Vec<Status> {
    let mut status = match guess {
        None => vec![Status::Free; n],
        Some(w) => w
            .iter()
            .map(|&x| {
                if x <= LOWER {
                    Status::AtLower
                } else if x >= UPPER {
                    Status::AtUpper
                } else {
                    Status::Free
                }
            })
            .collect(),
    };
    for &v in data.vertices() {
        status[v] = Status::Fixed;
    }
    status
}

/// What a vertex is during the active-set iterations.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Status {
    Fixed,
    Free,
    AtLower,
    AtUpper,
}

/// Runs the active-set iterations on column `j` from `status`; leaves the bounded solution in
/// `w`. On entry `w` holds the Dirichlet values at fixed vertices and either the solution for
/// `status` (`resolve_first == false`: the unconstrained solution, all free) or a guess whose
/// free entries are re-solved first (`resolve_first == true`).
fn solve_column(
    system: &EnergySystem,
    j: usize,
    w: &mut [f64],
    mut status: Vec<Status>,
    resolve_first: bool,
    options: &BbwOptions,
) -> Result<(), WeightsError> {
    let n = system.n();
    let diagonal = system.diagonal();
    let feasibility = options.feasibility_tolerance;
    let optimality = options.optimality_tolerance;
    let mut g = vec![0.0; n];
    let mut free = vec![false; n];
    let mut n_changes = 0;
    let mut factor = None;
    if resolve_first {
        resolve(system, &status, &mut free, &mut factor, w)?;
    }
    // Iteration 0 checks the starting solution; each later one follows a re-solve.
    for iteration in 0..=options.max_iterations {
        if options.stop.as_ref().is_some_and(StopSignal::is_raised) {
            return Err(WeightsError::Stopped);
        }
        system.apply(w, &mut g);
        n_changes = 0;
        for v in 0..n {
            // −g_v / Q_vv: how far w_v would move to zero its own gradient (weight units).
            let pull = -g[v] / diagonal[v];
            let next = match status[v] {
                Status::Free if w[v] < LOWER - feasibility => Status::AtLower,
                Status::Free if w[v] > UPPER + feasibility => Status::AtUpper,
                Status::AtLower if pull > optimality => Status::Free,
                Status::AtUpper if pull < -optimality => Status::Free,
                s => s,
            };
            if next != status[v] {
                status[v] = next;
                n_changes += 1;
            }
        }
        if n_changes == 0 {
            for (x, s) in w.iter_mut().zip(&status) {
                if *s == Status::Free {
                    // `+ 0.0` turns a −0.0 into 0.0.
                    *x = x.clamp(LOWER, UPPER) + 0.0;
                }
            }
            tracing::debug!(
                column = j,
                iterations = iteration,
                at_lower = status.iter().filter(|&&s| s == Status::AtLower).count(),
                at_upper = status.iter().filter(|&&s| s == Status::AtUpper).count(),
                "bounded biharmonic weight settled"
            );
            return Ok(());
        }
        if iteration == options.max_iterations {
            break;
        }
        resolve(system, &status, &mut free, &mut factor, w)?;
    }
    Err(WeightsError::NotConverged {
        column: j,
        iterations: options.max_iterations,
        n_changes,
    })
}

/// Puts bound vertices on their bounds and re-solves the free ones given all others,
/// refactoring `factor` when it covers the free set, else analysing a new covered set (the
/// free vertices and [`COVER_RINGS`] rings of neighbours around them, fixed ones left out).
fn resolve(
    system: &EnergySystem,
    status: &[Status],
    free: &mut [bool],
    factor: &mut Option<ReducedCholesky>,
    w: &mut [f64],
) -> Result<(), WeightsError> {
    for (v, s) in status.iter().enumerate() {
        free[v] = *s == Status::Free;
        match s {
            Status::AtLower => w[v] = LOWER,
            Status::AtUpper => w[v] = UPPER,
            _ => {}
        }
    }
    let factor = match factor {
        Some(f) if f.covers(free) => f,
        _ => factor.insert(ReducedCholesky::analyse(system, &cover(system, status))?),
    };
    factor.refactor(system, free)?;
    factor.solve_free(system, w);
    Ok(())
}

/// How many rings of `Q`'s pattern (two mesh rings each) around the free vertices an analysis
/// covers: the active set's edge moves by about one per iteration, so one analysis serves
/// several iterations while the factorisations grow by a band only.
const COVER_RINGS: usize = 2;

/// The vertices that are free, or within [`COVER_RINGS`] rings of a free one and not fixed.
fn cover(system: &EnergySystem, status: &[Status]) -> Vec<bool> {
    let mut covered: Vec<bool> = status.iter().map(|&s| s == Status::Free).collect();
    for _ in 0..COVER_RINGS {
        let previous = covered.clone();
        for (v, c) in covered.iter_mut().enumerate() {
            if !*c && status[v] != Status::Fixed {
                *c = system.neighbours(v).iter().any(|&u| previous[u]);
            }
        }
    }
    covered
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::operators::polyharmonic_energy;
    use kurbo::Rect;

    /// A 2 × 1 rectangle in 24 × 12 cells with four handles: big enough for every bound to be
    /// active somewhere, small enough for a unit test.
    fn strip() -> (TriMesh, Vec<usize>) {
        let mesh = TriMesh::grid(Rect::new(0.0, 0.0, 2.0, 1.0), 24, 12).unwrap();
        // Row-major vertices, 25 per row.
        let handles = vec![3 * 25 + 3, 9 * 25 + 4, 6 * 25 + 12, 6 * 25 + 21];
        (mesh, handles)
    }

    /// The KKT conditions checked independently of the solver: with g = Qw, free vertices have
    /// g = 0, vertices at 0 have g ≥ 0, vertices at 1 have g ≤ 0 (relative to max |Q|).
    fn kkt_residual(mesh: &TriMesh, fixed: &[usize], w: &[f64]) -> f64 {
        let q = polyharmonic_energy(mesh, 2);
        let q_max = q.val().iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let mut g = vec![0.0; w.len()];
        for j in 0..q.ncols() {
            for (i, &x) in q.row_idx_of_col(j).zip(q.val_of_col(j)) {
                g[i] += x * w[j];
            }
        }
        let mut worst: f64 = 0.0;
        for v in (0..w.len()).filter(|v| !fixed.contains(v)) {
            let r = g[v] / q_max;
            worst = worst.max(if w[v] == LOWER {
                -r
            } else if w[v] == UPPER {
                r
            } else {
                r.abs()
            });
        }
        worst
    }

    /// KKT residual allowed: rounding of g (a few units of 1e-16 times the ~20 terms of a row).
    const KKT_ROUNDING: f64 = 1e-12;

    #[test]
    fn bbw_is_bounded_interpolating_kkt_point() {
        let (mesh, handles) = strip();
        let data = DirichletData::handles(&handles).unwrap();
        let raw = bounded_biharmonic(&mesh, &data, &BbwOptions::default()).unwrap();
        let unbounded = crate::weights::harmonic_weights(&mesh, &handles, 2).unwrap();
        let (lo, hi) = unbounded
            .as_slice()
            .iter()
            .fold((1.0f64, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
        assert!(
            lo < -0.01 && hi > 1.01,
            "the bounds matter here: [{lo}, {hi}]"
        );
        for i in 0..handles.len() {
            let w = raw.column(i);
            assert!(w.iter().all(|x| (LOWER..=UPPER).contains(x)));
            assert!(
                w.iter().filter(|&&x| x == LOWER).count() > 10,
                "lower bound active"
            );
            for (j, &v) in handles.iter().enumerate() {
                assert_eq!(w[v], if i == j { 1.0 } else { 0.0 });
            }
            let r = kkt_residual(&mesh, &handles, &w);
            assert!(r < KKT_ROUNDING, "handle {i}: KKT residual {r:e}");
            // Control: the unbounded weights violate the conditions (negative values are
            // "free" there with g = 0, so clamp them to see a wrong-sign multiplier).
            let clamped: Vec<f64> = unbounded
                .column(i)
                .iter()
                .map(|x| x.clamp(0.0, 1.0))
                .collect();
            assert!(kkt_residual(&mesh, &handles, &clamped) > 1e-6);
        }
        let normalised = bbw_weights(&mesh, &handles, &BbwOptions::default()).unwrap();
        for v in 0..mesh.n_vertices() {
            let sum: f64 = normalised.row(v).iter().sum();
            assert!((sum - 1.0).abs() < 1e-15, "vertex {v}: {sum}");
        }
    }

    #[test]
    fn bbw_parallel_equals_sequential() {
        let (mesh, handles) = strip();
        let a = bbw_weights(&mesh, &handles, &BbwOptions::default()).unwrap();
        let b = bbw_weights(&mesh, &handles, &BbwOptions::default().with_parallel(true)).unwrap();
        assert_eq!(a, b);
    }

    #[test]
    fn bbw_rejects_bad_input_and_reports_non_convergence() {
        let (mesh, handles) = strip();
        let data = DirichletData::handles(&handles).unwrap();
        assert!(matches!(
            bounded_biharmonic(&mesh, &data, &BbwOptions::default().with_max_iterations(0)),
            Err(WeightsError::InvalidOption {
                name: "max_iterations",
                ..
            })
        ));
        for bad in [0.0, -1.0, f64::NAN] {
            for options in [
                BbwOptions::default().with_feasibility_tolerance(bad),
                BbwOptions::default().with_optimality_tolerance(bad),
            ] {
                assert!(matches!(
                    bounded_biharmonic(&mesh, &data, &options),
                    Err(WeightsError::InvalidOption { .. })
                ));
            }
        }
        let outside = DirichletData::new(vec![0, 5], vec![1.0, -0.5], 1).unwrap();
        assert_eq!(
            bounded_biharmonic(&mesh, &outside, &BbwOptions::default()),
            Err(WeightsError::ValueOutOfBounds {
                vertex: 5,
                column: 0,
                value: -0.5,
                lower: LOWER,
                upper: UPPER
            })
        );
        // One re-solve is not enough on this mesh: an error, not a wrong answer.
        assert!(matches!(
            bounded_biharmonic(&mesh, &data, &BbwOptions::default().with_max_iterations(1)),
            Err(WeightsError::NotConverged { iterations: 1, .. })
        ));
    }
}
