//! Volumetric bounded biharmonic weights on Catmull–Clark cages
//! ([`splineskin::subdiv::surface_weights::VolumeBbw`], scenes' `"family": "bbw"`):
//!
//! * on the bundled tube (bones) and OpenSubdiv's shapes (points): every weight in `[0, 1]`,
//!   rows summing to 1, each handle's own weight near 1 at its handle;
//! * shape-aware: on a U of two arms, moving one arm's handle moves the other arm's tip less
//!   than a tenth as far as its own (Shepard weights, which measure straight-line distance
//!   across the gap, move it far more);
//! * the weight time of a 3 000-vertex cage with 4 handles is printed (`--nocapture`).

mod common;

use std::collections::HashMap;
use std::time::Instant;

use splineskin::subdiv::surface_weights::{SurfaceWeights, VolumeBbw, VolumeBbwOptions};
use splineskin::subdiv::{
    affine3_translation, farthest_point_sample, read_obj, refine_uniform, Cage, Handles3,
    LimitMesh, LimitOptions, LimitSurface, SubdivScene, SubdivSetup, SurfaceWeightSpec,
    AFFINE3_IDENTITY, DEFAULT_GAUSS_POINTS,
};
use splineskin::weights::ShepardOptions;

/// A cage of unit voxels at `cells` (integer corners): their boundary quads, outward.
fn voxel_cage(cells: &[[i32; 3]]) -> Cage {
    let filled: std::collections::HashSet<[i32; 3]> = cells.iter().copied().collect();
    let mut index: HashMap<[i32; 3], u32> = HashMap::new();
    let mut positions = Vec::new();
    let mut faces = Vec::new();
    for &c in cells {
        for axis in 0..3 {
            for side in [0, 1] {
                let mut n = c;
                n[axis] += if side == 1 { 1 } else { -1 };
                if filled.contains(&n) {
                    continue;
                }
                let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
                let corner = |du: i32, dv: i32| {
                    let mut p = c;
                    p[axis] += side;
                    p[u] += du;
                    p[v] += dv;
                    p
                };
                let mut quad = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)];
                if side == 0 {
                    quad.reverse();
                }
                let face = quad
                    .iter()
                    .map(|p| {
                        *index.entry(*p).or_insert_with(|| {
                            positions.push(p.map(f64::from));
                            (positions.len() - 1) as u32
                        })
                    })
                    .collect();
                faces.push(face);
            }
        }
    }
    Cage::new(positions, faces, Default::default()).unwrap()
}

fn setup_with(
    cage: &Cage,
    handles: Handles3,
    weights: SurfaceWeightSpec,
) -> (SubdivScene, SubdivSetup) {
    let scene = SubdivScene {
        file: "test".into(),
        obj: "test.obj".into(),
        handles,
        weights,
        quadrature: DEFAULT_GAUSS_POINTS,
        poses: Vec::new(),
        animation: None,
    };
    let setup = scene.setup_with(cage.clone()).unwrap();
    (scene, setup)
}

/// Bounds, partition of unity and each handle's weight at its own handle.
fn check_weights(name: &str, w: &dyn SurfaceWeights, cage: &Cage, handles: &Handles3) {
    let h = handles.n_handles();
    let mut row = vec![0.0; h];
    for (v, &p) in cage.positions().iter().enumerate() {
        w.eval_cage_vertex(v as u32, p, &mut row).unwrap();
        let sum: f64 = row.iter().sum();
        assert!(
            row.iter().all(|&x| (0.0..=1.0).contains(&x)),
            "{name}: vertex {v}: {row:?}"
        );
        assert!((sum - 1.0).abs() < 1e-9, "{name}: vertex {v}: sum {sum}");
    }
    for i in 0..handles.n_handles() {
        let at = handles.closest_point(i, handles.pivot(i));
        w.eval_cage_vertex(0, at, &mut row).unwrap();
        assert!(row[i] > 0.75, "{name}: handle {i} at {at:?}: {row:?}");
    }
}

#[test]
fn volume_bbw_is_bounded_a_partition_of_unity_and_one_at_its_handles() {
    let tube = std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/subdiv/tube-scene.json"
    ));
    let scene = SubdivScene::load(tube).unwrap();
    let cage = read_obj(&scene.obj).unwrap();
    let surface = LimitSurface::new(&cage, &LimitOptions::default()).unwrap();
    let w = VolumeBbw::new(
        &cage,
        &surface,
        &scene.handles,
        &VolumeBbwOptions::default(),
    )
    .unwrap();
    println!(
        "tube: {} grid nodes, cell {:.3}",
        w.n_nodes(),
        w.cell_size()
    );
    check_weights("tube", &w, &cage, &scene.handles);
    let Some(root) = common::data_root() else {
        return;
    };
    for (name, n) in [
        ("catmark_torus", 3),
        ("catmark_car", 4),
        ("catmark_bishop", 4),
    ] {
        let cage = read_obj(&root.join(format!("subdiv/shapes/{name}.obj"))).unwrap();
        let surface = LimitSurface::new(&cage, &LimitOptions::default()).unwrap();
        let points = farthest_point_sample(cage.positions(), n)
            .iter()
            .map(|&v| cage.positions()[v])
            .collect();
        let handles = Handles3::new(points, vec![]).unwrap();
        let w = VolumeBbw::new(&cage, &surface, &handles, &VolumeBbwOptions::default()).unwrap();
        println!("{name}: {} grid nodes", w.n_nodes());
        check_weights(name, &w, &cage, &handles);
    }
}

#[test]
fn volume_bbw_is_shape_aware_across_a_gap() {
    // A U: a base of 7 voxels along x, two arms 5 voxels tall at its ends, 5 voxels apart.
    let mut cells = Vec::new();
    for x in 0..7 {
        cells.push([x, 0, 0]);
    }
    for y in 1..6 {
        cells.push([0, y, 0]);
        cells.push([6, y, 0]);
    }
    let cage = voxel_cage(&cells);
    let tip = |x: f64| [x, 5.5, 0.5];
    let handles = Handles3::new(vec![tip(0.5), tip(6.5), [3.5, 0.5, 0.5]], vec![]).unwrap();
    // The cage vertex at the top of each arm: its limit point is the arm's tip.
    let top = |x: f64| {
        let p = [x, 6.0, 0.0];
        cage.positions().iter().position(|&q| q == p).unwrap() as u32
    };
    let (moved_arm, other_arm) = (top(0.0), top(7.0));
    let shove = affine3_translation([0.0, 0.0, 1.0]);
    let mut ratios = Vec::new();
    for (family, weights) in [
        ("bbw", SurfaceWeightSpec::Bbw(VolumeBbwOptions::default())),
        (
            "shepard",
            SurfaceWeightSpec::Shepard(ShepardOptions::default()),
        ),
    ] {
        let (_, setup) = setup_with(&cage, handles.clone(), weights);
        let mut fitted = vec![[0.0; 3]; cage.n_vertices()];
        setup
            .rig
            .update(&[shove, AFFINE3_IDENTITY, AFFINE3_IDENTITY], &mut fitted)
            .unwrap();
        let surface = setup.full_surface().unwrap();
        let mesh = LimitMesh::new(&cage, &surface, 1).unwrap();
        let (mut rest, mut posed) = (
            vec![[0.0; 3]; mesh.n_vertices()],
            vec![[0.0; 3]; mesh.n_vertices()],
        );
        mesh.positions(cage.positions(), &mut rest);
        mesh.positions(&fitted, &mut posed);
        let moved = |v: u32| {
            let m = mesh.cage_vertex(v).unwrap() as usize;
            (0..3)
                .map(|k| (posed[m][k] - rest[m][k]).powi(2))
                .sum::<f64>()
                .sqrt()
        };
        let ratio = moved(other_arm) / moved(moved_arm);
        println!(
            "{family}: the moved arm's tip {:.3}, the other's {:.4}: ratio {ratio:.4}",
            moved(moved_arm),
            moved(other_arm)
        );
        ratios.push(ratio);
    }
    assert!(
        ratios[0] < 0.1,
        "bbw: the other arm moves {} as far",
        ratios[0]
    );
    assert!(
        ratios[1] > ratios[0],
        "shepard should leak more across the gap: {ratios:?}"
    );
}

#[test]
fn volume_bbw_time_on_a_3000_vertex_cage() {
    let Some(root) = common::data_root() else {
        return;
    };
    let rook = read_obj(&root.join("subdiv/shapes/catmark_rook.obj")).unwrap();
    let cage = refine_uniform(&rook, 1).unwrap().levels()[0]
        .to_cage()
        .unwrap();
    let surface = LimitSurface::new(&cage, &LimitOptions::default()).unwrap();
    let points = farthest_point_sample(cage.positions(), 4)
        .iter()
        .map(|&v| cage.positions()[v])
        .collect();
    let handles = Handles3::new(points, vec![]).unwrap();
    let start = Instant::now();
    let w = VolumeBbw::new(&cage, &surface, &handles, &VolumeBbwOptions::default()).unwrap();
    println!(
        "catmark_rook refined once: {} vertices, 4 handles, {} grid nodes: volumetric BBW in {:.2} s",
        cage.n_vertices(),
        w.n_nodes(),
        start.elapsed().as_secs_f64()
    );
    check_weights("rook", &w, &cage, &handles);
}
