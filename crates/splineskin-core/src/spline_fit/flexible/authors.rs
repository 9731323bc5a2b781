//! [`FlexibleRule::Authors`], compatibility mode: the paper authors' schedule and stopping test.
//!
//! Their solver starts with a direction step along the *input's* tangent directions, then
//! alternates ratio and direction steps (`layout.rs`; each side's direction its own current
//! one, [`Sides::Own`]), for at most [`AUTHORS_MAX_ROUNDS`] rounds, and stops when a solution
//! agrees with the previous one of either kind per coordinate,
//!
//! ```text
//! |a − b| ≤ AUTHORS_ATOL + AUTHORS_RTOL · |b|        (numpy's allclose(atol = 1, rtol = 1e-3))
//! ```
//!
//! No energy check is made. (Their published code can also reset a curve end whose tangent
//! turned by 90° or more to 0.1 units along the previous direction, `clamp_solution`; the
//! reference outputs in `authors-solver-outputs` were made without it: with it the clam scene
//! moves by 1.3e-3 of the diagonal, without it it agrees to 2e-14. So it is not reproduced.)

use kurbo::{Point, Vec2};

use super::energy::PathNodes;
use super::layout::{FlexPath, PathRun, Scratch, Sides};
#[cfg(doc)]
use super::options::FlexibleRule;
use crate::spline_fit::FitError;

/// The authors' cap on rounds (a direction and a ratio step each): 10.
pub const AUTHORS_MAX_ROUNDS: usize = 10;

/// The authors' stopping test: absolute tolerance per coordinate, 1 drawing unit (px).
pub const AUTHORS_ATOL: f64 = 1.0;

/// The authors' stopping test: relative tolerance per coordinate, 1e-3.
pub const AUTHORS_RTOL: f64 = 1e-3;

/// [`FlexibleRule::Authors`] (file doc): their preparation step (or `warm`), then at
/// most [`AUTHORS_MAX_ROUNDS`] rounds.
pub(super) fn iterate_authors(
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
        let done =
            allclose(&last_odd, &even) || last_even.as_ref().is_some_and(|l| allclose(l, &even));
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

/// numpy's `allclose(a, b, atol, rtol)` with the authors' tolerances, per coordinate:
/// `|a − b| ≤ atol + rtol · |b|`.
fn allclose(a: &[Point], b: &[Point]) -> bool {
    a.iter().zip(b).all(|(p, q)| {
        (p.x - q.x).abs() <= AUTHORS_ATOL + AUTHORS_RTOL * q.x.abs()
            && (p.y - q.y).abs() <= AUTHORS_ATOL + AUTHORS_RTOL * q.y.abs()
    })
}

#[cfg(test)]
mod tests {
    use super::super::fixture::{case, g1_sine, pose, Case};
    use super::super::options::FlexibleRule;
    use super::*;

    /// The authors' iteration on the fixture at `pose(angle)` (tolerance 1e-5), with the case
    /// it ran on.
    fn authors_run(angle: f64) -> (PathRun, Case) {
        let mut c = case(FlexibleRule::Authors, 1e-5, &pose(angle));
        let fp = &c.solver.paths[0];
        let nodes = &c.solver.nodes[fp.path];
        let run = iterate_authors(fp, nodes, &mut c.sc, c.e_start, None).unwrap();
        (run, c)
    }

    #[test]
    fn allclose_is_numpys_rule() {
        let p = |x: f64| vec![Point::new(x, 0.0)];
        // |a − b| ≤ 1 + 1e-3 |b|.
        assert!(allclose(&p(0.0), &p(1.0)));
        assert!(!allclose(&p(0.0), &p(1.01)));
        assert!(allclose(&p(1000.0), &p(1002.0)));
        assert!(!allclose(&p(1000.0), &p(1003.0)));
        // Relative to b, not a (as numpy).
        assert!(allclose(&p(3000.0), &p(2997.0)) && !allclose(&p(-3000.0), &p(-2995.0)));
    }

    #[test]
    fn iterate_authors_stops_after_one_round_at_the_rest_pose() {
        // The identity pose's target is the input itself: the first direction step along the
        // input's tangents lands on it, the ratio step keeps it, and the round's direction
        // step agrees with it, so the iteration stops there.
        let (run, c) = authors_run(0.0);
        assert_eq!(run.energies.len(), 4, "{:?}", run.energies);
        for (p, q) in run.x.iter().zip(&c.input) {
            assert!((*p - *q).hypot() <= 1e-12 * 10.0, "{p:?} vs {q:?}");
        }
    }

    #[test]
    fn iterate_authors_keeps_g1_within_its_round_cap() {
        let (run, _) = authors_run(0.5);
        assert!(run.energies.len() <= 3 + 2 * AUTHORS_MAX_ROUNDS);
        assert!(g1_sine(&run.x) <= 1e-10);
        assert!(!run.warm);
    }
}
