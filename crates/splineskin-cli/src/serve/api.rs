//! The HTTP routes of the editor.
//!
//! | route | request | response |
//! |---|---|---|
//! | `GET /`, `GET /{*path}` | | the page and its assets ([`super::assets`]) |
//! | `GET /api/initial` | | the drawing given on the command line, [`DocumentInfo`] |
//! | `POST /api/open` | the file's bytes (SVG or scene), `x-file-name` header | [`DocumentInfo`] |
//! | `POST /api/rig` | [`SceneRequest`] | the operator `O`, `f64` LE row-major `(2 · n_points) × (6 · n_handles)`; header `x-splineskin-rig`: the rig's id |
//! | `POST /api/rigs/{id}/solve` | [`PoseRequest`] | deformed points, `f64` LE `x0, y0, x1, y1, …` (flexible G¹ when the scene asks, warm-started from the previous solve) |
//! | `POST /api/defop` | [`SceneRequest`] with family `defop-arap` or `defop-sarap` (`weights.samples`: training samples) | `G_spline` `f64` LE row-major `(2 · n_points) × |Ψ|`, then the thin-plate centres `f64` LE row-major `n_centres × 2 · n_handles` (scaled displacements `z_k`); header `x-splineskin-defop`: [`DefOpInfo`](super::defop_routes::DefOpInfo) JSON (id, handle basis kind, scale, rest handles `P`, sizes, seconds). Per frame `points = G_spline · ψ(Q)`, `ψ = (1, z, φ(‖z − z_k‖)…)`, `z = (Q − P)/scale`, `φ(r) = r² log r` (`splineskin::defop::HandleBasis`) |
//! | `POST /api/defops/{id}/deform` | [`DeformRequest`](super::defop_routes::DeformRequest) `{"handles": [[x, y], …]}` (the configuration `Q`) | the library's deformation at `Q`, `f64` LE `x0, y0, x1, y1, …` (the page's product is checked against it) |
//! | `GET /api/progress/{job}` | | the stage of the precomputation whose request carried `x-splineskin-job: {job}`: `{"stage": "queued" \| "weights" \| "rig" \| "domain" \| "training" \| "join", "seconds": …}` (seconds in that stage), with `"done", "total", "step", "steps"` while training (ground-truth solves done of all, bootstrapping stage of all), or `{"stage": null}` when none runs |
//! | `GET /api/rigs/{id}/weights?handle&x0&y0&x1&y1&width&height` | | handle's weight at the centres of a `width × height` grid over the box, `f32` LE, row by row from `y0` |
//! | `GET /api/rigs/{id}/mesh` | | [`MeshWire`](super::rig_routes::MeshWire): the triangulated domain the weights were solved on and every handle's weight at its vertices (mesh families; 400 for closed-form weights) |
//! | `POST /api/documents/{id}/export?viewbox=keep\|fit[&rig={id}\|&defop={id}]` | deformed points, `f64` LE, then with `rig` the pose (`a…f` per handle) or with `defop` the configuration `Q` (`x, y` per handle), `f64` LE ([`ExportQuery`](super::wire::ExportQuery)) | the SVG document with them ([`write_svg_following`](splineskin::drawing::svg_out::write_svg_following)): gradients, patterns, markers, text and images carried by the best-fit affine map of the rig's skinning map or the operator's deformation (at rest without either); `fit` grows the viewBox to include the art, `keep` (default) leaves it |
//! | `POST /api/documents/{id}/outside` | deformed points, `f64` LE | [`ViewBoxReport`](super::wire::ViewBoxReport): the paths that leave the viewBox, how far, and the viewBox `fit` writes |
//! | `POST /api/documents/{id}/scene` | [`EditScene`] | the scene file (ours, drawing inline) |
//! | `POST /api/documents/{id}/lottie` | [`EditScene`] with an `animation` | the Lottie animation `splineskin animate SCENE -o anim.json` writes of it; header `x-splineskin-lottie`: [`LottieReport`](super::document_routes::LottieReport) JSON (keyframes and bytes written and with every frame, warnings) |
//!
//! Errors are JSON [`ErrorBody`] `{"error": "…"}` naming the file and element concerned, with
//! status 400 (bad input), 404 (no such document or rig: dropped, [`super::store`]), 413 (too
//! large) or 500 (a bug). Every `POST` must carry the header `x-splineskin: 1`, which a page of
//! another site cannot send without a CORS preflight this server never grants; on loopback,
//! requests whose `Host` is not the server's own are refused (DNS rebinding).
//!
//! Precomputation, solves, weight grids and exports run on blocking threads, at most
//! [`MAX_JOBS`] at a time; a page that closes mid-request leaves the server as it was.

use std::sync::Arc;

use axum::extract::{DefaultBodyLimit, Request, State};
use axum::http::{header, HeaderValue, Method, StatusCode};
use axum::middleware::{self, Next};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::Router;

use super::app::{ApiError, App, API_HEADER, MAX_JSON_BYTES};
use super::defop_routes::{defop, deform};
use super::document::MAX_UPLOAD_BYTES;
use super::document_routes::{export, initial, lottie, open, outside, save_scene};
use super::rig_routes::{mesh, progress, rig, solve, weights};

/// The router of the editor on state `app`.
pub fn router(app: Arc<App>) -> Router {
    let json_limit = DefaultBodyLimit::max(MAX_JSON_BYTES);
    Router::new()
        .route("/api/initial", get(initial))
        .route(
            "/api/open",
            post(open).layer(DefaultBodyLimit::max(MAX_UPLOAD_BYTES)),
        )
        .route("/api/rig", post(rig).layer(json_limit))
        .route("/api/rigs/{id}/solve", post(solve).layer(json_limit))
        .route("/api/defop", post(defop).layer(json_limit))
        .route("/api/defops/{id}/deform", post(deform).layer(json_limit))
        .route("/api/rigs/{id}/weights", get(weights))
        .route("/api/rigs/{id}/mesh", get(mesh))
        .route("/api/progress/{job}", get(progress))
        .route(
            "/api/documents/{id}/export",
            post(export).layer(DefaultBodyLimit::max(MAX_UPLOAD_BYTES)),
        )
        .route(
            "/api/documents/{id}/outside",
            post(outside).layer(DefaultBodyLimit::max(MAX_UPLOAD_BYTES)),
        )
        .route(
            "/api/documents/{id}/scene",
            post(save_scene).layer(json_limit),
        )
        .route("/api/documents/{id}/lottie", post(lottie).layer(json_limit))
        .route("/api/{*rest}", get(no_route).post(no_route))
        .route("/", get(super::assets::index))
        .route("/{*path}", get(super::assets::asset))
        .layer(middleware::from_fn_with_state(app.clone(), guard))
        .with_state(app)
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
            return ApiError::new(
                StatusCode::FORBIDDEN,
                format!(
                    "host '{host}' is not this server (expected one of {})",
                    app.hosts.join(", ")
                ),
            )
            .into_response();
        }
    }
    if request.method() == Method::POST && request.headers().get(API_HEADER).is_none() {
        return ApiError::new(
            StatusCode::FORBIDDEN,
            format!("POST requests need the header '{API_HEADER}: 1' (sent by the editor's page)"),
        )
        .into_response();
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

async fn no_route() -> ApiError {
    ApiError::new(StatusCode::NOT_FOUND, "no such API route")
}
