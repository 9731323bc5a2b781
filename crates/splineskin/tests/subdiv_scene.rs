//! Subdivision scenes read from files ([`splineskin::subdiv::SubdivScene`]): paths relative to
//! the scene, the three weight families set up into a rig that reproduces the cage under the
//! identity pose, and errors naming the scene, the OBJ or the weight file.

mod common;

use common::test_dir::TestDir;
use splineskin::subdiv::{SubdivScene, SubdivSceneError};

/// A box `[0, 2] × [0, 1] × [0, 1]` of two cells; vertex 2 is at (2, 0, 0).
const BOX: &str = "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\n\
                   v 0 0 1\nv 1 0 1\nv 2 0 1\nv 0 1 1\nv 1 1 1\nv 2 1 1\n\
                   f 1 4 5 2\nf 2 5 6 3\nf 7 8 11 10\nf 8 9 12 11\n\
                   f 1 2 8 7\nf 2 3 9 8\nf 4 10 11 5\nf 5 11 12 6\nf 1 7 10 4\nf 3 6 12 9\n";

fn scene(weights: &str, extra: &str) -> String {
    format!(
        r#"{{"splineskin_subdiv_scene": 1, "obj": "box.obj",
  "handles": [{{"position": [-0.5, 0.5, 0.5]}}],
  "bones": [{{"ends": [[1.2, 0.5, 0.5], [1.8, 0.5, 0.5]]}}],
  "weights": {weights},
  "poses": [{{"transforms": [{{}}, {{"rotate": {{"axis": [0, 1, 0], "degrees": 40}}}}]}}]{extra}}}"#
    )
}

fn write(dir: &TestDir, name: &str, text: &str) -> std::path::PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn subdiv_scene_families_set_up_and_reproduce_the_cage() {
    let dir = TestDir::new("splineskin-subdiv-scene-");
    write(&dir, "box.obj", BOX);
    let csv: String = (0..12)
        .map(|v| if v % 3 == 0 { "1, 0\n" } else { "0.5, 0.5\n" })
        .collect();
    write(&dir, "w.csv", &csv);
    for weights in [
        r#"{"family": "shepard", "exponent": 3}"#,
        r#"{"family": "bone_heat", "level": 3}"#,
        r#"{"family": "file", "path": "w.csv"}"#,
    ] {
        let path = write(&dir, "scene.json", &scene(weights, r#", "quadrature": 5"#));
        let scene = SubdivScene::load(&path).unwrap();
        assert_eq!(scene.quadrature, 5);
        let setup = scene.setup().unwrap();
        assert_eq!(setup.rig.n_handles(), 2);
        let mut out = vec![[0.0; 3]; setup.cage.n_vertices()];
        setup.rig.update(&scene.pose(0).unwrap(), &mut out).unwrap();
        // The pose turns the bone: the cage's far end (vertex 2, at x = 2) moves.
        let moved = (0..3)
            .map(|k| (out[2][k] - setup.cage.positions()[2][k]).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!(moved > 0.1, "{weights}: {moved}");
        let identity = vec![splineskin::subdiv::AFFINE3_IDENTITY; 2];
        setup.rig.update(&identity, &mut out).unwrap();
        for (o, p) in out.iter().zip(setup.cage.positions()) {
            for k in 0..3 {
                assert!((o[k] - p[k]).abs() < 1e-12, "{weights}");
            }
        }
    }
}

#[test]
fn subdiv_scene_errors_name_the_file() {
    let dir = TestDir::new("splineskin-subdiv-scene-errors-");
    // The message of setting up the scene `scene.json` written with `weights`.
    let setup_error = |weights: &str| {
        let path = write(&dir, "scene.json", &scene(weights, ""));
        SubdivScene::load(&path)
            .unwrap()
            .setup()
            .err()
            .unwrap()
            .to_string()
    };
    // The OBJ is missing.
    let path = write(&dir, "scene.json", &scene(r#"{"family": "shepard"}"#, ""));
    let scene_file = path.display().to_string();
    let err = SubdivScene::load(&path).unwrap().setup().err().unwrap();
    let message = err.to_string();
    assert!(
        matches!(err, SubdivSceneError::Obj { .. }) && message.contains("box.obj: cannot read"),
        "{message}"
    );
    assert!(message.starts_with(&scene_file), "{message}");
    // A bad OBJ: the OBJ's line is named.
    write(&dir, "box.obj", "v 0 0 0\nv 1 0 nan\nf 1 2 1\n");
    let message = setup_error(r#"{"family": "shepard"}"#);
    assert!(message.contains("box.obj:2"), "{message}");
    // A weight file with a NaN, and one that is missing.
    write(&dir, "box.obj", BOX);
    let csv: String = (0..12)
        .map(|v| if v == 7 { "NaN, 1\n" } else { "1, 0\n" })
        .collect();
    write(&dir, "w.csv", &csv);
    let message = setup_error(r#"{"family": "file", "path": "w.csv"}"#);
    assert!(
        message.contains("w.csv:8: column 1: weight NaN; expected a finite number ≥ 0"),
        "{message}"
    );
    let message = setup_error(r#"{"family": "file", "path": "missing.csv"}"#);
    assert!(message.contains("missing.csv: cannot read"), "{message}");
    // A missing scene.
    let message = SubdivScene::load(&dir.join("nope.json"))
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("nope.json: cannot read the scene"),
        "{message}"
    );
}

#[test]
fn subdiv_scene_on_the_car() {
    let Some(root) = common::data_root() else {
        return;
    };
    let dir = TestDir::new("splineskin-subdiv-scene-car-");
    let obj = root.join("subdiv/shapes/catmark_car.obj");
    let text = format!(
        r#"{{"splineskin_subdiv_scene": 1, "obj": {},
  "handles": [{{"position": [-2, 0.5, 0]}}, {{"position": [2, 0.5, 0]}}],
  "weights": {{"family": "bone_heat"}}}}"#,
        serde_json::to_string(&obj.display().to_string()).unwrap()
    );
    let path = write(&dir, "car.json", &text);
    let scene = SubdivScene::load(&path).unwrap();
    assert_eq!(scene.obj, obj, "an absolute OBJ path is kept");
    let setup = scene.setup().unwrap();
    assert_eq!(setup.cage.n_vertices(), 1642);
    let mut out = vec![[0.0; 3]; 1642];
    setup.rig.update(&scene.pose(0).unwrap(), &mut out).unwrap();
    let diag = setup.cage.bounding_box_diagonal();
    for (o, p) in out.iter().zip(setup.cage.positions()) {
        for k in 0..3 {
            assert!((o[k] - p[k]).abs() < 1e-12 * diag);
        }
    }
}

/// The bundled example (`assets/subdiv/tube-scene.json`, the pictures of docs/subdivision.md): it sets up,
/// and on both poses ours is closer to the skinned surface than naive, in max and RMS.
#[test]
fn subdiv_scene_bundled_tube() {
    let path = std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/subdiv/tube-scene.json"
    ));
    let scene = SubdivScene::load(path).unwrap();
    assert_eq!(scene.poses.len(), 2);
    let setup = scene.setup().unwrap();
    assert_eq!((setup.cage.n_vertices(), setup.cage.n_faces()), (72, 66));
    let samples = splineskin::subdiv::ComparisonSamples::new(&setup, 3).unwrap();
    for pose in 0..2 {
        let c = splineskin::subdiv::compare_subdiv(&setup, &samples, &scene.pose(pose).unwrap())
            .unwrap();
        assert!(
            c.ours.summary.max < c.naive.summary.max && c.ours.summary.rms < c.naive.summary.rms,
            "pose {pose}: {:?} vs {:?}",
            c.ours.summary,
            c.naive.summary
        );
    }
}
