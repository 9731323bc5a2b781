//! From a drawing to a deformation without writing JSON, through the binary:
//!
//! * `splineskin rig DRAWING.svg -o SCENE.json`: the scene reads back (its drawing named
//!   relative to the scene's folder, or inline), and `deform` of it at the rest pose gives the
//!   drawing back; automatic pins lie inside the drawing's filled shapes (by kurbo's winding
//!   number, independent of the placement's own test) and are spread (the covering bound of
//!   `splineskin::scene::pins`); `--pin` pins are kept bit for bit;
//! * `deform`, `animate` and `weights` of an SVG with `--pin`/`--move`/`--rotate`/`--scale`:
//!   the same result as the equivalent scene;
//! * bad input: each error names the flag or file and what was expected, and writes nothing.

mod common;

use common::measure::max_distance;
use std::path::{Path, PathBuf};

use common::cli::{assert_no_problems, failure_problems, ok_stderr, run, words};
use common::test_dir::TestDir;
use kurbo::{BezPath, Point, Shape};
use splineskin::drawing::{read_svg, read_svg_file, Drawing, ImportOptions};
use splineskin::scene::{MeshFamily, Scene, WeightSpec};

/// The bundled fish (made for this project).
fn fish() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../splineskin/assets/demo.svg")
}

/// A small drawing of our own: a 100 × 60 body with a 50 × 50 square beside it and an open
/// stroke (not a shape).
const BLOCKS: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 200 100">
  <path fill="#88c" d="M10 20 C40 10 80 10 110 20 L110 80 C80 90 40 90 10 80 Z"/>
  <rect x="140" y="25" width="50" height="50" fill="#c88"/>
  <path fill="none" stroke="black" d="M10 95 C60 99 120 99 190 95"/>
</svg>"##;

fn blocks_dir(name: &str) -> TestDir {
    let dir = TestDir::new(&format!("splineskin-rig-cli-{name}-"));
    std::fs::write(dir.join("blocks.svg"), BLOCKS).unwrap();
    dir
}

/// The deformed chain points of a `deform -o OUT.json`.
fn read_points(path: &Path) -> Vec<Point> {
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    v["paths"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|p| p["points"].as_array().unwrap().clone())
        .map(|q| Point::new(q[0].as_f64().unwrap(), q[1].as_f64().unwrap()))
        .collect()
}

/// The closed paths of `drawing` as kurbo paths, one per element of the source.
fn closed_shapes(drawing: &Drawing) -> Vec<BezPath> {
    let source = drawing.source.as_ref().unwrap();
    let mut shapes: Vec<(usize, BezPath)> = Vec::new();
    for (i, path) in drawing.paths.iter().enumerate() {
        if !path.closed {
            continue;
        }
        let element = source.element_of_path(i).unwrap();
        if shapes.last().is_none_or(|(e, _)| *e != element) {
            shapes.push((element, BezPath::new()));
        }
        let bez = &mut shapes.last_mut().unwrap().1;
        bez.move_to(path.points[0]);
        for j in 0..path.n_curves() {
            let c = path.curve(j);
            bez.curve_to(c.p1, c.p2, c.p3);
        }
        bez.close_path();
    }
    shapes.into_iter().map(|(_, b)| b).collect()
}

fn min_pairwise(pins: &[Point]) -> f64 {
    let mut d = f64::INFINITY;
    for (a, p) in pins.iter().enumerate() {
        for q in &pins[a + 1..] {
            d = d.min((*p - *q).hypot());
        }
    }
    d
}

/// Inset of automatic pins, in cells of the 256-cell grid, plus one cell of discretisation
/// (`splineskin::scene::pins::INSET_CELLS` + 1).
const ERODE_CELLS: f64 = 3.0;

#[test]
fn rig_scene_reads_back_and_deforms_at_rest_to_the_drawing() {
    let dir = TestDir::new("splineskin-rig-cli-fish-");
    std::fs::create_dir(dir.join("scenes")).unwrap();
    let fish = fish();
    // `splineskin rig FISH` with the arguments of `line`; its stderr.
    let rig_fish = |line: &str| {
        let mut args = vec!["rig", fish.to_str().unwrap()];
        args.extend(words(line));
        ok_stderr(&dir, &args)
    };
    let stderr = rig_fish("-o scenes/fish.json");
    assert!(stderr.contains("placed automatically"), "{stderr}");
    let text = std::fs::read_to_string(dir.join("scenes/fish.json")).unwrap();
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(json["splineskin_scene"], 1);
    // Named relative to the scene's folder, so the pair can move together.
    let svg = json["svg"].as_str().unwrap();
    assert!(svg.starts_with("../") && svg.ends_with("demo.svg"), "{svg}");
    assert!(json.get("svg_text").is_none());
    let scene = Scene::load(&dir.join("scenes/fish.json")).unwrap();
    assert_eq!(scene.weights, WeightSpec::Mesh(MeshFamily::Bbw));
    let drawing = read_svg_file(&fish, &ImportOptions::default()).unwrap();
    assert_eq!(scene.svg_text, std::fs::read_to_string(&fish).unwrap());
    let n = scene.handles.len();
    assert!((3..=6).contains(&n), "{n} pins");

    // Every pin inside one of the fish's filled shapes (odd winding: inside under either rule).
    let shapes = closed_shapes(&drawing);
    for p in &scene.handles {
        assert!(
            shapes.iter().any(|s| s.winding(*p) % 2 != 0),
            "pin {p:?} is on no filled shape"
        );
    }
    // Spread: n pins by farthest points over candidates covering at least the body's area
    // less a band of the inset along its outline are at least √(A / (n π)) − cell/√2 apart.
    let body = shapes
        .iter()
        .max_by(|a, b| a.area().abs().total_cmp(&b.area().abs()))
        .unwrap();
    let bounds = drawing.control_bounds().unwrap();
    let cell = bounds.width().max(bounds.height()) / 256.0;
    let area = body.area().abs() - body.perimeter(1e-3) * ERODE_CELLS * cell;
    let bound = (area / (n as f64 * std::f64::consts::PI)).sqrt() - cell;
    let spread = min_pairwise(&scene.handles);
    assert!(spread >= bound, "pins {spread} apart, bound {bound}");

    // deform at the rest pose reproduces the drawing (weights summing to one).
    ok_stderr(&dir, &words("deform scenes/fish.json -o rest.json"));
    let rest = read_points(&dir.join("rest.json"));
    let error = max_distance(&rest, &drawing.flat_points());
    assert!(
        error <= 1e-9 * drawing.diagonal(),
        "rest pose moved by {error}"
    );

    // --inline: the same scene with the document inside.
    rig_fish("-o inline.json --inline");
    let inline = Scene::load(&dir.join("inline.json")).unwrap();
    assert_eq!(inline.handles, scene.handles);
    assert_eq!(inline.svg_text, scene.svg_text);

    // --text-outlines: inline, the label as paths of its glyphs (14 outlines), same pins.
    rig_fish("-o outlined.json --text-outlines");
    let outlined = Scene::load(&dir.join("outlined.json")).unwrap();
    assert_eq!(outlined.handles, scene.handles);
    assert!(!outlined.svg_text.contains("<text"));
    assert!(outlined.svg_text.contains("<path id=\"label\""));
    let with_label = read_svg(&outlined.svg_text, &ImportOptions::default()).unwrap();
    assert_eq!(with_label.paths.len(), drawing.paths.len() + 14);
}

#[test]
fn rig_pins_land_on_each_shape_and_keep_given_ones() {
    let dir = blocks_dir("pins");
    ok_stderr(&dir, &words("rig blocks.svg -o auto.json --pins 4"));
    let scene = Scene::load(&dir.join("auto.json")).unwrap();
    assert_eq!(scene.handles.len(), 4);
    let body = |p: &Point| p.x > 10.0 && p.x < 110.0 && p.y > 20.0 && p.y < 80.0;
    let square = |p: &Point| p.x > 140.0 && p.x < 190.0 && p.y > 25.0 && p.y < 75.0;
    assert!(
        scene.handles.iter().all(|p| body(p) || square(p)),
        "{:?}",
        scene.handles
    );
    assert!(scene.handles.iter().any(square), "{:?}", scene.handles);
    // Shepard weights asked for; the drawing named by its file name, beside the scene.
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("auto.json")).unwrap()).unwrap();
    assert_eq!(json["svg"], "blocks.svg");

    // Given pins are kept exactly (off the art too), first; --pins adds automatic ones.
    ok_stderr(&dir, &words("rig blocks.svg -o mixed.json --pin 0.1,0.2 --pin -7.25,1e-3 --pins 3 --weights shepard"));
    let mixed = Scene::load(&dir.join("mixed.json")).unwrap();
    assert_eq!(mixed.handles.len(), 3);
    assert_eq!(mixed.handles[0], Point::new(0.1, 0.2));
    assert_eq!(mixed.handles[1], Point::new(-7.25, 1e-3));
    assert!(body(&mixed.handles[2]) || square(&mixed.handles[2]));
    assert_eq!(mixed.weights, WeightSpec::Shepard { exponent: 2.0 });
    // --pin alone: exactly those pins.
    ok_stderr(
        &dir,
        &words("rig blocks.svg -o given.json --pin 30,50 --pin 160,50"),
    );
    let given = Scene::load(&dir.join("given.json")).unwrap();
    assert_eq!(
        given.handles,
        vec![Point::new(30.0, 50.0), Point::new(160.0, 50.0)]
    );
}

/// The pose flags and the scene format's `{"translate", "rotate", "scale"}` are one pose, and an
/// SVG with flags is the scene `rig` writes for them.
#[test]
fn deform_svg_with_pins_equals_deform_of_the_scene() {
    let dir = blocks_dir("equivalent");
    let scene = r#"{"splineskin_scene": 1, "svg": "blocks.svg",
            "handles": [{"position": [30, 50]}, {"position": [90, 50]}, {"position": [165, 50]}],
            "weights": {"family": "{family}"},
            "pose": [{}, {"translate": [5, -3], "rotate": 15}, {"scale": [1.5, 0.5], "rotate": -20}]}"#;
    let flags = [
        "--pin",
        "30,50",
        "--pin",
        "90,50",
        "--pin",
        "165,50",
        "--move",
        "1:5,-3",
        "--rotate",
        "1:15",
        "--rotate",
        "2:-20",
        "--scale",
        "2:1.5,0.5",
    ];
    for family in ["shepard", "bbw"] {
        std::fs::write(dir.join("scene.json"), scene.replace("{family}", family)).unwrap();
        ok_stderr(&dir, &words("deform scene.json -o from-scene.svg"));
        let mut args = vec![
            "deform",
            "blocks.svg",
            "-o",
            "from-flags.svg",
            "--weights",
            family,
        ];
        args.extend(flags);
        let stderr = ok_stderr(&dir, &args);
        assert!(stderr.contains("pins 0 (30, 50) given"), "{stderr}");
        let a = std::fs::read_to_string(dir.join("from-scene.svg")).unwrap();
        let b = std::fs::read_to_string(dir.join("from-flags.svg")).unwrap();
        assert_eq!(a, b, "{family}");
        assert_ne!(a, BLOCKS, "{family}: nothing moved");
        // rig with the same flags writes that scene.
        let mut args = vec![
            "rig",
            "blocks.svg",
            "-o",
            "rigged.json",
            "--weights",
            family,
        ];
        args.extend(flags);
        ok_stderr(&dir, &args);
        ok_stderr(&dir, &words("deform rigged.json -o from-rig.svg"));
        let c = std::fs::read_to_string(dir.join("from-rig.svg")).unwrap();
        assert_eq!(a, c, "{family}");
    }
}

#[test]
fn deform_svg_without_pins_places_them_and_rests() {
    let dir = blocks_dir("auto");
    let stderr = ok_stderr(&dir, &words("deform blocks.svg -o rest.json"));
    assert!(stderr.contains("bbw weights"), "{stderr}");
    let drawing = read_svg(BLOCKS, &ImportOptions::default()).unwrap();
    let rest = read_points(&dir.join("rest.json"));
    assert!(max_distance(&rest, &drawing.flat_points()) <= 1e-9 * drawing.diagonal());
    // A move of an automatic pin moves the drawing.
    ok_stderr(
        &dir,
        &words("deform blocks.svg -o moved.json --move 0:4,4 --weights shepard"),
    );
    let moved = read_points(&dir.join("moved.json"));
    assert!(max_distance(&moved, &drawing.flat_points()) > 1.0);
}

#[test]
fn animate_svg_goes_to_the_pose_and_back() {
    let dir = blocks_dir("animate");
    let pose = [
        "--pin",
        "30,50",
        "--pin",
        "165,50",
        "--move",
        "1:0,20",
        "--weights",
        "shepard",
    ];
    let mut args = vec!["animate", "blocks.svg", "-o", "frames"];
    args.extend(pose);
    ok_stderr(&dir, &args);
    let mut args = vec!["deform", "blocks.svg", "-o", "posed.svg"];
    args.extend(pose);
    ok_stderr(&dir, &args);
    let frame = |name: &str| {
        read_svg_file(&dir.join(name), &ImportOptions::default())
            .unwrap()
            .flat_points()
    };
    let rest = read_svg(BLOCKS, &ImportOptions::default())
        .unwrap()
        .flat_points();
    // 30 fps over 2 s: frames 0..=60; rest at 0 and 60, the pose at 30.
    assert!(dir.join("frames/frame-0060.svg").is_file());
    assert!(!dir.join("frames/frame-0061.svg").exists());
    assert!(max_distance(&frame("frames/frame-0000.svg"), &rest) < 1e-9);
    assert!(max_distance(&frame("frames/frame-0060.svg"), &rest) < 1e-9);
    let posed = frame("posed.svg");
    assert!(max_distance(&frame("frames/frame-0030.svg"), &posed) < 1e-9);
    assert!(max_distance(&posed, &rest) > 1.0);
}

#[test]
fn weights_of_an_svg_draw_its_pins() {
    let dir = blocks_dir("weights");
    let stderr = ok_stderr(
        &dir,
        &words("weights blocks.svg -o w.png --pins 3 --weights shepard"),
    );
    assert!(
        stderr.contains("shepard weights, 3 of 3 handles"),
        "{stderr}"
    );
    assert!(dir.join("w.png").is_file());
}

/// `--margin`: the body and the square of the blocks (30 units apart, a diagonal of about 200)
/// are separate parts with the default margin (a pin on the body leaves the square where its
/// own pin holds it), one part with a margin of a tenth of the diagonal (the square follows a
/// little); `rig` writes the margin into the scene.
#[test]
fn margin_joins_parts_closer_than_twice_it() {
    let dir = blocks_dir("margin");
    let square_moves = |extra: &[&str]| {
        let pins = ["--pin", "60,50", "--pin", "165,50"];
        let mut rest_args = vec!["deform", "blocks.svg", "-o", "rest.json"];
        rest_args.extend(pins);
        rest_args.extend(extra);
        ok_stderr(&dir, &rest_args);
        let mut args = vec!["deform", "blocks.svg", "-o", "out.json", "--move", "0:10,0"];
        args.extend(pins);
        args.extend(extra);
        ok_stderr(&dir, &args);
        let rest = read_points(&dir.join("rest.json"));
        let moved = read_points(&dir.join("out.json"));
        // The square's corner (140, 25).
        let d = |i: usize| (rest[i] - Point::new(140.0, 25.0)).hypot();
        let k = (0..rest.len())
            .min_by(|&a, &b| d(a).total_cmp(&d(b)))
            .unwrap();
        (moved[k] - rest[k]).hypot()
    };
    let apart = square_moves(&[]);
    let joined = square_moves(&["--margin", "0.1"]);
    assert!(apart < 1e-9, "{apart}");
    assert!(joined > 0.05, "{joined}");
    ok_stderr(
        &dir,
        &words("rig blocks.svg -o rigged.json --pin 60,50 --pin 165,50 --margin 0.1"),
    );
    let scene: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("rigged.json")).unwrap()).unwrap();
    assert_eq!(scene["domain"]["margin"], 0.1);
    assert_eq!(scene["domain"]["shape"], "art");
}

/// A failing run: stderr must hold every `expect` substring, and `output` must not exist.
struct Failure<'a> {
    name: &'a str,
    args: Vec<&'a str>,
    expect: &'a [&'a str],
    output: &'a str,
}

/// A case named `name` running `line` (split at whitespace), whose output is the argument
/// after `-o`.
fn failure<'a>(name: &'a str, line: &'a str, expect: &'a [&'a str]) -> Failure<'a> {
    let args: Vec<&str> = line.split_whitespace().collect();
    let output = args[args.iter().position(|&a| a == "-o").unwrap() + 1];
    Failure {
        name,
        args,
        expect,
        output,
    }
}

#[test]
fn rig_and_svg_inputs_refuse_bad_input_clearly() {
    let dir = blocks_dir("failures");
    std::fs::write(
        dir.join("empty.svg"),
        r#"<svg xmlns="http://www.w3.org/2000/svg"><title>nothing</title></svg>"#,
    )
    .unwrap();
    std::fs::write(dir.join("scene.json"), "{}").unwrap();
    std::fs::write(
        dir.join("real.json"),
        r#"{"splineskin_scene": 1, "svg": "blocks.svg", "handles": [{"position": [30, 50]}]}"#,
    )
    .unwrap();
    let cases = [
        failure(
            "nan pin",
            "rig blocks.svg -o out.json --pin nan,1",
            &["--pin", "nan", "not a finite number"],
        ),
        failure(
            "one number",
            "deform blocks.svg -o out.svg --pin 12",
            &["--pin", "expected X,Y"],
        ),
        failure(
            "not a number",
            "deform blocks.svg -o out.svg --pin 1,x",
            &["--pin", "'x' is not a number"],
        ),
        failure(
            "pin index out of range",
            "deform blocks.svg -o out.svg --pin 30,50 --pin 160,50 --move 2:1,1",
            &["--move 2", "there is no pin 2", "2 pins"],
        ),
        failure(
            "bad move",
            "deform blocks.svg -o out.svg --move a:1,1",
            &["--move", "'a' is not a pin index", "I:DX,DY"],
        ),
        failure(
            "rotated twice",
            "deform blocks.svg -o out.svg --rotate 0:5 --rotate 0:6",
            &["--rotate is given twice for pin 0"],
        ),
        failure(
            "same pin twice",
            "rig blocks.svg -o out.json --pin 30,50 --pin 30,50",
            &["--pin 30,50", "given twice"],
        ),
        failure(
            "nothing to pin",
            "rig empty.svg -o out.json",
            &["empty.svg", "nothing to pin"],
        ),
        failure(
            "zero pins",
            "rig blocks.svg -o out.json --pins 0",
            &["blocks.svg", "--pins", "expected a count from 1"],
        ),
        failure(
            "fewer pins than given",
            "rig blocks.svg -o out.json --pin 30,50 --pin 160,50 --pins 1",
            &["--pins", "1 pins asked for with 2 given", "from 2"],
        ),
        failure(
            "rig to svg",
            "rig blocks.svg -o out.svg",
            &["out.svg", "expected a name ending in .json"],
        ),
        failure(
            "rig of a scene",
            "rig real.json -o out.json",
            &["real.json", "expected an SVG drawing"],
        ),
        failure(
            "flags on a scene",
            "deform real.json -o out.svg --pin 1,1 --move 0:1,1",
            &["real.json", "--pin, --move apply to an SVG drawing"],
        ),
        failure(
            "not a scene",
            "deform scene.json -o out.svg",
            &["scene.json", "not a scene", "splineskin rig", "--pin X,Y"],
        ),
        failure(
            "animation without a pose",
            "animate blocks.svg -o out.svg --pins 3",
            &["blocks.svg", "nothing moves", "--move"],
        ),
        failure(
            "pins on a mesh",
            "weights --mesh mesh.json -o out.json --pin 1,1",
            &["mesh.json", "--pin applies to an SVG drawing"],
        ),
        failure(
            "margin out of range",
            "deform blocks.svg -o out.svg --pins 2 --margin 2",
            &["--margin", "0 to 1"],
        ),
        failure(
            "margin without a mesh",
            "rig blocks.svg -o out.json --pins 2 --weights shepard --margin 0.1",
            &["--margin", "shepard", "no domain"],
        ),
    ];
    let mut problems = Vec::new();
    for case in &cases {
        let out = run(&dir, &case.args);
        problems.extend(failure_problems(
            case.name,
            &case.args,
            &out,
            &dir,
            case.expect,
            case.output,
        ));
    }
    assert_no_problems(&problems, cases.len());
}

#[test]
fn deform_scale_strokes_scales_widths_only_when_asked() {
    let dir = blocks_dir("strokes");
    let mut args = vec![
        "deform",
        "blocks.svg",
        "-o",
        "plain.svg",
        "--weights",
        "shepard",
        "--pin",
        "30,50",
        "--pin",
        "90,50",
        "--pin",
        "165,50",
    ];
    for pin in ["0:2", "1:2", "2:2"] {
        args.extend(["--scale", pin]);
    }
    ok_stderr(&dir, &args);
    let plain = std::fs::read_to_string(dir.join("plain.svg")).unwrap();
    assert!(!plain.contains("stroke-width"), "{plain}");
    args[3] = "scaled.svg";
    args.push("--scale-strokes");
    ok_stderr(&dir, &args);
    let scaled = std::fs::read_to_string(dir.join("scaled.svg")).unwrap();
    // The open stroke (width 1, element 2) under every pin scaled by 2 about itself: the local
    // scale √|det| of the least-squares affine map of the Shepard skinning map over it.
    let drawing = read_svg(BLOCKS, &ImportOptions::default()).unwrap();
    let pins = [(30.0, 50.0), (90.0, 50.0), (165.0, 50.0)].map(Point::from);
    let field = splineskin::weights::Shepard::new(&pins, Default::default());
    let pose = pins.map(|p| kurbo::Affine::scale_about(2.0, p));
    let mut w = [0.0; 3];
    let maps = splineskin::drawing::follow::ElementMaps::from_map(
        &drawing,
        &mut |p| splineskin::naive::skin_point(&field, &pose, p, &mut w),
        &Default::default(),
    )
    .unwrap();
    let expected = splineskin::drawing::follow::local_scale(maps.element_map(2).unwrap());
    let width: f64 = scaled
        .split("stroke-width:")
        .nth(1)
        .and_then(|s| s.split('"').next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no stroke width: {scaled}"));
    assert!(
        (width - expected).abs() <= 1e-12 * expected,
        "{width} vs {expected}"
    );
    assert!(
        (1.2..2.0).contains(&width),
        "a scale by 2 shrunk by the pins' falloff: {width}"
    );
}
