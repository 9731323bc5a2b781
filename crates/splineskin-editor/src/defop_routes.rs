//! The routes about deformation operators: the page's point handles joined to an operator
//! trained on the drawing's domain (DESIGN.md top, "The join"; §4), and the server's own
//! evaluation of it (the crate's documentation has the table of routes).
//!
//! ```text
//! POST /api/defop:  the scene's defop section (page_scene::defop_settings: the page's energy
//!                   and samples) → Scene::defop_shape (the drawing's domain) → train, as
//!                   `splineskin defop train` does → DefOpRig::precompute   (once, seconds)
//! page, each frame: points = G_spline · ψ(Q)                              (rig.js, DefOpLiveRig)
//! ```
//!
//! The operator moves the drawing by the handles' *positions* `Q`: the page evaluates
//! `q_i = T_i(p_i)` from each handle's map `T_i` and rest position `p_i`, so rotating or
//! scaling a handle about itself moves nothing. Flexible G¹ does not apply (the join keeps the
//! drawing's junction constraints as they are); a scene asking for it is refused.

use kurbo::{Point, Vec2};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

use splineskin::defop::{
    extend, train, trained_distance, DefOpError, FunctionMaps, Progress, SplineJoin,
};
use splineskin::drawing::carry::CarryOperator;
use splineskin::scene::Compat;

use crate::document_routes::gone_operator;
use crate::editor::Editor;
use crate::page_scene::defop_energy;
use crate::progress::{Count, Followed};
use crate::request::{ApiError, Request, Response, MAX_OPERATOR_BYTES};
use crate::rig_routes::checked_scene;
use crate::store::{OperatorBase, OperatorRig};
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
    /// Of those, the samples added following the user's drags (`POST /api/defops/{id}/follow`).
    pub n_followed: usize,
    /// The sampling radius, root user units: a configuration is in the trained region when
    /// some sample has every handle within [`FOLLOW_FRACTION`] of it of the configuration's
    /// ([`splineskin::defop::trained_distance`]).
    pub reach: f64,
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
        let library_scene = checked_scene(&document, scene)?;
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
        let mut options = settings.train_options(&shape.mesh);
        if let Some(followed) = followed {
            options = options.with_stop(followed.stop_signal());
        }
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
        .map_err(|e| match e {
            DefOpError::Stopped => {
                ApiError::new(409, format!("{}: training stopped as asked", document.name))
            }
            e => bad(&e),
        })?;
        report("join");
        let t2 = clock();
        // The handles pin the art under them (SplineJoin::new), as DefOpRig::precompute does.
        let pins: Vec<Point> = shape
            .handles
            .iter()
            .map(|&h| shape.mesh.vertices[h])
            .collect();
        let join = SplineJoin::new(&drawing, &shape.mesh, &pins, &fit).map_err(|e| bad(&e))?;
        let rig = join.rig(&training.op).map_err(|e| bad(&e))?;
        let t3 = clock();
        let base = Arc::new(OperatorBase {
            reach: options.reach(&shape.mesh),
            mesh: shape.mesh,
            options,
            join,
            n_trained: training.configurations.len(),
        });
        let rig = OperatorRig {
            document: request.document.clone(),
            rig,
            training,
            base,
        };
        let info = operator_info(&rig, [t1 - t0, t2 - t1, t3 - t2]);
        check_operator_size(&document.name, &rig)?;
        (rig, info)
    };
    operator_response(editor, rig, info)
}

/// The response of a new operator rig: kept in the store, its numbers ([`defop_body`]) in the
/// body, its [`DefOpInfo`] in the header.
fn operator_response(
    editor: &Editor,
    rig: OperatorRig,
    mut info: DefOpInfo,
) -> Result<Response, ApiError> {
    let body = defop_body(&rig.rig);
    info.id = editor.store().add_defop(rig);
    let json = serde_json::to_string(&info).map_err(|e| ApiError::new(500, e.to_string()))?;
    Ok(Response::f64s(&body).with_header(DEFOP_HEADER, crate::document_routes::ascii_json(&json)))
}

/// The page's description of `rig` (its id is set when the store keeps it).
fn operator_info(rig: &OperatorRig, seconds: [f64; 3]) -> DefOpInfo {
    let basis = rig.rig.handle_basis();
    let mesh = &rig.base.mesh;
    DefOpInfo {
        id: String::new(),
        kind: basis.kind().name(),
        scale: basis.scale(),
        rest: basis.rest().iter().map(|p| [p.x, p.y]).collect(),
        n_functions: basis.n_functions(),
        n_centres: basis.n_centres(),
        n_points: rig.rig.n_points(),
        n_samples: rig.training.configurations.len(),
        n_followed: rig.training.configurations.len() - rig.base.n_trained,
        reach: rig.base.reach,
        n_vertices: mesh.vertices.len(),
        n_triangles: mesh.triangles.len(),
        seconds,
        n_nodes_outside: rig.rig.n_nodes_outside(),
    }
}

/// Refuses an operator the page would hold more than [`MAX_OPERATOR_BYTES`] of.
fn check_operator_size(name: &str, rig: &OperatorRig) -> Result<(), ApiError> {
    let basis = rig.rig.handle_basis();
    let bytes = 8 * (rig.rig.coefficients().len() + basis.n_centres() * 2 * basis.n_handles());
    if bytes > MAX_OPERATOR_BYTES {
        return Err(ApiError::bad(format!(
            "{name}: the operator takes {} MiB (at most {} MiB): use fewer samples or handles",
            bytes >> 20,
            MAX_OPERATOR_BYTES >> 20
        )));
    }
    Ok(())
}

/// The numbers the page evaluates: `G_spline` row-major `(2 · n_points) × |Ψ|` (row `2k + d`:
/// coordinate `d` of chain point `k`), then the thin-plate centres row-major
/// `n_centres × 2 n_handles` (centre `k`'s scaled displacement `z_k`, x and y of each handle
/// in turn).
fn defop_body(rig: &splineskin::defop::DefOpRig) -> Vec<f64> {
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

/// `GET /api/defops/{id}/carry`: the operator's carry operator, laid out as a rig's
/// ([`crate::rig_routes::carry`]) with the `|Ψ|` handle functions in place of the pose: the
/// operator's map is `D(x, Q) = Σ_j ψ_j(Q) D_j(x)` ([`FunctionMaps`]), linear in `ψ(Q)`, so the
/// best-fit maps of the carried text, images and paint are too
/// ([`splineskin::drawing::carry::CarryOperator`]), and equal those Export SVG writes for the
/// same configuration. Empty when the document has no such element.
pub(crate) fn carry(editor: &Editor, id: &str) -> Result<Response, ApiError> {
    let rig = editor.store().defop(id).ok_or_else(|| gone_operator(id))?;
    let document = editor.document(&rig.document)?;
    if document.info.carried.is_empty() && document.info.painted.is_empty() {
        return Ok(Response::f64s(&[]));
    }
    let bad = |e: &dyn std::fmt::Display| ApiError::bad(format!("{}: {e}", document.name));
    let maps = FunctionMaps::new(&rig.base.mesh, &rig.training.op).map_err(|e| bad(&e))?;
    let n = maps.n_functions();
    let mut xy = vec![0.0; 2 * n];
    let painted = &document.info.painted;
    let carry = CarryOperator::with_elements(&document.drawing, painted, n, &mut |p, d| {
        maps.eval(p, &mut xy);
        for (d, xy) in d.iter_mut().zip(xy.chunks_exact(2)) {
            *d = Vec2::new(xy[0], xy[1]);
        }
        // The map has no part free of ψ (ψ₀ = 1 is one of the inputs).
        d[n] = Vec2::ZERO;
    })
    .map_err(|e| bad(&e))?;
    Ok(Response::f64s(carry.coefficients()))
}

/// Most samples following the user adds to one training (about 4 s of symmetric-ARAP solves
/// on the octopus in release, and `|Ψ|` grows by one per sample for thin-plate splines):
/// past it the operator stays as it is, and the answer says so.
pub const MAX_FOLLOWED_SAMPLES: usize = 400;

/// The trained region, as a fraction of the sampling radius: a configuration is in it when
/// some sample has every handle within this fraction of the radius of the configuration's
/// (`trained_distance ≤ FOLLOW_FRACTION · reach`): 0.25. Following starts there, before the
/// operator's prediction degrades, so that each ground-truth solve starts close to its
/// answer (tens of milliseconds on the octopus when the step is short) and each refit moves
/// the drawing little.
pub const FOLLOW_FRACTION: f64 = 0.25;

/// On release ([`FollowRequest::settle`]) the configuration is added alone when it lies
/// outside the scene's trained region and farther than this fraction of the sampling radius
/// from every sample: 0.01 (an operator reproduces its samples; nearer, the difference is
/// below what the page shows).
pub const SETTLE_FRACTION: f64 = 0.01;

/// The body of `POST /api/defops/{id}/follow`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FollowRequest {
    /// The handle configuration `Q` the user dragged to, one `[x, y]` per handle.
    pub handles: Vec<[f64; 2]>,
    /// The drag ended here: add `Q` itself when it lies outside the scene's region and is no
    /// sample yet ([`SETTLE_FRACTION`]), even within the reach of a followed one.
    #[serde(default)]
    pub settle: bool,
}

/// The answer of `POST /api/defops/{id}/follow` when the operator stays as it is (a new
/// operator is answered as `POST /api/defop` answers).
#[derive(Clone, Debug, Serialize)]
pub struct FollowAnswer {
    /// Always `false`: no new operator.
    pub followed: bool,
    /// Why: `inside` (the configuration is in the trained region) or `limit` (following
    /// added [`MAX_FOLLOWED_SAMPLES`] already).
    pub reason: &'static str,
    /// [`splineskin::defop::trained_distance`] of the configuration, root user units.
    pub distance: f64,
    /// The sampling radius it is compared with.
    pub reach: f64,
}

/// `POST /api/defops/{id}/follow`: the operator following the user. When the handles are
/// outside the region the operator was trained on (no sample has every handle within
/// [`FOLLOW_FRACTION`] of the sampling radius of theirs), the ground truth is solved at `Q`,
/// started from the operator's prediction (the paper's bootstrapping), the operator is
/// refitted over every sample (`splineskin::defop::extend`) and joined again by products
/// alone (`SplineJoin::rig`). A thin-plate operator reproduces its samples, so at `Q` the
/// drawing is the ground truth's fit; the handles stay interpolated at every configuration
/// (the fit's constraint) and hold the art under them (the join's). The page blends from the
/// old operator to the new over a few frames, so nothing jumps.
pub(crate) fn follow(editor: &Editor, id: &str, request: &Request) -> Result<Response, ApiError> {
    let request: FollowRequest = request.json()?;
    let rig = editor.store().defop(id).ok_or_else(|| gone_operator(id))?;
    let name = editor.document(&rig.document)?.name.clone();
    let n_handles = rig.rig.n_handles();
    if request.handles.len() != n_handles {
        return Err(ApiError::bad(format!(
            "{name}: follow: {} handle positions for an operator of {n_handles} handles",
            request.handles.len()
        )));
    }
    let q: Vec<Point> = request
        .handles
        .iter()
        .map(|&[x, y]| Point::new(x, y))
        .collect();
    if let Some(k) = q.iter().position(|p| !p.is_finite()) {
        return Err(ApiError::bad(format!(
            "{name}: follow: handle {k} is at ({}, {}), not a finite position",
            q[k].x, q[k].y
        )));
    }
    let base = &rig.base;
    let samples = &rig.training.configurations;
    let distance = trained_distance(samples, &q);
    let outside_scene =
        trained_distance(&samples[..base.n_trained], &q) > FOLLOW_FRACTION * base.reach;
    let wanted = distance > FOLLOW_FRACTION * base.reach
        || (request.settle && outside_scene && distance > SETTLE_FRACTION * base.reach);
    let n_followed = samples.len() - base.n_trained;
    let stay = |reason| {
        Response::json(&FollowAnswer {
            followed: false,
            reason,
            distance,
            reach: base.reach,
        })
    };
    if !wanted {
        return stay("inside");
    }
    if n_followed >= MAX_FOLLOWED_SAMPLES {
        return stay("limit");
    }
    let bad = |e: &dyn std::fmt::Display| ApiError::bad(format!("{name}: follow: {e}"));
    let clock = editor.progress.clock();
    let t0 = clock();
    let mut training = rig.training.clone();
    extend(&base.mesh, &base.options, &mut training, &[q], &|_| {}).map_err(|e| bad(&e))?;
    let t1 = clock();
    let joined = base.join.rig(&training.op).map_err(|e| bad(&e))?;
    let t2 = clock();
    let followed = OperatorRig {
        document: rig.document.clone(),
        rig: joined,
        training,
        base: base.clone(),
    };
    check_operator_size(&name, &followed)?;
    let info = operator_info(&followed, [0.0, t1 - t0, t2 - t1]);
    operator_response(editor, followed, info)
}
