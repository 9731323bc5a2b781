//! The routes about documents: the initial one, uploads, export and scene files
//! ([`super::api`] has the table of routes).

use std::sync::Arc;

use axum::body::Bytes;
use axum::extract::rejection::{BytesRejection, JsonRejection};
use axum::extract::{Path, Query, State};
use axum::http::{header, HeaderMap, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::Json;
use kurbo::Point;
use splineskin::drawing::svg_out::{
    art_bounds, art_outside_view_box, write_svg_view_box, ViewBoxRule,
};

use super::api::{run_job, ApiError, App};
use super::document::Document;
use super::rig_routes::page_scene;
use super::scene_file::scene_json;
use super::wire::{DocumentInfo, EditScene, OutsideWire, ViewBoxReport};

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

/// The query of `POST /api/documents/{id}/export`: `?viewbox=keep|fit` (default `keep`).
#[derive(Debug, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExportQuery {
    /// What the export does with the root viewBox when the deformed art leaves it.
    viewbox: Option<String>,
}

/// `POST /api/documents/{id}/export`.
pub async fn export(
    State(app): State<Arc<App>>,
    Path(id): Path<String>,
    query: Result<Query<ExportQuery>, axum::extract::rejection::QueryRejection>,
    body: Result<Bytes, BytesRejection>,
) -> Result<Response, ApiError> {
    let Query(query) = query.map_err(|e| ApiError::bad(format!("export: {e}")))?;
    let rule = match query.viewbox.as_deref() {
        None | Some("keep") => ViewBoxRule::Keep,
        Some("fit") => ViewBoxRule::Fit,
        Some(other) => {
            return Err(ApiError::bad(format!(
                "export: viewbox={other} (expected keep or fit)"
            )))
        }
    };
    let body = body?;
    let document = app.document(&id)?;
    let svg = run_job(&app, move || {
        let points = points_of(&document, &body)?;
        write_svg_view_box(&document.drawing, &points, rule)
            .map_err(|e| ApiError::bad(e.to_string()))
    })
    .await?;
    Ok((
        [(header::CONTENT_TYPE, "image/svg+xml; charset=utf-8")],
        svg,
    )
        .into_response())
}

/// `POST /api/documents/{id}/outside`: which paths of the drawing through the posted points
/// leave the document's viewBox, and the viewBox a `fit` export would write.
pub async fn outside(
    State(app): State<Arc<App>>,
    Path(id): Path<String>,
    body: Result<Bytes, BytesRejection>,
) -> Result<Json<ViewBoxReport>, ApiError> {
    let body = body?;
    let document = app.document(&id)?;
    let report = run_job(&app, move || {
        let points = points_of(&document, &body)?;
        let bad = |e: splineskin::drawing::SvgError| ApiError::bad(e.to_string());
        let mut outside = art_outside_view_box(&document.drawing, &points).map_err(bad)?;
        outside.sort_by(|a, b| b.distance.total_cmp(&a.distance));
        let view_box = document.info.view_box;
        let input = document.drawing.source.as_ref().map_or_else(
            || {
                let [x, y, w, h] = view_box;
                kurbo::Rect::new(x, y, x + w, y + h)
            },
            |s| s.view_box(),
        );
        let fitted = match art_bounds(&document.drawing, &points).map_err(bad)? {
            Some(art) if !outside.is_empty() => input.union(art),
            _ => input,
        };
        Ok(ViewBoxReport {
            view_box,
            fitted: [fitted.x0, fitted.y0, fitted.width(), fitted.height()],
            outside: outside
                .into_iter()
                .map(|o| OutsideWire {
                    path: o.path_index,
                    element: o.element,
                    distance: o.distance,
                })
                .collect(),
        })
    })
    .await?;
    Ok(Json(report))
}

/// The deformed points of a request body (`f64` LE `x0, y0, x1, y1, …`), as many as the
/// document's drawing has.
fn points_of(document: &Document, body: &[u8]) -> Result<Vec<Point>, ApiError> {
    let n = document.drawing.n_points();
    if body.len() != 16 * n {
        return Err(ApiError::bad(format!(
            "{}: {} bytes of points for a drawing of {n} points (expected {})",
            document.name,
            body.len(),
            16 * n
        )));
    }
    Ok(body
        .chunks_exact(16)
        .map(|c| {
            let x = f64::from_le_bytes(c[..8].try_into().expect("8 bytes"));
            let y = f64::from_le_bytes(c[8..].try_into().expect("8 bytes"));
            Point::new(x, y)
        })
        .collect())
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
