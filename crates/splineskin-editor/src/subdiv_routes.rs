//! The Catmull–Clark page's routes (`web/subdiv/`): an OBJ cage opened, and what the page needs
//! to draw its limit surface at any cage positions without asking again.
//!
//! `POST /api/subdiv/open?level=K` answers [`CageWire`]: the cage (positions, faces, edges for
//! its wireframe) and the limit surface sampled at level `K` ([`LimitMesh`]: `(2^K)²` quads per
//! cage quad) as triangles and **limit stencils**: each surface vertex `s_m = Σ_j w_mj c_j`, a
//! sparse row over the cage vertices `c_j` (the page's per-frame tessellation is that sparse
//! product, then the normals).

use serde::{Deserialize, Serialize};
use splineskin::subdiv::{parse_obj, LimitMesh, LimitOptions, LimitSurface, MAX_LIMIT_MESH_LEVEL};

use crate::request::{ApiError, Request, Response};

/// Tessellation level when the page does not say: 3 (64 quads per cage quad).
pub const DEFAULT_PAGE_LEVEL: usize = 3;

/// The query of `POST /api/subdiv/open`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OpenQuery {
    /// Tessellation level, 1 ..= [`MAX_LIMIT_MESH_LEVEL`] (default [`DEFAULT_PAGE_LEVEL`]).
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

/// `POST /api/subdiv/open?level=K`: the body is the OBJ text, `x-file-name` its name.
pub(crate) fn open(request: &Request) -> Result<Response, ApiError> {
    let query: OpenQuery = request.query("subdiv/open")?;
    let level = query.level.unwrap_or(DEFAULT_PAGE_LEVEL);
    if !(1..=MAX_LIMIT_MESH_LEVEL).contains(&level) {
        return Err(ApiError::new(
            400,
            format!("level {level}; expected 1 ..= {MAX_LIMIT_MESH_LEVEL}"),
        ));
    }
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
