//! The fit system of one path: assembly of the KKT matrix and right-hand sides, one LU
//! factorisation (`crate::linalg::lu_solve_in_place`: dense for small paths, sparse
//! otherwise), and the solve for all `6h` right-hand sides.
//!
//! The energy of path `P` (Liu et al. 2014 §4; DESIGN.md §1) over its unknown chain points `x`
//! (two coordinates each, interleaved) is
//!
//! ```text
//! E(x) = Σ_j Σ_d  x_jdᵀ Â_j x_jd − 2 x_jdᵀ (Σ_i T_i Ŵ_ij)_d + const
//! Â_j  = ∫ b bᵀ dμ_j                       (4×4, curve j)
//! Ŵ_ij = C̄_j ∫ w_i(B_j(t)) b bᵀ dμ_j       (3×4, C̄_j the homogeneous input controls; weighted_integrals.rs)
//! ```
//!
//! with `x_jd` the four coordinates `d` of curve `j`. Minimising it subject to the junction rows
//! `C x = 0` ([`super::constraints`]) gives the KKT system
//!
//! ```text
//! [ H  Cᵀ ] [x]   [ B vec(T) ]
//! [ C  0  ] [λ] = [    0     ]      H = blocks of Â_j (per coordinate), B = 2m × 6h
//! ```
//!
//! `x = O vec(T)` with `O` the first `2m` rows of `K⁻¹ [B; 0]`: one factorisation, `6h` solves.
//! Column `6i + c` of `B` belongs to coefficient `c` of handle `i`'s affine map in SVG order
//! `(a, b, c, d, e, f)`, i.e. `T_i = [[a, c, e], [b, d, f]]`: entry `T[r][s]` is coefficient
//! `2s + r`.
//!
//! **Centring.** The right-hand sides use the path's coordinates about its own bounding-box
//! centre `o`: with `S` the homogeneous translation by `o`, `C̄ = S C̄_o`, so
//! `T_i Ŵ_ij = (T_i S) Ŵ^o_ij` and the operator solved with `C̄_o` acts on
//! `vec(T_i S) = (a, b, c, d, a o_x + c o_y + e, b o_x + d o_y + f)`, which is linear in
//! `vec(T_i)`; its columns are turned back once. The result is the same in exact arithmetic;
//! in floating point the solve then sees numbers of the path's own size, so a small path far
//! from the origin is fitted as accurately as the same path at the origin.
//!
//! **Groups.** Paths that share curves ([`super::shared_curves`]) are solved as one system
//! whose energy is the sum of the members' energies, each divided by the square of its own
//! size: `E = Σ_p (D / d_p)² E_p`, `d_p` the diagonal of member `p`'s control-point box and
//! `D` the group's largest. Each `E_p` counts all of the member's curves, so a shared curve
//! enters once per member that runs along it, with that member's factor. Summed in absolute
//! units, a small piece sharing its sides with long bars would be sacrificed to them: an
//! error of 2 % of a long bar is many times the piece's size. Relative to their sizes, every
//! member is fitted as well as it would be alone, as far as the shared curves allow. A lone
//! path (a single member) is unchanged: its curves once each.
//!
//! **Balance.** `H` and `B` are divided by the largest curve measure of the system (its
//! length, or squared length with arc length), so that `H`'s entries are of order one like the
//! constraint rows' (which are divided by their largest tangent length): the minimiser is the
//! same, and the KKT matrix's conditioning no longer depends on the drawing's size.

use faer::sparse::Triplet;
use faer::Mat;
use kurbo::{Point, Vec2};

use super::constraints::{junction_rows, push_pins, tangent_junctions, ConstraintRows};
use super::quadrature::SampledCurves;
use super::weighted_integrals::weighted_integral;
use super::{ConstraintForm, FitError, FitOptions};
use crate::drawing::Path;
use crate::linalg::lu_solve_in_place;

/// Relative size of the smallest singular value below which a path's system counts as rank
/// deficient (compatibility mode's check): 1e-12.
pub const RANK_TOLERANCE: f64 = 1e-12;

/// Largest KKT size for the dense rank check (the check is `O(N³)`): 4000.
pub const MAX_RANK_CHECK_SIZE: usize = 4000;

/// Which coefficients of the handles' maps the right-hand sides cover.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HandleMaps {
    /// Affine maps: `6h` columns, column `6i + c` coefficient `c` of handle `i` (SVG order).
    Affine,
    /// Translations only (the maps `[0 0 e; 0 0 f]`, the DefOp join): `2h` columns, column
    /// `2i + d` coordinate `d` of handle `i`'s translation (the affine columns `6i + 4 + d`).
    Translation,
}

/// The solved operator of one path.
pub struct PathOperator {
    /// `2m × 6h` (or `2m × 2h` for [`HandleMaps::Translation`]), column-major: rows are the
    /// unknowns (point `k`, coordinate `d` at `2k + d`).
    pub operator: Mat<f64>,
    /// Number of constraint rows used.
    pub n_constraints: usize,
    /// Whether the system was found rank deficient (only checked when asked).
    pub rank_deficient: bool,
}

/// A point of a path's curve held where the deformation takes the art under it: curve `curve`
/// (of the path) at parameter `t` must equal `Σ_i w_i T_i a`, with `a` the curve's rest point
/// there and `w_i` the weights at `a`. For translations (the deformation-operator join) that is
/// the deformed mesh interpolated at `a`, so a pin on a curve holds the art under it: the
/// curve passes through the pin at every configuration. Two rows per point (x and y) join the
/// junction rows of the KKT system ([`solve_path_with_points`]):
///
/// ```text
/// Σ_k b_k(t) x_{(3j+k), d} = Σ_i w_i (T_i ā)_d           ā = (a_x, a_y, 1) about the centre
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct PointConstraint {
    /// The curve, numbered within the path.
    pub curve: usize,
    /// The parameter on it, in `[0, 1]`.
    pub t: f64,
    /// The rest point `a` (the curve's point at `t`).
    pub point: Point,
    /// The non-zero weights at `a`: `(handle, w_i)`.
    pub weights: Vec<(usize, f64)>,
}

/// Assembles and solves the system of `path` (index `path_index`, for messages), whose first
/// curve is curve `first_curve` of `samples`, for the right-hand sides of `maps`.
pub fn solve_path(
    path_index: usize,
    path: &Path,
    samples: &SampledCurves,
    first_curve: usize,
    options: &FitOptions,
    maps: HandleMaps,
) -> Result<PathOperator, FitError> {
    solve_path_with_points(path_index, path, samples, first_curve, options, maps, &[])
}

/// [`solve_path`] with the path's curve points in `points` held by [`PointConstraint`]s
/// (independent of each other and of the junction rows: at most one per curve, none on an
/// anchor that another holds). A point-like path ignores them (it moves as one point).
pub fn solve_path_with_points(
    path_index: usize,
    path: &Path,
    samples: &SampledCurves,
    first_curve: usize,
    options: &FitOptions,
    maps: HandleMaps,
    points: &[PointConstraint],
) -> Result<PathOperator, FitError> {
    if is_point(&path.points) {
        let h = samples.n_handles();
        let n_x = 2 * path.n_unknown_points();
        return Ok(point_operator(
            path,
            samples.curve(first_curve),
            maps,
            n_x,
            h,
        ));
    }
    let member = GroupMember {
        index: path_index,
        path,
        first_curve,
        unknowns: (0..path.n_unknown_points()).collect(),
        copies: Vec::new(),
    };
    let n = path.n_unknown_points();
    let mut solved = solve_group(&[member], n, samples, options, maps, points)?;
    Ok(solved.pop().expect("one path, one operator"))
}

/// A path of a group solved as one system ([`solve_group`]).
pub(crate) struct GroupMember<'a> {
    /// Path index in the drawing (for messages).
    pub index: usize,
    /// The path.
    pub path: &'a Path,
    /// Index of its first curve in the samples.
    pub first_curve: usize,
    /// The group unknown of each of the path's unknown points.
    pub unknowns: Vec<usize>,
    /// Its curves that are copies of a curve fitted elsewhere in the group (their points are
    /// the original's unknowns; a lone path counts their energy once, a group's member counts
    /// them as its own: module doc, "Groups").
    pub copies: Vec<usize>,
}

/// Assembles and solves the system of a group of paths whose unknowns are shared as
/// `members[p].unknowns` says (`n_unknowns` points in all;
/// [`super::shared_curves`]): each curve's energy once, every member's junction rows over the
/// group's unknowns with dependent rows left out. Returns each member's operator.
pub(crate) fn solve_group(
    members: &[GroupMember<'_>],
    n_unknowns: usize,
    samples: &SampledCurves,
    options: &FitOptions,
    maps: HandleMaps,
    points: &[PointConstraint],
) -> Result<Vec<PathOperator>, FitError> {
    let h = samples.n_handles();
    let n_x = 2 * n_unknowns;
    let path_index = members[0].index;

    let rows = if members.len() == 1 && members[0].copies.is_empty() {
        let path = members[0].path;
        junction_rows(
            &path.points,
            path.closed,
            &path.joints,
            options.constraint_form,
            &options.junctions,
        )
    } else {
        group_rows(members, options)
    };
    // Held points ([`PointConstraint`]; lone paths only) after the junction rows, two each.
    let points = if members.len() == 1 { points } else { &[] };
    let n = n_x + rows.n_rows + 2 * points.len();

    let n_curves: usize = members.iter().map(|m| m.path.n_curves()).sum();
    let mut triplets: Vec<Triplet<usize, usize, f64>> =
        Vec::with_capacity(n_curves * 32 + 2 * rows.entries.len());
    // Homogeneous rows of C̄ kept (x, y, 1 or only 1) and the columns per handle.
    let per_handle = match maps {
        HandleMaps::Affine => 6,
        HandleMaps::Translation => 2,
    };
    let mut rhs = Mat::<f64>::zeros(n, per_handle * h);
    // The system is solved about the group's own centre `o` (module doc, "Centring").
    let o = centre(members.iter().flat_map(|m| m.path.points.iter().copied()));
    add_energy(members, samples, maps, o, &mut triplets, &mut rhs);
    for &(r, col, v) in &rows.entries {
        triplets.push(Triplet::new(n_x + r, col, v));
        triplets.push(Triplet::new(col, n_x + r, v));
    }
    if let [member] = members {
        add_held_points(
            member,
            points,
            maps,
            o,
            n_x + rows.n_rows,
            &mut triplets,
            &mut rhs,
        );
    }
    let rank_deficient = options.check_rank && is_rank_deficient(n, &triplets);
    lu_solve_in_place(n, &triplets, rhs.as_mut()).map_err(|e| FitError::Solver {
        path: path_index,
        detail: e.to_string(),
    })?;

    let mut operator = rhs.subrows(0, n_x).to_owned();
    // The group's rest points, about the centre (one per unknown).
    let rest = canonical_rest(members, n_unknowns, o);
    let mut mean_weights = None;
    if maps == HandleMaps::Affine {
        if options.constraint_form == ConstraintForm::Ours {
            mean_weights = reproduce_similarities(&mut operator, members, &rest, samples, &rows);
        }
        uncentre(&mut operator, o);
    }
    if !rank_deficient
        && operator
            .col_iter()
            .any(|c| c.iter().any(|v| !v.is_finite()))
    {
        return Err(FitError::Singular { path: path_index });
    }
    if let [member] = members {
        if member.unknowns.iter().enumerate().all(|(k, &u)| k == u) {
            return Ok(vec![PathOperator {
                operator,
                n_constraints: rows.n_rows,
                rank_deficient,
            }]);
        }
    }
    let shared = SharedOperator {
        operator: &operator,
        rest: &rest,
        o,
        mean_weights: mean_weights.as_deref(),
        n_constraints: rows.n_rows,
        rank_deficient,
    };
    Ok(members
        .iter()
        .enumerate()
        .map(|(g, member)| shared.member_operator(g, member))
        .collect())
}

/// Adds the members' fit energies to the system (module doc): each curve's Gram block to
/// `triplets` and its weighted integrals of the rest curve (about `o`) to `rhs`, each member
/// relative to its own size ("Groups") and all divided by the largest curve measure
/// ("Balance").
fn add_energy(
    members: &[GroupMember<'_>],
    samples: &SampledCurves,
    maps: HandleMaps,
    o: Vec2,
    triplets: &mut Vec<Triplet<usize, usize, f64>>,
    rhs: &mut Mat<f64>,
) {
    let (first_row, per_handle) = match maps {
        HandleMaps::Affine => (0, 6),
        HandleMaps::Translation => (2, 2),
    };
    let mut weighted = Vec::with_capacity(samples.n_handles());
    let scales = relative_scales(members);
    let largest_measure = members
        .iter()
        .zip(&scales)
        .flat_map(|(m, &s)| {
            (0..m.path.n_curves())
                .map(move |j| s * samples.curve(m.first_curve + j).omega.iter().sum::<f64>())
        })
        .fold(0.0, f64::max);
    let balance = if largest_measure > 0.0 {
        1.0 / largest_measure
    } else {
        1.0
    };
    for (member, &scale) in members.iter().zip(&scales) {
        let path = member.path;
        // A lone path counts each curve once (a curve it runs along twice, once); in a group
        // every member counts all of its curves, copies included, with its own scale.
        let skip_copies = members.len() == 1;
        let balance = balance * scale;
        let unknown = |chain_index: usize| member.unknowns[path.unknown_index(chain_index)];
        for j in 0..path.n_curves() {
            if skip_copies && member.copies.contains(&j) {
                continue;
            }
            let c = path.curve_points(j).map(|p| p - o);
            let nodes = samples.curve(member.first_curve + j);
            let a = nodes.gram();
            nodes.weighted_grams(&mut weighted);
            let idx = [0, 1, 2, 3].map(|k| unknown(3 * j + k));
            for (k, &pk) in idx.iter().enumerate() {
                for (l, &pl) in idx.iter().enumerate() {
                    for d in 0..2 {
                        triplets.push(Triplet::new(2 * pk + d, 2 * pl + d, balance * a[k][l]));
                    }
                }
            }
            for (i, mij) in weighted.iter().enumerate() {
                let w = weighted_integral(&c, mij);
                for (l, &pl) in idx.iter().enumerate() {
                    for (s, ws) in w.iter().enumerate().skip(first_row) {
                        for d in 0..2 {
                            rhs[(2 * pl + d, per_handle * i + 2 * (s - first_row) + d)] +=
                                balance * ws[l];
                        }
                    }
                }
            }
        }
    }
}

/// Adds the rows holding `points` on a lone path (`member`), two each from row `first`: the
/// curve's point at `t` equals the held point's skinned position.
fn add_held_points(
    member: &GroupMember<'_>,
    points: &[PointConstraint],
    maps: HandleMaps,
    o: Vec2,
    first: usize,
    triplets: &mut Vec<Triplet<usize, usize, f64>>,
    rhs: &mut Mat<f64>,
) {
    for (pi, held) in points.iter().enumerate() {
        let t = held.t;
        let s = 1.0 - t;
        let b = [s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t];
        let a = held.point - o;
        for d in 0..2 {
            let row = first + 2 * pi + d;
            for (k, bk) in b.iter().enumerate() {
                let col = 2 * member.unknowns[member.path.unknown_index(3 * held.curve + k)] + d;
                triplets.push(Triplet::new(row, col, *bk));
                triplets.push(Triplet::new(col, row, *bk));
            }
            for &(i, w) in &held.weights {
                match maps {
                    HandleMaps::Translation => rhs[(row, 2 * i + d)] += w,
                    HandleMaps::Affine => {
                        rhs[(row, 6 * i + d)] += w * a.x;
                        rhs[(row, 6 * i + 2 + d)] += w * a.y;
                        rhs[(row, 6 * i + 4 + d)] += w;
                    }
                }
            }
        }
    }
}

/// A group's solved operator over its shared unknowns, to be split into its members' own.
struct SharedOperator<'a> {
    operator: &'a Mat<f64>,
    /// The canonical rest points about `o`, one per unknown.
    rest: &'a [Vec2],
    o: Vec2,
    /// The handles' mean weights over the group (affine maps, our constraint form).
    mean_weights: Option<&'a [f64]>,
    n_constraints: usize,
    rank_deficient: bool,
}

impl SharedOperator<'_> {
    /// Member `g`'s operator: the rows of its unknowns, its copies' offsets carried.
    fn member_operator(&self, g: usize, member: &GroupMember<'_>) -> PathOperator {
        let operator = self.operator;
        let mut own = Mat::<f64>::zeros(2 * member.unknowns.len(), operator.ncols());
        for (k, &u) in member.unknowns.iter().enumerate() {
            for d in 0..2 {
                for c in 0..operator.ncols() {
                    own[(2 * k + d, c)] = operator[(2 * u + d, c)];
                }
            }
            // A copy's point differs from the canonical one by δ (within the sharing
            // tolerance): it follows as the canonical point plus δ under the handles' linear
            // parts averaged by their mean weights, Σ_i ω_i L_i δ, so that the identity and
            // similarities reproduce the copy's own input while the deformed copies stay within
            // |L δ| of each other.
            let delta = member.path.points[k] - (self.rest[u] + self.o).to_point();
            if let Some(mean) = self.mean_weights {
                if delta != Vec2::ZERO {
                    for (i, &m) in mean.iter().enumerate() {
                        own[(2 * k, 6 * i)] += m * delta.x;
                        own[(2 * k, 6 * i + 2)] += m * delta.y;
                        own[(2 * k + 1, 6 * i + 1)] += m * delta.x;
                        own[(2 * k + 1, 6 * i + 3)] += m * delta.y;
                    }
                }
            }
        }
        PathOperator {
            operator: own,
            // The group's rows are counted once, with its first path.
            n_constraints: if g == 0 { self.n_constraints } else { 0 },
            rank_deficient: self.rank_deficient,
        }
    }
}

/// The factor `s_p = (D / d_p)²` by which member `p`'s energy is multiplied in a group
/// ([`solve_group`]; module doc, "Groups"): `d_p` the diagonal of the member's control-point
/// box, `D` the largest of the group (so every factor is at least one). A member with no
/// extent (a dot) gets the factor of the smallest member that has one, or one.
fn relative_scales(members: &[GroupMember<'_>]) -> Vec<f64> {
    if members.len() == 1 {
        return vec![1.0];
    }
    let diagonals: Vec<f64> = members
        .iter()
        .map(|m| {
            let (lo, hi) = m.path.points.iter().fold(
                (Vec2::new(f64::MAX, f64::MAX), Vec2::new(f64::MIN, f64::MIN)),
                |(lo, hi), p| {
                    (
                        Vec2::new(lo.x.min(p.x), lo.y.min(p.y)),
                        Vec2::new(hi.x.max(p.x), hi.y.max(p.y)),
                    )
                },
            );
            (hi - lo).hypot()
        })
        .collect();
    let largest = diagonals.iter().copied().fold(0.0, f64::max);
    let smallest = diagonals
        .iter()
        .copied()
        .filter(|&d| d > 0.0)
        .fold(largest, f64::min);
    diagonals
        .iter()
        .map(|&d| {
            let d = if d > 0.0 { d } else { smallest };
            if d > 0.0 {
                (largest / d).powi(2)
            } else {
                1.0
            }
        })
        .collect()
}

/// The junction rows of a group ([`solve_group`]): every member's junctions over the group's
/// unknowns, except those whose two tangent neighbours are already related at the same
/// junction point by junctions written before (from any path of the group), then rows that
/// follow from others left out.
///
/// Each junction relates its two tangents at the point by a similarity (`v' = (l_v/l_u)
/// R(θ) u'`). Where paths meet at a shared point, their junctions form a graph on the
/// point's tangent neighbours, and a cycle in it (a junction met again through a shared curve,
/// or a circle's smooth point that is also the corner of a half disc on each side: arc–arc,
/// arc–side, side–arc) relates a tangent to itself by the product of the cycle's
/// similarities. In one geometry that product is the identity and the cycle's last junction
/// follows from the others; but each path's rows use its own copy of the shared curves, equal
/// only to [`super::shared_curves::SHARED_CURVE_TOLERANCE`], and two kinds may differ (strict
/// C¹ in one path, G¹ with the input's near-1 ratio in another): the product is then off the
/// identity by about that tolerance, the rows count as independent, and together they force
/// the tangents to vanish (OpenMoji's half moons grouped with their circle collapsed by 31
/// units). So each point keeps a spanning forest of its junctions, in path order (the first
/// path's kind rules); the junction left out holds to the sharing tolerance.
fn group_rows(members: &[GroupMember<'_>], options: &FitOptions) -> ConstraintRows {
    let mut rows = ConstraintRows::default();
    // Per junction point, a union-find over the tangent neighbours already related there.
    let mut related: std::collections::HashMap<(usize, usize), (usize, usize)> =
        std::collections::HashMap::new();
    fn find(
        related: &mut std::collections::HashMap<(usize, usize), (usize, usize)>,
        mut key: (usize, usize),
    ) -> (usize, usize) {
        while let Some(&up) = related.get(&key) {
            if up == key {
                break;
            }
            key = up;
        }
        key
    }
    for member in members {
        let path = member.path;
        for mut t in tangent_junctions(
            &path.points,
            path.closed,
            &path.joints,
            options.constraint_form,
            &options.junctions,
        ) {
            if t.vanishes() {
                continue;
            }
            let map = |i: usize| member.unknowns[i];
            t.a = map(t.a);
            t.p = map(t.p);
            t.b = map(t.b);
            for q in &mut t.pins {
                *q = map(*q);
            }
            let (ra, rb) = (
                find(&mut related, (t.p, t.a)),
                find(&mut related, (t.p, t.b)),
            );
            if ra == rb {
                continue;
            }
            related.insert(ra, ra);
            related.insert(rb, ra);
            for row in t.rows(t.lengths) {
                rows.push_row(&row);
            }
            push_pins(&mut rows, &t);
        }
    }
    rows.independent().0
}

/// Whether every point of the chain is the same point, to rounding: its bounding box is
/// within 4 ulps of its coordinates' magnitude (a zero-length subpath such as `M4,5 L4,5 Z`,
/// or a `<line>` with equal ends, which round caps draw as a dot).
fn is_point(points: &[Point]) -> bool {
    let o = centre(points.iter().copied());
    let magnitude = o.x.abs().max(o.y.abs());
    points
        .iter()
        .all(|p| (*p - o.to_point()).hypot() <= 4.0 * f64::EPSILON * magnitude)
}

/// The operator of a path that is a single point `p` (see [`is_point`]): it has no length, so
/// no energy to fit, and every chain point follows the skinning map at `p`,
/// `p' = Σ_i w_i(p) T_i p̄` (the limit of the fit of a curve shrinking to `p`). The weights are
/// those sampled at the first quadrature node (every node is at `p`).
fn point_operator(
    path: &Path,
    nodes: super::quadrature::CurveNodes<'_>,
    maps: HandleMaps,
    n_x: usize,
    h: usize,
) -> PathOperator {
    let p = path.points[0];
    let w = &nodes.weights[..h];
    let per_handle = match maps {
        HandleMaps::Affine => 6,
        HandleMaps::Translation => 2,
    };
    let mut operator = Mat::<f64>::zeros(n_x, per_handle * h);
    for r in 0..n_x {
        let d = r % 2;
        for (i, &wi) in w.iter().enumerate() {
            match maps {
                // x' = Σ w_i (a x + c y + e), y' = Σ w_i (b x + d y + f).
                HandleMaps::Affine => {
                    operator[(r, 6 * i + d)] = wi * p.x;
                    operator[(r, 6 * i + 2 + d)] = wi * p.y;
                    operator[(r, 6 * i + 4 + d)] = wi;
                }
                HandleMaps::Translation => operator[(r, 2 * i + d)] = wi,
            }
        }
    }
    PathOperator {
        operator,
        n_constraints: 0,
        rank_deficient: false,
    }
}

/// The centre of the bounding box of `points` (at least one).
pub(crate) fn centre(points: impl IntoIterator<Item = Point>) -> Vec2 {
    let mut points = points.into_iter();
    let first = points.next().expect("a chain has points");
    let (mut lo, mut hi) = (first, first);
    for p in points {
        lo = Point::new(lo.x.min(p.x), lo.y.min(p.y));
        hi = Point::new(hi.x.max(p.x), hi.y.max(p.y));
    }
    lo.midpoint(hi).to_vec2()
}

/// How far from one the handle weights at a quadrature node may sum for the fit to treat them
/// as a partition of unity (`reproduce_similarities`): 1e-12, a few ulps of a normalised sum
/// (as the subdivision rig's own tolerance).
pub const PARTITION_TOLERANCE: f64 = 1e-12;

/// Largest residual of a junction row at the rest points, relative to the diagonal of the
/// system's rest points, for the rest chain to count as satisfying its rows
/// (`reproduce_similarities`): 1e-8 (junctions are classified C¹ when the input is C¹ to
/// 1e-9 relative, [`crate::drawing::junction::DEFAULT_C1_RATIO`]).
pub const REST_RESIDUAL_TOLERANCE: f64 = 1e-8;

/// A direction of the map coefficients `(a, b, c, d, e, f)` and the image of a centred rest
/// point under the map it is.
type SimilarityDirection = ([f64; 6], fn(Vec2) -> Vec2);

/// Makes the similarity part of a group's operator `O` (solved about the centre `o`, before
/// [`uncentre`]) exact: one similarity on every handle gives exactly that similarity of the
/// rest points.
///
/// Where the weights are a partition of unity, one map `S` on every handle makes the skinned
/// target `S B_j(t)`; for a similarity `S` (rotation, uniform scale, translation) that is a
/// chain satisfying every junction row of our form (the rows `l_u v' − l_v R(θ) u' = 0` and the
/// pins are invariant under similarities), so the minimiser is `S x₀` exactly: `Σ_i O_i vec(S)
/// = vec(S x₀)`. The solve only gives that to `cond(K) · ε`, and [`uncentre`] multiplies the
/// translation columns' defect by `|o|`: a path of size 1e-4 at (40, 27) missed its own
/// position at the identity pose by 1e-4 of its size. Here the defect `r_s = S_s c − Σ_i O_i s`
/// of each of the four similarity directions `s` of the centred maps (`c` the centred rest
/// points; `s` = `a = d = 1` scale, `b = −c = 1` quarter turn, `e = 1`, `f = 1` translations)
/// is handed back to the handles in proportion to their mean weights `ω_i` over the group's
/// curves (`Σ_i ω_i = 1`), `O_i += ω_i r_s sᵀ / |s|²`: the other two directions of the maps
/// (shears) are untouched, and the change is of the size of the defect. Weights that are not
/// a partition of unity to [`PARTITION_TOLERANCE`] at every node leave `O` as solved (there the
/// fit does not reproduce similarities anyway). The rows are differences of points, so every
/// chain's translations satisfy them; rotations and scalings of the rest chain satisfy them
/// only when the rest chain does (not where a junction kind the input does not have was
/// imposed, e.g. a scene's override making a corner C¹): then only the translations are made
/// exact (to [`REST_RESIDUAL_TOLERANCE`]).
fn reproduce_similarities(
    operator: &mut Mat<f64>,
    members: &[GroupMember<'_>],
    rest: &[Vec2],
    samples: &SampledCurves,
    rows: &ConstraintRows,
) -> Option<Vec<f64>> {
    let h = samples.n_handles();
    let mut mean = vec![0.0; h];
    let mut total = 0.0;
    for member in members {
        let path = member.path;
        for j in 0..path.n_curves() {
            let nodes = samples.curve(member.first_curve + j);
            for (q, &omega) in nodes.omega.iter().enumerate() {
                let w = &nodes.weights[q * h..][..h];
                if (w.iter().sum::<f64>() - 1.0).abs() > PARTITION_TOLERANCE {
                    return None;
                }
                total += omega;
                for (m, wi) in mean.iter_mut().zip(w) {
                    *m += omega * wi;
                }
            }
        }
    }
    if total <= 0.0 {
        return None;
    }
    let sum: f64 = mean.iter().sum();
    for m in &mut mean {
        *m /= sum;
    }
    // Does the rest chain satisfy the rows (not where a junction kind was imposed that the
    // input does not have)? Rows are differences, so translations always do.
    let mut residual = vec![0.0; rows.n_rows];
    for &(r, col, v) in &rows.entries {
        residual[r] += v * if col % 2 == 0 {
            rest[col / 2].x
        } else {
            rest[col / 2].y
        };
    }
    let (lo, hi) = rest.iter().fold(
        (Vec2::new(f64::MAX, f64::MAX), Vec2::new(f64::MIN, f64::MIN)),
        |(lo, hi), c| {
            (
                Vec2::new(lo.x.min(c.x), lo.y.min(c.y)),
                Vec2::new(hi.x.max(c.x), hi.y.max(c.y)),
            )
        },
    );
    // A group's rows are each written on its own path's copy of the shared curves, which
    // the canonical rest points match only to the sharing tolerance.
    let relative = if members.len() > 1 || !members[0].copies.is_empty() {
        REST_RESIDUAL_TOLERANCE.max(10.0 * super::shared_curves::SHARED_CURVE_TOLERANCE)
    } else {
        REST_RESIDUAL_TOLERANCE
    };
    let tolerance = relative * (hi - lo).hypot();
    let rest_satisfies = residual.iter().all(|r| r.abs() <= tolerance);
    // The four similarity directions of the map coefficients (a, b, c, d, e, f), and the
    // image of a centred rest point c under each: scale c, quarter turn (−c_y, c_x), e, f.
    let directions: [SimilarityDirection; 4] = [
        ([1.0, 0.0, 0.0, 1.0, 0.0, 0.0], |c| c),
        ([0.0, 1.0, -1.0, 0.0, 0.0, 0.0], |c| Vec2::new(-c.y, c.x)),
        ([0.0, 0.0, 0.0, 0.0, 1.0, 0.0], |_| Vec2::new(1.0, 0.0)),
        ([0.0, 0.0, 0.0, 0.0, 0.0, 1.0], |_| Vec2::new(0.0, 1.0)),
    ];
    let first = if rest_satisfies { 0 } else { 2 };
    for &(s, image) in &directions[first..] {
        let norm2: f64 = s.iter().map(|v| v * v).sum();
        for (u, &c) in rest.iter().enumerate() {
            let want = image(c);
            for (d, want) in [want.x, want.y].into_iter().enumerate() {
                let r = 2 * u + d;
                let mut got = 0.0;
                for i in 0..h {
                    for (k, &sk) in s.iter().enumerate() {
                        got += sk * operator[(r, 6 * i + k)];
                    }
                }
                let defect = want - got;
                for (i, &m) in mean.iter().enumerate() {
                    for (k, &sk) in s.iter().enumerate() {
                        if sk != 0.0 {
                            operator[(r, 6 * i + k)] += m * defect * sk / norm2;
                        }
                    }
                }
            }
        }
    }
    Some(mean)
}

/// The rest position of each of a group's unknowns about `o`: the first member's point
/// written to it (a shared curve's original comes before its copies).
fn canonical_rest(members: &[GroupMember<'_>], n_unknowns: usize, o: Vec2) -> Vec<Vec2> {
    let mut rest = vec![None; n_unknowns];
    for member in members {
        for (k, &u) in member.unknowns.iter().enumerate() {
            rest[u].get_or_insert(member.path.points[k] - o.to_point());
        }
    }
    rest.into_iter()
        .map(|r| r.expect("every unknown is some member's point"))
        .collect()
}

/// Turns the columns of an operator solved for maps of centred coordinates into columns for
/// the maps themselves: `vec(T S) = M vec(T)` with `S` the translation by `o` (module doc), so
/// column `a` gains `o_x` times column `e`, `c` gains `o_y` times `e`, `b` and `d` the same
/// of `f`.
fn uncentre(operator: &mut Mat<f64>, o: Vec2) {
    for i in 0..operator.ncols() / 6 {
        let base = 6 * i;
        for r in 0..operator.nrows() {
            let (e, f) = (operator[(r, base + 4)], operator[(r, base + 5)]);
            operator[(r, base)] += o.x * e;
            operator[(r, base + 2)] += o.y * e;
            operator[(r, base + 1)] += o.x * f;
            operator[(r, base + 3)] += o.y * f;
        }
    }
}

/// Whether the (small) `n × n` matrix with `entries` is numerically singular: smallest
/// singular value below [`RANK_TOLERANCE`] times the largest. Matrices larger than
/// [`MAX_RANK_CHECK_SIZE`] are not checked (reported as full rank).
fn is_rank_deficient(n: usize, entries: &[Triplet<usize, usize, f64>]) -> bool {
    if n > MAX_RANK_CHECK_SIZE {
        tracing::warn!("rank check skipped for a system of size {n}");
        return false;
    }
    // Entries out of range are reported by the solve that follows.
    let Ok(dense) = crate::linalg::lu::dense(n, entries) else {
        return false;
    };
    match dense.singular_values() {
        Ok(s) => {
            let max = s.iter().cloned().fold(0.0, f64::max);
            let min = s.iter().cloned().fold(f64::INFINITY, f64::min);
            min <= RANK_TOLERANCE * max
        }
        Err(_) => true,
    }
}
