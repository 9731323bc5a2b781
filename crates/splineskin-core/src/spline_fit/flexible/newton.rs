//! [`FlexibleRule::Newton`]: Newton steps on the points, tangent scalars and turns of a path's
//! flexible junctions together.
//!
//! At a flexible junction with point `P_p` the two neighbours are `P_a = P_p + α R(φ) û`,
//! `P_b = P_p + β R(φ) v̂`: the tangent scalars `α, β > 0` and a common turn `φ` of both
//! tangents (G¹: `û = −v̂`; fixed angle: `û = −R(−θ) v̂`); every other point is free. `E` is
//! quadratic in the points and scalars and smooth in `φ`. A step ([`FlexPath::newton_step`])
//! linearises the turn about the current directions, `P_a ≈ P_p + α û + α₀ δφ û⊥`, and solves
//! one linear KKT system for all points, scalars and turns, with the neighbours' second
//! derivatives `∂²P_a/∂φ² = −α û` and `∂²P_a/∂α∂φ = û⊥` weighted by the energy gradient at the
//! neighbour (the exact Hessian of `E`). Where that step is not a descent direction (its
//! predicted decrease `−gᵀΔx ≤ 0`: the Hessian is indefinite there) they are dropped
//! (Gauss–Newton, always a descent).
//!
//! The scalars are kept positive by an active set: a scalar the step would take below
//! [`MIN_HELD_FRACTION`] of the input's tangent length on that side (or below its current value,
//! if it is already smaller) is held there, its unknown fixed in the KKT system, and the step
//! solved again until no other scalar goes below its bound; a tangent that wants to vanish then
//! reaches its bound in one step and the other unknowns converge as Newton does (shortening the
//! whole step instead made such a path creep, halving the scalar for 17 steps). The step is
//! shortened so that no junction turns by more than [`MAX_TURN`], then halved until `E`
//! decreases ([`FlexPath::newton_update`]); the turn is applied as a rotation
//! ([`Layout::newton_point`]), so the new points satisfy every junction exactly.
//!
//! The iteration ([`iterate_newton`]) stops when a step lowers `E` by less than
//! [`FlexibleOptions::tolerance`] relative and, if the step was cut by the turn limit or
//! halved, its quadratic model promised no more over the whole step; when any step lowers it by
//! no more than the path's noise floor (`energy.rs`); or when a whole Newton step lowered it by
//! what its model predicted, to that tolerance (the model is then accurate, so the step landed
//! at its minimiser). The tolerances include the noise floor. A shortened step's small gain
//! alone is no sign of convergence: the first step far from the optimum, cut short by the turn
//! limit, gained 1.3e-5 relative at one scale and 4.5e-6 at another while its model promised
//! half the energy, and a stop on it left the fit at the fixed-ratio result (energy 333
//! against 171) depending on rounding.

use kurbo::{Point, Vec2};

use super::energy::PathNodes;
use super::layout::{rotate, tangent_lengths, FlexPath, Layout, PathRun, Scratch, Sides, Slot};
use super::options::FlexibleOptions;
#[cfg(doc)]
use super::options::FlexibleRule;
use crate::spline_fit::FitError;

/// The least fraction of the input's tangent length a Newton step lets a tangent scalar reach:
/// 1e-3; a step that would take it lower holds it there (`newton.rs`, active set).
pub const MIN_HELD_FRACTION: f64 = 1e-3;

/// Largest turn of a junction's tangents in one Gauss–Newton step: π/4 (the linearisation
/// of the turn is poor beyond).
pub const MAX_TURN: f64 = std::f64::consts::FRAC_PI_4;

/// Halvings of a Gauss–Newton step tried before the iteration stops: 30.
const MAX_HALVINGS: usize = 30;

/// [`FlexibleRule::Newton`] from `run.x` (file doc).
pub(super) fn iterate_newton(
    options: &FlexibleOptions,
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
    while run.energies.len() <= options.max_steps && e > sc.floor {
        // No decrease along the step (rounding, or NaN): converged as far as arithmetic goes.
        let Some(u) = fp.newton_update(nodes, sc, &run.x, e)? else {
            break;
        };
        // Converged when the step gained little, or when a whole Newton step did what its
        // quadratic model said (the model is then accurate, and the step lands at its
        // minimiser).
        // A shortened or halved step's small gain says nothing about convergence when the
        // whole step promised much more (the first step far from the optimum, cut short by
        // the turn limit, can gain little): it stops the iteration only when the model's
        // decrease over the whole step is within the tolerance too, or at the noise floor.
        let tol = options.tolerance * e + sc.floor;
        let small = u.whole || u.predicted <= tol;
        let done = (small && e - u.energy <= tol)
            || e - u.energy <= sc.floor
            || u.model_error.is_some_and(|m| m <= tol);
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

/// The result of [`FlexPath::newton_update`].
pub(super) struct NewtonUpdate {
    /// The new points.
    pub(super) x: Vec<Point>,
    /// Their energy.
    pub(super) energy: f64,
    /// Whether the step was shortened to keep a scalar positive or a turn small.
    pub(super) shortened: bool,
    /// Whether the whole step was taken (neither cut by the turn limit nor halved).
    pub(super) whole: bool,
    /// The quadratic model's decrease of the energy over the whole step (`−gᵀΔx`).
    pub(super) predicted: f64,
    /// For a whole Newton step, how far its energy decrease was from the quadratic model's.
    pub(super) model_error: Option<f64>,
}

/// The minimiser of the linearised Gauss–Newton problem ([`FlexPath::newton_step`]).
pub(super) struct NewtonStep {
    /// The unknown points that stay free (direction-step numbering).
    pub(super) free: Vec<Point>,
    /// The scalars, side `σ` at index `σ`.
    pub(super) scalars: Vec<f64>,
    /// The turn `δφ` of each junction, radians counter-clockwise.
    pub(super) turns: Vec<f64>,
}

impl FlexPath {
    /// One Newton step from `x` (on the constraint set, energy `e`), or a Gauss–Newton step
    /// where Newton's is not a descent direction; shortened to keep every scalar above its floor
    /// and every turn below [`MAX_TURN`], then halved until the energy is below `e` (file doc).
    /// `None` if no length lowers the energy.
    pub(super) fn newton_update(
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
        // if it is already below (file doc).
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
            // The model's decrease of E over the whole step: −gᵀ Δx (file doc).
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
                    whole: t == 1.0,
                    predicted,
                    model_error,
                }));
            }
            t *= 0.5;
        }
        Ok(None)
    }

    /// The Gauss–Newton step at the current directions `dirs` and scalars `sigma`: the
    /// direction step with each junction's turn `δφ` as one more unknown, linearised
    /// (file doc); each `(side, value)` of `held` fixes that scalar at that value.
    pub(super) fn newton_step(
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
            .solve(&sc.entries, &mut sc.kkt, &mut sc.rhs)
            .map_err(super::layout::kkt_error(self.path))?;
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
    pub(super) fn linear_change(
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
    pub(super) fn newton_point(
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

#[cfg(test)]
mod tests {
    use super::super::fixture::{case, g1_sine, pose, ratio};
    use super::super::options::{FlexibleOptions, FlexibleRule};
    use super::*;

    /// Largest sine between a G¹ junction's tangents accepted: rounding of points of size ~10
    /// (the turn is applied as a rotation, so the junction holds to the last bits).
    const G1_SINE: f64 = 1e-12;

    #[test]
    fn newton_update_lowers_energy_and_keeps_g1() {
        let mut c = case(FlexibleRule::Newton, 1e-5, &pose(0.5));
        let fp = &c.solver.paths[0];
        let nodes = &c.solver.nodes[fp.path];
        c.sc.least = vec![0.0; fp.layout.n_scalars()];
        let u = fp
            .newton_update(nodes, &mut c.sc, &c.start, c.e_start)
            .unwrap()
            .expect("a descent step");
        assert!(u.energy < c.e_start);
        assert_eq!(u.energy, nodes.energy(&c.sc.target, &u.x));
        assert!(g1_sine(&u.x) <= G1_SINE);
        // The ratio is free: it leaves the input's 2.
        assert!((ratio(&u.x) - 2.0).abs() > 1e-3);
    }

    #[test]
    fn iterate_newton_is_monotone_and_stationary() {
        let mut c = case(FlexibleRule::Newton, 1e-12, &pose(0.5));
        let fp = &c.solver.paths[0];
        let nodes = &c.solver.nodes[fp.path];
        let options = FlexibleOptions::default().with_tolerance(1e-12);
        let run = PathRun {
            x: c.start.clone(),
            energies: vec![c.e_start],
            shortened: 0,
            warm: false,
        };
        let run = iterate_newton(&options, fp, nodes, &mut c.sc, run).unwrap();
        assert!(run.energies.windows(2).all(|e| e[1] <= e[0]));
        assert!(run.energies.len() - 1 <= options.max_steps);
        let e = *run.energies.last().unwrap();
        assert!(e < c.e_start);
        assert!(g1_sine(&run.x) <= G1_SINE);
        // Stationary: no further step lowers the energy by more than the tolerance.
        if let Some(u) = fp.newton_update(nodes, &mut c.sc, &run.x, e).unwrap() {
            assert!(
                e - u.energy <= 1e-12 * e + c.sc.floor,
                "{e} -> {}",
                u.energy
            );
        }
    }

    #[test]
    fn newton_point_follows_the_linear_change_and_keeps_g1() {
        let mut c = case(FlexibleRule::Newton, 1e-5, &pose(0.5));
        // The fixed-ratio fit is stationary in the turn already; turn the junction's tangents
        // by 0.3 rad about its point (still G¹) so that the step turns them back.
        let mut x0 = c.start.clone();
        for k in [2, 4] {
            x0[k] = x0[3] + rotate(x0[k] - x0[3], 0.3);
        }
        c.start = x0;
        let fp = &c.solver.paths[0];
        let nodes = &c.solver.nodes[fp.path];
        let layout = &fp.layout;
        let mut dirs = vec![Vec2::ZERO; layout.n_scalars()];
        layout.joint_directions(&c.start, Sides::Derived, &mut dirs);
        let j = &layout.flexible[0];
        let sigma = vec![
            (c.start[j.a] - c.start[j.p]).dot(dirs[0]),
            (c.start[j.b] - c.start[j.p]).dot(dirs[1]),
        ];
        let zero = vec![Vec2::ZERO; 2];
        let step = fp
            .newton_step(nodes, &mut c.sc, &dirs, &sigma, &zero, &[])
            .unwrap();
        assert!(step.turns[0] < -0.1, "turns back: {}", step.turns[0]);
        let dx = layout.linear_change(&c.start, &step, &dirs, &sigma);
        let dx_max = dx.iter().fold(0.0f64, |m, v| m.max(v.hypot()));
        // At t = 0 the start itself; for small t, x + t Δx to first order (the second-order
        // part is ~ t² σ δφ², 1e-7 here against t ‖Δx‖ ~ 1e-4).
        for t in [0.0, 1e-4] {
            let x = layout.newton_point(&c.start, &step, &dirs, &sigma, t);
            for ((p, q), d) in x.iter().zip(&c.start).zip(&dx) {
                let err = (*p - (*q + t * *d)).hypot();
                assert!(err <= 1e-3 * t * dx_max + 1e-13, "t {t}: {err}");
            }
        }
        for t in [0.25, 0.5, 1.0] {
            let x = layout.newton_point(&c.start, &step, &dirs, &sigma, t);
            assert!(g1_sine(&x) <= G1_SINE);
        }
    }
}
