//! The page's files (`crates/splineskin-cli/web/`: HTML, CSS, plain ES modules, no build
//! step), embedded in the binary by rust-embed (in debug builds too: `debug-embed`), served
//! with their content type and a content security policy that lets the page run its own
//! scripts only (an opened drawing's scripts and event attributes never run).

use axum::extract::Path;
use axum::http::{header, HeaderValue, StatusCode};
use axum::response::{IntoResponse, Response};

#[derive(rust_embed::Embed)]
#[folder = "web/"]
struct Web;

/// The page's content security policy: scripts and connections to this server only; inline
/// styles allowed (drawings carry them); images from this server, `data:` and `blob:` (weight
/// fields are drawn into canvases and shown as images).
const CONTENT_SECURITY_POLICY: &str = "default-src 'self'; script-src 'self'; \
     style-src 'self' 'unsafe-inline'; img-src 'self' data: blob:; connect-src 'self'; \
     object-src 'none'; base-uri 'none'; frame-ancestors 'none'";

/// `GET /`: the page.
pub async fn index() -> Response {
    serve("index.html")
}

/// `GET /{*path}`: an embedded file, or 404.
pub async fn asset(Path(path): Path<String>) -> Response {
    serve(&path)
}

fn serve(path: &str) -> Response {
    let Some(file) = Web::get(path) else {
        return (StatusCode::NOT_FOUND, format!("{path}: no such file")).into_response();
    };
    let mut response = file.data.into_owned().into_response();
    let headers = response.headers_mut();
    headers.insert(
        header::CONTENT_TYPE,
        HeaderValue::from_static(content_type(path)),
    );
    headers.insert(
        header::CONTENT_SECURITY_POLICY,
        HeaderValue::from_static(CONTENT_SECURITY_POLICY),
    );
    for (name, value) in ISOLATION_HEADERS {
        headers.insert(name, HeaderValue::from_static(value));
    }
    response
}

/// The content security policy of a static build (in its `index.html`, as a `<meta>`: a static
/// host sends no header of ours): [`CONTENT_SECURITY_POLICY`]'s, with WebAssembly compiled
/// from the page's own module and the page's own worker allowed.
const STATIC_CONTENT_SECURITY_POLICY: &str = "default-src 'self'; \
     script-src 'self' 'wasm-unsafe-eval'; worker-src 'self'; \
     style-src 'self' 'unsafe-inline'; img-src 'self' data: blob:; connect-src 'self'; \
     object-src 'none'; base-uri 'none'";

/// The name of the WebAssembly module in a static build (`editor-worker.js` loads it).
pub const STATIC_WASM_NAME: &str = "splineskin.wasm";

/// The name of the threaded module in a static build (`backend.js` loads it on a
/// cross-origin-isolated page).
pub const STATIC_WASM_THREADS_NAME: &str = "splineskin-threads.wasm";

/// The headers that make a page cross-origin isolated, so that it has shared memory and the
/// threaded module can run: sent by `splineskin serve`, and asked of a static host by a static
/// build's `_headers` file (the format of Netlify and Cloudflare Pages; docs/webassembly.md says
/// how for other hosts).
pub const ISOLATION_HEADERS: [(&str, &str); 2] = [
    ("cross-origin-opener-policy", "same-origin"),
    ("cross-origin-embedder-policy", "require-corp"),
];

/// The `package.json` of a static build: its scripts are ES modules wherever the folder sits.
pub const STATIC_PACKAGE_JSON: &str = "{\n  \"private\": true,\n  \"type\": \"module\"\n}\n";

/// The pages of a static build (the editor and the Catmull–Clark page): each is marked to
/// answer its requests in a worker and carries the content security policy.
const STATIC_PAGES: [&str; 2] = ["index.html", "subdiv/index.html"];

/// The files of a static build of the editor: the page's files, its pages ([`STATIC_PAGES`])
/// marked to answer their requests in a worker (`data-backend="wasm"`, web/backend.js) and
/// carrying the content security policy, the WebAssembly module `wasm` as [`STATIC_WASM_NAME`], and the
/// bundled fish as `demo.svg` (for `example.html`, the JavaScript API's example), a
/// `package.json` saying its scripts are ES modules ([`STATIC_PACKAGE_JSON`]); with
/// `threaded`, the threaded module as [`STATIC_WASM_THREADS_NAME`]; and a `_headers` file asking
/// the host for [`ISOLATION_HEADERS`]. The Catmull–Clark page's routes (limit surfaces, rigs,
/// exports) are answered by the same module.
pub fn static_files(wasm: Vec<u8>, threaded: Option<Vec<u8>>) -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<(String, Vec<u8>)> = Web::iter()
        .filter_map(|name| Some((name.to_string(), Web::get(&name)?.data.into_owned())))
        .collect();
    for (name, bytes) in &mut files {
        if STATIC_PAGES.contains(&name.as_str()) {
            let html = String::from_utf8_lossy(bytes)
                .replacen(
                    "<html lang=\"en\">",
                    "<html lang=\"en\" data-backend=\"wasm\">",
                    1,
                )
                .replacen(
                    "<meta charset=\"utf-8\">",
                    &format!(
                        "<meta charset=\"utf-8\">\n  <meta http-equiv=\"Content-Security-Policy\" \
                         content=\"{STATIC_CONTENT_SECURITY_POLICY}\">"
                    ),
                    1,
                );
            *bytes = html.into_bytes();
        }
    }
    files.push((STATIC_WASM_NAME.to_string(), wasm));
    if let Some(threaded) = threaded {
        files.push((STATIC_WASM_THREADS_NAME.to_string(), threaded));
    }
    let mut headers = String::from("/*\n");
    for (name, value) in ISOLATION_HEADERS {
        headers.push_str(&format!("  {name}: {value}\n"));
    }
    files.push(("_headers".to_string(), headers.into_bytes()));
    // Its scripts are ES modules: so says a package.json, for Node, which would otherwise read
    // them as CommonJS inside a project whose own package.json says so (as `npm init` writes).
    files.push((
        "package.json".to_string(),
        STATIC_PACKAGE_JSON.as_bytes().to_vec(),
    ));
    // The bundled fish, which the JavaScript API's example (example.html) opens.
    files.push((
        "demo.svg".to_string(),
        splineskin::examples::DEMO_SVG.as_bytes().to_vec(),
    ));
    files
}

/// The content type of an asset, by extension.
fn content_type(path: &str) -> &'static str {
    match path.rsplit('.').next().unwrap_or("") {
        "html" => "text/html; charset=utf-8",
        "js" | "mjs" => "text/javascript; charset=utf-8",
        "ts" => "text/plain; charset=utf-8",
        "css" => "text/css; charset=utf-8",
        "svg" => "image/svg+xml",
        "png" => "image/png",
        "wasm" => "application/wasm",
        _ => "application/octet-stream",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_static_build_marks_both_pages_for_the_worker_with_the_policy() {
        let files = static_files(vec![0], None);
        for page in STATIC_PAGES {
            let (_, bytes) = files
                .iter()
                .find(|(name, _)| name == page)
                .unwrap_or_else(|| panic!("{page} missing"));
            let html = String::from_utf8_lossy(bytes);
            assert!(html.contains("data-backend=\"wasm\""), "{page}");
            assert!(
                html.contains(STATIC_CONTENT_SECURITY_POLICY),
                "{page}: the policy"
            );
        }
        assert!(files.iter().any(|(name, _)| name == "subdiv/main.js"));
        assert!(files.iter().any(|(name, _)| name == STATIC_WASM_NAME));
    }
}
