//! `splineskin defop …` through the binary, on a small bar drawing (a 100 × 30 rectangle,
//! three point handles) trained on a coarse domain with few samples:
//!
//! * `train` → `eval`: the rest configuration gives back the rest mesh, the handle vertices
//!   land on their targets, both handle-file forms are read, the PNG is drawn;
//! * `train` on an OBJ mesh whose vertices hold the handles; refused when a handle is off the
//!   mesh's vertices;
//! * `study --quick --json`: the keys, and the thin-plate error falls with the samples;
//! * `bench --json`: a positive `evals_per_s`;
//! * `deform`: the drawing through the scene's operator follows a posed handle;
//! * bad inputs refused with the file named, exit status 1, no output left behind.

mod common;

use std::path::Path;

use common::cli::{defop_eval, failed, json_lines, ok, run_ok, s, splineskin};
use common::test_dir::TestDir;
use kurbo::Point;
use splineskin::defop::OperatorFile;
use splineskin::weight_map::RgbaImage;

const BAR_SVG: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 30"><path d="M0 0 H100 V30 H0 Z" fill="#888"/></svg>"##;

/// The bar scene with a `defop` section (`extra` adds keys to it).
fn write_scene(dir: &Path, extra: &str) -> std::path::PathBuf {
    std::fs::write(dir.join("bar.svg"), BAR_SVG).unwrap();
    let scene = format!(
        r#"{{
  "splineskin_scene": 1,
  "svg": "bar.svg",
  "handles": [ {{ "position": [10, 15] }}, {{ "position": [90, 15] }}, {{ "position": [50, 15] }} ],
  "defop": {{ "energy": "arap", "samples": 24, "region": {{ "disc": 0.05 }},
              "domain": {{ "max_area_fraction": 0.02, "samples_per_diagonal": 20 }} {extra} }}
}}"#
    );
    let path = dir.join("bar-scene.json");
    std::fs::write(&path, scene).unwrap();
    path
}

/// Trains the bar's operator into `dir/op.bin`.
fn trained(dir: &Path) -> std::path::PathBuf {
    write_scene(dir, "");
    let op = dir.join("op.bin");
    let stdout = run_ok(dir, "defop train bar-scene.json -o op.bin --held-out 3");
    assert!(stdout.contains("3 handles, 24 samples"), "{stdout}");
    assert!(stdout.contains("held-out error"), "{stdout}");
    op
}

#[derive(serde::Deserialize)]
struct Deformed {
    vertices: Vec<[f64; 2]>,
    triangles: Vec<[usize; 3]>,
    handles: Vec<[f64; 2]>,
}

#[test]
fn defop_cli_train_then_eval_round_trip() {
    let dir = TestDir::new("splineskin-defop-cli-");
    let op_path = trained(&dir);
    let file = OperatorFile::load(&op_path).unwrap();
    assert_eq!(file.op.n_handles(), 3);

    // Rest configuration: the rest mesh.
    let rest = dir.join("rest.json");
    std::fs::write(&rest, "[[10, 15], [90, 15], [50, 15]]").unwrap();
    let out = dir.join("rest-out.json");
    ok(&defop_eval(&op_path, &rest, &out));
    let d: Deformed = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
    assert_eq!(d.triangles, file.mesh.triangles);
    for (a, b) in d.vertices.iter().zip(&file.mesh.vertices) {
        assert!((Point::new(a[0], a[1]) - *b).hypot() < 1e-9, "{a:?} {b:?}");
    }

    // Moved handles, the object form: the handle vertices land on their targets.
    let targets = [[5.0, 20.0], [97.0, 8.0], [52.0, 18.0]];
    let moved = dir.join("moved.json");
    std::fs::write(
        &moved,
        format!(
            "{{\"handles\": {}}}",
            serde_json::to_string(&targets).unwrap()
        ),
    )
    .unwrap();
    ok(&defop_eval(&op_path, &moved, &out));
    let d: Deformed = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
    assert_eq!(d.handles, targets.to_vec());
    for (&h, t) in file.op.handles().iter().zip(&targets) {
        let p = d.vertices[h];
        assert!((p[0] - t[0]).abs() < 1e-9 && (p[1] - t[1]).abs() < 1e-9);
    }

    // PNG: drawn, mostly white with the mesh in colour.
    let png = dir.join("moved.png");
    ok(&defop_eval(&op_path, &moved, &png));
    let image = RgbaImage::decode_png(&std::fs::read(&png).unwrap()).unwrap();
    let coloured = image.pixels.iter().filter(|p| p[0] != p[2]).count();
    assert!(coloured > 1000, "{coloured} coloured pixels");
}

#[test]
fn defop_cli_bench_json() {
    let dir = TestDir::new("splineskin-defop-cli-");
    let op = trained(&dir);
    // `defop bench OP --json --batches 3 EXTRA…`, its one JSON line.
    let bench = |extra: &[&str]| -> serde_json::Value {
        let mut args = vec!["defop", "bench", s(&op), "--json", "--batches", "3"];
        args.extend_from_slice(extra);
        serde_json::from_str(ok(&splineskin(&args)).trim()).unwrap()
    };
    let v = bench(&[]);
    assert!(v["evals_per_s"].as_f64().unwrap() > 0.0);
    assert!(v["eval_s"].as_f64().unwrap() > 0.0);
    assert_eq!(v["handle_functions"].as_u64(), Some(1 + 6 + 25));
    assert!(v.get("join_update_s").is_none(), "{v}");

    // With the scene it was trained for: the join's precompute and per-frame update too.
    let v = bench(&["--scene", s(&dir.join("bar-scene.json"))]);
    assert!(v["join_precompute_s"].as_f64().unwrap() > 0.0, "{v}");
    assert!(v["join_update_s"].as_f64().unwrap() > 0.0, "{v}");
    assert!(v["join_points"].as_u64().unwrap() >= 4, "{v}");
}

#[test]
fn defop_cli_study_quick_json() {
    let dir = TestDir::new("splineskin-defop-cli-");
    let scene = write_scene(&dir, "");
    let plot = dir.join("study.png");
    let rows: Vec<serde_json::Value> = json_lines(&ok(&splineskin(&[
        "defop",
        "study",
        s(&scene),
        "-o",
        s(&plot),
        "--quick",
        "--json",
        "--max-samples",
        "60",
        "--held-out",
        "4",
    ])));
    assert!(!rows.is_empty());
    for r in &rows {
        assert!(r["basis"].is_string() && r["samples"].is_u64() && r["error"].is_f64());
    }
    let tps: Vec<f64> = rows
        .iter()
        .filter(|r| r["basis"] == "tps")
        .map(|r| r["error"].as_f64().unwrap())
        .collect();
    assert!(tps.len() >= 2 && tps.last() < tps.first(), "{tps:?}");
    let image = RgbaImage::decode_png(&std::fs::read(&plot).unwrap()).unwrap();
    assert!(image.width > 100 && image.height > 100);
}

#[test]
fn defop_cli_train_on_a_mesh_file() {
    let dir = TestDir::new("splineskin-defop-cli-");
    // A 4 × 2 grid over the bar with vertices at the handles (10, 15), (90, 15), (50, 15)?
    // Columns at x = 10, 30, 50, 70, 90 and rows at y = 0, 15, 30.
    let mut obj = String::new();
    for y in [0, 15, 30] {
        for x in [10, 30, 50, 70, 90] {
            obj.push_str(&format!("v {x} {y} 0\n"));
        }
    }
    for r in 0..2 {
        for c in 0..4 {
            let a = r * 5 + c + 1;
            obj.push_str(&format!("f {a} {} {}\n", a + 1, a + 6));
            obj.push_str(&format!("f {a} {} {}\n", a + 6, a + 5));
        }
    }
    std::fs::write(dir.join("bar.obj"), &obj).unwrap();
    let scene = write_scene(&dir, r#", "mesh": "bar.obj""#);
    let op = dir.join("mesh-op.bin");
    let stdout = run_ok(
        &dir,
        "defop train bar-scene.json -o mesh-op.bin --held-out 0",
    );
    assert!(stdout.contains("15 vertices, 16 triangles"), "{stdout}");
    let file = OperatorFile::load(&op).unwrap();
    assert_eq!(file.op.handles(), &[5, 9, 7]);

    // A handle off the vertices is refused, naming it.
    let off = obj.replace("v 50 15 0", "v 51 15 0");
    std::fs::write(dir.join("bar.obj"), off).unwrap();
    let op2 = dir.join("refused.bin");
    let err = failed(&splineskin(&["defop", "train", s(&scene), "-o", s(&op2)]));
    assert!(
        err.contains("bar.obj") && err.contains("handles[2]"),
        "{err}"
    );
    assert!(!op2.exists());
}

#[test]
fn defop_cli_refuses_bad_inputs_naming_the_file() {
    let dir = TestDir::new("splineskin-defop-cli-");
    let op = trained(&dir);
    let out = dir.join("out.json");
    let eval = |op: &Path, handles: &Path| defop_eval(op, handles, &out);
    let write = |name: &str, text: &str| {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    };
    let good = write("good.json", "[[10, 15], [90, 15], [50, 15]]");
    let cases = [
        (eval(&dir.join("missing.bin"), &good), "missing.bin"),
        (
            eval(&write("not-op.bin", "hello, not an operator"), &good),
            "not a splineskin operator",
        ),
        (eval(&op, &write("bad.json", "[[10, 15],")), "bad.json"),
        (
            eval(&op, &write("two.json", "[[10, 15], [90, 15]]")),
            "2 handle positions",
        ),
        (
            eval(&op, &write("nan.json", "[[NaN, 15], [90, 15], [50, 15]]")),
            "nan.json",
        ),
        (
            eval(
                &op,
                &write("huge.json", "[[1e999, 15], [90, 15], [50, 15]]"),
            ),
            "huge.json",
        ),
        (eval(&op, &dir.join("missing.json")), "missing.json"),
    ];
    for (output, expected) in cases {
        let err = failed(&output);
        assert!(err.contains(expected), "expected {expected:?} in {err}");
    }
    assert!(!out.exists());
    let err = failed(&splineskin(&["defop", "bench", s(&dir.join("not-op.bin"))]));
    assert!(err.contains("not-op.bin"), "{err}");
    let err = failed(&splineskin(&[
        "defop",
        "train",
        s(&dir.join("nope.json")),
        "-o",
        s(&dir.join("x.bin")),
    ]));
    assert!(err.contains("nope.json"), "{err}");
}

#[test]
fn defop_cli_deform_through_the_operator() {
    let dir = TestDir::new("splineskin-defop-cli-");
    let _ = trained(&dir);
    // The same scene naming its operator, with a pose moving the right handle up.
    let scene = dir.join("posed.json");
    let text = std::fs::read_to_string(dir.join("bar-scene.json"))
        .unwrap()
        .replace(
            r#""samples": 24,"#,
            r#""samples": 24, "operator": "op.bin","#,
        )
        .replace(
            "\"defop\"",
            r#""poses": [{"name": "lift", "transforms": [{}, {"position": [92, 22]}, {}]},
                {"name": "turn", "transforms": [{}, {"rotate": 30, "scale": 2}, {}]},
                {"name": "rest", "transforms": [{}, {}, {}]}], "defop""#,
        );
    std::fs::write(&scene, text).unwrap();
    let json = |pose: &str, name: &str| {
        let out = dir.join(name);
        run_ok(
            &dir,
            &format!("defop deform posed.json -o {name} --pose {pose}"),
        );
        let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
        v["paths"][0]["points"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| Point::new(p[0].as_f64().unwrap(), p[1].as_f64().unwrap()))
            .collect::<Vec<Point>>()
    };
    // The right handle moves 7 up and 2 right: the bar's right end follows.
    let lifted = json("lift", "lift.json");
    let max_x = lifted.iter().map(|p| p.x).fold(f64::MIN, f64::max);
    assert!(max_x > 95.0, "{lifted:?}");
    let right_top = lifted
        .iter()
        .filter(|p| p.x > 95.0)
        .map(|p| p.y)
        .fold(f64::MIN, f64::max);
    assert!(right_top > 30.5, "the right end rises: {lifted:?}");
    // The lifted bar leaves the viewBox (0 0 100 30, which the bar fills at rest): `keep`
    // keeps the viewBox and says how far, `fit` grows it to the curves' exact bounds.
    let svg = dir.join("lift.svg");
    let out = splineskin(&[
        "defop",
        "deform",
        s(&scene),
        "-o",
        s(&svg),
        "--pose",
        "lift",
    ]);
    ok(&out);
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("<path"));
    assert!(text.contains(r#"viewBox="0 0 100 30""#), "{text}");
    let bounds = lifted
        .chunks(3)
        .zip(lifted.iter().skip(3).step_by(3))
        .map(|(c, &p3)| {
            use kurbo::ParamCurveExtrema;
            kurbo::CubicBez::new(c[0], c[1], c[2], p3).bounding_box()
        })
        .fold(kurbo::Rect::new(0.0, 0.0, 100.0, 30.0), |r, b| r.union(b));
    let overshoot = [-bounds.x0, bounds.x1 - 100.0, -bounds.y0, bounds.y1 - 30.0]
        .into_iter()
        .fold(0.0f64, f64::max);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains(&format!(
            "lift.svg: the deformed art leaves the viewBox (cropped): path (line 1) by {overshoot:.3}"
        )),
        "{overshoot} in {stderr}"
    );
    let fit = dir.join("lift-fit.svg");
    ok(&splineskin(&[
        "defop",
        "deform",
        s(&scene),
        "-o",
        s(&fit),
        "--pose",
        "lift",
        "--viewbox",
        "fit",
    ]));
    let text = std::fs::read_to_string(&fit).unwrap();
    let at = text.find("viewBox=\"").unwrap() + 9;
    let found: Vec<f64> = text[at..at + text[at..].find('"').unwrap()]
        .split(' ')
        .map(|v| v.parse().unwrap())
        .collect();
    let expected = [bounds.x0, bounds.y0, bounds.width(), bounds.height()];
    for k in 0..4 {
        // The JSON and SVG runs solve the same system: equal to rounding, far below 1e-9 of
        // the bar's size.
        assert!(
            (found[k] - expected[k]).abs() < 1e-7,
            "{found:?} vs {expected:?}"
        );
    }

    // Turning and scaling a handle about its own position moves nothing, and the run says so.
    let rest = json("rest", "rest.json");
    let turned = json("turn", "turn.json");
    assert_eq!(turned, rest);
    let out = splineskin(&[
        "defop",
        "deform",
        s(&scene),
        "-o",
        s(&dir.join("turn.svg")),
        "--pose",
        "turn",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("note: pose 1 rotates or scales handles 1;"),
        "{stderr}"
    );

    // Without an operator: refused, saying how to get one.
    let plain = dir.join("bar-scene.json");
    let err = failed(&splineskin(&[
        "defop",
        "deform",
        s(&plain),
        "-o",
        s(&dir.join("no.svg")),
    ]));
    assert!(
        err.contains("no operator") && err.contains("bar-scene.json"),
        "{err}"
    );
    assert!(!dir.join("no.svg").exists());
}

#[test]
fn defop_cli_train_covers_the_scene_poses() {
    let dir = TestDir::new("splineskin-defop-cli-cover-");
    let _ = trained(&dir);
    // The scene with a pose lifting the right handle far beyond the sampling discs.
    let text = std::fs::read_to_string(dir.join("bar-scene.json"))
        .unwrap()
        .replace(
            "\"defop\"",
            r#""poses": [{"name": "lift", "transforms": [{}, {"position": [95, 40]}, {}]}], "defop""#,
        );
    std::fs::write(dir.join("posed.json"), text).unwrap();
    let out = splineskin(&[
        "defop",
        "train",
        s(&dir.join("posed.json")),
        "--cover",
        "poses",
        "-o",
        s(&dir.join("cover.bin")),
        "--held-out",
        "0",
    ]);
    let stdout = ok(&out);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("along the way to 1 poses configurations"),
        "{stdout}{stderr}"
    );
    let file = OperatorFile::load(&dir.join("cover.bin")).unwrap();
    assert!(file
        .metadata
        .sample_region
        .as_deref()
        .unwrap()
        .contains("along the way"));
    // A scene without poses that move a handle has nothing to cover: refused, nothing written.
    let err = failed(&splineskin(&[
        "defop",
        "train",
        s(&dir.join("bar-scene.json")),
        "--cover",
        "poses",
        "-o",
        s(&dir.join("none.bin")),
    ]));
    assert!(
        err.contains("--cover poses") && err.contains("bar-scene.json"),
        "{err}"
    );
    assert!(!dir.join("none.bin").exists());
    // An unknown cover is an argument error (clap's exit status 2), naming what is expected.
    let out = splineskin(&[
        "defop",
        "train",
        s(&dir.join("posed.json")),
        "--cover",
        "everything",
        "-o",
        s(&dir.join("none.bin")),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("expected none, poses or animation"),
        "{err}"
    );
}
