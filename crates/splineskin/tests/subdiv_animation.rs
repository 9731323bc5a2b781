//! Animated subdivision scenes ([`SubdivScene::animation_frames`]) and their hand-off
//! ([`splineskin::subdiv::handoff`]): keyframes resolved by index, name or transforms; frames at
//! the keyframes equal to the keyframes' poses; rigid keyframes interpolated rigidly, and one
//! map on every handle reproduced by the fitted cage; errors naming the
//! element; USD and glTF writers refusing frames they cannot write.

use std::path::Path;

use splineskin::subdiv::handoff::{
    write_glb, write_usda, CageFrames, HandoffError, SurfaceFrames, UpAxis,
};
use splineskin::subdiv::{affine3_apply, parse_obj, Affine3, SubdivScene};

/// A box `[0, 2] × [0, 1] × [0, 1]` of two cells.
const BOX: &str = "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\n\
                   v 0 0 1\nv 1 0 1\nv 2 0 1\nv 0 1 1\nv 1 1 1\nv 2 1 1\n\
                   f 1 4 5 2\nf 2 5 6 3\nf 7 8 11 10\nf 8 9 12 11\n\
                   f 1 2 8 7\nf 2 3 9 8\nf 4 10 11 5\nf 5 11 12 6\nf 1 7 10 4\nf 3 6 12 9\n";

fn scene_text(animation: &str) -> String {
    format!(
        r#"{{"splineskin_subdiv_scene": 1, "obj": "box.obj",
  "handles": [{{"position": [-0.5, 0.5, 0.5]}}, {{"position": [2.5, 0.5, 0.5]}}],
  "poses": [{{"name": "lift", "transforms": [{{}}, {{"translate": [0, 1, 0]}}]}}],
  "animation": {animation}}}"#
    )
}

fn parse(animation: &str) -> Result<SubdivScene, String> {
    SubdivScene::parse(&scene_text(animation), "anim.json", Path::new(""))
        .map_err(|e| e.to_string())
}

fn close(a: &Affine3, b: &Affine3, tol: f64) -> bool {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .all(|(x, y)| (x - y).abs() <= tol)
}

#[test]
fn keyframes_resolve_by_index_name_and_transforms() {
    let scene = parse(
        r#"{"fps": 4, "keyframes": [
            {"time": 0, "pose": [{}, {}], "easing": "ease-in"},
            {"time": 0.5, "pose": "lift"},
            {"time": 1, "pose": 0}]}"#,
    )
    .unwrap();
    let frames = scene.animation_frames().unwrap();
    let times: Vec<f64> = frames.iter().map(|f| f.0).collect();
    assert_eq!(times, [0.0, 0.25, 0.5, 0.75, 1.0]);
    let lift = scene.pose(0).unwrap();
    assert!(
        close(&frames[2].1[1], &lift[1], 0.0),
        "a keyframe's pose exactly"
    );
    assert!(close(&frames[4].1[1], &lift[1], 0.0));
    // Ease-in at a quarter of the way... half of the segment's time: u = 0.25 of the lift.
    let p = affine3_apply(&frames[1].1[1], [2.5, 0.5, 0.5]);
    assert!((p[1] - 0.75).abs() < 1e-15, "{p:?}");
}

#[test]
fn errors_name_the_element() {
    let cases = [
        (
            r#"{"keyframes": [{"time": 0, "pose": "jump"}]}"#,
            "animation.keyframes[0].pose: no pose is named 'jump'",
        ),
        (
            r#"{"keyframes": [{"time": 0, "pose": 3}]}"#,
            "animation.keyframes[0].pose: pose 3",
        ),
        (
            r#"{"keyframes": [{"time": 0, "pose": [{}]}]}"#,
            "animation.keyframes[0].pose: 1 transforms; expected one per handle, 2",
        ),
        (
            r#"{"keyframes": [{"time": 0, "pose": 0, "easing": "bounce"}]}"#,
            "animation.keyframes[0].easing: 'bounce' is not an easing",
        ),
        (
            r#"{"fps": 0, "keyframes": [{"time": 0, "pose": 0}]}"#,
            "animation.fps: frame rate 0",
        ),
        (
            r#"{"keyframes": [{"time": 1, "pose": 0}, {"time": 0.5, "pose": 0}]}"#,
            "animation: keyframes[1]: time 0.5 is not after",
        ),
        (
            r#"{"keyframes": [{"time": 0, "pose": [{}, {"scale": [1, 0, 1]}]}]}"#,
            "animation: keyframes[0].transforms[1]",
        ),
        (
            r#"{"keyframes": [{"time": 0, "pose": [{}, {"rotate": {"axis": [0, 0, 0], "degrees": 9}}]}]}"#,
            "animation.keyframes[0].pose[1].rotate",
        ),
    ];
    for (animation, want) in cases {
        let message = parse(animation).unwrap_err();
        assert!(message.starts_with("anim.json: "), "{message}");
        assert!(message.contains(want), "{animation}: {message}");
    }
    let still = parse(r#"{"keyframes": [{"time": 0, "pose": 0}]}"#).unwrap();
    let message = still.animation_frames().unwrap_err().to_string();
    assert!(message.contains("lasts 0 s"), "{message}");
    let none = SubdivScene::parse(
        r#"{"splineskin_subdiv_scene": 1, "obj": "box.obj", "handles": [{"position": [0, 0, 0]}]}"#,
        "plain.json",
        Path::new(""),
    )
    .unwrap();
    let message = none.animation_frames().unwrap_err().to_string();
    assert!(
        message.contains("plain.json: animation: the scene has no animation"),
        "{message}"
    );
}

#[test]
fn rigid_keyframes_stay_rigid_and_one_map_on_every_handle_gives_that_map() {
    // Both handles turn a quarter about the z axis through (1, 0.5, 0.5) and rise by 1. Between
    // the keyframes each handle's map turns about its own pivot, so the two differ, but each
    // stays rigid; at the keyframes every handle has the one map and the fitted cage is the rest
    // cage under it.
    let cage = parse_obj(BOX, "box.obj").unwrap();
    let turn = r#"{"matrix": [[0, -1, 0, 1.5], [1, 0, 0, 0.5], [0, 0, 1, 1]]}"#;
    let scene = parse(&format!(
        r#"{{"fps": 10, "keyframes": [{{"time": 0, "pose": [{{}}, {{}}]}}, {{"time": 1, "pose": [{turn}, {turn}]}}]}}"#
    ))
    .unwrap();
    let setup = scene.setup_with(cage.clone()).unwrap();
    let frames = scene.animation_frames().unwrap();
    assert_eq!(frames.len(), 11);
    for (t, pose) in &frames {
        for a in pose {
            // RᵀR = I: the linear part is a rotation.
            for i in 0..3 {
                for j in 0..3 {
                    let dot: f64 = (0..3).map(|k| a[k][i] * a[k][j]).sum();
                    let want = if i == j { 1.0 } else { 0.0 };
                    assert!((dot - want).abs() < 1e-14, "t = {t}: {a:?}");
                }
            }
        }
    }
    let mut out = vec![[0.0; 3]; cage.n_vertices()];
    for (t, pose) in [&frames[0], &frames[10]] {
        assert_eq!(pose[0], pose[1], "t = {t}");
        setup.rig.update(pose, &mut out).unwrap();
        for (o, p) in out.iter().zip(cage.positions()) {
            let want = affine3_apply(&pose[0], *p);
            assert!(
                (0..3).all(|k| (o[k] - want[k]).abs() < 1e-9),
                "t = {t}: {o:?} vs {want:?}"
            );
        }
    }
    // Halfway, the handle at (2.5, 0.5, 0.5) has turned an eighth.
    let mid = &frames[5].1[1];
    let h = std::f64::consts::FRAC_1_SQRT_2;
    assert!(
        (mid[0][0] - h).abs() < 1e-14 && (mid[1][0] - h).abs() < 1e-14,
        "{mid:?}"
    );
}

#[test]
fn writers_refuse_frames_they_cannot_write() {
    let cage = parse_obj(BOX, "box.obj").unwrap();
    let rest = cage.positions().to_vec();
    let mut bad = rest.clone();
    bad[3][1] = f64::NAN;
    let frames = |positions: &[Vec<[f64; 3]>], times: &[f64]| {
        write_usda(&CageFrames {
            cage: &cage,
            times,
            positions,
            fps: 10.0,
            name: "box",
            up: UpAxis::Z,
        })
    };
    assert!(matches!(
        frames(&[rest.clone(), bad.clone()], &[0.0, 0.1]),
        Err(HandoffError::NonFinite {
            frame: 1,
            vertex: 3,
            ..
        })
    ));
    assert!(matches!(
        frames(std::slice::from_ref(&rest), &[0.0, 0.1]),
        Err(HandoffError::Frames { .. })
    ));
    assert!(matches!(
        frames(&[rest.clone(), rest[..5].to_vec()], &[0.0, 0.1]),
        Err(HandoffError::PointCount {
            frame: 1,
            got: 5,
            expected: 12
        })
    ));
    assert!(matches!(
        frames(&[rest.clone(), rest.clone()], &[0.1, 0.1]),
        Err(HandoffError::Frames { .. })
    ));
    let usda = frames(&[rest.clone(), rest.clone()], &[0.0, 0.1]).unwrap();
    assert!(usda.contains("upAxis = \"Z\""));
    let too_many: Vec<Vec<[f64; 3]>> = vec![rest.clone(); 1001];
    let times: Vec<f64> = (0..1001).map(|k| k as f64).collect();
    let glb = write_glb(&SurfaceFrames {
        triangles: &[[0, 1, 2]],
        times: &times,
        positions: &too_many,
        name: "box",
        up: UpAxis::Y,
    });
    assert!(matches!(
        glb,
        Err(HandoffError::TooManyFrames {
            n_frames: 1001,
            max: 1000
        })
    ));
    let glb = write_glb(&SurfaceFrames {
        triangles: &[[0, 1, 99]],
        times: &[0.0],
        positions: &[rest],
        name: "box",
        up: UpAxis::Y,
    });
    assert!(matches!(glb, Err(HandoffError::Frames { .. })), "{glb:?}");
}
