//! The routes about deformation operators: the page's point handles joined to an operator
//! trained on the drawing's domain (DESIGN.md top, "The join"; §4), and the server's own
//! evaluation of it (the crate's documentation has the table of routes).
//!
//! ```text
//! POST /api/defop:  the scene's defop section (scene_file::defop_settings: the page's energy
//!                   and samples) → Scene::defop_shape (the drawing's domain) → train, as
//!                   `splineskin defop train` does → DefOpRig::precompute   (once, seconds)
//! page, each frame: points = G_spline · ψ(Q)                              (rig.js, DefOpLiveRig)
//! ```
//!
//! The operator moves the drawing by the handles' *positions* `Q`: the page evaluates
//! `q_i = T_i(p_i)` from each handle's map `T_i` and rest position `p_i`, so rotating or
//! scaling a handle about itself moves nothing. Flexible G¹ does not apply (the join keeps the
//! drawing's junction constraints as they are); a scene asking for it is refused.

use kurbo::Point;
use serde::{Deserialize, Serialize};
use splineskin::defop::{train, DefOpRig, Progress};
use splineskin::scene::Compat;

use crate::document_routes::gone_operator;
use crate::editor::{ApiError, Editor, Request, Response, MAX_OPERATOR_BYTES};
use crate::progress::{Count, Followed};
use crate::rig_routes::page_scene;
use crate::scene_file::defop_energy;
use crate::store::OperatorRig;
use crate::wire::{EditScene, SceneRequest};

/// Most training samples the page may ask for: 5 000 (about 2 minutes for the 9-handle
/// octopus on two cores; the issue's budget is 1 000 samples in 2 minutes).
pub const MAX_EDITOR_SAMPLES: usize = 5000;

/// Most point handles an operator takes: 64 (its thin-plate basis has `1 + 2n + m`
/// functions, and every sample is a solve with `n` constraints).
pub const MAX_DEFOP_HANDLES: usize = 64;

/// The header carrying [`DefOpInfo`] in the response of `POST /api/defop`.
pub const DEFOP_HEADER: &str = "x-splineskin-defop";

/// What the page needs, besides the numbers of the body, to evaluate `ψ(Q)`
/// (`splineskin::defop::HandleBasis`): sent as JSON in the header [`DEFOP_HEADER`].
#[derive(Clone, Debug, Serialize)]
pub struct DefOpInfo {
    /// The operator rig's id (for `POST /api/defops/{id}/deform`).
    pub id: String,
    /// The handle basis: `linear`, `quadratic`, `cubic` or `tps`.
    pub kind: &'static str,
    /// The length unit of `z = (Q − P) / scale`, root user units.
    pub scale: f64,
    /// The rest configuration `P`, one `[x, y]` per handle.
    pub rest: Vec<[f64; 2]>,
    /// `|Ψ|`.
    pub n_functions: usize,
    /// Thin-plate centres `m` (0 for polynomials).
    pub n_centres: usize,
    /// Chain points written.
    pub n_points: usize,
    /// Samples trained on, the rest configuration included.
    pub n_samples: usize,
    /// Vertices of the mesh trained on (the drawing's triangulated domain).
    pub n_vertices: usize,
    /// Triangles of the domain.
    pub n_triangles: usize,
    /// Seconds spent: triangulating, training, joining.
    pub seconds: [f64; 3],
    /// Quadrature nodes of the drawing outside the mesh (nearest-boundary values used).
    pub n_nodes_outside: usize,
}

/// `POST /api/defop`.
pub(crate) fn defop(
    editor: &Editor,
    request: &Request,
    followed: Option<&Followed>,
) -> Result<Response, ApiError> {
    let request: SceneRequest = request.json()?;
    let document = editor.document(&request.document)?;
    let stage = followed.map(|f| f.reporter());
    let count = followed.map(|f| f.counter());
    let clock = editor.progress.clock();
    let (rig, info) = {
        let scene = &request.scene;
        check_defop_scene(&document.name, scene)?;
        // Validated and read like any scene file (the one "Save scene" writes, whose `defop`
        // section holds the page's energy and sample count): the drawing with the page's
        // junction kinds, the fit options, the operator's settings.
        let library_scene = page_scene(&document, scene)?;
        let bad = |e: &dyn std::fmt::Display| ApiError::bad(format!("{}: {e}", document.name));
        let settings = library_scene.defop.clone().ok_or_else(|| {
            ApiError::new(
                500,
                "the page's scene lost its defop section (a bug in splineskin, please report it)",
            )
        })?;
        // The page's count is checked above; an opened scene's count is checked here.
        check_samples(&document.name, settings.samples)?;
        let (drawing, _) = library_scene
            .drawing_with_junctions(Compat::None)
            .map_err(|e| bad(&e))?;
        let fit = library_scene.fit_options(Compat::None).with_parallel(true);

        let report = |name: &'static str| {
            if let Some(stage) = &stage {
                stage(name);
            }
        };
        report("domain");
        let t0 = clock();
        // As `splineskin defop train` does, so that the saved scene trains the same operator.
        let shape = library_scene.defop_shape(&settings).map_err(|e| bad(&e))?;
        let spatial = settings
            .spatial_basis
            .build(&shape.mesh, &shape.handles)
            .map_err(|e| bad(&e))?;
        report("training");
        let t1 = clock();
        let options = settings.train_options(&shape.mesh);
        let on_progress = |p: Progress| {
            if let Some(count) = &count {
                count(
                    "training",
                    Count {
                        done: p.solved,
                        total: p.to_solve,
                        step: p.stage + 1,
                        steps: p.n_stages,
                    },
                );
            }
        };
        let training = train(
            &shape.mesh,
            &shape.handles,
            &spatial,
            &options,
            &on_progress,
        )
        .map_err(|e| bad(&e))?;
        report("join");
        let t2 = clock();
        let rig =
            DefOpRig::precompute(&drawing, &shape.mesh, &training.op, &fit).map_err(|e| bad(&e))?;

        let t3 = clock();
        let basis = rig.handle_basis();
        let info = DefOpInfo {
            id: String::new(),
            kind: basis.kind().name(),
            scale: basis.scale(),
            rest: basis.rest().iter().map(|p| [p.x, p.y]).collect(),
            n_functions: basis.n_functions(),
            n_centres: basis.n_centres(),
            n_points: rig.n_points(),
            n_samples: training.configurations.len(),
            n_vertices: shape.mesh.vertices.len(),
            n_triangles: shape.mesh.triangles.len(),
            seconds: [t1 - t0, t2 - t1, t3 - t2],
            n_nodes_outside: rig.n_nodes_outside(),
        };
        let bytes = 8 * (rig.coefficients().len() + info.n_centres * 2 * scene.handles.len());
        if bytes > MAX_OPERATOR_BYTES {
            return Err(ApiError::bad(format!(
                "{}: the operator takes {} MiB (at most {} MiB): use fewer samples or handles",
                document.name,
                bytes >> 20,
                MAX_OPERATOR_BYTES >> 20
            )));
        }
        let rig = OperatorRig {
            document: request.document.clone(),
            rig,
            mesh: shape.mesh,
            op: training.op,
        };
        (rig, info)
    };
    let body = defop_body(&rig.rig);
    let mut info = info;
    info.id = editor.store().add_defop(rig);
    let json = serde_json::to_string(&info).map_err(|e| ApiError::new(500, e.to_string()))?;
    Ok(Response::f64s(&body).with_header(DEFOP_HEADER, crate::document_routes::ascii_json(&json)))
}

/// The numbers the page evaluates: `G_spline` row-major `(2 · n_points) × |Ψ|` (row `2k + d`:
/// coordinate `d` of chain point `k`), then the thin-plate centres row-major
/// `n_centres × 2 n_handles` (centre `k`'s scaled displacement `z_k`, x and y of each handle
/// in turn).
fn defop_body(rig: &DefOpRig) -> Vec<f64> {
    let basis = rig.handle_basis();
    let rows = 2 * rig.n_points();
    let cols = basis.n_functions();
    let g = rig.coefficients(); // column-major
    let mut body = Vec::with_capacity(rows * cols + basis.n_centres() * 2 * basis.n_handles());
    for r in 0..rows {
        body.extend((0..cols).map(|c| g[c * rows + r]));
    }
    for k in 0..basis.n_centres() {
        body.extend_from_slice(basis.centre(k));
    }
    body
}

/// Refuses a page scene the operator cannot train on, naming the problem.
fn check_defop_scene(name: &str, scene: &EditScene) -> Result<(), ApiError> {
    let family = &scene.weights.family;
    if defop_energy(family).is_none() {
        return Err(ApiError::bad(format!(
            "{name}: '{family}' is not a deformation operator (defop-arap or defop-sarap)"
        )));
    }
    if let Some(samples) = scene.weights.samples {
        check_samples(name, samples)?;
    }
    let n_handles = scene.handles.len();
    if n_handles == 0 {
        return Err(ApiError::bad(format!(
            "{name}: a deformation operator needs at least one point handle"
        )));
    }
    if n_handles > MAX_DEFOP_HANDLES {
        return Err(ApiError::bad(format!(
            "{name}: {n_handles} handles (a deformation operator takes at most \
             {MAX_DEFOP_HANDLES})"
        )));
    }
    if let Some(i) = scene
        .handles
        .iter()
        .position(|h| !h.iter().all(|v| v.is_finite()))
    {
        return Err(ApiError::bad(format!(
            "{name}: handle {i} is at ({}, {}), not a finite position",
            scene.handles[i][0], scene.handles[i][1]
        )));
    }
    if scene.flexible {
        return Err(ApiError::bad(format!(
            "{name}: flexible G¹ does not apply to a deformation operator (its join keeps the \
             drawing's junction constraints): turn it off"
        )));
    }
    Ok(())
}

/// Refuses a sample count outside `1..=`[`MAX_EDITOR_SAMPLES`].
fn check_samples(name: &str, n_samples: usize) -> Result<(), ApiError> {
    if (1..=MAX_EDITOR_SAMPLES).contains(&n_samples) {
        Ok(())
    } else {
        Err(ApiError::bad(format!(
            "{name}: {n_samples} training samples (from 1 to {MAX_EDITOR_SAMPLES})"
        )))
    }
}

/// The body of `POST /api/defops/{id}/deform`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DeformRequest {
    /// The handle configuration `Q`, one `[x, y]` per handle (root user units).
    pub handles: Vec<[f64; 2]>,
}

/// `POST /api/defops/{id}/deform`: the library's `DefOpRig::deform` at `Q`, the reference
/// the page's own product is tested against.
pub(crate) fn deform(editor: &Editor, id: &str, request: &Request) -> Result<Response, ApiError> {
    let request: DeformRequest = request.json()?;
    let rig = editor.store().defop(id).ok_or_else(|| gone_operator(id))?;
    {
        let q: Vec<Point> = request
            .handles
            .iter()
            .map(|&[x, y]| Point::new(x, y))
            .collect();
        let points = rig
            .rig
            .deform(&q)
            .map_err(|e| ApiError::bad(e.to_string()))?;
        let flat: Vec<f64> = points.iter().flat_map(|p| [p.x, p.y]).collect();
        Ok(Response::f64s(&flat))
    }
}
