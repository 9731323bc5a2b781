//! Vertex placement: the handles, boundary loops, bone chains and curve samples that become
//! the triangulation's vertices and constraint edges, near-duplicates merged.

use std::collections::HashMap;

use kurbo::{Point, Rect};

use super::super::grid::BucketGrid;
use super::super::polygon::{segment_distance, PolygonIndex};
use super::outline::Outline;
use super::sampling::Scale;

/// What is triangulated: the vertices and constraint edges, and where the inputs went.
pub(super) struct Placed {
    pub(super) verts: VertexSet,
    pub(super) constraints: Vec<[usize; 2]>,
    /// Each point handle's vertex.
    pub(super) handle_vertices: Vec<usize>,
    /// Each boundary loop's vertices.
    pub(super) loop_vertices: Vec<Vec<usize>>,
    /// Each bone's chain of vertices, from its first end.
    pub(super) bone_chains: Vec<Vec<usize>>,
    /// Curve samples that became vertices (those of boundary paths counted whole).
    pub(super) n_curve_samples: usize,
}

/// Places the vertices: the point handles, the boundary loops (with their edges as
/// constraints), the bones' chains, and the curve samples inside the domain that are neither
/// near a boundary or bone segment nor merged with another vertex (within half the spacing).
pub(super) fn place_vertices(
    loops: &[&[Point]],
    outline: &Outline,
    samples: &[Vec<Point>],
    points: &[Point],
    bones: &[[Point; 2]],
    spacing: f64,
    scale: Scale,
) -> Placed {
    let domain_index = PolygonIndex::new(loops);
    let merge = 0.5 * spacing;
    let mut verts = VertexSet::new(merge, scale.coincident);
    let handle_vertices: Vec<usize> = points.iter().map(|&p| verts.add_fixed(p)).collect();
    let mut constraints: Vec<[usize; 2]> = Vec::new();
    let mut add_loop = |verts: &mut VertexSet, poly: &[Point]| -> Vec<usize> {
        let idx: Vec<usize> = poly.iter().map(|&p| verts.add_fixed(p)).collect();
        for k in 0..idx.len() {
            let (a, b) = (idx[k], idx[(k + 1) % idx.len()]);
            if a != b {
                constraints.push([a, b]);
            }
        }
        idx
    };
    let loop_vertices: Vec<Vec<usize>> = loops.iter().map(|l| add_loop(&mut verts, l)).collect();
    let bone_chains: Vec<Vec<usize>> = bones
        .iter()
        .map(|b| {
            let n = (((b[1] - b[0]).hypot() / spacing).ceil() as usize).max(1);
            (0..=n)
                .map(|k| verts.add_fixed(b[0].lerp(b[1], k as f64 / n as f64)))
                .collect()
        })
        .collect();
    let near_segment = near_segment_test(&domain_index, bones, merge);
    let mut n_curve_samples = 0;
    for (path, s) in samples.iter().enumerate() {
        if Some(path) == outline.boundary_path || outline.hole_paths.contains(&path) {
            n_curve_samples += s.len();
            continue;
        }
        for &p in s {
            if domain_index.contains(p) && !near_segment(p) && verts.add_sample(p) {
                n_curve_samples += 1;
            }
        }
    }
    Placed {
        verts,
        constraints,
        handle_vertices,
        loop_vertices,
        bone_chains,
        n_curve_samples,
    }
}

/// Whether a point lies within `merge` of a segment of the boundary, its holes or a bone
/// (curve samples there are skipped: they would make slivers against the constraint edges).
pub(super) fn near_segment_test(
    domain_index: &PolygonIndex,
    bones: &[[Point; 2]],
    merge: f64,
) -> impl Fn(Point) -> bool {
    let mut segments: Vec<(Point, Point)> = domain_index.edges().to_vec();
    segments.extend(bones.iter().map(|b| (b[0], b[1])));
    let seg_bounds = segments
        .iter()
        .fold(domain_index.bounds(), |r, s| r.union_pt(s.0).union_pt(s.1));
    let seg_diag = seg_bounds.width().hypot(seg_bounds.height());
    let seg_cell = (4.0 * merge).max(seg_diag / 2048.0);
    let seg_grid = BucketGrid::build(seg_bounds, seg_cell, segments.len(), |k, emit| {
        BucketGrid::segment_pieces(seg_cell, segments[k].0, segments[k].1, emit)
    });
    move |p: Point| {
        let mut near = false;
        seg_grid.for_cells_in(Rect::from_center_size(p, (2.0 * merge, 2.0 * merge)), |b| {
            near = near
                || b.iter().any(|&k| {
                    let (a, c) = segments[k as usize];
                    segment_distance(p, a, c).0 < merge
                });
        });
        near
    }
}

/// The points of the triangulation, with merging of near-duplicates through a hash of cells
/// of side `merge`.
pub(super) struct VertexSet {
    pub(super) points: Vec<Point>,
    cells: HashMap<(i64, i64), Vec<usize>>,
    merge: f64,
    coincident: f64,
}

impl VertexSet {
    pub(super) fn new(merge: f64, coincident: f64) -> VertexSet {
        VertexSet {
            points: Vec::new(),
            cells: HashMap::new(),
            merge,
            coincident,
        }
    }

    pub(super) fn key(&self, p: Point) -> (i64, i64) {
        (
            (p.x / self.merge).floor() as i64,
            (p.y / self.merge).floor() as i64,
        )
    }

    /// The nearest existing point within `radius` (≤ `merge`).
    pub(super) fn nearest(&self, p: Point, radius: f64) -> Option<usize> {
        let (kx, ky) = self.key(p);
        let mut best = None;
        let mut best_d = radius;
        for dy in -1..=1 {
            for dx in -1..=1 {
                if let Some(v) = self.cells.get(&(kx + dx, ky + dy)) {
                    for &i in v {
                        let d = (self.points[i] - p).hypot();
                        if d <= best_d {
                            best_d = d;
                            best = Some(i);
                        }
                    }
                }
            }
        }
        best
    }

    pub(super) fn push(&mut self, p: Point) -> usize {
        let i = self.points.len();
        self.points.push(p);
        let key = self.key(p);
        self.cells.entry(key).or_default().push(i);
        i
    }

    /// A point that must be a vertex: merged only with a coincident one.
    pub(super) fn add_fixed(&mut self, p: Point) -> usize {
        match self.nearest(p, self.coincident) {
            Some(i) => i,
            None => self.push(p),
        }
    }

    /// A curve sample: skipped (false) when within `merge` of an existing vertex.
    pub(super) fn add_sample(&mut self, p: Point) -> bool {
        if self.nearest(p, self.merge).is_some() {
            return false;
        }
        self.push(p);
        true
    }
}
