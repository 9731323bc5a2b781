//! `splineskin subdiv bench SCENE…|MESH.obj… [--json] [--handles N]`: medians of the rig's
//! precomputation (limit surface, quadrature, weights at the nodes, `Â` factored and solved:
//! [`SubdivScene::setup_with`], the OBJ already read) and of its per-frame update, per input.
//!
//! A scene is timed with its own handles and weights; a bare `.obj` gets `--handles N` point
//! handles by farthest-point sampling of its vertices and Shepard weights. Updates are timed
//! over random rigid poses (a turn of up to 0.5 rad about a random axis through each handle's
//! pivot and a shift of up to a tenth of the diagonal; seeded, so reproducible).
//!
//! `--json` prints one object per input with exactly the keys `scene`, `vertices`, `faces`,
//! `handles`, `precompute_s`, `update_s` (seconds).

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use crate::output::has_extension;
use anyhow::{Context, Result};
use serde::Serialize;
use splineskin::subdiv::{
    affine3_about, farthest_point_sample, read_obj, rotation_axis_angle, Affine3, Cage, Handles3,
    Point3, SubdivScene, SurfaceWeightSpec, DEFAULT_GAUSS_POINTS, LINEAR3_IDENTITY,
};
use splineskin::weights::ShepardOptions;

/// Fewest timed precomputations per input.
const MIN_PRECOMPUTES: usize = 3;
/// Precomputations go on until this much time has been spent (or [`MAX_PRECOMPUTES`]).
const PRECOMPUTE_BUDGET: Duration = Duration::from_secs(2);
const MAX_PRECOMPUTES: usize = 50;
/// Past this much time, precomputation stops even before [`MIN_PRECOMPUTES`] runs.
const PRECOMPUTE_LIMIT: Duration = Duration::from_secs(60);
/// Fewest timed updates.
const MIN_UPDATES: usize = 200;
/// Distinct random poses cycled through by the updates.
const N_POSES: usize = 64;
/// Largest turn of a random pose, radians.
const MAX_TURN: f64 = 0.5;
/// Largest shift of a random pose per axis, as a fraction of the cage's diagonal.
const MAX_SHIFT: f64 = 0.1;

#[derive(clap::Args)]
pub struct Args {
    /// Scenes (JSON) or bare cages (`.obj`).
    inputs: Vec<PathBuf>,
    /// Print one JSON object per line instead of a table.
    #[arg(long)]
    json: bool,
    /// Point handles placed on a bare `.obj` by farthest-point sampling.
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..=1000))]
    handles: u32,
    /// Number of timed updates (at least 200).
    #[arg(long, default_value_t = 2000)]
    updates: usize,
    /// Seed of the random poses.
    #[arg(long, default_value_t = 2014)]
    seed: u64,
}

#[derive(Serialize)]
struct Row {
    scene: String,
    vertices: usize,
    faces: usize,
    handles: usize,
    precompute_s: f64,
    update_s: f64,
}

pub fn run(args: Args) -> Result<()> {
    anyhow::ensure!(!args.inputs.is_empty(), "no scenes or OBJ files given");
    if !args.json {
        println!(
            "{:<50} {:>8} {:>8} {:>8} {:>15} {:>12}",
            "input", "vertices", "faces", "handles", "precompute (s)", "update (s)"
        );
    }
    for input in &args.inputs {
        let (scene, cage) = load(input, args.handles as usize)?;
        let row = measure(input, &scene, cage, &args)?;
        if args.json {
            println!("{}", serde_json::to_string(&row)?);
        } else {
            println!(
                "{:<50} {:>8} {:>8} {:>8} {:>15.4e} {:>12.4e}",
                row.scene, row.vertices, row.faces, row.handles, row.precompute_s, row.update_s
            );
        }
    }
    Ok(())
}

/// The scene to time and its cage: the file's own, or for an `.obj` one made around it.
fn load(input: &Path, n_handles: usize) -> Result<(SubdivScene, Cage)> {
    let is_obj = has_extension(input, "obj");
    if !is_obj {
        let scene = SubdivScene::load(input)?;
        let cage = read_obj(&scene.obj)
            .with_context(|| format!("{}: reading its cage", input.display()))?;
        return Ok((scene, cage));
    }
    let cage = read_obj(input)?;
    let chosen = farthest_point_sample(cage.positions(), n_handles);
    anyhow::ensure!(
        chosen.len() == n_handles,
        "{}: {n_handles} handles asked for, but the cage has only {} distinct vertex positions",
        input.display(),
        chosen.len()
    );
    let points = chosen.iter().map(|&v| cage.positions()[v]).collect();
    let scene = SubdivScene {
        file: input.display().to_string(),
        obj: input.to_path_buf(),
        handles: Handles3::new(points, vec![])?,
        weights: SurfaceWeightSpec::Shepard(ShepardOptions::default()),
        quadrature: DEFAULT_GAUSS_POINTS,
        poses: Vec::new(),
        animation: None,
    };
    Ok((scene, cage))
}

fn measure(input: &Path, scene: &SubdivScene, cage: Cage, args: &Args) -> Result<Row> {
    let (vertices, faces) = (cage.n_vertices(), cage.n_faces());
    let diagonal = cage.bounding_box_diagonal();
    let start = Instant::now();
    let mut times = Vec::new();
    let mut setup = None;
    while times.len() < MIN_PRECOMPUTES
        || (start.elapsed() < PRECOMPUTE_BUDGET && times.len() < MAX_PRECOMPUTES)
    {
        if !times.is_empty() && start.elapsed() > PRECOMPUTE_LIMIT {
            break;
        }
        let t = Instant::now();
        let s = scene.setup_with(cage.clone())?;
        times.push(t.elapsed().as_secs_f64());
        setup = Some(s);
    }
    let setup = setup.context("no precomputation ran (a bug)")?;
    let h = scene.handles.n_handles();
    let mut rng = SplitMix(args.seed);
    let poses: Vec<Vec<Affine3>> = (0..N_POSES)
        .map(|_| {
            (0..h)
                .map(|i| rng.rigid(scene.handles.pivot(i), MAX_SHIFT * diagonal))
                .collect()
        })
        .collect();
    let mut out = vec![[0.0; 3]; vertices];
    let n = args.updates.max(MIN_UPDATES);
    let mut update_times = Vec::with_capacity(n);
    for k in 0..n {
        let pose = &poses[k % N_POSES];
        let t = Instant::now();
        setup.rig.update(pose, &mut out)?;
        update_times.push(t.elapsed().as_secs_f64());
        std::hint::black_box(&out);
    }
    Ok(Row {
        scene: input.display().to_string(),
        vertices,
        faces,
        handles: h,
        precompute_s: median(times),
        update_s: median(update_times),
    })
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        f64::NAN
    } else if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// SplitMix64: reproducible random poses without a dependency.
struct SplitMix(u64);

impl SplitMix {
    /// Uniform in `[lo, hi)`.
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        lo + (hi - lo) * ((z >> 11) as f64 / (1u64 << 53) as f64)
    }

    /// A random rigid map about `pivot` (module documentation).
    fn rigid(&mut self, pivot: Point3, reach: f64) -> Affine3 {
        let axis = [
            self.range(-1.0, 1.0),
            self.range(-1.0, 1.0),
            self.range(-1.0, 1.0),
        ];
        let turn =
            rotation_axis_angle(axis, self.range(-MAX_TURN, MAX_TURN)).unwrap_or(LINEAR3_IDENTITY);
        let shift = [
            self.range(-reach, reach),
            self.range(-reach, reach),
            self.range(-reach, reach),
        ];
        affine3_about(pivot, &turn, shift)
    }
}
