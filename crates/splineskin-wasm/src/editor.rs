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
use splineskin::defop::StopSignal;
use splineskin_editor::document::Document;
use splineskin_editor::{Editor, Request};

use crate::INPUT;

thread_local! {
    static EDITOR: RefCell<Option<Editor>> = const { RefCell::new(None) };
    static RESPONSE: RefCell<Vec<u8>> = const { RefCell::new(Vec::new()) };
    /// The stop signal of every job this thread's editor follows ([`splineskin_stop_flag`]).
    static STOP: StopSignal = StopSignal::new();
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

/// The address of the stop flag every followed job of this module's editor checks (one byte,
/// an `AtomicBool`): a host whose memory is shared with the module (the threaded build) stops
/// the request being answered by storing 1 there, which the module cannot be told otherwise
/// while it computes; bounded biharmonic weights stop at their next active-set iteration and
/// the request answers 409. Once raised it stays raised: the host then drops this instance.
#[allow(unsafe_code)]
#[no_mangle]
pub extern "C" fn splineskin_stop_flag() -> usize {
    EDITOR.with_borrow_mut(|editor| {
        editor.get_or_insert_with(new_editor);
    });
    STOP.with(|stop| stop.address())
}

fn new_editor() -> Editor {
    let editor = Editor::with_clock(Document::bundled().ok(), host::clock);
    editor.progress.share_stop(STOP.with(|stop| stop.clone()));
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The fish's document and a bounded biharmonic rig request on it with three pins.
    fn rig_request() -> Request {
        let initial = handle(&Request::get("/api/initial"));
        let info: serde_json::Value = serde_json::from_slice(&initial.body).expect("json");
        let body = serde_json::json!({
            "document": info["id"],
            "scene": {
                "handles": [[440, 215], [150, 210], [300, 250]],
                "pose": [[1, 0, 0, 1, 0, 0], [1, 0, 0, 1, 0, 0], [1, 0, 0, 1, 0, 0]],
                "weights": {"family": "bbw"},
                "junctions": [],
                "flexible": false
            }
        });
        Request::post("/api/rig", body.to_string()).with_header("x-splineskin", "1")
    }

    #[test]
    fn the_stop_flag_stops_followed_rigs_and_only_when_raised() {
        let flag = splineskin_stop_flag();
        assert_eq!(flag, STOP.with(|s| s.address()), "the shared signal's flag");
        let followed = |job: &str| rig_request().with_header("x-splineskin-job", job);
        assert_eq!(
            handle(&followed("rig-1")).status,
            200,
            "not raised: answered"
        );
        STOP.with(|s| s.raise());
        let stopped = handle(&followed("rig-2"));
        assert_eq!(
            stopped.status,
            409,
            "{}",
            String::from_utf8_lossy(&stopped.body)
        );
        // A request no job names is not followed, so not stopped.
        assert_eq!(handle(&rig_request()).status, 200);
    }
}
