//! Conformance of the authors' SVG reading (`drawing::authors_svg`) with the chains their
//! editor sent to their solver, as recorded in
//! `../shared/data/vectorskinning/authors-solver-outputs/*.json` (`input_paths`).
//!
//! Every case must match **bitwise**: same number of chains, same `closed`, every chain point
//! equal as `f64` (the values are `float32` widened to `f64` on both sides).
//!
//! The reference numbers are read with Rust's correctly rounded `f64::from_str`: serde_json
//! without its `float_roundtrip` feature (as this crate uses it) rounds some 17-digit decimals
//! to a neighbouring double (`127.65299987792969` becomes `…967`), which would make exact
//! comparison meaningless. [`quote_numbers`] hands the numbers to serde as their exact text.

#[path = "common/external_data.rs"]
mod external_data;

use std::path::{Path, PathBuf};

use kurbo::Point;
use serde::Deserialize;
use splineskin::drawing::authors_svg::{authors_joints, read_authors_paths, AuthorsPath};
use splineskin::drawing::JointKind;

/// What these tests read of an `authors-solver-outputs/*.json` file.
#[derive(Deserialize)]
struct SolverOutput {
    /// `tests-and-results/<dir>/<file>`: the scene, under `vectorskinning/<dir>/<file>`.
    source_json: String,
    input_paths: Vec<InputPath>,
    /// Per path, per joint: `[kind, fixed]`.
    constraints_used: Vec<Vec<(String, bool)>>,
}

/// One chain as the authors' editor parsed it.
#[derive(Deserialize)]
struct InputPath {
    closed: bool,
    cubic_bezier_chain: Vec<[Decimal; 2]>,
}

/// A JSON number kept as its text (see [`quote_numbers`]).
#[derive(Deserialize)]
#[serde(transparent)]
struct Decimal(String);

impl Decimal {
    /// The correctly rounded `f64` of the text.
    fn value(&self) -> f64 {
        self.0
            .parse()
            .unwrap_or_else(|e| panic!("reference number {:?}: {e}", self.0))
    }
}

/// `json` with every number (outside strings) turned into a JSON string of its exact text.
fn quote_numbers(json: &str) -> String {
    let mut out = String::with_capacity(json.len() + json.len() / 4);
    let mut chars = json.chars().peekable();
    let (mut in_string, mut escaped) = (false, false);
    while let Some(c) = chars.next() {
        if in_string {
            out.push(c);
            if escaped {
                escaped = false;
            } else if c == '\\' {
                escaped = true;
            } else if c == '"' {
                in_string = false;
            }
        } else if c == '-' || c.is_ascii_digit() {
            out.push('"');
            out.push(c);
            while let Some(&d) = chars.peek() {
                if !(d.is_ascii_digit() || matches!(d, '.' | 'e' | 'E' | '+' | '-')) {
                    break;
                }
                out.push(d);
                chars.next();
            }
            out.push('"');
        } else {
            in_string = c == '"';
            out.push(c);
        }
    }
    out
}

/// What these tests read of a scene (`*-deformation.json`).
#[derive(Deserialize)]
struct Scene {
    #[serde(rename = "gInputSVGText")]
    input_svg_text: String,
}

/// The directory of the solver outputs and its `*.json` files, sorted.
fn solver_output_files(root: &Path) -> Vec<PathBuf> {
    let dir = root.join("vectorskinning/authors-solver-outputs");
    let entries = std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    let mut files: Vec<PathBuf> = entries
        .map(|entry| entry.expect("readable directory entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    files
}

/// Reads a JSON file into `T`, first passing its text through `prepare`.
fn read_json<T: for<'de> Deserialize<'de>>(path: &Path, prepare: fn(&str) -> String) -> T {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&prepare(&text)).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Loads a solver output and the chains our reader gives for its scene.
fn load_case(root: &Path, file: &Path) -> (SolverOutput, Vec<AuthorsPath>) {
    let output: SolverOutput = read_json(file, quote_numbers);
    let relative = output
        .source_json
        .strip_prefix("tests-and-results/")
        .unwrap_or_else(|| {
            panic!(
                "{}: unexpected source_json {}",
                file.display(),
                output.source_json
            )
        });
    let scene: Scene = read_json(&root.join("vectorskinning").join(relative), str::to_owned);
    let ours = read_authors_paths(&scene.input_svg_text)
        .unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    (output, ours)
}

/// `None` if `ours` equals `reference` bitwise, else a description of the first difference
/// and the largest coordinate difference.
fn compare(ours: &[AuthorsPath], reference: &[InputPath]) -> Option<String> {
    if ours.len() != reference.len() {
        return Some(format!(
            "{} chains, expected {}",
            ours.len(),
            reference.len()
        ));
    }
    let mut first = None;
    let mut largest = 0.0f64;
    for (i, (a, b)) in ours.iter().zip(reference).enumerate() {
        if a.closed != b.closed {
            first.get_or_insert(format!(
                "chain {i}: closed = {}, expected {}",
                a.closed, b.closed
            ));
        }
        if a.points.len() != b.cubic_bezier_chain.len() {
            let n = b.cubic_bezier_chain.len();
            first.get_or_insert(format!(
                "chain {i}: {} points, expected {n}",
                a.points.len()
            ));
            continue;
        }
        for (k, (p, q)) in a.points.iter().zip(&b.cubic_bezier_chain).enumerate() {
            let q = Point::new(q[0].value(), q[1].value());
            if p.x.to_bits() != q.x.to_bits() || p.y.to_bits() != q.y.to_bits() {
                first.get_or_insert(format!("chain {i} point {k}: {p:?}, expected {q:?}"));
                largest = largest.max((p.x - q.x).abs()).max((p.y - q.y).abs());
            }
        }
    }
    first.map(|f| format!("{f} (largest coordinate difference {largest:e})"))
}

#[test]
fn authors_svg_reproduces_every_reference_input_exactly() {
    let Some(root) = external_data::shared_data() else {
        return;
    };
    let files = solver_output_files(&root);
    assert!(!files.is_empty(), "no reference outputs found");
    let mut failures = Vec::new();
    let mut n_points = 0;
    for file in &files {
        let (output, ours) = load_case(&root, file);
        n_points += ours.iter().map(|p| p.points.len()).sum::<usize>();
        if let Some(problem) = compare(&ours, &output.input_paths) {
            failures.push(format!("{}: {problem}", file.display()));
        }
    }
    println!(
        "{} of {} cases match bitwise ({n_points} chain points)",
        files.len() - failures.len(),
        files.len()
    );
    assert!(failures.is_empty(), "mismatches:\n{}", failures.join("\n"));
}

/// Scenes whose saved joint kinds are the editor's defaults (no kind edited by hand, saved
/// with the detection described in the reference README). The other scenes' kinds were
/// edited (`A` → `C0` in the box and U-shape, a few `C0` in the clam) or saved when the editor
/// labelled smooth joints `C1` instead of `G1`.
const SCENES_WITH_DEFAULT_KINDS: [&str; 16] = [
    "box-simplest__With_A__box-simplest.json",
    "clam-songrun__clam-FourControls-Shepard__clam-songrun.json",
    "clam-songrun__clam-Jacobian-Shepard__clam-songrun.json",
    "clam-songrun__clam-Jacobian2-Shepard__clam-songrun.json",
    "clam-songrun__clam-Ours2-Shepard__clam-songrun.json",
    "clam-songrun__clam-TwoEndpoints-Shepard__clam-songrun.json",
    "schneider__long-bean-simpler__after1__long-bean-simpler.json",
    "schneider__long-bean-simpler__after2__long-bean-simpler.json",
    "songrun-caterpillar__caterpillar-songrun1-original.json",
    "songrun-caterpillar__caterpillar-songrun1.json",
    "songrun-caterpillar__caterpillar-songrun2.json",
    "turtle-seven-stack__comparison__shepard__2__point__turtles-seven.json",
    "turtle-seven-stack__comparison__shepard__4__point__turtles-seven.json",
    "turtle-seven-stack__comparison__shepard__jacobian__turtles-seven.json",
    "turtle-seven-stack__zooming__animation__after-zoomout__turtles-seven.json",
    "turtle-seven-stack__zooming__animation__after__turtles-seven.json",
];

/// The reference's name for a kind (`None` for open ends).
fn reference_kind_name(kind: JointKind) -> &'static str {
    match kind {
        JointKind::End => "None",
        JointKind::C0 => "C0",
        JointKind::C1 => "C1",
        JointKind::G1 => "G1",
        JointKind::FixedAngle => "A",
    }
}

#[test]
fn authors_joints_reproduce_default_kinds_of_unedited_scenes() {
    let Some(root) = external_data::shared_data() else {
        return;
    };
    let dir = root.join("vectorskinning/authors-solver-outputs");
    let mut n_joints = 0;
    for name in SCENES_WITH_DEFAULT_KINDS {
        let (output, ours) = load_case(&root, &dir.join(name));
        assert_eq!(ours.len(), output.constraints_used.len(), "{name}");
        for (i, (path, used)) in ours.iter().zip(&output.constraints_used).enumerate() {
            let kinds = authors_joints(&path.points, path.closed)
                .unwrap_or_else(|| panic!("{name} chain {i}: not a valid chain"));
            let names: Vec<&str> = kinds.into_iter().map(reference_kind_name).collect();
            let expected: Vec<&str> = used.iter().map(|(kind, _)| kind.as_str()).collect();
            assert_eq!(names, expected, "{name} chain {i}");
            n_joints += names.len();
        }
    }
    println!(
        "{n_joints} joints of {} scenes match",
        SCENES_WITH_DEFAULT_KINDS.len()
    );
}
