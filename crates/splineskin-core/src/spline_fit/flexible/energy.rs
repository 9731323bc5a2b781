//! One path's fit energy and the quantities built from it, about a point `o` (the path's centre,
//! so that the arithmetic sees numbers of the path's own size wherever it lies).
//!
//! With the fit's quadrature nodes `t_q` (weights `ω_q`, measure included) on the path's curves,
//! the Bernstein basis `b(t_q)`, the handle weights `w_i(q)` and maps `T_i`:
//!
//! ```text
//! target        s_q − o = Σ_i w_i(q) L_i (B(t_q) − o) + (Σ_i w_i(q) − 1) o,   L_i = τ(−o) T_i τ(o)
//! energy        E(x)    = Σ_q ω_q ‖Σ_k b_k(t_q) x_k − s_q‖²
//! right side    b       = Σ_q ω_q b(t_q) s_qᵀ                      (the rig's Σ_i T_i Ŵ_ij)
//! half-gradient g       = H x − b = ½ ∇E(x)                        (H the curves' Gram blocks)
//! noise floor   E_noise = (NOISE_DISTANCE · max_q ‖s_q − o‖∞)² · Σ_q ω_q
//! ```
//!
//! (`τ` a translation, `x` the path's unknown points about `o`.) `E_noise` is the energy of a
//! deviation of [`NOISE_DISTANCE`] times the target's size all along the path: energy decreases
//! below it are rounding (a target the curves can follow exactly, e.g. one affine map for the
//! whole path, has an energy of that order), so the iterations stop there.

use kurbo::{Affine, Point, Vec2};

use crate::bezier;
use crate::spline_fit::quadrature::SampledCurves;

/// Distances below this fraction of a path's largest target coordinate are taken for
/// rounding: 1e-10 (the noise floor of `energy.rs`, used by the stopping tests).
pub const NOISE_DISTANCE: f64 = 1e-10;

/// The quadrature data of one path, for its target, right-hand side and energy.
#[derive(Clone, Debug)]
pub(super) struct PathNodes {
    /// First chain point of the path in the drawing's flat layout.
    pub(super) offset: usize,
    /// Chain points (`3n + 1`).
    pub(super) n_chain: usize,
    /// Unknown points (`3n` closed, `3n + 1` open).
    pub(super) m: usize,
    /// The unknown indices of each curve's control points.
    pub(super) curves: Vec<[usize; 4]>,
    /// Gram matrix of each curve under the fit's rule.
    pub(super) grams: Vec<[[f64; 4]; 4]>,
    /// Node range of curve `j`: `node_start[j] .. node_start[j + 1]`.
    pub(super) node_start: Vec<usize>,
    /// Bernstein basis at each node.
    pub(super) bern: Vec<[f64; 4]>,
    /// Node weight `ω_q` (measure included).
    pub(super) omega: Vec<f64>,
    /// The input curve's point `B(t_q)`, about `centre`.
    pub(super) rest: Vec<Point>,
    /// The centre of the bounding box of the path's chain points: the iteration works in
    /// coordinates about it, so that its arithmetic sees numbers of the path's own size
    /// wherever the path lies.
    pub(super) centre: Vec2,
    /// Handle weights at the nodes, `n_handles` per node.
    pub(super) weights: Vec<f64>,
}

impl PathNodes {
    /// The energy of the path's points in the flat buffer `flat`, computed about `o` (as the
    /// iteration computes it, so that both agree to the last bit).
    pub(super) fn energy_about(
        &self,
        pose: &[Affine],
        o: Vec2,
        flat: &[Point],
        s: &mut Vec<Point>,
    ) -> f64 {
        self.target_about(pose, o, s);
        let x: Vec<Point> = self.unknowns(flat).iter().map(|p| *p - o).collect();
        self.energy(s, &x)
    }

    /// The skinned target `s_q = Σ_i w_i(q) T_i B(t_q)` about a point `o`, `s_q − o`: with `r_q = B(t_q) − o` and
    /// `L_i = τ(−o) T_i τ(o)` (`τ` a translation), `s_q − o = Σ_i w_i L_i r_q + (Σ_i w_i − 1) o`.
    pub(super) fn target_about(&self, pose: &[Affine], o: Vec2, s: &mut Vec<Point>) {
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
    pub(super) fn rhs(&self, s: &[Point], b: &mut Vec<f64>) {
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
    pub(super) fn energy(&self, s: &[Point], x: &[Point]) -> f64 {
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
    pub(super) fn noise_floor(&self, s: &[Point]) -> f64 {
        let size = s
            .iter()
            .fold(0.0f64, |m, p| m.max(p.x.abs()).max(p.y.abs()));
        let measure: f64 = self.omega.iter().sum();
        (NOISE_DISTANCE * size).powi(2) * measure
    }

    /// `H x − b` per unknown point (`H` the Gram matrices, `b` the right-hand side of
    /// [`PathNodes::rhs`]): half the gradient of `E` at `x`.
    pub(super) fn half_gradient(&self, x: &[Point], b: &[f64]) -> Vec<Vec2> {
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
    pub(super) fn unknowns<'a>(&self, flat: &'a [Point]) -> &'a [Point] {
        &flat[self.offset..self.offset + self.m]
    }

    /// Writes the unknown points `x` into a flat chain buffer (a closed path repeats its
    /// first point at the end).
    pub(super) fn write(&self, x: &[Point], flat: &mut [Point]) {
        let out = &mut flat[self.offset..self.offset + self.n_chain];
        out[..self.m].copy_from_slice(x);
        if self.n_chain > self.m {
            out[self.m] = x[0];
        }
    }
}

/// The quadrature data of `path` (whose first curve is curve `first_curve` of `samples` and
/// first chain point `offset` in the flat layout).
pub(super) fn path_nodes(
    path: &crate::drawing::Path,
    samples: &SampledCurves,
    first_curve: usize,
    offset: usize,
) -> PathNodes {
    let m = path.n_unknown_points();
    let unknown = |i: usize| path.unknown_index(i);
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
        centre: crate::spline_fit::system::centre(path.points.iter().copied()),
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

#[cfg(test)]
mod tests {
    use super::super::fixture::{case, pose};
    use super::super::options::FlexibleRule;
    use super::*;

    #[test]
    fn energy_of_the_input_at_the_rest_pose_is_below_the_noise_floor() {
        // Shepard weights sum to 1, so the identity pose's target is the input curve itself.
        let c = case(FlexibleRule::Newton, 1e-5, &pose(0.0));
        let nodes = &c.solver.nodes[0];
        let e = nodes.energy(&c.sc.target, &c.input);
        assert!(c.sc.floor > 0.0);
        assert!(e <= c.sc.floor, "{e} > {}", c.sc.floor);
        // And any visible move of a point costs far more than the floor.
        let mut moved = c.input.clone();
        moved[1].y += 1e-6;
        assert!(nodes.energy(&c.sc.target, &moved) > 1e3 * c.sc.floor);
    }

    #[test]
    fn half_gradient_is_half_the_energy_gradient() {
        let c = case(FlexibleRule::Newton, 1e-5, &pose(0.5));
        let nodes = &c.solver.nodes[0];
        // A point away from any minimiser: the fixed-ratio fit, bent.
        let mut x = c.start.clone();
        x[1].x += 0.3;
        x[5].y -= 0.2;
        let g = nodes.half_gradient(&x, &c.sc.b);
        let g_max = g.iter().fold(0.0f64, |m, v| m.max(v.hypot()));
        assert!(g_max > 1e-3);
        // E is quadratic: central differences are exact up to rounding (E ~ 10, h = 1e-3:
        // ~1e-12).
        let h = 1e-3;
        for k in 0..nodes.m {
            for d in 0..2 {
                let mut e = [0.0; 2];
                for (i, sign) in [1.0, -1.0].into_iter().enumerate() {
                    let mut y = x.clone();
                    if d == 0 {
                        y[k].x += sign * h;
                    } else {
                        y[k].y += sign * h;
                    }
                    e[i] = nodes.energy(&c.sc.target, &y);
                }
                let fd = (e[0] - e[1]) / (2.0 * h);
                let gk = if d == 0 { g[k].x } else { g[k].y };
                assert!(
                    (fd - 2.0 * gk).abs() <= 1e-8 * g_max,
                    "{k},{d}: {fd} vs {}",
                    2.0 * gk
                );
            }
        }
    }

    #[test]
    fn energy_about_agrees_with_the_centred_energy() {
        let pose = pose(0.5);
        let c = case(FlexibleRule::Newton, 1e-5, &pose);
        let nodes = &c.solver.nodes[0];
        let o = nodes.centre;
        let flat: Vec<Point> = c.start.iter().map(|p| *p + o).collect();
        let mut s = Vec::new();
        // About the centre (as the iteration computes it) and about the origin.
        assert_eq!(nodes.energy_about(&pose, o, &flat, &mut s), c.e_start);
        let e0 = nodes.energy_about(&pose, Vec2::ZERO, &flat, &mut s);
        assert!(
            (e0 - c.e_start).abs() <= 1e-9 * c.e_start,
            "{e0} vs {}",
            c.e_start
        );
    }
}
