//! Malformed input through the command line: every case must fail cleanly.
//!
//! Each case writes its files into a fresh folder, runs the `splineskin` binary there and
//! checks that
//!
//! * the exit status is a failure, and not a panic (stderr has no "panicked"),
//! * stderr names the offending file and says what was wrong or expected (each case lists the
//!   substrings it requires),
//! * no output was written: neither the output file nor a leftover `.NAME.tmp-*` temporary
//!   in its folder.
//!
//! Positive controls (a small valid scene deforms, in both formats and both modes) prove the
//! harness sees success and files when they happen, and [`harness_rejects_a_successful_run`]
//! shows that the failure check itself fails on a run that succeeds.

mod common;

use std::path::Path;
use std::process::{Command, Output};

use common::cli::assert_no_problems;
use common::test_dir::TestDir;

/// A small valid drawing: one open cubic and a closed triangle.
const SVG: &str = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100">
  <path id="wave" d="M10 50 C30 20 70 20 90 50"/>
  <path id="tri" d="M20 80 L50 60 L80 80 Z"/>
</svg>"#;

/// Two handles, at the ends of the wave.
const HANDLES: &str = r#""handles": [{"position": [10, 50]}, {"position": [90, 50]}]"#;

/// An identity transform in the authors' format.
const IDENTITY: &str = r#"{"a": 1, "b": 0, "c": 0, "d": 1, "e": 0, "f": 0}"#;

/// A scene of ours: the SVG file `drawing.svg` next to it, two handles, one pose, and `extra`
/// (`, "key": value…`).
fn ours(extra: &str) -> String {
    format!(
        r#"{{"splineskin_scene": 1, "svg": "drawing.svg", {HANDLES},
  "pose": [{{"rotate": 10}}, {{"translate": [5, 0]}}]{extra}}}"#
    )
}

/// A scene of ours with `svg` given inline (`svg_text`), and no pose.
fn ours_inline(svg: &str, extra: &str) -> String {
    format!(
        r#"{{"splineskin_scene": 1, "svg_text": {}, {HANDLES}{extra}}}"#,
        json_string(svg)
    )
}

/// A scene in the authors' format around `svg`, two handles, and `extra`.
fn authors(svg: &str, extra: &str) -> String {
    format!(
        r#"{{"gInputSVGText": {}, "gHandles": [{{"pos": [10, 50], "transform": {IDENTITY}}},
  {{"pos": [90, 50], "transform": {{"a": 1, "b": 0, "c": 0, "d": 1, "e": 3, "f": 4}}}}]{extra}}}"#,
        json_string(svg)
    )
}

fn json_string(s: &str) -> String {
    serde_json::to_string(s).unwrap()
}

/// A document with one `<path>` whose `d` is `d` and optional `transform`.
fn svg_with(d: &str, transform: Option<&str>) -> String {
    let t = transform
        .map(|t| format!(r#" transform="{t}""#))
        .unwrap_or_default();
    format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100"><path id="p"{t} d="{d}"/></svg>"#
    )
}

/// A fresh, empty folder for one case.
fn case_dir(name: &str) -> TestDir {
    TestDir::new(&format!("splineskin-malformed-{name}-"))
}

/// One run of the binary.
struct Case<'a> {
    /// Folder name and label in messages.
    name: &'a str,
    /// Files to write first: (name relative to the case folder, contents).
    files: Vec<(&'a str, Vec<u8>)>,
    /// Arguments (file names relative to the case folder, where the binary runs).
    args: Vec<&'a str>,
    /// The output the run must not leave behind (relative to the case folder), if any.
    output: Option<&'a str>,
    /// Substrings stderr must contain (the file named and what was expected).
    expect: Vec<&'a str>,
}

impl Case<'_> {
    /// Writes the files and runs the binary in a fresh folder.
    fn run(&self) -> (TestDir, Output) {
        let dir = case_dir(self.name);
        for (name, contents) in &self.files {
            let path = dir.join(name);
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(path, contents).unwrap();
        }
        let out = Command::new(env!("CARGO_BIN_EXE_splineskin"))
            .args(&self.args)
            .current_dir(&dir)
            .output()
            .unwrap();
        (dir, out)
    }

    /// Checks a run against the case: `Err` says what is wrong.
    fn check_failure(&self, dir: &Path, out: &Output) -> Result<(), String> {
        let stderr = String::from_utf8_lossy(&out.stderr);
        let label = format!("{} ({})\nstderr: {stderr}", self.name, self.args.join(" "));
        if out.status.success() {
            return Err(format!("{label}: exited with success"));
        }
        if out.status.code() != Some(1) {
            return Err(format!("{label}: exit status {:?}, expected 1", out.status));
        }
        if stderr.contains("panicked") {
            return Err(format!("{label}: panicked"));
        }
        if !stderr.starts_with("error: ") && !stderr.contains("\nerror: ") {
            return Err(format!("{label}: no 'error: ' line"));
        }
        // A file name, not a placeholder for one.
        for placeholder in ["<svg text>", "<drawing>", "<inline>"] {
            if stderr.contains(placeholder) {
                return Err(format!("{label}: names {placeholder} instead of a file"));
            }
        }
        // One message, said once: no long `: `-separated part repeated (anyhow's chain used to
        // print sources that the message already quoted).
        for line in stderr.lines().filter(|l| l.starts_with("error: ")) {
            let parts: Vec<&str> = line.split(": ").filter(|p| p.len() >= 12).collect();
            if let Some(p) = parts
                .iter()
                .find(|p| parts.iter().filter(|q| q == p).count() > 1)
            {
                return Err(format!("{label}: the message repeats {p:?}"));
            }
        }
        for want in &self.expect {
            if !stderr.contains(want) {
                return Err(format!("{label}: stderr lacks {want:?}"));
            }
        }
        if let Some(output) = self.output {
            let path = dir.join(output);
            if path.is_file() {
                return Err(format!("{label}: {} was written", path.display()));
            }
            if let (Some(folder), Some(file)) = (path.parent(), path.file_name()) {
                let prefix = format!(".{}.tmp-", file.to_string_lossy());
                if let Ok(entries) = std::fs::read_dir(folder) {
                    for e in entries.flatten() {
                        if e.file_name().to_string_lossy().starts_with(&prefix) {
                            return Err(format!("{label}: leftover {:?}", e.path()));
                        }
                    }
                }
            }
        }
        Ok(())
    }
}

/// Runs every case and reports all failures at once. The folders of the failed cases are kept
/// (the failed assertion keeps them as it drops them); the others are removed.
fn run_failures(cases: Vec<Case>) {
    let mut problems = Vec::new();
    let mut failed = Vec::new();
    for case in &cases {
        let (dir, out) = case.run();
        if let Err(e) = case.check_failure(&dir, &out) {
            problems.push(e);
            failed.push(dir);
        }
    }
    assert_no_problems(&problems, cases.len());
}

fn file(name: &str, contents: impl Into<Vec<u8>>) -> (&str, Vec<u8>) {
    (name, contents.into())
}

/// A `deform` case: the scene `scene.json` (with `drawing.svg` next to it unless the case
/// writes its own), output `out.svg` unless `args` give another.
fn deform<'a>(
    name: &'a str,
    files: Vec<(&'a str, Vec<u8>)>,
    extra_args: &[&'a str],
    expect: &[&'a str],
) -> Case<'a> {
    let mut all = vec![file("drawing.svg", SVG)];
    for f in files {
        all.retain(|(n, _)| *n != f.0);
        all.push(f);
    }
    let output = extra_args
        .iter()
        .position(|a| *a == "-o")
        .map(|i| extra_args[i + 1])
        .unwrap_or("out.svg");
    let mut args = vec!["deform", "scene.json"];
    if !extra_args.contains(&"-o") {
        args.extend(["-o", "out.svg"]);
    }
    args.extend_from_slice(extra_args);
    Case {
        name,
        files: all,
        args,
        output: Some(output),
        expect: expect.to_vec(),
    }
}

const VS: [&str; 2] = ["--compat", "vectorskinning"];

#[test]
fn malformed_deform_scene_of_ours() {
    let nan = svg_with("M0 0 L NaN 5", None);
    let inf = svg_with("M0 0 C1 1 2 2 inf 5", None);
    let huge = svg_with("M0 0 L1e300 5", None);
    run_failures(vec![
        deform(
            "empty-scene",
            vec![file("scene.json", "")],
            &[],
            &["scene.json", "not a scene", "expected our format"],
        ),
        deform(
            "not-json",
            vec![file("scene.json", "hello, world")],
            &[],
            &["scene.json", "not a scene"],
        ),
        deform(
            "truncated-json",
            vec![file(
                "scene.json",
                r#"{"splineskin_scene": 1, "svg": "drawing.svg", "handl"#,
            )],
            &[],
            &["scene.json", "invalid scene JSON", "line 1"],
        ),
        deform("missing-scene", vec![], &[], &["scene.json", "cannot read"]),
        deform(
            "missing-svg",
            vec![file(
                "scene.json",
                ours("").replace("drawing.svg", "nothere.svg"),
            )],
            &[],
            &[
                "scene.json",
                "svg",
                "nothere.svg",
                "cannot read the drawing",
                "expected an SVG file",
            ],
        ),
        deform(
            "empty-svg",
            vec![file("scene.json", ours("")), file("drawing.svg", "")],
            &[],
            &["drawing.svg", "empty", "expected an <svg> document"],
        ),
        deform(
            "svg-not-xml",
            vec![
                file("scene.json", ours("")),
                file("drawing.svg", "M0 0 L10 10"),
            ],
            &[],
            &["drawing.svg", "not well-formed XML"],
        ),
        deform(
            "svg-cut-short",
            vec![
                file("scene.json", ours("")),
                file(
                    "drawing.svg",
                    "<svg xmlns=\"http://www.w3.org/2000/svg\">\n  <g>\n    <path d=\"M0 0 L5",
                ),
            ],
            &[],
            &["drawing.svg:3:21:", "unexpected end of stream", "cut short"],
        ),
        deform(
            "svg-without-paths",
            vec![file(
                "scene.json",
                ours_inline(
                    r#"<svg xmlns="http://www.w3.org/2000/svg"><text>hi</text></svg>"#,
                    "",
                ),
            )],
            &[],
            &[
                "scene.json",
                "no paths",
                "expected at least one rendered path",
            ],
        ),
        deform(
            "nan-in-path-data",
            vec![file("scene.json", ours("")), file("drawing.svg", nan)],
            &[],
            &[
                "drawing.svg",
                "path#p",
                "no paths",
                "path data d=",
                "drawn up to its first error",
            ],
        ),
        deform(
            "inf-in-path-data",
            vec![file("scene.json", ours("")), file("drawing.svg", inf)],
            &[],
            &[
                "drawing.svg",
                "path#p",
                "no paths",
                "drawn up to its first error",
            ],
        ),
        deform(
            "huge-path-data",
            vec![file("scene.json", ours("")), file("drawing.svg", huge)],
            &[],
            &[
                "drawing.svg",
                "path#p",
                "expected numbers within ±1e9",
                "1e300",
            ],
        ),
        deform(
            "huge-svg-transform",
            vec![
                file("scene.json", ours("")),
                file("drawing.svg", svg_with("M0 0 L5 5", Some("scale(1e300)"))),
            ],
            &[],
            &[
                "drawing.svg",
                "path#p",
                "attribute transform=",
                "within ±1e9",
            ],
        ),
        deform(
            "nan-in-pose",
            vec![file(
                "scene.json",
                ours("").replace(r#"{"rotate": 10}"#, "[NaN, 0, 0, 1, 0, 0]"),
            )],
            &[],
            &["scene.json", "invalid scene JSON", "line 2"],
        ),
        deform(
            "inf-in-pose",
            vec![file(
                "scene.json",
                ours("").replace(r#"{"rotate": 10}"#, r#"{"rotate": 1e999}"#),
            )],
            &[],
            &["scene.json", "invalid scene JSON", "number out of range"],
        ),
        deform(
            "huge-pose",
            vec![file(
                "scene.json",
                ours("").replace(r#"{"rotate": 10}"#, "[1e300, 0, 0, 1, 0, 0]"),
            )],
            &[],
            &[
                "scene.json",
                "poses[0].transforms[0]",
                "not finite or beyond ±1e9",
            ],
        ),
        deform(
            "huge-handle",
            vec![file(
                "scene.json",
                ours("").replace("[90, 50]", "[1e300, 50]"),
            )],
            &[],
            &[
                "scene.json",
                "handles[1].position",
                "(1e300, 50.0) is not a finite position within ±1e9",
            ],
        ),
        deform(
            "pose-with-too-few-transforms",
            vec![file(
                "scene.json",
                ours("").replace(r#"{"rotate": 10}, "#, ""),
            )],
            &[],
            &[
                "scene.json",
                "poses[0]",
                "1 transforms for 2 handles",
                "one per handle",
            ],
        ),
        deform(
            "unknown-pose-index",
            vec![file("scene.json", ours(""))],
            &["--pose", "3"],
            &["scene.json", "pose '3' does not exist", "(poses: 0"],
        ),
        deform(
            "unknown-pose-name",
            vec![file("scene.json", ours(""))],
            &["--pose", "jump"],
            &["scene.json", "pose 'jump' does not exist", "(poses: 0"],
        ),
        deform(
            "no-handles",
            vec![file(
                "scene.json",
                ours_inline(SVG, "").replace(HANDLES, r#""handles": []"#),
            )],
            &[],
            &["scene.json", "handles", "place at least one"],
        ),
        deform(
            "junction-on-missing-path",
            vec![file(
                "scene.json",
                ours(r#", "junctions": [{"path": 7, "joint": 1, "kind": "C1"}]"#),
            )],
            &[],
            &[
                "scene.json",
                "junctions[0]",
                "path 7 does not exist",
                "has 2",
            ],
        ),
        deform(
            "junction-on-missing-joint",
            vec![file(
                "scene.json",
                ours(r#", "junctions": [{"path": 1, "joint": 9, "kind": "G1"}]"#),
            )],
            &[],
            &[
                "scene.json",
                "junctions[0]",
                "joint 9 does not exist",
                "path 1 has 3",
            ],
        ),
        deform(
            "junction-on-open-end",
            vec![file(
                "scene.json",
                ours(r#", "junctions": [{"path": 0, "joint": 0, "kind": "C1"}]"#),
            )],
            &[],
            &["scene.json", "junctions[0]", "open end"],
        ),
        deform(
            "junction-of-unknown-kind",
            vec![file(
                "scene.json",
                ours(r#", "junctions": [{"path": 0, "joint": 1, "kind": "C7"}]"#),
            )],
            &[],
            &["scene.json", "invalid scene JSON", "C7"],
        ),
        // mvc weighs a cage only: with point handles it is refused on load.
        deform(
            "weights-mvc-with-points",
            vec![file(
                "scene.json",
                ours(r#", "weights": {"family": "mvc"}"#),
            )],
            &[],
            &["scene.json", "weights", "cage's vertices only"],
        ),
        deform(
            "weights-garbage",
            vec![file(
                "scene.json",
                ours(r#", "weights": {"family": "zorglub"}"#),
            )],
            &[],
            &[
                "scene.json",
                "unknown weight family 'zorglub'",
                "expected shepard",
            ],
        ),
        deform(
            "weights-bad-exponent",
            vec![file(
                "scene.json",
                ours(r#", "weights": {"family": "shepard", "exponent": -2}"#),
            )],
            &[],
            &["scene.json", "weights.exponent", "not in (0, 64]"],
        ),
        deform(
            "engine-jacobian-flexible",
            vec![file("scene.json", ours(r#", "engine": "jacobian""#))],
            &["--flexible"],
            &[
                "scene.json",
                "flexible junctions apply to engine 'ours'",
                "'jacobian'",
            ],
        ),
        deform(
            "engine-garbage",
            vec![file("scene.json", ours(r#", "engine": "warp9""#))],
            &[],
            &["scene.json", "unknown engine 'warp9'", "expected ours"],
        ),
        deform(
            "unknown-output-extension",
            vec![file("scene.json", ours(""))],
            &["-o", "out.txt"],
            &[
                "out.txt",
                "unknown output type",
                "expected a name ending in .svg, .png or .json",
            ],
        ),
        deform(
            "output-without-extension",
            vec![file("scene.json", ours(""))],
            &["-o", "out"],
            &["out", "unknown output type"],
        ),
        deform(
            "output-into-missing-folder",
            vec![file("scene.json", ours(""))],
            &["-o", "no/such/folder/out.svg"],
            &["no/such/folder/out.svg", "cannot write"],
        ),
        deform(
            "output-onto-a-folder",
            vec![file("scene.json", ours("")), file("taken.svg/keep", "")],
            &["-o", "taken.svg"],
            &["taken.svg", "cannot write"],
        ),
    ]);
}

#[test]
fn malformed_deform_scene_of_ours_in_compatibility_mode() {
    let with_vs = |extra: &[&'static str]| -> Vec<&'static str> {
        let mut v = VS.to_vec();
        v.extend_from_slice(extra);
        v
    };
    let a = with_vs(&[]);
    let json_out = with_vs(&["-o", "out.json"]);
    run_failures(vec![
        deform(
            "vs-svg-not-xml",
            vec![file("scene.json", ours("")), file("drawing.svg", "<svg")],
            &a,
            &["drawing.svg", "expected well-formed XML"],
        ),
        deform(
            "vs-nan-in-path-data",
            vec![
                file("scene.json", ours("")),
                file("drawing.svg", svg_with("M0 0 L NaN 5", None)),
            ],
            &a,
            &[
                "drawing.svg",
                "<path> #0 (id \"p\")",
                "expected valid SVG path data",
            ],
        ),
        deform(
            "vs-huge-path-data",
            vec![
                file("scene.json", ours("")),
                file("drawing.svg", svg_with("M0 0 L1e300 5", None)),
            ],
            &a,
            &[
                "drawing.svg",
                "<path> #0",
                "segment 1 ('L')",
                "finite float32 range",
            ],
        ),
        deform(
            "vs-svg-without-paths",
            vec![file(
                "scene.json",
                ours_inline(
                    r#"<svg xmlns="http://www.w3.org/2000/svg"><rect width="5" height="5"/></svg>"#,
                    "",
                ),
            )],
            &a,
            &[
                "scene.json",
                "no paths to fit",
                "expected at least one path",
            ],
        ),
        deform(
            "vs-missing-svg",
            vec![file(
                "scene.json",
                ours("").replace("drawing.svg", "nothere.svg"),
            )],
            &a,
            &["scene.json", "nothere.svg", "cannot read the drawing"],
        ),
        deform(
            "vs-huge-pose",
            vec![file(
                "scene.json",
                ours("").replace(r#"{"rotate": 10}"#, "[1, 0, 0, 1, -1e300, 0]"),
            )],
            &a,
            &[
                "scene.json",
                "poses[0].transforms[0]",
                "not finite or beyond ±1e9",
            ],
        ),
        deform(
            "vs-junction-on-missing-path",
            vec![file(
                "scene.json",
                ours(r#", "junctions": [{"path": 2, "joint": 1, "kind": "C0"}]"#),
            )],
            &a,
            &["scene.json", "junctions[0]", "path 2 does not exist"],
        ),
        deform(
            "vs-weights-mvc-with-points",
            vec![file(
                "scene.json",
                ours(r#", "weights": {"family": "mvc"}"#),
            )],
            &a,
            &["scene.json", "weights", "cage's vertices only"],
        ),
        // A curve of zero length makes the authors' system singular. On this one (all of its
        // points exactly at the origin) the LU meets an exact zero pivot and gives NaN, which
        // no output can hold (JSON would have written `null` before the fix).
        deform(
            "vs-zero-length-curve",
            vec![
                file("scene.json", ours("")),
                file("drawing.svg", svg_with("M0 0 L0 0 L20 30 Z", None)),
            ],
            &json_out,
            &[
                "scene.json",
                "path 0",
                "not finite",
                "rank deficient",
                "nothing written to out.json",
            ],
        ),
    ]);
}

#[test]
fn malformed_deform_authors_scene() {
    let svg = svg_with("M10 50 C30 20 70 20 90 50", None);
    let scene =
        |name: &'static str, text: String, extra_args: &[&'static str], expect: &[&'static str]| {
            let mut c = deform(name, vec![file("scene.json", text)], extra_args, expect);
            c.files.retain(|(n, _)| *n != "drawing.svg");
            c
        };
    let a: &[&str] = &[];
    let mut cases = Vec::new();
    for (mode, args) in [("", a), ("vs-", &VS[..])] {
        let n =
            |s: &str| -> &'static str { Box::leak(format!("authors-{mode}{s}").into_boxed_str()) };
        cases.extend([
            scene(n("empty-svg"), authors("", ""), args, &["scene.json (gInputSVGText)", "expected"]),
            scene(n("svg-not-xml"), authors("not < xml", ""), args, &["scene.json (gInputSVGText)", "XML"]),
            scene(
                n("nan-in-path-data"),
                authors(&svg_with("M0 0 L5 NaN", None), ""),
                args,
                &["scene.json (gInputSVGText)", "path data"],
            ),
            scene(
                n("huge-path-data"),
                authors(&svg_with("M0 0 L5 -1e300", None), ""),
                args,
                if mode.is_empty() {
                    &["scene.json (gInputSVGText)", "path#p", "expected numbers within ±1e9"]
                } else {
                    &["scene.json (gInputSVGText)", "<path> #0", "finite float32 range"]
                },
            ),
            scene(
                n("nan-in-handle-transform"),
                authors(&svg, "").replacen(r#""e": 0"#, r#""e": NaN"#, 1),
                args,
                &["scene.json", "invalid scene JSON", "expected value"],
            ),
            scene(
                n("huge-handle-transform"),
                authors(&svg, "").replacen(r#""a": 1"#, r#""a": 1e300"#, 1),
                args,
                &["scene.json", "gHandles[0].transform", "not finite or beyond ±1e9"],
            ),
            scene(
                n("huge-handle-position"),
                authors(&svg, "").replace("[90, 50]", "[90, -1e300]"),
                args,
                &["scene.json", "gHandles[1].pos", "not a finite position"],
            ),
            scene(
                n("frame-with-wrong-count"),
                authors(&svg, &format!(r#", "animationFrames": [[{IDENTITY}, {IDENTITY}], [{IDENTITY}]]"#)),
                args,
                &["scene.json", "animationFrames[1]", "1 transforms for 2 handles"],
            ),
            scene(
                n("huge-frame"),
                authors(&svg, &format!(r#", "animationFrames": [[{IDENTITY}, {}]]"#, IDENTITY.replace(r#""f": 0"#, r#""f": 1e300"#))),
                args,
                &["scene.json", "animationFrames[0][1]", "not finite or beyond ±1e9"],
            ),
            scene(
                n("unknown-frame"),
                authors(&svg, &format!(r#", "animationFrames": [[{IDENTITY}, {IDENTITY}]]"#)),
                &[args, &["--pose", "2"]].concat().leak()[..],
                &["scene.json", "pose '2' does not exist", "(poses: 0, 1 'frame 0')"],
            ),
            // The authors' scenes have point handles only: mvc, a cage's family, cannot weigh them.
            scene(
                n("weights-mvc"),
                authors(&svg, r#", "weightFunction": "mvc""#),
                args,
                &["scene.json", "weights", "cage's vertices only"],
            ),
            scene(
                n("weights-garbage"),
                authors(&svg, r#", "weightFunction": "magic""#),
                args,
                &["scene.json", "unknown weight family 'magic'", "expected shepard"],
            ),
            scene(
                n("engine-garbage"),
                authors(&svg, r#", "engineType": "quantum""#),
                args,
                &["scene.json", "unknown engine 'quantum'", "expected ours"],
            ),
            scene(
                n("unknown-continuity"),
                authors(&svg, r#", "gPathsControlPointConstraints": [[{"continuity": "C0"}, {"continuity": "C9"}]]"#),
                args,
                &["scene.json", "gPathsControlPointConstraints[0][1]", "unknown continuity 'C9'"],
            ),
            scene(
                n("arc-length-not-bool"),
                authors(&svg, r#", "usingArcLengthParameterization": "yes""#),
                args,
                &["scene.json", "invalid scene JSON", "expected a boolean"],
            ),
            scene(
                n("no-handles"),
                format!(r#"{{"gInputSVGText": {}, "gHandles": []}}"#, json_string(&svg)),
                args,
                &["scene.json", "handles", "place at least one"],
            ),
            scene(
                n("handles-missing"),
                format!(r#"{{"gInputSVGText": {}}}"#, json_string(&svg)),
                args,
                &["scene.json", "missing field `gHandles`"],
            ),
        ]);
    }
    run_failures(cases);
}

/// `info FILE.svg` in both modes.
#[test]
fn malformed_info_svg() {
    let info = |name: &'static str, svg: String, compat: bool, expect: &[&'static str]| Case {
        name,
        files: vec![file("in.svg", svg)],
        args: if compat {
            vec!["info", "in.svg", "--compat", "vectorskinning"]
        } else {
            vec!["info", "in.svg"]
        },
        output: None,
        expect: expect.to_vec(),
    };
    let no_paths = r#"<svg xmlns="http://www.w3.org/2000/svg"><g><text>x</text></g></svg>"#;
    let mut cases = vec![
        info(
            "info-huge-transform",
            svg_with("M0 0 L1 1", Some("matrix(1 0 0 1 0 1e300)")),
            false,
            &["in.svg", "attribute transform=", "within ±1e9"],
        ),
        info(
            "info-huge-after-transform",
            svg_with("M0 0 L1e8 1", Some("scale(100)")),
            false,
            &["in.svg", "path#p", "beyond ±1000000000 in root user units"],
        ),
        info(
            "info-bad-viewbox",
            SVG.replace("0 0 100 100", "0 0 0 100"),
            false,
            &["in.svg", "viewBox", "positive width and height"],
        ),
        info(
            "info-root-not-svg",
            "<html><path d='M0 0 L1 1'/></html>".into(),
            false,
            &["in.svg", "root element is <html>", "expected <svg>"],
        ),
        info(
            "info-use-of-missing",
            format!(
                r##"<svg xmlns="http://www.w3.org/2000/svg"><use href="#nope"/>{}</svg>"##,
                ""
            ),
            false,
            &["in.svg", "no paths"],
        ),
    ];
    for compat in [false, true] {
        let n = |s: &str| -> &'static str {
            Box::leak(format!("info-{}{s}", if compat { "vs-" } else { "" }).into_boxed_str())
        };
        cases.extend([
            info(n("empty"), String::new(), compat, &["in.svg", "expected"]),
            info(
                n("not-xml"),
                "just words".into(),
                compat,
                &["in.svg", "XML"],
            ),
            Case {
                files: vec![file("in.svg", &b"\xff\xfe<svg/>"[..])],
                ..info(n("not-utf8"), String::new(), compat, &["in.svg", "UTF-8"])
            },
            info(
                n("no-paths"),
                no_paths.into(),
                compat,
                &["in.svg", "no paths", "expected at least one"],
            ),
            info(
                n("nan-in-path-data"),
                svg_with("M0 0 L NaN 1", None),
                compat,
                &["in.svg", "path data"],
            ),
            info(
                n("inf-in-path-data"),
                svg_with("M0 0 L inf 1", None),
                compat,
                &["in.svg", "path data"],
            ),
            info(
                n("huge-path-data"),
                svg_with("M0 0 L 1e300 1", None),
                compat,
                &["in.svg"],
            ),
        ]);
    }
    cases.push(Case {
        name: "info-missing-file",
        files: vec![],
        args: vec!["info", "nothere.svg"],
        output: None,
        expect: vec!["nothere.svg", "cannot read"],
    });
    cases.push(Case {
        name: "info-vs-missing-file",
        files: vec![],
        args: vec!["info", "nothere.svg", "--compat", "vectorskinning"],
        output: None,
        expect: vec!["nothere.svg", "cannot read"],
    });
    cases.push(Case {
        name: "info-missing-scene",
        files: vec![],
        args: vec!["info", "nothere.json"],
        output: None,
        expect: vec!["nothere.json", "cannot read"],
    });
    run_failures(cases);
}

/// `bench` with bad scenes and arguments.
#[test]
fn malformed_bench() {
    let bench = |name: &'static str,
                 files: Vec<(&'static str, Vec<u8>)>,
                 args: &[&'static str],
                 expect: &[&'static str]| {
        let mut all = vec![file("drawing.svg", SVG)];
        all.extend(files);
        let mut a = vec!["bench", "--updates", "1"];
        a.extend_from_slice(args);
        Case {
            name,
            files: all,
            args: a,
            output: None,
            expect: expect.to_vec(),
        }
    };
    run_failures(vec![
        bench("bench-nothing", vec![], &[], &["no scenes given"]),
        bench(
            "bench-missing-scene",
            vec![],
            &["nothere.json"],
            &["nothere.json", "cannot read"],
        ),
        bench(
            "bench-empty-scene",
            vec![file("scene.json", "")],
            &["scene.json"],
            &["scene.json", "not a scene"],
        ),
        bench(
            "bench-not-json",
            vec![file("scene.json", "[1, 2")],
            &["scene.json"],
            &["scene.json", "not a scene"],
        ),
        bench(
            "bench-second-scene-bad",
            vec![
                file("good.json", ours("")),
                file(
                    "scene.json",
                    ours("").replace(r#"{"rotate": 10}"#, "[1, 0, 0, 1, 0, 1e300]"),
                ),
            ],
            &["good.json", "scene.json"],
            &["scene.json", "poses[0].transforms[0]"],
        ),
        bench(
            "bench-mvc-with-points",
            vec![file(
                "scene.json",
                ours(r#", "weights": {"family": "mvc"}"#),
            )],
            &["scene.json"],
            &["scene.json", "weights", "cage's vertices only"],
        ),
        bench(
            "bench-clockwise-cage",
            vec![file(
                "scene.json",
                kinds(
                    r#""cage": [[0, 0], [0, 100], [100, 100], [100, 0]], "weights": {"family": "harmonic"}"#,
                ),
            )],
            &["scene.json"],
            &["scene.json", "cage", "clockwise"],
        ),
        bench(
            "bench-missing-svg",
            vec![file(
                "scene.json",
                ours("").replace("drawing.svg", "gone.svg"),
            )],
            &["scene.json"],
            &["scene.json", "gone.svg", "cannot read the drawing"],
        ),
        bench(
            "bench-nan-path-data",
            vec![
                file("scene.json", ours("")),
                file("drawing.svg", svg_with("M0 0 L NaN 1", None)),
            ],
            &["scene.json"],
            &["drawing.svg", "path data"],
        ),
        bench(
            "bench-vs-no-paths",
            vec![file(
                "scene.json",
                ours_inline(
                    r#"<svg xmlns="http://www.w3.org/2000/svg"><circle r="5"/></svg>"#,
                    "",
                ),
            )],
            &["scene.json", "--compat", "vectorskinning"],
            &["scene.json", "no paths to fit"],
        ),
        bench(
            "bench-authors-engine",
            vec![file(
                "scene.json",
                authors(SVG, r#", "engineType": "jacobian""#),
            )],
            &["scene.json"],
            &[
                "scene.json",
                "engine 'jacobian'",
                "bench times engine 'ours' only",
            ],
        ),
        bench(
            "bench-synthetic-too-big",
            vec![],
            &["--synthetic", "18446744073709551615"],
            &["--synthetic", "expected at most"],
        ),
    ]);
}

/// Positive controls: valid scenes in both formats and both modes produce their output, so
/// the harness does see success and written files.
#[test]
fn malformed_harness_positive_controls() {
    let authors_scene = authors(
        &svg_with("M10 50 C30 20 70 20 90 50 S120 80 150 50", None),
        "",
    );
    for (name, scene, args) in [
        ("control-ours-svg", ours(""), vec!["-o", "out.svg"]),
        (
            "control-ours-json-vs",
            ours(""),
            vec!["-o", "out.json", "--compat", "vectorskinning"],
        ),
        (
            "control-authors-json",
            authors_scene.clone(),
            vec!["-o", "out.json"],
        ),
        (
            "control-authors-svg-vs",
            authors_scene,
            vec!["-o", "out.svg", "--compat", "vectorskinning"],
        ),
    ] {
        let output = args[1];
        let case = Case {
            name,
            files: vec![file("drawing.svg", SVG), file("scene.json", scene)],
            args: [vec!["deform", "scene.json"], args].concat(),
            output: Some(output),
            expect: vec![],
        };
        let (dir, out) = case.run();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{name}: {stderr}");
        assert!(stderr.contains(&format!("-> {output}")), "{name}: {stderr}");
        let written = std::fs::read_to_string(dir.join(output)).unwrap();
        if output.ends_with(".json") {
            let v: serde_json::Value = serde_json::from_str(&written).unwrap();
            let paths = v["paths"].as_array().unwrap();
            assert!(!paths.is_empty(), "{name}: {written}");
            for p in paths {
                let pts = p["points"].as_array().unwrap();
                assert_eq!(pts.len() % 3, 1, "{name}: {written}");
                assert!(pts
                    .iter()
                    .flat_map(|q| q.as_array().unwrap())
                    .all(|c| c.as_f64().is_some_and(f64::is_finite)));
            }
        } else {
            assert!(written.contains("<path"), "{name}: {written}");
        }
        if name == "control-ours-svg" {
            // Our mode writes into the input document: its ids are kept.
            assert!(written.contains("id=\"wave\""), "{name}: {written}");
        }
        // No temporary file is left next to the output.
        let leftovers: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .flatten()
            .filter(|e| e.file_name().to_string_lossy().contains(".tmp-"))
            .collect();
        assert!(leftovers.is_empty(), "{name}: {leftovers:?}");
        // The failure check rejects this successful run (the harness can fail).
        assert!(case.check_failure(&dir, &out).is_err(), "{name}");
    }
}

/// The failure check catches each way a run can go wrong: output left behind, a leftover
/// temporary, a message that repeats itself, a missing substring.
#[test]
fn malformed_harness_rejects_bad_outcomes() {
    let case = deform(
        "harness-self-check",
        vec![file("scene.json", "")],
        &[],
        &["scene.json", "not a scene"],
    );
    let (dir, out) = case.run();
    assert_eq!(case.check_failure(&dir, &out), Ok(()));
    std::fs::write(dir.join(".out.svg.tmp-123"), "").unwrap();
    assert!(case
        .check_failure(&dir, &out)
        .unwrap_err()
        .contains("leftover"));
    std::fs::remove_file(dir.join(".out.svg.tmp-123")).unwrap();
    std::fs::write(dir.join("out.svg"), "").unwrap();
    assert!(case
        .check_failure(&dir, &out)
        .unwrap_err()
        .contains("was written"));
    std::fs::remove_file(dir.join("out.svg")).unwrap();
    let repeated = Output {
        status: out.status,
        stdout: Vec::new(),
        stderr: b"error: scene.json: not a scene: No such file or directory (os error 2): \
                  No such file or directory (os error 2)\n"
            .to_vec(),
    };
    assert!(case
        .check_failure(&dir, &repeated)
        .unwrap_err()
        .contains("repeats"));
    let wrong = Case {
        expect: vec!["a message nobody writes"],
        ..case
    };
    assert!(wrong
        .check_failure(&dir, &out)
        .unwrap_err()
        .contains("lacks"));
}

/// A scene of ours with the SVG file `drawing.svg` and the members `members` (handles of any
/// kind, weights, domain, poses).
fn kinds(members: &str) -> String {
    format!("{{\"splineskin_scene\": 1, \"svg\": \"drawing.svg\",\n  {members}}}")
}

/// A counter-clockwise cage around `SVG`.
const CAGE: &str = r#""cage": [[0, 0], [100, 0], [100, 100], [0, 100]]"#;

/// Coarse domain options (a few hundred vertices) to keep the mesh families fast.
const COARSE: &str = r#""domain": {"max_area_fraction": 0.002, "samples_per_diagonal": 100}"#;

/// Bones, cages and domain options (issue 4): bad handles and options through `deform`, `info`
/// and `bench`, each naming the scene and the element.
#[test]
fn malformed_handle_kinds() {
    let harmonic = r#""weights": {"family": "harmonic"}"#;
    let k = |name: &'static str, members: String, expect: &[&'static str]| {
        deform(name, vec![file("scene.json", kinds(&members))], &[], expect)
    };
    let mut cases = vec![
        k(
            "kinds-handle-outside-cage",
            format!(r#"{CAGE}, "handles": [{{"position": [150, 50]}}], {harmonic}, {COARSE}"#),
            &["scene.json", "handles[0]", "outside the domain"],
        ),
        k(
            "kinds-bone-outside-cage",
            format!(
                r#"{CAGE}, "bones": [{{"ends": [[50, 50], [150, 50]]}}], {harmonic}, {COARSE}"#
            ),
            &["scene.json", "bones[0]", "not inside the domain"],
        ),
        k(
            "kinds-coincident-handles",
            r#""handles": [{"position": [10, 50]}, {"position": [10, 50]}]"#.into(),
            &["scene.json", "handles[0] and handles[1]", "coincide"],
        ),
        k(
            "kinds-crossing-bones",
            format!(
                r#""bones": [{{"ends": [[10, 10], [90, 90]]}}, {{"ends": [[10, 90], [90, 10]]}}], {harmonic}, {COARSE}"#
            ),
            &["scene.json", "bones[0] and bones[1]", "intersect"],
        ),
        k(
            "kinds-self-intersecting-cage",
            format!(r#""cage": [[0, 0], [100, 100], [100, 0], [0, 100]], {harmonic}"#),
            &["scene.json", "cage[", "not simple"],
        ),
        k(
            "kinds-clockwise-cage",
            format!(r#""cage": [[0, 0], [0, 100], [100, 100], [100, 0]], {harmonic}"#),
            &["scene.json", "cage", "clockwise", "counter-clockwise"],
        ),
        k(
            "kinds-cage-of-two",
            format!(r#""cage": [[0, 0], [100, 0]], {harmonic}"#),
            &["scene.json", "cage", "at least 3"],
        ),
        k(
            "kinds-empty-cage",
            format!(r#""cage": [], {harmonic}"#),
            &["scene.json", "cage", "at least 3"],
        ),
        k(
            "kinds-nan-in-cage",
            format!("\"cage\": [[0, 0], [100, 0],\n [NaN, 100]], {harmonic}"),
            &["scene.json", "invalid scene JSON", "line 3"],
        ),
        k(
            "kinds-nan-in-bone",
            "\"bones\": [{\"ends\": [[0, 0],\n [NaN, 5]]}]".into(),
            &["scene.json", "invalid scene JSON", "line 3"],
        ),
        k(
            "kinds-inf-in-bone",
            r#""bones": [{"ends": [[0, 0], [1e999, 5]]}]"#.into(),
            &["scene.json", "invalid scene JSON", "number out of range"],
        ),
        k(
            "kinds-huge-cage-vertex",
            format!(r#""cage": [[0, 0], [1e300, 0], [0, 100]], {harmonic}"#),
            &["scene.json", "cage[1]", "not a finite position within ±1e9"],
        ),
        k(
            "kinds-huge-bone-end",
            r#""bones": [{"ends": [[0, 0], [0, -1e300]]}]"#.into(),
            &["scene.json", "bones[0].ends[1]", "not a finite position"],
        ),
        k(
            "kinds-zero-length-bone",
            r#""bones": [{"ends": [[10, 10], [10, 10]]}]"#.into(),
            &["scene.json", "bones[0]", "zero length"],
        ),
        k(
            "kinds-unknown-top-level-key",
            r#""handles": [{"position": [10, 50]}], "cage_vertices": [[0, 0]]"#.into(),
            &["scene.json", "unknown field `cage_vertices`"],
        ),
        k(
            "kinds-unknown-bone-key",
            r#""bones": [{"ends": [[0, 0], [0, 10]], "rigid": true}]"#.into(),
            &[
                "scene.json",
                "unknown field `rigid`",
                "expected `ends` or `transform`",
            ],
        ),
        k(
            "kinds-unknown-bone-transform",
            r#""bones": [{"ends": [[0, 0], [0, 10]], "transform": "bendy"}]"#.into(),
            &["scene.json", "unknown variant `bendy`", "`rigid`"],
        ),
        k(
            "kinds-unknown-domain-key",
            format!(
                r#""handles": [{{"position": [10, 50]}}], {harmonic}, "domain": {{"min_angel": 20}}"#
            ),
            &["scene.json", "unknown field `min_angel`"],
        ),
        k(
            "kinds-domain-min-angle",
            format!(
                r#""handles": [{{"position": [10, 50]}}], {harmonic}, "domain": {{"min_angle": 50}}"#
            ),
            &["scene.json", "domain.min_angle", "out of range"],
        ),
        k(
            "kinds-domain-area-fraction",
            format!(
                r#""handles": [{{"position": [10, 50]}}], {harmonic}, "domain": {{"max_area_fraction": 0}}"#
            ),
            &["scene.json", "domain.max_area_fraction", "out of range"],
        ),
        k(
            "kinds-domain-with-shepard",
            r#""handles": [{"position": [10, 50]}], "domain": {"holes": true}"#.into(),
            &["scene.json", "domain", "mesh families"],
        ),
        k(
            "kinds-shepard-cage",
            CAGE.to_string(),
            &["scene.json", "weights", "not a cage"],
        ),
        k(
            "kinds-mvc-with-bones",
            format!(
                r#"{CAGE}, "bones": [{{"ends": [[10, 10], [20, 20]]}}], "weights": {{"family": "mvc"}}"#
            ),
            &["scene.json", "weights", "cage's vertices only"],
        ),
        k(
            "kinds-mvc-domain-options",
            format!(r#"{CAGE}, "weights": {{"family": "mvc"}}, {COARSE}"#),
            &["scene.json", "domain", "mesh families", "not to 'mvc'"],
        ),
        k(
            "kinds-rigid-bone-scaled",
            r#""handles": [{"position": [10, 50]}], "bones": [{"ends": [[35, 45], [65, 40]]}],
               "pose": [[1, 0, 0, 1, 0, 0], {"scale": 2}]"#
                .into(),
            &[
                "scene.json",
                "poses[0].transforms[1] (bones[0])",
                "rotation and translation",
            ],
        ),
        k(
            "kinds-ends-for-a-point",
            r#""handles": [{"position": [10, 50]}], "pose": [{"ends": [[0, 0], [1, 1]]}]"#.into(),
            &["scene.json", "poses[0].transforms[0]", "poses a bone"],
        ),
        k(
            "kinds-cage-positions-count",
            format!(r#"{CAGE}, {harmonic}, "poses": [{{"cage_positions": [[0, 0], [1, 1]]}}]"#),
            &[
                "scene.json",
                "poses[0].cage_positions",
                "2 positions for 4 cage vertices",
            ],
        ),
        k(
            "kinds-pose-count",
            format!(
                r#"{CAGE}, "handles": [{{"position": [50, 50]}}], {harmonic}, "pose": [[1, 0, 0, 1, 0, 0]]"#
            ),
            &[
                "scene.json",
                "poses[0]",
                "1 transforms for 5 handles",
                "1 point handles, then 4 cage vertices",
            ],
        ),
        k(
            "kinds-no-handles",
            harmonic.to_string(),
            &["scene.json", "handles", "place at least one"],
        ),
    ];
    // The empty domain: a drawing of one point, no cage.
    cases.push(deform(
        "kinds-empty-domain",
        vec![
            file(
                "scene.json",
                kinds(&format!(
                    r#""handles": [{{"position": [10, 10]}}], {harmonic}"#
                )),
            ),
            file("drawing.svg", svg_with("M10 10 L10 10", None)),
        ],
        &[],
        &["scene.json", "domain", "empty domain"],
    ));
    // `info` refuses a scene whose cage is invalid (it is checked on load).
    cases.push(Case {
        name: "kinds-info-clockwise-cage",
        files: vec![
            file("drawing.svg", SVG),
            file(
                "scene.json",
                kinds(&format!(
                    r#""cage": [[0, 0], [0, 100], [100, 100], [100, 0]], {harmonic}"#
                )),
            ),
        ],
        args: vec!["info", "scene.json"],
        output: None,
        expect: vec!["scene.json", "cage", "clockwise"],
    });
    run_failures(cases);
}

/// Positive controls for the handle kinds: a bone scene and a cage scene deform, `info`
/// reports the kinds and the domain's size.
#[test]
fn malformed_handle_kinds_positive_controls() {
    let scenes = [
        (
            "control-bones",
            kinds(&format!(
                r#""handles": [{{"position": [10, 50]}}],
                   "bones": [{{"ends": [[35, 45], [65, 40]]}}, {{"ends": [[65, 40], [85, 70]], "transform": "affine"}}],
                   "weights": {{"family": "harmonic"}}, {COARSE},
                   "pose": [{{"translate": [0, 5]}}, {{"ends": [[35, 45], [60, 30]]}}, {{"ends": [[60, 30], [90, 60]]}}]"#
            )),
            "3 handles (1 points, then 2 bones (1 rigid, 1 affine))",
        ),
        (
            "control-cage",
            kinds(&format!(
                r#"{CAGE}, "weights": {{"family": "harmonic"}}, {COARSE},
                   "poses": [{{"cage_positions": [[0, 0], [100, 0], [130, 120], [0, 100]]}}]"#
            )),
            "4 handles (4 cage vertices)",
        ),
        (
            "control-cage-mvc",
            kinds(&format!(
                r#"{CAGE}, "weights": {{"family": "mvc"}},
                   "pose": [{{"position": [0, 0]}}, [1, 0, 0, 1, 0, 0], {{"translate": [30, 20]}}, {{"position": [0, 100]}}]"#
            )),
            "4 handles (4 cage vertices)",
        ),
    ];
    for (name, scene, summary) in scenes {
        let case = Case {
            name,
            files: vec![file("drawing.svg", SVG), file("scene.json", scene)],
            args: vec!["deform", "scene.json", "-o", "out.json"],
            output: Some("out.json"),
            expect: vec![],
        };
        let (dir, out) = case.run();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{name}: {stderr}");
        let written = std::fs::read_to_string(dir.join("out.json")).unwrap();
        let v: serde_json::Value = serde_json::from_str(&written).unwrap();
        assert_eq!(v["paths"].as_array().unwrap().len(), 2, "{name}");
        assert!(case.check_failure(&dir, &out).is_err(), "{name}");
        let info = Command::new(env!("CARGO_BIN_EXE_splineskin"))
            .args(["info", "scene.json"])
            .current_dir(&dir)
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&info.stdout);
        assert!(info.status.success(), "{name}: {stdout}");
        assert!(stdout.contains(summary), "{name}: {stdout}");
        // Mesh families report their domain; mean value coordinates have none.
        assert_eq!(
            stdout.contains("domain: ") && stdout.contains(" triangles"),
            !name.ends_with("mvc"),
            "{name}: {stdout}"
        );
    }
}

/// What browsers draw although it is not strictly valid is read as they read it, with a
/// warning naming the file, the element and what was done: a transform that does not parse
/// (NaN, a number beyond floating point) is ignored, as chromium ignores it.
#[test]
fn lenient_input_is_read_with_warnings() {
    for (name, transform) in [
        ("lenient-nan-transform", "translate(NaN 1)"),
        ("lenient-inf-transform", "matrix(1 0 0 1 0 -1e999)"),
    ] {
        let case = Case {
            name,
            files: vec![file("in.svg", svg_with("M0 0 L1 1", Some(transform)))],
            args: vec!["info", "in.svg"],
            output: None,
            expect: Vec::new(),
        };
        let (_dir, out) = case.run();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{name}: {stderr}");
        let expected = format!(
            "warning: in.svg: path#p (line 1): attribute transform=\"{transform}\" ignored (not \
             a transform list), as browsers ignore it"
        );
        assert!(stderr.contains(&expected), "{name}: {stderr}");
    }
}
