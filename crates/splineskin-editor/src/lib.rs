//! The splineskin editor's work, whatever carries its page's requests.
//!
//! The page (`crates/splineskin-cli/web/`) asks for everything it does not compute itself —
//! opening a drawing, weights and the rig's operator, flexible G¹ solves, weight grids,
//! exports — by requests to routes under `/api/`. [`Editor::handle`] answers them: `splineskin
//! serve` carries them over HTTP (its server adds the transport's guards and runs heavy
//! requests on worker threads, [`Editor::is_heavy`]), and the WebAssembly build answers the
//! same requests inside the page, in a Web Worker, with no server at all.
//!
//! ```text
//! page ── Request {method, path, query, headers, body} ──► Editor::handle ──► Response
//!          (HTTP: splineskin serve │ postMessage: a Web Worker running splineskin-wasm)
//! ```
//!
//! | route | request | response |
//! |---|---|---|
//! | `GET /`, `GET /{*path}` | | the page and its assets (served by `splineskin serve`, not by this crate) |
//! | `GET /api/initial` | | the drawing given on the command line, [`DocumentInfo`](wire::DocumentInfo) |
//! | `POST /api/open` | the file's bytes (SVG or scene), `x-file-name` header | [`DocumentInfo`](wire::DocumentInfo) |
//! | `POST /api/weights/columns` | [`ColumnsRequest`](wire::ColumnsRequest) `{"document", "scene", "columns": [j, …]}` (weights `bbw`) | [`SolvedColumns`](splineskin::scene::SolvedColumns) JSON `{"n_vertices", "columns", "values"}`: those raw bounded biharmonic columns on the scene's domain, for `POST /api/rig`'s `solved` (the static editor solves a rig's columns in several workers) |
//! | `POST /api/rig` | [`RigRequest`](wire::RigRequest) `{"document", "scene"[, "solved"]}` | the operator `O`, `f64` LE row-major `(2 · n_points) × (6 · n_handles)`; header `x-splineskin-rig`: the rig's id |
//! | `POST /api/rigs/{id}/solve` | [`PoseRequest`](wire::PoseRequest) | deformed points, `f64` LE `x0, y0, x1, y1, …` (flexible G¹ when the scene asks, warm-started from the previous solve) |
//! | `POST /api/defop` | [`SceneRequest`](wire::SceneRequest) with family `defop-arap` or `defop-sarap` (`weights.samples`: training samples) | `G_spline` `f64` LE row-major `(2 · n_points) × |Ψ|`, then the thin-plate centres `f64` LE row-major `n_centres × 2 · n_handles` (scaled displacements `z_k`); header `x-splineskin-defop`: [`DefOpInfo`](crate::defop_routes::DefOpInfo) JSON (id, handle basis kind, scale, rest handles `P`, sizes, seconds). Per frame `points = G_spline · ψ(Q)`, `ψ = (1, z, φ(‖z − z_k‖)…)`, `z = (Q − P)/scale`, `φ(r) = r² log r` (`splineskin::defop::HandleBasis`) |
//! | `GET /api/defops/{id}/carry` | | the operator's carry operator: per carried text or image, then per element with its own paint or a stroke frame, its best-fit map's six coefficients as rows of `|Ψ| + 1` f64 (the handle functions `ψ(Q)`, a constant), as `GET /api/rigs/{id}/carry` for a rig (`crate::defop_routes::carry`) |
//! | `POST /api/defops/{id}/deform` | [`DeformRequest`](crate::defop_routes::DeformRequest) `{"handles": [[x, y], …]}` (the configuration `Q`) | the library's deformation at `Q`, `f64` LE `x0, y0, x1, y1, …` (the page's product is checked against it) |
//! | `POST /api/defops/{id}/follow` | `{"handles": [[x, y], …], "settle": bool}` (the configuration the user dragged to; `settle` on release) | outside the trained region, a new operator trained with samples there, laid out as `POST /api/defop` answers (its header too); inside, JSON `{"followed": false, "reason", "distance", "reach"}` (`crate::defop_routes::follow`) |
//! | `GET /api/progress/{job}` | | the stage of the precomputation whose request carried `x-splineskin-job: {job}`: `{"stage": "queued" \| "weights" \| "rig" \| "domain" \| "training" \| "join", "seconds": …}` (seconds in that stage), with `"done", "total", "step", "steps"` while training (ground-truth solves done of all, bootstrapping stage of all), or `{"stage": null}` when none runs |
//! | `POST /api/progress/{job}/stop` | | asks that precomputation to stop: a training ends at its next ground-truth solve, bounded biharmonic weights at their next active-set iteration, and its request answers 409; `{"stopping": true}`, or 404 when no such job runs |
//! | `GET /api/rigs/{id}/weights?handle&x0&y0&x1&y1&width&height` | | handle's weight at the centres of a `width × height` grid over the box, `f32` LE, row by row from `y0` |
//! | `GET /api/rigs/{id}/operator` | | the rig's operator `O`, as `POST /api/rig` answers it |
//! | `GET /api/rigs/{id}/carry` | | the rig's carry operator: per carried text or image, then per element of `DocumentInfo::painted` (its own paint copies or a stroke frame), its best-fit map's six coefficients as rows of `6h + 1` f64 (pose, constant) |
//! | `POST /api/rigs/{id}/refine` | [`RefineRequest`](wire::RefineRequest) `{"scene", "poses": [[[a…f], …], …], "tolerance"}` | [`RefineAnswer`](wire::RefineAnswer): with anchors inserted (adaptive control points, `splineskin::adaptive`), the refined drawing as a new document and its rig (the same weights); else how far the fit is |
//! | `GET /api/rigs/{id}/mesh` | | [`MeshWire`](crate::rig_routes::MeshWire): the triangulated domain the weights were solved on and every handle's weight at its vertices (mesh families; 400 for closed-form weights) |
//! | `POST /api/documents/{id}/export?viewbox=keep\|fit[&rig={id}\|&defop={id}]` | deformed points, `f64` LE, then with `rig` the pose (`a…f` per handle) or with `defop` the configuration `Q` (`x, y` per handle), `f64` LE ([`ExportQuery`](crate::wire::ExportQuery)) | the SVG document with them ([`write_svg_with`](splineskin::drawing::svg_out::write_svg_with)): gradients, patterns, markers, text and images carried by the best-fit affine map of the rig's skinning map or the operator's deformation (at rest without either); `fit` grows the viewBox to include the art, `keep` (default) leaves it |
//! | `POST /api/documents/{id}/outside` | deformed points, `f64` LE | [`ViewBoxReport`](crate::wire::ViewBoxReport): the paths that leave the viewBox, how far, and the viewBox `fit` writes |
//! | `POST /api/documents/{id}/pins` | [`PinsRequest`](wire::PinsRequest) | `{"pins": [[x, y], …]}`: the page's pins first, then pins placed over the art as `splineskin rig` places them ([`place_pins`](splineskin::scene::place_pins)), at most [`MAX_AUTO_PINS`](crate::document_routes::MAX_AUTO_PINS) when the page has fewer |
//! | `POST /api/documents/{id}/scene` | [`EditScene`](wire::EditScene) | the scene file (ours, drawing inline) |
//! | `POST /api/documents/{id}/animation?format=svg\|gif\|apng[&viewbox=keep\|fit]` | [`EditScene`](wire::EditScene) with an `animation` | what `splineskin animate SCENE -o anim.svg\|anim.gif\|anim.png` writes of it (the animated SVG, or every frame rendered 480 pixels on its longer side into a GIF or APNG); header `x-splineskin-warning` when a build without fonts leaves text out |
//! | `POST /api/subdiv/open?level=K` | an OBJ cage's text, `x-file-name` header | [`CageWire`](subdiv_routes::CageWire): the cage, its wireframe, and its limit surface at level `K` as triangles and limit stencils over the cage vertices (the Catmull–Clark page, `web/subdiv/`) |
//! | `POST /api/subdiv/rig` | [`RigWireRequest`](subdiv_routes::RigWireRequest) `{"name", "obj", "level"?, "scene": {handles, bones, weights, …}}` | [`RigWire`](subdiv_routes::RigWire): the rig's factors `B_i[v]` (fitted cage `c'_v = Σ_i T_i · B_i[v]`) and every handle's weight at the surface vertices of the level |
//! | `POST /api/subdiv/export?format=usda\|glb\|obj[&up=y\|z]` | as `POST /api/subdiv/rig`, the scene with `poses` or an `animation` | the file `splineskin subdiv animate` writes of the animation, or of pose 0 as one frame (`obj`: the fitted cage `subdiv deform` writes) |
//! | `POST /api/documents/{id}/lottie` | [`EditScene`](wire::EditScene) with an `animation` | the Lottie animation `splineskin animate SCENE -o anim.json` writes of it; header `x-splineskin-lottie`: [`LottieReport`](crate::document_routes::LottieReport) JSON (keyframes and bytes written and with every frame, warnings) |
//!
//! Errors are JSON [`ErrorBody`](wire::ErrorBody) `{"error": "…"}` naming the file and element
//! concerned, with status 400 (bad input), 404 (no such document or rig: dropped,
//! [`store`]), 413 (too large), 422 (a request of the wrong shape) or 500 (a bug). Over HTTP,
//! every `POST` must carry the header `x-splineskin: 1`, which a page of another site cannot
//! send without a CORS preflight the server never grants; on loopback, requests whose `Host`
//! is not the server's own are refused (DNS rebinding).
//!
//! Modules, from the top: [`routes`] (the dispatch, [`Editor::handle`]), [`document_routes`],
//! [`rig_routes`] and [`defop_routes`] (the routes), [`editor`] (the editor's state),
//! [`request`] (requests, responses, errors, limits), [`document`] (an opened drawing),
//! [`store`] (documents and rigs by id, bounded), [`progress`] (stages of running
//! precomputations), [`wire`] (JSON exchanged with the page), [`page_scene`] (the page's scene
//! as a scene file of ours), [`page_constants`] (the names and limits the page imports, written
//! as `web/constants.js`).
//!
//! ```
//! use splineskin_editor::{document::Document, Editor, Request};
//! let editor = Editor::new(Some(Document::bundled()?));
//! let response = editor.handle(&Request::get("/api/initial"));
//! assert_eq!(response.status, 200);
//! let info: serde_json::Value = serde_json::from_slice(&response.body)?;
//! assert!(!info["rest"].as_array().expect("rest points").is_empty());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod defop_routes;
pub mod document;
pub mod document_routes;
pub mod editor;
pub mod page_constants;
pub mod page_scene;
pub mod progress;
pub mod request;
pub mod rig_routes;
pub mod routes;
pub mod store;
pub mod subdiv_routes;
pub mod wire;

pub use editor::Editor;
pub use request::{error_message, ApiError, Request, Response};
