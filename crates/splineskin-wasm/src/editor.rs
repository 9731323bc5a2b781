//! The editor's requests answered in WebAssembly: the page's Web Worker hands each request to
//! [`splineskin_editor_request`] and gets the response of
//! [`splineskin_editor::Editor::handle`], the very routes `splineskin serve` answers over HTTP.
//!
//! ```text
//! input buffer:  header JSON {"method", "path", "query", "headers": [[name, value], …]} ‖ body
//! k = splineskin_editor_request(header_len, total_len)
//! response buffer (splineskin_response, splineskin_response_len bytes):
//!                header JSON {"status", "content_type", "headers": [[name, value], …]} ‖ body
//!                (the header is its first k bytes)
//! ```
//!
//! The module imports two functions from the host, in the import module `splineskin`:
//! `now() -> f64` (milliseconds of a monotonic clock, `performance.now()`) and
//! `progress(job, job_len, json, json_len)` (addresses and lengths of UTF-8: a followed job's
//! name and its stage as `GET /api/progress/{job}` answers it), called while a precomputation
//! runs so that the page can show its stage.

use std::cell::RefCell;

use serde::{Deserialize, Serialize};
use splineskin_editor::document::Document;
use splineskin_editor::{Editor, Request};

use crate::INPUT;

thread_local! {
    static EDITOR: RefCell<Option<Editor>> = const { RefCell::new(None) };
    static RESPONSE: RefCell<Vec<u8>> = const { RefCell::new(Vec::new()) };
}

/// The head of a request: everything but the body.
#[derive(Deserialize)]
struct RequestHead {
    method: String,
    path: String,
    #[serde(default)]
    query: String,
    #[serde(default)]
    headers: Vec<(String, String)>,
}

/// The head of a response: everything but the body.
#[derive(Serialize)]
struct ResponseHead<'a> {
    status: u16,
    content_type: &'a str,
    headers: &'a [(&'static str, String)],
}

/// Answers the request in the input buffer (its head's JSON in the first `head_len` bytes, its
/// body up to `len`), writing the response to the response buffer; returns the length of the
/// response's head. A request that cannot be read is answered as a 400.
#[allow(unsafe_code)]
#[no_mangle]
pub extern "C" fn splineskin_editor_request(head_len: usize, len: usize) -> usize {
    let request = INPUT.with_borrow(|b| {
        let len = len.min(b.len());
        let head_len = head_len.min(len);
        serde_json::from_slice::<RequestHead>(&b[..head_len]).map(|head| Request {
            method: head.method,
            path: head.path,
            query: head.query,
            headers: head
                .headers
                .into_iter()
                .map(|(k, v)| (k.to_ascii_lowercase(), v))
                .collect(),
            body: b[head_len..len].to_vec(),
        })
    });
    let response = match request {
        Ok(request) => handle(&request),
        Err(e) => {
            splineskin_editor::ApiError::bad(format!("bad request head: {e}")).into_response()
        }
    };
    let head = serde_json::to_vec(&ResponseHead {
        status: response.status,
        content_type: response.content_type,
        headers: &response.headers,
    })
    .unwrap_or_else(|_| br#"{"status":500,"content_type":"","headers":[]}"#.to_vec());
    RESPONSE.with_borrow_mut(|r| {
        r.clear();
        r.extend_from_slice(&head);
        r.extend_from_slice(&response.body);
    });
    head.len()
}

/// The address of the response buffer.
#[allow(unsafe_code)]
#[no_mangle]
pub extern "C" fn splineskin_response() -> usize {
    RESPONSE.with_borrow(|r| r.as_ptr() as usize)
}

/// The length in bytes of the response buffer (head and body).
#[allow(unsafe_code)]
#[no_mangle]
pub extern "C" fn splineskin_response_len() -> usize {
    RESPONSE.with_borrow(|r| r.len())
}

/// Answers `request` with this module's editor, made on the first request with the bundled
/// drawing as its initial one (as `splineskin serve` without a file). Callable natively too.
///
/// ```
/// use splineskin_editor::Request;
/// let response = splineskin_wasm::editor::handle(&Request::get("/api/initial"));
/// assert_eq!(response.status, 200);
/// let info: serde_json::Value = serde_json::from_slice(&response.body).unwrap();
/// assert_eq!(info["name"], "demo-scene.json (bundled)");
/// ```
pub fn handle(request: &Request) -> splineskin_editor::Response {
    EDITOR.with_borrow_mut(|editor| {
        let editor = editor.get_or_insert_with(new_editor);
        editor.handle(request)
    })
}

fn new_editor() -> Editor {
    let editor = Editor::with_clock(Document::bundled().ok(), host::clock);
    editor.progress.set_listener(Box::new(|job, stage| {
        let json = splineskin_editor::rig_routes::stage_json(Some(stage)).to_string();
        host::progress(job, &json);
    }));
    editor
}

/// What the host provides: its clock and a way to tell the page a job's stage.
#[cfg(target_arch = "wasm32")]
mod host {
    #[link(wasm_import_module = "splineskin")]
    extern "C" {
        #[link_name = "now"]
        fn host_now() -> f64;
        #[link_name = "progress"]
        fn host_progress(job: usize, job_len: usize, json: usize, json_len: usize);
    }

    /// Seconds of the host's monotonic clock.
    #[allow(unsafe_code)]
    pub fn clock() -> f64 {
        // SAFETY: an imported function of no arguments returning a number.
        unsafe { host_now() / 1000.0 }
    }

    /// Tells the host job `job`'s stage (`json`).
    #[allow(unsafe_code)]
    pub fn progress(job: &str, json: &str) {
        // SAFETY: the host reads the two UTF-8 strings at these addresses during the call.
        unsafe {
            host_progress(
                job.as_ptr() as usize,
                job.len(),
                json.as_ptr() as usize,
                json.len(),
            )
        }
    }
}

/// Natively (tests, doctests): the system's clock, and no one to tell.
#[cfg(not(target_arch = "wasm32"))]
mod host {
    pub use splineskin_editor::progress::system_clock as clock;

    /// Nothing: natively, pages ask the server.
    pub fn progress(_job: &str, _json: &str) {}
}
