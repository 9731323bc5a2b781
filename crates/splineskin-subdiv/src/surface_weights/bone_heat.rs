//! Bone-heat weights (Baran & Popović 2007, *Automatic rigging and animation of 3D
//! characters*, §4): each handle's weight is the equilibrium temperature of the surface when
//! the handle heats the points that see it as their nearest handle.
//!
//! ```text
//! (K + M H) w_i = M H p_i          for every handle i
//! ```
//!
//! | symbol | meaning |
//! |---|---|
//! | `K = −L` | cotangent stiffness of the limit mesh ([`splineskin_core::mesh::cotangent`]), `n × n` |
//! | `M` | its lumped (barycentric) mass, diagonal |
//! | `H` | heat: `H_jj = k·c / d_j²` when the nearest *visible* handle of vertex `j` is at distance `d_j`, shared by `k` equidistant handles; `c =` [`HEAT_CONSTANT`]; 0 when no handle is visible |
//! | `p_i` | `p_ij = 1/k` if handle `i` is one of the `k` nearest visible handles of `j`, else 0 |
//!
//! (Baran & Popović write `−Δ w_i + H w_i = H p_i` with `Δ` the discrete Laplace operator
//! `M⁻¹L`; multiplying by `M` gives the symmetric positive definite system above, factored
//! **once** by a sparse Cholesky and solved for all handles.) Where the `p_i` sum to one, so do
//! the `w_i` (`K·1 = 0`); rows are normalised anyway.
//!
//! # The mesh
//!
//! The equation is solved on the limit surface itself: a [`LimitMesh`] (vertices on the limit
//! surface, the topology of a uniform refinement), by default of the first level from 2 on that
//! has at least [`BONE_HEAT_MIN_QUADS`] quads (at most [`BONE_HEAT_MAX_LEVEL`]). Weights
//! anywhere on the surface are the bilinear interpolation of the cell holding the location
//! ([`LimitMesh::locate`]): C⁰, exactly a partition of unity. A cage vertex (for the naive
//! method) takes the weights of its limit point, which is a mesh vertex.
//!
//! # Visibility (approximated)
//!
//! A handle is *visible* from a mesh vertex when the straight segment from the vertex to the
//! handle's closest point crosses no triangle of the limit mesh (the quads split along their
//! shorter diagonal), ignoring crossings within [`VISIBILITY_MARGIN_FRACTION`] of the
//! bounding-box diagonal of either end — the surface the segment starts on, and a handle that
//! lies on the surface. This is Baran & Popović's test on the piecewise linear limit mesh
//! rather than on the surface. Vertices that see no handle get no heat and take their weights
//! by diffusion alone; if a whole connected part of the mesh sees no handle (say, handles
//! placed on another part), that part is heated without the visibility test, with a
//! `tracing` warning, since otherwise its weights would be undetermined.
//!
//! Distances are floored at [`DISTANCE_FLOOR_FRACTION`] of the diagonal, so a vertex on a
//! handle gets a large but finite heat (its weight is then 1 to about that fraction squared).

use super::super::affine3::{distance2, norm, sub};
use super::super::cage::{bounds3, Cage, Point3};
use super::super::error::SurfaceWeightsError;
use super::super::handles::Handles3;
use super::super::limit::LimitSurface;
use super::super::limit_mesh::LimitMesh;
use super::super::visibility::TriangleBvh;
use super::{SurfaceSample, SurfaceWeights};
use splineskin_core::linalg::{solve_spd_in_place, Csc};
use splineskin_core::mesh::cotangent::quad_stiffness_and_mass;

/// The fewest quads of the limit mesh the default level reaches: 8 192 (the torus's 32 quads
/// refined 4 times; the car's 1 575 twice, 25 200 quads). Enough for weights that vary over a
/// few cage faces; the solve is then well under a second.
pub const BONE_HEAT_MIN_QUADS: usize = 8192;

/// The deepest default level: 4 (256 quads per cage quad).
pub const BONE_HEAT_MAX_LEVEL: usize = 4;

/// The shallowest default level: 2 (16 quads per cage quad).
pub const BONE_HEAT_MIN_LEVEL: usize = 2;

/// Baran & Popović's heat constant `c`: 1 (their choice; `H` then has units of a Laplacian,
/// 1/length², so the weights do not depend on the model's scale).
pub const HEAT_CONSTANT: f64 = 1.0;

/// Handles whose distances differ by less than this fraction are equidistant (and share a
/// vertex's heat): rounding-level, so that mirror-symmetric handles heat a symmetric mesh
/// symmetrically.
pub const TIE_TOLERANCE: f64 = 1e-9;

/// Floor of the handle distance, as a fraction of the bounding-box diagonal: 1e-6.
pub const DISTANCE_FLOOR_FRACTION: f64 = 1e-6;

/// Crossings of the surface this close to either end of a visibility segment are ignored,
/// as a fraction of the bounding-box diagonal: 1e-3 (a tenth of a percent, below the size of a
/// mesh cell at the default levels).
pub const VISIBILITY_MARGIN_FRACTION: f64 = 1e-3;

/// Options of [`BoneHeat::new`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct BoneHeatOptions {
    /// Level of the limit mesh the heat equation is solved on (1 ..=
    /// [`MAX_LIMIT_MESH_LEVEL`](super::super::limit_mesh::MAX_LIMIT_MESH_LEVEL)). Default:
    /// `None`, the first level from [`BONE_HEAT_MIN_LEVEL`] with at least
    /// [`BONE_HEAT_MIN_QUADS`] quads, at most [`BONE_HEAT_MAX_LEVEL`].
    pub level: Option<usize>,
    /// Test visibility (module documentation). Default: `true`.
    pub visibility: bool,
}

impl Default for BoneHeatOptions {
    fn default() -> Self {
        BoneHeatOptions {
            level: None,
            visibility: true,
        }
    }
}

impl BoneHeatOptions {
    /// Sets [`BoneHeatOptions::level`].
    pub fn with_level(mut self, level: Option<usize>) -> Self {
        self.level = level;
        self
    }

    /// Sets [`BoneHeatOptions::visibility`].
    pub fn with_visibility(mut self, visibility: bool) -> Self {
        self.visibility = visibility;
        self
    }
}

/// Bone-heat weights on a limit mesh (module documentation).
///
/// ```
/// use splineskin_subdiv::{parse_obj, BoneHeat, BoneHeatOptions, Handles3, LimitOptions, LimitSurface};
///
/// // A box 4 long with a bone along each half of its axis.
/// let text = "v 0 0 0\nv 4 0 0\nv 4 1 0\nv 0 1 0\nv 0 0 1\nv 4 0 1\nv 4 1 1\nv 0 1 1\n\
///             f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
/// let cage = parse_obj(text, "box.obj")?;
/// let surface = LimitSurface::new(&cage, &LimitOptions::default())?;
/// let bones = vec![[[0.5, 0.5, 0.5], [1.8, 0.5, 0.5]], [[3.5, 0.5, 0.5], [2.2, 0.5, 0.5]]];
/// let handles = Handles3::new(vec![], bones)?;
/// let heat = BoneHeat::new(&cage, &surface, &handles, &BoneHeatOptions::default())?;
/// // Every mesh vertex's weights sum to one; the cage's first vertex (at x = 0) follows the
/// // first bone more than the second.
/// let w0 = heat.mesh_weights(heat.mesh().cage_vertex(0).unwrap() as usize);
/// assert!((w0[0] + w0[1] - 1.0).abs() < 1e-12 && w0[0] > w0[1]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct BoneHeat {
    mesh: LimitMesh,
    n_handles: usize,
    /// Vertex-major, normalised.
    weights: Vec<f64>,
}

impl BoneHeat {
    /// Solves the heat equation for `handles` on the limit surface `surface` of `cage`.
    pub fn new(
        cage: &Cage,
        surface: &LimitSurface,
        handles: &Handles3,
        options: &BoneHeatOptions,
    ) -> Result<Self, SurfaceWeightsError> {
        let level = match options.level {
            Some(l) => l,
            None => default_level(cage, surface),
        };
        let mesh = LimitMesh::new(cage, surface, level)?;
        let n = mesh.n_vertices();
        let h = handles.n_handles();
        let mut positions = vec![[0.0; 3]; n];
        mesh.positions(cage.positions(), &mut positions);
        let diagonal = bounding_diagonal(&positions);
        let floor = DISTANCE_FLOOR_FRACTION * diagonal;
        let bvh = options
            .visibility
            .then(|| TriangleBvh::new(&positions, &mesh.triangles(&positions)));
        let margin = VISIBILITY_MARGIN_FRACTION * diagonal;
        // Heat H_jj and targets p_ij (vertex-major), with and without the visibility test.
        let mut heat = vec![0.0; n];
        let mut target = vec![0.0; n * h];
        let mut distance = vec![0.0; h];
        let mut visible = vec![true; h];
        let mut nearest = |j: usize, test: bool, heat: &mut [f64], target: &mut [f64]| {
            let x = positions[j];
            for i in 0..h {
                let c = handles.closest_point(i, x);
                distance[i] = norm(sub(c, x)).max(floor);
                visible[i] = match (&bvh, test) {
                    (Some(bvh), true) => !bvh.blocks(x, c, margin),
                    _ => true,
                };
            }
            let d_min = (0..h)
                .filter(|&i| visible[i])
                .map(|i| distance[i])
                .fold(f64::INFINITY, f64::min);
            let row = &mut target[j * h..][..h];
            row.fill(0.0);
            heat[j] = 0.0;
            if d_min.is_finite() {
                let ties: Vec<usize> = (0..h)
                    .filter(|&i| visible[i] && distance[i] <= d_min * (1.0 + TIE_TOLERANCE))
                    .collect();
                let k = ties.len() as f64;
                for &i in &ties {
                    row[i] = 1.0 / k;
                }
                heat[j] = k * HEAT_CONSTANT / (d_min * d_min);
            }
        };
        for j in 0..n {
            nearest(j, true, &mut heat, &mut target);
        }
        if options.visibility {
            let parts = components(n, mesh.quads());
            let n_parts = parts.iter().max().map_or(0, |&m| m + 1);
            let mut heated = vec![false; n_parts];
            for j in 0..n {
                heated[parts[j]] |= heat[j] > 0.0;
            }
            for (part, _) in heated.iter().enumerate().filter(|(_, &hot)| !hot) {
                tracing::warn!(
                    part,
                    "bone heat: no handle is visible from a connected part of the surface; \
                     heating it by distance alone"
                );
                for j in (0..n).filter(|&j| parts[j] == part) {
                    nearest(j, false, &mut heat, &mut target);
                }
            }
        }
        let (entries, mass) = quad_stiffness_and_mass(&positions, mesh.quads());
        let shift: Vec<f64> = (0..n).map(|j| mass[j] * heat[j]).collect();
        let system = Csc::upper_from_entries(n, entries, &shift);
        // Right-hand sides, column-major: column i is M H p_i.
        let mut columns = vec![0.0; n * h];
        for j in 0..n {
            for i in 0..h {
                columns[i * n + j] = shift[j] * target[j * h + i];
            }
        }
        solve_spd_in_place(&system, &mut columns).map_err(|e| SurfaceWeightsError::Solve {
            what: format!("{e}; expected K + M H positive definite"),
        })?;
        let mut weights = vec![0.0; n * h];
        for j in 0..n {
            let row = &mut weights[j * h..][..h];
            for i in 0..h {
                row[i] = columns[i * n + j];
            }
            let sum: f64 = row.iter().sum();
            if !(sum > 0.0 && sum.is_finite()) {
                return Err(SurfaceWeightsError::Solve {
                    what: format!(
                        "the weights of limit mesh vertex {j} sum to {sum}; expected a positive number"
                    ),
                });
            }
            row.iter_mut().for_each(|w| *w /= sum);
        }
        Ok(BoneHeat {
            mesh,
            n_handles: h,
            weights,
        })
    }

    /// The limit mesh the weights were solved on.
    pub fn mesh(&self) -> &LimitMesh {
        &self.mesh
    }

    /// The weights of mesh vertex `v` (`n_handles` long).
    ///
    /// # Panics
    /// If `v >= mesh().n_vertices()`.
    pub fn mesh_weights(&self, v: usize) -> &[f64] {
        &self.weights[v * self.n_handles..][..self.n_handles]
    }
}

impl SurfaceWeights for BoneHeat {
    fn n_handles(&self) -> usize {
        self.n_handles
    }

    fn eval(&self, at: &SurfaceSample<'_>, out: &mut [f64]) -> Result<(), SurfaceWeightsError> {
        out.fill(0.0);
        for (v, b) in self.mesh.locate(at.location)? {
            if b != 0.0 {
                for (o, w) in out.iter_mut().zip(self.mesh_weights(v as usize)) {
                    *o += b * w;
                }
            }
        }
        Ok(())
    }

    fn eval_cage_vertex(
        &self,
        vertex: u32,
        _position: Point3,
        out: &mut [f64],
    ) -> Result<(), SurfaceWeightsError> {
        let v = self
            .mesh
            .cage_vertex(vertex)
            .ok_or(SurfaceWeightsError::NoSurface { vertex })?;
        out.copy_from_slice(self.mesh_weights(v as usize));
        Ok(())
    }
}

/// The first level from [`BONE_HEAT_MIN_LEVEL`] with at least [`BONE_HEAT_MIN_QUADS`] quads,
/// at most [`BONE_HEAT_MAX_LEVEL`].
fn default_level(cage: &Cage, surface: &LimitSurface) -> usize {
    // Quads at level 1: n per n-gon (4 per quad); ×4 per further level.
    let level1: usize = (0..cage.n_faces())
        .filter(|&f| !surface.is_hole(f as u32))
        .map(|f| cage.face(f).len())
        .sum();
    (BONE_HEAT_MIN_LEVEL..=BONE_HEAT_MAX_LEVEL)
        .find(|&l| level1 << (2 * (l - 1)) >= BONE_HEAT_MIN_QUADS)
        .unwrap_or(BONE_HEAT_MAX_LEVEL)
}

/// The length of the bounding-box diagonal of `points`.
fn bounding_diagonal(points: &[Point3]) -> f64 {
    let (lo, hi) = bounds3(points);
    distance2(lo, hi).sqrt()
}

/// The connected part of every vertex (`0..n_parts`), joined through quads.
fn components(n: usize, quads: &[[u32; 4]]) -> Vec<usize> {
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut v: usize) -> usize {
        while parent[v] != v {
            parent[v] = parent[parent[v]];
            v = parent[v];
        }
        v
    }
    for q in quads {
        for k in 1..4 {
            let (a, b) = (
                root(&mut parent, q[0] as usize),
                root(&mut parent, q[k] as usize),
            );
            if a != b {
                parent[a.max(b)] = a.min(b);
            }
        }
    }
    let mut label = vec![usize::MAX; n];
    let mut next = 0;
    (0..n)
        .map(|v| {
            let r = root(&mut parent, v);
            if label[r] == usize::MAX {
                label[r] = next;
                next += 1;
            }
            label[r]
        })
        .collect()
}
