//! Handle kinds through scenes (issue 4): bones and cages in our scene format, their weights,
//! poses and invariants, bad input, and the cached weights of [`Puppet`].
//!
//! Mesh families run on coarse domains (the scene's `domain` options) to keep the tests fast.

#[path = "common/measure.rs"]
mod measure;

use kurbo::{Affine, Point};
use measure::diagonal;
use splineskin::scene::{Bone, BoneTransform, Compat, Puppet, Scene, SceneError};
use splineskin::spline_fit::SplineRig;
use splineskin::weights::WeightField;

/// The drawing: an open cubic across the middle and a closed triangle below it, inside
/// `0..100 × 0..100`.
const SVG: &str = "<svg xmlns='http://www.w3.org/2000/svg' viewBox='0 0 100 100'>\
<path d='M10 50 C30 20 70 20 90 50'/><path d='M20 80 L50 60 L80 80 Z'/></svg>";

/// Coarse domain options: a few hundred vertices.
/// (The enclosing domain: these tests are about handle kinds on one connected domain; the
/// art-shaped one has its own tests, `art_domain.rs`.)
const COARSE: &str =
    r#""domain": {"max_area_fraction": 0.002, "samples_per_diagonal": 100, "shape": "enclosing"}"#;

/// Invariants hold to this fraction of the drawing's bounding-box diagonal: 1e-9. The fit is
/// exact for them (partition of unity; linear precision for the cage's weights), so what is
/// left is the rounding of the solves (about 1e-13 here).
const INVARIANT_TOLERANCE: f64 = 1e-9;

/// A scene of ours around `SVG` with the given JSON members (`"key": value, …`).
fn scene(members: &str) -> Result<Scene, SceneError> {
    let json = format!(
        r#"{{"splineskin_scene": 1, "svg_text": {}, {members}}}"#,
        serde_json::to_string(SVG).unwrap()
    );
    Scene::from_json(&json, "test.json", None)
}

/// Rest points and deformed points of `scene` by `pose`.
fn deform(scene: &Scene, pose: &[Affine]) -> (Vec<Point>, Vec<Point>) {
    let setup = scene.setup(Compat::None).expect("setup");
    let rig =
        SplineRig::precompute(&setup.drawing, setup.weights.as_ref(), &setup.options).expect("rig");
    let mut out = vec![Point::ZERO; rig.n_points()];
    rig.update(pose, &mut out).expect("update");
    (setup.drawing.flat_points(), out)
}

/// Largest distance between `map · rest[k]` and `out[k]`, as a fraction of the diagonal.
fn max_error(rest: &[Point], out: &[Point], map: impl Fn(usize, Point) -> Point) -> f64 {
    let d = diagonal(rest);
    rest.iter()
        .zip(out)
        .enumerate()
        .map(|(k, (&p, &q))| (map(k, p) - q).hypot() / d)
        .fold(0.0, f64::max)
}

/// Identity pose and one map `a` on every handle (as the handle's kind takes it: cage vertices
/// translate to `a · v`, which the scene does for a transform given to a cage vertex).
fn check_invariants(s: &Scene, a: Affine, label: &str) {
    let n = s.n_handles();
    let (rest, out) = deform(s, &vec![Affine::IDENTITY; n]);
    let e = max_error(&rest, &out, |_, p| p);
    assert!(
        e <= INVARIANT_TOLERANCE,
        "{label}: identity pose off by {e:e}"
    );
    let pose: Vec<Affine> = match &s.cage {
        None => vec![a; n],
        Some(cage) => cage.iter().map(|&v| Affine::translate(a * v - v)).collect(),
    };
    let (rest, out) = deform(s, &pose);
    let e = max_error(&rest, &out, |_, p| a * p);
    assert!(e <= INVARIANT_TOLERANCE, "{label}: one map off by {e:e}");
    // Control: a different map on one handle moves the result away from `a`.
    let mut other = pose.clone();
    other[0] = Affine::translate((5.0, 0.0)) * other[0];
    let (rest, out) = deform(s, &other);
    assert!(
        max_error(&rest, &out, |_, p| a * p) > 1e-3,
        "{label}: the control pose did not move anything"
    );
}

#[test]
fn scene_handles_bone_weight_is_one_along_the_bone() {
    for family in ["harmonic", "bbw"] {
        let s = scene(&format!(
            r#""handles": [{{"position": [10, 50]}}, {{"position": [90, 50]}}],
               "bones": [{{"ends": [[35, 45], [65, 40]]}}],
               "weights": {{"family": "{family}"}}, {COARSE}"#
        ))
        .unwrap();
        let setup = s.setup(Compat::None).unwrap();
        let domain = setup
            .domain
            .as_ref()
            .expect("a mesh family keeps its domain");
        assert!(
            domain.mesh.n_vertices() < 2000,
            "{}",
            domain.mesh.n_vertices()
        );
        let mut w = [0.0; 3];
        for k in 0..=20 {
            let p = Point::new(35.0, 45.0).lerp(Point::new(65.0, 40.0), k as f64 / 20.0);
            setup.weights.eval(p, &mut w);
            // Barycentric rounding of points on the bone's edges: 1e-12.
            assert!((w[2] - 1.0).abs() <= 1e-12, "{family}: w at {p:?} = {w:?}");
            assert!(
                w[0].abs() <= 1e-12 && w[1].abs() <= 1e-12,
                "{family}: {w:?}"
            );
        }
        // Off the bone the bone's weight drops: the check above can fail.
        setup.weights.eval(Point::new(50.0, 70.0), &mut w);
        assert!(w[2] < 0.99, "{family}: {w:?}");
    }
}

#[test]
fn scene_handles_bone_invariants() {
    let a = Affine::new([1.1, 0.2, -0.3, 0.9, 4.0, -7.0]);
    let rigid = Affine::rotate_about(0.4, (50.0, 50.0)).then_translate((3.0, -2.0).into());
    for family in [
        r#""shepard""#,
        r#""harmonic""#,
        r#""biharmonic""#,
        r#""bbw""#,
    ] {
        let domain = if family.contains("shepard") {
            String::new()
        } else {
            format!(", {COARSE}")
        };
        // Affine bones take any map.
        let s = scene(&format!(
            r#""handles": [{{"position": [10, 50]}}],
               "bones": [{{"ends": [[35, 45], [65, 40]], "transform": "affine"}},
                         {{"ends": [[65, 40], [85, 70]], "transform": "affine"}}],
               "weights": {{"family": {family}}}{domain}"#
        ))
        .unwrap();
        check_invariants(&s, a, &format!("{family} affine bones"));
        // Rigid bones take rotations and translations.
        let s = scene(&format!(
            r#""handles": [{{"position": [10, 50]}}],
               "bones": [{{"ends": [[35, 45], [65, 40]]}}, {{"ends": [[20, 60], [40, 75]]}}],
               "weights": {{"family": {family}}}{domain}"#
        ))
        .unwrap();
        assert_eq!(s.bones[0].transform, BoneTransform::Rigid);
        check_invariants(&s, rigid, &format!("{family} rigid bones"));
    }
}

/// The poses of a bone given by end points, against maps derived by hand.
///
/// Rest `p₀ = (10, 20)`, `p₁ = (10, 30)` (direction (0, 1), length 10); posed `q₀ = (40, 20)`,
/// `q₁ = (20, 20)` (direction (−1, 0), length 20). The rotation taking (0, 1) to (−1, 0) is
/// +90°, `R = [[0, −1], [1, 0]]`, SVG `(a, b, c, d) = (0, 1, −1, 0)`.
/// * rigid: `T(x) = q₀ + R (x − p₀)`: `(e, f) = q₀ − R p₀ = (40, 20) − (−20, 10) = (60, 10)`;
/// * affine: scale 2, `(a, b, c, d) = (0, 2, −2, 0)`, `(e, f) = (40, 20) − (−40, 20) = (80, 0)`.
#[test]
fn scene_handles_bone_pose_from_ends() {
    let s = scene(
        r#""bones": [{"ends": [[10, 20], [10, 30]]}, {"ends": [[60, 20], [60, 30]], "transform": "affine"}],
           "poses": [
             {"name": "ends", "transforms": [{"ends": [[40, 20], [20, 20]]}, {"ends": [[90, 20], [70, 20]]}]},
             {"name": "matrices", "transforms": [{"rotate": 90, "translate": [30, 0]}, [1, 0.5, 0, 2, 0, 0]]}
           ]"#,
    )
    .unwrap();
    let t = &s.poses[0].transforms;
    assert_eq!(t.len(), 2);
    let close = |got: Affine, want: [f64; 6]| {
        got.as_coeffs()
            .iter()
            .zip(want)
            .all(|(g, w)| (g - w).abs() <= 1e-13)
    };
    assert!(close(t[0], [0.0, 1.0, -1.0, 0.0, 60.0, 10.0]), "{t:?}");
    // The affine bone: rest (60, 20)–(60, 30), posed (90, 20)–(70, 20): scale 2,
    // (e, f) = q₀ − R₂ p₀ = (90, 20) − (−40, 120) = (130, −100).
    assert!(close(t[1], [0.0, 2.0, -2.0, 0.0, 130.0, -100.0]), "{t:?}");
    assert!((t[1] * Point::new(60.0, 30.0) - Point::new(70.0, 20.0)).hypot() < 1e-12);
    // Named parts turn about the bone's first end: +90° about (10, 20), then (30, 0).
    assert!(close(
        s.poses[1].transforms[0],
        [0.0, 1.0, -1.0, 0.0, 60.0, 10.0]
    ));
    // An affine bone takes any matrix as it is.
    assert_eq!(
        s.poses[1].transforms[1].as_coeffs(),
        [1.0, 0.5, 0.0, 2.0, 0.0, 0.0]
    );
    // A rigid bone refuses a matrix that scales.
    let e = scene(r#""bones": [{"ends": [[10, 20], [10, 30]]}], "pose": [[2, 0, 0, 2, 0, 0]]"#)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("poses[0].transforms[0] (bones[0])") && e.contains("rotation and translation"),
        "{e}"
    );
    // A rigid bone posed with coincident ends has no direction.
    let e =
        scene(r#""bones": [{"ends": [[10, 20], [10, 30]]}], "pose": [{"ends": [[5, 5], [5, 5]]}]"#)
            .unwrap_err()
            .to_string();
    assert!(e.contains("direction is undefined"), "{e}");
    // The library's own map agrees with the scene's.
    let bone = Bone {
        ends: [Point::new(10.0, 20.0), Point::new(10.0, 30.0)],
        transform: BoneTransform::Rigid,
    };
    assert_eq!(
        bone.posed_by_ends([Point::new(40.0, 20.0), Point::new(20.0, 20.0)])
            .unwrap(),
        t[0]
    );
}

/// A cage around the drawing (counter-clockwise: positive shoelace area).
const CAGE: &str = r#""cage": [[0, 0], [100, 0], [100, 100], [0, 100]]"#;

#[test]
fn scene_handles_cage_translation_and_local_move() {
    for family in ["mvc", "harmonic", "biharmonic", "bbw"] {
        let domain = if family == "mvc" {
            String::new()
        } else {
            format!(", {COARSE}")
        };
        let s = scene(&format!(
            r#"{CAGE}, "weights": {{"family": "{family}"}}{domain},
               "poses": [{{"cage_positions": [[7, -3], [107, -3], [107, 97], [7, 97]]}},
                         {{"cage_positions": [[0, 0], [100, 0], [130, 120], [0, 100]]}},
                         {{"transforms": [{{"position": [7, -3]}}, {{"translate": [7, -3]}},
                                          [1, 0, 0, 1, 7, -3], {{"position": [7, 97]}}]}}]"#
        ))
        .unwrap();
        assert_eq!(s.n_handles(), 4);
        // Three ways to write the same translation.
        assert_eq!(s.poses[0].transforms, s.poses[2].transforms, "{family}");
        let (rest, out) = deform(&s, &s.poses[0].transforms);
        let e = max_error(&rest, &out, |_, p| p + kurbo::Vec2::new(7.0, -3.0));
        assert!(
            e <= INVARIANT_TOLERANCE,
            "{family}: translation off by {e:e}"
        );
        // Moving corner 2 (100, 100) by (30, 20) moves the drawing near it more than far
        // from it, and in that direction.
        let (rest, out) = deform(&s, &s.poses[1].transforms);
        let moved = |k: usize| out[k] - rest[k];
        let near = (0..rest.len())
            .min_by(|&a, &b| {
                let d = |k: usize| (rest[k] - Point::new(100.0, 100.0)).hypot();
                d(a).total_cmp(&d(b))
            })
            .unwrap();
        let far = (0..rest.len())
            .min_by(|&a, &b| {
                let d = |k: usize| (rest[k] - Point::new(0.0, 0.0)).hypot();
                d(a).total_cmp(&d(b))
            })
            .unwrap();
        assert!(
            moved(near).hypot() > 3.0 * moved(far).hypot(),
            "{family}: near {:?} far {:?}",
            moved(near),
            moved(far)
        );
        assert!(moved(near).x > 1.0 && moved(near).y > 1.0, "{family}");
    }
}

#[test]
fn scene_handles_cage_invariants() {
    // Harmonic and mean value coordinates are linearly precise: one affine map on every cage
    // vertex maps the drawing (inside the cage) by it.
    let a = Affine::new([1.1, 0.2, -0.3, 0.9, 4.0, -7.0]);
    let s = scene(&format!(
        r#"{CAGE}, "weights": {{"family": "harmonic"}}, {COARSE}"#
    ))
    .unwrap();
    check_invariants(&s, a, "harmonic cage");
    let s = scene(&format!(r#"{CAGE}, "weights": {{"family": "mvc"}}"#)).unwrap();
    check_invariants(&s, a, "mvc cage");
    // A cage of six vertices, not convex, cutting through the drawing (the triangle's apex
    // (50, 60) is outside it): mean value coordinates are defined, and linearly precise,
    // outside the cage too.
    let s = scene(
        r#""cage": [[0, 0], [60, 10], [100, 0], [100, 100], [50, 55], [0, 100]],
           "weights": {"family": "mvc"}"#,
    )
    .unwrap();
    check_invariants(&s, a, "mvc non-convex cage");
    // Points and bones inside a cage: the cage's weights take the boundary, the others are 0
    // there; every invariant holds for translations.
    let s = scene(&format!(
        r#"{CAGE}, "handles": [{{"position": [50, 45]}}], "bones": [{{"ends": [[20, 40], [30, 60]]}}],
           "weights": {{"family": "harmonic"}}, {COARSE}"#
    ))
    .unwrap();
    assert_eq!(s.n_handles(), 6);
    let t = Affine::translate((3.0, 4.0));
    let (rest, out) = deform(&s, &[t; 6]);
    let e = max_error(&rest, &out, |_, p| t * p);
    assert!(e <= INVARIANT_TOLERANCE, "mixed cage: {e:e}");
    let (rest, out) = deform(&s, &[Affine::IDENTITY; 6]);
    assert!(max_error(&rest, &out, |_, p| p) <= INVARIANT_TOLERANCE);
}

/// The `harmonic` family on a cage alone is exactly the library's harmonic coordinates.
#[test]
fn scene_handles_harmonic_cage_is_harmonic_coordinates() {
    let s = scene(&format!(
        r#"{CAGE}, "weights": {{"family": "harmonic"}}, {COARSE}"#
    ))
    .unwrap();
    let setup = s.setup(Compat::None).unwrap();
    let domain = setup.domain.as_ref().unwrap();
    let reference = splineskin::weights::harmonic_coordinates(domain).unwrap();
    let field =
        splineskin::domain::MeshWeights::new(&domain.mesh, reference.into_values(), 4).unwrap();
    let (mut a, mut b) = ([0.0; 4], [0.0; 4]);
    for p in [(50.0, 50.0), (12.5, 80.25), (99.0, 1.0), (140.0, 30.0)] {
        setup.weights.eval(p.into(), &mut a);
        field.eval(p.into(), &mut b);
        assert_eq!(a, b, "at {p:?}");
    }
}

/// Errors of scenes, by the element they name.
#[test]
fn scene_handles_bad_input_names_the_element() {
    let cases: Vec<(&str, String, &[&str])> = vec![
        (
            "handle outside the cage",
            format!(r#"{CAGE}, "handles": [{{"position": [150, 50]}}], "weights": {{"family": "harmonic"}}, {COARSE}"#),
            &["handles[0]", "outside the domain"],
        ),
        (
            "bone outside the cage",
            format!(r#"{CAGE}, "bones": [{{"ends": [[50, 50], [150, 50]]}}], "weights": {{"family": "bbw"}}, {COARSE}"#),
            &["bones[0]", "not inside the domain"],
        ),
        (
            "handle on the cage",
            format!(r#"{CAGE}, "handles": [{{"position": [100, 50]}}], "weights": {{"family": "harmonic"}}, {COARSE}"#),
            &["handles[0]", "lies on the cage's edge 1 (from cage[1] to cage[2])"],
        ),
        (
            "coincident handles",
            r#""handles": [{"position": [10, 50]}, {"position": [20, 50]}, {"position": [10, 50]}]"#.into(),
            &["handles[0] and handles[2]", "coincide"],
        ),
        (
            "nearly coincident handles",
            format!(r#""handles": [{{"position": [10, 50]}}, {{"position": [10, 50.00000000001]}}], "weights": {{"family": "harmonic"}}, {COARSE}"#),
            &["handles[0] and handles[1]", "coincide"],
        ),
        (
            "crossing bones",
            format!(r#""bones": [{{"ends": [[10, 10], [90, 90]]}}, {{"ends": [[10, 90], [90, 10]]}}], "weights": {{"family": "harmonic"}}, {COARSE}"#),
            &["bones[0] and bones[1]", "intersect"],
        ),
        (
            "zero-length bone",
            r#""bones": [{"ends": [[10, 10], [10, 10]]}]"#.into(),
            &["bones[0]", "zero length"],
        ),
        (
            "self-intersecting cage",
            r#""cage": [[0, 0], [100, 100], [100, 0], [0, 100]], "weights": {"family": "harmonic"}"#.into(),
            &["cage[", "not simple"],
        ),
        (
            "clockwise cage",
            r#""cage": [[0, 0], [0, 100], [100, 100], [100, 0]], "weights": {"family": "harmonic"}"#.into(),
            &["cage", "clockwise", "reverse"],
        ),
        (
            "cage of two vertices",
            r#""cage": [[0, 0], [100, 0]], "weights": {"family": "harmonic"}"#.into(),
            &["cage", "at least 3"],
        ),
        (
            "cage repeating its first vertex",
            r#""cage": [[0, 0], [100, 0], [100, 100], [0, 0]], "weights": {"family": "harmonic"}"#.into(),
            &["cage[3]", "zero length"],
        ),
        (
            "huge cage vertex",
            r#""cage": [[0, 0], [1e300, 0], [0, 100]], "weights": {"family": "harmonic"}"#.into(),
            &["cage[1]", "not a finite position"],
        ),
        (
            "huge bone end",
            r#""bones": [{"ends": [[0, 0], [0, -1e300]]}]"#.into(),
            &["bones[0].ends[1]", "not a finite position"],
        ),
        (
            "shepard on a cage",
            CAGE.to_string(),
            &["weights", "not a cage"],
        ),
        (
            "mvc without a cage",
            r#""bones": [{"ends": [[10, 10], [20, 20]]}], "weights": {"family": "mvc"}"#.into(),
            &["weights", "cage's vertices only"],
        ),
        (
            "mvc with a clockwise cage",
            r#""cage": [[0, 0], [0, 100], [100, 100]], "weights": {"family": "mvc"}"#.into(),
            &["cage", "clockwise"],
        ),
        (
            "mvc with points",
            format!(r#"{CAGE}, "handles": [{{"position": [50, 50]}}], "weights": {{"family": "mvc"}}"#),
            &["weights", "cage's vertices only"],
        ),
        (
            "domain options with shepard",
            r#""handles": [{"position": [50, 50]}], "domain": {"min_angle": 20}"#.into(),
            &["domain", "mesh families"],
        ),
        (
            "min angle out of range",
            r#""handles": [{"position": [50, 50]}], "weights": {"family": "harmonic"}, "domain": {"min_angle": 50}"#.into(),
            &["domain.min_angle", "out of range"],
        ),
        (
            "unknown domain option",
            r#""handles": [{"position": [50, 50]}], "weights": {"family": "harmonic"}, "domain": {"min_angel": 20}"#.into(),
            &["unknown field `min_angel`"],
        ),
        (
            "unknown bone key",
            r#""bones": [{"ends": [[0, 0], [0, 10]], "kind": "rigid"}]"#.into(),
            &["unknown field `kind`"],
        ),
        (
            "unknown bone transform",
            r#""bones": [{"ends": [[0, 0], [0, 10]], "transform": "bendy"}]"#.into(),
            &["unknown variant `bendy`", "rigid"],
        ),
        (
            "ends for a point handle",
            r#""handles": [{"position": [50, 50]}], "pose": [{"ends": [[0, 0], [1, 1]]}]"#.into(),
            &["poses[0].transforms[0]", "\"ends\" poses a bone"],
        ),
        (
            "cage positions without a cage",
            r#""handles": [{"position": [50, 50]}], "poses": [{"transforms": [[1, 0, 0, 1, 0, 0]], "cage_positions": [[0, 0]]}]"#.into(),
            &["poses[0].cage_positions", "no cage"],
        ),
        (
            "wrong number of cage positions",
            format!(r#"{CAGE}, "weights": {{"family": "harmonic"}}, "poses": [{{"cage_positions": [[0, 0]]}}]"#),
            &["poses[0].cage_positions", "1 positions for 4 cage vertices"],
        ),
        (
            "too few transforms with kinds",
            format!(r#"{CAGE}, "handles": [{{"position": [50, 50]}}], "weights": {{"family": "harmonic"}}, "pose": [[1, 0, 0, 1, 0, 0]]"#),
            &["poses[0]", "1 transforms for 5 handles", "1 point handles, then 4 cage vertices"],
        ),
    ];
    let mut problems = Vec::new();
    for (label, members, expect) in &cases {
        let e = match scene(members).and_then(|s| s.setup(Compat::None).map(|_| ())) {
            Ok(()) => {
                problems.push(format!("{label}: accepted"));
                continue;
            }
            Err(e) => e.to_string(),
        };
        for want in expect.iter().chain(&["test.json"]) {
            if !e.contains(want) {
                problems.push(format!("{label}: {e:?} lacks {want:?}"));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// The empty domain: a drawing of one point, no cage.
#[test]
fn scene_handles_empty_domain() {
    let json = r#"{"splineskin_scene": 1,
        "svg_text": "<svg xmlns='http://www.w3.org/2000/svg'><path d='M10 10 L10 10'/></svg>",
        "handles": [{"position": [10, 10]}], "weights": {"family": "harmonic"}}"#;
    let e = Scene::from_json(json, "empty.json", None)
        .unwrap()
        .setup(Compat::None)
        .err()
        .map(|e| e.to_string());
    let e = e.expect("an empty domain is an error");
    assert!(
        e.contains("empty.json") && e.contains("empty domain"),
        "{e}"
    );
}

/// The puppet's cache: a pose change reuses weights and rig, a rest change recomputes both,
/// and the result is exactly that of a setup from scratch.
#[test]
fn scene_handles_puppet_caches_weights() {
    let members = |x: f64| {
        format!(
            r#""handles": [{{"position": [10, 50]}}, {{"position": [{x}, 50]}}],
               "bones": [{{"ends": [[35, 45], [65, 40]]}}],
               "weights": {{"family": "harmonic"}}, {COARSE}"#
        )
    };
    let s = scene(&members(90.0)).unwrap();
    let mut puppet = Puppet::from_scene(&s, Compat::None).unwrap();
    assert_eq!(puppet.stats().weight_builds, 1);
    assert_eq!(puppet.stats().rig_builds, 1);
    let mut out = vec![Point::ZERO; puppet.n_points()];
    let pose = [
        Affine::translate((1.0, 2.0)),
        Affine::rotate_about(0.3, (90.0, 50.0)),
        Affine::rotate_about(-0.2, (35.0, 45.0)),
    ];
    for k in 0..5 {
        puppet
            .set_transform(1, Affine::rotate_about(0.1 * k as f64, (90.0, 50.0)))
            .unwrap();
        puppet.update(&mut out).unwrap();
    }
    puppet.set_pose(&pose).unwrap();
    puppet.update(&mut out).unwrap();
    let stats = puppet.stats();
    assert_eq!(
        (stats.weight_builds, stats.rig_builds, stats.updates),
        (1, 1, 6)
    );
    assert!(!puppet.is_stale());
    let before = out.clone();

    // Setting a handle where it is changes nothing.
    puppet.set_point_handle(1, Point::new(90.0, 50.0)).unwrap();
    assert!(!puppet.is_stale());
    // A refused edit (onto another handle) changes nothing either.
    let e = puppet
        .set_point_handle(1, Point::new(10.0, 50.0))
        .unwrap_err();
    assert!(e.to_string().contains("handles[0] and handles[1]"), "{e}");
    assert!(!puppet.is_stale());
    assert_eq!(puppet.handles().points[1], Point::new(90.0, 50.0));

    // The rest change: stale until the next update, which recomputes both once.
    puppet.set_point_handle(1, Point::new(85.0, 50.0)).unwrap();
    assert!(puppet.is_stale() && puppet.weights().is_none() && puppet.rig().is_none());
    puppet.update(&mut out).unwrap();
    puppet.update(&mut out).unwrap();
    let stats = puppet.stats();
    assert_eq!(
        (stats.weight_builds, stats.rig_builds, stats.updates),
        (2, 2, 8)
    );
    assert_ne!(out, before, "the rest change changed the result");

    // From scratch on the edited scene: exactly the same points.
    let edited = scene(&members(85.0)).unwrap();
    let (_, scratch) = deform(&edited, &pose);
    assert_eq!(out, scratch);
    let mut fresh = Puppet::from_scene(&edited, Compat::None).unwrap();
    fresh.set_pose(&pose).unwrap();
    let mut fresh_out = vec![Point::ZERO; fresh.n_points()];
    fresh.update(&mut fresh_out).unwrap();
    assert_eq!(out, fresh_out);
    assert_eq!(
        puppet.domain().unwrap().mesh.vertices,
        fresh.domain().unwrap().mesh.vertices
    );

    // Fit options: the rig only.
    let options = puppet
        .fit_options()
        .with_measure(splineskin::spline_fit::Measure::ArcLength);
    puppet.set_fit_options(options);
    assert!(puppet.weights().is_some() && puppet.rig().is_none());
    puppet.update(&mut out).unwrap();
    let stats = puppet.stats();
    assert_eq!((stats.weight_builds, stats.rig_builds), (2, 3));

    // Adding and removing a handle: the pose follows, weights are recomputed.
    let i = puppet.add_point_handle(Point::new(50.0, 90.0)).unwrap();
    assert_eq!(i, 2);
    assert_eq!(puppet.n_handles(), 4);
    assert_eq!(puppet.pose()[2], Affine::IDENTITY);
    assert_eq!(puppet.pose()[3], pose[2], "the bone's map moved to index 3");
    let mut out4 = vec![Point::ZERO; puppet.n_points()];
    puppet.update(&mut out4).unwrap();
    assert_eq!(puppet.stats().weight_builds, 3);
    puppet.remove_point_handle(2).unwrap();
    assert_eq!(puppet.pose(), &pose[..]);
    // The family: recomputed; the same family again: nothing.
    puppet
        .set_weights(splineskin::scene::WeightSpec::Shepard { exponent: 2.0 })
        .unwrap();
    puppet.update(&mut out).unwrap();
    assert_eq!(puppet.stats().weight_builds, 4);
    puppet
        .set_weights(splineskin::scene::WeightSpec::Shepard { exponent: 2.0 })
        .unwrap();
    assert!(!puppet.is_stale());
    assert!(puppet.domain().is_none(), "Shepard has no domain");
}

/// A puppet with flexible junctions: its first update is exactly the flexible solver's cold
/// solve, a small drag is warm-started from the previous frame and lands where a cold solve of
/// the new pose does (to the iteration's tolerance), pose changes rebuild nothing, and turning
/// flexible off gives exactly the rig's fixed-ratio result.
#[test]
fn scene_handles_puppet_flexible_junctions() {
    use splineskin::spline_fit::quadrature::SampledCurves;
    use splineskin::spline_fit::{FlexibleOptions, FlexibleSolver};
    // A G1 S-curve (outgoing tangent twice the incoming) and two point handles.
    let json = r#"{"splineskin_scene": 1, "flexible": true,
        "svg_text": "<svg xmlns='http://www.w3.org/2000/svg'><path d='M0 0 C30 40 70 40 100 0 C160 -80 170 -40 200 0'/></svg>",
        "handles": [{"position": [0, 0]}, {"position": [200, 0]}]}"#;
    let s = Scene::from_json(json, "flex.json", None).unwrap();
    let mut puppet = Puppet::from_scene(&s, Compat::None).unwrap();
    assert!(puppet.flexible().is_some());
    let setup = s.setup(Compat::None).unwrap();
    let samples = SampledCurves::sample(&setup.drawing, setup.weights.as_ref(), &setup.options);
    let solver = FlexibleSolver::new(
        &setup.drawing,
        &samples,
        &setup.options,
        FlexibleOptions::default(),
    )
    .unwrap();
    assert!(solver.n_flexible_junctions() > 0);
    let pose = |a: f64| [Affine::IDENTITY, Affine::rotate_about(a, (200.0, 0.0))];
    let n = puppet.n_points();
    let (mut out, mut cold) = (vec![Point::ZERO; n], vec![Point::ZERO; n]);

    puppet.set_pose(&pose(0.6)).unwrap();
    puppet.update(&mut out).unwrap();
    let report = solver.solve(&pose(0.6), None, &mut cold).unwrap();
    assert_eq!(out, cold, "first update: the cold flexible solve");
    assert!(
        report.energy() < report.fixed_ratio_energy,
        "flexible lowers the energy"
    );

    // A small drag: warm-started, close to the cold solve of the new pose.
    puppet.set_pose(&pose(0.62)).unwrap();
    puppet.update(&mut out).unwrap();
    solver.solve(&pose(0.62), None, &mut cold).unwrap();
    let size = 200.0;
    let gap = out
        .iter()
        .zip(&cold)
        .map(|(a, b)| (*a - *b).hypot())
        .fold(0.0, f64::max);
    assert!(gap < 1e-3 * size, "warm vs cold: {gap}");
    assert_eq!(puppet.stats().rig_builds, 1);
    assert_eq!(puppet.stats().weight_builds, 1);

    // Flexible off: the rig's fixed-ratio result exactly, after one rig rebuild.
    puppet.set_flexible(None);
    puppet.update(&mut out).unwrap();
    let mut fixed = vec![Point::ZERO; n];
    solver.rig().update(&pose(0.62), &mut fixed).unwrap();
    assert_eq!(out, fixed);
    assert_eq!(puppet.stats().rig_builds, 2);
    assert_eq!(puppet.stats().weight_builds, 1);
    assert_ne!(
        fixed, cold,
        "the flexible result differs from the fixed-ratio one"
    );
}

/// A puppet refuses a scene whose engine is a naive baseline (rather than silently deforming
/// it with the rig), naming the element.
#[test]
fn scene_handles_puppet_refuses_naive_engines() {
    let json = r#"{"splineskin_scene": 1, "engine": "jacobian",
        "svg_text": "<svg xmlns='http://www.w3.org/2000/svg'><path d='M0 0 C1 1 2 1 3 0'/></svg>",
        "handles": [{"position": [0, 0]}]}"#;
    let s = Scene::from_json(json, "naive.json", None).unwrap();
    let e = Puppet::from_scene(&s, Compat::None).err().expect("refused");
    let text = e.to_string();
    assert!(
        text.contains("naive.json") && text.contains("engine") && text.contains("'jacobian'"),
        "{text}"
    );
}

/// Harmonic and biharmonic weights sum to 1 at every vertex of the domain to the last bits
/// (their rows are divided by their sums after the solve, whose own rounding leaves a few
/// hundred ulps on large domains): what makes the identity come back exactly for a path far
/// smaller than its distance to the origin.
#[test]
fn scene_handles_mesh_weights_partition_unity_to_rounding() {
    for family in ["harmonic", "biharmonic"] {
        let s = scene(&format!(
            r#""handles": [{{"position": [10, 50]}}, {{"position": [90, 50]}}, {{"position": [50, 75]}}],
               "bones": [{{"ends": [[35, 45], [65, 40]]}}],
               "weights": {{"family": "{family}"}}"#
        ))
        .unwrap();
        let setup = s.setup(Compat::None).unwrap();
        let domain = setup
            .domain
            .as_ref()
            .expect("a mesh family keeps its domain");
        let h = setup.weights.n_handles();
        let mut w = vec![0.0; h];
        let mut worst: f64 = 0.0;
        for &v in &domain.mesh.vertices {
            setup.weights.eval(v, &mut w);
            worst = worst.max((w.iter().sum::<f64>() - 1.0).abs());
        }
        assert!(
            worst <= h as f64 * f64::EPSILON,
            "{family}: rows sum to 1 within {worst:e} ({} ulps) on {} vertices",
            worst / f64::EPSILON,
            domain.mesh.n_vertices()
        );
    }
}
