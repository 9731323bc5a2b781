//! `SubdivRig` invariants (DESIGN.md §3) on a cube made here and, when `../shared/data` is
//! present, on OpenSubdiv regression shapes (a torus, holes, creases, the car):
//!
//! * the identity pose gives back the cage, and one affine map on every handle gives that map
//!   of the cage (weights summing to one at every node make `Σ_i Ŵ_i = C̄ Â`), also on the
//!   cube, whose `Â` is singular;
//! * the fit is the least-squares optimum of `∫ ‖C' m_p − s(p)‖² dp` over all cages, so in that
//!   quadrature norm it is never farther from the skinned limit surface `s` than the naive
//!   method (skinning the cage vertices themselves) — the figures are printed;
//! * a cage vertex that no limit stencil uses is refused with its index.

mod common;

use common::Rng;
use splineskin::subdiv::{
    parse_obj, read_obj, Affine3, Cage, LimitOptions, LimitQuadrature, LimitSurface, Point3,
    SubdivError, SubdivRig, AFFINE3_IDENTITY, DEFAULT_GAUSS_POINTS,
};

/// Largest accepted error of the identity and common-affine poses, as a fraction of the
/// bounding-box diagonal: rounding (precompute restores `Σ_i B_i = P̄` after the solve).
const REPRODUCTION_TOLERANCE: f64 = 1e-13;

/// Normalised inverse-distance (Shepard, exponent 2) weights of `handles` at `p`.
fn shepard(handles: &[Point3], p: Point3, out: &mut [f64]) {
    let mut sum = 0.0;
    for (w, h) in out.iter_mut().zip(handles) {
        let d2: f64 = (0..3).map(|k| (p[k] - h[k]).powi(2)).sum();
        *w = 1.0 / d2.max(1e-300);
        sum += *w;
    }
    for w in out.iter_mut() {
        *w /= sum;
    }
}

fn apply(t: &Affine3, p: Point3) -> Point3 {
    std::array::from_fn(|r| t[r][0] * p[0] + t[r][1] * p[1] + t[r][2] * p[2] + t[r][3])
}

impl Rng {
    /// A rotation about a random axis, scaled, and translated by up to `reach`.
    fn affine(&mut self, reach: f64) -> Affine3 {
        let axis = [
            self.range(-1.0, 1.0),
            self.range(-1.0, 1.0),
            self.range(-1.0, 1.0),
        ];
        let len = axis.iter().map(|a| a * a).sum::<f64>().sqrt().max(1e-9);
        let [x, y, z] = axis.map(|a| a / len);
        let (s, c) = self.range(-1.5, 1.5).sin_cos();
        let k = self.range(0.7, 1.3);
        let r = [
            [
                c + x * x * (1.0 - c),
                x * y * (1.0 - c) - z * s,
                x * z * (1.0 - c) + y * s,
            ],
            [
                y * x * (1.0 - c) + z * s,
                c + y * y * (1.0 - c),
                y * z * (1.0 - c) - x * s,
            ],
            [
                z * x * (1.0 - c) - y * s,
                z * y * (1.0 - c) + x * s,
                c + z * z * (1.0 - c),
            ],
        ];
        std::array::from_fn(|row| {
            [
                k * r[row][0],
                k * r[row][1],
                k * r[row][2],
                self.range(-reach, reach),
            ]
        })
    }
}

/// Checks one cage with `n_handles` handles placed at random cage vertices; returns (ours,
/// naive) quadrature-RMS distances to the skinned surface over a few random poses, as
/// fractions of the diagonal.
fn check(name: &str, cage: &Cage, n_handles: usize, rng: &mut Rng) -> (f64, f64) {
    let diag = cage.bounding_box_diagonal();
    let surface = LimitSurface::new(cage, &LimitOptions::default()).unwrap();
    let q = LimitQuadrature::new(&surface, DEFAULT_GAUSS_POINTS).unwrap();
    // Distinct cage vertices as handles.
    let mut chosen: Vec<usize> = Vec::new();
    while chosen.len() < n_handles {
        let v = (rng.next_f64() * cage.n_vertices() as f64) as usize;
        if !chosen.contains(&v) {
            chosen.push(v);
        }
    }
    let handles: Vec<Point3> = chosen.iter().map(|&v| cage.positions()[v]).collect();
    let mut g = vec![[0.0; 3]; q.n_nodes()];
    q.positions(cage.positions(), &mut g);
    let mut node_weights = vec![0.0; q.n_nodes() * n_handles];
    for (k, p) in g.iter().enumerate() {
        shepard(
            &handles,
            *p,
            &mut node_weights[k * n_handles..][..n_handles],
        );
    }
    let rig = SubdivRig::precompute(cage, &q, &node_weights, n_handles).unwrap();
    let mut out = vec![[0.0; 3]; cage.n_vertices()];
    let err = |out: &[Point3], expected: &dyn Fn(Point3) -> Point3| {
        out.iter()
            .zip(cage.positions())
            .map(|(o, p)| {
                let e = expected(*p);
                (0..3).map(|k| (o[k] - e[k]).powi(2)).sum::<f64>().sqrt()
            })
            .fold(0.0f64, f64::max)
            / diag
    };

    rig.update(&vec![AFFINE3_IDENTITY; n_handles], &mut out)
        .unwrap();
    let identity = err(&out, &|p| p);
    assert!(
        identity <= REPRODUCTION_TOLERANCE,
        "{name}: identity pose off by {identity:.2e}"
    );
    let t = rng.affine(diag);
    rig.update(&vec![t; n_handles], &mut out).unwrap();
    let common = err(&out, &|p| apply(&t, p));
    assert!(
        common <= REPRODUCTION_TOLERANCE,
        "{name}: common affine off by {common:.2e}"
    );

    // Ours against naive, in the quadrature norm the fit minimises.
    let mut vertex_weights = vec![0.0; n_handles];
    let (mut ours, mut naive) = (0.0f64, 0.0f64);
    for _ in 0..3 {
        let pose: Vec<Affine3> = (0..n_handles).map(|_| rng.affine(0.3 * diag)).collect();
        rig.update(&pose, &mut out).unwrap();
        let naive_cage: Vec<Point3> = cage
            .positions()
            .iter()
            .map(|&p| {
                shepard(&handles, p, &mut vertex_weights);
                let mut s = [0.0; 3];
                for (w, t) in vertex_weights.iter().zip(&pose) {
                    let tp = apply(t, p);
                    for k in 0..3 {
                        s[k] += w * tp[k];
                    }
                }
                s
            })
            .collect();
        let (mut e_ours, mut e_naive, mut area) = (0.0, 0.0, 0.0);
        for (k, node) in q.nodes().iter().enumerate() {
            let w = &node_weights[k * n_handles..][..n_handles];
            let mut target = [0.0; 3];
            for (wi, t) in w.iter().zip(&pose) {
                let tp = apply(t, g[k]);
                for c in 0..3 {
                    target[c] += wi * tp[c];
                }
            }
            let st = q.stencil(k);
            let d2 = |p: Point3| (0..3).map(|c| (p[c] - target[c]).powi(2)).sum::<f64>();
            e_ours += node.weight * d2(st.position(&out));
            e_naive += node.weight * d2(st.position(&naive_cage));
            area += node.weight;
        }
        // The fit minimises the energy plus the ε-pull (rig.rs), hence the slack.
        assert!(
            e_ours <= e_naive * (1.0 + 1e-4),
            "{name}: the fit ({e_ours:.3e}) is worse than naive ({e_naive:.3e})"
        );
        ours = ours.max((e_ours / area).sqrt() / diag);
        naive = naive.max((e_naive / area).sqrt() / diag);
    }
    println!(
        "{name:<24} {:>5} vertices {n_handles} handles: identity {identity:.1e}, common affine \
         {common:.1e}, RMS to target: ours {ours:.2e}, naive {naive:.2e} (worst of 3 poses)",
        cage.n_vertices()
    );
    (ours, naive)
}

const CUBE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
                    f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

#[test]
fn subdiv_rig_cube() {
    let cage = parse_obj(CUBE, "cube.obj").unwrap();
    let mut rng = Rng(11);
    let (ours, naive) = check("cube", &cage, 2, &mut rng);
    assert!(ours < naive, "{ours} vs {naive}");
}

#[test]
fn subdiv_rig_regression_shapes() {
    let Some(root) = common::data_root() else {
        return;
    };
    let mut rng = Rng(5);
    for (name, n_handles) in [
        ("catmark_torus", 2),
        ("catmark_torus_creases1", 3),
        ("catmark_hole_test2", 2),
        ("catmark_nonquads", 3),
        ("catmark_car", 4),
    ] {
        let cage = read_obj(&root.join(format!("subdiv/shapes/{name}.obj"))).unwrap();
        let (ours, naive) = check(name, &cage, n_handles, &mut rng);
        assert!(ours < naive, "{name}: {ours} vs {naive}");
    }
}

#[test]
fn subdiv_rig_refuses_vertices_without_surface() {
    // A cube with a ninth vertex used by no face.
    let text = CUBE.to_owned() + "v 5 5 5\n";
    let cage = parse_obj(&text, "cube9.obj").unwrap();
    let surface = LimitSurface::new(&cage, &LimitOptions::default()).unwrap();
    let q = LimitQuadrature::new(&surface, 2).unwrap();
    let weights = vec![1.0; q.n_nodes()];
    let err = SubdivRig::precompute(&cage, &q, &weights, 1).unwrap_err();
    assert!(
        matches!(&err, SubdivError::BadRig { what } if what.starts_with("cage vertex 8 has no influence")),
        "{err}"
    );
    // Wrong sizes are refused too, and so are wrong per-frame buffers.
    let cage = parse_obj(CUBE, "cube.obj").unwrap();
    let surface = LimitSurface::new(&cage, &LimitOptions::default()).unwrap();
    let q = LimitQuadrature::new(&surface, 2).unwrap();
    assert!(SubdivRig::precompute(&cage, &q, &[1.0; 3], 1).is_err());
    let rig = SubdivRig::precompute(&cage, &q, &vec![1.0; q.n_nodes()], 1).unwrap();
    let mut out = vec![[0.0; 3]; 7];
    assert!(matches!(
        rig.update(&[AFFINE3_IDENTITY], &mut out),
        Err(SubdivError::SizeMismatch {
            expected: 8,
            found: 7,
            ..
        })
    ));
}
