//! The bundled demo drawing and scene (`assets/demo.svg`, `assets/demo-scene.json`): the scene
//! loads, names the bundled SVG, and has the handles and poses it promises; the SVG parses and
//! contains the features it exists to show.

#[path = "common/measure.rs"]
mod measure;

use std::path::Path as FsPath;

use splineskin::drawing::svg_in::{read_svg, ImportOptions};
use splineskin::drawing::JointKind;
use splineskin::examples::{DEMO_SCENE, DEMO_SVG};
use splineskin::scene::{Scene, SceneFormat, WeightSpec};

fn assets_dir() -> &'static FsPath {
    FsPath::new(concat!(env!("CARGO_MANIFEST_DIR"), "/assets"))
}

#[test]
fn demo_scene_loads_with_its_handles_and_poses() {
    let scene = Scene::from_json(DEMO_SCENE, "demo-scene.json", Some(assets_dir())).unwrap();
    assert_eq!(scene.format, SceneFormat::Ours);
    assert_eq!(scene.svg_text, DEMO_SVG);
    assert_eq!(scene.weights, WeightSpec::Shepard { exponent: 2.0 });
    scene.check_supported().unwrap();
    assert_eq!(scene.handles.len(), 5);
    // Every handle lies on the 600 × 400 canvas.
    for h in &scene.handles {
        assert!(
            (0.0..=600.0).contains(&h.x) && (0.0..=400.0).contains(&h.y),
            "{h:?}"
        );
    }
    let names: Vec<_> = scene.poses.iter().map(|p| p.name.as_deref()).collect();
    assert_eq!(names, [Some("swish"), Some("nose-up"), Some("flap")]);
    for pose in &scene.poses {
        assert_eq!(pose.transforms.len(), scene.handles.len());
        // Each pose moves at least one handle, by rotations of at most 35°.
        assert!(pose
            .transforms
            .iter()
            .any(|t| *t != kurbo::Affine::IDENTITY));
        for t in &pose.transforms {
            let [a, b, ..] = t.as_coeffs();
            assert!(b.atan2(a).abs() <= 35f64.to_radians(), "{t:?}");
        }
    }
}

#[test]
fn demo_svg_parses_with_its_elements() {
    let tree = usvg::Tree::from_str(DEMO_SVG, &usvg::Options::default()).unwrap();
    assert_eq!((tree.size().width(), tree.size().height()), (600.0, 400.0));
    let mut ids = Vec::new();
    collect_path_ids(tree.root(), &mut ids);
    for id in [
        "tail",
        "dorsal-fin",
        "anal-fin",
        "body",
        "stripe",
        "scale-1",
        "scale-2",
        "scale-3",
        "gill",
        "pectoral-fin",
        "mouth",
        "eye",
        "pupil",
        "bubble-1",
        "bubble-2",
        "plate",
    ] {
        assert!(ids.iter().any(|i| i == id), "no path '{id}' in {ids:?}");
    }
    for needle in [
        "<linearGradient",
        "<g id=\"scales\"",
        "transform=",
        "<circle",
        "<ellipse",
        "rx=\"10\"",
        "<text",
    ] {
        assert!(DEMO_SVG.contains(needle), "{needle}");
    }
}

#[test]
fn demo_svg_imports_with_every_joint_kind() {
    use JointKind::{End, FixedAngle, C0, C1, G1};
    let drawing = read_svg(DEMO_SVG, &ImportOptions::default()).unwrap();
    // Eleven path elements (the scales' group holds three), four circles/ellipses, one rect.
    assert_eq!(drawing.paths.len(), 16);
    assert_eq!(drawing.n_curves(), 58);
    // The body: two corners at the tail stalk, G¹ junctions with unequal handles around the
    // back and head, and an exact C¹ one (integer points, equal handles) under the belly.
    assert_eq!(drawing.paths[3].joints, [C0, G1, G1, G1, G1, C1, C0]);
    // The dorsal fin's squared-off tip is an exact right angle.
    assert_eq!(drawing.paths[1].joints, [C0, FixedAngle, C0]);
    // The stripe's two edges bend with exact C¹ junctions.
    assert_eq!(drawing.paths[4].joints, [C0, C1, C0, C0, C1, C0]);
    // The gill is an open stroke with one G¹ bend.
    assert_eq!(drawing.paths[8].joints, [End, G1, End]);
    let count = |kind| measure::joint_count(&drawing, kind);
    assert!(count(G1) >= 6 && count(C1) >= 3 && count(C0) >= 6 && count(FixedAngle) >= 1);
}

fn collect_path_ids(group: &usvg::Group, out: &mut Vec<String>) {
    for node in group.children() {
        match node {
            usvg::Node::Group(g) => collect_path_ids(g, out),
            usvg::Node::Path(p) => out.push(p.id().to_string()),
            _ => {}
        }
    }
}
