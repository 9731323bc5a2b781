//! The join of a deformation operator with the spline fit (`defop::DefOpRig`, issue 7 item 6)
//! on the bundled fish and its five point handles: the rest configuration gives the drawing
//! back, the join equals the spline fit of the operator's deformed mesh, every junction
//! constraint holds after deformation, per-frame updates allocate nothing, and against the
//! ground truth (ARAP, symmetric ARAP) on held-out configurations the joined curves are close
//! and closer than simpler deformations.

#[path = "common/alloc_checks.rs"]
mod alloc_checks;
#[path = "common/defop_data.rs"]
mod defop_data;
#[path = "common/measure.rs"]
mod measure;

use alloc_checks::{assert_counter_counts, assert_refusals_allocate_nothing};
use defop_data::{arap_solutions, rest_and_disc_samples};
use measure::max_distance;
use std::sync::OnceLock;
use std::time::Instant;

use counting_alloc::{count, Counts};
use kurbo::{Affine, CubicBez, ParamCurve, ParamCurveNearest, Point, Vec2};
use splineskin::defop::{
    flipped_triangles, train, training_domain_options, Arap, ArapOptions, DefOp, DefOpError,
    DefOpOptions, DefOpRig, EigenOperator, Energy, HandleBasisKind, MeshMap, SampleRegion, Sampler,
    SarapOptions, SpatialBasis, SplineJoin, SymmetricArap, TrainOptions, Training,
    DEFAULT_DISC_FRACTION, PIN_SNAP_FRACTION,
};
use splineskin::domain::{Domain, DomainOptions, MeshWeights};
use splineskin::drawing::{read_svg, Drawing, ImportOptions, JointKind, JunctionOptions};
use splineskin::examples::{demo_scene, DEMO_SVG};
use splineskin::mesh::TriMesh;
use splineskin::metrics::{chain_metrics, MetricsOptions};
use splineskin::spline_fit::{FitOptions, SplineRig};
use splineskin::weights::{Shepard, ShepardOptions};

/// Training samples besides the rest configuration: small enough for the dev profile.
const N_TRAINING_SAMPLES: usize = 80;
/// Held-out configurations of the accuracy test.
const N_HELD_OUT: usize = 8;
/// Random configurations of the exactness tests.
const N_RANDOM: usize = 4;

struct Fish {
    drawing: Drawing,
    handles: Vec<Point>,
    domain: Domain,
}

fn fish() -> &'static Fish {
    static FISH: OnceLock<Fish> = OnceLock::new();
    FISH.get_or_init(|| {
        let drawing = read_svg(DEMO_SVG, &ImportOptions::default()).expect("demo svg");
        let handles = demo_scene().handles;
        let domain =
            Domain::build(&drawing, &handles, &[], &training_domain_options()).expect("domain");
        Fish {
            drawing,
            handles,
            domain,
        }
    })
}

fn mesh_diagonal(mesh: &TriMesh) -> f64 {
    let r = mesh.vertices.iter().fold(
        kurbo::Rect::from_points(mesh.vertices[0], mesh.vertices[0]),
        |r, &p| r.union_pt(p),
    );
    r.width().hypot(r.height())
}

/// Sample disc radius: the training's default.
fn radius() -> f64 {
    DEFAULT_DISC_FRACTION * mesh_diagonal(&fish().domain.mesh)
}

fn trained(energy: Energy) -> &'static Training {
    static SARAP: OnceLock<Training> = OnceLock::new();
    static ARAP: OnceLock<Training> = OnceLock::new();
    let cell = match energy {
        Energy::Arap => &ARAP,
        Energy::SymmetricArap => &SARAP,
    };
    cell.get_or_init(|| {
        let f = fish();
        let spatial = SpatialBasis::hats(&f.domain.mesh).unwrap();
        let options = TrainOptions::default()
            .with_energy(energy)
            .with_n_samples(N_TRAINING_SAMPLES);
        let clock = Instant::now();
        let training = train(
            &f.domain.mesh,
            &f.domain.handle_vertices,
            &spatial,
            &options,
            &|_| {},
        )
        .expect("training");
        eprintln!(
            "fish {energy:?}: {} vertices, {} triangles, {N_TRAINING_SAMPLES} samples trained in {:.1} s",
            f.domain.mesh.n_vertices(),
            f.domain.mesh.n_triangles(),
            clock.elapsed().as_secs_f64()
        );
        training
    })
}

/// A coarse fish domain with a reduced spatial basis (linearly precise Laplacian
/// eigenfunctions) fitted to ARAP solutions: the join's `Dᵀ` path.
fn reduced() -> &'static (Domain, DefOp) {
    static REDUCED: OnceLock<(Domain, DefOp)> = OnceLock::new();
    REDUCED.get_or_init(|| {
        let f = fish();
        let options = DomainOptions::default()
            .with_samples_per_diagonal(30.0)
            .with_max_area_fraction(1.0 / 150.0);
        let domain = Domain::build(&f.drawing, &f.handles, &[], &options).unwrap();
        let mesh = &domain.mesh;
        let spatial =
            SpatialBasis::laplacian_eigenfunctions(mesh, 40, EigenOperator::LinearlyPrecise)
                .unwrap();
        let arap = Arap::new(mesh, &domain.handle_vertices, ArapOptions::default()).unwrap();
        let configurations = rest_and_disc_samples(&f.handles, radius(), 3, 24);
        let solutions = arap_solutions(&arap, mesh, &configurations);
        let op = DefOp::fit(
            mesh,
            &domain.handle_vertices,
            &spatial,
            &configurations,
            &solutions,
            &DefOpOptions::default(),
        )
        .unwrap();
        (domain, op)
    })
}

fn configurations_in_discs(rest: &[Point], radius: f64, seed: u64, n: usize) -> Vec<Vec<Point>> {
    Sampler::new(rest, &[(SampleRegion::Disc { radius }, 1.0)], seed)
        .unwrap()
        .configurations(n)
}

/// The spline fit (an independent `SplineRig`) of the mesh `positions` interpolated linearly
/// in the triangles of `mesh` along the curves: two "handles" whose weights are the x and y
/// coordinates of the vertices, and maps that are the unit translations.
fn fit_of_mesh(
    drawing: &Drawing,
    mesh: &TriMesh,
    positions: &[Point],
    options: &FitOptions,
) -> Vec<Point> {
    let (field, pose) = mesh_target(mesh, positions);
    let rig = SplineRig::precompute(drawing, &field, options).unwrap();
    let mut out = vec![Point::ZERO; rig.n_points()];
    rig.update(&pose, &mut out).unwrap();
    out
}

/// The target "positions interpolated on the mesh" as a weight field and pose: weights x and
/// y of the vertices, maps the unit translations, so that `Σ w_i T_i x̄ = position(x)`.
fn mesh_target(mesh: &TriMesh, positions: &[Point]) -> (MeshWeights, [Affine; 2]) {
    let w: Vec<f64> = positions.iter().flat_map(|p| [p.x, p.y]).collect();
    let field = MeshWeights::new(mesh, w, 2).unwrap();
    let pose = [
        Affine::new([0.0, 0.0, 0.0, 0.0, 1.0, 0.0]),
        Affine::new([0.0, 0.0, 0.0, 0.0, 0.0, 1.0]),
    ];
    (field, pose)
}

#[test]
fn join_rest_configuration_reproduces_the_drawing() {
    let f = fish();
    let diag = f.drawing.diagonal();
    let input = f.drawing.flat_points();
    let training = trained(Energy::SymmetricArap);
    let rig =
        DefOpRig::from_domain(&f.drawing, &f.domain, &training.op, &FitOptions::default()).unwrap();
    assert_eq!(rig.n_nodes_outside(), 0, "the fish lies in its domain");
    let hats = max_distance(&rig.deform(&f.handles).unwrap(), &input) / diag;
    let (domain, op) = reduced();
    let rig = DefOpRig::from_domain(&f.drawing, domain, op, &FitOptions::default()).unwrap();
    let eigen = max_distance(&rig.deform(&f.handles).unwrap(), &input) / diag;
    eprintln!("rest configuration: largest distance to the input / diagonal: hats + TPS {hats:.1e}, 40 eigenfunctions + TPS {eigen:.1e}");
    // Rounding of the fit (a sparse LU per path), of G's fit and of the 2 000-term products.
    assert!(hats < 1e-12, "{hats:e}");
    assert!(eigen < 1e-12, "{eigen:e}");
}

#[test]
fn join_equals_the_fit_of_the_deformed_mesh() {
    let f = fish();
    let diag = f.drawing.diagonal();
    let training = trained(Energy::SymmetricArap);
    let (domain, op) = reduced();
    // The default fit, and the paper authors' discretisation (midpoint rule over samples,
    // arc-length measure, their constraint rows): the join follows the fit's options.
    let cases: [(&str, &Domain, &DefOp, FitOptions); 3] = [
        ("hats", &f.domain, &training.op, FitOptions::default()),
        ("eigenfunctions", domain, op, FitOptions::default()),
        (
            "hats, authors' rule",
            &f.domain,
            &training.op,
            FitOptions::vectorskinning(true),
        ),
    ];
    for (name, domain, op, options) in cases {
        let clock = Instant::now();
        // Without pins (they constrain the fit where they hold the art: tested below).
        let rig = SplineJoin::new(&f.drawing, &domain.mesh, &[], &options)
            .unwrap()
            .rig(op)
            .unwrap();
        eprintln!(
            "{name}: precompute {:.3} s (dev profile)",
            clock.elapsed().as_secs_f64()
        );
        let mut worst: f64 = 0.0;
        for q in configurations_in_discs(&f.handles, 2.0 * radius(), 11, N_RANDOM) {
            let positions = op.eval(&q).unwrap();
            let want = fit_of_mesh(&f.drawing, &domain.mesh, &positions, &options);
            let got = rig.deform(&q).unwrap();
            worst = worst.max(max_distance(&got, &want) / diag);
            // Not the rest drawing: the configurations move the handles.
            assert!(max_distance(&got, &f.drawing.flat_points()) / diag > 1e-3);
        }
        eprintln!(
            "{name}: join vs fit of the deformed mesh, largest distance / diagonal {worst:.1e}"
        );
        assert!(worst < 1e-10, "{name}: {worst:e}");
        // Paths joined on rayon's pool give the same operator, bit for bit.
        let parallel = SplineJoin::new(&f.drawing, &domain.mesh, &[], &options.with_parallel(true))
            .unwrap()
            .rig(op)
            .unwrap();
        assert_eq!(parallel.coefficients(), rig.coefficients(), "{name}");
    }
}

/// The curve point nearest `p`: (path, curve, t, point, distance).
fn nearest_curve_point(drawing: &Drawing, p: Point) -> (usize, usize, f64, Point, f64) {
    let mut best = (0, 0, 0.0, p, f64::INFINITY);
    for (pi, path) in drawing.paths.iter().enumerate() {
        for j in 0..path.n_curves() {
            let [a, b, c, d] = path.curve_points(j);
            let curve = CubicBez::new(a, b, c, d);
            let n = curve.nearest(p, 1e-13);
            if n.distance_sq.sqrt() < best.4 {
                best = (pi, j, n.t, curve.eval(n.t), n.distance_sq.sqrt());
            }
        }
    }
    best
}

/// A pin holds the art under it (the join's side of Proposition 1): with the fish's pins moved
/// onto their nearest curve point, the curve passes through each pin at every configuration
/// (the deformed mesh there), where the unconstrained least-squares fit lets it slide; pins
/// off the art hold nothing; the rest configuration still gives the drawing back.
#[test]
fn pins_hold_the_art_under_them() {
    let f = fish();
    let diag = f.drawing.diagonal();
    let options = FitOptions::default();
    let under: Vec<_> = f
        .handles
        .iter()
        .map(|&h| nearest_curve_point(&f.drawing, h))
        .collect();
    let on_art: Vec<Point> = under.iter().map(|u| u.3).collect();
    let domain = Domain::build(&f.drawing, &on_art, &[], &training_domain_options()).unwrap();
    let mesh = &domain.mesh;
    // The scene's own pins are inside the fish's fills (1.8 to 18 units from a curve).
    let snap = PIN_SNAP_FRACTION * mesh.bounding_box_diagonal();
    assert!(
        under.iter().all(|u| u.4 > snap),
        "{:?}",
        under.iter().map(|u| u.4).collect::<Vec<_>>()
    );
    assert_eq!(
        SplineJoin::new(&f.drawing, mesh, &f.handles, &options)
            .unwrap()
            .n_held(),
        0
    );
    let train_options = TrainOptions::default()
        .with_energy(Energy::Arap)
        .with_n_samples(20)
        .with_regions(vec![(SampleRegion::Disc { radius: radius() }, 1.0)]);
    let spatial = SpatialBasis::hats(mesh).unwrap();
    let training = train(
        mesh,
        &domain.handle_vertices,
        &spatial,
        &train_options,
        &|_| {},
    )
    .unwrap();
    let join = SplineJoin::new(&f.drawing, mesh, &on_art, &options).unwrap();
    assert_eq!(join.n_held(), on_art.len());
    let pinned = join.rig(&training.op).unwrap();
    // DefOpRig::precompute pins the operator's handles.
    let direct = DefOpRig::from_domain(&f.drawing, &domain, &training.op, &options).unwrap();
    assert_eq!(direct.coefficients(), pinned.coefficients());
    let free = SplineJoin::new(&f.drawing, mesh, &[], &options)
        .unwrap()
        .rig(&training.op)
        .unwrap();
    let art = |points: &[Point], (pi, j, t): (usize, usize, f64)| {
        let first = f.drawing.path_ranges().nth(pi).unwrap().start + 3 * j;
        CubicBez::new(
            points[first],
            points[first + 1],
            points[first + 2],
            points[first + 3],
        )
        .eval(t)
    };
    let back = max_distance(&pinned.deform(&on_art).unwrap(), &f.drawing.flat_points()) / diag;
    assert!(back < 1e-12, "rest: {back:e}");
    let (mut worst_pinned, mut worst_free, mut worst_map): (f64, f64, f64) = (0.0, 0.0, 0.0);
    for q in configurations_in_discs(&on_art, 3.0 * radius(), 5, N_RANDOM) {
        let map = MeshMap::from_operator(mesh, &training.op, &q).unwrap();
        let (with, without) = (pinned.deform(&q).unwrap(), free.deform(&q).unwrap());
        for (u, &target) in under.iter().zip(&q) {
            let at = (u.0, u.1, u.2);
            worst_pinned = worst_pinned.max((art(&with, at) - target).hypot() / diag);
            worst_free = worst_free.max((art(&without, at) - target).hypot() / diag);
            worst_map = worst_map.max((map.apply(u.3) - target).hypot() / diag);
        }
    }
    eprintln!(
        "fish, pins on the curves: the art under a pin vs the pin, largest / diagonal: pinned {worst_pinned:.1e}, unpinned {worst_free:.1e} (the operator's mesh there {worst_map:.1e})"
    );
    assert!(
        worst_map < 1e-9,
        "the operator interpolates its handles: {worst_map:e}"
    );
    assert!(worst_pinned < 1e-9, "pinned: {worst_pinned:e}");
    assert!(worst_free > 1e-5, "unpinned: {worst_free:e}");
}

/// Signed angle from `u` to `v`.
fn signed_angle(u: Vec2, v: Vec2) -> f64 {
    u.cross(v).atan2(u.dot(v))
}

/// The tangent neighbours of joint `p` (chain index) in our form: the first point on each
/// side farther than `eps` from it (`None` at an open end or a fully degenerate side).
fn neighbours(points: &[Point], closed: bool, p: usize, eps: f64) -> Option<(usize, usize)> {
    let m = points.len() - 1;
    if !closed && (p == 0 || p == m) {
        return None;
    }
    let back = if p == 0 { m } else { p };
    let fwd = if p == m { 0 } else { p };
    let a = (1..=3)
        .map(|k| back - k)
        .find(|&i| (points[i] - points[p]).hypot() > eps)?;
    let b = (1..=3)
        .map(|k| fwd + k)
        .find(|&i| (points[i] - points[p]).hypot() > eps)?;
    Some((a, b))
}

#[test]
fn join_keeps_every_junction_constraint() {
    let f = fish();
    let diag = f.drawing.diagonal();
    let options = JunctionOptions::default();
    let training = trained(Energy::SymmetricArap);
    let rig =
        DefOpRig::from_domain(&f.drawing, &f.domain, &training.op, &FitOptions::default()).unwrap();
    let (mut c1, mut g1_angle, mut g1_ratio, mut closed) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let mut counts = [0usize; 3];
    for q in configurations_in_discs(&f.handles, 2.0 * radius(), 12, N_RANDOM) {
        let out = rig.deform(&q).unwrap();
        let mut offset = 0;
        for path in &f.drawing.paths {
            let n = path.points.len();
            let o = &out[offset..offset + n];
            offset += n;
            if path.closed {
                closed = closed.max((o[0] - o[n - 1]).hypot() / diag);
                counts[2] += 1;
            }
            let eps = {
                let r = path.points.iter().fold(
                    kurbo::Rect::from_points(path.points[0], path.points[0]),
                    |r, &p| r.union_pt(p),
                );
                r.width().hypot(r.height()) * options.coincidence
            };
            for (k, &kind) in path.joints.iter().enumerate() {
                let p = 3 * k;
                let Some((a, b)) = neighbours(&path.points, path.closed, p, eps) else {
                    continue;
                };
                let (u, v) = (
                    path.points[p] - path.points[a],
                    path.points[b] - path.points[p],
                );
                let p2 = if path.closed && p == n - 1 { 0 } else { p };
                let (u2, v2) = (o[p2] - o[a], o[b] - o[p2]);
                match kind {
                    JointKind::C1 => {
                        c1 = c1.max((v2 - u2).hypot() / diag);
                        counts[0] += 1;
                    }
                    JointKind::G1 => {
                        let input = signed_angle(u, v);
                        // The input's own angle; a corner saved G¹ is C⁰ (rest-preserving).
                        if input.abs() > options.smooth_angle {
                            continue;
                        }
                        let theta = input;
                        g1_angle = g1_angle.max((signed_angle(u2, v2) - theta).abs());
                        let ratio = v.hypot() / u.hypot();
                        g1_ratio = g1_ratio.max(((v2.hypot() / u2.hypot()) / ratio - 1.0).abs());
                        counts[1] += 1;
                    }
                    _ => {}
                }
            }
        }
    }
    eprintln!(
        "junctions ({} C¹, {} G¹, {} closed path checks): C¹ |v' − u'| / diagonal {c1:.1e}, G¹ angle {g1_angle:.1e} rad, ratio {g1_ratio:.1e}, closing gap / diagonal {closed:.1e}",
        counts[0], counts[1], counts[2]
    );
    assert!(
        counts[0] > 0 && counts[1] > 0 && counts[2] > 0,
        "{counts:?}"
    );
    // The constraints are exact rows of each path's KKT system: rounding only.
    assert!(c1 < 1e-12, "{c1:e}");
    assert!(g1_angle < 1e-9, "{g1_angle:e}");
    assert!(g1_ratio < 1e-9, "{g1_ratio:e}");
    assert_eq!(
        closed, 0.0,
        "a closed path's last point is its first, copied"
    );
}

/// The ground truth of `energy` at `q`: ARAP from the rest pose; symmetric ARAP from the ARAP
/// solution when it flips nothing, else from the rest pose.
fn ground_truth(mesh: &TriMesh, handles: &[usize], energy: Energy, q: &[Point]) -> Vec<Point> {
    let mut arap_solution = mesh.vertices.clone();
    Arap::new(mesh, handles, ArapOptions::default())
        .unwrap()
        .solve(q, &mut arap_solution)
        .unwrap();
    if energy == Energy::Arap {
        return arap_solution;
    }
    let mut u = if flipped_triangles(mesh, &arap_solution).unwrap().is_empty() {
        arap_solution
    } else {
        mesh.vertices.clone()
    };
    SymmetricArap::new(mesh, handles, SarapOptions::default())
        .unwrap()
        .solve(q, &mut u)
        .unwrap();
    u
}

#[test]
fn join_is_close_to_the_ground_truth() {
    let f = fish();
    let mesh = &f.domain.mesh;
    let handles = &f.domain.handle_vertices;
    let held_out = configurations_in_discs(&f.handles, radius(), 4242, N_HELD_OUT);
    let metrics = MetricsOptions::default();
    let input = f.drawing.flat_points();
    for energy in [Energy::SymmetricArap, Energy::Arap] {
        let training = trained(energy);
        let rig =
            DefOpRig::from_domain(&f.drawing, &f.domain, &training.op, &FitOptions::default())
                .unwrap();
        // The same samples fitted with the linear handle basis, joined the same way.
        let linear = DefOp::fit(
            mesh,
            handles,
            training.op.spatial_basis(),
            &training.configurations,
            &training.solutions,
            &DefOpOptions::default().with_handle_basis(HandleBasisKind::Linear),
        )
        .unwrap();
        let linear_rig =
            DefOpRig::from_domain(&f.drawing, &f.domain, &linear, &FitOptions::default()).unwrap();
        // Skinning with Shepard weights and the handles' translations (point handles carry
        // no rotation), fitted by the spline fit.
        let shepard = Shepard::new(&f.handles, ShepardOptions::default());
        let shepard_rig =
            SplineRig::precompute(&f.drawing, &shepard, &FitOptions::default()).unwrap();
        let names = [
            "join (TPS)",
            "join (linear Ψ)",
            "Shepard LBS",
            "rest drawing",
            "fit of truth",
        ];
        let mut max = [0.0f64; 5];
        let mut rms2 = [0.0f64; 5];
        for q in &held_out {
            let truth = ground_truth(mesh, handles, energy, q);
            let (field, pose) = mesh_target(mesh, &truth);
            let translations: Vec<Affine> = q
                .iter()
                .zip(&f.handles)
                .map(|(q, p)| Affine::translate(*q - *p))
                .collect();
            let mut shepard_points = vec![Point::ZERO; shepard_rig.n_points()];
            shepard_rig
                .update(&translations, &mut shepard_points)
                .unwrap();
            let results = [
                rig.deform(q).unwrap(),
                linear_rig.deform(q).unwrap(),
                shepard_points,
                input.clone(),
                fit_of_mesh(&f.drawing, mesh, &truth, &FitOptions::default()),
            ];
            for (k, points) in results.iter().enumerate() {
                let m = chain_metrics(&f.drawing, &field, &pose, points, &metrics).unwrap();
                max[k] = max[k].max(m.overall.max);
                rms2[k] += m.overall.rms * m.overall.rms / N_HELD_OUT as f64;
            }
        }
        let rms = rms2.map(f64::sqrt);
        for k in 0..5 {
            eprintln!(
                "{energy:?}, {N_HELD_OUT} held-out configurations (discs of {:.1}), {}: max {:.2e}, RMS {:.2e} of the diagonal",
                radius(),
                names[k],
                max[k],
                rms[k]
            );
        }
        // Measured bounds with margin.
        assert!(max[0] < MAX_JOIN_ERROR, "{energy:?}: {:e}", max[0]);
        assert!(rms[0] < RMS_JOIN_ERROR, "{energy:?}: {:e}", rms[0]);
        // Better than the linear handle basis on the same samples, and than Shepard skinning
        // and the rest drawing by a clear factor.
        assert!(
            rms[0] < rms[1],
            "{energy:?}: TPS {:e} vs linear {:e}",
            rms[0],
            rms[1]
        );
        for k in 2..4 {
            assert!(
                4.0 * rms[0] < rms[k],
                "{energy:?}: join {:e} vs {} {:e}",
                rms[0],
                names[k],
                rms[k]
            );
        }
        // And not better than the fit of the truth itself (the best any cubic chain of this
        // structure does, up to the different norms).
        assert!(rms[4] <= rms[0] * 1.5, "{energy:?}");
    }
}

/// Largest distance of the join's curves to the ground truth over the held-out
/// configurations, as a fraction of the diagonal: measured 9.3e-3 (symmetric ARAP) and
/// 5.9e-3 (ARAP) with 80 samples; the spline fit of the ground truth itself is at 5.7e-3 and
/// 5.0e-3 (a cubic chain cannot follow the piecewise-linear mesh exactly).
const MAX_JOIN_ERROR: f64 = 1.5e-2;
/// Its root mean square: measured 1.7e-3 and 9.3e-4 (fit of the truth: 4.9e-4, 4.4e-4;
/// Shepard skinning of the handles' translations 1.3e-2; the rest drawing 2.9e-2).
const RMS_JOIN_ERROR: f64 = 3e-3;

#[test]
fn join_update_allocates_nothing() {
    assert_counter_counts();
    let f = fish();
    let (domain, op) = reduced();
    let rig = DefOpRig::from_domain(&f.drawing, domain, op, &FitOptions::default()).unwrap();
    let mut evaluator = rig.evaluator();
    let mut out = vec![Point::ZERO; rig.n_points()];
    let q: Vec<Point> = f
        .handles
        .iter()
        .map(|&p| p + Vec2::new(3.0, -2.0))
        .collect();
    evaluator.update(&q, &mut out).unwrap();
    let (result, counts) = count(|| evaluator.update(std::hint::black_box(&q), &mut out));
    result.unwrap();
    assert_eq!(counts, Counts::default());
    assert_refusals_allocate_nothing(|p, o| evaluator.update(p, o), &q, &mut out);
}

#[test]
fn join_refuses_bad_input() {
    let f = fish();
    let (domain, op) = reduced();
    let options = FitOptions::default();
    let rig = DefOpRig::from_domain(&f.drawing, domain, op, &options).unwrap();
    let mut out = vec![Point::ZERO; rig.n_points()];
    let mut evaluator = rig.evaluator();
    assert_eq!(
        evaluator.update(&f.handles[..4], &mut out),
        Err(DefOpError::TargetCount {
            given: 4,
            n_handles: 5
        })
    );
    let mut q = f.handles.clone();
    q[2].y = f64::NAN;
    assert!(matches!(
        evaluator.update(&q, &mut out),
        Err(DefOpError::NonFiniteTarget { handle: 2, .. })
    ));
    assert_eq!(
        evaluator.update(&f.handles, &mut out[..3]),
        Err(DefOpError::BufferLength {
            given: 3,
            expected: rig.n_points()
        })
    );
    // The operator of another mesh.
    assert!(matches!(
        DefOpRig::precompute(&f.drawing, &f.domain.mesh, op, &options),
        Err(DefOpError::BasisMismatch { .. })
    ));
    // A domain whose handles are not the operator's.
    let mut other = domain.clone();
    other.handle_vertices.swap(0, 1);
    assert!(matches!(
        DefOpRig::from_domain(&f.drawing, &other, op, &options),
        Err(DefOpError::HandleMismatch { .. })
    ));
    // The drawing far from the mesh (moved by its own size).
    let mut moved = f.drawing.clone();
    for path in &mut moved.paths {
        for p in &mut path.points {
            *p += Vec2::new(1000.0, 0.0);
        }
    }
    assert!(matches!(
        DefOpRig::precompute(&moved, &domain.mesh, op, &options),
        Err(DefOpError::DrawingOutsideMesh { path: 0, .. })
    ));
    // A non-finite control point.
    let mut broken = f.drawing.clone();
    broken.paths[1].points[2].x = f64::INFINITY;
    assert!(matches!(
        DefOpRig::precompute(&broken, &domain.mesh, op, &options),
        Err(DefOpError::Fit(_))
    ));
}
