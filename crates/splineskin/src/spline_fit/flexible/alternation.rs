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
