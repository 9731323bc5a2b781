//! Bounded biharmonic weights solved a few columns at a time and put back together.
//!
//! Each handle's bounded biharmonic weight is a program of its own (the columns of
//! [`crate::weights::bbw`] share no constraint), so the columns of one rig can be solved in
//! different processes: a WebAssembly module runs on one thread, and the static editor spreads
//! a rig's columns over several Web Workers this way. Every worker builds the same domain from
//! the same scene ([`crate::domain::Domain::build`] is deterministic), solves its columns with
//! [`bbw_columns`], and the rig is then built with all of them given
//! ([`super::WeightInputs::solved`]): the weights are the ones a single solve gives, bit for
//! bit.

use serde::{Deserialize, Serialize};

use crate::domain::{Domain, DomainOptions};
use crate::drawing::Drawing;
use crate::weights::bbw::BbwOptions;
use crate::weights::coarse_to_fine::bbw_coarse_to_fine;
use crate::weights::{DirichletData, VertexWeights, WeightsError};

use super::setup::{bbw_only, handle_dirichlet_data, mesh_domain, WeightInputs};
use super::{MeshFamily, Scene, SceneError};

/// Raw (not normalised) bounded biharmonic columns of a rig, solved on the domain its scene
/// builds: `values[k * n_vertices + v]` is column `columns[k]` (a handle in rig order) at
/// domain vertex `v`.
///
/// ```
/// use splineskin::scene::{Compat, Scene};
/// let json = r#"{"splineskin_scene": 1,
///   "svg_text": "<svg xmlns='http://www.w3.org/2000/svg'><path d='M0 0 C1 1 2 1 3 0' stroke='black'/></svg>",
///   "handles": [{"position": [0, 0]}, {"position": [1.5, 0.7]}, {"position": [3, 0]}],
///   "weights": {"family": "bbw"}}"#;
/// let scene = Scene::from_json(json, "example", None)?;
/// let first = scene.bbw_columns(Compat::None, &[0, 2], None)?;
/// let second = scene.bbw_columns(Compat::None, &[1], None)?;
/// assert_eq!(first.columns, [0, 2]);
/// assert_eq!(first.values.len(), 2 * first.n_vertices);
/// // Handle 0's column is 1 at its own vertex and 0 at the others'.
/// assert!(first.values[..first.n_vertices].iter().all(|w| (0.0..=1.0).contains(w)));
/// # let _ = second;
/// # Ok::<(), splineskin::scene::SceneError>(())
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolvedColumns {
    /// Vertices of the domain they were solved on.
    pub n_vertices: usize,
    /// The handles (rig order) of the columns, in the order of `values`.
    pub columns: Vec<usize>,
    /// The columns, one after the other, `n_vertices` each.
    pub values: Vec<f64>,
}

impl SolvedColumns {
    /// Checks them against a domain of `n_vertices` vertices and a rig of `n_handles` handles:
    /// the shape, columns that exist and do not repeat, values in `[0, 1]`. Errors name
    /// `weights.solved` of `origin`.
    fn check(&self, n_vertices: usize, n_handles: usize, origin: &str) -> Result<(), SceneError> {
        let invalid = |message: String| SceneError::invalid(origin, "weights.solved", message);
        if self.n_vertices != n_vertices {
            return Err(invalid(format!(
                "solved on a domain of {} vertices; this scene's has {n_vertices} (expected the \
                 same scene and domain options)",
                self.n_vertices
            )));
        }
        if self.values.len() != self.columns.len() * n_vertices {
            return Err(invalid(format!(
                "{} values for {} columns of {n_vertices} vertices",
                self.values.len(),
                self.columns.len()
            )));
        }
        let mut seen = vec![false; n_handles];
        for &c in &self.columns {
            match seen.get_mut(c) {
                None => {
                    return Err(invalid(format!(
                        "column {c} does not exist (the rig has {n_handles} handles)"
                    )))
                }
                Some(true) => return Err(invalid(format!("column {c} is given twice"))),
                Some(s) => *s = true,
            }
        }
        if let Some(k) = self.values.iter().position(|w| !(0.0..=1.0).contains(w)) {
            return Err(invalid(format!(
                "column {} at vertex {}: {} is not a bounded weight (expected 0 to 1)",
                self.columns[k / n_vertices],
                k % n_vertices,
                self.values[k]
            )));
        }
        Ok(())
    }
}

impl Scene {
    /// The raw bounded biharmonic columns `columns` (handles in rig order) of this scene's
    /// weights, solved on the domain [`Scene::setup`] builds; `stop` ends the solve early with
    /// the error of [`Scene::setup_with`]. Errors if the scene's weights are not `bbw`,
    /// a column does not exist, or as [`Scene::setup`].
    pub fn bbw_columns(
        &self,
        compat: super::Compat,
        columns: &[usize],
        stop: Option<&crate::stop::StopSignal>,
    ) -> Result<SolvedColumns, SceneError> {
        bbw_only(&self.weights, &self.origin, "weights")?;
        self.check_supported()?;
        let (drawing, _) = self.drawing_with_junctions(compat)?;
        let inputs = WeightInputs {
            stop,
            ..self.weight_inputs(compat)
        };
        bbw_columns(&drawing, &inputs, columns)
    }
}

/// The raw bounded biharmonic columns `columns` of `inputs`' handles on `drawing`'s domain
/// ([`Scene::bbw_columns`]).
pub fn bbw_columns(
    drawing: &Drawing,
    inputs: &WeightInputs<'_>,
    columns: &[usize],
) -> Result<SolvedColumns, SceneError> {
    let (options, domain, data) = mesh_domain(drawing, inputs, MeshFamily::Bbw.name())?;
    let raw = solve_columns(drawing, inputs, &options, &domain, &data, columns)?;
    Ok(SolvedColumns {
        n_vertices: raw.n_vertices(),
        columns: columns.to_vec(),
        values: (0..columns.len()).flat_map(|k| raw.column(k)).collect(),
    })
}

/// Every raw bounded biharmonic column of `inputs`' handles on `domain`: those given in
/// `inputs.solved` (checked against the domain), the others solved here. `n_vertices × h`.
pub(super) fn all_columns(
    drawing: &Drawing,
    inputs: &WeightInputs<'_>,
    options: &DomainOptions,
    domain: &Domain,
    data: &DirichletData,
) -> Result<VertexWeights, SceneError> {
    let h = data.n_columns();
    let Some(solved) = inputs.solved else {
        let all: Vec<usize> = (0..h).collect();
        return solve_columns(drawing, inputs, options, domain, data, &all);
    };
    let n = domain.mesh.n_vertices();
    solved.check(n, h, inputs.origin)?;
    // Row-major, as VertexWeights holds them: vertex v's weights at v * h ..
    let mut values = vec![0.0; n * h];
    let mut given = vec![false; h];
    for (k, &c) in solved.columns.iter().enumerate() {
        for (v, &w) in solved.values[k * n..(k + 1) * n].iter().enumerate() {
            values[v * h + c] = w;
        }
        given[c] = true;
    }
    let missing: Vec<usize> = (0..h).filter(|&c| !given[c]).collect();
    if !missing.is_empty() {
        let raw = solve_columns(drawing, inputs, options, domain, data, &missing)?;
        for (v, row) in values.chunks_mut(h).enumerate() {
            for (&c, &w) in missing.iter().zip(raw.row(v)) {
                row[c] = w;
            }
        }
    }
    VertexWeights::from_row_major(n, h, values).map_err(|e| weights_error(inputs, e))
}

/// The raw columns `columns` of `data` on `domain` (`n_vertices × columns.len()`), solved
/// coarse to fine (same minimiser, a fraction of the active-set re-solves), columns in
/// parallel. Errors name a column that does not exist.
fn solve_columns(
    drawing: &Drawing,
    inputs: &WeightInputs<'_>,
    options: &DomainOptions,
    domain: &Domain,
    data: &DirichletData,
    columns: &[usize],
) -> Result<VertexWeights, SceneError> {
    let name = MeshFamily::Bbw.name();
    let selected = data
        .select_columns(columns)
        .map_err(|e| weights_error(inputs, e))?;
    let coarse_data = |d: &Domain| {
        handle_dirichlet_data(d, inputs, name)
            .ok()?
            .select_columns(columns)
            .ok()
    };
    let handles = &inputs.handles;
    bbw_coarse_to_fine(
        drawing,
        handles.points,
        &handles.bone_segments(),
        options,
        domain,
        &selected,
        coarse_data,
        &BbwOptions::default()
            .with_parallel(true)
            .with_stop(inputs.stop.cloned()),
    )
    .map_err(|e| weights_error(inputs, e))
}

/// A weights error of the `bbw` family of `inputs`' scene.
fn weights_error(inputs: &WeightInputs<'_>, e: WeightsError) -> SceneError {
    SceneError::Weights {
        origin: inputs.origin.to_string(),
        family: MeshFamily::Bbw.name(),
        source: Box::new(e),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Compat, SetupControl};
    use kurbo::Point;

    /// Two separate shapes (a wave and a blob), four pins: big enough for coarse levels, and
    /// columns whose bounds are active.
    fn scene() -> Scene {
        let json = r#"{"splineskin_scene": 1,
          "svg_text": "<svg xmlns='http://www.w3.org/2000/svg' viewBox='0 0 200 100'><path d='M10 50 C40 0 80 100 110 50' stroke='black' stroke-width='6' fill='none'/><path d='M130 20 C190 10 190 90 130 80 Z' fill='red'/></svg>",
          "handles": [{"position": [10, 50]}, {"position": [60, 50]}, {"position": [110, 50]},
                      {"position": [160, 50]}],
          "weights": {"family": "bbw"}}"#;
        Scene::from_json(json, "two shapes", None).unwrap()
    }

    /// The weights of a setup at a grid of points over the drawing.
    fn sampled(setup: &crate::scene::Setup) -> Vec<f64> {
        let h = setup.weights.n_handles();
        let mut out = Vec::new();
        let mut row = vec![0.0; h];
        for i in 0..=20 {
            for j in 0..=10 {
                setup
                    .weights
                    .eval(Point::new(10.0 * i as f64, 10.0 * j as f64), &mut row);
                out.extend_from_slice(&row);
            }
        }
        out
    }

    #[test]
    fn columns_solved_apart_give_the_same_weights_bit_for_bit() {
        let scene = scene();
        let whole = scene.setup(Compat::None).unwrap();
        let first = scene.bbw_columns(Compat::None, &[3, 0], None).unwrap();
        let second = scene.bbw_columns(Compat::None, &[1, 2], None).unwrap();
        let mut all = first.clone();
        all.columns.extend(&second.columns);
        all.values.extend(&second.values);
        for given in [&first, &all] {
            let control = SetupControl {
                solved: Some(given),
                ..Default::default()
            };
            let apart = scene.setup_with(Compat::None, control).unwrap();
            assert_eq!(sampled(&apart), sampled(&whole));
        }
        // Control: other values given for a column change the weights.
        let mut wrong = all.clone();
        wrong.values[..all.n_vertices].fill(0.5);
        let control = SetupControl {
            solved: Some(&wrong),
            ..Default::default()
        };
        let changed = scene.setup_with(Compat::None, control).unwrap();
        assert_ne!(sampled(&changed), sampled(&whole));
    }

    #[test]
    fn bad_solved_columns_are_refused_with_their_element() {
        let scene = scene();
        let good = scene.bbw_columns(Compat::None, &[0, 1], None).unwrap();
        let n = good.n_vertices;
        let mut cases: Vec<(SolvedColumns, &str)> = Vec::new();
        let mut other_domain = good.clone();
        other_domain.n_vertices += 1;
        cases.push((other_domain, "vertices"));
        let mut short = good.clone();
        short.values.pop();
        cases.push((short, "values for 2 columns"));
        let mut missing = good.clone();
        missing.columns[1] = 7;
        cases.push((missing, "column 7 does not exist"));
        let mut twice = good.clone();
        twice.columns[1] = 0;
        cases.push((twice, "column 0 is given twice"));
        let mut unbounded = good.clone();
        unbounded.values[n + 5] = f64::NAN;
        cases.push((unbounded, "column 1 at vertex 5"));
        for (solved, expected) in cases {
            let control = SetupControl {
                solved: Some(&solved),
                ..Default::default()
            };
            let message = scene
                .setup_with(Compat::None, control)
                .err()
                .unwrap()
                .to_string();
            assert!(
                message.contains("weights.solved") && message.contains(expected),
                "{message}"
            );
        }
        let message = scene
            .bbw_columns(Compat::None, &[4], None)
            .unwrap_err()
            .to_string();
        assert!(message.contains("column 4 does not exist"), "{message}");
    }

    #[test]
    fn columns_apart_are_for_bbw_only() {
        let json = scene_json().replace("\"bbw\"", "\"harmonic\"");
        let harmonic = Scene::from_json(&json, "harmonic", None).unwrap();
        let message = harmonic
            .bbw_columns(Compat::None, &[0], None)
            .unwrap_err()
            .to_string();
        assert!(message.contains("'bbw' weights only"), "{message}");
        // Columns given to another family are refused, not ignored.
        let bbw = Scene::from_json(&scene_json(), "bbw", None).unwrap();
        let solved = bbw.bbw_columns(Compat::None, &[0, 1], None).unwrap();
        let control = SetupControl {
            solved: Some(&solved),
            ..Default::default()
        };
        let message = harmonic
            .setup_with(Compat::None, control)
            .err()
            .unwrap()
            .to_string();
        assert!(
            message.contains("weights.solved") && message.contains("'bbw' weights only"),
            "{message}"
        );
    }

    fn scene_json() -> String {
        r#"{"splineskin_scene": 1,
          "svg_text": "<svg xmlns='http://www.w3.org/2000/svg'><path d='M0 0 C1 1 2 1 3 0' stroke='black'/></svg>",
          "handles": [{"position": [0, 0]}, {"position": [3, 0]}],
          "weights": {"family": "bbw"}}"#
            .to_string()
    }
}
