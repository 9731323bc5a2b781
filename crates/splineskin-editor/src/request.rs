//! What the editor exchanges with a page: a [`Request`], its [`Response`], the error type
//! ([`ApiError`]: JSON `{"error": …}` with a status) and the limits the routes enforce. The
//! routes and the editor's dispatch ([`crate::routes`]) import this module; it imports none of
//! them.

use serde::de::DeserializeOwned;

use crate::document::MAX_UPLOAD_BYTES;
use crate::wire::ErrorBody;

/// Largest JSON request: 16 MiB (a scene of the page holds handles, a pose and junction
/// overrides, never the drawing).
pub const MAX_JSON_BYTES: usize = 16 << 20;

/// Most point handles a rig takes: 512.
pub const MAX_HANDLES: usize = 512;

/// Most poses one refinement request measures: 64 (the page sends the latest poses seen
/// while dragging and the keyframes').
pub const MAX_REFINE_POSES: usize = 64;

/// Largest operator sent to the page: 512 MiB (`8 · 2 · n_points · 6 · n_handles` bytes), what
/// a browser tab holds comfortably.
pub const MAX_OPERATOR_BYTES: usize = 512 << 20;

/// Largest side of a weight grid, in samples: 1024.
pub const MAX_GRID_SIDE: u32 = 1024;

/// The header naming a rig in the response of `POST /api/rig` (the rig's id).
pub const RIG_HEADER: &str = "x-splineskin-rig";

/// A request of the page: `GET` or `POST`, a path under `/api/`, its query string, the headers
/// the routes read ([`JOB_HEADER`](crate::progress::JOB_HEADER), `x-file-name`) and the body.
///
/// ```
/// use splineskin_editor::{Editor, Request};
/// let editor = Editor::new(None);
/// let response = editor.handle(&Request::get("/api/progress/job-1"));
/// assert_eq!(response.status, 200);
/// assert_eq!(response.body, br#"{"stage":null}"#);
/// ```
#[derive(Clone, Debug, Default)]
pub struct Request {
    /// `GET` or `POST`.
    pub method: String,
    /// The path, `/api/…`, without the query.
    pub path: String,
    /// The query string, without `?` (empty when none).
    pub query: String,
    /// Headers, names in lower case.
    pub headers: Vec<(String, String)>,
    /// The body.
    pub body: Vec<u8>,
}

impl Request {
    /// `GET target` (`target`: a path, with a query after `?` if any).
    pub fn get(target: &str) -> Request {
        Request::new("GET", target, Vec::new())
    }

    /// `POST target` with `body`.
    pub fn post(target: &str, body: impl Into<Vec<u8>>) -> Request {
        Request::new("POST", target, body.into())
    }

    fn new(method: &str, target: &str, body: Vec<u8>) -> Request {
        let (path, query) = target.split_once('?').unwrap_or((target, ""));
        Request {
            method: method.to_string(),
            path: path.to_string(),
            query: query.to_string(),
            headers: Vec::new(),
            body,
        }
    }

    /// The request with header `name: value` added (`name` in lower case).
    pub fn with_header(mut self, name: &str, value: &str) -> Request {
        self.headers
            .push((name.to_ascii_lowercase(), value.to_string()));
        self
    }

    /// The value of header `name` (lower case), if sent.
    pub fn header(&self, name: &str) -> Option<&str> {
        self.headers
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_str())
    }

    /// The body read as JSON of type `T`, a bad field named by its path (`handles[1]: …`).
    pub(crate) fn json<T: DeserializeOwned>(&self) -> Result<T, ApiError> {
        if self.body.len() > MAX_JSON_BYTES {
            return Err(too_large(self.body.len(), MAX_JSON_BYTES));
        }
        let deserializer = &mut serde_json::Deserializer::from_slice(&self.body);
        serde_path_to_error::deserialize(deserializer).map_err(|e| {
            let status = if e.inner().is_data() { 422 } else { 400 };
            let at = e.path().to_string();
            let inner = e.into_inner();
            let message = if at == "." {
                format!("bad request: {inner}")
            } else {
                format!("bad request: {at}: {inner}")
            };
            ApiError::new(status, message)
        })
    }

    /// The query read as type `T`.
    pub(crate) fn query<T: DeserializeOwned>(&self, route: &str) -> Result<T, ApiError> {
        serde_urlencoded::from_str(&self.query).map_err(|e| ApiError::bad(format!("{route}: {e}")))
    }

    /// The body, refused past [`MAX_UPLOAD_BYTES`].
    pub(crate) fn upload(&self) -> Result<&[u8], ApiError> {
        if self.body.len() > MAX_UPLOAD_BYTES {
            return Err(too_large(self.body.len(), MAX_UPLOAD_BYTES));
        }
        Ok(&self.body)
    }
}

fn too_large(bytes: usize, limit: usize) -> ApiError {
    ApiError::new(
        413,
        format!("the upload is larger than the {limit}-byte limit ({bytes} bytes)"),
    )
}

/// The answer to a [`Request`]: a status, the headers the page reads and the body.
#[derive(Clone, Debug, PartialEq)]
pub struct Response {
    /// The HTTP status.
    pub status: u16,
    /// The body's media type.
    pub content_type: &'static str,
    /// Headers besides the content type (names in lower case).
    pub headers: Vec<(&'static str, String)>,
    /// The body.
    pub body: Vec<u8>,
}

impl Response {
    /// A `200` with `body` of type `content_type`.
    pub fn ok(content_type: &'static str, body: impl Into<Vec<u8>>) -> Response {
        Response {
            status: 200,
            content_type,
            headers: Vec::new(),
            body: body.into(),
        }
    }

    /// A `200` with `value` as JSON.
    pub fn json(value: &impl serde::Serialize) -> Result<Response, ApiError> {
        let body = serde_json::to_vec(value).map_err(|e| ApiError::new(500, e.to_string()))?;
        Ok(Response::ok("application/json", body))
    }

    /// A `200` with `values` as little-endian `f64`s.
    pub fn f64s(values: &[f64]) -> Response {
        Response::ok("application/octet-stream", f64_bytes(values))
    }

    /// The response with header `name: value` added.
    pub fn with_header(mut self, name: &'static str, value: String) -> Response {
        self.headers.push((name, value));
        self
    }

    /// The value of header `name`, if set.
    pub fn header(&self, name: &str) -> Option<&str> {
        self.headers
            .iter()
            .find(|(k, _)| *k == name)
            .map(|(_, v)| v.as_str())
    }
}

/// An error response: a status and a message for the page.
#[derive(Debug)]
pub struct ApiError {
    /// The HTTP status: 400 (bad input), 404 (no such document or rig), 409 (stopped as
    /// asked), 413 (too large), 422 (a request of the wrong shape) or 500 (a bug).
    pub status: u16,
    message: String,
}

impl ApiError {
    /// An error of status `status`.
    pub fn new(status: u16, message: impl Into<String>) -> ApiError {
        ApiError {
            status,
            message: message.into(),
        }
    }

    /// A 400.
    pub fn bad(message: impl Into<String>) -> ApiError {
        ApiError::new(400, message)
    }

    /// The message.
    pub fn message(&self) -> &str {
        &self.message
    }

    /// The error as a response: JSON [`ErrorBody`].
    pub fn into_response(self) -> Response {
        let body = serde_json::to_vec(&ErrorBody {
            error: self.message,
        })
        .unwrap_or_else(|_| br#"{"error":"internal error"}"#.to_vec());
        Response {
            status: self.status,
            content_type: "application/json",
            headers: Vec::new(),
            body,
        }
    }
}

impl From<anyhow::Error> for ApiError {
    fn from(e: anyhow::Error) -> ApiError {
        ApiError::bad(error_message(&e))
    }
}

/// An error and its causes in one line, each cause added unless the text so far says it
/// already.
pub fn error_message(e: &anyhow::Error) -> String {
    splineskin::errors::message_with_causes(e.as_ref())
}

/// `values` as little-endian bytes.
pub(crate) fn f64_bytes(values: &[f64]) -> Vec<u8> {
    let mut out = Vec::with_capacity(8 * values.len());
    for v in values {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out
}
