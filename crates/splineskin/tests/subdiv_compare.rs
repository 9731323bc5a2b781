//! Ours against the naive method on the limit surface ([`splineskin::subdiv::compare_subdiv`],
//! Liu et al. 2014 Fig. 8):
//!
//! * the identity pose gives zero error for both, one affine map on every handle gives zero
//!   error for both (ours fits exactly that map of the cage; the naive cage is that map of the
//!   cage, and the limit surface of an affine image is the affine image of the limit surface);
//! * on torus-like shapes and the car, with two to four handles, Shepard, bone-heat and
//!   volumetric bounded biharmonic weights and random rigid poses, ours is closer to the skinned surface than naive, in RMS and in
//!   max; the table is printed (`--nocapture`) and the car's picture is written to
//!   `$CARGO_TARGET_TMPDIR/subdiv-compare/`.

mod common;

use common::Rng;
use splineskin::subdiv::surface_weights::VolumeBbwOptions;
use splineskin::subdiv::{
    affine3_about, compare_subdiv, farthest_point_sample, parse_obj, read_obj,
    render_comparison_png, rotation_axis_angle, Affine3, Cage, ComparisonPictureOptions,
    ComparisonSamples, Handles3, SubdivScene, SubdivSetup, SurfaceWeightSpec, AFFINE3_IDENTITY,
    DEFAULT_COMPARE_LEVEL, DEFAULT_GAUSS_POINTS,
};
use splineskin::subdiv::{BoneHeatOptions, Pose3};
use splineskin::weights::ShepardOptions;

/// Zero-error poses: rounding of the rig (1e-13, `subdiv_rig.rs`) and of the limit stencils.
const EXACT_TOLERANCE: f64 = 1e-12;

/// A scene around `cage` with `n` point handles by farthest-point sampling of its vertices.
fn setup(cage: &Cage, n: usize, weights: SurfaceWeightSpec) -> (SubdivScene, SubdivSetup) {
    let chosen = farthest_point_sample(cage.positions(), n);
    let points = chosen.iter().map(|&v| cage.positions()[v]).collect();
    let scene = SubdivScene {
        file: "test".into(),
        obj: "test.obj".into(),
        handles: Handles3::new(points, vec![]).unwrap(),
        weights,
        quadrature: DEFAULT_GAUSS_POINTS,
        poses: Vec::<Pose3>::new(),
        animation: None,
    };
    let setup = scene.setup_with(cage.clone()).unwrap();
    (scene, setup)
}

impl Rng {
    /// A rigid map about `pivot`: a turn of up to `max_angle` radians about a random axis,
    /// then a shift of up to `reach` per axis.
    fn rigid(&mut self, pivot: [f64; 3], max_angle: f64, reach: f64) -> Affine3 {
        let axis = [
            self.range(-1.0, 1.0),
            self.range(-1.0, 1.0),
            self.range(-1.0, 1.0),
        ];
        let r = rotation_axis_angle(axis, self.range(-max_angle, max_angle)).unwrap_or([
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ]);
        let d = [
            self.range(-reach, reach),
            self.range(-reach, reach),
            self.range(-reach, reach),
        ];
        affine3_about(pivot, &r, d)
    }
}

fn shepard() -> SurfaceWeightSpec {
    SurfaceWeightSpec::Shepard(ShepardOptions::default())
}

fn bone_heat() -> SurfaceWeightSpec {
    SurfaceWeightSpec::BoneHeat(BoneHeatOptions::default())
}

fn bbw() -> SurfaceWeightSpec {
    SurfaceWeightSpec::Bbw(VolumeBbwOptions::default())
}

const CUBE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
                    f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

#[test]
fn subdiv_compare_identity_and_common_affine_are_exact() {
    let cage = parse_obj(CUBE, "cube.obj").unwrap();
    for weights in [shepard(), bone_heat(), bbw()] {
        let (scene, setup) = setup(&cage, 2, weights);
        let samples = ComparisonSamples::new(&setup, 2).unwrap();
        let c = compare_subdiv(&setup, &samples, &scene.pose(0).unwrap()).unwrap();
        for (name, r) in [("ours", &c.ours), ("naive", &c.naive)] {
            assert!(r.summary.max < EXACT_TOLERANCE, "{name}: {:?}", r.summary);
        }
        let mut rng = Rng(3);
        let t = rng.rigid([0.3, 0.2, 0.1], 1.0, 0.5);
        let t: Affine3 = std::array::from_fn(|r| {
            std::array::from_fn(|k| if k < 3 { 1.3 * t[r][k] } else { t[r][k] })
        });
        let c = compare_subdiv(&setup, &samples, &[t, t]).unwrap();
        for (name, r) in [("ours", &c.ours), ("naive", &c.naive)] {
            assert!(r.summary.max < EXACT_TOLERANCE, "{name}: {:?}", r.summary);
        }
        // And a pose that is not one common map is not exact for either.
        let other = rng.rigid([1.0, 1.0, 1.0], 1.0, 0.5);
        let c = compare_subdiv(&setup, &samples, &[AFFINE3_IDENTITY, other]).unwrap();
        assert!(c.naive.summary.max > 1e-3, "{:?}", c.naive.summary);
        assert!(c.ours.summary.rms < c.naive.summary.rms);
    }
}

#[test]
fn subdiv_compare_ours_beats_naive() {
    let Some(root) = common::data_root() else {
        return;
    };
    let out_dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("subdiv-compare");
    std::fs::create_dir_all(&out_dir).unwrap();
    println!(
        "{:<22} {:>6} {:>9} {:>7} {:>11} {:>11} {:>11} {:>11}",
        "shape", "verts", "weights", "handles", "ours max", "naive max", "ours rms", "naive rms"
    );
    let mut rng = Rng(2014);
    for (name, n_handles) in [
        ("catmark_torus", 2),
        ("catmark_torus", 3),
        ("catmark_torus_creases0", 2),
        ("catmark_torus_creases1", 3),
        ("catmark_toroidal_tet", 2),
        ("catmark_car", 2),
        ("catmark_car", 4),
    ] {
        let cage = read_obj(&root.join(format!("subdiv/shapes/{name}.obj"))).unwrap();
        let diag = cage.bounding_box_diagonal();
        for (family, weights) in [
            ("shepard", shepard()),
            ("bone_heat", bone_heat()),
            ("bbw", bbw()),
        ] {
            let (scene, setup) = setup(&cage, n_handles, weights);
            let samples = ComparisonSamples::new(&setup, DEFAULT_COMPARE_LEVEL).unwrap();
            let pose: Vec<Affine3> = (0..n_handles)
                .map(|i| rng.rigid(scene.handles.pivot(i), 0.6, 0.1 * diag))
                .collect();
            let c = compare_subdiv(&setup, &samples, &pose).unwrap();
            println!(
                "{name:<22} {:>6} {family:>9} {n_handles:>7} {:>11.3e} {:>11.3e} {:>11.3e} {:>11.3e}",
                cage.n_vertices(),
                c.ours.summary.max,
                c.naive.summary.max,
                c.ours.summary.rms,
                c.naive.summary.rms
            );
            assert!(
                c.ours.summary.rms < c.naive.summary.rms,
                "{name} {family} {n_handles}: rms {:?} vs {:?}",
                c.ours.summary,
                c.naive.summary
            );
            assert!(
                c.ours.summary.max < c.naive.summary.max,
                "{name} {family} {n_handles}: max {:?} vs {:?}",
                c.ours.summary,
                c.naive.summary
            );
            if name == "catmark_car" || (name == "catmark_torus" && n_handles == 3) {
                let png = render_comparison_png(&samples, &c, &ComparisonPictureOptions::default())
                    .unwrap();
                assert_eq!(&png[1..4], b"PNG");
                std::fs::write(
                    out_dir.join(format!("{name}-{family}-{n_handles}.png")),
                    png,
                )
                .unwrap();
            }
        }
    }
}
