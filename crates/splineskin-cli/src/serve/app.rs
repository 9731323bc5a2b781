//! The editor server's state ([`App`]), its limits, its error type ([`ApiError`]: JSON
//! `{"error": …}` with a status) and what every route shares: running heavy work on a blocking
//! thread within [`MAX_JOBS`] slots ([`run_job`]) and binary `f64` responses ([`binary`]).
//! The routes ([`super::api`]) and their handlers import this module; it imports none of them.

use std::sync::{Arc, Mutex};

use axum::body::Body;
use axum::extract::rejection::{BytesRejection, JsonRejection};
use axum::http::{header, HeaderValue, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::Json;
use splineskin::scene::Puppet;
use tokio::sync::Semaphore;

use super::document::{Document, MAX_UPLOAD_BYTES};
use super::progress::{Followed, ProgressBoard, JOB_HEADER};
use super::store::{Rig, Store};
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
    /// Follows the job the request names in its [`JOB_HEADER`] (if any, and if valid) until
    /// the returned guard is dropped ([`ProgressBoard::follow`]).
    pub(super) fn follow_job(&self, headers: &axum::http::HeaderMap) -> Option<Followed> {
        let name = headers.get(JOB_HEADER)?.to_str().ok()?;
        self.progress.follow(name)
    }

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

/// Locks `rig`'s puppet; a lock poisoned by a failed solve is an internal error.
pub(super) fn lock_puppet(rig: &Rig) -> Result<std::sync::MutexGuard<'_, Puppet>, ApiError> {
    rig.puppet.lock().map_err(|_| {
        ApiError::new(
            StatusCode::INTERNAL_SERVER_ERROR,
            "the rig failed earlier (a bug): build it again",
        )
    })
}
