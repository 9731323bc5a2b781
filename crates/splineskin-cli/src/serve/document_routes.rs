//! The routes about documents: the initial one, uploads, export and scene files
//! ([`super::api`] has the table of routes).

use std::sync::Arc;

use axum::body::Bytes;
use axum::extract::rejection::{BytesRejection, JsonRejection};
use axum::extract::{Path, State};
use axum::http::{header, HeaderMap, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::Json;
use kurbo::Point;
use splineskin::drawing::svg_out::write_svg;

use super::api::{run_job, ApiError, App};
use super::document::Document;
use super::rig_routes::page_scene;
use super::scene_file::scene_json;
use super::wire::{DocumentInfo, EditScene};

/// `GET /api/initial`.
pub async fn initial(State(app): State<Arc<App>>) -> Result<Json<DocumentInfo>, ApiError> {
    let document = app
        .store()
        .initial()
        .ok_or_else(|| ApiError::new(StatusCode::NOT_FOUND, "no initial document"))?;
    Ok(Json(document.info.clone()))
}

/// `POST /api/open`.
pub async fn open(
    State(app): State<Arc<App>>,
    headers: HeaderMap,
    body: Result<Bytes, BytesRejection>,
) -> Result<Json<DocumentInfo>, ApiError> {
    let body = body?;
    let name = headers
        .get("x-file-name")
        .and_then(|v| v.to_str().ok())
        .map(percent_decode)
        .filter(|n| !n.is_empty())
        .unwrap_or_else(|| "upload".to_string());
    let document = run_job(&app, move || Ok(Document::open(&name, &body)?)).await?;
    let document = app.store().add_document(document);
    Ok(Json(document.info.clone()))
}

/// Decodes `%XX` escapes (the page sends file names with `encodeURIComponent`); anything
/// malformed is kept as it is.
fn percent_decode(s: &str) -> String {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' && i + 2 < bytes.len() {
            if let Some(b) = s
                .get(i + 1..i + 3)
                .and_then(|hex| u8::from_str_radix(hex, 16).ok())
            {
                out.push(b);
                i += 3;
                continue;
            }
        }
        out.push(bytes[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// `POST /api/documents/{id}/export`.
pub async fn export(
    State(app): State<Arc<App>>,
    Path(id): Path<String>,
    body: Result<Bytes, BytesRejection>,
) -> Result<Response, ApiError> {
    let body = body?;
    let document = app.document(&id)?;
    let svg = run_job(&app, move || {
        let n = document.drawing.n_points();
        if body.len() != 16 * n {
            return Err(ApiError::bad(format!(
                "{}: {} bytes of points for a drawing of {n} points (expected {})",
                document.name,
                body.len(),
                16 * n
            )));
        }
        let points: Vec<Point> = body
            .chunks_exact(16)
            .map(|c| {
                let x = f64::from_le_bytes(c[..8].try_into().expect("8 bytes"));
                let y = f64::from_le_bytes(c[8..].try_into().expect("8 bytes"));
                Point::new(x, y)
            })
            .collect();
        write_svg(&document.drawing, &points).map_err(|e| ApiError::bad(e.to_string()))
    })
    .await?;
    Ok((
        [(header::CONTENT_TYPE, "image/svg+xml; charset=utf-8")],
        svg,
    )
        .into_response())
}

/// `POST /api/documents/{id}/scene`.
pub async fn save_scene(
    State(app): State<Arc<App>>,
    Path(id): Path<String>,
    request: Result<Json<EditScene>, JsonRejection>,
) -> Result<Response, ApiError> {
    let Json(scene) = request?;
    let document = app.document(&id)?;
    let json = run_job(&app, move || {
        // Validated as it will be read back.
        page_scene(&document, &scene)?;
        Ok(scene_json(&document.svg_text, &scene, &document.extras))
    })
    .await?;
    Ok(([(header::CONTENT_TYPE, "application/json")], json).into_response())
}
