//! The step-independent description of a path with flexible junctions ([`Layout`],
//! [`FlexPath`], built by [`flex_path`]) and the two linear steps of the alternation, which the
//! Newton and authors' rules share.
//!
//! A G¹ or fixed-angle junction (points `a`, `p`, `b`: the tangent neighbour before, the
//! junction point, the neighbour after) is flexible unless its tangents vanish or a neighbour is
//! an on-curve point or appears in another junction's rows. Both steps minimise `E`
//! (`energy.rs`) over a set that contains the current solution `x⁽ᵏ⁾`:
//!
//! * **ratio step** ([`FlexPath::ratio_step`]) — the rig's rows
//!   `l_u · v' − l_v · R(θ) · u' = 0` ([`crate::spline_fit::constraints`]) with the lengths
//!   `l_u = ‖P_p − P_a‖`, `l_v = ‖P_b − P_p‖` of `x⁽ᵏ⁾`; KKT matrix `[H, Cᵀ; C, 0]`
//!   ([`ratio_entries`]);
//! * **direction step** ([`FlexPath::direction_step`]) — at every flexible junction the two
//!   neighbours become a scalar along a fixed direction: `P_a = P_p + α û`, `P_b = P_p + β v̂`,
//!   `v̂` the current outgoing unit tangent and `û = −R(−θ) v̂` (G¹, `θ = 0`: `û = −v̂`;
//!   [`Layout::joint_directions`]); `α`, `β` are new unknowns and the neighbours leave the
//!   system: `x = S z`, KKT matrix `[SᵀHS, (CS)ᵀ; CS, 0]` ([`Layout::direction_entries`], which
//!   also builds the Newton step's matrix, `newton.rs`).
//!
//! Every KKT matrix keeps its pattern (every entry, zero or not) and is eliminated in chain
//! order, each constraint row after its unknowns ([`elimination_keys`]), and solved by
//! `crate::linalg::LdltLu` (`LDLᵀ` in that order, a pivoting LU where that fails).

use kurbo::{Point, Vec2};

use super::energy::PathNodes;
use crate::drawing::JointKind;
use crate::linalg::{LdltLu, LdltLuScratch, LinalgError};
use crate::spline_fit::constraints::{
    push_pins, tangent_junctions, ConstraintRows, TangentJunction,
};
use crate::spline_fit::{ConstraintForm, FitError, FitOptions};

/// The place of an unknown point in the direction step's unknowns `z`.
#[derive(Clone, Copy, Debug)]
pub(super) enum Slot {
    /// A point of its own: `z[2f], z[2f + 1]`.
    Free(usize),
    /// A flexible junction's neighbour `P_p + σ · dir_σ`: free point `f` (the junction point)
    /// and scalar `σ` (`z[2 n_free + σ]`).
    Along { base: usize, scalar: usize },
}

/// The step-independent description of a path with flexible junctions.
#[derive(Clone, Debug)]
pub(super) struct Layout {
    /// The flexible junctions (G¹ and fixed angle), whose ratio or directions the steps update.
    pub(super) flexible: Vec<TangentJunction>,
    /// All other rows: tangent rows with the input lengths, and pins.
    pub(super) fixed_rows: ConstraintRows,
    /// The input's unknown points (the authors' first direction step uses their tangents).
    pub(super) input: Vec<Point>,
    /// Per unknown point, its place in the direction step.
    pub(super) slots: Vec<Slot>,
    /// Points that stay unknowns in the direction step.
    pub(super) n_free: usize,
}

/// One path with flexible junctions: its layout and its three step systems (ratio, direction,
/// Gauss–Newton).
#[derive(Clone, Debug)]
pub(super) struct FlexPath {
    /// Index of the path in the drawing (and in [`FlexibleSolver::nodes`]).
    pub(super) path: usize,
    pub(super) layout: Layout,
    pub(super) ratio: LdltLu,
    pub(super) direction: LdltLu,
    /// The Gauss–Newton step's system: the direction step's plus a turn per junction.
    pub(super) newton: LdltLu,
}

/// Scratch of one path's solve.
#[derive(Default)]
pub(super) struct Scratch {
    pub(super) target: Vec<Point>,
    pub(super) b: Vec<f64>,
    pub(super) entries: Vec<(usize, usize, f64)>,
    pub(super) kkt: LdltLuScratch,
    pub(super) rhs: Vec<f64>,
    /// The energy under which the path counts as converged ([`PathNodes::noise_floor`]).
    pub(super) floor: f64,
    /// Per tangent scalar, the least value a Newton step holds it at:
    /// [`MIN_HELD_FRACTION`] of the input's tangent length on that side.
    pub(super) least: Vec<f64>,
}

/// The result of one path's iteration.
pub(super) struct PathRun {
    pub(super) x: Vec<Point>,
    pub(super) energies: Vec<f64>,
    pub(super) shortened: usize,
    pub(super) warm: bool,
}

/// Where the direction step takes each side's direction from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Sides {
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
    pub(super) fn joint_directions(&self, x: &[Point], sides: Sides, dirs: &mut [Vec2]) {
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
    pub(super) fn terms(
        &self,
        k: usize,
        d: usize,
        dirs: &[Vec2],
    ) -> impl Iterator<Item = (usize, f64)> {
        self.terms_turning(k, d, dirs, None)
    }

    /// [`Layout::terms`], and with `sigma` (the current scalars) the linearised turn of the
    /// junction too: `P_a = P_p + α û + σ_a δφ û⊥` (Gauss–Newton step, `newton.rs`), `δφ` of
    /// junction `q` at `z[2 n_free + n_scalars + q]`.
    pub(super) fn terms_turning(
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
    pub(super) fn n_scalars(&self) -> usize {
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
    pub(super) fn direction_entries(
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
    pub(super) fn ratio_step(
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
            .solve(&sc.entries, &mut sc.kkt, &mut sc.rhs)
            .map_err(kkt_error(self.path))?;
        Ok((0..nodes.m)
            .map(|k| Point::new(sc.rhs[2 * k], sc.rhs[2 * k + 1]))
            .collect())
    }

    /// The direction step along `dirs` ([`Layout::joint_directions`]): the points and the
    /// scalars (side `σ` at index `σ`).
    pub(super) fn direction_step(
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
            .solve(&sc.entries, &mut sc.kkt, &mut sc.rhs)
            .map_err(kkt_error(self.path))?;
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

/// The tangent lengths `(‖P_p − P_a‖, ‖P_b − P_p‖)` of junction `j` in the points `x`.
pub(super) fn tangent_lengths(j: &TangentJunction, x: &[Point]) -> (f64, f64) {
    ((x[j.p] - x[j.a]).hypot(), (x[j.b] - x[j.p]).hypot())
}

/// `v / ‖v‖`, or `None` for a zero (or non-finite) vector.
pub(super) fn unit(v: Vec2) -> Option<Vec2> {
    let l = v.hypot();
    (l > 0.0 && l.is_finite()).then(|| v / l)
}

/// `R(θ) v`, counter-clockwise.
pub(super) fn rotate(v: Vec2, theta: f64) -> Vec2 {
    let (s, c) = theta.sin_cos();
    Vec2::new(c * v.x - s * v.y, s * v.x + c * v.y)
}

/// The ratio step's KKT entries `[H, Cᵀ; C, 0]` in a fixed order: the curves' Gram blocks,
/// the fixed rows, then two rows per junction of `varying` with `lengths(junction)`.
pub(super) fn ratio_entries(
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
pub(super) fn elimination_keys(
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

/// The flexible systems of path `pi`, or `None` if it has no flexible junction.
///
/// A G¹ or fixed-angle junction is flexible unless its tangents vanish or one of its
/// neighbours `a`, `b` is an on-curve point or appears in another junction's rows (then it
/// could not be replaced by a scalar; it keeps the input's ratio, as in the rig).
pub(super) fn flex_path(
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
    let ratio = LdltLu::new(n, &entries, &keys).map_err(kkt_error(pi))?;
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
    let direction = LdltLu::new(n, &entries, &keys).map_err(kkt_error(pi))?;
    let sigma = vec![1.0; layout.n_scalars()];
    let grad = vec![Vec2::new(1.0, 1.0); layout.n_scalars()];
    layout.direction_entries(nodes, &dirs, Some((&sigma, &grad)), &mut entries);
    let n_z = n_z + layout.flexible.len();
    let n = n_z + layout.fixed_rows.n_rows;
    let keys = elimination_keys(n, n_z, z_key, &entries);
    let newton = LdltLu::new(n, &entries, &keys).map_err(kkt_error(pi))?;
    Ok(Some(FlexPath {
        path: pi,
        layout,
        ratio,
        direction,
        newton,
    }))
}

/// The fit error of a failed KKT solve of path `path`: [`FitError::Singular`] for a solution
/// that is not finite, otherwise [`FitError::Solver`] with the stage and faer's report.
pub(super) fn kkt_error(path: usize) -> impl Fn(LinalgError) -> FitError {
    move |e| {
        if e.is_singular() {
            FitError::Singular { path }
        } else {
            FitError::Solver {
                path,
                detail: format!("flexible G1, {e}"),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::fixture::{case, g1_sine, pose, ratio};
    use super::super::options::FlexibleRule;
    use super::*;

    #[test]
    fn flex_path_makes_the_g1_neighbours_scalars() {
        let c = case(FlexibleRule::Newton, 1e-5, &pose(0.5));
        let layout = &c.solver.paths[0].layout;
        assert_eq!(layout.flexible.len(), 1);
        let j = &layout.flexible[0];
        assert_eq!((j.a, j.p, j.b), (2, 3, 4));
        // Seven unknown points, two of them now scalars along the junction point (free 2).
        assert_eq!(layout.n_free, 5);
        assert!(matches!(
            layout.slots[2],
            Slot::Along { base: 2, scalar: 0 }
        ));
        assert!(matches!(
            layout.slots[4],
            Slot::Along { base: 2, scalar: 1 }
        ));
        assert!(matches!(layout.slots[3], Slot::Free(2)));
        assert!(matches!(layout.slots[5], Slot::Free(3)));
    }

    #[test]
    fn ratio_step_at_the_fixed_ratio_fit_returns_it() {
        // The rig's result minimises E under the input's ratio, which the start has.
        let mut c = case(FlexibleRule::Newton, 1e-5, &pose(0.5));
        let fp = &c.solver.paths[0];
        let x = fp
            .ratio_step(&c.solver.nodes[0], &mut c.sc, &c.start)
            .unwrap();
        assert!((ratio(&c.start) - 2.0).abs() <= 1e-12);
        for (p, q) in x.iter().zip(&c.start) {
            assert!((*p - *q).hypot() <= 1e-12 * 10.0, "{p:?} vs {q:?}");
        }
    }

    #[test]
    fn direction_step_lowers_energy_and_keeps_g1() {
        let mut c = case(FlexibleRule::Newton, 1e-5, &pose(0.5));
        let fp = &c.solver.paths[0];
        let nodes = &c.solver.nodes[0];
        let mut dirs = vec![Vec2::ZERO; 2];
        fp.layout
            .joint_directions(&c.start, Sides::Derived, &mut dirs);
        // G¹: opposite unit directions.
        assert!((dirs[0] + dirs[1]).hypot() <= 1e-15 && (dirs[1].hypot() - 1.0).abs() <= 1e-15);
        let (x, scalars) = fp.direction_step(nodes, &mut c.sc, &dirs).unwrap();
        let e = nodes.energy(&c.sc.target, &x);
        assert!(e < c.e_start);
        assert!(g1_sine(&x) <= 1e-12);
        assert!((x[2] - x[3]).dot(dirs[0]) - scalars[0] <= 1e-12 * 10.0);
        assert!(((x[4] - x[3]).hypot() - scalars[1]).abs() <= 1e-12 * 10.0);
    }

    #[test]
    fn elimination_keys_put_each_row_after_its_unknowns() {
        // Unknowns keyed 0, 1, 2; row 3 uses unknowns 0 and 2, row 4 only unknown 1.
        let entries = [(3, 0, 1.0), (3, 2, 1.0), (4, 1, 1.0), (0, 3, 1.0)];
        let keys = elimination_keys(5, 3, |i| i as f64, &entries);
        assert_eq!(keys, vec![0.0, 1.0, 2.0, 2.5, 1.5]);
    }
}
