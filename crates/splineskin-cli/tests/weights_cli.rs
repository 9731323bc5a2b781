//! `splineskin weights` through the binary, both modes:
//!
//! * `--mesh MESH.json --kind … -o OUT.json`: the weights it writes (against libigl's on the
//!   reference-igl meshes, and by their defining properties on a small mesh written here);
//! * `SCENE -o OUT.png`: the picture's size and panels (from the library's layout), the colour
//!   of pixels whose weight is known (1 and 0 at the handles of Shepard weights; the field
//!   evaluated by the library at harmonic weights' pixels), and that mesh lines and iso-lines
//!   change the picture;
//!
//! and clean failures on bad input — each names the file and the element, exits with status 1
//! without panicking, and leaves no output behind.

mod common;

use std::path::{Path, PathBuf};
use std::process::Output;

use common::cli::{assert_no_problems, failure_problems, run, words};
use common::test_dir::TestDir;
use kurbo::Point;
use serde::Deserialize;
use splineskin::scene::{Compat, Scene};
use splineskin::weight_map::colour_map::{viridis, weight_colour};
use splineskin::weight_map::{HandleMarker, RgbaImage, WeightMapLayout, WeightMapOptions};

/// A 3 × 2 grid of unit squares (12 vertices, 12 counter-clockwise triangles), as JSON
/// `"V"` and `"F"` arrays.
fn grid_mesh() -> (String, String) {
    let mut v = Vec::new();
    for y in 0..3 {
        for x in 0..4 {
            v.push(format!("[{x}, {y}]"));
        }
    }
    let mut f = Vec::new();
    for y in 0..2 {
        for x in 0..3 {
            let a = y * 4 + x;
            f.push(format!("[{a}, {}, {}]", a + 1, a + 5));
            f.push(format!("[{a}, {}, {}]", a + 5, a + 4));
        }
    }
    (format!("[{}]", v.join(", ")), format!("[{}]", f.join(", ")))
}

/// A mesh file with the grid's vertices and triangles replaced where given.
fn mesh_file(v: Option<&str>, f: Option<&str>, handles: &str) -> String {
    let (gv, gf) = grid_mesh();
    format!(
        r#"{{"mesh": {{"V": {}, "F": {}}}, "handles": {{"indices": {handles}}}}}"#,
        v.unwrap_or(&gv),
        f.unwrap_or(&gf)
    )
}

/// A fresh folder for one run (or, holding one folder per case, for a set of failing runs).
fn case_dir(name: &str) -> TestDir {
    TestDir::new(&format!("splineskin-weights-cli-{name}-"))
}

/// A fresh folder `name` in `root`, for one case of a set.
fn case_subdir(root: &Path, name: &str) -> PathBuf {
    let dir = root.join(name);
    std::fs::create_dir(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    dir
}

#[derive(Deserialize)]
struct WeightsOut {
    weights: Vec<Vec<f64>>,
}

fn read_weights(path: &Path) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(path).unwrap();
    serde_json::from_str::<WeightsOut>(&text).unwrap().weights
}

/// A failing case: `mesh` written to `mesh.json` (if any), then `args` run; stderr must hold
/// every `expect` substring.
struct Failure<'a> {
    name: &'a str,
    mesh: Option<String>,
    args: Vec<&'a str>,
    expect: Vec<&'a str>,
}

/// Checks a failed run: `Err` says what is wrong. `output` must not exist afterwards, nor a
/// temporary file of the atomic write.
fn check_failure(case: &Failure, dir: &Path, out: &Output, output: &str) -> Result<(), String> {
    let problems = failure_problems(case.name, &case.args, out, dir, &case.expect, output);
    if problems.is_empty() {
        Ok(())
    } else {
        Err(problems.join("\n"))
    }
}

fn run_failures(cases: Vec<Failure>) {
    let root = case_dir("failures");
    for case in &cases {
        case_subdir(&root, case.name);
    }
    run_failures_in_place(&root, cases);
}

/// [`run_failures`] in the case folders `root/NAME` as they are (files written there
/// beforehand stay).
fn run_failures_in_place(root: &Path, cases: Vec<Failure>) {
    let mut problems = Vec::new();
    for case in &cases {
        let dir = root.join(case.name);
        if let Some(mesh) = &case.mesh {
            std::fs::write(dir.join("mesh.json"), mesh).unwrap();
        }
        let out = run(&dir, &case.args);
        let output = case
            .args
            .iter()
            .position(|&a| a == "-o")
            .map_or("out.json", |k| case.args[k + 1]);
        match check_failure(case, &dir, &out, output) {
            Ok(()) => {
                let _ = std::fs::remove_dir_all(&dir);
            }
            Err(e) => problems.push(e),
        }
    }
    assert_no_problems(&problems, cases.len());
}

/// Every kind on the small grid: handles interpolated, rows summing to one (harmonic and
/// biharmonic weights of identity data do; BBW rows are normalised), BBW within [0, 1].
#[test]
fn weights_cli_small_mesh_every_kind() {
    let dir = case_dir("small");
    std::fs::write(dir.join("mesh.json"), mesh_file(None, None, "[0, 11, 5]")).unwrap();
    for kind in ["harmonic", "biharmonic", "bbw"] {
        let name = format!("{kind}.json");
        let out = run(
            &dir,
            &[
                "weights",
                "--mesh",
                "mesh.json",
                "--kind",
                kind,
                "-o",
                &name,
            ],
        );
        assert!(
            out.status.success(),
            "{kind}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let w = read_weights(&dir.join(&name));
        assert_eq!(w.len(), 12, "{kind}: one row per vertex");
        for (i, &v) in [0usize, 11, 5].iter().enumerate() {
            for j in 0..3 {
                assert_eq!(
                    w[v][j],
                    if i == j { 1.0 } else { 0.0 },
                    "{kind}: handle {i}"
                );
            }
        }
        for (v, row) in w.iter().enumerate() {
            assert_eq!(row.len(), 3);
            let sum: f64 = row.iter().sum();
            assert!((sum - 1.0).abs() < 1e-12, "{kind}: row {v} sums to {sum}");
            if kind == "bbw" {
                assert!(
                    row.iter().all(|x| (0.0..=1.0).contains(x)),
                    "{kind}: {row:?}"
                );
            }
        }
    }
}

/// The reference files themselves, as input: the output matches libigl's weights.
#[test]
fn weights_cli_reads_reference_igl_files() {
    let Some(data) = common::external_data::shared_data() else {
        return;
    };
    #[derive(Deserialize)]
    struct Reference {
        weights: ReferenceWeights,
    }
    #[derive(Deserialize)]
    struct ReferenceWeights {
        harmonic_k1: Matrix,
        harmonic_k2: Matrix,
        bbw_normalized: Matrix,
    }
    #[derive(Deserialize)]
    #[allow(non_snake_case)]
    struct Matrix {
        W: Vec<Vec<f64>>,
    }
    let dir = case_dir("reference");
    for shape in ["bar", "ushape"] {
        let input = data.join("reference-igl").join(format!("{shape}.json"));
        let text = std::fs::read_to_string(&input).unwrap();
        let reference: Reference = serde_json::from_str(&text).unwrap();
        // Tolerances of the library's conformance tests (crates/splineskin/tests/weights_igl.rs).
        for (kind, expected, tolerance) in [
            ("harmonic", &reference.weights.harmonic_k1.W, 1e-9),
            ("biharmonic", &reference.weights.harmonic_k2.W, 1e-9),
            ("bbw", &reference.weights.bbw_normalized.W, 1e-6),
        ] {
            let name = format!("{shape}-{kind}.json");
            let out = run(
                &dir,
                &[
                    "weights",
                    "--mesh",
                    input.to_str().unwrap(),
                    "--kind",
                    kind,
                    "-o",
                    &name,
                ],
            );
            assert!(
                out.status.success(),
                "{}",
                String::from_utf8_lossy(&out.stderr)
            );
            let w = read_weights(&dir.join(&name));
            assert_eq!(w.len(), expected.len());
            let worst = w
                .iter()
                .zip(expected)
                .flat_map(|(a, b)| a.iter().zip(b).map(|(x, y)| (x - y).abs()))
                .fold(0.0, f64::max);
            assert!(worst <= tolerance, "{shape} {kind}: max |Δ| = {worst:e}");
        }
    }
}

#[test]
fn weights_cli_bad_input_fails_cleanly() {
    let mesh_args = |kind: &'static str| {
        let mut args = words("weights --mesh mesh.json -o out.json --kind");
        args.push(kind);
        args
    };
    let tri = Some("[[0, 0], [1, 0], [0, 1]]");
    run_failures(vec![
        Failure {
            name: "missing-file",
            mesh: None,
            args: mesh_args("bbw"),
            expect: vec!["mesh.json", "cannot read"],
        },
        Failure {
            name: "bad-json",
            mesh: Some(r#"{"mesh": {"V": [[0, 0], "#.into()),
            args: mesh_args("bbw"),
            expect: vec!["mesh.json", "not a mesh file", "line 1"],
        },
        Failure {
            name: "no-handles-key",
            mesh: Some(r#"{"mesh": {"V": [], "F": []}}"#.into()),
            args: mesh_args("harmonic"),
            expect: vec!["mesh.json", "missing field `handles`"],
        },
        Failure {
            name: "handle-out-of-range",
            mesh: Some(mesh_file(None, None, "[0, 12]")),
            args: mesh_args("harmonic"),
            expect: vec!["mesh.json", "handles.indices[1] = 12", "12 vertices"],
        },
        Failure {
            name: "duplicate-handle",
            mesh: Some(mesh_file(None, None, "[3, 5, 3]")),
            args: mesh_args("bbw"),
            expect: vec![
                "mesh.json",
                "handles.indices[0] and handles.indices[2]",
                "vertex 3",
            ],
        },
        Failure {
            name: "no-handles",
            mesh: Some(mesh_file(None, None, "[]")),
            args: mesh_args("bbw"),
            expect: vec!["mesh.json", "handles.indices is empty"],
        },
        Failure {
            name: "non-finite-coordinate",
            mesh: Some(mesh_file(
                Some("[[0, 0], [1e400, 0], [0, 1]]"),
                Some("[[0, 1, 2]]"),
                "[0]",
            )),
            args: mesh_args("biharmonic"),
            expect: vec!["mesh.json", "number out of range", "line 1"],
        },
        Failure {
            name: "clockwise-triangle",
            mesh: Some(mesh_file(tri, Some("[[0, 2, 1]]"), "[0]")),
            args: mesh_args("harmonic"),
            expect: vec!["mesh.json", "mesh.F[0]", "counter-clockwise"],
        },
        Failure {
            name: "degenerate-triangle",
            mesh: Some(mesh_file(
                Some("[[0, 0], [1, 0], [0, 1], [2, 0]]"),
                Some("[[0, 1, 2], [0, 1, 3]]"),
                "[0]",
            )),
            args: mesh_args("harmonic"),
            expect: vec!["mesh.json", "mesh.F[1]", "signed area 0"],
        },
        Failure {
            name: "triangle-index-out-of-range",
            mesh: Some(mesh_file(tri, Some("[[0, 1, 7]]"), "[0]")),
            args: mesh_args("bbw"),
            expect: vec!["mesh.json", "mesh.F[0]", "index 7 out of range"],
        },
        Failure {
            name: "no-triangles",
            mesh: Some(mesh_file(tri, Some("[]"), "[0]")),
            args: mesh_args("bbw"),
            expect: vec!["mesh.json", "no triangles"],
        },
        Failure {
            name: "vertex-in-no-triangle",
            mesh: Some(mesh_file(
                Some("[[0, 0], [1, 0], [0, 1], [5, 5]]"),
                Some("[[0, 1, 2]]"),
                "[0]",
            )),
            args: mesh_args("bbw"),
            expect: vec!["mesh.json", "vertex 3 belongs to no triangle"],
        },
        Failure {
            name: "part-without-handle",
            mesh: Some(mesh_file(
                Some("[[0, 0], [1, 0], [0, 1], [5, 5], [6, 5], [5, 6]]"),
                Some("[[0, 1, 2], [3, 4, 5]]"),
                "[0, 1]",
            )),
            args: mesh_args("biharmonic"),
            expect: vec!["mesh.json", "vertex 3", "holds no handle"],
        },
        Failure {
            name: "output-not-json",
            mesh: Some(mesh_file(None, None, "[0, 11]")),
            args: words("weights --mesh mesh.json -o out.png"),
            expect: vec!["out.png", "written as JSON"],
        },
        Failure {
            name: "scene-and-mesh",
            mesh: Some(mesh_file(None, None, "[0, 11]")),
            args: words("weights scene.json --mesh mesh.json -o out.json"),
            expect: vec!["cannot be used with"],
        },
        Failure {
            name: "neither-scene-nor-mesh",
            mesh: None,
            args: words("weights -o out.json"),
            expect: vec!["required", "--mesh"],
        },
    ]);
}

/// An arc from (0, 0) to (100, 0) bulging up to y = 30 (SVG y points down), and two handles
/// on the x axis, about 24 units from it.
const ARC_SVG: &str =
    r#"<svg xmlns=\"http://www.w3.org/2000/svg\"><path d=\"M0 0 C30 40 70 40 100 0\"/></svg>"#;
const ARC_HANDLES: [Point; 2] = [Point::new(25.0, 0.0), Point::new(75.0, 0.0)];

/// Our scene format with the arc inline, its two handles and weights of `family`.
fn arc_scene(family: &str) -> String {
    let handles: Vec<String> = ARC_HANDLES
        .iter()
        .map(|p| format!(r#"{{"position": [{}, {}]}}"#, p.x, p.y))
        .collect();
    format!(
        r#"{{"splineskin_scene": 1, "svg_text": "{ARC_SVG}", "handles": [{}], "weights": {{"family": "{family}"}}}}"#,
        handles.join(", ")
    )
}

/// Runs `weights scene.json -o OUT …` in `dir`; the image, decoded.
fn draw(dir: &Path, output: &str, extra: &[&str]) -> (RgbaImage, String) {
    let mut args = vec!["weights", "scene.json", "-o", output];
    args.extend_from_slice(extra);
    let out = run(dir, &args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{args:?}: {stderr}");
    let png = std::fs::read(dir.join(output)).unwrap();
    (RgbaImage::decode_png(&png).unwrap(), stderr)
}

fn markers() -> Vec<HandleMarker> {
    ARC_HANDLES
        .iter()
        .map(|&p| HandleMarker::Point(p))
        .collect()
}

/// Two Shepard handles: two panels stacked (the arc's frame is wide), sized as the library's
/// layout says (and as worked out by hand: 232 × 244 at 220 px panels, see the library's
/// `weight_map_layout_by_hand`); in panel i the pixel at handle i has the map's top colour
/// (weight 1 − 5e-5 at its centre) and the pixel at the other handle its bottom colour.
/// `--handle 1` draws that panel alone.
#[test]
fn weights_cli_scene_shepard_panels() {
    let dir = case_dir("scene-shepard");
    std::fs::write(dir.join("scene.json"), arc_scene("shepard")).unwrap();
    let (image, stderr) = draw(&dir, "w.png", &["--width", "220"]);
    assert!(
        stderr.contains("shepard weights, 2 of 2 handles"),
        "{stderr}"
    );
    let scene = Scene::load(&dir.join("scene.json")).unwrap();
    let drawing = scene.drawing(Compat::None).unwrap();
    let options = WeightMapOptions::default().with_panel_width(220);
    let layout = WeightMapLayout::new(&drawing, &markers(), None, &options).unwrap();
    assert_eq!((image.width, image.height), (232, 244));
    assert_eq!((layout.width, layout.height), (232, 244));
    assert_eq!(layout.panels.len(), 2);
    for panel in 0..2 {
        for (i, &h) in ARC_HANDLES.iter().enumerate() {
            let want = if i == panel {
                viridis(1.0)
            } else {
                viridis(0.0)
            };
            let at = layout.to_pixel(panel, h).unwrap();
            assert_eq!(image.colour_at(at), Some(want), "panel {panel}, handle {i}");
        }
    }
    // Between the panels: the gutter, white.
    let gutter = Point::new(100.5, f64::from(layout.panels[1].y) - 3.0);
    assert_eq!(image.colour_at(gutter), Some([255, 255, 255]));

    let (one, _) = draw(&dir, "one.png", &["--width", "220", "--handle", "1"]);
    let layout =
        WeightMapLayout::new(&drawing, &markers(), None, &options.with_handle(Some(1))).unwrap();
    assert_eq!((one.width, one.height), (232, 244 - 104));
    assert_eq!((layout.width, layout.height), (one.width, one.height));
    let at = |h: Point| one.colour_at(layout.to_pixel(0, h).unwrap());
    assert_eq!(at(ARC_HANDLES[1]), Some(viridis(1.0)));
    assert_eq!(at(ARC_HANDLES[0]), Some(viridis(0.0)));
}

/// Harmonic weights (a mesh family, solved on the triangulated domain): pixels away from the
/// curves and markers have the colour of the library's field at their centre; mesh lines and
/// iso-lines change pixels inside the panels only, and the size stays the same.
#[test]
fn weights_cli_scene_harmonic_mesh_lines() {
    let dir = case_dir("scene-harmonic");
    std::fs::write(dir.join("scene.json"), arc_scene("harmonic")).unwrap();
    let (plain, stderr) = draw(&dir, "plain.png", &[]);
    assert!(stderr.contains("harmonic weights (domain of"), "{stderr}");
    assert!(
        stderr.contains(" vertices over the art (1 part"),
        "{stderr}"
    );
    let (meshed, _) = draw(&dir, "mesh.png", &["--mesh-lines"]);
    let (iso, _) = draw(&dir, "iso.png", &["--iso-lines"]);

    let scene = Scene::load(&dir.join("scene.json")).unwrap();
    let setup = scene.setup(Compat::None).unwrap();
    let mesh = setup.domain.as_ref().map(|d| &d.mesh);
    assert!(mesh.is_some());
    let layout = WeightMapLayout::new(
        &setup.drawing,
        &markers(),
        mesh,
        &WeightMapOptions::default(),
    )
    .unwrap();
    assert_eq!((plain.width, plain.height), (layout.width, layout.height));
    assert_eq!((meshed.width, meshed.height), (layout.width, layout.height));
    // Far from the arc and the handle rings (at least 8 units at 4.7 px per unit).
    let probes = [
        Point::new(50.0, 15.0),
        Point::new(50.0, -3.0),
        Point::new(10.0, 25.0),
        ARC_HANDLES[0],
        ARC_HANDLES[1],
    ];
    let mut w = vec![0.0; 2];
    for (panel, placement) in layout.panels.iter().enumerate() {
        for &p in &probes {
            let at = layout.to_pixel(panel, p).unwrap();
            let centre = layout.pixel_centre(
                (at.x.floor() as u32) - placement.x,
                (at.y.floor() as u32) - placement.y,
            );
            setup.weights.eval(centre, &mut w);
            let want = weight_colour(w[placement.handle]);
            assert_eq!(plain.colour_at(at), Some(want), "panel {panel} at {p:?}");
        }
    }
    let inside_panels = |x: u32, y: u32| {
        layout.panels.iter().any(|p| {
            (p.x..p.x + layout.panel_width).contains(&x)
                && (p.y..p.y + layout.panel_height).contains(&y)
        })
    };
    for (name, other) in [("mesh lines", &meshed), ("iso-lines", &iso)] {
        let mut n_changed = 0;
        for y in 0..plain.height {
            for x in 0..plain.width {
                if plain.pixel(x, y) != other.pixel(x, y) {
                    assert!(inside_panels(x, y), "{name} changed pixel ({x}, {y})");
                    n_changed += 1;
                }
            }
        }
        // The mesh has thousands of edges; nine iso-levels cross each panel.
        assert!(n_changed > 2000, "{name}: {n_changed} pixels changed");
    }
}

/// Bones and cage vertices are handles too: a bone gets a panel after the point handles (and
/// is in the frame), a cage's vertices one each; `--handle` counts them all.
#[test]
fn weights_cli_scene_bones_and_cage() {
    let dir = case_dir("scene-bones");
    let bone = [Point::new(60.0, -5.0), Point::new(90.0, -5.0)];
    let scene = format!(
        r#"{{"splineskin_scene": 1, "svg_text": "{ARC_SVG}", "handles": [{{"position": [25, 0]}}],
            "bones": [{{"ends": [[{}, {}], [{}, {}]]}}], "weights": {{"family": "shepard"}}}}"#,
        bone[0].x, bone[0].y, bone[1].x, bone[1].y
    );
    std::fs::write(dir.join("scene.json"), scene).unwrap();
    let (image, stderr) = draw(&dir, "w.png", &[]);
    assert!(stderr.contains("2 of 2 handles"), "{stderr}");
    let drawing = Scene::load(&dir.join("scene.json"))
        .unwrap()
        .drawing(Compat::None)
        .unwrap();
    let markers = [
        HandleMarker::Point(ARC_HANDLES[0]),
        HandleMarker::Segment(bone),
    ];
    let options = WeightMapOptions::default();
    let layout = WeightMapLayout::new(&drawing, &markers, None, &options).unwrap();
    let without_bone = WeightMapLayout::new(&drawing, &markers[..1], None, &options).unwrap();
    assert!(
        layout.frame.y0 < without_bone.frame.y0,
        "the bone is in the frame"
    );
    assert_eq!((image.width, image.height), (layout.width, layout.height));
    assert_eq!(layout.panels.len(), 2);
    let at = |panel: usize| image.colour_at(layout.to_pixel(panel, ARC_HANDLES[0]).unwrap());
    assert_eq!(at(0), Some(viridis(1.0)));
    assert_eq!(at(1), Some(viridis(0.0)));

    // A cage alone, harmonic coordinates of the caged domain: four handles, four panels.
    let dir = case_dir("scene-cage");
    let scene = format!(
        r#"{{"splineskin_scene": 1, "svg_text": "{ARC_SVG}",
            "cage": [[-10, -10], [110, -10], [110, 40], [-10, 40]],
            "weights": {{"family": "harmonic"}}}}"#
    );
    std::fs::write(dir.join("scene.json"), scene).unwrap();
    let (image, stderr) = draw(&dir, "w.png", &["--width", "200"]);
    assert!(stderr.contains("4 of 4 handles"), "{stderr}");
    let scene = Scene::load(&dir.join("scene.json")).unwrap();
    let setup = scene.setup(Compat::None).unwrap();
    let cage = scene.cage.clone().unwrap();
    let markers: Vec<HandleMarker> = cage.iter().map(|&p| HandleMarker::Point(p)).collect();
    let options = WeightMapOptions::default().with_panel_width(200);
    let mesh = setup.domain.as_ref().map(|d| &d.mesh);
    let layout = WeightMapLayout::new(&setup.drawing, &markers, mesh, &options).unwrap();
    assert_eq!(layout.panels.len(), 4);
    assert_eq!((image.width, image.height), (layout.width, layout.height));
    let out = run(
        &dir,
        &["weights", "scene.json", "-o", "x.png", "--handle", "4"],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && stderr.contains("the scene has 4"),
        "{stderr}"
    );
    assert!(!dir.join("x.png").exists());
}

#[test]
fn weights_cli_scene_bad_input_fails_cleanly() {
    let scene = arc_scene("shepard");
    let cases = vec![
        Failure {
            name: "scene-missing",
            mesh: None,
            args: words("weights missing.json -o w.png"),
            expect: vec!["missing.json", "cannot read"],
        },
        Failure {
            name: "scene-unknown-handle",
            mesh: None,
            args: words("weights scene.json -o w.png --handle 2"),
            expect: vec![
                "scene.json",
                "--handle 2",
                "no such handle",
                "the scene has 2",
            ],
        },
        Failure {
            name: "scene-unwritable-output",
            mesh: None,
            args: words("weights scene.json -o no-such-folder/w.png"),
            expect: vec!["no-such-folder/w.png", "cannot write"],
        },
        Failure {
            name: "scene-output-not-png",
            mesh: None,
            args: words("weights scene.json -o w.jpg"),
            expect: vec!["w.jpg", "drawn as PNG", ".png"],
        },
        Failure {
            name: "scene-output-json",
            mesh: None,
            args: words("weights scene.json -o w.json"),
            expect: vec!["w.json", "drawn as PNG"],
        },
        Failure {
            name: "scene-width-too-small",
            mesh: None,
            args: words("weights scene.json -o w.png --width 8"),
            expect: vec!["scene.json", "panel width 8 px", "32"],
        },
        Failure {
            name: "scene-kind",
            mesh: None,
            args: words("weights scene.json --kind harmonic -o w.png"),
            expect: vec!["--kind", "cannot be used with"],
        },
        Failure {
            name: "mesh-with-mesh-lines",
            mesh: Some(mesh_file(None, None, "[0, 11]")),
            args: words("weights --mesh mesh.json --mesh-lines -o out.json"),
            expect: vec!["--mesh-lines", "cannot be used with"],
        },
    ];
    let root = case_dir("scene-failures");
    for case in &cases {
        let dir = case_subdir(&root, case.name);
        std::fs::write(dir.join("scene.json"), &scene).unwrap();
    }
    run_failures_in_place(&root, cases);
    let bad_json = Failure {
        name: "scene-bad-json",
        mesh: None,
        args: words("weights scene.json -o w.png"),
        expect: vec!["scene.json", "line 1"],
    };
    let dir = case_subdir(&root, bad_json.name);
    std::fs::write(
        dir.join("scene.json"),
        r#"{"splineskin_scene": 1, "handles": ["#,
    )
    .unwrap();
    run_failures_in_place(&root, vec![bad_json]);
}

/// The failure check itself fails on a successful run (so the cases above prove something).
#[test]
fn weights_cli_failure_check_rejects_success() {
    let case = Failure {
        name: "control",
        mesh: Some(mesh_file(None, None, "[0, 11]")),
        args: words("weights --mesh mesh.json -o out.json"),
        expect: vec![],
    };
    let dir = case_dir(case.name);
    std::fs::write(dir.join("mesh.json"), case.mesh.as_ref().unwrap()).unwrap();
    let out = run(&dir, &case.args);
    assert!(out.status.success());
    assert!(dir.join("out.json").is_file());
    assert!(check_failure(&case, &dir, &out, "out.json").is_err());
}
