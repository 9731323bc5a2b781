//! Keyframe animation ([`splineskin::animation`]) and the animated SVG
//! ([`splineskin::drawing::svg_animate`]): the decomposition round-trips, interpolation is exact
//! at keyframes and turns (not shrinks) between them, frames at keyframes equal the deformed
//! pose, the animated document has one `<animate>` per deformed element with one value per
//! frame, the authors' zooming animation loads and animates, and scene errors name the element.

#[path = "common/external_data.rs"]
mod external_data;

use std::f64::consts::PI;

use kurbo::{Affine, Point, Vec2};
use splineskin::animation::{
    deform_frames, interpolate_map, AffineParts, Animation, AnimationError, Easing, Keyframe,
};
use splineskin::drawing::svg_animate::write_animated_svg;
use splineskin::drawing::svg_out::write_svg;
use splineskin::scene::{Compat, Scene, Setup};
use splineskin::spline_fit::SplineRig;

/// Round-off of composing a decomposed map with entries of order 1–10: a few ulps times the
/// entries; 1e-12 leaves room and still catches any wrong sign or swapped factor.
const EXACT: f64 = 1e-12;

/// A small deterministic generator (64-bit LCG), values in `[lo, hi)`.
struct Lcg(u64);
impl Lcg {
    fn next(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }
}

fn max_diff(a: Affine, b: Affine) -> f64 {
    a.as_coeffs()
        .iter()
        .zip(b.as_coeffs())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// `scene` set up in default mode, and the rig of its drawing and weights.
fn setup_and_rig(scene: &Scene) -> (Setup, SplineRig) {
    let setup = scene.setup(Compat::None).unwrap();
    let rig =
        SplineRig::precompute(&setup.drawing, setup.weights.as_ref(), &setup.options).unwrap();
    (setup, rig)
}

#[test]
fn animation_decompose_round_trips_including_reflections() {
    let mut rng = Lcg(7);
    let (mut n_reflections, mut n) = (0, 0);
    while n < 2000 {
        let m = Affine::new([
            rng.next(-3.0, 3.0),
            rng.next(-3.0, 3.0),
            rng.next(-3.0, 3.0),
            rng.next(-3.0, 3.0),
            rng.next(-50.0, 50.0),
            rng.next(-50.0, 50.0),
        ]);
        if m.determinant().abs() < 1e-3 {
            continue;
        }
        n += 1;
        let pivot = Point::new(rng.next(-20.0, 20.0), rng.next(-20.0, 20.0));
        let parts = AffineParts::decompose(m, pivot).unwrap();
        assert!(parts.scale.x > 0.0);
        // The reflection lives in the sign of s_y, and only there.
        assert_eq!(parts.scale.y < 0.0, m.determinant() < 0.0, "{m:?}");
        n_reflections += usize::from(m.determinant() < 0.0);
        assert!(parts.angle > -PI && parts.angle <= PI);
        assert!(
            max_diff(parts.compose(pivot), m) < EXACT,
            "{m:?}: {:?}",
            parts.compose(pivot)
        );
        assert!((m * pivot - parts.pivot_image).hypot() < EXACT);
    }
    assert!(n_reflections > 500, "{n_reflections} reflections in {n}");
    assert!(
        AffineParts::decompose(Affine::new([1.0, 2.0, 2.0, 4.0, 0.0, 0.0]), Point::ZERO).is_none()
    );
    assert!(AffineParts::decompose(
        Affine::new([f64::NAN, 0.0, 0.0, 1.0, 0.0, 0.0]),
        Point::ZERO
    )
    .is_none());
}

/// Random invertible maps for `n_handles` handles.
fn random_pose(rng: &mut Lcg, n_handles: usize) -> Vec<Affine> {
    (0..n_handles)
        .map(|_| {
            Affine::translate(Vec2::new(rng.next(-40.0, 40.0), rng.next(-40.0, 40.0)))
                * Affine::rotate(rng.next(-PI, PI))
                * Affine::scale_non_uniform(rng.next(0.5, 2.0), rng.next(-2.0, -0.5))
        })
        .collect()
}

#[test]
fn animation_exact_at_keyframes_with_uneven_times() {
    let mut rng = Lcg(11);
    let times = [0.0, 0.1, 0.35, 1.0, 1.05, 3.0];
    let keys: Vec<Keyframe> = times
        .iter()
        .map(|&time| Keyframe::new(time, random_pose(&mut rng, 3)))
        .collect();
    let a = Animation::new(30.0, keys.clone()).unwrap();
    let pivots = [
        Point::new(1.0, 2.0),
        Point::new(-5.0, 3.0),
        Point::new(9.0, 9.0),
    ];
    let sampler = a.sampler(&pivots).unwrap();
    let mut pose = vec![Affine::IDENTITY; 3];
    for k in &keys {
        sampler.pose_at(k.time, &mut pose);
        assert_eq!(pose, k.transforms, "t = {}", k.time);
    }
    // Held outside the keyframes.
    sampler.pose_at(-1.0, &mut pose);
    assert_eq!(pose, keys[0].transforms);
    sampler.pose_at(7.0, &mut pose);
    assert_eq!(pose, keys[5].transforms);
    // Between keyframes: u is measured in the segment's own length (uneven spacing).
    sampler.pose_at(1.025, &mut pose);
    for (i, &c) in pivots.iter().enumerate() {
        let want = interpolate_map(keys[3].transforms[i], keys[4].transforms[i], c, 0.5).unwrap();
        assert!(max_diff(pose[i], want) < EXACT);
    }
}

#[test]
fn animation_halfway_between_rotations_is_the_half_angle_turn() {
    let c = Point::new(30.0, -10.0);
    for (from, to) in [
        (0.0, 0.5 * PI),
        (0.2, 1.4),
        (0.9 * PI, -0.9 * PI),
        (0.0, PI),
    ] {
        let a = Affine::rotate_about(from, c);
        let b = Affine::rotate_about(to, c);
        let half = interpolate_map(a, b, c, 0.5).unwrap();
        let mut turn = to - from;
        if turn > PI {
            turn -= 2.0 * PI;
        } else if turn <= -PI {
            turn += 2.0 * PI;
        }
        let want = Affine::rotate_about(from + 0.5 * turn, c);
        assert!(max_diff(half, want) < EXACT, "{from} -> {to}: {half:?}");
        // A rotation: unit determinant, pivot fixed.
        assert!((half.determinant() - 1.0).abs() < EXACT);
        assert!((half * c - c).hypot() < EXACT);
    }
    // Control: lerping the matrix entries of a half turn collapses the drawing to a point.
    let (a, b) = (Affine::rotate_about(0.0, c), Affine::rotate_about(PI, c));
    let lerp: Vec<f64> = a
        .as_coeffs()
        .iter()
        .zip(b.as_coeffs())
        .map(|(x, y)| 0.5 * (x + y))
        .collect();
    let lerped = Affine::new([lerp[0], lerp[1], lerp[2], lerp[3], lerp[4], lerp[5]]);
    assert!(lerped.determinant().abs() < 1e-15);
    let ours = interpolate_map(a, b, c, 0.5).unwrap();
    assert!((ours.determinant() - 1.0).abs() < EXACT);
    // Scales interpolate geometrically: halfway between ×1 and ×4 is ×2.
    let s = interpolate_map(Affine::IDENTITY, Affine::scale(4.0), Point::ZERO, 0.5).unwrap();
    assert!(max_diff(s, Affine::scale(2.0)) < EXACT);
}

/// A segment's easing changes only how far along it the pose is: at elapsed fraction `u` the
/// pose is the linear segment's pose at `e(u)`, for each easing of a scene file; a hold keeps
/// the first keyframe's maps bit for bit until the next keyframe's time.
#[test]
fn animation_easing_reparametrises_the_segment() {
    let c = Point::new(12.0, -3.0);
    let from = Affine::rotate_about(0.3, c) * Affine::scale(1.5);
    let to = Affine::translate((40.0, 7.0)) * Affine::rotate_about(-1.1, c);
    type Curve = fn(f64) -> f64;
    let easings: [(&str, Curve); 5] = [
        ("linear", |u: f64| u),
        ("ease-in", |u: f64| u * u),
        ("ease-out", |u: f64| 1.0 - (1.0 - u) * (1.0 - u)),
        ("ease-in-out", |u: f64| 3.0 * u * u - 2.0 * u * u * u),
        ("hold", |u: f64| if u < 1.0 { 0.0 } else { 1.0 }),
    ];
    for (name, e) in easings {
        let easing = Easing::from_name(name).unwrap();
        let mut first = Keyframe::new(0.5, vec![from]);
        first.easing = easing;
        let a = Animation::new(30.0, vec![first, Keyframe::new(2.5, vec![to])]).unwrap();
        let sampler = a.sampler(&[c]).unwrap();
        let mut pose = [Affine::IDENTITY];
        for u in [0.0, 0.1, 0.25, 0.5, 0.8, 0.99, 1.0] {
            sampler.pose_at(0.5 + 2.0 * u, &mut pose);
            let want = interpolate_map(from, to, c, e(u)).unwrap();
            assert!(
                max_diff(pose[0], want) < EXACT,
                "{name} at u = {u}: {:?} vs {want:?}",
                pose[0]
            );
        }
        if easing == Easing::Hold {
            sampler.pose_at(2.4999, &mut pose);
            assert_eq!(pose[0], from);
        }
    }
    // The easing shows in a scene file, on the segment after its keyframe.
    let scene = demo_scene(
        r#"{"keyframes": [{"time": 0, "pose": 0, "easing": "ease-in"}, {"time": 1, "pose": 1}]}"#,
    )
    .unwrap();
    let keys = scene.animation.unwrap();
    assert_eq!(keys.keyframes()[0].easing, Easing::EaseIn);
    assert_eq!(keys.keyframes()[1].easing, Easing::Linear);
}

/// The demo fish with an animation of uneven keyframes (inline, by index and by name).
fn demo_scene(animation: &str) -> Result<Scene, splineskin::scene::SceneError> {
    let mut json: serde_json::Value =
        serde_json::from_str(splineskin::examples::DEMO_SCENE).unwrap();
    let obj = json.as_object_mut().unwrap();
    obj.remove("svg");
    obj.insert("svg_text".into(), splineskin::examples::DEMO_SVG.into());
    obj.insert("animation".into(), serde_json::from_str(animation).unwrap());
    Scene::from_json(&json.to_string(), "fish.json", None)
}

const FISH_ANIMATION: &str = r#"{"fps": 8, "keyframes": [
    {"time": 0, "pose": [{}, {}, {}, {}, {}]},
    {"time": 0.25, "pose": "swish"},
    {"time": 1.0, "pose": 1},
    {"time": 1.5, "pose": {"transforms": [{}, {}, {"rotate": 170}, {}, {}]}}]}"#;

#[test]
fn animation_frames_at_keyframes_equal_the_deformed_pose() {
    let scene = demo_scene(FISH_ANIMATION).unwrap();
    let animation = scene.animation.clone().unwrap();
    assert_eq!(animation.keyframes().len(), 4);
    assert_eq!(animation.fps(), 8.0);
    // The keyframes by name and index are the scene's poses.
    assert_eq!(
        animation.keyframes()[1].transforms,
        scene.poses[0].transforms
    );
    assert_eq!(
        animation.keyframes()[2].transforms,
        scene.poses[1].transforms
    );
    let (setup, rig) = setup_and_rig(&scene);
    let times = animation.frame_times().unwrap();
    assert_eq!(times.len(), 13);
    let sampler = animation.sampler(&scene.handle_set().pivots()).unwrap();
    let frames = deform_frames(&sampler, &times, rig.n_points(), true, |pose, out| {
        rig.update(pose, out)
    })
    .unwrap();
    let mut checked = 0;
    for (f, &t) in times.iter().enumerate() {
        let Some(key) = animation.keyframes().iter().find(|k| k.time == t) else {
            continue;
        };
        let mut want = vec![Point::ZERO; rig.n_points()];
        rig.update(&key.transforms, &mut want).unwrap();
        let err = frames[f]
            .iter()
            .zip(&want)
            .map(|(a, b)| (*a - *b).hypot())
            .fold(0.0, f64::max);
        assert!(err < EXACT, "frame {f} at {t} s: {err:e}");
        checked += 1;
    }
    assert_eq!(checked, 4);
    // Frame 0 is the identity pose: the drawing itself (the fit reproduces it).
    let rest = setup.drawing.flat_points();
    let err = frames[0]
        .iter()
        .zip(&rest)
        .map(|(a, b)| (*a - *b).hypot())
        .fold(0.0, f64::max);
    assert!(err < 1e-9, "{err:e}");
    // Between keyframes something moves.
    assert!(frames[1]
        .iter()
        .zip(&frames[0])
        .any(|(a, b)| (*a - *b).hypot() > 0.1));

    // The animated document.
    let svg = write_animated_svg(&setup.drawing, &frames, &times).unwrap();
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let still = write_svg(&setup.drawing, &frames[0]).unwrap();
    let still_doc = roxmltree::Document::parse(&still).unwrap();
    let animated_paths: Vec<_> = doc
        .descendants()
        .filter(|n| n.has_tag_name("path"))
        .collect();
    let still_paths: Vec<_> = still_doc
        .descendants()
        .filter(|n| n.has_tag_name("path"))
        .collect();
    assert_eq!(animated_paths.len(), still_paths.len());
    let n_elements = setup.drawing.source.as_ref().unwrap().n_elements();
    let animates: Vec<_> = doc
        .descendants()
        .filter(|n| n.has_tag_name("animate"))
        .collect();
    assert_eq!(animates.len(), n_elements);
    for (path, still) in animated_paths.iter().zip(&still_paths) {
        let anim: Vec<_> = path
            .children()
            .filter(|n| n.has_tag_name("animate"))
            .collect();
        if anim.is_empty() {
            // Not a deformed element (e.g. in <defs>): unchanged.
            assert_eq!(path.attribute("d"), still.attribute("d"));
            continue;
        }
        assert_eq!(anim.len(), 1);
        let a = anim[0];
        assert_eq!(a.attribute("attributeName"), Some("d"));
        assert_eq!(a.attribute("repeatCount"), Some("indefinite"));
        assert_eq!(a.attribute("dur"), Some("1.5s"));
        let values: Vec<&str> = a.attribute("values").unwrap().split(';').collect();
        assert_eq!(values.len(), frames.len());
        let key_times: Vec<f64> = a
            .attribute("keyTimes")
            .unwrap()
            .split(';')
            .map(|v| v.parse().unwrap())
            .collect();
        assert_eq!(key_times.len(), frames.len());
        assert_eq!((key_times[0], key_times[12]), (0.0, 1.0));
        assert_eq!(key_times[6], 0.5);
        let commands = |d: &str| {
            d.chars()
                .filter(|c| c.is_ascii_alphabetic())
                .collect::<String>()
        };
        let numbers = |d: &str| {
            d.split(|c: char| c.is_ascii_alphabetic() || c == ' ')
                .filter(|s| !s.is_empty())
                .count()
        };
        for v in &values {
            assert_eq!(commands(v), commands(values[0]));
            assert_eq!(numbers(v), numbers(values[0]));
        }
        // The first value and the static `d` are the first frame's geometry, as the still
        // export writes it.
        assert_eq!(Some(values[0]), still.attribute("d"));
        assert_eq!(path.attribute("d"), still.attribute("d"));
    }
}

/// The authors' "zooming animation" (one handle, 1200 recorded frames): loads with its frames as
/// keyframes 1/30 s apart, and a frame at a keyframe is the drawing mapped by that frame's
/// affine map (one handle: every weight is 1, so the fit is exactly that map).
#[test]
fn animation_authors_turtles_zooming() {
    let Some(root) = external_data::shared_data() else {
        return;
    };
    let path = root.join(
        "vectorskinning/turtle-seven-stack/zooming animation/after-zoomout/turtles-seven-deformation2.json",
    );
    let scene = Scene::load(&path).unwrap();
    let animation = scene.animation.clone().unwrap();
    assert_eq!(animation.keyframes().len(), 1200);
    assert_eq!(animation.keyframes()[30].time, 1.0);
    assert_eq!(animation.duration(), 1199.0 / 30.0);
    // Keyframe k is the file's animationFrames[k] (pose k + 1).
    assert_eq!(
        animation.keyframes()[599].transforms,
        scene.poses[600].transforms
    );
    let (setup, rig) = setup_and_rig(&scene);
    let sampler = animation.sampler(&scene.handle_set().pivots()).unwrap();
    let times = [0.0, 599.0 / 30.0, 19.99, 1199.0 / 30.0];
    let frames = deform_frames(&sampler, &times, rig.n_points(), false, |pose, out| {
        rig.update(pose, out)
    })
    .unwrap();
    let rest = setup.drawing.flat_points();
    for (f, &t) in times.iter().enumerate() {
        let mut pose = [Affine::IDENTITY];
        sampler.pose_at(t, &mut pose);
        let zoom = pose[0].as_coeffs()[0];
        // Relative to the zoomed size (up to ×26 of a drawing ~500 units wide).
        let scale = 500.0 * zoom.abs().max(1.0);
        let err = frames[f]
            .iter()
            .zip(&rest)
            .map(|(q, p)| (*q - pose[0] * *p).hypot())
            .fold(0.0, f64::max);
        assert!(err < 1e-9 * scale, "t = {t}: {err:e}");
    }
    // Frame 599 is the 26× zoom of the file.
    let mut pose = [Affine::IDENTITY];
    sampler.pose_at(599.0 / 30.0, &mut pose);
    assert_eq!(pose[0].as_coeffs()[0], 26.3113393432659);
}

#[test]
fn animation_scene_errors_name_the_element() {
    let err = |animation: &str| demo_scene(animation).unwrap_err().to_string();
    let e = err(r#"{"keyframes": []}"#);
    assert!(e.contains("fish.json: animation: no keyframes"), "{e}");
    let e = err(
        r#"{"keyframes": [{"time": 0, "pose": 0}, {"time": 1, "pose": 1}, {"time": 1, "pose": 2}]}"#,
    );
    assert!(
        e.contains("fish.json: animation: keyframes[2]: time 1 is not after keyframes[1]'s 1"),
        "{e}"
    );
    let e = err(r#"{"keyframes": [{"time": 0, "pose": 7}]}"#);
    assert!(
        e.contains(
            "fish.json: animation.keyframes[0].pose: pose 7 does not exist (the scene has 3"
        ),
        "{e}"
    );
    let e = err(r#"{"keyframes": [{"time": 0, "pose": "dive"}]}"#);
    assert!(
        e.contains("animation.keyframes[0].pose: no pose is named 'dive'"),
        "{e}"
    );
    let e = err(r#"{"keyframes": [{"time": 0, "pose": [{}, {}]}]}"#);
    assert!(
        e.contains("animation.keyframes[0].pose: 2 transforms for 5"),
        "{e}"
    );
    let e = err(r#"{"keyframes": [{"time": -1, "pose": 0}]}"#);
    assert!(
        e.contains("animation: keyframes[0]: time -1 is not a finite"),
        "{e}"
    );
    let e = err(r#"{"keyframes": [{"time": 0, "pose": 0, "easing": "bounce"}]}"#);
    assert!(
        e.contains("animation.keyframes[0].easing: 'bounce' is not an easing (expected one of linear, ease-in, ease-out, ease-in-out, hold)"),
        "{e}"
    );
    let e = err(r#"{"fps": 0, "keyframes": [{"time": 0, "pose": 0}]}"#);
    assert!(e.contains("animation.fps: frame rate 0"), "{e}");
    let e = err(r#"{"keyframes": [{"time": 0, "pose": [[1, 2, 2, 4, 0, 0], {}, {}, {}, {}]}]}"#);
    assert!(
        e.contains("animation: keyframes[0].transforms[0]: [1.0, 2.0, 2.0, 4.0, 0.0, 0.0] is not finite or its linear part is singular"),
        "{e}"
    );
    // NaN cannot be written in JSON; the library refuses it.
    let key = |time: f64| Keyframe::new(time, vec![Affine::IDENTITY]);
    assert!(matches!(
        Animation::new(30.0, vec![key(0.0), key(f64::NAN)]),
        Err(AnimationError::Time { keyframe: 1, .. })
    ));
    assert!(matches!(
        Animation::new(f64::NAN, vec![key(0.0)]),
        Err(AnimationError::Fps { .. })
    ));
    assert_eq!(
        Animation::<Affine>::new(30.0, vec![]),
        Err(AnimationError::NoKeyframes)
    );
}
