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

use crate::drawing::Drawing;

use super::handle_weights::{bbw_only, mesh_domain, solve_columns, SolvedColumns, WeightInputs};
use super::{MeshFamily, Scene, SceneError};

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
