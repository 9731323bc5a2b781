//! Weights given at the vertices of a triangle mesh, evaluated anywhere by point location and
//! barycentric interpolation: the [`crate::weights::WeightField`] of the mesh-based families
//! (harmonic, biharmonic, bounded biharmonic; DESIGN.md §2; the trait is implemented in
//! `weights`, which builds on this module).
//!
//! Inside triangle `(a, b, c)` the weights are the linear interpolant
//!
//! ```text
//! w(p) = λ_a W_a + λ_b W_b + λ_c W_c,   λ_a = (b − p) × (c − p) / ((b − a) × (c − a)),  …
//! ```
//!
//! (`W_v` the row of vertex `v`), which reproduces every affine function exactly. Outside the
//! mesh (and in its holes) a point takes the weights of the nearest point of the mesh boundary,
//! interpolated linearly along that boundary edge (DESIGN.md §2). The result is continuous
//! everywhere and smooth inside each triangle; across mesh edges it is only C⁰, which is what
//! [`MeshWeights::edge_crossings`] reports to the quadrature.
//!
//! **Integration error.** Restricted to a cubic `B(t)`, the interpolant is a cubic polynomial in
//! `t` on each piece between consecutive edge crossings, so `w_i(B(t)) b(t) b(t)ᵀ` has degree
//! 9 there and the default composite rule (8 Gauss–Legendre nodes per piece, exact to degree
//! 15; `spline_fit::quadrature`) integrates it exactly — the only error left is rounding and
//! the accuracy of the crossing parameters ([`super::crossings::T_ACCURACY`]). The test
//! `kinks_make_weighted_grams_exact` (in `weights::mesh_field`) measures it against an independent exact integration on a
//! structured mesh: ≤ 1e-13 relative to `ℓ_j Â_00` (measured 1.1e-15; the same rule without
//! the kinks is off by 1.2e-3). Outside
//! the mesh the nearest-boundary weights are smooth between changes of the nearest feature,
//! which are not reported: curves outside the domain are integrated to the accuracy of the
//! rule on a merely continuous function. Parts of the art attached to a vertex
//! ([`MeshWeights::with_attachments`]) take that vertex's weights everywhere in them: constant,
//! so integrated exactly.

use kurbo::{CubicBez, ParamCurve, Point, Rect};

use super::crossings::cubic_segment_crossings;
use super::grid::BucketGrid;
use super::polygon::{segment_distance, PolygonIndex};
use super::{Attachment, DomainError};
use crate::mesh::TriMesh;

/// Barycentric slack of point location: `1e-12`. A point whose smallest barycentric
/// coordinate in a triangle is above `−1e-12` counts as inside it. Interior points on an edge
/// are found in either neighbour (the interpolant is continuous, so both give the same value to
/// rounding); the slack only keeps points on the mesh boundary, after rounding, on the fast path.
pub const BARYCENTRIC_SLACK: f64 = 1e-12;

/// Two crossing parameters closer than this are one kink: `1e-12` (in `t`). A curve through a
/// mesh vertex crosses every edge meeting there at (nearly) the same parameter.
pub const KINK_MERGE: f64 = 1e-12;

/// Largest number of pieces a curve is cut into to gather the mesh edges near it: 4096.
const MAX_COVER_PIECES: usize = 4096;

/// Per-vertex weights on a triangle mesh, evaluated by point location (a uniform grid of
/// triangle buckets) and barycentric interpolation. Immutable once built, so `Send + Sync`.
///
/// ```
/// use kurbo::Point;
/// use splineskin_core::domain::MeshWeights;
/// use splineskin_core::mesh::TriMesh;
/// use splineskin_core::weights::WeightField;
///
/// // The unit square, two triangles; one handle whose weight is x + 2y.
/// let v = [(0., 0.), (1., 0.), (1., 1.), (0., 1.)].map(Point::from).to_vec();
/// let mesh = TriMesh::new(v, vec![[0, 1, 2], [0, 2, 3]])?;
/// let w = MeshWeights::new(&mesh, vec![0.0, 1.0, 3.0, 2.0], 1)?;
/// let mut out = [0.0];
/// w.eval(Point::new(0.25, 0.5), &mut out);
/// assert!((out[0] - 1.25).abs() < 1e-15);
/// // Outside: the nearest boundary point, here (1, 0.5).
/// w.eval(Point::new(3.0, 0.5), &mut out);
/// assert!((out[0] - 2.0).abs() < 1e-15);
/// // The straight cubic from (0, 0.5) to (1, 0.5) crosses the diagonal at t = ½.
/// let line = [(0., 0.5), (1. / 3., 0.5), (2. / 3., 0.5), (1., 0.5)].map(Point::from);
/// let mut kinks = Vec::new();
/// w.kinks(&line, &mut kinks);
/// assert_eq!(kinks.len(), 1);
/// assert!((kinks[0] - 0.5).abs() < 1e-14);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct MeshWeights {
    vertices: Vec<Point>,
    triangles: Vec<[u32; 3]>,
    /// `n_vertices × n_handles`, row-major.
    weights: Vec<f64>,
    n_handles: usize,
    triangle_grid: BucketGrid,
    /// Unique undirected edges.
    edges: Vec<[u32; 2]>,
    edge_grid: BucketGrid,
    /// Boundary edges (one triangle only), as vertex pairs.
    boundary: Vec<[u32; 2]>,
    boundary_grid: BucketGrid,
    /// Parts outside the mesh that take one vertex's weights ([`MeshWeights::with_attachments`]).
    attached: Vec<AttachedPart>,
}

/// An [`Attachment`] indexed for containment tests.
#[derive(Clone, Debug)]
struct AttachedPart {
    bounds: Rect,
    region: PolygonIndex,
    vertex: u32,
}

impl MeshWeights {
    /// Weights `weights` (`mesh.n_vertices() × n_handles`, row-major: entry `v · n_handles + i`
    /// is `w_i` at vertex `v`) on `mesh`.
    ///
    /// Errors: an invalid mesh ([`TriMesh::check`]), more than `u32::MAX` vertices, a wrong
    /// length, a non-finite weight, no handles, or an edge shared by more than two triangles.
    pub fn new(
        mesh: &TriMesh,
        weights: Vec<f64>,
        n_handles: usize,
    ) -> Result<MeshWeights, DomainError> {
        mesh.check()?;
        let n_vertices = mesh.n_vertices();
        if n_handles == 0 {
            return Err(DomainError::NoHandles);
        }
        if n_vertices > u32::MAX as usize || mesh.n_triangles() > u32::MAX as usize {
            return Err(DomainError::TooLarge {
                n_vertices,
                n_triangles: mesh.n_triangles(),
            });
        }
        let expected = n_vertices.checked_mul(n_handles);
        if expected != Some(weights.len()) {
            return Err(DomainError::WeightsLength {
                n_vertices,
                n_handles,
                len: weights.len(),
            });
        }
        if let Some(k) = weights.iter().position(|w| !w.is_finite()) {
            return Err(DomainError::NonFiniteWeight {
                vertex: k / n_handles,
                handle: k % n_handles,
            });
        }
        let triangles: Vec<[u32; 3]> = mesh.triangles.iter().map(|t| t.map(|v| v as u32)).collect();

        // Unique edges with their triangle counts: sort the directed half-edges by their
        // undirected key.
        let mut half: Vec<([u32; 2], u32)> = Vec::with_capacity(3 * triangles.len());
        for t in &triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                half.push(([a.min(b), a.max(b)], a));
            }
        }
        half.sort_unstable();
        let mut edges = Vec::with_capacity(half.len() / 2 + 1);
        let mut boundary = Vec::new();
        let mut k = 0;
        while k < half.len() {
            let key = half[k].0;
            let mut l = k + 1;
            while l < half.len() && half[l].0 == key {
                l += 1;
            }
            match l - k {
                1 => {
                    // Oriented as in its triangle (the mesh on its left).
                    let a = half[k].1;
                    let b = if a == key[0] { key[1] } else { key[0] };
                    boundary.push([a, b]);
                }
                2 => {}
                n_triangles => {
                    return Err(DomainError::NonManifoldEdge {
                        a: key[0] as usize,
                        b: key[1] as usize,
                        n_triangles,
                    })
                }
            }
            edges.push(key);
            k = l;
        }

        let vertices = mesh.vertices.clone();
        let bounds = vertices
            .iter()
            .fold(Rect::from_points(vertices[0], vertices[0]), |r, &p| {
                r.union_pt(p)
            });
        // About one triangle per cell on average.
        let cell = (bounds.area() / triangles.len() as f64).sqrt();
        let triangle_grid = BucketGrid::build(bounds, cell, triangles.len(), |k, emit| {
            let [a, b, c] = triangles[k].map(|v| vertices[v as usize]);
            emit(Rect::from_points(a, b).union_pt(c));
        });
        let cell = triangle_grid.cell_size();
        let segment = |e: &[u32; 2]| (vertices[e[0] as usize], vertices[e[1] as usize]);
        let edge_grid = BucketGrid::build(bounds, cell, edges.len(), |k, emit| {
            let (a, b) = segment(&edges[k]);
            BucketGrid::segment_pieces(cell, a, b, emit);
        });
        let boundary_grid = BucketGrid::build(bounds, cell, boundary.len(), |k, emit| {
            let (a, b) = segment(&boundary[k]);
            BucketGrid::segment_pieces(cell, a, b, emit);
        });
        Ok(MeshWeights {
            vertices,
            triangles,
            weights,
            n_handles,
            triangle_grid,
            edges,
            edge_grid,
            boundary,
            boundary_grid,
            attached: Vec::new(),
        })
    }

    /// These weights where every point of an attached part (outside the mesh, inside the
    /// part's loops) takes the weights of the part's vertex: the parts of an art-shaped domain
    /// left out for holding no handle ([`super::Domain::attachments`]) move as one piece with
    /// the art beside them. Attachments naming a vertex out of range, or without a loop, are
    /// ignored.
    ///
    /// ```
    /// use kurbo::Point;
    /// use splineskin_core::domain::{Attachment, MeshWeights};
    /// use splineskin_core::mesh::TriMesh;
    /// use splineskin_core::weights::WeightField;
    ///
    /// let v = [(0., 0.), (1., 0.), (1., 1.), (0., 1.)].map(Point::from).to_vec();
    /// let mesh = TriMesh::new(v, vec![[0, 1, 2], [0, 2, 3]])?;
    /// let square = [(3., 0.), (4., 0.), (4., 1.), (3., 1.)].map(Point::from).to_vec();
    /// let w = MeshWeights::new(&mesh, vec![0.0, 1.0, 3.0, 2.0], 1)?
    ///     .with_attachments(&[Attachment { loops: vec![square], vertex: 2 }]);
    /// let mut out = [0.0];
    /// // In the attached square: vertex 2's weight, wherever.
    /// w.eval(Point::new(3.2, 0.1), &mut out);
    /// assert_eq!(out[0], 3.0);
    /// // Elsewhere outside: the nearest boundary point's, as before.
    /// w.eval(Point::new(2.0, 0.5), &mut out);
    /// assert!((out[0] - 2.0).abs() < 1e-15);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn with_attachments(mut self, attachments: &[Attachment]) -> MeshWeights {
        self.attached = attachments
            .iter()
            .filter(|a| a.vertex < self.vertices.len() && a.loops.iter().any(|l| l.len() >= 3))
            .map(|a| {
                let loops: Vec<&[Point]> = a.loops.iter().map(Vec::as_slice).collect();
                let region = PolygonIndex::new(&loops);
                AttachedPart {
                    bounds: region.bounds(),
                    region,
                    vertex: a.vertex as u32,
                }
            })
            .collect();
        self
    }

    /// The vertex of the attached part holding `p`, if any.
    fn attached_vertex(&self, p: Point) -> Option<u32> {
        self.attached
            .iter()
            .find(|a| a.bounds.contains(p) && a.region.contains(p))
            .map(|a| a.vertex)
    }

    /// Number of mesh vertices.
    pub fn n_vertices(&self) -> usize {
        self.vertices.len()
    }

    /// The weights of all handles at vertex `v` (a row of the matrix given to
    /// [`MeshWeights::new`]).
    pub fn vertex_weights(&self, v: usize) -> &[f64] {
        &self.weights[v * self.n_handles..(v + 1) * self.n_handles]
    }

    /// Number of boundary edges (edges of one triangle only).
    pub fn n_boundary_edges(&self) -> usize {
        self.boundary.len()
    }

    /// The triangle containing `p` and its barycentric coordinates, or `None` if `p` is outside
    /// the mesh (by more than [`BARYCENTRIC_SLACK`]).
    ///
    /// ```
    /// use kurbo::Point;
    /// use splineskin_core::domain::MeshWeights;
    /// use splineskin_core::mesh::TriMesh;
    /// let v = [(0., 0.), (2., 0.), (0., 2.)].map(Point::from).to_vec();
    /// let mesh = TriMesh::new(v, vec![[0, 1, 2]])?;
    /// let w = MeshWeights::new(&mesh, vec![1.0, 0.0, 0.0], 1)?;
    /// let (t, l) = w.locate(Point::new(0.5, 0.5)).unwrap();
    /// assert_eq!(t, 0);
    /// assert!((l[0] - 0.5).abs() < 1e-15 && (l[1] - 0.25).abs() < 1e-15);
    /// assert!(w.locate(Point::new(2.0, 2.0)).is_none());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn locate(&self, p: Point) -> Option<(usize, [f64; 3])> {
        let (ix, iy) = self.triangle_grid.cell_of(p);
        let mut best: Option<(usize, [f64; 3])> = None;
        let mut best_min = f64::NEG_INFINITY;
        for &t in self.triangle_grid.bucket(ix, iy) {
            let l = self.barycentric(t as usize, p);
            let m = l[0].min(l[1]).min(l[2]);
            if m >= 0.0 {
                return Some((t as usize, l));
            }
            if m > best_min {
                best_min = m;
                best = Some((t as usize, l));
            }
        }
        best.filter(|_| best_min >= -BARYCENTRIC_SLACK)
    }

    /// Barycentric coordinates of `p` in triangle `t` (see the module documentation).
    #[inline]
    fn barycentric(&self, t: usize, p: Point) -> [f64; 3] {
        let [a, b, c] = self.triangles[t].map(|v| self.vertices[v as usize]);
        let area2 = (b - a).cross(c - a);
        let la = (b - p).cross(c - p) / area2;
        let lb = (c - p).cross(a - p) / area2;
        [la, lb, 1.0 - la - lb]
    }

    /// The nearest point of the mesh boundary to `p`: boundary edge index and parameter along
    /// it. A ring search over the grid's cells, stopped once no unvisited cell can be nearer.
    fn nearest_boundary(&self, p: Point) -> Option<(usize, f64)> {
        let (cx, cy) = self.boundary_grid.cell_of(p);
        let (nx, ny) = self.boundary_grid.dims();
        let cell = self.boundary_grid.cell_size();
        let mut best: Option<(usize, f64)> = None;
        let mut best_d = f64::INFINITY;
        let visit = |bucket: &[u32], best: &mut Option<(usize, f64)>, best_d: &mut f64| {
            for &e in bucket {
                let [a, b] = self.boundary[e as usize];
                let (d, s) =
                    segment_distance(p, self.vertices[a as usize], self.vertices[b as usize]);
                if d < *best_d {
                    *best_d = d;
                    *best = Some((e as usize, s));
                }
            }
        };
        for r in 0..nx.max(ny) {
            let (x0, x1) = (cx.saturating_sub(r), (cx + r).min(nx - 1));
            let (y0, y1) = (cy.saturating_sub(r), (cy + r).min(ny - 1));
            for iy in y0..=y1 {
                let on_edge_row = iy + r == cy || iy == cy + r;
                if on_edge_row {
                    for ix in x0..=x1 {
                        visit(self.boundary_grid.bucket(ix, iy), &mut best, &mut best_d);
                    }
                } else {
                    if cx >= r {
                        visit(
                            self.boundary_grid.bucket(cx - r, iy),
                            &mut best,
                            &mut best_d,
                        );
                    }
                    if r > 0 && cx + r < nx {
                        visit(
                            self.boundary_grid.bucket(cx + r, iy),
                            &mut best,
                            &mut best_d,
                        );
                    }
                }
            }
            // Every cell not yet visited is more than r cells away on some axis, so at least
            // r · cell from p.
            if best_d <= r as f64 * cell {
                break;
            }
        }
        best
    }
}

/// Where a point falls in the mesh: the (up to) three vertices whose values interpolate there
/// and their coefficients (see [`MeshWeights::interpolation`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interpolation {
    /// The vertices: a triangle's corners, or a boundary edge's two ends and (coefficient 0)
    /// the first again.
    pub vertices: [u32; 3],
    /// Their coefficients (barycentric inside; `1 − s`, `s`, 0 along the nearest boundary
    /// edge outside). They sum to one.
    pub coefficients: [f64; 3],
    /// Distance from the point to the mesh (0 inside), drawing units.
    pub outside_distance: f64,
}

impl MeshWeights {
    /// The vertices and coefficients that interpolate vertex values at `p` (the module doc's
    /// rule: barycentric inside a triangle, the nearest boundary point's linear interpolation
    /// along its edge outside), or `None` for a mesh without boundary (unreachable for a valid
    /// mesh). Every weight this field evaluates is `Σ coefficient · W_vertex`.
    pub fn interpolation(&self, p: Point) -> Option<Interpolation> {
        if let Some((t, l)) = self.locate(p) {
            return Some(Interpolation {
                vertices: self.triangles[t],
                coefficients: l,
                outside_distance: 0.0,
            });
        }
        if let Some(v) = self.attached_vertex(p) {
            return Some(Interpolation {
                vertices: [v, v, v],
                coefficients: [1.0, 0.0, 0.0],
                outside_distance: (p - self.vertices[v as usize]).hypot(),
            });
        }
        let (e, s) = self.nearest_boundary(p)?;
        let [a, b] = self.boundary[e];
        let (pa, pb) = (self.vertices[a as usize], self.vertices[b as usize]);
        Some(Interpolation {
            vertices: [a, b, a],
            coefficients: [1.0 - s, s, 0.0],
            outside_distance: (p - pa.lerp(pb, s)).hypot(),
        })
    }
}

impl MeshWeights {
    /// Number of handles (weights per vertex).
    pub fn n_handles(&self) -> usize {
        self.n_handles
    }

    /// Writes the weights at `p` into `out` (`n_handles` long): the barycentric interpolant
    /// of the vertex weights inside the mesh, the nearest boundary point's outside (module
    /// doc); NaN for a mesh without boundary (unreachable for a valid mesh). The mesh-family
    /// weight fields evaluate through this ([`crate::weights::WeightField::eval`]).
    pub fn weights_at(&self, p: Point, out: &mut [f64]) {
        let h = self.n_handles;
        debug_assert_eq!(out.len(), h);
        match self.interpolation(p) {
            Some(at) => {
                out.fill(0.0);
                for (&v, &c) in at.vertices.iter().zip(&at.coefficients) {
                    let w = self.vertex_weights(v as usize);
                    for (o, &wv) in out.iter_mut().zip(w) {
                        *o += c * wv;
                    }
                }
            }
            // A valid mesh has a boundary; unreachable, but never panic in evaluation.
            None => out.fill(f64::NAN),
        }
    }

    /// Appends the parameters where the cubic crosses mesh edges (interior and boundary),
    /// found exactly on the cubic ([`super::crossings`]), merged when closer than
    /// [`KINK_MERGE`], ascending: where the interpolant is only C⁰ along the curve (the
    /// field's [`crate::weights::WeightField::kinks`]).
    pub fn edge_crossings(&self, curve: &[Point; 4], out: &mut Vec<f64>) {
        let start = out.len();
        let cubic = CubicBez::new(curve[0], curve[1], curve[2], curve[3]);
        let polygon_len = (curve[1] - curve[0]).hypot()
            + (curve[2] - curve[1]).hypot()
            + (curve[3] - curve[2]).hypot();
        let cell = self.edge_grid.cell_size();
        let n_pieces = if polygon_len.is_finite() {
            ((polygon_len / cell).ceil() as usize).clamp(1, MAX_COVER_PIECES)
        } else {
            return;
        };
        // Edges in the cells covered by the pieces' control-point boxes (each piece lies in the
        // convex hull of its control points).
        let mut candidates: Vec<u32> = Vec::new();
        for k in 0..n_pieces {
            let piece =
                cubic.subsegment(k as f64 / n_pieces as f64..(k + 1) as f64 / n_pieces as f64);
            let r = Rect::from_points(piece.p0, piece.p1)
                .union_pt(piece.p2)
                .union_pt(piece.p3);
            self.edge_grid
                .for_cells_in(r, |bucket| candidates.extend_from_slice(bucket));
        }
        candidates.sort_unstable();
        candidates.dedup();
        for &e in &candidates {
            let [a, b] = self.edges[e as usize];
            cubic_segment_crossings(
                curve,
                self.vertices[a as usize],
                self.vertices[b as usize],
                out,
            );
        }
        merge_kinks(out, start);
    }
}

/// Sorts `out[start..]` ascending and keeps one parameter of each run whose successive gaps
/// are at most [`KINK_MERGE`] (the run's first): crossings that close are one kink.
pub(crate) fn merge_kinks(out: &mut Vec<f64>, start: usize) {
    out[start..].sort_by(f64::total_cmp);
    let mut keep = start;
    for k in start..out.len() {
        if keep == start || out[k] - out[keep - 1] > KINK_MERGE {
            out[keep] = out[k];
            keep += 1;
        }
    }
    out.truncate(keep);
}

/// Meshes and fields of the tests here and of the mesh-family weight field's tests
/// (`weights`).
#[cfg(test)]
pub(crate) mod test_meshes {
    use super::MeshWeights;
    use crate::mesh::TriMesh;
    use kurbo::Point;

    /// An `n × n` grid of `h`-squares over `[0, n h]²`, each split by its diagonal from
    /// `(i, j)` to `(i+1, j+1)`. Vertex `(i, j)` is `j (n + 1) + i`.
    pub(crate) fn grid_mesh(n: usize, h: f64) -> TriMesh {
        let mut v = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                v.push(Point::new(i as f64 * h, j as f64 * h));
            }
        }
        let id = |i: usize, j: usize| j * (n + 1) + i;
        let mut t = Vec::new();
        for j in 0..n {
            for i in 0..n {
                t.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                t.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        TriMesh::new(v, t).unwrap()
    }

    /// Two weight functions sampled at the vertices: smooth, not affine.
    pub(crate) fn wavy(p: Point) -> [f64; 2] {
        [
            (0.3 * p.x).sin() * (0.2 * p.y).cos() + 0.1 * p.x,
            (p.x * p.y * 0.01).cos() - 0.05 * p.y,
        ]
    }

    pub(crate) fn sampled(mesh: &TriMesh, f: impl Fn(Point) -> [f64; 2]) -> MeshWeights {
        let w: Vec<f64> = mesh.vertices.iter().flat_map(|&p| f(p)).collect();
        MeshWeights::new(mesh, w, 2).unwrap()
    }
}

#[cfg(test)]
mod tests {
    use super::test_meshes::{grid_mesh, sampled, wavy};
    use super::*;

    #[test]
    fn mesh_weights_reproduce_affine_functions() {
        let mesh = grid_mesh(7, 3.0);
        let affine = |p: Point| [1.0 + 2.0 * p.x - 3.0 * p.y, -0.5 + 0.25 * p.x + 4.0 * p.y];
        let w = sampled(&mesh, affine);
        let mut out = [0.0; 2];
        for k in 0..500 {
            // Points spread over the square, including its vertices and edges.
            let p = Point::new((k * 37 % 211) as f64 / 10.0, (k * 53 % 211) as f64 / 10.0);
            w.weights_at(p, &mut out);
            let e = affine(p);
            for i in 0..2 {
                assert!(
                    (out[i] - e[i]).abs() < 1e-12 * 100.0,
                    "{p:?}: {out:?} vs {e:?}"
                );
            }
        }
    }

    #[test]
    fn mesh_weights_outside_take_nearest_boundary_point() {
        let mesh = grid_mesh(4, 1.0);
        let affine = |p: Point| [p.x + 10.0 * p.y, 1.0 - p.x];
        let w = sampled(&mesh, affine);
        let mut out = [0.0; 2];
        for (p, nearest) in [
            ((-2.0, 1.5), (0.0, 1.5)),
            ((5.0, 2.25), (4.0, 2.25)),
            ((2.5, -7.0), (2.5, 0.0)),
            ((6.0, 6.0), (4.0, 4.0)),
            ((-1.0, -3.0), (0.0, 0.0)),
        ] {
            w.weights_at(Point::from(p), &mut out);
            let e = affine(Point::from(nearest));
            for i in 0..2 {
                assert!((out[i] - e[i]).abs() < 1e-12, "{p:?}: {out:?} vs {e:?}");
            }
        }
        assert_eq!(w.n_boundary_edges(), 16);
    }

    #[test]
    fn mesh_weights_reject_bad_input() {
        let mesh = grid_mesh(1, 1.0);
        assert_eq!(
            MeshWeights::new(&mesh, vec![0.0; 7], 2).unwrap_err(),
            DomainError::WeightsLength {
                n_vertices: 4,
                n_handles: 2,
                len: 7
            }
        );
        let mut w = vec![0.0; 8];
        w[5] = f64::NAN;
        assert_eq!(
            MeshWeights::new(&mesh, w, 2).unwrap_err(),
            DomainError::NonFiniteWeight {
                vertex: 2,
                handle: 1
            }
        );
        assert_eq!(
            MeshWeights::new(&mesh, vec![], 0).unwrap_err(),
            DomainError::NoHandles
        );
        // Three triangles on one edge.
        let v = [(0., 0.), (1., 0.), (0., 1.), (0.5, 1.), (1., 1.)]
            .map(Point::from)
            .to_vec();
        let fan = TriMesh::new(v, vec![[0, 1, 2], [0, 1, 3], [0, 1, 4]]).unwrap();
        assert!(matches!(
            MeshWeights::new(&fan, vec![0.0; 5], 1).unwrap_err(),
            DomainError::NonManifoldEdge {
                a: 0,
                b: 1,
                n_triangles: 3
            }
        ));
    }

    #[test]
    fn kinks_of_a_line_are_its_edge_crossings() {
        // y = 0.5 from x = 0.25 to x = 3.75 on the unit grid: crosses x = 1, 2, 3 (vertical
        // edges) and x − y = 0, 1, 2, 3 → x = 0.5, 1.5, 2.5, 3.5 (diagonals); no horizontal.
        let w = sampled(&grid_mesh(4, 1.0), wavy);
        let (x0, x3) = (0.25, 3.75);
        let line =
            [x0, x0 + (x3 - x0) / 3.0, x0 + 2.0 * (x3 - x0) / 3.0, x3].map(|x| Point::new(x, 0.5));
        let mut kinks = vec![42.0]; // kinks appends: earlier content stays
        w.edge_crossings(&line, &mut kinks);
        let expected: Vec<f64> = [0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5]
            .iter()
            .map(|x| (x - x0) / (x3 - x0))
            .collect();
        assert_eq!(kinks[0], 42.0);
        assert_eq!(kinks.len(), 1 + expected.len(), "{kinks:?}");
        for (k, e) in kinks[1..].iter().zip(&expected) {
            assert!((k - e).abs() < 1e-14, "{kinks:?}");
        }
        // Through vertices: the diagonal y = x crosses at every grid vertex (each met by six
        // edges), reported once each.
        let diag = [0.5, 1.5, 2.5, 3.5].map(|s| Point::new(s, s));
        let mut kinks = Vec::new();
        w.edge_crossings(&diag, &mut kinks);
        let expected = [1.0 / 6.0, 0.5, 5.0 / 6.0];
        assert_eq!(kinks.len(), 3, "{kinks:?}");
        for (k, e) in kinks.iter().zip(&expected) {
            assert!((k - e).abs() < 1e-14, "{kinks:?}");
        }
    }
}
