//! Bounded biharmonic weights on the volume a Catmull–Clark surface encloses (Jacobson, Baran,
//! Popović & Sorkine 2011; the paper's 3D figures use them on a tetrahedral mesh of the
//! volume, made by TetGen, whose licence this project cannot carry).
//!
//! The volume is discretised here by a regular grid ([`VolumeGrid`]): the nodes inside the
//! limit surface (tessellated at level 1) by generalized winding number, which copes with open
//! boundaries, holes and self-touching parts. On those nodes, with `G` the 7-point graph
//! Laplacian of the grid restricted to them (natural boundary conditions where a neighbour is
//! outside) and unit masses (the grid is uniform, so `h` only scales the energy),
//!
//! ```text
//! minimise  ½ wᵀ Q w,  Q = G G,   subject to  w[b] = bc,   0 ≤ w ≤ 1     (per handle)
//! ```
//!
//! the same program and active-set solver as the 2D weights
//! ([`splineskin_core::weights::bbw::bounded_minimiser`]), rows then normalised. Handles fix
//! nodes: a point handle its nearest inside node, a bone every inside node nearest to a sample
//! of its segment (samples every half cell; a node claimed by an earlier handle stays
//! with it, so bones meeting at a joint share it). A part of the volume with no handle is left
//! out (its weights would be undetermined).
//!
//! At a point of the surface the weights are the trilinear interpolation of the nodes of its
//! cell that are inside, renormalised; where none is, those of the nearest inside node.

use splineskin_core::linalg::csc::Csc;
use splineskin_core::weights::bbw::{bounded_minimiser, BbwOptions};
use splineskin_core::weights::{DirichletData, VertexWeights};

use super::super::cage::{Cage, Point3};
use super::super::handles::Handles3;
use super::super::limit::LimitSurface;
use super::super::limit_mesh::LimitMesh;
use super::volume_grid::{VolumeGrid, OUTSIDE};
use super::{SpatialWeights, SurfaceWeightsError};

/// Cells along the longest side of the bounding box by default: 24.
pub const DEFAULT_VOLUME_RESOLUTION: usize = 24;

/// The finest grid accepted: 128 cells along the longest side.
pub const MAX_VOLUME_RESOLUTION: usize = 128;

/// Options of [`VolumeBbw`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct VolumeBbwOptions {
    /// Grid cells along the longest side of the surface's bounding box (4 ..=
    /// [`MAX_VOLUME_RESOLUTION`]). Default [`DEFAULT_VOLUME_RESOLUTION`].
    pub resolution: usize,
    /// The active-set solver's options.
    pub bbw: BbwOptions,
}

impl Default for VolumeBbwOptions {
    fn default() -> Self {
        VolumeBbwOptions {
            resolution: DEFAULT_VOLUME_RESOLUTION,
            bbw: BbwOptions::default(),
        }
    }
}

impl VolumeBbwOptions {
    /// With `resolution` cells along the longest side.
    pub fn with_resolution(mut self, resolution: usize) -> Self {
        self.resolution = resolution;
        self
    }
}

/// Volumetric bounded biharmonic weights (module documentation).
pub struct VolumeBbw {
    grid: VolumeGrid,
    /// Rows of the inside nodes that were solved (the others are left out: [`OUTSIDE`] in
    /// `grid.index` after solving).
    weights: VertexWeights,
    /// Positions of the solved nodes, for the nearest-node fallback.
    positions: Vec<Point3>,
}

impl VolumeBbw {
    /// The weights of `handles` in the volume of `cage`'s limit `surface`.
    ///
    /// ```
    /// use splineskin_subdiv::surface_weights::{SurfaceWeights, VolumeBbw, VolumeBbwOptions};
    /// use splineskin_subdiv::{parse_obj, Handles3, LimitOptions, LimitSurface};
    ///
    /// let cube = "v 0 0 0\nv 4 0 0\nv 4 1 0\nv 0 1 0\nv 0 0 1\nv 4 0 1\nv 4 1 1\nv 0 1 1\n\
    ///             f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
    /// let cage = parse_obj(cube, "bar.obj")?;
    /// let surface = LimitSurface::new(&cage, &LimitOptions::default())?;
    /// let handles = Handles3::new(vec![[0.8, 0.5, 0.5], [3.2, 0.5, 0.5]], vec![])?;
    /// let w = VolumeBbw::new(&cage, &surface, &handles, &VolumeBbwOptions::default())?;
    /// let mut row = [0.0; 2];
    /// w.eval_cage_vertex(0, cage.positions()[0], &mut row)?;
    /// assert!(row[0] > 0.9 && (row[0] + row[1] - 1.0).abs() < 1e-12, "{row:?}");
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn new(
        cage: &Cage,
        surface: &LimitSurface,
        handles: &Handles3,
        options: &VolumeBbwOptions,
    ) -> Result<Self, SurfaceWeightsError> {
        if !(4..=MAX_VOLUME_RESOLUTION).contains(&options.resolution) {
            return Err(SurfaceWeightsError::BadOption {
                what: format!(
                    "volume resolution {}; expected 4 ..= {MAX_VOLUME_RESOLUTION} cells",
                    options.resolution
                ),
            });
        }
        let mesh = LimitMesh::new(cage, surface, 1)?;
        let mut points = vec![[0.0; 3]; mesh.n_vertices()];
        mesh.positions(cage.positions(), &mut points);
        let triangles = mesh.triangles(&points);
        let mut grid = VolumeGrid::new(&points, &triangles, options.resolution);
        if grid.nodes.is_empty() {
            return Err(volume_error(
                "no grid node lies inside the surface (is it flat, or open everywhere?)".into(),
            ));
        }
        let mut fixed = fix_handles(&grid, handles)?;
        keep_parts_with_handles(&mut grid, &mut fixed);
        let (q, data) = energy_and_data(&grid, &fixed, handles.n_handles())?;
        let mut weights =
            bounded_minimiser(q, &data, &options.bbw).map_err(|e| volume_error(e.to_string()))?;
        weights
            .normalize_rows()
            .map_err(|e| volume_error(e.to_string()))?;
        let positions = grid.nodes.iter().map(|&g| grid.position(g)).collect();
        Ok(VolumeBbw {
            grid,
            weights,
            positions,
        })
    }

    /// Number of grid nodes the weights were solved on.
    pub fn n_nodes(&self) -> usize {
        self.grid.nodes.len()
    }

    /// The grid's cell side, in the cage's units.
    pub fn cell_size(&self) -> f64 {
        self.grid.h
    }

    /// The weights at `p` (module documentation).
    fn eval_at(&self, p: Point3, out: &mut [f64]) {
        out.fill(0.0);
        let g = &self.grid;
        let mut base = [0usize; 3];
        let mut t = [0.0; 3];
        for k in 0..3 {
            let x = ((p[k] - g.origin[k]) / g.h).clamp(0.0, (g.dims[k] - 1) as f64);
            let c = (x.floor() as usize).min(g.dims[k] - 2);
            base[k] = c;
            t[k] = x - c as f64;
        }
        let mut total = 0.0;
        for corner in 0..8 {
            let offset = [corner & 1, (corner >> 1) & 1, (corner >> 2) & 1];
            let node = g.node(std::array::from_fn(|k| base[k] + offset[k]));
            let row = g.index[node];
            if row == OUTSIDE {
                continue;
            }
            let weight: f64 = (0..3)
                .map(|k| if offset[k] == 1 { t[k] } else { 1.0 - t[k] })
                .product();
            if weight > 0.0 {
                total += weight;
                for (o, w) in out.iter_mut().zip(self.weights.row(row as usize)) {
                    *o += weight * w;
                }
            }
        }
        if total > 0.0 {
            out.iter_mut().for_each(|o| *o /= total);
        } else {
            let nearest = nearest(&self.positions, p);
            out.copy_from_slice(self.weights.row(nearest));
        }
    }
}

impl SpatialWeights for VolumeBbw {
    fn n_spatial_handles(&self) -> usize {
        self.weights.n_handles()
    }

    fn weights_at(&self, x: Point3, out: &mut [f64]) {
        self.eval_at(x, out);
    }
}

fn volume_error(what: String) -> SurfaceWeightsError {
    SurfaceWeightsError::Solve {
        what: format!("volumetric BBW: {what}"),
    }
}

/// The index of the point of `points` nearest to `p`.
fn nearest(points: &[Point3], p: Point3) -> usize {
    let d2 = |q: &Point3| (0..3).map(|k| (q[k] - p[k]).powi(2)).sum::<f64>();
    (0..points.len())
        .min_by(|&a, &b| d2(&points[a]).total_cmp(&d2(&points[b])))
        .unwrap_or(0)
}

/// The inside nodes each handle fixes, as `(inside node, handle)` (module documentation).
fn fix_handles(
    grid: &VolumeGrid,
    handles: &Handles3,
) -> Result<Vec<(usize, usize)>, SurfaceWeightsError> {
    let positions: Vec<Point3> = grid.nodes.iter().map(|&g| grid.position(g)).collect();
    let mut owner = vec![usize::MAX; grid.nodes.len()];
    let mut fixed = Vec::new();
    for i in 0..handles.n_handles() {
        let samples: Vec<Point3> = match handles.points().get(i) {
            Some(&p) => vec![p],
            None => {
                let [a, b] = handles.bones()[i - handles.points().len()];
                let length = (0..3).map(|k| (b[k] - a[k]).powi(2)).sum::<f64>().sqrt();
                let n = ((2.0 * length / grid.h).ceil() as usize).max(1);
                (0..=n)
                    .map(|s| {
                        let u = s as f64 / n as f64;
                        std::array::from_fn(|k| a[k] + u * (b[k] - a[k]))
                    })
                    .collect()
            }
        };
        let before = fixed.len();
        for p in samples {
            let node = nearest(&positions, p);
            if owner[node] == usize::MAX {
                owner[node] = i;
                fixed.push((node, i));
            }
        }
        if fixed.len() == before {
            return Err(SurfaceWeightsError::BadHandle {
                handle: i,
                what: "its nearest grid nodes all belong to earlier handles; raise the volume \
                       resolution or move the handles apart"
                    .into(),
            });
        }
    }
    Ok(fixed)
}

/// Marks outside the inside nodes whose 6-connected part holds no fixed node, and renumbers
/// (the fixed nodes' numbers in `fixed` follow).
fn keep_parts_with_handles(grid: &mut VolumeGrid, fixed: &mut [(usize, usize)]) {
    let n = grid.nodes.len();
    let mut reached = vec![false; n];
    let mut stack: Vec<usize> = fixed.iter().map(|&(v, _)| v).collect();
    for &v in &stack {
        reached[v] = true;
    }
    while let Some(v) = stack.pop() {
        let neighbours: Vec<usize> = grid.neighbours(grid.nodes[v]).collect();
        for m in neighbours {
            let row = grid.index[m];
            if row != OUTSIDE && !reached[row as usize] {
                reached[row as usize] = true;
                stack.push(row as usize);
            }
        }
    }
    if reached.iter().all(|&r| r) {
        return;
    }
    let mut renumber = vec![OUTSIDE; n];
    let mut kept = Vec::new();
    for (v, &g) in grid.nodes.iter().enumerate() {
        if reached[v] {
            renumber[v] = kept.len() as u32;
            kept.push(g);
        } else {
            grid.index[g] = OUTSIDE;
        }
    }
    for (k, &g) in kept.iter().enumerate() {
        grid.index[g] = k as u32;
    }
    grid.nodes = kept;
    for f in fixed.iter_mut() {
        f.0 = renumber[f.0] as usize;
    }
}

/// `Q = G G` on the inside nodes and the handles' Dirichlet data.
fn energy_and_data(
    grid: &VolumeGrid,
    fixed: &[(usize, usize)],
    n_handles: usize,
) -> Result<(Csc, DirichletData), SurfaceWeightsError> {
    let n = grid.nodes.len();
    let mut triplets = Vec::with_capacity(7 * n);
    for (v, &g) in grid.nodes.iter().enumerate() {
        let mut degree = 0.0;
        for m in grid.neighbours(g) {
            let row = grid.index[m];
            if row != OUTSIDE {
                triplets.push((v, row as usize, -1.0));
                degree += 1.0;
            }
        }
        triplets.push((v, v, degree));
    }
    let laplacian = Csc::from_triplets(n, triplets);
    let q = laplacian.times_diagonal_times(&vec![1.0; n], &laplacian);
    let vertices = fixed.iter().map(|&(v, _)| v).collect();
    let mut values = vec![0.0; fixed.len() * n_handles];
    for (r, &(_, i)) in fixed.iter().enumerate() {
        values[r * n_handles + i] = 1.0;
    }
    let data =
        DirichletData::new(vertices, values, n_handles).map_err(|e| volume_error(e.to_string()))?;
    Ok((q, data))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{parse_obj, LimitOptions};

    /// A 4 × 1 × 1 bar; without its top face when `open`.
    fn bar(open: bool) -> Cage {
        let mut text = String::from(
            "v 0 0 0\nv 4 0 0\nv 4 1 0\nv 0 1 0\nv 0 0 1\nv 4 0 1\nv 4 1 1\nv 0 1 1\n\
             f 1 4 3 2\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n",
        );
        if !open {
            text.push_str("f 5 6 7 8\n");
        }
        parse_obj(&text, "bar.obj").unwrap()
    }

    fn weights(cage: &Cage) -> VolumeBbw {
        let surface = LimitSurface::new(cage, &LimitOptions::default()).unwrap();
        let handles = Handles3::new(vec![[0.8, 0.5, 0.5], [3.2, 0.5, 0.5]], vec![]).unwrap();
        VolumeBbw::new(cage, &surface, &handles, &VolumeBbwOptions::default()).unwrap()
    }

    #[test]
    fn the_weights_interpolate_the_handles_at_their_nodes() {
        let w = weights(&bar(false));
        let mut row = [0.0; 2];
        for (i, p) in [[0.8, 0.5, 0.5], [3.2, 0.5, 0.5]].into_iter().enumerate() {
            let node = nearest(&w.positions, p);
            w.eval_at(w.positions[node], &mut row);
            let mut want = [0.0; 2];
            want[i] = 1.0;
            assert_eq!(row, want, "handle {i} at its node");
        }
    }

    #[test]
    fn an_open_cage_still_has_a_volume_and_bounded_weights() {
        // Without its top, the bar's inside reaches the outside through the opening: the
        // winding number votes inside near the bottom, and the band keeps the walls.
        let (open, closed) = (weights(&bar(true)), weights(&bar(false)));
        assert!(open.n_nodes() > 0 && open.n_nodes() <= closed.n_nodes() + closed.n_nodes() / 2);
        let mut row = [0.0; 2];
        for x in [0.0, 1.0, 2.0, 3.0, 4.0] {
            open.eval_at([x, 0.5, 0.1], &mut row);
            assert!(row.iter().all(|w| (0.0..=1.0).contains(w)), "{row:?}");
            assert!((row[0] + row[1] - 1.0).abs() < 1e-12);
        }
        open.eval_at([0.2, 0.5, 0.2], &mut row);
        assert!(row[0] > 0.9, "{row:?}");
    }

    #[test]
    fn a_resolution_out_of_range_is_refused() {
        let cage = bar(false);
        let surface = LimitSurface::new(&cage, &LimitOptions::default()).unwrap();
        let handles = Handles3::new(vec![[0.8, 0.5, 0.5]], vec![]).unwrap();
        let options = VolumeBbwOptions::default().with_resolution(2);
        let e = VolumeBbw::new(&cage, &surface, &handles, &options)
            .err()
            .unwrap();
        assert!(e.to_string().contains("volume resolution 2"), "{e}");
    }
}
