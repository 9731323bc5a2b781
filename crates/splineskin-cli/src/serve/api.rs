//! The HTTP routes of the editor.
//!
//! | route | request | response |
//! |---|---|---|
//! | `GET /`, `GET /{*path}` | | the page and its assets ([`super::assets`]) |
//! | `GET /api/initial` | | the drawing given on the command line, [`DocumentInfo`] |
//! | `POST /api/open` | the file's bytes (SVG or scene), `x-file-name` header | [`DocumentInfo`] |
//! | `POST /api/rig` | [`SceneRequest`] | the operator `O`, `f64` LE row-major `(2 · n_points) × (6 · n_handles)`; header `x-splineskin-rig`: the rig's id |
//! | `POST /api/rigs/{id}/solve` | [`PoseRequest`] | deformed points, `f64` LE `x0, y0, x1, y1, …` (flexible G¹ when the scene asks, warm-started from the previous solve) |
//! | `POST /api/defop` | [`SceneRequest`] with family `defop-arap` or `defop-sarap` (`weights.samples`: training samples) | `G_spline` `f64` LE row-major `(2 · n_points) × |Ψ|`, then the thin-plate centres `f64` LE row-major `n_centres × 2 · n_handles` (scaled displacements `z_k`); header `x-splineskin-defop`: [`DefOpInfo`](super::defop_routes::DefOpInfo) JSON (id, handle basis kind, scale, rest handles `P`, sizes, seconds). Per frame `points = G_spline · ψ(Q)`, `ψ = (1, z, φ(‖z − z_k‖)…)`, `z = (Q − P)/scale`, `φ(r) = r² log r` (`splineskin::defop::HandleBasis`) |
//! | `POST /api/defops/{id}/deform` | [`DeformRequest`](super::defop_routes::DeformRequest) `{"handles": [[x, y], …]}` (the configuration `Q`) | the library's deformation at `Q`, `f64` LE `x0, y0, x1, y1, …` (the page's product is checked against it) |
//! | `GET /api/progress/{job}` | | the stage of the precomputation whose request carried `x-splineskin-job: {job}`: `{"stage": "queued" \| "weights" \| "rig" \| "domain" \| "training" \| "join", "seconds": …}` (seconds in that stage), with `"done", "total", "step", "steps"` while training (ground-truth solves done of all, bootstrapping stage of all), or `{"stage": null}` when none runs |
//! | `GET /api/rigs/{id}/weights?handle&x0&y0&x1&y1&width&height` | | handle's weight at the centres of a `width × height` grid over the box, `f32` LE, row by row from `y0` |
//! | `POST /api/documents/{id}/export?viewbox=keep\|fit[&rig={id}\|&defop={id}]` | deformed points, `f64` LE, then with `rig` the pose (`a…f` per handle) or with `defop` the configuration `Q` (`x, y` per handle), `f64` LE ([`ExportQuery`](super::wire::ExportQuery)) | the SVG document with them ([`write_svg_following`](splineskin::drawing::svg_out::write_svg_following)): gradients, patterns, markers, text and images carried by the best-fit affine map of the rig's skinning map or the operator's deformation (at rest without either); `fit` grows the viewBox to include the art, `keep` (default) leaves it |
//! | `POST /api/documents/{id}/outside` | deformed points, `f64` LE | [`ViewBoxReport`](super::wire::ViewBoxReport): the paths that leave the viewBox, how far, and the viewBox `fit` writes |
//! | `POST /api/documents/{id}/scene` | [`EditScene`] | the scene file (ours, drawing inline) |
//!
//! Errors are JSON [`ErrorBody`] `{"error": "…"}` naming the file and element concerned, with
//! status 400 (bad input), 404 (no such document or rig: dropped, [`super::store`]), 413 (too
//! large) or 500 (a bug). Every `POST` must carry the header `x-splineskin: 1`, which a page of
//! another site cannot send without a CORS preflight this server never grants; on loopback,
//! requests whose `Host` is not the server's own are refused (DNS rebinding).
//!
//! Precomputation, solves, weight grids and exports run on blocking threads, at most
//! [`MAX_JOBS`] at a time; a page that closes mid-request leaves the server as it was.

use std::sync::{Arc, Mutex};

use axum::body::Body;
use axum::extract::rejection::{BytesRejection, JsonRejection};
use axum::extract::{DefaultBodyLimit, Request, State};
use axum::http::{header, HeaderValue, Method, StatusCode};
use axum::middleware::{self, Next};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::{Json, Router};
use tokio::sync::Semaphore;

use super::defop_routes::{defop, deform};
use super::document::{Document, MAX_UPLOAD_BYTES};
use super::document_routes::{export, initial, open, outside, save_scene};
use super::progress::ProgressBoard;
use super::rig_routes::{progress, rig, solve, weights};
use super::store::Store;
use super::wire::ErrorBody;

/// Heavy jobs (precomputation, solves, weight grids, exports) run at once: 2, the cores of the
/// machines this is made for; more wait their turn.
pub const MAX_JOBS: usize = 2;

/// Largest JSON request: 16 MiB (a scene of the page holds handles, a pose and junction
/// overrides, never the drawing).
pub const MAX_JSON_BYTES: usize = 16 << 20;

/// Most point handles a rig takes: 512.
pub const MAX_HANDLES: usize = 512;

/// Largest operator sent to the page: 512 MiB (`8 · 2 · n_points · 6 · n_handles` bytes), what
/// a browser tab holds comfortably.
pub const MAX_OPERATOR_BYTES: usize = 512 << 20;

/// Largest side of a weight grid, in samples: 1024.
pub const MAX_GRID_SIDE: u32 = 1024;

/// The header every `POST` carries.
pub const API_HEADER: &str = "x-splineskin";

/// The header naming a rig in [`rig`]'s response (the rig's id).
pub const RIG_HEADER: &str = "x-splineskin-rig";

/// The server's state.
pub struct App {
    /// Documents and rigs.
    pub store: Mutex<Store>,
    /// Slots for heavy jobs (a job holds its slot until it ends, even when its request is
    /// gone).
    pub jobs: Arc<Semaphore>,
    /// The `Host` values accepted (empty: any, when serving beyond loopback on request).
    pub hosts: Vec<String>,
    /// The stages of the precomputations pages follow.
    pub progress: Arc<ProgressBoard>,
}

impl App {
    /// A server state holding `initial` as the drawing shown first; `hosts` as in
    /// [`App::hosts`].
    pub fn new(initial: Document, hosts: Vec<String>) -> Arc<App> {
        let mut store = Store::default();
        store.set_initial(initial);
        Arc::new(App {
            store: Mutex::new(store),
            jobs: Arc::new(Semaphore::new(MAX_JOBS)),
            hosts,
            progress: Arc::default(),
        })
    }

    pub(super) fn store(&self) -> std::sync::MutexGuard<'_, Store> {
        // The store's methods do not panic midway; a poisoned lock holds consistent data.
        self.store.lock().unwrap_or_else(|e| e.into_inner())
    }

    pub(super) fn document(&self, id: &str) -> Result<Arc<Document>, ApiError> {
        self.store().document(id).ok_or_else(|| {
            ApiError::new(
                StatusCode::NOT_FOUND,
                format!("document {id} is no longer open on the server: open the drawing again"),
            )
        })
    }
}

/// The router of the editor on state `app`.
pub fn router(app: Arc<App>) -> Router {
    let json_limit = DefaultBodyLimit::max(MAX_JSON_BYTES);
    Router::new()
        .route("/api/initial", get(initial))
        .route(
            "/api/open",
            post(open).layer(DefaultBodyLimit::max(MAX_UPLOAD_BYTES)),
        )
        .route("/api/rig", post(rig).layer(json_limit))
        .route("/api/rigs/{id}/solve", post(solve).layer(json_limit))
        .route("/api/defop", post(defop).layer(json_limit))
        .route("/api/defops/{id}/deform", post(deform).layer(json_limit))
        .route("/api/rigs/{id}/weights", get(weights))
        .route("/api/progress/{job}", get(progress))
        .route(
            "/api/documents/{id}/export",
            post(export).layer(DefaultBodyLimit::max(MAX_UPLOAD_BYTES)),
        )
        .route(
            "/api/documents/{id}/outside",
            post(outside).layer(DefaultBodyLimit::max(MAX_UPLOAD_BYTES)),
        )
        .route(
            "/api/documents/{id}/scene",
            post(save_scene).layer(json_limit),
        )
        .route("/api/{*rest}", get(no_route).post(no_route))
        .route("/", get(super::assets::index))
        .route("/{*path}", get(super::assets::asset))
        .layer(middleware::from_fn_with_state(app.clone(), guard))
        .with_state(app)
}

/// Refuses foreign `Host`s (on loopback) and `POST`s without [`API_HEADER`].
async fn guard(State(app): State<Arc<App>>, request: Request, next: Next) -> Response {
    if !app.hosts.is_empty() {
        let host = request
            .headers()
            .get(header::HOST)
            .and_then(|h| h.to_str().ok())
            .unwrap_or("");
        if !app.hosts.iter().any(|h| h.eq_ignore_ascii_case(host)) {
            return ApiError::new(
                StatusCode::FORBIDDEN,
                format!(
                    "host '{host}' is not this server (expected one of {})",
                    app.hosts.join(", ")
                ),
            )
            .into_response();
        }
    }
    if request.method() == Method::POST && request.headers().get(API_HEADER).is_none() {
        return ApiError::new(
            StatusCode::FORBIDDEN,
            format!("POST requests need the header '{API_HEADER}: 1' (sent by the editor's page)"),
        )
        .into_response();
    }
    let mut response = next.run(request).await;
    let headers = response.headers_mut();
    headers.insert(
        "x-content-type-options",
        HeaderValue::from_static("nosniff"),
    );
    headers
        .entry(header::CACHE_CONTROL)
        .or_insert(HeaderValue::from_static("no-store"));
    response
}

/// An error response: a status and a message for the page.
#[derive(Debug)]
pub struct ApiError {
    pub(super) status: StatusCode,
    message: String,
}

impl ApiError {
    pub(super) fn new(status: StatusCode, message: impl Into<String>) -> ApiError {
        ApiError {
            status,
            message: message.into(),
        }
    }

    pub(super) fn bad(message: impl Into<String>) -> ApiError {
        ApiError::new(StatusCode::BAD_REQUEST, message)
    }
}

impl From<anyhow::Error> for ApiError {
    fn from(e: anyhow::Error) -> ApiError {
        ApiError::bad(crate::error_message(&e))
    }
}

impl From<JsonRejection> for ApiError {
    fn from(e: JsonRejection) -> ApiError {
        ApiError::new(e.status(), format!("bad request: {}", e.body_text()))
    }
}

impl From<BytesRejection> for ApiError {
    fn from(e: BytesRejection) -> ApiError {
        let message = if e.status() == StatusCode::PAYLOAD_TOO_LARGE {
            format!("the upload is larger than the {MAX_UPLOAD_BYTES}-byte limit")
        } else {
            format!("bad request: {}", e.body_text())
        };
        ApiError::new(e.status(), message)
    }
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        (
            self.status,
            Json(ErrorBody {
                error: self.message,
            }),
        )
            .into_response()
    }
}

/// Runs `job` on a blocking thread once a job slot is free. The job keeps its slot until it
/// ends, also when the request is dropped midway (a page reloaded or closed), so that at most
/// [`MAX_JOBS`] run at once whatever pages do. A panic (a bug) becomes a 500.
pub(super) async fn run_job<T: Send + 'static>(
    app: &App,
    job: impl FnOnce() -> Result<T, ApiError> + Send + 'static,
) -> Result<T, ApiError> {
    let slot =
        app.jobs.clone().acquire_owned().await.map_err(|_| {
            ApiError::new(StatusCode::SERVICE_UNAVAILABLE, "the server is stopping")
        })?;
    let job = move || {
        let result = job();
        drop(slot);
        result
    };
    match tokio::task::spawn_blocking(job).await {
        Ok(result) => result,
        Err(e) => Err(ApiError::new(
            StatusCode::INTERNAL_SERVER_ERROR,
            format!("internal error (a bug in splineskin, please report it): {e}"),
        )),
    }
}

async fn no_route() -> ApiError {
    ApiError::new(StatusCode::NOT_FOUND, "no such API route")
}

/// `values` as little-endian bytes.
pub(super) fn f64_bytes(values: &[f64]) -> Vec<u8> {
    let mut out = Vec::with_capacity(8 * values.len());
    for v in values {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out
}

/// A binary response, with the rig's id header when given.
pub(super) fn binary(bytes: Vec<u8>, rig: Option<&str>) -> Result<Response, ApiError> {
    let mut response = Response::new(Body::from(bytes));
    let headers = response.headers_mut();
    headers.insert(
        header::CONTENT_TYPE,
        HeaderValue::from_static("application/octet-stream"),
    );
    if let Some(id) = rig {
        headers.insert(
            RIG_HEADER,
            HeaderValue::from_str(id).map_err(|e| ApiError::bad(e.to_string()))?,
        );
    }
    Ok(response)
}
