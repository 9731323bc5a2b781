//! The editor's HTTP API, exercised through the router without a socket (tower's `oneshot`).

use axum::body::Body;
use axum::http::{header, Request, StatusCode};
use axum::Router;
use http_body_util::BodyExt;
use kurbo::Point;
use splineskin::animation::Easing;
use splineskin::drawing::{read_svg, ImportOptions};
use splineskin::examples::DEMO_SVG;
use tower::ServiceExt;

use splineskin_editor::defop_routes::DEFOP_HEADER;
use splineskin_editor::document::{Document, MAX_UPLOAD_BYTES};
use splineskin_editor::progress::Count;
use splineskin_editor::request::RIG_HEADER;

use super::http::{router, App, API_HEADER, MAX_JOBS};

const HOST: &str = "127.0.0.1:7464";

fn app() -> Router {
    router(App::new(
        Document::bundled().expect("the bundled drawing opens"),
        vec![HOST.to_string()],
    ))
}

async fn send(
    app: &Router,
    request: Request<Body>,
) -> (StatusCode, axum::http::HeaderMap, Vec<u8>) {
    let response = app
        .clone()
        .oneshot(request)
        .await
        .expect("the router answers");
    let status = response.status();
    let headers = response.headers().clone();
    let body = response
        .into_body()
        .collect()
        .await
        .expect("a body")
        .to_bytes()
        .to_vec();
    (status, headers, body)
}

/// Sends `request`, asserts that it succeeded (the body is the message otherwise) and returns
/// the headers and body.
/// The id of the rig a `POST /api/rig` answer names.
fn rig_id(headers: &axum::http::HeaderMap) -> String {
    headers[RIG_HEADER].to_str().expect("ascii").to_string()
}

async fn send_ok(app: &Router, request: Request<Body>) -> (axum::http::HeaderMap, Vec<u8>) {
    let (status, headers, body) = send(app, request).await;
    assert_eq!(status, StatusCode::OK, "{}", String::from_utf8_lossy(&body));
    (headers, body)
}

/// Sends `request`, asserts that it was refused with `expected` and returns the message of
/// its JSON error body.
async fn refused_with(app: &Router, request: Request<Body>, expected: StatusCode) -> String {
    let (status, _, body) = send(app, request).await;
    assert_eq!(status, expected, "{}", String::from_utf8_lossy(&body));
    json(&body)["error"].as_str().expect("message").to_string()
}

/// The message of the `400 Bad Request` that `request` is answered with.
async fn bad_request(app: &Router, request: Request<Body>) -> String {
    refused_with(app, request, StatusCode::BAD_REQUEST).await
}

/// The message of the `404 Not Found` that `request` is answered with.
async fn not_found(app: &Router, request: Request<Body>) -> String {
    refused_with(app, request, StatusCode::NOT_FOUND).await
}

fn get(uri: &str) -> Request<Body> {
    Request::get(uri)
        .header(header::HOST, HOST)
        .body(Body::empty())
        .expect("a request")
}

fn post(uri: &str) -> axum::http::request::Builder {
    Request::post(uri)
        .header(header::HOST, HOST)
        .header(API_HEADER, "1")
}

fn post_json(uri: &str, json: &serde_json::Value) -> Request<Body> {
    post(uri)
        .header(header::CONTENT_TYPE, "application/json")
        .body(Body::from(json.to_string()))
        .expect("a request")
}

fn json(body: &[u8]) -> serde_json::Value {
    serde_json::from_slice(body).expect("JSON")
}

fn f64s(bytes: &[u8]) -> Vec<f64> {
    bytes
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect()
}

/// Opens the file `bytes` under the (URL-encoded) file name `name` and returns its description.
async fn open_file(app: &Router, name: &str, bytes: impl Into<Body>) -> serde_json::Value {
    let request = post("/api/open")
        .header("x-file-name", name)
        .body(bytes.into())
        .expect("a request");
    let (_, body) = send_ok(app, request).await;
    json(&body)
}

/// Opens the bundled SVG (no handles) and returns its description.
async fn open_demo_svg(app: &Router) -> serde_json::Value {
    open_file(app, "fish%20drawing.svg", DEMO_SVG).await
}

/// A router with the bundled SVG opened: the router, the document's description and its id.
async fn demo_app() -> (Router, serde_json::Value, String) {
    let app = app();
    let info = open_demo_svg(&app).await;
    let id = info["id"].as_str().expect("id").to_string();
    (app, info, id)
}

/// [`demo_app`] with the server's state, for tests that look into it.
async fn demo_app_state() -> (std::sync::Arc<App>, Router, String) {
    let state = App::new(
        Document::bundled().expect("the bundled drawing opens"),
        vec![HOST.to_string()],
    );
    let app = router(state.clone());
    let info = open_demo_svg(&app).await;
    let id = info["id"].as_str().expect("id").to_string();
    (state, app, id)
}

/// `POST /api/defops/{rig}/deform` of the handles at `q`.
fn operator_deform(rig: &str, q: &[[f64; 2]]) -> Request<Body> {
    post_json(
        &format!("/api/defops/{rig}/deform"),
        &serde_json::json!({ "handles": q }),
    )
}

/// The operator's description a `/api/defop` answer carries in its header.
fn defop_info(headers: &axum::http::HeaderMap) -> serde_json::Value {
    serde_json::from_str(headers[DEFOP_HEADER].to_str().expect("ASCII")).expect("JSON")
}

/// `POST /api/defop` of `scene`, answered: the operator's description and the answer's body.
async fn train(app: &Router, scene: &serde_json::Value) -> (serde_json::Value, Vec<u8>) {
    let (headers, body) = send_ok(app, post_json("/api/defop", scene)).await;
    (defop_info(&headers), body)
}

/// The largest `|a_k − b_k|` over the pairs of `a` and `b`.
fn largest_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

fn two_handle_scene(document: &str, flexible: bool) -> serde_json::Value {
    serde_json::json!({
        "document": document,
        "scene": {
            "handles": [[440.0, 200.0], [110.0, 205.0]],
            "pose": [[1.0, 0.0, 0.0, 1.0, 0.0, 0.0], [1.0, 0.0, 0.0, 1.0, 0.0, 0.0]],
            "weights": {"family": "shepard", "exponent": 2.0},
            "junctions": [],
            "flexible": flexible
        }
    })
}

#[tokio::test]
async fn serve_initial_is_the_bundled_fish_marked_for_the_page() {
    let app = app();
    let (status, headers, body) = send(&app, get("/api/initial")).await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(headers["x-content-type-options"], "nosniff");
    let info = json(&body);
    let drawing = read_svg(DEMO_SVG, &ImportOptions::default()).expect("the fish reads");
    assert_eq!(
        info["rest"].as_array().expect("rest").len(),
        2 * drawing.n_points()
    );
    assert_eq!(info["n_curves"], drawing.n_curves());
    assert_eq!(
        info["scene"]["handles"].as_array().expect("handles").len(),
        5
    );
    // Its animation is the page's timeline: five keyframes of five maps.
    let keys = info["scene"]["animation"]["keyframes"]
        .as_array()
        .expect("the bundled scene's keyframes");
    assert_eq!(keys.len(), 5);
    assert_eq!(keys[1]["time"], 0.8);
    assert_eq!(keys[1]["pose"].as_array().expect("a pose").len(), 5);
    let n_elements = info["elements"].as_array().expect("elements").len();
    let svg = info["svg"].as_str().expect("svg");
    for k in 0..n_elements {
        assert!(
            svg.contains(&format!("data-splineskin-element=\"{k}\"")),
            "element {k} marked"
        );
    }
}

#[tokio::test]
async fn serve_page_and_assets_are_embedded_with_a_content_security_policy() {
    let app = app();
    let (status, headers, body) = send(&app, get("/")).await;
    assert_eq!(status, StatusCode::OK);
    assert!(String::from_utf8_lossy(&body).contains("<script type=\"module\" src=\"main.js\">"));
    assert!(headers[header::CONTENT_SECURITY_POLICY]
        .to_str()
        .expect("ascii")
        .contains("script-src 'self'"));
    // Cross-origin isolated, so that the page has shared memory (docs/webassembly.md).
    assert_eq!(headers["cross-origin-opener-policy"], "same-origin");
    assert_eq!(headers["cross-origin-embedder-policy"], "require-corp");
    let (status, headers, _) = send(&app, get("/main.js")).await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(
        headers[header::CONTENT_TYPE],
        "text/javascript; charset=utf-8"
    );
    let (status, _, _) = send(&app, get("/../Cargo.toml")).await;
    assert_eq!(status, StatusCode::NOT_FOUND);
}

#[tokio::test]
async fn serve_rig_operator_reproduces_the_rest_pose_and_export_reads_back() {
    let app = app();
    let info = open_demo_svg(&app).await;
    assert_eq!(info["name"], "fish drawing.svg");
    // An SVG opens with Puppet Warp's shape-aware weights.
    assert_eq!(
        info["scene"]["weights"],
        serde_json::json!({"family": "bbw"})
    );
    let id = info["id"].as_str().expect("id");
    let (headers, body) = send_ok(&app, post_json("/api/rig", &two_handle_scene(id, false))).await;
    assert!(headers[RIG_HEADER]
        .to_str()
        .expect("ascii")
        .starts_with('r'));
    let rest: Vec<f64> = serde_json::from_value(info["rest"].clone()).expect("rest");
    let operator = f64s(&body);
    let n_cols = 6 * 2;
    assert_eq!(operator.len(), rest.len() * n_cols);
    // O · vec(identity, identity) is the rest drawing.
    let identity = [1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0];
    for (r, &x) in rest.iter().enumerate() {
        let y: f64 = (0..n_cols)
            .map(|c| operator[r * n_cols + c] * identity[c])
            .sum();
        assert!(
            (x - y).abs() < 1e-9 * (1.0 + x.abs()),
            "row {r}: {y} for {x}"
        );
    }
    // Exporting the rest points gives a document with the same curves.
    let bytes: Vec<u8> = rest.iter().flat_map(|v| v.to_le_bytes()).collect();
    let request = post(&format!("/api/documents/{id}/export"))
        .body(Body::from(bytes))
        .expect("a request");
    let (_, body) = send_ok(&app, request).await;
    let svg = String::from_utf8(body).expect("text");
    let back = read_svg(&svg, &ImportOptions::default()).expect("the export reads back");
    assert_eq!(
        back.n_curves(),
        info["n_curves"].as_u64().expect("count") as usize
    );
    // Points of the wrong count are refused with a message.
    let request = post(&format!("/api/documents/{id}/export"))
        .body(Body::from(vec![0u8; 16]))
        .expect("a request");
    let message = bad_request(&app, request).await;
    assert!(message.contains("expected"), "{message}");
}

#[tokio::test]
async fn serve_flexible_solve_translates_exactly_under_one_translation() {
    let (app, info, id) = demo_app().await;
    let (headers, _) = send_ok(&app, post_json("/api/rig", &two_handle_scene(&id, true))).await;
    let rig = rig_id(&headers);
    let pose = serde_json::json!({"pose": [[1, 0, 0, 1, 12.5, -3], [1, 0, 0, 1, 12.5, -3]]});
    let (_, body) = send_ok(&app, post_json(&format!("/api/rigs/{rig}/solve"), &pose)).await;
    let points = f64s(&body);
    let rest = info["rest"].as_array().expect("rest");
    assert_eq!(points.len(), rest.len());
    for (k, (p, r)) in points.iter().zip(rest).enumerate() {
        let shift = if k % 2 == 0 { 12.5 } else { -3.0 };
        let r = r.as_f64().expect("a number");
        assert!(
            (p - (r + shift)).abs() < 1e-6,
            "coordinate {k}: {p} for {r} + {shift}"
        );
    }
    // A rig that was never built is reported as gone.
    let message = not_found(&app, post_json("/api/rigs/r999/solve", &pose)).await;
    assert!(message.contains("precompute again"), "{message}");
}

/// `POST /api/rigs/{id}/refine`: a bend one cubic per curve cannot follow gets anchors
/// inserted; the refined document keeps every anchor of the artist's in order, its rig (same
/// weights) reproduces its rest, its export marks the inserted anchors, and the same pose asks
/// for nothing more.
#[tokio::test]
async fn serve_refine_inserts_anchors_where_the_fit_falls_short() {
    let (app, info, id) = demo_app().await;
    let mut scene = two_handle_scene(&id, false);
    let (headers, _) = send_ok(&app, post_json("/api/rig", &scene)).await;
    let rig = rig_id(&headers);
    // The head turned 50° about its handle, the tail held.
    let turn = kurbo::Affine::translate((440.0, 200.0))
        * kurbo::Affine::rotate(50f64.to_radians())
        * kurbo::Affine::translate((-440.0, -200.0));
    let pose = serde_json::json!([turn.as_coeffs(), [1.0, 0.0, 0.0, 1.0, 0.0, 0.0]]);
    scene["scene"]["pose"] = pose.clone();
    let tolerance = 1e-3;
    let (_, body) = send_ok(
        &app,
        refine_request(&rig, &scene["scene"], serde_json::json!([pose]), tolerance),
    )
    .await;
    let answer = json(&body);
    assert_eq!(answer["refined"], true, "{answer}");
    let n_inserted = answer["n_inserted"].as_u64().expect("count") as usize;
    let n_before = info["n_curves"].as_u64().expect("count") as usize;
    assert!(n_inserted > 0);
    assert_eq!(
        answer["n_curves"].as_u64(),
        Some((n_before + n_inserted) as u64)
    );
    assert_eq!(answer["met"], true);
    assert!(answer["worst"].as_f64().expect("worst") <= tolerance);
    let refined = &answer["document"];
    assert_eq!(refined["n_curves"], answer["n_curves"]);
    // Every anchor of the artist's, in order, at its place; the inserted ones marked.
    let (old_rest, new_rest) = (numbers(&info["rest"]), numbers(&refined["rest"]));
    let scale = 500.0;
    let (moved, marked) = kept_anchors(&info, refined, &old_rest, &new_rest, scale);
    assert_eq!(answer["moved"], serde_json::json!(moved));
    assert_eq!(marked, n_inserted);
    // The refined rig's operator reproduces the refined rest at the identity.
    let new_rig = answer["rig"].as_str().expect("rig id");
    let (_, body) = send_ok(&app, get(&format!("/api/rigs/{new_rig}/operator"))).await;
    let operator = f64s(&body);
    assert_eq!(operator.len(), new_rest.len() * 12);
    for (r, &x) in new_rest.iter().enumerate() {
        let y =
            operator[r * 12] + operator[r * 12 + 3] + operator[r * 12 + 6] + operator[r * 12 + 9];
        assert!((x - y).abs() <= 1e-9 * scale, "row {r}: {y} for {x}");
    }
    // Its export marks the inserted anchors and reads back with every curve.
    let new_id = refined["id"].as_str().expect("id");
    let bytes: Vec<u8> = new_rest.iter().flat_map(|v| v.to_le_bytes()).collect();
    let (_, body) = send_ok(
        &app,
        post(&format!("/api/documents/{new_id}/export"))
            .body(Body::from(bytes))
            .expect("a request"),
    )
    .await;
    let svg = String::from_utf8(body).expect("text");
    assert!(svg.contains("data-splineskin-inserted=\""), "no marks");
    let back = read_svg(&svg, &ImportOptions::default()).expect("the export reads back");
    assert_eq!(back.n_curves(), n_before + n_inserted);
    // The same pose on the refined rig: nothing more to insert.
    let mut refined_scene = refined["scene"].clone();
    refined_scene["pose"] = pose.clone();
    let (_, body) = send_ok(
        &app,
        refine_request(
            new_rig,
            &refined_scene,
            serde_json::json!([pose]),
            tolerance,
        ),
    )
    .await;
    let again = json(&body);
    assert_eq!(
        (again["refined"].as_bool(), again["met"].as_bool()),
        (Some(false), Some(true)),
        "{again}"
    );
    refine_refusals(&app, &rig, &scene["scene"], &pose, tolerance).await;
}

/// `POST /api/rigs/{rig}/refine` of `scene` for `poses` within `tolerance`.
fn refine_request(
    rig: &str,
    scene: &serde_json::Value,
    poses: serde_json::Value,
    tolerance: f64,
) -> Request<Body> {
    post_json(
        &format!("/api/rigs/{rig}/refine"),
        &serde_json::json!({"scene": scene, "poses": poses, "tolerance": tolerance}),
    )
}

/// The numbers of a JSON array.
fn numbers(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .expect("array")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect()
}

/// Checks that every anchor of `info`'s drawing stands, in order, at its place in the refined
/// document `refined` (rest points `old_rest`, `new_rest`; drawing size `scale`); returns, per
/// path, the refined joints the old ones went to, and how many joints are marked inserted.
fn kept_anchors(
    info: &serde_json::Value,
    refined: &serde_json::Value,
    old_rest: &[f64],
    new_rest: &[f64],
    scale: f64,
) -> (Vec<serde_json::Value>, usize) {
    let (mut old_at, mut new_at, mut marked) = (0, 0, 0);
    let mut moved = Vec::new();
    for (old, new) in info["paths"]
        .as_array()
        .expect("paths")
        .iter()
        .zip(refined["paths"].as_array().expect("paths"))
    {
        let flags: Vec<bool> = serde_json::from_value(new["inserted"].clone()).expect("flags");
        marked += flags.iter().filter(|&&b| b).count();
        let kept: Vec<usize> = (0..flags.len()).filter(|&j| !flags[j]).collect();
        moved.push(serde_json::json!(kept));
        assert_eq!(kept.len(), old["joints"].as_array().expect("joints").len());
        for (k, &j) in kept.iter().enumerate() {
            for c in 0..2 {
                let (a, b) = (old_rest[old_at + 6 * k + c], new_rest[new_at + 6 * j + c]);
                assert!(
                    (a - b).abs() <= 1e-12 * scale,
                    "anchor {k} moved: {a} → {b}"
                );
            }
        }
        old_at += 2 * old["n_points"].as_u64().expect("n") as usize;
        new_at += 2 * new["n_points"].as_u64().expect("n") as usize;
    }
    (moved, marked)
}

/// `POST /api/rigs/{id}/refine` refusals name what is wrong: a tolerance of 0, no poses, a pose
/// of the wrong length, a rig that does not exist.
async fn refine_refusals(
    app: &Router,
    rig: &str,
    scene: &serde_json::Value,
    pose: &serde_json::Value,
    tolerance: f64,
) {
    let message = bad_request(
        app,
        refine_request(rig, scene, serde_json::json!([pose]), 0.0),
    )
    .await;
    assert!(message.contains("tolerance"), "{message}");
    let message = bad_request(
        app,
        refine_request(rig, scene, serde_json::json!([]), tolerance),
    )
    .await;
    assert!(message.contains("0 poses"), "{message}");
    let message = bad_request(
        app,
        refine_request(
            rig,
            scene,
            serde_json::json!([[[1.0, 0.0, 0.0, 1.0, 0.0, 0.0]]]),
            tolerance,
        ),
    )
    .await;
    assert!(message.contains("pose 0"), "{message}");
    not_found(
        app,
        refine_request("r999", scene, serde_json::json!([pose]), tolerance),
    )
    .await;
}

#[tokio::test]
async fn serve_weight_grid_is_one_at_its_handle() {
    let (app, _, id) = demo_app().await;
    let (_, headers, _) = send(&app, post_json("/api/rig", &two_handle_scene(&id, false))).await;
    let rig = rig_id(&headers);
    // A 3 × 3 grid whose centre sample is handle 1's rest position.
    let uri =
        format!("/api/rigs/{rig}/weights?handle=1&x0=107&y0=202&x1=113&y1=208&width=3&height=3");
    let (_, body) = send_ok(&app, get(&uri)).await;
    let grid: Vec<f32> = body
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes(c.try_into().expect("4 bytes")))
        .collect();
    assert_eq!(grid.len(), 9);
    assert_eq!(grid[4], 1.0, "Shepard weights interpolate: {grid:?}");
    assert!(grid.iter().all(|&w| w > 0.9 && w <= 1.0), "{grid:?}");
    let uri = format!("/api/rigs/{rig}/weights?handle=2&x0=0&y0=0&x1=1&y1=1&width=3&height=3");
    let message = bad_request(&app, get(&uri)).await;
    assert!(message.contains("no such handle"), "{message}");
}

#[tokio::test]
async fn serve_malformed_upload_is_a_message_and_the_server_goes_on() {
    let app = app();
    let request = post("/api/open")
        .header("x-file-name", "broken.svg")
        .body(Body::from(
            "<svg xmlns='http://www.w3.org/2000/svg'><path d='M0 0 C 1",
        ))
        .expect("a request");
    let message = bad_request(&app, request).await;
    assert!(message.starts_with("broken.svg"), "{message}");
    // Binary garbage, a scene of the wrong shape, a scene naming a file on the server.
    for (name, bytes) in [
        (
            "f.json",
            b"{\"splineskin_scene\": 1, \"svg\": \"/etc/hostname\"}".to_vec(),
        ),
        ("x.svg", vec![0xff, 0xfe, 0x00]),
        ("s.json", b"{\"splineskin_scene\": 1}".to_vec()),
    ] {
        let request = post("/api/open")
            .header("x-file-name", name)
            .body(Body::from(bytes))
            .expect("a request");
        let message = bad_request(&app, request).await;
        assert!(message.contains(name), "{message}");
        if name == "f.json" {
            assert!(message.contains("no file is read"), "{message}");
        }
    }
    open_demo_svg(&app).await;
}

#[tokio::test]
async fn serve_refuses_oversized_uploads_foreign_hosts_and_bare_posts() {
    let app = app();
    let request = post("/api/open")
        .body(Body::from(vec![b' '; MAX_UPLOAD_BYTES + 1]))
        .expect("a request");
    let message = refused_with(&app, request, StatusCode::PAYLOAD_TOO_LARGE).await;
    assert!(message.contains("limit"), "{message}");
    let request = Request::post("/api/open")
        .header(header::HOST, HOST)
        .body(Body::from(DEMO_SVG))
        .expect("a request");
    let (status, _, _) = send(&app, request).await;
    assert_eq!(
        status,
        StatusCode::FORBIDDEN,
        "a POST without the editor's header"
    );
    let request = Request::get("/api/initial")
        .header(header::HOST, "evil.example:7464")
        .body(Body::empty())
        .expect("a request");
    let (status, _, _) = send(&app, request).await;
    assert_eq!(status, StatusCode::FORBIDDEN, "a foreign Host");
}

#[tokio::test]
async fn serve_saved_scene_reads_back_as_the_page_left_it() {
    let (app, info, id) = demo_app().await;
    let mut scene = two_handle_scene(&id, true)["scene"].clone();
    scene["pose"][1] = serde_json::json!([0.0, 1.0, -1.0, 0.0, 300.0, 100.0]);
    // A smooth junction made a corner.
    let (path, joint) = info["paths"]
        .as_array()
        .expect("paths")
        .iter()
        .enumerate()
        .find_map(|(p, path)| {
            let joints = path["joints"].as_array().expect("joints");
            joints.iter().position(|k| k == "G1").map(|j| (p, j))
        })
        .expect("the fish has a G1 junction");
    scene["junctions"] = serde_json::json!([{"path": path, "joint": joint, "kind": "C0"}]);
    // A timeline of three keyframes, the first segment eased.
    let identity = [1.0, 0.0, 0.0, 1.0, 0.0, 0.0];
    scene["animation"] = serde_json::json!({"fps": 24.0, "keyframes": [
        {"time": 0.0, "pose": [identity, identity], "easing": "ease-in-out"},
        {"time": 0.75, "pose": [identity, [0.0, 1.0, -1.0, 0.0, 300.0, 100.0]], "easing": "hold"},
        {"time": 1.5, "pose": [[1.0, 0.0, 0.0, 1.0, 5.0, 0.0], identity], "easing": "linear"}
    ]});
    let (_, body) = send_ok(
        &app,
        post_json(&format!("/api/documents/{id}/scene"), &scene),
    )
    .await;
    let text = String::from_utf8(body).expect("text");
    let read = splineskin::scene::Scene::from_json(&text, "saved", None).expect("it reads");
    assert_eq!(
        read.handles,
        vec![Point::new(440.0, 200.0), Point::new(110.0, 205.0)]
    );
    assert!(read.flexible);
    assert_eq!(read.junctions.len(), 1);
    assert_eq!(
        read.poses[0].transforms[1].as_coeffs(),
        [0.0, 1.0, -1.0, 0.0, 300.0, 100.0]
    );
    let animation = read.animation.as_ref().expect("the timeline is saved");
    assert_eq!(animation.fps(), 24.0);
    let keys = animation.keyframes();
    assert_eq!(
        keys.iter().map(|k| (k.time, k.easing)).collect::<Vec<_>>(),
        [
            (0.0, Easing::EaseInOut),
            (0.75, Easing::Hold),
            (1.5, Easing::Linear)
        ]
    );
    assert_eq!(
        keys[1].transforms[1].as_coeffs(),
        [0.0, 1.0, -1.0, 0.0, 300.0, 100.0]
    );
    // Reopening it gives the page the same scene.
    let reopened = open_file(&app, "saved.json", text).await;
    assert_eq!(reopened["scene"], scene);
    // Coincident handles are refused, naming the handle.
    scene["handles"][1] = serde_json::json!([440.0, 200.0]);
    let message = bad_request(
        &app,
        post_json(&format!("/api/documents/{id}/scene"), &scene),
    )
    .await;
    assert!(message.contains("handles[1]"), "{message}");
}

#[tokio::test]
async fn serve_requests_dropped_midway_leave_the_server_serving() {
    let (state, app, id) = demo_app_state().await;
    // Rig requests abandoned right after they start (a page reloaded mid-request).
    for _ in 0..4 {
        let request = post_json("/api/rig", &two_handle_scene(&id, true));
        let pending = app.clone().oneshot(request);
        let _ = tokio::time::timeout(std::time::Duration::from_micros(1), pending).await;
    }
    // The server answers as before, and the abandoned jobs give their slots back when done.
    send_ok(&app, post_json("/api/rig", &two_handle_scene(&id, false))).await;
    for _ in 0..500 {
        if state.jobs.available_permits() == MAX_JOBS {
            break;
        }
        tokio::time::sleep(std::time::Duration::from_millis(10)).await;
    }
    assert_eq!(state.jobs.available_permits(), MAX_JOBS);
    let (status, _, _) = send(&app, get("/api/initial")).await;
    assert_eq!(status, StatusCode::OK);
}

#[tokio::test]
async fn serve_progress_follows_a_precomputation_until_it_ends() {
    let (state, app, id) = demo_app_state().await;
    // While followed, the board gives the stage the job told it; after, nothing.
    let followed = state.editor.progress.follow("job-1").expect("a valid name");
    assert!(
        state.editor.progress.follow("job-1").is_none(),
        "one follower per name"
    );
    assert!(state.editor.progress.follow("no spaces").is_none());
    let (_, _, body) = send(&app, get("/api/progress/job-1")).await;
    assert_eq!(json(&body)["stage"], "queued");
    followed.reporter()("weights");
    let (_, _, body) = send(&app, get("/api/progress/job-1")).await;
    assert_eq!(json(&body)["stage"], "weights");
    assert!(json(&body)["done"].is_null(), "no count unless reported");
    let count = Count {
        done: 7,
        total: 40,
        step: 2,
        steps: 3,
    };
    followed.counter()("training", count);
    let (_, _, body) = send(&app, get("/api/progress/job-1")).await;
    let report = json(&body);
    assert_eq!(
        (
            &report["stage"],
            &report["done"],
            &report["total"],
            &report["step"],
            &report["steps"]
        ),
        (
            &serde_json::json!("training"),
            &serde_json::json!(7),
            &serde_json::json!(40),
            &serde_json::json!(2),
            &serde_json::json!(3)
        )
    );
    drop(followed);
    let (_, _, body) = send(&app, get("/api/progress/job-1")).await;
    assert!(json(&body)["stage"].is_null());
    // A rig request naming its job is followed while it runs and forgotten when it ends.
    let mut request = post_json("/api/rig", &two_handle_scene(&id, false));
    request
        .headers_mut()
        .insert("x-splineskin-job", "job-2".parse().expect("a header"));
    let (status, _, _) = send(&app, request).await;
    assert_eq!(status, StatusCode::OK);
    assert!(state.editor.progress.stage("job-2").is_none());
}

/// `POST /api/progress/{job}/stop`.
async fn stop_job(app: &Router, job: &str) -> (StatusCode, axum::http::HeaderMap, Vec<u8>) {
    let request = post(&format!("/api/progress/{job}/stop"))
        .body(Body::empty())
        .expect("a request");
    send(app, request).await
}

/// Sends `request` as job `job` (header `x-splineskin-job`) on a task of its own.
fn spawn_followed(
    app: &Router,
    mut request: axum::http::Request<Body>,
    job: &str,
) -> tokio::task::JoinHandle<(StatusCode, axum::http::HeaderMap, Vec<u8>)> {
    request
        .headers_mut()
        .insert("x-splineskin-job", job.parse().expect("a header"));
    let app = app.clone();
    tokio::spawn(async move { send(&app, request).await })
}

/// Polls `GET /api/progress/{job}` (up to a minute) until `done` holds of its report; the last
/// report.
async fn progress_until(
    app: &Router,
    job: &str,
    done: impl Fn(&serde_json::Value) -> bool,
) -> serde_json::Value {
    let mut seen = serde_json::Value::Null;
    for _ in 0..6000 {
        let (_, _, body) = send(app, get(&format!("/api/progress/{job}"))).await;
        seen = json(&body);
        if done(&seen) {
            break;
        }
        tokio::time::sleep(std::time::Duration::from_millis(10)).await;
    }
    seen
}

#[tokio::test]
async fn serve_stop_ends_bounded_biharmonic_weights_at_their_next_iteration() {
    let (app, _, id) = demo_app().await;
    let handles = [
        [440.0, 200.0],
        [110.0, 205.0],
        [300.0, 150.0],
        [250.0, 260.0],
        [380.0, 250.0],
        [180.0, 180.0],
    ];
    let scene = serde_json::json!({
        "document": id,
        "scene": {
            "handles": handles,
            "pose": vec![[1.0, 0.0, 0.0, 1.0, 0.0, 0.0]; handles.len()],
            "weights": {"family": "bbw"},
            "junctions": [],
            "flexible": false
        }
    });
    let rig = spawn_followed(&app, post_json("/api/rig", &scene), "bbw-1");
    // Waits until the weights are being computed, then asks them to stop.
    let seen = progress_until(&app, "bbw-1", |seen| seen["stage"] == "weights").await;
    assert_eq!(seen["stage"], "weights", "{seen}");
    let (status, _, _) = stop_job(&app, "bbw-1").await;
    assert_eq!(status, StatusCode::OK);
    let (status, _, body) = rig.await.expect("the rig request ends");
    let said = String::from_utf8_lossy(&body);
    assert_eq!(status, StatusCode::CONFLICT, "{said}");
    assert!(said.contains("weights stopped as asked"), "{said}");
    // Not stopped, the same request rigs.
    let (status, headers, _) = send(&app, post_json("/api/rig", &scene)).await;
    assert_eq!(status, StatusCode::OK);
    assert!(headers.contains_key(RIG_HEADER));
}

/// `POST /api/weights/columns` then `POST /api/rig` with them `solved`: the static editor's
/// split of a rig over its workers gives the operator of one solve, bit for bit; columns that
/// do not fit the scene are refused with their element named.
#[tokio::test]
async fn serve_columns_solved_apart_make_the_same_rig() {
    let (app, _, id) = demo_app().await;
    let mut request = two_handle_scene(&id, false);
    request["scene"]["handles"] =
        serde_json::json!([[440.0, 200.0], [110.0, 205.0], [300.0, 150.0]]);
    request["scene"]["pose"] = serde_json::json!(vec![[1.0, 0.0, 0.0, 1.0, 0.0, 0.0]; 3]);
    request["scene"]["weights"] = serde_json::json!({"family": "bbw"});
    let (_, whole) = send_ok(&app, post_json("/api/rig", &request)).await;
    let columns_of = |columns: serde_json::Value| {
        let mut asked = request.clone();
        asked["columns"] = columns;
        post_json("/api/weights/columns", &asked)
    };
    let (_, first) = send_ok(&app, columns_of(serde_json::json!([2, 0]))).await;
    let (_, second) = send_ok(&app, columns_of(serde_json::json!([1]))).await;
    let (first, second) = (json(&first), json(&second));
    assert_eq!(first["columns"], serde_json::json!([2, 0]));
    let mut solved = first.clone();
    solved["columns"] = serde_json::json!([2, 0, 1]);
    let mut values = first["values"].as_array().expect("values").clone();
    values.extend(second["values"].as_array().expect("values").iter().cloned());
    solved["values"] = serde_json::Value::Array(values);
    let mut given = request.clone();
    given["solved"] = solved.clone();
    let (_, apart) = send_ok(&app, post_json("/api/rig", &given)).await;
    assert_eq!(f64s(&apart), f64s(&whole));
    // Control: the same columns under swapped handles change the operator.
    let mut changed = given.clone();
    changed["solved"]["columns"] = serde_json::json!([0, 2, 1]);
    let (_, other) = send_ok(&app, post_json("/api/rig", &changed)).await;
    assert_ne!(f64s(&other), f64s(&whole));
    let mut wrong = given.clone();
    wrong["solved"]["n_vertices"] = serde_json::json!(3);
    let message = bad_request(&app, post_json("/api/rig", &wrong)).await;
    assert!(
        message.contains("weights.solved") && message.contains("3 vertices"),
        "{message}"
    );
    let message = bad_request(&app, columns_of(serde_json::json!([5]))).await;
    assert!(message.contains("column 5 does not exist"), "{message}");
    let message = bad_request(&app, columns_of(serde_json::json!([]))).await;
    assert!(message.contains("0 columns asked for"), "{message}");
    let mut shepard = two_handle_scene(&id, false);
    shepard["columns"] = serde_json::json!([0]);
    let message = bad_request(&app, post_json("/api/weights/columns", &shepard)).await;
    assert!(message.contains("'bbw' weights only"), "{message}");
}

#[tokio::test]
async fn serve_stop_ends_a_training_at_its_next_solve() {
    let (app, _, id) = demo_app().await;
    // 5 000 samples: minutes of training unless stopped.
    let request = post_json("/api/defop", &operator_scene(&id, "defop-arap", 5000));
    let training = spawn_followed(&app, request, "train-1");
    // Waits until solves are being counted.
    let seen = progress_until(&app, "train-1", |seen| {
        seen["stage"] == "training" && seen["done"].as_u64().unwrap_or(0) > 0
    })
    .await;
    assert_eq!(seen["stage"], "training", "{seen}");
    let (status, _, body) = stop_job(&app, "train-1").await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(json(&body)["stopping"], true);
    let (status, _, body) = training.await.expect("the training request ends");
    assert_eq!(
        status,
        StatusCode::CONFLICT,
        "{}",
        String::from_utf8_lossy(&body)
    );
    assert!(
        json(&body)["error"]
            .as_str()
            .unwrap_or("")
            .contains("stopped"),
        "{}",
        String::from_utf8_lossy(&body)
    );
    let done = seen["done"].as_u64().expect("a count");
    assert!(done < 5000, "stopped midway, after {done} solves");
    // The job is over: nothing to report, nothing to stop.
    let (_, _, body) = send(&app, get("/api/progress/train-1")).await;
    assert!(json(&body)["stage"].is_null());
    let (status, _, body) = stop_job(&app, "train-1").await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    assert!(json(&body)["error"]
        .as_str()
        .unwrap_or("")
        .contains("train-1"));
    // The server trains as before afterwards.
    let (status, _, _) = send(
        &app,
        post_json("/api/defop", &operator_scene(&id, "defop-arap", 12)),
    )
    .await;
    assert_eq!(status, StatusCode::OK);
}

/// A scene of the bundled fish with two handles and a trained operator's settings.
fn operator_scene(document: &str, family: &str, samples: usize) -> serde_json::Value {
    let mut scene = two_handle_scene(document, false);
    scene["scene"]["weights"] = serde_json::json!({"family": family, "samples": samples});
    scene
}

/// The handle functions `ψ(Q)` restated from the route's documented layout (api.rs): from the
/// header, and the thin-plate centres after `G_spline` in the body.
fn operator_psi(info: &serde_json::Value, data: &[f64], q: &[[f64; 2]]) -> Vec<f64> {
    let n_psi = info["n_functions"].as_u64().expect("n_functions") as usize;
    let n_centres = info["n_centres"].as_u64().expect("n_centres") as usize;
    let rows = 2 * info["n_points"].as_u64().expect("n_points") as usize;
    let scale = info["scale"].as_f64().expect("scale");
    let rest: Vec<[f64; 2]> = serde_json::from_value(info["rest"].clone()).expect("rest");
    let d = 2 * rest.len();
    let mut psi = vec![1.0];
    for (q, p) in q.iter().zip(&rest) {
        psi.extend([(q[0] - p[0]) / scale, (q[1] - p[1]) / scale]);
    }
    let centres = &data[rows * n_psi..];
    for k in 0..n_centres {
        let r2: f64 = (0..d)
            .map(|a| (psi[1 + a] - centres[k * d + a]).powi(2))
            .sum();
        psi.push(if r2 > 0.0 { 0.5 * r2 * r2.ln() } else { 0.0 });
    }
    assert_eq!(psi.len(), n_psi);
    psi
}

/// The page's evaluation restated from the route's documented layout: `ψ(Q)`
/// ([`operator_psi`]), then the row-major product with `G_spline`.
fn operator_points(info: &serde_json::Value, data: &[f64], q: &[[f64; 2]]) -> Vec<f64> {
    let psi = operator_psi(info, data, q);
    let n_psi = psi.len();
    let rows = 2 * info["n_points"].as_u64().expect("n_points") as usize;
    (0..rows)
        .map(|r| (0..n_psi).map(|c| data[r * n_psi + c] * psi[c]).sum())
        .collect()
}

#[tokio::test]
async fn serve_operator_layout_reproduces_the_library_and_the_rest_drawing() {
    let (app, info, id) = demo_app().await;
    let rest: Vec<f64> = serde_json::from_value(info["rest"].clone()).expect("rest");
    let diagonal = {
        let (xs, ys): (Vec<f64>, Vec<f64>) = rest.chunks_exact(2).map(|p| (p[0], p[1])).unzip();
        let span = |v: &[f64]| {
            v.iter().cloned().fold(f64::MIN, f64::max) - v.iter().cloned().fold(f64::MAX, f64::min)
        };
        span(&xs).hypot(span(&ys))
    };
    let (op, body) = train(&app, &operator_scene(&id, "defop-arap", 12)).await;
    assert_eq!(op["kind"], "tps");
    assert_eq!(op["n_samples"], 13, "the rest configuration and 12 samples");
    assert_eq!(op["n_centres"], 13);
    assert_eq!(op["n_functions"], 1 + 4 + 13);
    let n_points = rest.len() / 2;
    assert_eq!(op["n_points"], n_points);
    let data = f64s(&body);
    assert_eq!(data.len(), 2 * n_points * 18 + 13 * 4);

    // The layout as documented, at rest and at a moved configuration, against the library.
    let handles = [[440.0, 200.0], [110.0, 205.0]];
    let moved = [[452.0, 188.0], [104.0, 230.0]];
    let rig = op["id"].as_str().expect("id");
    for q in [handles, moved] {
        let (_, body) = send_ok(&app, operator_deform(rig, &q)).await;
        let library = f64s(&body);
        let page = operator_points(&op, &data, &q);
        let worst = largest_difference(&page, &library);
        // Same numbers summed in another order: rounding only.
        assert!(worst < 1e-9 * diagonal, "page vs library {worst:e}");
        if q == handles {
            let off = largest_difference(&library, &rest);
            // The join reproduces the drawing at rest (DefOpRig's doc): to rounding.
            assert!(off < 1e-9 * diagonal, "rest configuration off by {off:e}");
        } else {
            let moved_by = largest_difference(&library, &rest);
            assert!(moved_by > 5.0, "moved handles should move the drawing");
        }
    }
}

/// `POST /api/defops/{id}/follow`: inside the trained region the operator stays; dragged far,
/// a new operator holds the configuration as a sample (asked again, it stays, at distance 0)
/// and is evaluated like any other; bad requests are refused with messages.
#[tokio::test]
async fn serve_operator_follows_a_far_configuration() {
    let (app, _, id) = demo_app().await;
    let (op, _) = train(&app, &operator_scene(&id, "defop-arap", 12)).await;
    let rig = op["id"].as_str().expect("id").to_string();
    let reach = op["reach"].as_f64().expect("reach");
    assert_eq!(op["n_followed"], 0);
    let follow = |rig: String, handles: serde_json::Value, settle: bool| {
        let app = app.clone();
        async move {
            send(
                &app,
                post_json(
                    &format!("/api/defops/{rig}/follow"),
                    &serde_json::json!({ "handles": handles, "settle": settle }),
                ),
            )
            .await
        }
    };
    // At rest: inside, nothing trained.
    let rest = serde_json::json!([[440.0, 200.0], [110.0, 205.0]]);
    let (status, headers, body) = follow(rig.clone(), rest.clone(), true).await;
    assert_eq!(status, StatusCode::OK);
    assert!(headers.get(DEFOP_HEADER).is_none());
    let answer: serde_json::Value = serde_json::from_slice(&body).expect("JSON");
    assert_eq!(answer["followed"], false);
    assert_eq!(answer["reason"], "inside");
    assert_eq!(answer["distance"], 0.0);
    // One handle 3 sampling radii away: a new operator with that sample.
    let far = serde_json::json!([[440.0, 200.0 - 3.0 * reach], [110.0, 205.0]]);
    let (status, headers, body) = follow(rig.clone(), far.clone(), false).await;
    assert_eq!(status, StatusCode::OK, "{}", String::from_utf8_lossy(&body));
    let followed = defop_info(&headers);
    assert_eq!(followed["n_followed"], 1);
    assert_eq!(followed["n_samples"], 14);
    assert_eq!(followed["n_functions"], 1 + 4 + 14);
    let new_rig = followed["id"].as_str().expect("id").to_string();
    assert_ne!(new_rig, rig);
    let data = f64s(&body);
    let q: [[f64; 2]; 2] = serde_json::from_value(far.clone()).expect("q");
    let (_, library) = send_ok(&app, operator_deform(&new_rig, &q)).await;
    let page = operator_points(&followed, &data, &q);
    let worst = page
        .iter()
        .zip(&f64s(&library))
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-9 * reach, "page vs library {worst:e}");
    let (status, headers, body) = follow(new_rig.clone(), far.clone(), true).await;
    assert_eq!(status, StatusCode::OK);
    assert!(headers.get(DEFOP_HEADER).is_none());
    let answer: serde_json::Value = serde_json::from_slice(&body).expect("JSON");
    assert_eq!(
        (answer["reason"].as_str(), answer["distance"].as_f64()),
        (Some("inside"), Some(0.0))
    );

    // Refusals: a handle count the operator does not have, a missing field, an unknown rig.
    let (status, _, body) = follow(rig.clone(), serde_json::json!([[1.0, 2.0]]), false).await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert!(
        String::from_utf8_lossy(&body).contains("1 handle positions for an operator of 2 handles")
    );
    let (status, _, body) = follow(
        rig.clone(),
        serde_json::json!([[1.0, null], [0.0, 0.0]]),
        false,
    )
    .await;
    assert_eq!(
        status,
        StatusCode::UNPROCESSABLE_ENTITY,
        "{}",
        String::from_utf8_lossy(&body)
    );
    let (status, _, body) = follow("o999".into(), rest, false).await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    assert!(String::from_utf8_lossy(&body).contains("no longer kept"));
}

#[tokio::test]
async fn serve_operator_refuses_what_it_cannot_train_with_a_message() {
    let (app, _, id) = demo_app().await;
    let refused = |scene: serde_json::Value, expected: &'static str| {
        let app = app.clone();
        async move {
            let (status, _, body) = send(&app, post_json("/api/defop", &scene)).await;
            assert!(status.is_client_error(), "{status}");
            let message = json(&body)["error"].as_str().expect("message").to_string();
            assert!(message.contains(expected), "{message}");
        }
    };
    let mut none = operator_scene(&id, "defop-sarap", 10);
    none["scene"]["handles"] = serde_json::json!([]);
    none["scene"]["pose"] = serde_json::json!([]);
    refused(none, "at least one point handle").await;
    let mut flexible = operator_scene(&id, "defop-sarap", 10);
    flexible["scene"]["flexible"] = serde_json::json!(true);
    refused(flexible, "flexible G¹ does not apply").await;
    refused(operator_scene(&id, "defop-sarap", 0), "training samples").await;
    refused(
        operator_scene(&id, "defop-arap", 3),
        "2 handles need at least 4 training samples",
    )
    .await;
    refused(
        operator_scene(&id, "defop-sarap", 1_000_000),
        "training samples",
    )
    .await;
    refused(
        operator_scene(&id, "shepard", 10),
        "not a deformation operator",
    )
    .await;
    let mut nan = operator_scene(&id, "defop-sarap", 10);
    nan["scene"]["handles"][0][0] = serde_json::json!(f64::NAN); // JSON null
    refused(nan, "scene.handles[0]").await;
    let message = not_found(
        &app,
        post_json(
            "/api/defops/o999/deform",
            &serde_json::json!({"handles": [[0.0, 0.0]]}),
        ),
    )
    .await;
    assert!(message.contains("train it again"), "{message}");
}

#[tokio::test]
async fn serve_saved_operator_scene_records_its_defop_section_and_offers_it_reopened() {
    let (app, _, id) = demo_app().await;
    let mut scene = operator_scene(&id, "defop-arap", 37)["scene"].clone();
    scene["pose"][1] = serde_json::json!([1.0, 0.0, 0.0, 1.0, 12.0, -30.0]);
    let (_, body) = send_ok(
        &app,
        post_json(&format!("/api/documents/{id}/scene"), &scene),
    )
    .await;
    let text = String::from_utf8(body).expect("text");
    let file: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    // The weights stay a family the library knows (the opened SVG's: bounded biharmonic); the
    // operator is in its own section, every setting written out (the editor's domain
    // included), so the CLI trains the same one.
    assert_eq!(file["weights"]["family"], "bbw");
    assert_eq!(file["defop"]["energy"], "arap");
    assert_eq!(file["defop"]["samples"], 37);
    assert_eq!(file["defop"]["handle_basis"], "tps");
    assert_eq!(file["defop"]["spatial_basis"], "hats");
    assert_eq!(
        file["defop"]["domain"]["max_area_fraction"],
        splineskin::defop::TRAINING_MAX_AREA_FRACTION
    );
    let read = splineskin::scene::Scene::from_json(&text, "saved", None).expect("it reads");
    let settings = read.defop.expect("a defop section");
    assert_eq!(settings.energy, splineskin::defop::Energy::Arap);
    assert_eq!(settings.samples, 37);
    // Reopened, the page gets the scene with its weights, the pose as it was, and the
    // operator offered.
    let reopened = open_file(&app, "saved.json", text).await;
    let mut as_weights = scene.clone();
    as_weights["weights"] = serde_json::json!({"family": "bbw"});
    assert_eq!(reopened["scene"], as_weights);
    assert_eq!(
        reopened["operator"],
        serde_json::json!({"family": "defop-arap", "samples": 37})
    );
    // Saved again from the reopened document: the same file.
    let reopened_id = reopened["id"].as_str().expect("id");
    let (_, _, again) = send(
        &app,
        post_json(&format!("/api/documents/{reopened_id}/scene"), &scene),
    )
    .await;
    let again: serde_json::Value = serde_json::from_slice(&again).expect("JSON");
    assert_eq!(again["defop"], file["defop"]);
    assert_eq!(again["weights"], file["weights"]);
    // The weights route does not build an operator's scene as weights.
    let message = bad_request(
        &app,
        post_json("/api/rig", &operator_scene(&id, "defop-sarap", 10)),
    )
    .await;
    assert!(message.contains("POST /api/defop"), "{message}");
}

/// The viewBox routes: every point moved by (+300, −20) takes the fish out of its viewBox;
/// `outside` names the paths with their overshoot and the viewBox a `fit` export writes, which
/// the export with `?viewbox=fit` writes; `keep` (and no query) write the input's; anything
/// else is refused with a message.
#[tokio::test]
async fn serve_outside_reports_and_export_fits_the_view_box() {
    let (app, info, id) = demo_app().await;
    let drawing = read_svg(DEMO_SVG, &ImportOptions::default()).expect("the fish");
    let moved: Vec<Point> = drawing
        .flat_points()
        .iter()
        .map(|&p| p + kurbo::Vec2::new(300.0, -20.0))
        .collect();
    let bytes: Vec<u8> = moved
        .iter()
        .flat_map(|p| [p.x.to_le_bytes(), p.y.to_le_bytes()])
        .flatten()
        .collect();
    let request = |uri: String| {
        post(&uri)
            .body(Body::from(bytes.clone()))
            .expect("a request")
    };
    let (_, body) = send_ok(&app, request(format!("/api/documents/{id}/outside"))).await;
    let report = json(&body);
    let expected = splineskin::drawing::svg_out::art_outside_view_box(&drawing, &moved).unwrap();
    let outside = report["outside"].as_array().expect("outside");
    assert_eq!(outside.len(), expected.len());
    assert!(!outside.is_empty());
    let distances: Vec<f64> = outside
        .iter()
        .map(|o| o["distance"].as_f64().expect("distance"))
        .collect();
    assert!(distances.windows(2).all(|w| w[0] >= w[1]), "farthest first");
    let farthest = expected
        .iter()
        .max_by(|a, b| a.distance.total_cmp(&b.distance))
        .unwrap();
    assert_eq!(distances[0], farthest.distance);
    assert_eq!(outside[0]["element"], farthest.element.as_str());
    assert_eq!(report["view_box"], info["view_box"]);
    let r = splineskin::drawing::svg_out::art_bounds(&drawing, &moved)
        .unwrap()
        .unwrap()
        .union(drawing.source.as_ref().unwrap().view_box());
    let fitted: Vec<f64> = serde_json::from_value(report["fitted"].clone()).expect("fitted");
    assert_eq!(fitted, [r.x0, r.y0, r.width(), r.height()]);

    let view_box_of = |svg: &[u8]| {
        let text = String::from_utf8(svg.to_vec()).expect("text");
        let at = text.find("viewBox=\"").expect("a viewBox") + 9;
        text[at..at + text[at..].find('"').unwrap()].to_string()
    };
    let (_, body) = send_ok(
        &app,
        request(format!("/api/documents/{id}/export?viewbox=fit")),
    )
    .await;
    let numbers: Vec<f64> = view_box_of(&body)
        .split(' ')
        .map(|v| v.parse().expect("a number"))
        .collect();
    assert_eq!(numbers, fitted, "the export writes the viewBox announced");
    let input = view_box_of(DEMO_SVG.as_bytes());
    for query in ["?viewbox=keep", ""] {
        let (status, _, body) =
            send(&app, request(format!("/api/documents/{id}/export{query}"))).await;
        assert_eq!(status, StatusCode::OK);
        assert_eq!(view_box_of(&body), input, "{query}");
    }
    let message = bad_request(
        &app,
        request(format!("/api/documents/{id}/export?viewbox=grow")),
    )
    .await;
    assert!(
        message.contains("viewbox=grow (expected keep or fit)"),
        "{message}"
    );
}

/// A drawing of our own for the export's carried elements: a plate filled with a horizontal
/// `userSpaceOnUse` gradient, and a label on it.
const PLATE_SVG: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 200 100">
  <defs><linearGradient id="g" gradientUnits="userSpaceOnUse" x1="0" y1="0" x2="200" y2="0">
    <stop offset="0" stop-color="#246"/><stop offset="1" stop-color="#fc6"/></linearGradient></defs>
  <rect x="10" y="20" width="180" height="60" fill="url(#g)"/>
  <text x="70" y="60" font-size="20" fill="#fff">plate</text>
</svg>"##;

/// The plate's three point handles.
const PLATE_HANDLES: [[f64; 2]; 3] = [[40.0, 50.0], [160.0, 50.0], [100.0, 30.0]];

async fn open_plate(app: &Router) -> serde_json::Value {
    open_file(app, "plate.svg", PLATE_SVG).await
}

/// The `matrix(a b c d e f)` of attribute `attribute` in the first start tag of `svg` that
/// begins with `start`, if it has one.
fn matrix_in(svg: &str, start: &str, attribute: &str) -> Option<kurbo::Affine> {
    let at = svg.find(start)?;
    let tag = &svg[at..at + svg[at..].find('>')?];
    let key = format!("{attribute}=\"matrix(");
    let from = tag.find(&key)? + key.len();
    let c: Vec<f64> = tag[from..from + tag[from..].find(')')?]
        .split([' ', ','])
        .filter(|v| !v.is_empty())
        .map(|v| v.parse().expect("a number"))
        .collect();
    Some(kurbo::Affine::new(c.try_into().ok()?))
}

fn le_bytes(values: impl IntoIterator<Item = f64>) -> Vec<u8> {
    values.into_iter().flat_map(|v| v.to_le_bytes()).collect()
}

/// `POST /api/documents/{id}/pins` places pins over the plate as `splineskin rig` does: inside
/// its rectangle, the page's own pin kept first and exactly; a body that is not a list of
/// points is refused with a message.
#[tokio::test]
async fn serve_pins_cover_the_art_and_keep_the_given_ones() {
    let app = app();
    let info = open_plate(&app).await;
    let id = info["id"].as_str().expect("id");
    let inside = |p: &[f64]| p[0] > 10.0 && p[0] < 190.0 && p[1] > 20.0 && p[1] < 80.0;
    let uri = format!("/api/documents/{id}/pins");
    let (_, body) = send_ok(&app, post_json(&uri, &serde_json::json!({"handles": []}))).await;
    let placed: Vec<[f64; 2]> = serde_json::from_value(json(&body)["pins"].clone()).expect("pins");
    assert!(placed.len() >= 2, "{placed:?}");
    assert!(placed.iter().all(|p| inside(p)), "{placed:?}");
    let given = [33.25, 41.5];
    let request = post_json(&uri, &serde_json::json!({"handles": [given]}));
    let (_, body) = send_ok(&app, request).await;
    let with_given: Vec<[f64; 2]> =
        serde_json::from_value(json(&body)["pins"].clone()).expect("pins");
    assert_eq!(with_given[0], given);
    assert!(with_given.len() >= 2 && with_given[1..].iter().all(|p| inside(p)));
    let message = refused_with(
        &app,
        post_json(&uri, &serde_json::json!({"handles": "all"})),
        StatusCode::UNPROCESSABLE_ENTITY,
    )
    .await;
    assert!(message.contains("handles"), "{message}");
}

/// The plate with its label inside a turned, moved group and scaled by its own transform.
const LABELLED_PLATE_SVG: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 200 100">
  <rect x="10" y="20" width="180" height="60" fill="#468"/>
  <g transform="translate(10 5) rotate(10)"><text x="40" y="40" font-size="14" transform="scale(1.2)">plate</text></g>
</svg>"##;

/// A bend of the plate's handles: the rig of document `info` under it, the maps its carry
/// operator gives there (per carried text or image, then per element of `painted`), and the
/// document Export SVG writes with it.
async fn carry_and_export_at_bend(
    app: &Router,
    info: &serde_json::Value,
) -> (Vec<kurbo::Affine>, String) {
    let id = info["id"].as_str().expect("id");
    let bend = [
        kurbo::Affine::IDENTITY,
        kurbo::Affine::translate((20.0, -10.0))
            * kurbo::Affine::rotate_about(0.4, Point::new(160.0, 50.0)),
        kurbo::Affine::translate((0.0, 15.0)),
    ];
    let scene = serde_json::json!({
        "document": id,
        "scene": {
            "handles": PLATE_HANDLES,
            "pose": bend.map(|t| t.as_coeffs()),
            "weights": {"family": "shepard", "exponent": 2.0},
            "junctions": [],
            "flexible": false
        }
    });
    let (headers, _) = send_ok(app, post_json("/api/rig", &scene)).await;
    let rig = rig_id(&headers);
    let (_, body) = send_ok(app, get(&format!("/api/rigs/{rig}/carry"))).await;
    let carry = f64s(&body);
    let width = 6 * bend.len() + 1;
    assert_eq!(carry.len() % (6 * width), 0, "rows of {width}");
    let x: Vec<f64> = bend
        .iter()
        .flat_map(|t| t.as_coeffs())
        .chain([1.0])
        .collect();
    let maps = carry
        .chunks_exact(6 * width)
        .map(|rows| {
            kurbo::Affine::new(std::array::from_fn(|r| {
                (0..width).map(|c| rows[r * width + c] * x[c]).sum::<f64>()
            }))
        })
        .collect();
    let rest = numbers(&info["rest"]);
    let body = le_bytes(
        rest.into_iter()
            .chain(bend.iter().flat_map(|t| t.as_coeffs())),
    );
    let request = post(&format!("/api/documents/{id}/export?rig={rig}"))
        .body(Body::from(body))
        .expect("a request");
    let (_, body) = send_ok(app, request).await;
    (maps, String::from_utf8(body).expect("text"))
}

/// The carry operator the page moves text with gives, at a bend of the plate, the map Export
/// SVG writes on the label (`P⁻¹ A P` before its own transform), to rounding; the shown
/// document marks the label and the description gives its group's map `P`.
#[tokio::test]
async fn serve_carry_operator_gives_the_exported_label_map() {
    let app = app();
    let info = open_file(&app, "labelled.svg", LABELLED_PLATE_SVG).await;
    let parent = kurbo::Affine::translate((10.0, 5.0)) * kurbo::Affine::rotate(10f64.to_radians());
    let carried: Vec<[f64; 6]> = serde_json::from_value(info["carried"].clone()).expect("carried");
    assert_eq!(carried.len(), 1);
    for (a, b) in carried[0].iter().zip(parent.as_coeffs()) {
        assert!((a - b).abs() < 1e-12, "{carried:?}");
    }
    let shown = info["svg"].as_str().expect("svg");
    assert!(shown.contains("data-splineskin-carried=\"0\""), "{shown}");
    let (maps, svg) = carry_and_export_at_bend(&app, &info).await;
    assert_eq!(maps.len(), 1);
    let expected = parent.inverse() * maps[0] * parent;
    let written = matrix_in(&svg, "<text", "transform").expect("the label carries a transform");
    assert!(
        svg.contains(") scale(1.2)\""),
        "its own transform follows: {svg}"
    );
    for (got, want) in written.as_coeffs().iter().zip(expected.as_coeffs()) {
        assert!(
            (got - want).abs() <= 1e-9 * 200.0,
            "{written:?} vs {expected:?}"
        );
    }
    // The label does move under the bend (a map left at rest would not pass the above).
    assert!((expected.as_coeffs()[5]).abs() > 1.0, "{expected:?}");
}

/// A stroke inside a non-uniform transform: the description gives where its stroke frame is
/// fitted (`stroke_frame`: its region's mean and covariance) and lists it in `painted`, so the
/// carry operator gives its best-fit map `A`; the frame the page makes of them is the one
/// Export SVG draws it in (`transform` `F L` for an element whose own transform is `L`). An
/// element in a similar frame has none.
#[tokio::test]
async fn serve_stroke_frames_are_described_for_the_page_as_export_draws_them() {
    let app = app();
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 200 100">
  <rect x="10" y="20" width="180" height="60" fill="#468"/>
  <path id="line" d="M5 20 L45 80" transform="scale(4 1)" stroke="#222" stroke-width="2" fill="none"/>
</svg>"##;
    let info = open_file(&app, "stretched.svg", svg).await;
    let elements = info["elements"].as_array().expect("elements");
    assert!(elements[0]["stroke_frame"].is_null(), "{info}");
    let centre = numbers(&elements[1]["stroke_frame"]["centre"]);
    let covariance = numbers(&elements[1]["stroke_frame"]["covariance"]);
    // The line from (20, 20) to (180, 80), sampled evenly: its midpoint.
    assert!(
        (centre[0] - 100.0).abs() < 1e-9 && (centre[1] - 50.0).abs() < 1e-9,
        "{centre:?}"
    );
    // Its samples lie along the line's direction (160, 60).
    let [cxx, cxy, cyy] = [covariance[0], covariance[1], covariance[2]];
    assert!(
        (cxy / cxx - 60.0 / 160.0).abs() < 1e-9 && (cxx * cyy - cxy * cxy).abs() < 1e-9 * cxx * cxx
    );
    assert_eq!(info["painted"], serde_json::json!([1]), "{info}");
    let (maps, exported) = carry_and_export_at_bend(&app, &info).await;
    assert_eq!(maps.len(), 1, "one element's map");
    let region = splineskin::drawing::follow::StrokeFrameRegion {
        centre: Point::new(centre[0], centre[1]),
        covariance: [covariance[0], covariance[1], covariance[2]],
    };
    let frame = region.frame(maps[0]);
    let expected = frame * kurbo::Affine::scale_non_uniform(4.0, 1.0);
    let line = exported.find("id=\"line\"").expect("the line is kept");
    let tag = &exported[exported[..line].rfind('<').expect("its tag")..];
    let written =
        matrix_in(tag, "<path", "transform").expect("the line is drawn in its stroke frame");
    for (got, want) in written.as_coeffs().iter().zip(expected.as_coeffs()) {
        assert!(
            (got - want).abs() <= 1e-9 * 200.0,
            "{written:?} vs {expected:?}\n{exported}"
        );
    }
    // The frame turns under the bend (the element's own transform alone would not pass).
    assert!(frame.as_coeffs()[1].abs() > 1e-2, "{frame:?}");
}

/// Every handle of the plate turned by 30° about its centre: the skinning map is that
/// rotation everywhere (the weights sum to one), so the export's label `transform` and the
/// gradient copy's `gradientTransform` are exactly it (to rounding of the fit: 1e-12 of the
/// drawing's size), whereas the export without `rig=` (the request as it was) leaves both at
/// rest. Wrong bodies and ids are refused with a message.
#[tokio::test]
async fn serve_export_carries_gradients_and_text_with_the_rig_pose() {
    let app = app();
    let info = open_plate(&app).await;
    let id = info["id"].as_str().expect("id");
    let turn = kurbo::Affine::translate((100.0, 50.0))
        * kurbo::Affine::rotate(30f64.to_radians())
        * kurbo::Affine::translate((-100.0, -50.0));
    let scene = serde_json::json!({
        "document": id,
        "scene": {
            "handles": PLATE_HANDLES,
            "pose": vec![turn.as_coeffs(); 3],
            "weights": {"family": "shepard", "exponent": 2.0},
            "junctions": [],
            "flexible": false
        }
    });
    let (headers, _) = send_ok(&app, post_json("/api/rig", &scene)).await;
    let rig = rig_id(&headers);
    // The page's points: the rig operator times the pose; here the rotation of the rest points
    // (what that product gives under one map on every handle).
    let rest: Vec<Point> = info["rest"]
        .as_array()
        .expect("rest")
        .chunks_exact(2)
        .map(|c| Point::new(c[0].as_f64().unwrap(), c[1].as_f64().unwrap()))
        .collect();
    let points = le_bytes(rest.iter().flat_map(|&p| {
        let q = turn * p;
        [q.x, q.y]
    }));
    let pose = le_bytes((0..3).flat_map(|_| turn.as_coeffs()));
    let export = |query: String, body: Vec<u8>| {
        post(&format!("/api/documents/{id}/export{query}"))
            .body(Body::from(body))
            .expect("a request")
    };

    let with_pose = [points.clone(), pose.clone()].concat();
    let (_, body) = send_ok(&app, export(format!("?rig={rig}"), with_pose.clone())).await;
    let svg = String::from_utf8(body).expect("text");
    let text = matrix_in(&svg, "<text", "transform").expect("the label carries a transform");
    let gradient = matrix_in(
        &svg,
        "<linearGradient id=\"splineskin-g",
        "gradientTransform",
    )
    .expect("a copy of the gradient with the map");
    assert!(svg.contains("fill:url(#splineskin-g-"), "{svg}");
    for (what, map) in [("label", text), ("gradient", gradient)] {
        for (a, b) in map.as_coeffs().iter().zip(turn.as_coeffs()) {
            assert!((a - b).abs() < 1e-12 * 200.0, "{what}: {map:?} vs {turn:?}");
        }
    }
    let back = read_svg(&svg, &ImportOptions::default()).expect("the export reads back");
    assert_eq!(back.n_curves(), 4);

    // Without rig= the body is the points alone, and the label and gradient stay at rest.
    let (status, _, body) = send(&app, export(String::new(), points.clone())).await;
    assert_eq!(status, StatusCode::OK);
    let svg = String::from_utf8(body).expect("text");
    assert!(matrix_in(&svg, "<text", "transform").is_none(), "{svg}");
    assert!(!svg.contains("splineskin-g-"), "{svg}");

    // Refused: a pose of the wrong length, a pose without rig=, an unknown rig, both keys,
    // a rig of another document.
    let error = |body: &[u8]| json(body)["error"].as_str().expect("message").to_string();
    let (status, _, body) = send(
        &app,
        export(
            format!("?rig={rig}"),
            [points.clone(), vec![0; 48]].concat(),
        ),
    )
    .await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert!(
        error(&body).contains("48 bytes after the points (expected the pose: 144 bytes"),
        "{}",
        error(&body)
    );
    let (status, _, body) = send(&app, export(String::new(), with_pose.clone())).await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert!(
        error(&body).contains("needs rig= or defop="),
        "{}",
        error(&body)
    );
    let (status, _, body) = send(&app, export("?rig=r999".into(), with_pose.clone())).await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    assert!(error(&body).contains("rig r999"), "{}", error(&body));
    let (status, _, body) = send(
        &app,
        export(format!("?rig={rig}&defop=o1"), with_pose.clone()),
    )
    .await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert!(error(&body).contains("both given"), "{}", error(&body));
    let other = open_plate(&app).await;
    let other_id = other["id"].as_str().expect("id");
    let request = post(&format!("/api/documents/{other_id}/export?rig={rig}"))
        .body(Body::from(with_pose))
        .expect("a request");
    let (status, _, body) = send(&app, request).await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert!(
        error(&body).contains(&format!("was built on document {id}, not {other_id}")),
        "{}",
        error(&body)
    );
}

/// The scene that trains an ARAP operator (20 samples) for the plate's handles on document `id`.
fn plate_operator_scene(id: &str) -> serde_json::Value {
    serde_json::json!({
        "document": id,
        "scene": {
            "handles": PLATE_HANDLES,
            "pose": vec![[1.0, 0.0, 0.0, 1.0, 0.0, 0.0]; 3],
            "weights": {"family": "defop-arap", "samples": 20},
            "junctions": [],
            "flexible": false
        }
    })
}

/// The label's `transform` in document `id` exported with operator `op` at the configuration
/// `q` (the points the server's own deformation there, which the page's product equals).
async fn operator_label_transform(
    app: &Router,
    id: &str,
    op: &str,
    q: &[[f64; 2]],
) -> kurbo::Affine {
    let (_, points) = send_ok(app, operator_deform(op, q)).await;
    let body = [points, le_bytes(q.iter().flatten().copied())].concat();
    let request = post(&format!("/api/documents/{id}/export?defop={op}"))
        .body(Body::from(body))
        .expect("a request");
    let (_, body) = send_ok(app, request).await;
    let svg = String::from_utf8(body).expect("text");
    matrix_in(&svg, "<text", "transform").expect("the label carries a transform")
}

/// The plate through a trained operator (ARAP, few samples), every handle turned by 10°
/// about its centre: the export with `defop=` and the configuration `Q` carries the label by
/// the operator's deformation, which reproduces that rigid motion to its training error.
#[tokio::test]
async fn serve_export_carries_text_with_the_operator() {
    let app = app();
    let info = open_plate(&app).await;
    let id = info["id"].as_str().expect("id");
    let (defop_info, _) = train(&app, &plate_operator_scene(id)).await;
    let op = defop_info["id"].as_str().expect("id");
    let turn = kurbo::Affine::translate((100.0, 50.0))
        * kurbo::Affine::rotate(10f64.to_radians())
        * kurbo::Affine::translate((-100.0, -50.0));
    let q: Vec<[f64; 2]> = PLATE_HANDLES
        .iter()
        .map(|&[x, y]| {
            let p = turn * Point::new(x, y);
            [p.x, p.y]
        })
        .collect();
    // The points: the server's own deformation at Q (the page's product equals it).
    let text = operator_label_transform(&app, id, op, &q).await;
    // Over the label (x 70–125, y 44–64): within 0.5 units of the rotation (a quarter of a
    // percent of the plate's diagonal; measured 0.19); left at rest it would be up to 5.8
    // units off.
    let (mut worst, mut at_rest) = (0.0f64, 0.0f64);
    for x in [70.0, 100.0, 125.0] {
        for y in [44.0, 64.0] {
            let p = Point::new(x, y);
            worst = worst.max((text * p - turn * p).hypot());
            at_rest = at_rest.max((turn * p - p).hypot());
        }
    }
    assert!(at_rest > 4.0, "the rotation moves the label: {at_rest}");
    assert!(worst < 0.5, "the label is {worst} from the rotation");
}

/// The operator's carry operator (`GET /api/defops/{id}/carry`) gives, at a bend of the
/// labelled plate, the map Export SVG with `defop=` writes on the label (`P⁻¹ A P`), to
/// rounding: the page moves text with the operator's art as the export does.
#[tokio::test]
async fn serve_operator_carry_gives_the_exported_label_map() {
    let app = app();
    let info = open_file(&app, "labelled.svg", LABELLED_PLATE_SVG).await;
    let id = info["id"].as_str().expect("id");
    let parent = kurbo::Affine::translate((10.0, 5.0)) * kurbo::Affine::rotate(10f64.to_radians());
    let (op_info, op_body) = train(&app, &plate_operator_scene(id)).await;
    let op = op_info["id"].as_str().expect("id");
    let q = [
        [PLATE_HANDLES[0][0], PLATE_HANDLES[0][1]],
        [PLATE_HANDLES[1][0] + 6.0, PLATE_HANDLES[1][1] - 9.0],
        [PLATE_HANDLES[2][0], PLATE_HANDLES[2][1] + 7.0],
    ];
    let psi = operator_psi(&op_info, &f64s(&op_body), &q);
    let (_, body) = send_ok(&app, get(&format!("/api/defops/{op}/carry"))).await;
    let carry = f64s(&body);
    let width = psi.len() + 1;
    assert_eq!(carry.len(), 6 * width, "one carried label");
    let x: Vec<f64> = psi.iter().copied().chain([1.0]).collect();
    let a = kurbo::Affine::new(std::array::from_fn(|r| {
        (0..width).map(|c| carry[r * width + c] * x[c]).sum::<f64>()
    }));
    let expected = parent.inverse() * a * parent;
    let written = operator_label_transform(&app, id, op, &q).await;
    for (got, want) in written.as_coeffs().iter().zip(expected.as_coeffs()) {
        assert!(
            (got - want).abs() <= 1e-9 * 200.0,
            "{written:?} vs {expected:?}"
        );
    }
    // The label does move under the bend (a map left at rest would not pass the above).
    let moved = (a * Point::new(60.0, 40.0) - Point::new(60.0, 40.0)).hypot();
    assert!(moved > 1.0, "{a:?}");
}

/// The page's `scene` on document `id` as "Save scene" writes it, read back by the library.
async fn saved_scene(
    app: &Router,
    id: &str,
    scene: &serde_json::Value,
) -> splineskin::scene::Scene {
    let uri = format!("/api/documents/{id}/scene");
    let (_, saved) = send_ok(app, post_json(&uri, scene)).await;
    let text = std::str::from_utf8(&saved).expect("text");
    splineskin::scene::Scene::from_json(text, "fish drawing.svg", None).expect("it reads")
}

#[tokio::test]
async fn serve_lottie_plays_the_page_timeline_as_animate_does() {
    let (app, _, id) = demo_app().await;
    let mut scene = two_handle_scene(&id, false)["scene"].clone();
    let uri = format!("/api/documents/{id}/lottie");
    // No timeline: refused, saying what to do.
    let message = bad_request(&app, post_json(&uri, &scene)).await;
    assert!(message.contains("no keyframes"), "{message}");
    let identity = [1.0, 0.0, 0.0, 1.0, 0.0, 0.0];
    let turned = [0.0, 1.0, -1.0, 0.0, 315.0, 95.0];
    scene["animation"] = serde_json::json!({"fps": 10.0, "keyframes": [
        {"time": 0.0, "pose": [identity, identity], "easing": "ease-in-out"},
        {"time": 1.0, "pose": [identity, turned]}
    ]});
    let (headers, body) = send_ok(&app, post_json(&uri, &scene)).await;
    let report = json(headers[splineskin_editor::document_routes::LOTTIE_HEADER].as_bytes());
    let lottie = json(&body);
    assert_eq!(lottie["fr"], 10.0);
    assert_eq!(lottie["op"], 10.0, "1 s at 10 fps: frames 0 … 10");
    assert!(lottie["layers"].as_array().is_some_and(|l| !l.is_empty()));
    assert_eq!(report["bytes"], body.len());
    let (k, every) = (
        report["keyframes"].as_u64().unwrap(),
        report["every_frame_keyframes"].as_u64().unwrap(),
    );
    assert!(0 < k && k <= every, "{k} of {every}");
    assert!(report["summary"]
        .as_str()
        .is_some_and(|s| s.contains("× 11 frames")));
    // The same file as the command writes from the saved scene.
    let read = saved_scene(&app, &id, &scene).await;
    let options = splineskin::drawing::lottie::LottieOptions::default().with_name("fish drawing");
    let made = splineskin::scene_animation::lottie_of_scene(
        &read,
        read.animation.as_ref().expect("animation"),
        splineskin::scene::PoseOptions::default(),
        &options,
        "saved",
    )
    .expect("the command's Lottie");
    assert_eq!(made.lottie.json.as_bytes(), &body[..]);
    // An operator family is refused with a message.
    scene["weights"] = serde_json::json!({"family": "defop-arap", "samples": 10});
    let message = bad_request(&app, post_json(&uri, &scene)).await;
    assert!(message.contains("pick a weight family"), "{message}");
}

/// `POST /api/documents/{id}/animation` writes the GIF and animated SVG the library's
/// [`SceneFrames`](splineskin::scene_animation::SceneFrames) writes of the saved scene (what
/// `animate` writes), and refuses an unknown format, a bad viewbox and a timeline without
/// keyframes with messages.
#[tokio::test]
async fn serve_animation_writes_what_animate_writes() {
    use splineskin::drawing::animated_image::AnimatedFormat;
    use splineskin::drawing::svg_out::ViewBoxRule;
    use splineskin::scene_animation::{AnimationRig, ANIMATED_IMAGE_SIZE};
    let (app, _, id) = demo_app().await;
    let mut scene = two_handle_scene(&id, false)["scene"].clone();
    let uri = |query: &str| format!("/api/documents/{id}/animation?{query}");
    let message = bad_request(&app, post_json(&uri("format=gif"), &scene)).await;
    assert!(message.contains("no keyframes"), "{message}");
    let identity = [1.0, 0.0, 0.0, 1.0, 0.0, 0.0];
    let moved = [1.0, 0.0, 0.0, 1.0, 30.0, -20.0];
    scene["animation"] = serde_json::json!({"fps": 4.0, "keyframes": [
        {"time": 0.0, "pose": [identity, identity]},
        {"time": 1.0, "pose": [identity, moved]}
    ]});
    let message = bad_request(&app, post_json(&uri("format=webm"), &scene)).await;
    assert!(message.contains("expected svg, gif or apng"), "{message}");
    let message = bad_request(&app, post_json(&uri("format=gif&viewbox=all"), &scene)).await;
    assert!(message.contains("expected keep or fit"), "{message}");
    let (_, gif) = send_ok(&app, post_json(&uri("format=gif"), &scene)).await;
    let (_, svg) = send_ok(&app, post_json(&uri("format=svg&viewbox=fit"), &scene)).await;
    // What the library writes of the saved scene, as animate does.
    let read = saved_scene(&app, &id, &scene).await;
    let animation = read.animation.clone().expect("animation");
    let rig = AnimationRig::of_scene(&read, &animation, Default::default(), "saved").expect("rig");
    let frames = rig.frames();
    let expected = frames
        .animated_image(
            AnimatedFormat::Gif,
            ANIMATED_IMAGE_SIZE,
            ViewBoxRule::Keep,
            |_, _, _| {},
        )
        .expect("the GIF");
    assert!(gif.starts_with(b"GIF89a"));
    assert!(gif == expected, "the route's GIF is the library's");
    let expected = frames.animated_svg(true, |_, _| {}).expect("the SVG");
    assert_eq!(String::from_utf8(svg).expect("text"), expected);
}

#[tokio::test]
async fn serve_mesh_is_the_weights_domain_with_weights_at_its_vertices() {
    let (app, _, id) = demo_app().await;
    // Inverse-distance weights have no mesh: said so.
    let (_, headers, _) = send(&app, post_json("/api/rig", &two_handle_scene(&id, false))).await;
    let rig = rig_id(&headers);
    let message = bad_request(&app, get(&format!("/api/rigs/{rig}/mesh"))).await;
    assert!(message.contains("have no mesh"), "{message}");
    // Harmonic weights are solved on one: a valid triangulation, weights summing to 1 and 1 at
    // each handle's vertex (the handles are vertices of the domain).
    let mut scene = two_handle_scene(&id, false);
    scene["scene"]["weights"] = serde_json::json!({"family": "harmonic"});
    let (_, headers, _) = send(&app, post_json("/api/rig", &scene)).await;
    let rig = rig_id(&headers);
    let (_, body) = send_ok(&app, get(&format!("/api/rigs/{rig}/mesh"))).await;
    let mesh = json(&body);
    let numbers = |key: &str| -> Vec<f64> {
        mesh[key]
            .as_array()
            .expect(key)
            .iter()
            .map(|v| v.as_f64().expect("a number"))
            .collect()
    };
    let (vertices, triangles, weights) = (
        numbers("vertices"),
        numbers("triangles"),
        numbers("weights"),
    );
    let n_vertices = vertices.len() / 2;
    assert_eq!(mesh["n_handles"], 2);
    assert!(n_vertices > 100 && triangles.len() > 100 && triangles.len() % 3 == 0);
    assert!(triangles.iter().all(|&i| (i as usize) < n_vertices));
    assert_eq!(weights.len(), 2 * n_vertices);
    for v in 0..n_vertices {
        let sum = weights[2 * v] + weights[2 * v + 1];
        assert!((sum - 1.0).abs() < 1e-5, "vertex {v}: weights sum to {sum}");
    }
    for (h, [x, y]) in [[440.0, 200.0], [110.0, 205.0]].into_iter().enumerate() {
        let v = (0..n_vertices)
            .find(|&v| vertices[2 * v] == x && vertices[2 * v + 1] == y)
            .expect("the handle is a vertex");
        assert!((weights[2 * v + h] - 1.0).abs() < 1e-6, "handle {h}");
    }
}

/// The page's quick preview of a mesh family (`weights.coarse`): the same family on a coarse
/// triangulation of the same art-shaped domain, eight times fewer vertices or more; refused for
/// weights without a mesh.
#[tokio::test]
async fn serve_coarse_preview_is_the_family_on_a_coarser_mesh_of_the_same_domain() {
    let (app, _, id) = demo_app().await;
    let mesh_of = |scene: serde_json::Value| {
        let app = app.clone();
        async move {
            let (_, headers, _) = send(&app, post_json("/api/rig", &scene)).await;
            let rig = rig_id(&headers);
            let (_, body) = send_ok(&app, get(&format!("/api/rigs/{rig}/mesh"))).await;
            json(&body)
        }
    };
    let mut exact = two_handle_scene(&id, false);
    exact["scene"]["weights"] = serde_json::json!({"family": "bbw"});
    let mut coarse = exact.clone();
    coarse["scene"]["weights"]["coarse"] = serde_json::json!(true);
    let (fine, quick) = (mesh_of(exact).await, mesh_of(coarse).await);
    let n = |m: &serde_json::Value| m["vertices"].as_array().expect("vertices").len() / 2;
    assert!(
        n(&quick) * 8 < n(&fine),
        "coarse {} vs exact {} vertices",
        n(&quick),
        n(&fine)
    );
    assert_eq!(quick["boundary"], fine["boundary"]);
    assert!(
        quick["boundary"]
            .as_str()
            .expect("text")
            .starts_with("the art"),
        "{}",
        quick["boundary"]
    );
    // Inverse-distance weights have no mesh to coarsen.
    let mut shepard = two_handle_scene(&id, false);
    shepard["scene"]["weights"]["coarse"] = serde_json::json!(true);
    let message = bad_request(&app, post_json("/api/rig", &shepard)).await;
    assert!(message.contains("weights.coarse"), "{message}");
}

#[test]
fn static_build_marks_its_page_carries_the_module_and_replaces_only_its_own_folder() {
    let tmp = tempfile::tempdir().expect("a temporary folder");
    let wasm = tmp.path().join("module.wasm");
    std::fs::write(&wasm, b"\0asm\x01\0\0\0").expect("written");
    let threads = tmp.path().join("threads.wasm");
    std::fs::write(&threads, b"\0asm\x01\0\0\x01").expect("written");
    let dir = tmp.path().join("site");
    super::write_static(&dir, Some(&wasm), Some(&threads)).expect("written");
    let html = std::fs::read_to_string(dir.join("index.html")).expect("index.html");
    assert!(
        html.contains("<html lang=\"en\" data-backend=\"wasm\">"),
        "{html}"
    );
    assert!(
        html.contains("'wasm-unsafe-eval'"),
        "a policy allowing the module"
    );
    for name in [
        "splineskin.wasm",
        "editor-worker.js",
        "wasm-editor.js",
        "backend.js",
        "splineskin.js",
        "splineskin.d.ts",
        "example.html",
        "example-node.mjs",
        "demo.svg",
    ] {
        assert!(dir.join(name).is_file(), "{name} written");
    }
    assert_eq!(
        std::fs::read(dir.join("splineskin.wasm")).expect("module"),
        b"\0asm\x01\0\0\0"
    );
    assert_eq!(
        std::fs::read(dir.join("splineskin-threads.wasm")).expect("threaded module"),
        b"\0asm\x01\0\0\x01"
    );
    let headers = std::fs::read_to_string(dir.join("_headers")).expect("_headers");
    assert!(
        headers.starts_with("/*\n")
            && headers.contains("  cross-origin-opener-policy: same-origin\n")
            && headers.contains("  cross-origin-embedder-policy: require-corp\n"),
        "{headers}"
    );
    // An earlier build is replaced (its threaded module too, by a build without one); another
    // folder is refused; so is a file that is no module.
    super::write_static(&dir, Some(&wasm), None).expect("an earlier build replaced");
    assert!(
        !dir.join("splineskin-threads.wasm").exists(),
        "the earlier threaded module removed"
    );
    let other = tmp.path().join("other");
    std::fs::create_dir(&other).expect("created");
    std::fs::write(other.join("notes.txt"), "mine").expect("written");
    let message = super::write_static(&other, Some(&wasm), None)
        .expect_err("refused")
        .to_string();
    assert!(message.contains("not a static build"), "{message}");
    assert_eq!(
        std::fs::read_to_string(other.join("notes.txt")).expect("kept"),
        "mine"
    );
    let text = tmp.path().join("text.wasm");
    std::fs::write(&text, "hello").expect("written");
    let message = super::write_static(&tmp.path().join("new"), Some(&text), None)
        .expect_err("refused")
        .to_string();
    assert!(message.contains("not a WebAssembly module"), "{message}");
    assert!(!tmp.path().join("new").exists(), "nothing written");
}

/// The page's `constants.js` is what `splineskin_editor::page_constants` generates from the Rust
/// values (`SPLINESKIN_WRITE_CONSTANTS=1` writes it again instead of comparing).
#[test]
fn page_constants_file_is_generated_from_rust() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/web/constants.js");
    let generated = splineskin_editor::page_constants::javascript();
    if std::env::var_os("SPLINESKIN_WRITE_CONSTANTS").is_some() {
        std::fs::write(path, &generated).expect("write web/constants.js");
    }
    let on_disk = std::fs::read_to_string(path).unwrap_or_default();
    assert!(
        on_disk == generated,
        "{path} is not what splineskin_editor::page_constants generates: \
         SPLINESKIN_WRITE_CONSTANTS=1 cargo test -p splineskin-cli page_constants writes it again"
    );
}

/// A rig of an opened document does not read its drawing again: the drawing read when the
/// document was opened is the scene's (one reading per request before).
#[test]
fn a_rig_request_does_not_read_the_drawing_again() {
    let editor = splineskin_editor::Editor::new(Some(Document::bundled().expect("the fish")));
    let initial = editor.handle(&splineskin_editor::Request::get("/api/initial"));
    let info = json(&initial.body);
    let body = serde_json::json!({
        "document": info["id"],
        "scene": {
            "handles": [[440, 215], [150, 210], [300, 250]],
            "pose": [[1, 0, 0, 1, 0, 0], [1, 0, 0, 1, 0, 0], [1, 0, 0, 1, 0, 0]],
            "weights": {"family": "shepard"},
            "junctions": [],
            "flexible": false
        }
    });
    let request =
        splineskin_editor::Request::post("/api/rig", body.to_string()).with_header(API_HEADER, "1");
    let (response, readings) = crate::test_support::svg_readings(|| editor.handle(&request));
    assert_eq!(
        response.status,
        200,
        "{}",
        String::from_utf8_lossy(&response.body)
    );
    assert_eq!(readings, 0, "SVG readings during the rig request");
}

/// Opening an SVG document or a scene reads the drawing once: the editor's document is made of
/// the drawing it read, with no scene file written and read back in between (an SVG was read
/// twice before).
#[test]
fn opening_a_drawing_or_a_scene_reads_the_drawing_once() {
    let (document, readings) =
        crate::test_support::svg_readings(|| Document::from_svg("fish.svg", DEMO_SVG));
    let document = document.expect("the fish opens");
    assert_eq!(document.drawing.n_curves(), 58);
    assert_eq!(readings, 1, "SVG readings while opening the drawing");
    let scene = splineskin::examples::demo_scene();
    let (document, readings) =
        crate::test_support::svg_readings(|| Document::from_scene(scene, "demo-scene.json"));
    let document = document.expect("the scene opens");
    assert_eq!(document.drawing.n_curves(), 58);
    assert_eq!(readings, 1, "SVG readings while opening the scene");
}
