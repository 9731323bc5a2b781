//! `splineskin subdiv deform | compare | bench | refine` through the binary, on a box cage made
//! here (and the car, when `../shared/data` is present):
//!
//! * deform writes the cage with its faces and tags, the identity pose gives the input back,
//!   and `--limit-mesh` writes the limit surface's quads;
//! * compare writes a PNG and one JSON row per method, ours below naive;
//! * bench `--json` rows have exactly the documented keys, for a scene and a bare `.obj`;
//! * refine multiplies the faces by 4 per level and carries the crease tags;
//! * malformed input (bad OBJ, missing files, NaN in a scene, a weight file with a wrong column
//!   count, wrong output names) fails with exit code 1, names the file, and leaves no output.

mod common;

use std::path::Path;

use common::cli::{json_lines, run_line, run_ok, temporaries};
use common::test_dir::TestDir;
use serde::Deserialize;

/// A box `[0, 2] × [0, 1] × [0, 1]` of two cells, with a crease around its middle.
const BOX: &str = "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\n\
                   v 0 0 1\nv 1 0 1\nv 2 0 1\nv 0 1 1\nv 1 1 1\nv 2 1 1\n\
                   f 1 4 5 2\nf 2 5 6 3\nf 7 8 11 10\nf 8 9 12 11\n\
                   f 1 2 8 7\nf 2 3 9 8\nf 4 10 11 5\nf 5 11 12 6\nf 1 7 10 4\nf 3 6 12 9\n\
                   t crease 2/1/0 1 4 2.5\n";

/// A scene around `box.obj`: a point handle at one end, a bone in the other half, `weights`,
/// and a pose turning the bone.
fn scene(weights: &str) -> String {
    scene_with(
        weights,
        r#"[{"name": "turn", "transforms": [{},
     {"rotate": {"axis": [0, 1, 0], "degrees": 35}, "translate": [0, 0.2, 0]}]}]"#,
    )
}

/// The same scene with the poses `poses`.
fn scene_with(weights: &str, poses: &str) -> String {
    format!(
        r#"{{"splineskin_subdiv_scene": 1, "obj": "box.obj",
  "handles": [{{"position": [0, 0.5, 0.5]}}],
  "bones": [{{"ends": [[1.2, 0.5, 0.5], [1.9, 0.5, 0.5]]}}],
  "weights": {weights},
  "poses": {poses}}}"#
    )
}

fn folder(name: &str) -> TestDir {
    let dir = TestDir::new(&format!("splineskin-subdiv-cli-{name}-"));
    std::fs::write(dir.join("box.obj"), BOX).unwrap();
    dir
}

/// [`folder`] with `scene.json`: the box scene under Shepard weights.
fn shepard_folder(name: &str) -> TestDir {
    let dir = folder(name);
    std::fs::write(dir.join("scene.json"), scene(r#"{"family": "shepard"}"#)).unwrap();
    dir
}

/// A [`shepard_folder`] named `name` and the two `--json` rows of `splineskin line` run there.
fn shepard_rows<T: serde::de::DeserializeOwned>(name: &str, line: &str) -> (TestDir, Vec<T>) {
    let dir = shepard_folder(name);
    let rows: Vec<T> = json_lines(&run_ok(&dir, line));
    assert_eq!(rows.len(), 2);
    (dir, rows)
}

/// `(positions, faces, tag lines)` of an OBJ file.
fn read(path: &Path) -> (Vec<[f64; 3]>, usize, Vec<String>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut v = Vec::new();
    let (mut faces, mut tags) = (0, Vec::new());
    for line in text.lines() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let c: Vec<f64> = words.map(|w| w.parse().unwrap()).collect();
                v.push([c[0], c[1], c[2]]);
            }
            Some("f") => faces += 1,
            Some("t") => tags.push(line.to_owned()),
            _ => {}
        }
    }
    (v, faces, tags)
}

#[test]
fn subdiv_cli_deform_writes_the_cage_and_its_limit_mesh() {
    let dir = shepard_folder("deform");
    run_ok(
        &dir,
        "subdiv deform scene.json -o out.obj --limit-mesh mesh.obj --level 2",
    );
    let (rest, faces, tags) = read(&dir.join("box.obj"));
    let (posed, posed_faces, posed_tags) = read(&dir.join("out.obj"));
    assert_eq!(
        (posed.len(), posed_faces, posed_tags.len()),
        (12, faces, tags.len())
    );
    assert_eq!(posed_tags[0], "t crease 2/1/0 1 4 2.5");
    // The bone turned: the far end moved, by far more than the near one.
    let moved = |v: usize| {
        (0..3)
            .map(|k| (posed[v][k] - rest[v][k]).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    assert!(
        moved(2) > 0.2 && moved(2) > 2.0 * moved(0),
        "{} {}",
        moved(2),
        moved(0)
    );
    // Level 2: 16 quads per cage quad.
    let (_, mesh_faces, _) = read(&dir.join("mesh.obj"));
    assert_eq!(mesh_faces, 16 * faces);

    // Without poses, pose 0 is the identity: the cage comes back.
    let identity = scene_with(r#"{"family": "bone_heat", "level": 2}"#, "[]");
    std::fs::write(dir.join("identity.json"), identity).unwrap();
    run_ok(&dir, "subdiv deform identity.json -o same.obj");
    let (same, _, _) = read(&dir.join("same.obj"));
    for (a, b) in same.iter().zip(&rest) {
        for k in 0..3 {
            assert!((a[k] - b[k]).abs() < 1e-12, "{a:?} vs {b:?}");
        }
    }
}

/// The cage and its limit mesh are written together: when the mesh cannot be written (its
/// folder does not exist), a cage file already there keeps its contents and no temporary is
/// left (the cage used to be written first, then removed, losing the earlier file).
#[test]
fn subdiv_cli_deform_writes_both_files_or_neither() {
    let dir = shepard_folder("deform-both");
    std::fs::write(dir.join("out.obj"), "# an earlier cage\n").unwrap();
    let out = run_line(
        &dir,
        "subdiv deform scene.json -o out.obj --limit-mesh missing-folder/mesh.obj",
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("missing-folder/mesh.obj"), "{stderr}");
    assert_eq!(
        std::fs::read_to_string(dir.join("out.obj")).unwrap(),
        "# an earlier cage\n"
    );
    let leftovers = temporaries(&dir);
    assert!(leftovers.is_empty(), "{leftovers:?}");
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CompareRow {
    scene: String,
    pose: usize,
    method: String,
    vertices: usize,
    faces: usize,
    handles: usize,
    samples: usize,
    max: f64,
    rms: f64,
    diagonal: f64,
}

#[test]
fn subdiv_cli_compare_writes_a_png_and_ours_beats_naive() {
    let (dir, rows) = shepard_rows::<CompareRow>(
        "compare",
        "subdiv compare scene.json -o cmp.png --json --level 2 --width 200",
    );
    assert_eq!(
        (rows[0].method.as_str(), rows[1].method.as_str()),
        ("ours", "naive")
    );
    for r in &rows {
        assert_eq!(
            (r.scene.as_str(), r.pose, r.vertices, r.faces, r.handles),
            ("scene.json", 0, 12, 10, 2)
        );
        assert!(r.samples > 100 && r.diagonal > 2.0 && r.max.is_finite());
    }
    assert!(rows[0].rms < rows[1].rms && rows[0].max < rows[1].max);
    let png = std::fs::read(dir.join("cmp.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct BenchRow {
    scene: String,
    vertices: usize,
    faces: usize,
    handles: usize,
    precompute_s: f64,
    update_s: f64,
}

#[test]
fn subdiv_cli_bench_json_keys() {
    let (_dir, rows) = shepard_rows::<BenchRow>(
        "bench",
        "subdiv bench --json --updates 200 --handles 3 scene.json box.obj",
    );
    assert_eq!((rows[0].scene.as_str(), rows[0].handles), ("scene.json", 2));
    assert_eq!((rows[1].scene.as_str(), rows[1].handles), ("box.obj", 3));
    for r in &rows {
        assert_eq!((r.vertices, r.faces), (12, 10));
        assert!(r.precompute_s > 0.0 && r.precompute_s.is_finite());
        assert!(r.update_s > 0.0 && r.update_s.is_finite());
    }
}

#[test]
fn subdiv_cli_refine_carries_tags() {
    let dir = folder("refine");
    run_ok(&dir, "subdiv refine box.obj --levels 2 -o fine.obj");
    let (v, faces, tags) = read(&dir.join("fine.obj"));
    assert_eq!(faces, 160);
    // The crease of sharpness 2.5 between vertices 1 and 4 (1-based 2, 5) is four level-2
    // edges of sharpness 0.5.
    let creases: Vec<&String> = tags.iter().filter(|t| t.starts_with("t crease")).collect();
    assert_eq!(creases.len(), 4, "{tags:?}");
    assert!(creases.iter().all(|t| t.ends_with(" 0.5")), "{creases:?}");
    assert!(v.len() > 100);
}

#[test]
fn subdiv_cli_car_scene() {
    let Some(root) = common::external_data::shared_data() else {
        return;
    };
    let dir = folder("car");
    let obj = root.join("subdiv/shapes/catmark_car.obj");
    let text = format!(
        r#"{{"splineskin_subdiv_scene": 1, "obj": {},
  "handles": [{{"position": [0.6, -0.3, 0.3]}}, {{"position": [0.6, -3.4, 0.3]}}],
  "poses": [{{"transforms": [{{}}, {{"rotate": {{"axis": [1, 0, 0], "degrees": 30}}}}]}}]}}"#,
        serde_json::to_string(&obj.display().to_string()).unwrap()
    );
    std::fs::write(dir.join("car.json"), text).unwrap();
    let rows: Vec<CompareRow> = json_lines(&run_ok(
        &dir,
        "subdiv compare car.json -o car.png --json --level 2",
    ));
    assert_eq!(rows[0].vertices, 1642);
    assert!(
        rows[0].rms < rows[1].rms,
        "{} vs {}",
        rows[0].rms,
        rows[1].rms
    );
}

/// A failing run: exit code 1, no panic, stderr naming `names`, and no `output` (nor a
/// temporary of it) left in the folder.
fn fails(dir: &Path, line: &str, names: &[&str], output: &str) {
    let out = run_line(dir, line);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let label = format!("{line}\nstderr: {stderr}");
    assert_eq!(out.status.code(), Some(1), "{label}");
    assert!(!stderr.contains("panicked"), "{label}");
    assert!(stderr.starts_with("error: "), "{label}");
    for name in names {
        assert!(stderr.contains(name), "{label}: lacks {name:?}");
    }
    assert!(!dir.join(output).exists(), "{label}: {output} was written");
    let leftovers = temporaries(dir);
    assert!(leftovers.is_empty(), "{label}: {leftovers:?}");
}

#[test]
fn subdiv_cli_malformed_input_fails_cleanly() {
    let dir = folder("malformed");
    let put = |name: &str, text: &str| std::fs::write(dir.join(name), text).unwrap();
    let shepard = scene(r#"{"family": "shepard"}"#);
    put("scene.json", &shepard);
    // A bad OBJ: a face with an index out of range, on line 2; a scene of a missing OBJ.
    put("bad.obj", "v 0 0 0\nf 1 2 3\n");
    put("bad.json", &shepard.replace("box.obj", "bad.obj"));
    put("lost.json", &shepard.replace("box.obj", "lost.obj"));
    // NaN in a scene: not JSON; an infinite coordinate: JSON, but refused by name.
    put(
        "nan.json",
        &shepard.replace("[0, 0.5, 0.5]", "[NaN, 0.5, 0.5]"),
    );
    put(
        "inf.json",
        &shepard.replace("[0, 0.5, 0.5]", "[1e999, 0.5, 0.5]"),
    );
    // A weight file with a wrong column count on line 3.
    put("w.csv", "1, 0\n1, 0\n1, 0, 0\n");
    put(
        "file.json",
        &scene(r#"{"family": "file", "path": "w.csv"}"#),
    );
    let columns = "3 columns; expected one per handle, 2";
    let cases: [(&str, &[&str], &str); 12] = [
        (
            "subdiv deform bad.json -o out.obj",
            &["bad.json", "bad.obj:2"],
            "out.obj",
        ),
        (
            "subdiv refine bad.obj --levels 1 -o out.obj",
            &["bad.obj:2"],
            "out.obj",
        ),
        ("subdiv bench bad.obj", &["bad.obj:2"], "out.obj"),
        // Missing files.
        (
            "subdiv deform nope.json -o out.obj",
            &["nope.json", "cannot read"],
            "out.obj",
        ),
        (
            "subdiv compare lost.json -o out.png",
            &["lost.json", "lost.obj", "cannot read"],
            "out.png",
        ),
        (
            "subdiv refine none.obj --levels 1 -o out.obj",
            &["none.obj"],
            "out.obj",
        ),
        (
            "subdiv deform nan.json -o out.obj",
            &["nan.json", "invalid scene JSON"],
            "out.obj",
        ),
        (
            "subdiv deform inf.json -o out.obj",
            &["inf.json"],
            "out.obj",
        ),
        (
            "subdiv compare file.json -o out.png",
            &["file.json", "w.csv:3", columns],
            "out.png",
        ),
        // A pose that does not exist, and wrong output names.
        (
            "subdiv deform scene.json -o out.obj --pose 3",
            &["scene.json", "pose 3"],
            "out.obj",
        ),
        (
            "subdiv deform scene.json -o out.svg",
            &["out.svg", ".obj"],
            "out.svg",
        ),
        (
            "subdiv compare scene.json -o out.obj",
            &["out.obj", ".png"],
            "out.obj",
        ),
    ];
    for (line, names, output) in cases {
        fails(&dir, line, names, output);
    }
}

/// `subdiv animate`: a USD file, a glTF file and a folder of OBJ frames from one animated
/// scene; the OBJ frames are `subdiv deform --frame N`'s cages; names it cannot write, a scene
/// without animation and a folder holding other files are refused, leaving nothing behind.
#[test]
fn subdiv_cli_animate_hands_off_every_frame() {
    let dir = folder("animate");
    let animated = scene(r#"{"family": "shepard"}"#).replacen(
        "\"poses\":",
        r#""animation": {"fps": 4, "keyframes": [{"time": 0, "pose": [{}, {}]}, {"time": 1, "pose": "turn", "easing": "ease-out"}]},
  "poses":"#,
        1,
    );
    std::fs::write(dir.join("anim.json"), animated).unwrap();
    std::fs::write(dir.join("still.json"), scene(r#"{"family": "shepard"}"#)).unwrap();
    run_ok(&dir, "subdiv animate anim.json -o anim.usda --up z");
    let usda = std::fs::read_to_string(dir.join("anim.usda")).unwrap();
    assert!(
        usda.contains("upAxis = \"Z\"") && usda.contains("endTimeCode = 4"),
        "{usda:.400}"
    );
    assert!(
        usda.contains("int[] creaseIndices = [1, 4]"),
        "the crease tag's vertices (0-based, as OBJ tags are)"
    );
    run_ok(&dir, "subdiv animate anim.json -o anim.glb --level 1");
    let glb = std::fs::read(dir.join("anim.glb")).unwrap();
    assert_eq!(&glb[..4], b"glTF");
    run_ok(&dir, "subdiv animate anim.json -o frames");
    let names: Vec<String> = {
        let mut n: Vec<String> = std::fs::read_dir(dir.join("frames"))
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        n.sort();
        n
    };
    assert_eq!(
        names,
        [
            "frame-0000.obj",
            "frame-0001.obj",
            "frame-0002.obj",
            "frame-0003.obj",
            "frame-0004.obj"
        ]
    );
    run_ok(&dir, "subdiv deform anim.json --frame 2 -o two.obj");
    assert_eq!(
        std::fs::read_to_string(dir.join("two.obj")).unwrap(),
        std::fs::read_to_string(dir.join("frames/frame-0002.obj")).unwrap()
    );
    let (last, _, tags) = read(&dir.join("frames/frame-0004.obj"));
    run_ok(&dir, "subdiv deform anim.json --pose 0 -o turn.obj");
    assert_eq!(
        read(&dir.join("turn.obj")).0,
        last,
        "the last frame is the last keyframe's pose"
    );
    assert_eq!(tags, ["t crease 2/1/0 1 4 2.5"]);
    // Again into the same folder: replaced (it holds only frames).
    run_ok(&dir, "subdiv animate anim.json -o frames --fps 2");
    assert_eq!(std::fs::read_dir(dir.join("frames")).unwrap().count(), 3);

    fails(
        &dir,
        "subdiv animate anim.json -o anim.gltf",
        &["anim.gltf", ".usda", ".glb"],
        "anim.gltf",
    );
    fails(
        &dir,
        "subdiv animate still.json -o still.usda",
        &["still.json", "animation"],
        "still.usda",
    );
    fails(
        &dir,
        "subdiv deform anim.json --frame 9 -o nine.obj",
        &["--frame 9", "5 frames"],
        "nine.obj",
    );
    fails(
        &dir,
        "subdiv animate anim.json -o box.obj.d --fps 0",
        &["--fps 0", "frame rate"],
        "box.obj.d",
    );
    std::fs::create_dir(dir.join("mixed")).unwrap();
    std::fs::write(dir.join("mixed/notes.txt"), "mine").unwrap();
    let out = run_line(&dir, "subdiv animate anim.json -o mixed");
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("notes.txt, which is not a frame"),
        "{stderr}"
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("mixed/notes.txt")).unwrap(),
        "mine"
    );
    assert!(temporaries(&dir).is_empty());
}
