//! The editor's request handler (`Editor::handle`, what `splineskin serve` and the WebAssembly
//! editor answer) with arbitrary requests on one editor.
//!
//! Input: requests separated by a line `---`; each is `METHOD TARGET` on its first line, then
//! `name: value` header lines up to an empty line, then the body (so that seeds read as
//! requests and mutations stay near them). In a target or body, `{doc}` is replaced by the
//! last document id an answer gave (its JSON `"id"`), `{rig}` by the last rig id (header
//! `x-splineskin-rig`) and `{defop}` by the last operator id (header `x-splineskin-defop`).
//! Every answer must be 2xx, 4xx or 503, and every 4xx must carry a message.
#![no_main]

use libfuzzer_sys::fuzz_target;
use splineskin_editor::{Editor, Request};

/// Requests per input at most: 8.
const MAX_REQUESTS: usize = 8;

fuzz_target!(|data: &[u8]| {
    let editor = Editor::new(None);
    let mut ids = Ids {
        doc: "d1".into(),
        rig: "r1".into(),
        defop: "o1".into(),
    };
    for part in split(data, b"\n---\n").take(MAX_REQUESTS) {
        let Some(request) = request(part, &ids) else {
            continue;
        };
        let response = editor.handle(&request);
        let status = response.status;
        assert!(
            (200..300).contains(&status) || (400..500).contains(&status) || status == 503,
            "status {status} for {} {}",
            request.method,
            request.path
        );
        if (400..500).contains(&status) {
            assert!(!response.body.is_empty(), "a {status} without a message");
        }
        if let Some(id) = json_id(&response.body) {
            ids.doc = id;
        }
        if let Some(rig) = response.header("x-splineskin-rig") {
            ids.rig = rig.to_string();
        }
        if let Some(id) = response.header("x-splineskin-defop").and_then(|h| json_id(h.as_bytes())) {
            ids.defop = id;
        }
    }
});

/// The ids the next requests may name.
struct Ids {
    doc: String,
    rig: String,
    defop: String,
}

/// The top-level `"id"` of a JSON object, if `bytes` is one.
fn json_id(bytes: &[u8]) -> Option<String> {
    let value = serde_json::from_slice::<serde_json::Value>(bytes).ok()?;
    Some(value.get("id")?.as_str()?.to_string())
}

/// `data` split at every `separator`.
fn split<'a>(data: &'a [u8], separator: &'a [u8]) -> impl Iterator<Item = &'a [u8]> + 'a {
    let mut rest = Some(data);
    std::iter::from_fn(move || {
        let r = rest?;
        match r.windows(separator.len()).position(|w| w == separator) {
            Some(i) => {
                rest = Some(&r[i + separator.len()..]);
                Some(&r[..i])
            }
            None => {
                rest = None;
                Some(r)
            }
        }
    })
}

/// `bytes` with the id placeholders replaced (module doc).
fn with_ids(bytes: &[u8], ids: &Ids) -> Vec<u8> {
    let mut out = bytes.to_vec();
    for (name, id) in [("{doc}", &ids.doc), ("{rig}", &ids.rig), ("{defop}", &ids.defop)] {
        let mut replaced = Vec::with_capacity(out.len());
        let mut rest = &out[..];
        while let Some(i) = rest.windows(name.len()).position(|w| w == name.as_bytes()) {
            replaced.extend_from_slice(&rest[..i]);
            replaced.extend_from_slice(id.as_bytes());
            rest = &rest[i + name.len()..];
        }
        replaced.extend_from_slice(rest);
        out = replaced;
    }
    out
}

/// One request in the input's form (module doc), `None` without a `METHOD TARGET` line.
fn request(part: &[u8], ids: &Ids) -> Option<Request> {
    let part = with_ids(part, ids);
    let (head, body) = match part.windows(2).position(|w| w == b"\n\n") {
        Some(i) => (&part[..i], &part[i + 2..]),
        None => (&part[..], &[][..]),
    };
    let head = String::from_utf8_lossy(head);
    let mut lines = head.lines();
    let (method, target) = lines.next()?.split_once(' ')?;
    let mut request = match method {
        "GET" => Request::get(target),
        _ => Request::post(target, body.to_vec()),
    };
    request.method = method.to_string();
    for line in lines {
        if let Some((name, value)) = line.split_once(':') {
            request = request.with_header(&name.trim().to_ascii_lowercase(), value.trim());
        }
    }
    Some(request)
}
