//! Typed reader for `../shared/data/vectorskinning/authors-solver-outputs/*.json`.
#![allow(dead_code, missing_docs)]

use kurbo::{Affine, Point};
use serde::Deserialize;
use splineskin::drawing::JointKind;

#[derive(Deserialize)]
pub struct InputPath {
    pub closed: bool,
    pub cubic_bezier_chain: Vec<[f64; 2]>,
}

#[derive(Deserialize)]
pub struct AuthorsCase {
    pub case: String,
    pub source_json: String,
    pub engine_type: String,
    pub weight_function: String,
    pub using_arc_length: bool,
    pub input_paths: Vec<InputPath>,
    pub constraints_used: Vec<Vec<(String, bool)>>,
    pub handle_positions: Vec<[f64; 2]>,
    pub handle_transforms_2x3: Vec<[[f64; 3]; 2]>,
    pub deformed_paths: Vec<Vec<[f64; 2]>>,
    pub singular_fallback_used: bool,
    /// BBW scenes: the authors' BBW solve failed and their code used Shepard weights instead
    /// (absent for other families).
    #[serde(default)]
    pub bbw_fell_back_to_shepard: Option<bool>,
}

impl AuthorsCase {
    pub fn load(path: &std::path::Path) -> AuthorsCase {
        let text = std::fs::read_to_string(path).expect("read case");
        serde_json::from_str(&text).expect("parse case")
    }

    pub fn joint_kinds(&self, path: usize) -> Vec<JointKind> {
        let closed = self.input_paths[path].closed;
        let mut v: Vec<JointKind> = self.constraints_used[path]
            .iter()
            .map(|(k, _)| match k.as_str() {
                "C0" => JointKind::C0,
                "C1" => JointKind::C1,
                "G1" => JointKind::G1,
                "A" => JointKind::FixedAngle,
                "None" => JointKind::End,
                other => panic!("unknown kind {other}"),
            })
            .collect();
        let n = (self.input_paths[path].cubic_bezier_chain.len() - 1) / 3;
        if !closed && v.len() == n {
            v.push(JointKind::End);
        }
        v
    }

    pub fn has_flexible_joints(&self) -> bool {
        self.constraints_used
            .iter()
            .flatten()
            .any(|(k, _)| k == "G1" || k == "A")
    }

    pub fn pose(&self) -> Vec<Affine> {
        self.handle_transforms_2x3
            .iter()
            .map(|m| Affine::new([m[0][0], m[1][0], m[0][1], m[1][1], m[0][2], m[1][2]]))
            .collect()
    }

    pub fn handles(&self) -> Vec<Point> {
        self.handle_positions
            .iter()
            .map(|p| Point::new(p[0], p[1]))
            .collect()
    }
}

/// Every case of `authors-solver-outputs` for which `keep` holds, sorted by file name.
pub fn cases_where(
    data_root: &std::path::Path,
    keep: impl Fn(&AuthorsCase) -> bool,
) -> Vec<AuthorsCase> {
    super::external_data::authors_solver_outputs(data_root)
        .iter()
        .map(|f| AuthorsCase::load(f))
        .filter(|c| keep(c))
        .collect()
}

/// Every case of `authors-solver-outputs` with Shepard weights, the paper's engine and no G¹ or
/// angle joints (the cases the linear fit must reproduce), sorted by name.
pub fn shepard_linear_cases(data_root: &std::path::Path) -> Vec<AuthorsCase> {
    cases_where(data_root, |c| {
        c.weight_function == "shepard" && c.engine_type == "ours" && !c.has_flexible_joints()
    })
}

/// The shared data folder with each of the 7 [`shepard_linear_cases`] (their count is
/// asserted); none when the data is missing (the calling test then skips, see
/// [`super::data_root`]).
pub fn seven_shepard_linear_cases() -> Vec<(std::path::PathBuf, AuthorsCase)> {
    let Some(root) = super::data_root() else {
        return Vec::new();
    };
    let cases = shepard_linear_cases(&root);
    assert_eq!(cases.len(), 7, "expected the 7 Shepard linear cases");
    cases.into_iter().map(|c| (root.clone(), c)).collect()
}

/// Every case of `authors-solver-outputs` with Shepard weights, the paper's engine and G¹ or
/// angle joints (flexible in their solver: the `fixed` flag of `[kind, fixed]` pins a joint's
/// position, and is false everywhere), sorted by name.
pub fn shepard_flexible_cases(data_root: &std::path::Path) -> Vec<AuthorsCase> {
    cases_where(data_root, |c| {
        c.weight_function == "shepard" && c.engine_type == "ours" && c.has_flexible_joints()
    })
}

/// Largest distance per path between `points` (flat, in the drawing's layout) and the
/// authors' `deformed` chains, divided by `diag`.
/// The largest of the per-path `errors` of the paths not in `excluded`.
pub fn worst_except(errors: &[f64], excluded: &[usize]) -> f64 {
    errors
        .iter()
        .enumerate()
        .filter(|(p, _)| !excluded.contains(p))
        .map(|(_, e)| *e)
        .fold(0.0, f64::max)
}

pub fn per_path_errors(
    drawing: &splineskin::drawing::Drawing,
    points: &[Point],
    deformed: &[Vec<[f64; 2]>],
    diag: f64,
) -> Vec<f64> {
    drawing
        .path_ranges()
        .zip(deformed)
        .map(|(range, theirs)| {
            assert_eq!(range.len(), theirs.len());
            points[range]
                .iter()
                .zip(theirs)
                .map(|(p, q)| (*p - Point::new(q[0], q[1])).hypot() / diag)
                .fold(0.0, f64::max)
        })
        .collect()
}
