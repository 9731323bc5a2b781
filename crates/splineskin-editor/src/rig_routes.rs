//! The routes about rigs: precomputation, flexible solves and weight grids (the crate's
//! documentation has the table of routes).

use kurbo::{Affine, Point};
use serde::Deserialize;
use splineskin::adaptive::AdaptiveOptions;
use splineskin::drawing::carry::CarryOperator;
use splineskin::naive::skin_point_derivatives;
use splineskin::scene::{Compat, Puppet, PuppetStage, Scene, SceneError, SetupControl};
use splineskin::weights::WeightsError;

use crate::document::Document;
use crate::editor::{lock_puppet, Editor};
use crate::page_scene::{defop_energy, scene_of_page};
use crate::progress::Followed;
use crate::request::{
    ApiError, Request, Response, MAX_GRID_SIDE, MAX_HANDLES, MAX_OPERATOR_BYTES, MAX_REFINE_POSES,
    RIG_HEADER,
};
use crate::wire::{
    ColumnsRequest, EditScene, PoseRequest, RefineAnswer, RefineRequest, RigRequest,
};
use splineskin::scene::WeightSpec;
use splineskin::weights::coarse_to_fine::preview_options;

/// The page's scene on `document` as a scene of the library, checked as a scene file of ours
/// is ([`scene_of_page`]), refusing rigs larger than [`MAX_HANDLES`] or
/// [`MAX_OPERATOR_BYTES`]; a coarse preview's domain coarsened.
pub(crate) fn checked_scene(document: &Document, scene: &EditScene) -> Result<Scene, ApiError> {
    let n_handles = scene.handles.len();
    if n_handles > MAX_HANDLES {
        return Err(ApiError::bad(format!(
            "{}: {n_handles} handles (at most {MAX_HANDLES})",
            document.name
        )));
    }
    let bytes = 8 * 2 * document.drawing.n_points() * 6 * n_handles;
    if bytes > MAX_OPERATOR_BYTES {
        return Err(ApiError::bad(format!(
            "{}: {n_handles} handles on {} points make a {} MiB operator (at most {} MiB): \
             use fewer handles",
            document.name,
            document.drawing.n_points(),
            bytes >> 20,
            MAX_OPERATOR_BYTES >> 20
        )));
    }
    // The drawing was read when the document was opened: not read again for each rig.
    let mut read = scene_of_page(
        &document.name,
        &document.svg_text,
        document.drawing.clone(),
        scene,
        &document.extras,
    )
    .map_err(|e| ApiError::bad(e.to_string()))?;
    // A request's only: never written.
    if scene.weights.coarse {
        if !matches!(read.weights, WeightSpec::Mesh(_)) {
            return Err(ApiError::bad(format!(
                "{}: weights.coarse: the '{}' weights have no mesh to coarsen (expected \
                 harmonic, biharmonic or bbw)",
                document.name,
                read.weights.name()
            )));
        }
        read.domain = preview_options(&read.domain);
    }
    Ok(read)
}

/// `POST /api/rig` ([`RigRequest`]).
pub(crate) fn rig(
    editor: &Editor,
    request: &Request,
    followed: Option<&Followed>,
) -> Result<Response, ApiError> {
    let request: RigRequest = request.json()?;
    let document = editor.document(&request.document)?;
    if defop_energy(&request.scene.weights.family).is_some() {
        return Err(ApiError::bad(format!(
            "{}: '{}' is a deformation operator, trained by POST /api/defop, not weights",
            document.name, request.scene.weights.family
        )));
    }
    let report = followed.map(|f| f.reporter());
    // A newer request (the page's next click) asks this one to stop: its weights end at the
    // next active-set iteration, and the cores go to the newer one.
    let stop = followed.map(|f| f.stop_signal());
    let scene = checked_scene(&document, &request.scene)?;
    let mut stage = |s: PuppetStage| {
        if let Some(report) = &report {
            report(match s {
                PuppetStage::Weights => "weights",
                _ => "rig",
            });
        }
    };
    let control = SetupControl {
        stop: stop.as_ref(),
        solved: request.solved.as_ref(),
    };
    let puppet = Puppet::from_scene_with(&scene, Compat::None, &mut stage, control)
        .map_err(|e| weights_error(&document.name, e))?;
    let response = Response::f64s(puppet.rig().map(|r| r.operator()).unwrap_or(&[]));
    let id = editor.store().add_rig(&request.document, puppet);
    Ok(response.with_header(RIG_HEADER, id))
}

/// `POST /api/weights/columns` ([`ColumnsRequest`]): some of a rig's bounded biharmonic
/// columns, for `POST /api/rig` to take as given ([`Scene::bbw_columns`]).
pub(crate) fn columns(
    editor: &Editor,
    request: &Request,
    followed: Option<&Followed>,
) -> Result<Response, ApiError> {
    let request: ColumnsRequest = request.json()?;
    let document = editor.document(&request.document)?;
    if request.columns.is_empty() || request.columns.len() > MAX_HANDLES {
        return Err(ApiError::bad(format!(
            "{}: {} columns asked for (expected 1 to {MAX_HANDLES})",
            document.name,
            request.columns.len()
        )));
    }
    if let Some(report) = followed.map(|f| f.reporter()) {
        report("weights");
    }
    let stop = followed.map(|f| f.stop_signal());
    let scene = checked_scene(&document, &request.scene)?;
    let solved = scene
        .bbw_columns(Compat::None, &request.columns, stop.as_ref())
        .map_err(|e| weights_error(&document.name, e))?;
    Response::json(&solved)
}

/// The answer to weights that could not be made: 409 when they were stopped as asked, else a
/// bad request naming what was wrong.
fn weights_error(name: &str, e: SceneError) -> ApiError {
    match &e {
        SceneError::Weights { source, .. }
            if source.downcast_ref::<WeightsError>() == Some(&WeightsError::Stopped) =>
        {
            ApiError::new(409, format!("{name}: weights stopped as asked"))
        }
        _ => ApiError::bad(e.to_string()),
    }
}

/// `POST /api/rigs/{id}/solve`.
pub(crate) fn solve(editor: &Editor, id: &str, request: &Request) -> Result<Response, ApiError> {
    let request: PoseRequest = request.json()?;
    let rig = editor.store().rig(id).ok_or_else(|| gone_rig(id))?;
    let points = (|| {
        let pose: Vec<Affine> = request.pose.iter().map(|&c| Affine::new(c)).collect();
        if let Some(k) = pose
            .iter()
            .position(|t| !t.as_coeffs().iter().all(|v| v.is_finite()))
        {
            return Err(ApiError::bad(format!("pose[{k}]: not finite")));
        }
        let mut puppet = lock_puppet(&rig)?;
        puppet
            .set_pose(&pose)
            .map_err(|e| ApiError::bad(e.to_string()))?;
        let mut points = vec![Point::ZERO; puppet.n_points()];
        puppet
            .update(&mut points)
            .map_err(|e| ApiError::bad(e.to_string()))?;
        let flat: Vec<f64> = points.iter().flat_map(|p| [p.x, p.y]).collect();
        Ok(Response::f64s(&flat))
    })();
    if let Err(e) = &points {
        if e.status == 500 {
            editor.store().remove_rig(id);
        }
    }
    points
}

/// `GET /api/rigs/{id}/operator`: the rig's operator `O`, as `POST /api/rig` answers it.
pub(crate) fn operator(editor: &Editor, id: &str) -> Result<Response, ApiError> {
    let rig = editor.store().rig(id).ok_or_else(|| gone_rig(id))?;
    let puppet = lock_puppet(&rig)?;
    Ok(Response::f64s(
        puppet.rig().map(|r| r.operator()).unwrap_or(&[]),
    ))
}

/// `GET /api/rigs/{id}/carry`: the rig's carry operator
/// ([`splineskin::drawing::carry::CarryOperator`] of its skinning map in the pose), as f64s:
/// per carried `<text>` and `<image>` of its document (in
/// [`crate::wire::DocumentInfo::carried`] order), then per element with its own paint copies
/// or a stroke frame ([`crate::wire::DocumentInfo::painted`]), the six coefficients of its best-fit map as rows
/// of `6h + 1` numbers (the pose's `6h` coefficients, handle by handle, then the constant).
/// Empty when the document has none of either; the page then asks no more.
pub(crate) fn carry(editor: &Editor, id: &str) -> Result<Response, ApiError> {
    let rig = editor.store().rig(id).ok_or_else(|| gone_rig(id))?;
    let document = editor.document(&rig.document)?;
    if document.info.carried.is_empty() && document.info.painted.is_empty() {
        return Ok(Response::f64s(&[]));
    }
    let puppet = lock_puppet(&rig)?;
    let field = puppet
        .weights()
        .ok_or_else(|| ApiError::bad("the rig's weights are not computed"))?;
    let mut w = vec![0.0; field.n_handles()];
    let n_inputs = 6 * field.n_handles();
    let painted = &document.info.painted;
    let carry = CarryOperator::with_elements(&document.drawing, painted, n_inputs, &mut |p, d| {
        skin_point_derivatives(field, p, d, &mut w)
    })
    .map_err(|e| ApiError::bad(format!("{}: {e}", document.name)))?;
    Ok(Response::f64s(carry.coefficients()))
}

/// `POST /api/rigs/{id}/refine` ([`RefineRequest`]): adaptive control points for the poses
/// the page has seen ([`splineskin::scene::Puppet::refined`]). When anchors are inserted, the
/// refined drawing is kept as a new document ([`Document::refined`]) with its rig, which
/// shares the refined rig's weights.
pub(crate) fn refine(editor: &Editor, id: &str, request: &Request) -> Result<Response, ApiError> {
    let request: RefineRequest = request.json()?;
    let rig = editor.store().rig(id).ok_or_else(|| gone_rig(id))?;
    let document = editor.document(&rig.document)?;
    if request.poses.is_empty() || request.poses.len() > MAX_REFINE_POSES {
        return Err(ApiError::bad(format!(
            "{}: {} poses to refine for (expected 1 to {MAX_REFINE_POSES})",
            document.name,
            request.poses.len()
        )));
    }
    let mut poses = Vec::with_capacity(request.poses.len());
    for (k, pose) in request.poses.iter().enumerate() {
        if let Some(i) = pose.iter().position(|c| !c.iter().all(|v| v.is_finite())) {
            return Err(ApiError::bad(format!("poses[{k}][{i}]: not finite")));
        }
        poses.push(pose.iter().map(|&c| Affine::new(c)).collect::<Vec<_>>());
    }
    let options = AdaptiveOptions::default().with_tolerance(request.tolerance);
    let refined = lock_puppet(&rig)?
        .refined(&poses, &options)
        .map_err(|e| ApiError::bad(e.to_string()))?;
    let n_inserted: usize = refined.inserted.iter().flatten().filter(|&&b| b).count();
    let n_curves = refined.puppet.drawing().n_curves();
    if n_inserted == 0 {
        return Response::json(&RefineAnswer {
            refined: false,
            document: None,
            rig: None,
            moved: Vec::new(),
            n_inserted,
            n_curves,
            worst: refined.worst,
            met: refined.met,
        });
    }
    let new_document = document
        .refined(refined.puppet.drawing(), &refined.inserted, &request.scene)
        .map_err(|e| ApiError::bad(format!("{e:#}")))?;
    let (info, rig) = {
        let mut store = editor.store();
        let kept = store.add_document(new_document);
        let rig = store.add_rig(&kept.info.id, refined.puppet);
        (kept.info.clone(), rig)
    };
    Response::json(&RefineAnswer {
        refined: true,
        document: Some(info),
        rig: Some(rig),
        moved: refined
            .inserted
            .iter()
            .map(|flags| (0..flags.len()).filter(|&j| !flags[j]).collect())
            .collect(),
        n_inserted,
        n_curves,
        worst: refined.worst,
        met: refined.met,
    })
}

pub(crate) fn gone_rig(id: &str) -> ApiError {
    ApiError::new(
        404,
        format!("rig {id} is no longer kept (the editor keeps the latest few): precompute again"),
    )
}

/// The query of `GET /api/rigs/{id}/weights`.
#[derive(Deserialize)]
pub struct GridQuery {
    /// The handle whose weight is sampled.
    handle: usize,
    /// The box sampled, `[x0, x1] × [y0, y1]` (root user units).
    x0: f64,
    y0: f64,
    x1: f64,
    y1: f64,
    /// Samples per row and rows.
    width: u32,
    height: u32,
}

/// `GET /api/rigs/{id}/weights`.
pub(crate) fn weights(editor: &Editor, id: &str, request: &Request) -> Result<Response, ApiError> {
    let q: GridQuery = request.query("weights")?;
    let rig = editor.store().rig(id).ok_or_else(|| gone_rig(id))?;
    if !(1..=MAX_GRID_SIDE).contains(&q.width) || !(1..=MAX_GRID_SIDE).contains(&q.height) {
        return Err(ApiError::bad(format!(
            "grid {} × {}: each side must be in 1..={MAX_GRID_SIDE}",
            q.width, q.height
        )));
    }
    if ![q.x0, q.y0, q.x1, q.y1].iter().all(|v| v.is_finite()) {
        return Err(ApiError::bad("grid box: not finite"));
    }
    let puppet = lock_puppet(&rig)?;
    let field = puppet
        .weights()
        .ok_or_else(|| ApiError::bad("the rig's weights are not computed"))?;
    let n = field.n_handles();
    if q.handle >= n {
        return Err(ApiError::bad(format!(
            "handle {}: no such handle (the rig has {n})",
            q.handle
        )));
    }
    let mut w = vec![0.0; n];
    let mut out = Vec::with_capacity(4 * (q.width * q.height) as usize);
    for r in 0..q.height {
        let y = q.y0 + (q.y1 - q.y0) * (r as f64 + 0.5) / q.height as f64;
        for c in 0..q.width {
            let x = q.x0 + (q.x1 - q.x0) * (c as f64 + 0.5) / q.width as f64;
            field.eval(Point::new(x, y), &mut w);
            out.extend_from_slice(&(w[q.handle] as f32).to_le_bytes());
        }
    }
    Ok(Response::ok("application/octet-stream", out))
}

/// `GET /api/progress/{job}`.
pub(crate) fn progress(editor: &Editor, job: &str) -> Result<Response, ApiError> {
    Response::json(&stage_json(editor.progress.stage(job)))
}

/// `POST /api/progress/{job}/stop`: asks the job to stop (a training ends at its next
/// ground-truth solve, bounded biharmonic weights at their next active-set iteration, and its
/// request answers 409). `{"stopping": true}`, or 404 when no such
/// job runs.
pub(crate) fn stop(editor: &Editor, job: &str) -> Result<Response, ApiError> {
    if editor.progress.stop(job) {
        Response::json(&serde_json::json!({"stopping": true}))
    } else {
        Err(ApiError::new(
            404,
            format!("no job {job} is running (it ended, or its request did not name it)"),
        ))
    }
}

/// A job's stage as `GET /api/progress/{job}` answers it.
pub fn stage_json(stage: Option<crate::progress::Stage>) -> serde_json::Value {
    match stage {
        Some((stage, seconds, None)) => serde_json::json!({"stage": stage, "seconds": seconds}),
        Some((stage, seconds, Some(c))) => serde_json::json!({
            "stage": stage, "seconds": seconds,
            "done": c.done, "total": c.total, "step": c.step, "steps": c.steps,
        }),
        None => serde_json::json!({"stage": null}),
    }
}

/// The triangulated domain of a rig's weights, and every handle's weight at its vertices
/// (`GET /api/rigs/{id}/mesh`).
#[derive(Debug, serde::Serialize)]
pub struct MeshWire {
    /// Vertex positions, `x0, y0, x1, y1, …` (root user units).
    pub vertices: Vec<f64>,
    /// Triangles as vertex indices, three per triangle.
    pub triangles: Vec<u32>,
    /// Weights, `n_handles` per vertex: `w[v · n_handles + i]` is handle `i`'s at vertex `v`.
    pub weights: Vec<f32>,
    /// Number of handles.
    pub n_handles: usize,
    /// What the domain covers, in words (e.g. `the art (2 parts)`: [`splineskin::domain::Boundary`]).
    pub boundary: String,
}

/// `GET /api/rigs/{id}/mesh`: the domain the rig's weights were solved on (mesh families), or
/// a 400 saying the family needs none.
pub(crate) fn mesh(editor: &Editor, id: &str) -> Result<Response, ApiError> {
    let rig = editor.store().rig(id).ok_or_else(|| gone_rig(id))?;
    let wire = {
        let puppet = lock_puppet(&rig)?;
        let domain = puppet.domain().ok_or_else(|| {
            ApiError::bad(
                "this rig's weights have no mesh (inverse-distance weights are closed-form; \
                 the smooth, peaked and unbounded families are solved on one)",
            )
        })?;
        let field = puppet
            .weights()
            .ok_or_else(|| ApiError::bad("the rig's weights are not computed"))?;
        let n = field.n_handles();
        let mesh = &domain.mesh;
        let mut w = vec![0.0; n];
        let mut weights = Vec::with_capacity(n * mesh.vertices.len());
        for &v in &mesh.vertices {
            field.eval(v, &mut w);
            weights.extend(w.iter().map(|&x| x as f32));
        }
        MeshWire {
            vertices: mesh.vertices.iter().flat_map(|p| [p.x, p.y]).collect(),
            triangles: mesh
                .triangles
                .iter()
                .flat_map(|t| t.map(|i| i as u32))
                .collect(),
            weights,
            n_handles: n,
            boundary: domain.boundary.to_string(),
        }
    };
    Response::json(&wire)
}
