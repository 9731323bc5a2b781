//! Handle weights on subdivision surfaces ([`splineskin::subdiv::surface_weights`]):
//!
//! * every family is a partition of unity at every quadrature node, and the rig built on it
//!   reproduces the cage under the identity and maps it by one common affine map;
//! * Shepard weights are 1 on their own point or bone; bone heat gives (almost) 1 at a handle
//!   on the surface and 1 on a part only its own bone sees (visibility), while without the
//!   visibility test heat leaks across a gap;
//! * mirror-symmetric shapes and handles give mirror-symmetric bone-heat weights;
//! * per-vertex weights carried by the limit stencils reproduce a linear function exactly
//!   (linear precision of the limit stencils).

mod common;

use splineskin::subdiv::{
    affine3_apply, node_weights, parse_obj, parse_weight_csv, read_obj, rotation_axis_angle,
    sample_weights, Affine3, BoneHeat, BoneHeatOptions, Cage, Handles3, LimitMesh, LimitOptions,
    LimitQuadrature, LimitSurface, Point3, Shepard3, SubdivRig, SurfaceWeights,
    SurfaceWeightsError, AFFINE3_IDENTITY, DEFAULT_GAUSS_POINTS,
};
use splineskin::weights::ShepardOptions;

/// Rounding of normalised weights summed over a handful of handles.
const PARTITION_TOLERANCE: f64 = 1e-13;

/// The identity and common-affine poses reproduce the cage to rounding (see `subdiv_rig.rs`).
const REPRODUCTION_TOLERANCE: f64 = 1e-12;

/// A box `[0, 4] × [0, 1] × [0, 1]` cut into four unit cells along x, mirror-symmetric about
/// x = 2.
fn bar() -> Cage {
    let mut text = String::new();
    for i in 0..5 {
        for (y, z) in [(0, 0), (1, 0), (1, 1), (0, 1)] {
            text += &format!("v {i} {y} {z}\n");
        }
    }
    // Ring i has vertices 4i + 1 .. 4i + 4 (1-based); end caps and side quads.
    text += "f 1 4 3 2\nf 17 18 19 20\n";
    for i in 0..4 {
        let a = 4 * i + 1;
        let b = a + 4;
        for k in 0..4 {
            let (k0, k1) = (k, (k + 1) % 4);
            text += &format!("f {} {} {} {}\n", a + k0, a + k1, b + k1, b + k0);
        }
    }
    parse_obj(&text, "bar.obj").unwrap()
}

/// Two unit-square-section boxes side by side with a gap: `[0, 1]` and `[1.2, 3.2]` in x.
fn two_boxes() -> Cage {
    let mut text = String::new();
    for (x0, x1) in [(0.0, 1.0), (1.2, 3.2)] {
        for z in [0.0, 1.0] {
            for (x, y) in [(x0, 0.0), (x1, 0.0), (x1, 1.0), (x0, 1.0)] {
                text += &format!("v {x} {y} {z}\n");
            }
        }
    }
    for o in [0, 8] {
        for f in [
            [1, 4, 3, 2],
            [5, 6, 7, 8],
            [1, 2, 6, 5],
            [2, 3, 7, 6],
            [3, 4, 8, 7],
            [4, 1, 5, 8],
        ] {
            text += &format!("f {} {} {} {}\n", f[0] + o, f[1] + o, f[2] + o, f[3] + o);
        }
    }
    parse_obj(&text, "two_boxes.obj").unwrap()
}

fn surface(cage: &Cage) -> LimitSurface {
    LimitSurface::new(cage, &LimitOptions::default()).unwrap()
}

/// Builds the rig of `field` and checks partition of unity, identity and a common affine map.
fn check_rig(name: &str, cage: &Cage, field: &dyn SurfaceWeights) {
    let s = surface(cage);
    let q = LimitQuadrature::new(&s, DEFAULT_GAUSS_POINTS).unwrap();
    let w = node_weights(field, cage, &q).unwrap();
    let h = field.n_handles();
    for (k, row) in w.chunks(h).enumerate() {
        let sum: f64 = row.iter().sum();
        assert!(
            (sum - 1.0).abs() < PARTITION_TOLERANCE,
            "{name}: node {k} sums to {sum}"
        );
        assert!(
            row.iter().all(|&x| x >= -1e-12),
            "{name}: node {k}: {row:?}"
        );
    }
    let rig = SubdivRig::precompute(cage, &q, &w, h).unwrap();
    let diag = cage.bounding_box_diagonal();
    let mut out = vec![[0.0; 3]; cage.n_vertices()];
    let r = rotation_axis_angle([0.3, -1.0, 0.4], 0.8).unwrap();
    let t: Affine3 = std::array::from_fn(|i| [1.1 * r[i][0], 1.1 * r[i][1], 1.1 * r[i][2], 0.5]);
    for (pose, expected) in [(AFFINE3_IDENTITY, AFFINE3_IDENTITY), (t, t)] {
        rig.update(&vec![pose; h], &mut out).unwrap();
        let worst = out
            .iter()
            .zip(cage.positions())
            .map(|(o, p)| dist(*o, affine3_apply(&expected, *p)))
            .fold(0.0, f64::max)
            / diag;
        assert!(worst < REPRODUCTION_TOLERANCE, "{name}: off by {worst:.2e}");
    }
}

fn dist(a: Point3, b: Point3) -> f64 {
    (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt()
}

#[test]
fn subdiv_weights_shepard_is_one_on_its_handle() {
    let handles = Handles3::new(
        vec![[2.0, 0.5, 1.5]],
        vec![[[0.5, 0.5, 0.5], [1.5, 0.5, 0.5]]],
    )
    .unwrap();
    let w = Shepard3::new(handles, ShepardOptions::default()).unwrap();
    let mut out = [0.0; 2];
    for x in [[0.5, 0.5, 0.5], [1.0, 0.5, 0.5], [1.5, 0.5, 0.5]] {
        w.at(x, &mut out);
        assert_eq!(out, [0.0, 1.0]);
    }
    w.at([2.0, 0.5, 1.5], &mut out);
    assert_eq!(out, [1.0, 0.0]);
    check_rig("bar, Shepard", &bar(), &w);
}

#[test]
fn subdiv_weights_bone_heat_symmetric_and_one_at_a_handle() {
    let cage = bar();
    let s = surface(&cage);
    let bones = vec![
        [[0.5, 0.5, 0.5], [1.7, 0.5, 0.5]],
        [[3.5, 0.5, 0.5], [2.3, 0.5, 0.5]],
    ];
    let handles = Handles3::new(vec![], bones).unwrap();
    let heat = BoneHeat::new(&cage, &s, &handles, &BoneHeatOptions::default()).unwrap();
    let mesh = heat.mesh();
    let mut p = vec![[0.0; 3]; mesh.n_vertices()];
    mesh.positions(cage.positions(), &mut p);
    // The mirror x → 4 − x maps the mesh onto itself and bone 0 onto bone 1.
    let mut worst = 0.0f64;
    for (v, x) in p.iter().enumerate() {
        let mirror = [4.0 - x[0], x[1], x[2]];
        let (m, d) = p
            .iter()
            .enumerate()
            .map(|(m, y)| (m, dist(*y, mirror)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap();
        assert!(d < 1e-12, "vertex {v} has no mirror image ({d:.1e})");
        worst = worst.max((heat.mesh_weights(v)[0] - heat.mesh_weights(m)[1]).abs());
    }
    assert!(worst < 1e-10, "asymmetry {worst:.2e}");
    // Ends follow their own bone, the middle is shared.
    let w0 = heat.mesh_weights(mesh.cage_vertex(0).unwrap() as usize);
    assert!(w0[0] > 0.95, "{w0:?}");
    check_rig("bar, bone heat", &cage, &heat);

    // A point handle on the surface (at a mesh vertex) gets weight 1 there, to the heat's
    // distance floor.
    let v = mesh.n_vertices() / 3;
    let handles = Handles3::new(vec![p[v], [2.0, 0.5, 0.5]], vec![]).unwrap();
    let heat = BoneHeat::new(&cage, &s, &handles, &BoneHeatOptions::default()).unwrap();
    let same_mesh = heat.mesh();
    let mut q = vec![[0.0; 3]; same_mesh.n_vertices()];
    same_mesh.positions(cage.positions(), &mut q);
    assert_eq!(dist(q[v], p[v]), 0.0, "the same mesh");
    let w = heat.mesh_weights(v);
    assert!(w[0] > 1.0 - 1e-6, "{w:?}");
}

#[test]
fn subdiv_weights_bone_heat_visibility() {
    // Bone A in the thin box, bone B near the far side of the thick one: the thick box's face
    // towards the gap is nearer to A, but A is out of its sight.
    let cage = two_boxes();
    let s = surface(&cage);
    let handles = Handles3::new(
        vec![],
        vec![
            [[0.5, 0.5, 0.3], [0.5, 0.5, 0.7]],
            [[2.8, 0.5, 0.3], [2.8, 0.5, 0.7]],
        ],
    )
    .unwrap();
    let visible = BoneHeat::new(&cage, &s, &handles, &BoneHeatOptions::default()).unwrap();
    let blind = BoneHeat::new(
        &cage,
        &s,
        &handles,
        &BoneHeatOptions::default().with_visibility(false),
    )
    .unwrap();
    let mesh = visible.mesh();
    let mut p = vec![[0.0; 3]; mesh.n_vertices()];
    mesh.positions(cage.positions(), &mut p);
    let (mut min_b, mut max_a_blind) = (f64::INFINITY, 0.0f64);
    for (v, x) in p.iter().enumerate() {
        if x[0] > 1.1 {
            min_b = min_b.min(visible.mesh_weights(v)[1]);
            max_a_blind = max_a_blind.max(blind.mesh_weights(v)[0]);
        } else {
            assert!(visible.mesh_weights(v)[0] > 1.0 - 1e-12);
        }
    }
    // Each box is its own connected part and sees only its own bone: the weights are exact.
    assert!(min_b > 1.0 - 1e-12, "{min_b}");
    // Without the test the face towards the gap is heated by A (0.19 of A measured at most).
    assert!(max_a_blind > 0.1, "{max_a_blind}");
    check_rig("two boxes, bone heat", &cage, &visible);
}

#[test]
fn subdiv_weights_vertex_file_is_carried_by_the_stencils() {
    let cage = bar();
    // Column 1 is x/4, column 0 the rest: carried by limit stencils, which reproduce linear
    // functions, column 1 is G(p).x/4 at every point of the surface.
    let text: String = cage
        .positions()
        .iter()
        .map(|p| format!("{}, {}\n", 1.0 - p[0] / 4.0, p[0] / 4.0))
        .collect();
    let table = parse_weight_csv(&text, "bar.csv", cage.n_vertices(), 2).unwrap();
    let s = surface(&cage);
    let q = LimitQuadrature::new(&s, DEFAULT_GAUSS_POINTS).unwrap();
    let w = node_weights(&table, &cage, &q).unwrap();
    let mut g = vec![[0.0; 3]; q.n_nodes()];
    q.positions(cage.positions(), &mut g);
    for (k, x) in g.iter().enumerate() {
        assert!((w[2 * k + 1] - x[0] / 4.0).abs() < 1e-14, "node {k}");
    }
    let mesh = LimitMesh::new(&cage, &s, 2).unwrap();
    let on_mesh = sample_weights(&table, &cage, &mesh).unwrap();
    assert_eq!(on_mesh.len(), 2 * mesh.n_vertices());
    check_rig("bar, vertex file", &cage, &table);
}

#[test]
fn subdiv_weights_bad_handles_are_refused() {
    let err = Handles3::new(vec![[0.0, f64::NAN, 0.0]], vec![]).unwrap_err();
    assert_eq!(
        err.to_string(),
        "handle 0: point [0.0, NaN, 0.0] is not finite"
    );
    let err = Handles3::new(vec![[0.0; 3]], vec![[[1.0, 1.0, 1.0], [1.0, 1.0, 1.0]]]).unwrap_err();
    assert!(
        matches!(err, SurfaceWeightsError::BadHandle { handle: 1, .. }),
        "{err}"
    );
    assert!(matches!(
        Handles3::new(vec![], vec![]),
        Err(SurfaceWeightsError::NoHandles)
    ));
}

#[test]
fn subdiv_weights_on_regression_shapes() {
    let Some(root) = common::data_root() else {
        return;
    };
    for name in ["catmark_torus", "catmark_hole_test2", "catmark_nonquads"] {
        let cage = read_obj(&root.join(format!("subdiv/shapes/{name}.obj"))).unwrap();
        let s = surface(&cage);
        let n = cage.n_vertices();
        let handles = Handles3::new(
            vec![cage.positions()[0], cage.positions()[n / 2]],
            vec![[cage.positions()[n / 3], cage.positions()[2 * n / 3]]],
        )
        .unwrap();
        let heat = BoneHeat::new(&cage, &s, &handles, &BoneHeatOptions::default()).unwrap();
        check_rig(&format!("{name}, bone heat"), &cage, &heat);
        let shepard = Shepard3::new(handles, ShepardOptions::default()).unwrap();
        check_rig(&format!("{name}, Shepard"), &cage, &shepard);
    }
}
