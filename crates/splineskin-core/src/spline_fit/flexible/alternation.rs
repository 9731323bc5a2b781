//! [`FlexibleRule::Alternating`], the method of the paper: ratio and direction steps
//! (`layout.rs`) in turn, each the minimiser of `E` over a set that contains the current
//! solution `x⁽ᵏ⁾`.
//!
//! `x⁽ᵏ⁾` lies in both sets (its tangents are parallel with positive lengths), so no step
//! increases `E`. The scalars are kept positive: when the direction step's minimiser has some
//! `α < MIN_SCALAR_FRACTION · α⁽ᵏ⁾`, the step goes from `x⁽ᵏ⁾` towards the minimiser only as far
//! as the first scalar reaches that floor,
//!
//! ```text
//! t = min over such sides of (α⁽ᵏ⁾ − floor) / (α⁽ᵏ⁾ − α*),    floor = MIN_SCALAR_FRACTION · α⁽ᵏ⁾
//! ```
//!
//! (`E` is convex along the segment and decreasing towards the minimiser, so the step still
//! does not increase it). A step whose energy comes out larger (rounding) is discarded and the
//! iteration stops. Iterations stop when a round (one step of each kind) lowers `E` by less
//! than [`FlexibleOptions::tolerance`] relative plus the path's noise floor (`energy.rs`), or
//! after [`FlexibleOptions::max_steps`] steps.

use kurbo::Vec2;

use super::energy::PathNodes;
use super::layout::{FlexPath, PathRun, Scratch, Sides};
use super::options::FlexibleOptions;
#[cfg(doc)]
use super::options::FlexibleRule;
use crate::spline_fit::FitError;

/// Smallest fraction of its current value a direction step may shrink a tangent scalar `α` to:
/// 0.5. Keeps the scalars positive (a negative one would reverse the tangent, a cusp).
pub const MIN_SCALAR_FRACTION: f64 = 0.5;

/// [`FlexibleRule::Alternating`] from `run.x` (file doc).
pub(super) fn iterate_alternating(
    options: &FlexibleOptions,
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
            if run.energies.len() > options.max_steps {
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
        if e_round - e <= options.tolerance * e_round + sc.floor {
            break;
        }
    }
    Ok(run)
}

#[cfg(test)]
mod tests {
    use super::super::fixture::{case, g1_sine, pose, ratio};
    use super::super::newton::iterate_newton;
    use super::super::options::{FlexibleOptions, FlexibleRule};
    use super::*;

    #[test]
    fn iterate_alternating_is_monotone_keeps_g1_and_meets_newton() {
        let tol = 1e-12;
        let options = FlexibleOptions::default()
            .with_tolerance(tol)
            .with_max_steps(2000);
        let mut runs = Vec::new();
        for rule in [FlexibleRule::Alternating, FlexibleRule::Newton] {
            let mut c = case(rule, tol, &pose(0.5));
            let fp = &c.solver.paths[0];
            let nodes = &c.solver.nodes[fp.path];
            let run = PathRun {
                x: c.start.clone(),
                energies: vec![c.e_start],
                shortened: 0,
                warm: false,
            };
            let run = if rule == FlexibleRule::Alternating {
                iterate_alternating(&options, fp, nodes, &mut c.sc, run)
            } else {
                iterate_newton(&options, fp, nodes, &mut c.sc, run)
            }
            .unwrap();
            runs.push((run, c.e_start));
        }
        let (alt, e_start) = &runs[0];
        let newton = &runs[1].0;
        let (e_alt, e_newton) = (
            *alt.energies.last().unwrap(),
            *newton.energies.last().unwrap(),
        );
        assert!(alt.energies.windows(2).all(|e| e[1] <= e[0]));
        assert!(e_alt < *e_start);
        // Alternating steps keep the tangents parallel exactly as a direction step puts them
        // (a ratio step keeps them parallel through its linear rows): rounding of size ~10.
        assert!(g1_sine(&alt.x) <= 1e-10);
        // Both rules minimise the same energy over the same set.
        assert!(
            (e_alt - e_newton).abs() <= 1e-6 * e_newton,
            "{e_alt} vs {e_newton}"
        );
        assert!((ratio(&alt.x) - ratio(&newton.x)).abs() <= 1e-3 * ratio(&newton.x));
    }
}
