//! Does a segment cross a triangle mesh? A bounding-volume hierarchy of the triangles
//! (axis-aligned boxes, split at the median of the longest axis) and the Möller–Trumbore
//! segment–triangle test: the visibility test of bone-heat weights (a bone is visible from a
//! surface point when the segment to its closest point crosses no part of the surface).

use super::affine3::{cross, dot, sub};
use super::cage::{bounds3, Point3};

/// Triangles per leaf of the hierarchy.
const LEAF_SIZE: usize = 4;

/// A triangle mesh prepared for segment queries.
#[derive(Clone, Debug)]
pub(crate) struct TriangleBvh {
    triangles: Vec<[Point3; 3]>,
    nodes: Vec<Node>,
}

#[derive(Clone, Copy, Debug)]
struct Node {
    lo: Point3,
    hi: Point3,
    /// Leaf: triangles `start..start + count`; inner node: children `start` and `start + 1`
    /// (`count == 0`).
    start: usize,
    count: usize,
}

impl TriangleBvh {
    /// Builds the hierarchy of `triangles` (vertex indices into `positions`).
    pub fn new(positions: &[Point3], triangles: &[[u32; 3]]) -> Self {
        let mut tris: Vec<[Point3; 3]> = triangles
            .iter()
            .map(|t| t.map(|v| positions[v as usize]))
            .collect();
        let mut nodes = Vec::with_capacity(2 * tris.len() / LEAF_SIZE + 1);
        if !tris.is_empty() {
            nodes.push(Node {
                lo: [0.0; 3],
                hi: [0.0; 3],
                start: 0,
                count: 0,
            });
            build(&mut tris, 0, 0, &mut nodes);
        }
        TriangleBvh {
            triangles: tris,
            nodes,
        }
    }

    /// Does the segment from `a` to `b` cross a triangle at a point farther than `margin` from
    /// both ends (measured along the segment)? The margin ignores the surface the segment
    /// starts on and the one a handle lying on the surface ends on.
    pub fn blocks(&self, a: Point3, b: Point3, margin: f64) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        let d = sub(b, a);
        let len = dot(d, d).sqrt();
        if len <= 2.0 * margin {
            return false;
        }
        let (t_min, t_max) = (margin / len, 1.0 - margin / len);
        let inv = d.map(|x| 1.0 / x);
        let mut stack = vec![0usize];
        while let Some(k) = stack.pop() {
            let node = self.nodes[k];
            if !slab_hit(node.lo, node.hi, a, inv, t_min, t_max) {
                continue;
            }
            if node.count == 0 {
                stack.push(node.start);
                stack.push(node.start + 1);
                continue;
            }
            for tri in &self.triangles[node.start..node.start + node.count] {
                if let Some(t) = segment_triangle(a, d, tri) {
                    if t > t_min && t < t_max {
                        return true;
                    }
                }
            }
        }
        false
    }
}

/// Fills node `k` for `tris[offset..]` (which `tris` holds), recursing.
fn build(tris: &mut [[Point3; 3]], offset: usize, k: usize, nodes: &mut Vec<Node>) {
    let (lo, hi) = bounds3(tris.iter().flatten());
    if tris.len() <= LEAF_SIZE {
        nodes[k] = Node {
            lo,
            hi,
            start: offset,
            count: tris.len(),
        };
        return;
    }
    let axis = (0..3)
        .max_by(|&x, &y| (hi[x] - lo[x]).total_cmp(&(hi[y] - lo[y])))
        .unwrap_or(0);
    let centre = |t: &[Point3; 3]| t[0][axis] + t[1][axis] + t[2][axis];
    let mid = tris.len() / 2;
    tris.select_nth_unstable_by(mid, |x, y| centre(x).total_cmp(&centre(y)));
    let first = nodes.len();
    let blank = Node {
        lo: [0.0; 3],
        hi: [0.0; 3],
        start: 0,
        count: 0,
    };
    nodes.push(blank);
    nodes.push(blank);
    nodes[k] = Node {
        lo,
        hi,
        start: first,
        count: 0,
    };
    let (left, right) = tris.split_at_mut(mid);
    build(left, offset, first, nodes);
    build(right, offset + mid, first + 1, nodes);
}

/// Does `a + t·d`, `t ∈ [t0, t1]`, meet the box `[lo, hi]`? (`inv = 1/d` per axis.)
fn slab_hit(lo: Point3, hi: Point3, a: Point3, inv: Point3, t0: f64, t1: f64) -> bool {
    let (mut enter, mut exit) = (t0, t1);
    for c in 0..3 {
        let (mut n, mut f) = ((lo[c] - a[c]) * inv[c], (hi[c] - a[c]) * inv[c]);
        if n > f {
            std::mem::swap(&mut n, &mut f);
        }
        // NaN (0 · ∞ for a segment inside a slab's plane) compares false: keep the bounds.
        if n > enter {
            enter = n;
        }
        if f < exit {
            exit = f;
        }
        if enter > exit {
            return false;
        }
    }
    true
}

/// How far outside a triangle (in barycentric coordinates) a crossing still counts: a
/// segment through a shared edge or vertex must not slip between the two triangles by
/// rounding (a crossing counted twice does no harm).
const EDGE_SLACK: f64 = 1e-9;

/// The parameter `t` at which the line `a + t·d` crosses triangle `tri` (Möller & Trumbore
/// 1997, barycentric bounds widened by [`EDGE_SLACK`]), `None` if it misses it or runs
/// parallel to it.
fn segment_triangle(a: Point3, d: Point3, tri: &[Point3; 3]) -> Option<f64> {
    let e1 = sub(tri[1], tri[0]);
    let e2 = sub(tri[2], tri[0]);
    let p = cross(d, e2);
    let det = dot(e1, p);
    if det.abs() <= f64::MIN_POSITIVE {
        return None;
    }
    let s = sub(a, tri[0]);
    let u = dot(s, p) / det;
    if !(-EDGE_SLACK..=1.0 + EDGE_SLACK).contains(&u) {
        return None;
    }
    let q = cross(s, e1);
    let v = dot(d, q) / det;
    if v < -EDGE_SLACK || u + v > 1.0 + EDGE_SLACK {
        return None;
    }
    Some(dot(e2, q) / det)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn visibility_segments_through_a_cube_are_blocked() {
        // The unit cube's 12 triangles.
        let (p, tris) = crate::test_support::unit_cube_triangles();
        let bvh = TriangleBvh::new(&p, &tris);
        // From outside to the centre: crosses one face.
        assert!(bvh.blocks([-1.0, 0.5, 0.5], [0.5, 0.5, 0.5], 1e-6));
        // From a face's centre to the cube's centre: starts on the surface, ignored.
        assert!(!bvh.blocks([0.0, 0.5, 0.5], [0.5, 0.5, 0.5], 1e-6));
        // From one face through the inside to the opposite face: ends on the surface.
        assert!(!bvh.blocks([0.0, 0.4, 0.5], [1.0, 0.6, 0.5], 1e-6));
        // Outside, passing by.
        assert!(!bvh.blocks([-1.0, 2.0, 0.5], [2.0, 2.0, 0.5], 1e-6));
        // From a face point, around the outside to the far side's outside: through the box.
        assert!(bvh.blocks([0.0, 0.5, 0.5], [2.0, 0.5, 0.5], 1e-6));
    }
}
