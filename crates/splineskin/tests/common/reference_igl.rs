//! Reader of `../shared/data/reference-igl/*.json`: libigl's operators and weights on two 2-D
//! meshes (layout in that folder's README).
#![allow(dead_code, non_snake_case)]

use std::path::Path;

use kurbo::Point;
use serde::Deserialize;
use splineskin::mesh::TriMesh;

/// The two shapes of reference-igl.
pub const SHAPES: [&str; 2] = ["bar", "ushape"];

/// One reference file (the parts the weight tests read).
#[derive(Deserialize)]
pub struct ReferenceIgl {
    pub shape: String,
    pub mesh: Mesh,
    pub handles: Handles,
    pub operators: Operators,
    pub weights: Weights,
    pub arap: Arap,
}

#[derive(Deserialize)]
pub struct Mesh {
    pub V: Vec<[f64; 2]>,
    pub F: Vec<[usize; 3]>,
    pub boundary_loop: Vec<usize>,
    pub total_area: f64,
}

#[derive(Deserialize)]
pub struct Handles {
    pub indices: Vec<usize>,
    pub rest_positions: Vec<[f64; 2]>,
}

#[derive(Deserialize)]
pub struct Operators {
    pub cotmatrix: Coo,
    pub massmatrix_voronoi_diag: Vec<f64>,
    pub massmatrix_barycentric_diag: Vec<f64>,
}

/// A sparse matrix as coordinate triplets (full symmetric storage, sorted by (i, j)).
#[derive(Deserialize)]
pub struct Coo {
    pub rows: usize,
    pub cols: usize,
    pub i: Vec<usize>,
    pub j: Vec<usize>,
    pub v: Vec<f64>,
}

#[derive(Deserialize)]
pub struct Weights {
    pub harmonic_k1: Matrix,
    pub harmonic_k2: Matrix,
    pub bbw_raw: BbwRaw,
    pub bbw_normalized: Matrix,
    pub biharmonic_coordinates_wang2015: Matrix,
}

/// `W`: `n_vertices` rows of one weight per handle.
#[derive(Deserialize)]
pub struct Matrix {
    pub W: Vec<Vec<f64>>,
}

#[derive(Deserialize)]
pub struct BbwRaw {
    pub W: Vec<Vec<f64>>,
    pub kkt_check: Vec<KktCheck>,
}

/// libigl's BBW per handle: residuals relative to max|Q|, counts at the bounds.
#[derive(Deserialize)]
pub struct KktCheck {
    pub handle: usize,
    pub max_abs_grad_inactive_rel: f64,
    pub min_grad_at_lower_bound_rel: f64,
    pub max_grad_at_upper_bound_rel: f64,
    pub n_at_lower: usize,
    pub n_at_upper: usize,
}

/// libigl's ARAP with positional constraints at the handles, from the rest pose.
#[derive(Deserialize)]
pub struct Arap {
    pub energy_type: String,
    pub cases: Vec<ArapCase>,
}

/// One target configuration and libigl's iterates for it.
#[derive(Deserialize)]
pub struct ArapCase {
    pub name: String,
    pub description: String,
    /// One target per handle.
    pub targets: Vec<[f64; 2]>,
    pub U_iter1: Vec<[f64; 2]>,
    pub U_iter10: Vec<[f64; 2]>,
    pub U_converged: Vec<[f64; 2]>,
    pub iterations_to_converge: usize,
    pub energy_iter1: f64,
    pub energy_iter10: f64,
    pub energy_converged: f64,
    pub flipped_triangles_converged: usize,
}

/// Points from `[x, y]` pairs.
pub fn points(xy: &[[f64; 2]]) -> Vec<Point> {
    xy.iter().map(|&[x, y]| Point::new(x, y)).collect()
}

impl ReferenceIgl {
    /// Reads `<data>/reference-igl/<shape>.json`.
    pub fn read(data: &Path, shape: &str) -> ReferenceIgl {
        let path = data.join("reference-igl").join(format!("{shape}.json"));
        let text =
            std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
    }

    /// Every shape of [`SHAPES`] with its reference; none when the shared data is missing
    /// (the calling test then skips, see [`super::data_root`]).
    pub fn all() -> Vec<(&'static str, ReferenceIgl)> {
        let Some(data) = super::data_root() else {
            return Vec::new();
        };
        SHAPES
            .iter()
            .map(|&shape| (shape, Self::read(&data, shape)))
            .collect()
    }

    /// The mesh, validated.
    pub fn tri_mesh(&self) -> TriMesh {
        let vertices = self.mesh.V.iter().map(|&[x, y]| Point::new(x, y)).collect();
        TriMesh::new(vertices, self.mesh.F.clone()).expect("the reference mesh is valid")
    }
}
