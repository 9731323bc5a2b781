//! The inside of a surface as the nodes of a regular grid, classified by generalized winding
//! number (Jacobson, Kavan & Sorkine-Hornung 2013, *Robust inside-outside segmentation using
//! generalized winding numbers*):
//!
//! ```text
//! w(p) = (1 / 4π) Σ_t Ω_t(p),    Ω_t(p) = 2 atan2(a · (b × c), |a||b||c| + (a·b)|c| + (b·c)|a| + (c·a)|b|)
//! ```
//!
//! with `a, b, c` the corners of triangle `t` minus `p` (Van Oosterom & Strackee 1983): `1`
//! inside a closed surface, `0` outside, and a smooth vote in between where the surface is open,
//! has holes or touches itself. A node is inside when `w ≥ ½`, **or** when it lies within
//! `(√3 / 2) h` of the surface: then every point of the surface has a node of its cell in the
//! volume (the nearest corner of its cell is at most that far from it), so thin parts and open
//! shells (a car's body panels) are a band of nodes rather than nothing.
//!
//! `w` is constant away from a closed surface, so it is computed at a few nodes of each part of
//! the grid the band leaves, and at every node only of a part where they disagree
//! ([`VolumeGrid::inside_off_band`]).

use super::super::cage::Point3;
use splineskin_core::mesh::vec3::{cross, dot, norm, sub};

/// Nodes of each part off the surface band whose winding numbers are compared (module
/// documentation).
const WINDING_SAMPLES: usize = 8;

/// The node marker of [`VolumeGrid::index`] for a node outside.
pub(crate) const OUTSIDE: u32 = u32::MAX;

/// A regular grid of nodes `origin + h · (i, j, k)` over a surface's bounding box (padded by a
/// cell on every side), each node inside or not.
#[derive(Clone, Debug)]
pub(crate) struct VolumeGrid {
    pub origin: Point3,
    /// The cell side.
    pub h: f64,
    /// Nodes per axis.
    pub dims: [usize; 3],
    /// Number of every inside node among the inside nodes, [`OUTSIDE`] for the others.
    pub index: Vec<u32>,
    /// The grid node of every inside node.
    pub nodes: Vec<usize>,
}

impl VolumeGrid {
    /// The grid of `resolution` cells along the longest side of the bounding box of
    /// `points`, its nodes inside the surface of `triangles` (over `points`) marked.
    pub fn new(points: &[Point3], triangles: &[[u32; 3]], resolution: usize) -> VolumeGrid {
        let (lo, hi) = super::super::cage::bounds3(points);
        let longest = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
        let h = longest / resolution as f64;
        let origin = lo.map(|c| c - h);
        let dims: [usize; 3] = std::array::from_fn(|k| ((hi[k] - lo[k]) / h).ceil() as usize + 3);
        let mut grid = VolumeGrid {
            origin,
            h,
            dims,
            index: Vec::new(),
            nodes: Vec::new(),
        };
        let band = grid.surface_band(points, triangles);
        let inside = grid.inside_off_band(&band, points, triangles);
        grid.index = vec![OUTSIDE; band.len()];
        for g in 0..band.len() {
            if inside[g] || band[g] {
                grid.index[g] = grid.nodes.len() as u32;
                grid.nodes.push(g);
            }
        }
        grid
    }

    pub fn n_grid_nodes(&self) -> usize {
        self.dims[0] * self.dims[1] * self.dims[2]
    }

    /// The grid node at `(i, j, k)`.
    pub fn node(&self, [i, j, k]: [usize; 3]) -> usize {
        i + self.dims[0] * (j + self.dims[1] * k)
    }

    /// `(i, j, k)` of grid node `g`.
    pub fn cell_of(&self, g: usize) -> [usize; 3] {
        let [nx, ny, _] = self.dims;
        [g % nx, (g / nx) % ny, g / (nx * ny)]
    }

    /// Where grid node `g` is.
    pub fn position(&self, g: usize) -> Point3 {
        let ijk = self.cell_of(g);
        std::array::from_fn(|k| self.origin[k] + self.h * ijk[k] as f64)
    }

    /// The grid nodes 6-adjacent to `g`.
    pub fn neighbours(&self, g: usize) -> impl Iterator<Item = usize> + '_ {
        let ijk = self.cell_of(g);
        (0..3).flat_map(move |axis| {
            [-1i64, 1].into_iter().filter_map(move |step| {
                let c = ijk[axis] as i64 + step;
                (c >= 0 && (c as usize) < self.dims[axis]).then(|| {
                    let mut n = ijk;
                    n[axis] = c as usize;
                    self.node(n)
                })
            })
        })
    }

    /// Whether each grid node off the band is inside (`w ≥ ½`; band nodes are `false` here).
    ///
    /// The band separates the grid (a 6-connected path of nodes off it cannot cross the
    /// surface: an edge of length `h` crossing it has an end within `h / 2` of it), and `w` is
    /// constant on each connected part of the rest when the surface is closed. So `w` is taken
    /// at [`WINDING_SAMPLES`] nodes spread over each part; where they disagree (the part reaches
    /// through a hole of an open surface), at every node of that part.
    fn inside_off_band(
        &self,
        band: &[bool],
        points: &[Point3],
        triangles: &[[u32; 3]],
    ) -> Vec<bool> {
        let n = self.n_grid_nodes();
        let inside_at = |g: &usize| winding_number(self.position(*g), points, triangles) >= 0.5;
        let mut inside = vec![false; n];
        let mut seen = vec![false; n];
        for seed in 0..n {
            if band[seed] || seen[seed] {
                continue;
            }
            let part = self.part_of(seed, band, &mut seen);
            let stride = part.len().div_ceil(WINDING_SAMPLES).max(1);
            let samples: Vec<usize> = part.iter().step_by(stride).copied().collect();
            let votes = parallel_map(&samples, inside_at);
            let value = if votes.iter().all(|&v| v == votes[0]) {
                vec![votes[0]; part.len()]
            } else {
                parallel_map(&part, inside_at)
            };
            for (&g, v) in part.iter().zip(value) {
                inside[g] = v;
            }
        }
        inside
    }

    /// The 6-connected part of the nodes off `band` holding `seed`, marking them seen.
    fn part_of(&self, seed: usize, band: &[bool], seen: &mut [bool]) -> Vec<usize> {
        let mut part = vec![seed];
        seen[seed] = true;
        let mut next = 0;
        while next < part.len() {
            let g = part[next];
            next += 1;
            for m in self.neighbours(g) {
                if !band[m] && !seen[m] {
                    seen[m] = true;
                    part.push(m);
                }
            }
        }
        part
    }

    /// Nodes within `(√3 / 2) h` of some triangle (module documentation).
    fn surface_band(&self, points: &[Point3], triangles: &[[u32; 3]]) -> Vec<bool> {
        let reach = 0.5 * 3f64.sqrt() * self.h;
        let mut band = vec![false; self.n_grid_nodes()];
        for t in triangles {
            let corners = t.map(|v| points[v as usize]);
            let range = self.node_range(&corners);
            for k in range[2].0..=range[2].1 {
                for j in range[1].0..=range[1].1 {
                    for i in range[0].0..=range[0].1 {
                        let g = self.node([i, j, k]);
                        if !band[g] && distance_to_triangle(self.position(g), corners) <= reach {
                            band[g] = true;
                        }
                    }
                }
            }
        }
        band
    }

    /// The nodes `(first, last)` per axis within a cell of the bounding box of `corners`.
    fn node_range(&self, corners: &[Point3; 3]) -> [(usize, usize); 3] {
        std::array::from_fn(|k| {
            let lo = corners.iter().map(|p| p[k]).fold(f64::INFINITY, f64::min);
            let hi = corners
                .iter()
                .map(|p| p[k])
                .fold(f64::NEG_INFINITY, f64::max);
            let first = (((lo - self.origin[k]) / self.h).floor() - 1.0).max(0.0) as usize;
            let last = (((hi - self.origin[k]) / self.h).ceil() + 1.0).max(0.0) as usize;
            (first, last.min(self.dims[k] - 1))
        })
    }
}

/// The distance from `p` to the triangle `[a, b, c]` (its closest point by the Voronoi regions
/// of the corners, edges and face: Ericson, *Real-Time Collision Detection*, §5.1.5).
pub(crate) fn distance_to_triangle(p: Point3, [a, b, c]: [Point3; 3]) -> f64 {
    let (ab, ac, ap) = (sub(b, a), sub(c, a), sub(p, a));
    let along =
        |x: Point3, s: f64, d: Point3| -> Point3 { std::array::from_fn(|k| x[k] + s * d[k]) };
    let (d1, d2) = (dot(ab, ap), dot(ac, ap));
    let closest = if d1 <= 0.0 && d2 <= 0.0 {
        a
    } else {
        let bp = sub(p, b);
        let (d3, d4) = (dot(ab, bp), dot(ac, bp));
        let cp = sub(p, c);
        let (d5, d6) = (dot(ab, cp), dot(ac, cp));
        let vc = d1 * d4 - d3 * d2;
        let vb = d5 * d2 - d1 * d6;
        let va = d3 * d6 - d5 * d4;
        if d3 >= 0.0 && d4 <= d3 {
            b
        } else if d6 >= 0.0 && d5 <= d6 {
            c
        } else if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
            along(a, d1 / (d1 - d3), ab)
        } else if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
            along(a, d2 / (d2 - d6), ac)
        } else if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
            along(b, (d4 - d3) / ((d4 - d3) + (d5 - d6)), sub(c, b))
        } else {
            let denominator = va + vb + vc;
            if denominator.abs() < f64::MIN_POSITIVE {
                // A degenerate (zero-area) triangle: its nearest corner.
                [a, b, c]
                    .into_iter()
                    .min_by(|x, y| norm(sub(p, *x)).total_cmp(&norm(sub(p, *y))))
                    .unwrap_or(a)
            } else {
                let (v, w) = (vb / denominator, vc / denominator);
                std::array::from_fn(|k| a[k] + v * ab[k] + w * ac[k])
            }
        }
    };
    norm(sub(p, closest))
}

/// `f` of every item, on rayon's threads.
fn parallel_map<T: Sync, U: Send>(items: &[T], f: impl Fn(&T) -> U + Sync) -> Vec<U> {
    splineskin_core::parallel::try_map(items, true, |_, x| Ok::<U, std::convert::Infallible>(f(x)))
        .unwrap_or_else(|never| match never {})
}

/// The generalized winding number of the triangles at `p` (module documentation).
pub(crate) fn winding_number(p: Point3, points: &[Point3], triangles: &[[u32; 3]]) -> f64 {
    let mut total = 0.0;
    for t in triangles {
        let [a, b, c] = t.map(|v| sub(points[v as usize], p));
        let (la, lb, lc) = (norm(a), norm(b), norm(c));
        let numerator = dot(a, cross(b, c));
        let denominator = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb;
        total += 2.0 * numerator.atan2(denominator);
    }
    total / (4.0 * std::f64::consts::PI)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube() -> (Vec<Point3>, Vec<[u32; 3]>) {
        crate::test_support::unit_cube_triangles()
    }

    #[test]
    fn winding_number_is_one_inside_zero_outside_and_a_half_on_the_surface() {
        let (p, t) = cube();
        assert!((winding_number([0.5, 0.5, 0.5], &p, &t) - 1.0).abs() < 1e-12);
        assert!(winding_number([2.0, 0.5, 0.5], &p, &t).abs() < 1e-12);
        assert!((winding_number([0.5, 0.5, 0.0], &p, &t) - 0.5).abs() < 1e-12);
        // Open (the top removed): inside still votes above a half near the bottom.
        let open: Vec<[u32; 3]> = t
            .iter()
            .copied()
            .filter(|f| !f.iter().all(|&v| v >= 4))
            .collect();
        assert!(winding_number([0.5, 0.5, 0.2], &p, &open) > 0.5);
        assert!(winding_number([0.5, 0.5, 3.0], &p, &open) < 0.5);
    }

    #[test]
    fn distance_to_a_triangle_from_each_region() {
        let t = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]];
        assert_eq!(distance_to_triangle([0.5, 0.5, 3.0], t), 3.0); // above the face
        assert_eq!(distance_to_triangle([-3.0, -4.0, 0.0], t), 5.0); // beyond corner a
        assert_eq!(distance_to_triangle([1.0, -2.0, 0.0], t), 2.0); // beyond edge ab
        let d = distance_to_triangle([2.0, 2.0, 0.0], t); // beyond edge bc
        assert!((d - 2f64.sqrt()).abs() < 1e-15, "{d}");
        assert_eq!(distance_to_triangle([5.0, 0.0, 0.0], t), 3.0); // beyond corner b
    }

    #[test]
    fn the_grid_marks_the_cubes_inside() {
        let (p, t) = cube();
        let grid = VolumeGrid::new(&p, &t, 8);
        // Nodes at multiples of 1/8 from −1/8: the 9³ in the closed cube are in (inside, or on
        // the surface and so in its band); the layer one step outside is 1/8 from the faces,
        // beyond the band's (√3 / 2) / 8.
        assert_eq!(grid.nodes.len(), 9 * 9 * 9);
        for &g in &grid.nodes {
            let q = grid.position(g);
            assert!(
                q.iter().all(|&c| (-1e-12..=1.0 + 1e-12).contains(&c)),
                "{q:?}"
            );
        }
    }
}
