//! The editor over HTTP: every request under `/api/` is handed to the library's
//! [`Editor`](splineskin_editor::Editor) (whose crate documents the routes), the page's files
//! are served from the binary ([`super::assets`]).
//!
//! What HTTP adds: every `POST` must carry the header `x-splineskin: 1`, which a page of
//! another site cannot send without a CORS preflight this server never grants; on loopback,
//! requests whose `Host` is not the server's own are refused (DNS rebinding). Heavy requests
//! (precomputation, solves, weight grids, exports: [`Editor::is_heavy`]) run on blocking
//! threads, at most [`MAX_JOBS`] at a time; a page that closes mid-request leaves the server as
//! it was.

use std::sync::Arc;

use axum::body::{Body, Bytes};
use axum::extract::rejection::BytesRejection;
use axum::extract::{DefaultBodyLimit, Request, State};
use axum::http::{header, HeaderMap, HeaderValue, Method, StatusCode, Uri};
use axum::middleware::{self, Next};
use axum::response::Response;
use axum::routing::{any, get};
use axum::Router;
use splineskin_editor::document::{Document, MAX_UPLOAD_BYTES};
use splineskin_editor::{ApiError, Editor};
use tokio::sync::Semaphore;

/// Heavy jobs (precomputation, solves, weight grids, exports) run at once: 2, the cores of the
/// machines this is made for; more wait their turn.
pub const MAX_JOBS: usize = 2;

/// The header every `POST` carries.
pub const API_HEADER: &str = "x-splineskin";

/// The server's state.
pub struct App {
    /// The editor answering the page's requests.
    pub editor: Editor,
    /// Slots for heavy jobs (a job holds its slot until it ends, even when its request is
    /// gone).
    pub jobs: Arc<Semaphore>,
    /// The `Host` values accepted (empty: any, when serving beyond loopback on request).
    pub hosts: Vec<String>,
}

impl App {
    /// A server state holding `initial` as the drawing shown first; `hosts` as in
    /// [`App::hosts`].
    pub fn new(initial: Document, hosts: Vec<String>) -> Arc<App> {
        Arc::new(App {
            editor: Editor::new(Some(initial)),
            jobs: Arc::new(Semaphore::new(MAX_JOBS)),
            hosts,
        })
    }
}

/// The router of the editor on state `app`.
pub fn router(app: Arc<App>) -> Router {
    Router::new()
        .route(
            "/api/{*rest}",
            any(api).layer(DefaultBodyLimit::max(MAX_UPLOAD_BYTES)),
        )
        .route("/", get(super::assets::index))
        .route("/{*path}", get(super::assets::asset))
        .layer(middleware::from_fn_with_state(app.clone(), guard))
        .with_state(app)
}

/// Any request under `/api/`: answered by the editor, heavy ones on a blocking thread within
/// the job slots.
async fn api(
    State(app): State<Arc<App>>,
    method: Method,
    uri: Uri,
    headers: HeaderMap,
    body: Result<Bytes, BytesRejection>,
) -> Response {
    let body = match body {
        Ok(body) => body,
        Err(e) => {
            let message = if e.status() == StatusCode::PAYLOAD_TOO_LARGE {
                format!("the upload is larger than the {MAX_UPLOAD_BYTES}-byte limit")
            } else {
                format!("bad request: {}", e.body_text())
            };
            return reply(ApiError::new(e.status().as_u16(), message).into_response());
        }
    };
    let request = splineskin_editor::Request {
        method: method.as_str().to_string(),
        path: uri.path().to_string(),
        query: uri.query().unwrap_or("").to_string(),
        headers: headers
            .iter()
            .filter_map(|(k, v)| Some((k.as_str().to_string(), v.to_str().ok()?.to_string())))
            .collect(),
        body: body.into(),
    };
    if !Editor::is_heavy(&request) {
        return reply(app.editor.handle(&request));
    }
    // Followed from now on, queued until a slot is free.
    let followed = app.editor.follow(&request);
    let Ok(slot) = app.jobs.clone().acquire_owned().await else {
        return reply(ApiError::new(503, "the server is stopping").into_response());
    };
    let job_app = app.clone();
    let job = move || {
        let response = job_app.editor.handle_followed(&request, followed.as_ref());
        drop(slot);
        response
    };
    match tokio::task::spawn_blocking(job).await {
        Ok(response) => reply(response),
        Err(e) => reply(
            ApiError::new(
                500,
                format!("internal error (a bug in splineskin, please report it): {e}"),
            )
            .into_response(),
        ),
    }
}

/// The editor's response as an HTTP response.
fn reply(response: splineskin_editor::Response) -> Response {
    let status = StatusCode::from_u16(response.status).unwrap_or(StatusCode::INTERNAL_SERVER_ERROR);
    let mut out = Response::new(Body::from(response.body));
    *out.status_mut() = status;
    let headers = out.headers_mut();
    headers.insert(
        header::CONTENT_TYPE,
        HeaderValue::from_static(response.content_type),
    );
    for (name, value) in response.headers {
        // The editor's header values are ASCII (JSON with `\u` escapes, ids).
        if let Ok(value) = HeaderValue::from_str(&value) {
            headers.insert(name, value);
        }
    }
    out
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
            return reply(
                ApiError::new(
                    403,
                    format!(
                        "host '{host}' is not this server (expected one of {})",
                        app.hosts.join(", ")
                    ),
                )
                .into_response(),
            );
        }
    }
    if request.method() == Method::POST && request.headers().get(API_HEADER).is_none() {
        return reply(
            ApiError::new(
                403,
                format!(
                    "POST requests need the header '{API_HEADER}: 1' (sent by the editor's page)"
                ),
            )
            .into_response(),
        );
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
