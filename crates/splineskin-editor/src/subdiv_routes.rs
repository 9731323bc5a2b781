//! The Catmull–Clark page's routes (`web/subdiv/`): an OBJ cage opened, and what the page needs
//! to draw its limit surface at any cage positions without asking again.
//!
//! `POST /api/subdiv/open?level=K` answers [`CageWire`]: the cage (positions, faces, edges for
//! its wireframe) and the limit surface sampled at level `K` ([`LimitMesh`]: `(2^K)²` quads per
//! cage quad) as triangles and **limit stencils**: each surface vertex `s_m = Σ_j w_mj c_j`, a
//! sparse row over the cage vertices `c_j` (the page's per-frame tessellation is that sparse
//! product, then the normals).
//!
//! `POST /api/subdiv/rig` ([`RigWireRequest`]: the OBJ text and the handles and weights of a
//! subdivision scene) answers [`RigWire`]: the rig's factors `B_i[v]` (the fitted cage is
//! `c'_v = Σ_i T_i · B_i[v]` for 3 × 4 maps `T_i`, [`SubdivRig`]), so the page's per-frame
//! update is that small product, every handle's weight at the surface vertices of level `K`
//! (to paint them, and for the skinned surface the fit is measured against) and at the cage
//! vertices (the naive method skins them).
//!
//! `POST /api/subdiv/export?format=usda|glb|obj` takes the same body (with the scene's poses or
//! animation) and answers the file `splineskin subdiv animate` (or, for one pose, `subdiv
//! deform`) writes of it.

use serde::{Deserialize, Serialize};
use splineskin::animation::DEFAULT_FPS;
use splineskin::subdiv::handoff::{FittedAnimation, UpAxis};
use splineskin::subdiv::surface_weights::{cage_weights, sample_weights};
use splineskin::subdiv::{
    parse_obj, to_obj_string, LimitMesh, LimitOptions, LimitSurface, SubdivRig, SubdivScene,
    SubdivSetup, MAX_LIMIT_MESH_LEVEL,
};

use crate::editor::Editor;
use crate::request::{ApiError, Request, Response};

/// Tessellation level when the page does not say, at most: 3 (64 quads per cage quad).
pub const DEFAULT_PAGE_LEVEL: usize = 3;

/// Quads of the page's limit surface a cage opened without a level gets at most: 32 768. The
/// page tessellates them every frame (about 10 ms for 50 000 quads in headless chromium's
/// software-rendered page, measured on OpenSubdiv's bishop refined once); a dense cage gets a
/// lower level ([`page_level`]) rather than a million triangles.
pub const PAGE_QUAD_BUDGET: usize = 1 << 15;

/// The level of the surface the page gets for a cage of `n_faces` faces when it does not ask
/// for one: the finest up to [`DEFAULT_PAGE_LEVEL`] whose `n_faces · 4^level` quads fit
/// [`PAGE_QUAD_BUDGET`], and level 1 at least.
///
/// ```
/// use splineskin_editor::subdiv_routes::page_level;
/// assert_eq!(page_level(66), 3); // the bundled tube: 4 224 quads
/// assert_eq!(page_level(6_396), 1); // OpenSubdiv's car refined once: 25 584 quads
/// assert_eq!(page_level(1_000), 2); // 16 000 quads
/// assert_eq!(page_level(1_000_000), 1);
/// ```
pub fn page_level(n_faces: usize) -> usize {
    (1..=DEFAULT_PAGE_LEVEL)
        .rev()
        .find(|&level| n_faces.saturating_mul(1 << (2 * level)) <= PAGE_QUAD_BUDGET)
        .unwrap_or(1)
}

/// The query of `POST /api/subdiv/open`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OpenQuery {
    /// Tessellation level, 1 ..= [`MAX_LIMIT_MESH_LEVEL`] (default [`page_level`] of the
    /// cage's faces).
    #[serde(default)]
    pub level: Option<usize>,
}

/// An opened cage and its sampled limit surface (module documentation).
#[derive(Serialize, Deserialize, Debug)]
pub struct CageWire {
    /// The file's name.
    pub name: String,
    /// Cage vertex positions, `x, y, z` flat.
    pub positions: Vec<f64>,
    /// Vertex counts of the faces, in order.
    pub face_sizes: Vec<u32>,
    /// The faces' vertices, face after face.
    pub face_vertices: Vec<u32>,
    /// Every edge of the faces once, `a, b` flat (the cage's wireframe).
    pub edges: Vec<u32>,
    /// The bounding box's diagonal.
    pub diagonal: f64,
    /// Tags: creases, corners, holes.
    pub n_tags: [usize; 3],
    /// The sampled limit surface.
    pub surface: SurfaceWire,
}

/// The limit surface at a level: its triangles and the stencils of its vertices.
#[derive(Serialize, Deserialize, Debug)]
pub struct SurfaceWire {
    /// The level.
    pub level: usize,
    /// Number of surface vertices.
    pub n_vertices: usize,
    /// Triangles, `a, b, c` flat, counter-clockwise seen from outside.
    pub triangles: Vec<u32>,
    /// Stencil `m` spans `offsets[m] .. offsets[m + 1]` of `indices` and `weights`.
    pub offsets: Vec<u32>,
    /// Cage vertices of the stencils.
    pub indices: Vec<u32>,
    /// Their weights.
    pub weights: Vec<f64>,
}

/// `POST /api/subdiv/rig`: a cage, its handles and weights (module documentation).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RigWireRequest {
    /// The OBJ file's name (for messages).
    pub name: String,
    /// The OBJ text.
    pub obj: String,
    /// Level of the surface the weights are sampled at (as `POST /api/subdiv/open` was asked).
    #[serde(default)]
    pub level: Option<usize>,
    /// A subdivision scene's `handles`, `bones`, `weights` and `quadrature`, as scene files
    /// write them (`splineskin::subdiv::scene`), without `obj`.
    pub scene: serde_json::Map<String, serde_json::Value>,
}

/// The answer of `POST /api/subdiv/rig` (module documentation).
#[derive(Serialize, Deserialize, Debug)]
pub struct RigWire {
    /// Cage vertices.
    pub n_vertices: usize,
    /// Handles (points, then bones).
    pub n_handles: usize,
    /// `B_i[v]`, four numbers each, vertex-major then handle (`[(v · h + i) · 4 + c]`).
    pub coefficients: Vec<f64>,
    /// Every handle's weight at every surface vertex of the level, vertex-major
    /// (`[m · h + i]`).
    pub surface_weights: Vec<f64>,
    /// Every handle's weight at every cage vertex, vertex-major: what the naive method (skin the
    /// cage, then subdivide) skins each vertex with.
    pub cage_weights: Vec<f64>,
    /// Seconds the weights and the rig took.
    pub seconds: f64,
}

/// `POST /api/subdiv/rig`. Timed with the editor's clock (WebAssembly has no
/// `std::time::Instant`).
pub(crate) fn rig(editor: &Editor, request: &Request) -> Result<Response, ApiError> {
    let clock = editor.progress.clock();
    let start = clock();
    let rigged = Rigged::of(request)?;
    let (name, setup) = (&rigged.name, &rigged.setup);
    let fail = |e: &dyn std::fmt::Display| ApiError::new(400, format!("{name}: {e}"));
    let surface = setup.full_surface().map_err(|e| fail(&e))?;
    let mesh = LimitMesh::new(&setup.cage, &surface, rigged.level).map_err(|e| fail(&e))?;
    let surface_weights =
        sample_weights(setup.weights.as_ref(), &setup.cage, &mesh).map_err(|e| fail(&e))?;
    let cage_weights = cage_weights(setup.weights.as_ref(), &setup.cage).map_err(|e| fail(&e))?;
    Response::json(&RigWire {
        n_vertices: setup.rig.n_vertices(),
        n_handles: setup.rig.n_handles(),
        coefficients: coefficients(&setup.rig),
        surface_weights,
        cage_weights,
        seconds: clock() - start,
    })
}

/// The query of `POST /api/subdiv/export`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExportQuery {
    /// `usda`, `glb` or `obj`.
    pub format: String,
    /// `y` (default) or `z`: the model's up axis.
    #[serde(default)]
    pub up: Option<String>,
}

/// `POST /api/subdiv/export?format=usda|glb|obj[&up=y|z]`: the body as `POST /api/subdiv/rig`
/// takes it; the scene's animation as `splineskin subdiv animate` writes it, or without one its
/// pose 0 as one frame (`obj`: the fitted cage of pose 0, as `subdiv deform` writes it).
pub(crate) fn export(request: &Request) -> Result<Response, ApiError> {
    let query: ExportQuery = request.query("subdiv/export")?;
    let up = match query.up.as_deref() {
        None | Some("y") => UpAxis::Y,
        Some("z") => UpAxis::Z,
        Some(other) => return Err(ApiError::bad(format!("up={other}; expected y or z"))),
    };
    let rigged = Rigged::of(request)?;
    let (name, scene, setup) = (&rigged.name, &rigged.scene, &rigged.setup);
    let fail = |e: &dyn std::fmt::Display| ApiError::new(400, format!("{name}: {e}"));
    let fitted = match scene.animation {
        Some(_) => FittedAnimation::new(scene, setup).map_err(|e| fail(&e))?,
        None => {
            let mut cage = vec![[0.0; 3]; setup.cage.n_vertices()];
            let pose = scene.pose(0).map_err(|e| fail(&e))?;
            setup.rig.update(&pose, &mut cage).map_err(|e| fail(&e))?;
            FittedAnimation {
                fps: DEFAULT_FPS,
                times: vec![0.0],
                cages: vec![cage],
            }
        }
    };
    let stem = name
        .rsplit_once('.')
        .map_or(name.as_str(), |(stem, _)| stem);
    match query.format.as_str() {
        "usda" => {
            let text = fitted.usda(setup, stem, up).map_err(|e| fail(&e))?;
            Ok(Response::ok("model/vnd.usda; charset=utf-8", text))
        }
        "glb" => {
            let glb = fitted
                .glb(setup, rigged.level, stem, up)
                .map_err(|e| fail(&e))?;
            Ok(Response::ok("model/gltf-binary", glb))
        }
        "obj" if fitted.cages.len() == 1 => {
            let mut cage = setup.cage.clone();
            cage.set_positions(fitted.cages[0].clone())
                .map_err(|e| fail(&e))?;
            Ok(Response::ok(
                "text/plain; charset=utf-8",
                to_obj_string(&cage),
            ))
        }
        "obj" => Err(ApiError::bad(
            "an OBJ file holds one pose; export an animation as usda or glb".to_string(),
        )),
        other => Err(ApiError::bad(format!(
            "format={other}; expected usda, glb or obj"
        ))),
    }
}

/// A request's cage, scene and precomputed setup ([`RigWireRequest`]).
struct Rigged {
    name: String,
    level: usize,
    scene: SubdivScene,
    setup: SubdivSetup,
}

impl Rigged {
    fn of(request: &Request) -> Result<Rigged, ApiError> {
        let body: RigWireRequest = serde_json::from_slice(request.upload()?)
            .map_err(|e| ApiError::bad(format!("subdiv: {e}")))?;
        let level = check_level(body.level)?;
        let name = body.name;
        let cage = parse_obj(&body.obj, &name).map_err(|e| ApiError::new(400, e.to_string()))?;
        let mut scene = body.scene;
        scene.insert("splineskin_subdiv_scene".into(), 1.into());
        scene.insert("obj".into(), name.clone().into());
        let text = serde_json::Value::Object(scene).to_string();
        let scene = SubdivScene::parse(&text, &format!("{name}: scene"), std::path::Path::new(""))
            .map_err(|e| ApiError::new(400, e.to_string()))?;
        let setup = scene
            .setup_with(cage)
            .map_err(|e| ApiError::new(400, e.to_string()))?;
        Ok(Rigged {
            name,
            level,
            scene,
            setup,
        })
    }
}

/// Every `B_i[v]`, vertex-major.
fn coefficients(rig: &SubdivRig) -> Vec<f64> {
    let mut out = Vec::with_capacity(4 * rig.n_vertices() * rig.n_handles());
    for v in 0..rig.n_vertices() {
        for i in 0..rig.n_handles() {
            out.extend(rig.coefficients(v, i));
        }
    }
    out
}

/// The level asked for, or the default; 400 outside 1 ..= [`MAX_LIMIT_MESH_LEVEL`].
fn check_level(level: Option<usize>) -> Result<usize, ApiError> {
    let level = level.unwrap_or(DEFAULT_PAGE_LEVEL);
    if (1..=MAX_LIMIT_MESH_LEVEL).contains(&level) {
        Ok(level)
    } else {
        Err(ApiError::new(
            400,
            format!("level {level}; expected 1 ..= {MAX_LIMIT_MESH_LEVEL}"),
        ))
    }
}

/// `POST /api/subdiv/open?level=K`: the body is the OBJ text, `x-file-name` its name.
pub(crate) fn open(request: &Request) -> Result<Response, ApiError> {
    let query: OpenQuery = request.query("subdiv/open")?;
    check_level(query.level)?;
    let name = request
        .header("x-file-name")
        .map(crate::document_routes::percent_decode)
        .filter(|n| !n.is_empty())
        .unwrap_or_else(|| "upload.obj".to_string());
    let text = std::str::from_utf8(request.upload()?).map_err(|e| {
        ApiError::new(
            400,
            format!("{name}: not UTF-8 text ({e}); expected an OBJ file"),
        )
    })?;
    let cage = parse_obj(text, &name).map_err(|e| ApiError::new(400, e.to_string()))?;
    let level = query.level.unwrap_or_else(|| page_level(cage.n_faces()));
    let fail = |e: &dyn std::fmt::Display| ApiError::new(400, format!("{name}: {e}"));
    let surface = LimitSurface::new(&cage, &LimitOptions::default()).map_err(|e| fail(&e))?;
    let mesh = LimitMesh::new(&cage, &surface, level).map_err(|e| fail(&e))?;
    let mut rest = vec![[0.0; 3]; mesh.n_vertices()];
    mesh.positions(cage.positions(), &mut rest);
    let stencils = mesh.stencils();
    let mut wire = SurfaceWire {
        level,
        n_vertices: mesh.n_vertices(),
        triangles: mesh.triangles(&rest).into_iter().flatten().collect(),
        offsets: vec![0],
        indices: Vec::new(),
        weights: Vec::new(),
    };
    for m in 0..stencils.n_stencils() {
        let (indices, weights) = stencils.stencil(m);
        wire.indices.extend_from_slice(indices);
        wire.weights.extend_from_slice(weights);
        wire.offsets.push(wire.indices.len() as u32);
    }
    let tags = cage.tags();
    Response::json(&CageWire {
        name,
        positions: cage.positions().iter().flatten().copied().collect(),
        face_sizes: cage.face_sizes().map(|n| n as u32).collect(),
        face_vertices: cage.face_vertices().to_vec(),
        edges: edges(cage.faces()),
        diagonal: cage.bounding_box_diagonal(),
        n_tags: [tags.creases.len(), tags.corners.len(), tags.holes.len()],
        surface: wire,
    })
}

/// Every edge of `faces` once, smaller vertex first, in order of first appearance.
fn edges<'a>(faces: impl Iterator<Item = &'a [u32]>) -> Vec<u32> {
    let mut seen = std::collections::HashSet::new();
    let mut out = Vec::new();
    for face in faces {
        for (k, &a) in face.iter().enumerate() {
            let b = face[(k + 1) % face.len()];
            let edge = (a.min(b), a.max(b));
            if seen.insert(edge) {
                out.extend([edge.0, edge.1]);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::editor::Editor;

    const TUBE: &str = include_str!("../../splineskin/assets/subdiv/tube.obj");

    fn open_tube(query: &str) -> Response {
        let editor = Editor::new(None);
        let request = Request::post(
            &format!("/api/subdiv/open{query}"),
            TUBE.as_bytes().to_vec(),
        )
        .with_header("x-file-name", "tube.obj");
        editor.handle(&request)
    }

    #[test]
    fn the_stencils_give_the_limit_surface_of_the_cage() {
        let response = open_tube("?level=2");
        assert_eq!(
            response.status,
            200,
            "{}",
            String::from_utf8_lossy(&response.body)
        );
        let wire: CageWire = serde_json::from_slice(&response.body).unwrap();
        let cage = parse_obj(TUBE, "tube.obj").unwrap();
        assert_eq!(
            (wire.name.as_str(), wire.positions.len()),
            ("tube.obj", 3 * 72)
        );
        assert_eq!(wire.face_sizes.len(), 66);
        assert_eq!(wire.n_tags[0], cage.tags().creases.len());
        // Every edge once: Euler's V − E + F = 2 for the closed tube.
        assert_eq!(72 - wire.edges.len() as i64 / 2 + 66, 2);
        let surface = LimitSurface::new(&cage, &LimitOptions::default()).unwrap();
        let mesh = LimitMesh::new(&cage, &surface, 2).unwrap();
        let mut want = vec![[0.0; 3]; mesh.n_vertices()];
        mesh.positions(cage.positions(), &mut want);
        let s = &wire.surface;
        assert_eq!(
            (s.n_vertices, s.triangles.len()),
            (want.len(), 6 * mesh.quads().len())
        );
        for (m, w) in want.iter().enumerate() {
            let (lo, hi) = (s.offsets[m] as usize, s.offsets[m + 1] as usize);
            for k in 0..3 {
                let got: f64 = (lo..hi)
                    .map(|e| s.weights[e] * wire.positions[3 * s.indices[e] as usize + k])
                    .sum();
                assert!((got - w[k]).abs() < 1e-12, "vertex {m}: {got} vs {}", w[k]);
            }
        }
    }

    #[test]
    fn the_rigs_factors_give_the_fitted_cage_and_the_weights_are_painted() {
        let editor = Editor::new(None);
        let body = serde_json::json!({
            "name": "tube.obj",
            "obj": TUBE,
            "level": 2,
            "scene": {
                "handles": [{"position": [0.5, 0.0, 0.0]}, {"position": [7.5, 0.0, 0.0]}],
                "weights": {"family": "bbw", "resolution": 16}
            }
        });
        let answer = editor.handle(&Request::post("/api/subdiv/rig", body.to_string()));
        assert_eq!(
            answer.status,
            200,
            "{}",
            String::from_utf8_lossy(&answer.body)
        );
        let wire: RigWire = serde_json::from_slice(&answer.body).unwrap();
        assert_eq!((wire.n_vertices, wire.n_handles), (72, 2));
        // The page's product against the library's rig for a pose.
        let cage = parse_obj(TUBE, "tube.obj").unwrap();
        let text = r#"{"splineskin_subdiv_scene": 1, "obj": "tube.obj",
            "handles": [{"position": [0.5, 0.0, 0.0]}, {"position": [7.5, 0.0, 0.0]}],
            "weights": {"family": "bbw", "resolution": 16}}"#;
        let scene = SubdivScene::parse(text, "t", std::path::Path::new("")).unwrap();
        let setup = scene.setup_with(cage).unwrap();
        let turn = [
            [0.0, -1.0, 0.0, 7.5],
            [1.0, 0.0, 0.0, -7.5],
            [0.0, 0.0, 1.0, 0.5],
        ];
        let pose = [splineskin::subdiv::AFFINE3_IDENTITY, turn];
        let mut want = vec![[0.0; 3]; 72];
        setup.rig.update(&pose, &mut want).unwrap();
        for (v, w) in want.iter().enumerate() {
            for k in 0..3 {
                let got: f64 = (0..2)
                    .map(|i| {
                        let b = &wire.coefficients[(v * 2 + i) * 4..][..4];
                        (0..4).map(|c| pose[i][k][c] * b[c]).sum::<f64>()
                    })
                    .sum();
                assert!((got - w[k]).abs() < 1e-12, "vertex {v}: {got} vs {}", w[k]);
            }
        }
        // Weights at every surface vertex of level 2, rows summing to 1, both handles present.
        let n = wire.surface_weights.len() / 2;
        assert_eq!(wire.surface_weights.len(), 2 * n);
        for row in wire.surface_weights.chunks(2) {
            assert!(
                (row[0] + row[1] - 1.0).abs() < 1e-12
                    && row.iter().all(|w| (0.0..=1.0).contains(w))
            );
        }
        assert!(wire.surface_weights.chunks(2).any(|r| r[0] > 0.99));
        assert!(wire.surface_weights.chunks(2).any(|r| r[1] > 0.99));
        assert_eq!(wire.cage_weights.len(), 2 * 72);
        assert!(wire
            .cage_weights
            .chunks(2)
            .all(|r| (r[0] + r[1] - 1.0).abs() < 1e-12));
        // A bad scene is refused naming the element.
        let bad = serde_json::json!({"name": "tube.obj", "obj": TUBE,
            "scene": {"handles": [{"position": [0.5, 0.0, 0.0]}], "weights": {"family": "bbw", "resolution": 1}}});
        let answer = editor.handle(&Request::post("/api/subdiv/rig", bad.to_string()));
        assert_eq!(answer.status, 400);
        let message = String::from_utf8_lossy(&answer.body);
        assert!(
            message.contains("tube.obj: scene: weights.resolution"),
            "{message}"
        );
    }

    #[test]
    fn the_export_is_what_the_command_line_writes_of_the_same_scene() {
        let editor = Editor::new(None);
        let turn = serde_json::json!({"matrix": [[0.0, -1.0, 0.0, 7.5], [1.0, 0.0, 0.0, -7.5], [0.0, 0.0, 1.0, 0.5]]});
        let scene = serde_json::json!({
            "handles": [{"position": [0.5, 0.0, 0.0]}, {"position": [7.5, 0.0, 0.0]}],
            "poses": [{"transforms": [{}, turn]}]
        });
        let body = serde_json::json!({"name": "tube.obj", "obj": TUBE, "level": 1, "scene": scene});
        let export = |format: &str| {
            let answer = editor.handle(&Request::post(
                &format!("/api/subdiv/export?format={format}"),
                body.to_string(),
            ));
            assert_eq!(
                answer.status,
                200,
                "{format}: {}",
                String::from_utf8_lossy(&answer.body)
            );
            answer.body
        };
        // The library's deform of pose 0, written as the command line writes it.
        let text = format!(
            r#"{{"splineskin_subdiv_scene": 1, "obj": "tube.obj", "handles": {}, "poses": {}}}"#,
            scene["handles"], scene["poses"]
        );
        let parsed = SubdivScene::parse(&text, "t", std::path::Path::new("")).unwrap();
        let setup = parsed
            .setup_with(parse_obj(TUBE, "tube.obj").unwrap())
            .unwrap();
        let mut cage = setup.cage.clone();
        let mut fitted = vec![[0.0; 3]; 72];
        setup
            .rig
            .update(&parsed.pose(0).unwrap(), &mut fitted)
            .unwrap();
        cage.set_positions(fitted.clone()).unwrap();
        assert_eq!(
            String::from_utf8(export("obj")).unwrap(),
            to_obj_string(&cage)
        );
        let usda = String::from_utf8(export("usda")).unwrap();
        assert!(usda.contains("defaultPrim = \"tube\"") && usda.contains("catmullClark"));
        let frames = FittedAnimation {
            fps: DEFAULT_FPS,
            times: vec![0.0],
            cages: vec![fitted],
        };
        assert_eq!(usda, frames.usda(&setup, "tube", UpAxis::Y).unwrap());
        assert_eq!(&export("glb")[..4], b"glTF");
        let bad = editor.handle(&Request::post(
            "/api/subdiv/export?format=fbx",
            body.to_string(),
        ));
        assert_eq!(bad.status, 400);
        assert!(String::from_utf8_lossy(&bad.body).contains("expected usda, glb or obj"));
    }

    #[test]
    fn bad_uploads_and_levels_are_refused_with_a_message() {
        let bad = open_tube("?level=9");
        assert_eq!(bad.status, 400);
        assert!(String::from_utf8_lossy(&bad.body).contains("level 9; expected 1 ..= 6"));
        let editor = Editor::new(None);
        let request = Request::post("/api/subdiv/open", b"v 0 0 0\nf 1 2 3\n".to_vec())
            .with_header("x-file-name", "broken.obj");
        let answer = editor.handle(&request);
        assert_eq!(answer.status, 400);
        assert!(
            String::from_utf8_lossy(&answer.body).contains("broken.obj:2"),
            "{}",
            String::from_utf8_lossy(&answer.body)
        );
    }
}
