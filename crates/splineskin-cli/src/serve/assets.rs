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
    response
}

/// The content type of an asset, by extension.
fn content_type(path: &str) -> &'static str {
    match path.rsplit('.').next().unwrap_or("") {
        "html" => "text/html; charset=utf-8",
        "js" | "mjs" => "text/javascript; charset=utf-8",
        "css" => "text/css; charset=utf-8",
        "svg" => "image/svg+xml",
        "png" => "image/png",
        _ => "application/octet-stream",
    }
}
