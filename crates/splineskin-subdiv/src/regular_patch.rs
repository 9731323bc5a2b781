//! Regular faces and their bicubic B-spline patches.
//!
//! Where the neighbourhood of a quad is regular, the Catmull–Clark limit surface over it is the
//! uniform bicubic B-spline patch of its 4×4 control grid (Stam 1998, §2; the refinement rules
//! on a regular grid are B-spline knot insertion):
//!
//! ```text
//! S(s, t) = Σᵢ Σⱼ Bᵢ(s) Bⱼ(t) P(i, j),  i, j = 0..3,  (s, t) ∈ [0, 1]²
//! B₀ = (1 − t)³/6,  B₁ = (3t³ − 6t² + 4)/6,  B₂ = (−3t³ + 3t² + 3t + 1)/6,  B₃ = t³/6
//! ```
//!
//! The face is the grid's middle cell: its corners `p₀ p₁ p₂ p₃` (in the caller's frame,
//! `(s, t) = (0,0), (1,0), (1,1), (0,1)`) are `P(1,1), P(2,1), P(2,2), P(1,2)`.
//!
//! A corner is regular when, in the *sector* of faces around it reached from the face without
//! crossing an infinitely sharp edge (a "wall": boundary, infinitely sharp crease, non-manifold
//! edge):
//!
//! | vertex rule | sector | how the grid is completed |
//! |---|---|---|
//! | smooth (no sharp edge, no vertex sharpness) | 4 quads, valence 4 | gathered |
//! | crease (exactly two sharp edges, both infinite) | 2 quads between the two walls | the row or column beyond the wall is the reflection `2a − b` |
//! | corner (infinite vertex sharpness, or more than two sharp edges, all infinite) | the face alone | reflections on both sides |
//!
//! and no edge at the corner and no corner sharpness is semi-sharp. The reflection `2a − b`
//! makes the B-spline reproduce the crease rule `(a + 6v + b)/8` along the wall and pin a
//! corner (OpenSubdiv's boundary patches, `useInfSharpPatch`); the same holds on each side of
//! an interior infinitely sharp crease, whose two sides subdivide independently.

use opensubdiv_rs::far::TopologyLevel;
use opensubdiv_rs::sdc::Crease;

/// A control point of a patch: weights over the vertices of the patch's level (one entry for
/// a gathered point, up to four for a reflected one).
pub(crate) type ControlPoint = Vec<(u32, f64)>;

/// The 4×4 control grid `P(i, j)`, index `4·j + i`.
pub(crate) type Grid = [ControlPoint; 16];

/// The grid position of each corner of the middle cell, and the cells' corner order.
const CORNER: [(i32, i32); 4] = [(1, 1), (2, 1), (2, 2), (1, 2)];

/// The 4×4 grid of the quad with corners `frame` (vertices of `level`, in the caller's
/// parametric order), or `None` if the face's neighbourhood is not regular.
pub(crate) fn regular_grid(level: TopologyLevel<'_>, face: usize, frame: [u32; 4]) -> Option<Grid> {
    if level.face_vertices(face).len() != 4 {
        return None;
    }
    let mut grid: [Option<u32>; 16] = [None; 16];
    let at = |p: (i32, i32)| (4 * p.1 + p.0) as usize;
    // Walls along the face's own edges: edge k runs from frame[k] to frame[k + 1].
    let mut wall = [false; 4];
    for k in 0..4 {
        let e = level.find_edge(frame[k], frame[(k + 1) % 4])? as usize;
        let s = level.edge_sharpness(e);
        if Crease::is_semi_sharp(s) {
            return None;
        }
        wall[k] = Crease::is_infinite(s);
        if !wall[k] && level.edge_faces(e).len() != 2 {
            return None;
        }
    }
    for k in 0..4 {
        let v = frame[k];
        let next = frame[(k + 1) % 4];
        let prev = frame[(k + 3) % 4];
        let c = CORNER[k];
        let cn = CORNER[(k + 1) % 4];
        let cp = CORNER[(k + 3) % 4];
        let dn = (cn.0 - c.0, cn.1 - c.1);
        let dp = (cp.0 - c.0, cp.1 - c.1);
        let add = |a: (i32, i32), b: (i32, i32)| (a.0 + b.0, a.1 + b.1);
        let neg = |a: (i32, i32)| (-a.0, -a.1);
        put(&mut grid, at(c), v)?;
        put(&mut grid, at(cn), next)?;
        put(&mut grid, at(cp), prev)?;

        let vs = level.vertex_sharpness(v as usize);
        let mut n_sharp = 0;
        for &e in level.vertex_edges(v as usize) {
            let s = level.edge_sharpness(e as usize);
            if Crease::is_semi_sharp(s) {
                return None;
            }
            if Crease::is_infinite(s) {
                n_sharp += 1;
            }
        }
        if Crease::is_semi_sharp(vs) {
            return None;
        }
        let corner_rule = Crease::is_infinite(vs) || n_sharp > 2;
        let (wall_next, wall_prev) = (wall[k], wall[(k + 3) % 4]);
        if corner_rule {
            // The face must be alone in its sector.
            if !(wall_next && wall_prev) {
                return None;
            }
            continue;
        }
        match n_sharp {
            0 => {
                if wall_next || wall_prev {
                    return None;
                }
                if level.vertex_edges(v as usize).len() != 4
                    || level.vertex_faces(v as usize).len() != 4
                {
                    return None;
                }
                // Across the edge to `next`: G = [v, next, a', v'].
                let g = neighbour(level, face as u32, v, next)?;
                let (v1, a1) = quad_others(level, g, v, next)?;
                put(&mut grid, at(add(c, neg(dp))), v1)?;
                put(&mut grid, at(add(add(c, dn), neg(dp))), a1)?;
                // Diagonal face D = [v, v', x, v''].
                let d = neighbour(level, g, v, v1)?;
                let (v2, x) = quad_others(level, d, v, v1)?;
                put(&mut grid, at(add(add(c, neg(dn)), neg(dp))), x)?;
                put(&mut grid, at(add(c, neg(dn))), v2)?;
                // Across the edge from `prev`: H = [v, prev, b'', v''], closing the ring.
                let h = neighbour(level, face as u32, v, prev)?;
                let (v2h, b2) = quad_others(level, h, v, prev)?;
                if v2h != v2 || neighbour(level, d, v, v2)? != h {
                    return None;
                }
                put(&mut grid, at(add(add(c, dp), neg(dn))), b2)?;
            }
            2 => {
                if wall_next == wall_prev {
                    return None;
                }
                // Sector: this face and the face across its other edge at v (from `prev`
                // when the edge to `next` is the wall, else to `next`), whose second edge at
                // v is the second wall. That face's two other vertices go to `c − away` and
                // `c + along − away` in the grid.
                let (across, away, along) = if wall_next {
                    (prev, dn, dp)
                } else {
                    (next, dp, dn)
                };
                let f = neighbour(level, face as u32, v, across)?;
                let (w, corner) = quad_others(level, f, v, across)?;
                if !is_wall(level, v, w)? {
                    return None;
                }
                put(&mut grid, at(add(c, neg(away))), w)?;
                put(&mut grid, at(add(add(c, along), neg(away))), corner)?;
            }
            _ => return None,
        }
    }
    // Complete the grid by reflection beyond the walls: columns first (left: edge 3, right:
    // edge 1), then rows (bottom: edge 0, top: edge 2), which gives the tensor-product
    // reflection at the grid's corners.
    let mut points: [Option<ControlPoint>; 16] =
        std::array::from_fn(|k| grid[k].map(|v| vec![(v, 1.0)]));
    let reflect =
        |points: &mut [Option<ControlPoint>; 16], target: usize, edge_side: usize, inner: usize| {
            if let (Some(a), Some(b)) = (points[edge_side].clone(), points[inner].clone()) {
                let mut r: ControlPoint = a.iter().map(|&(v, w)| (v, 2.0 * w)).collect();
                r.extend(b.iter().map(|&(v, w)| (v, -w)));
                points[target] = Some(r);
            }
        };
    for j in 0..4 {
        if wall[3] {
            reflect(&mut points, at((0, j)), at((1, j)), at((2, j)));
        }
        if wall[1] {
            reflect(&mut points, at((3, j)), at((2, j)), at((1, j)));
        }
    }
    for i in 0..4 {
        if wall[0] {
            reflect(&mut points, at((i, 0)), at((i, 1)), at((i, 2)));
        }
        if wall[2] {
            reflect(&mut points, at((i, 3)), at((i, 2)), at((i, 1)));
        }
    }
    let mut out: Vec<ControlPoint> = Vec::with_capacity(16);
    for p in points {
        out.push(p?);
    }
    out.try_into().ok()
}

/// Sets a grid point, or checks that it agrees with what was set before.
fn put(grid: &mut [Option<u32>; 16], k: usize, v: u32) -> Option<()> {
    match grid[k] {
        Some(old) if old != v => None,
        _ => {
            grid[k] = Some(v);
            Some(())
        }
    }
}

/// The face other than `face` across the edge `(a, b)`, if that edge has exactly two faces.
fn neighbour(level: TopologyLevel<'_>, face: u32, a: u32, b: u32) -> Option<u32> {
    let e = level.find_edge(a, b)? as usize;
    match level.edge_faces(e) {
        [f, g] if *f == face => Some(*g),
        [f, g] if *g == face => Some(*f),
        _ => None,
    }
}

/// In quad `g` containing the edge `(v, a)`: the vertex next to `v` other than `a`, and the
/// vertex opposite `v`.
fn quad_others(level: TopologyLevel<'_>, g: u32, v: u32, a: u32) -> Option<(u32, u32)> {
    let fv = level.face_vertices(g as usize);
    if fv.len() != 4 {
        return None;
    }
    let i = fv.iter().position(|&x| x == v)?;
    let (n, p) = (fv[(i + 1) % 4], fv[(i + 3) % 4]);
    let other = if n == a {
        p
    } else if p == a {
        n
    } else {
        return None;
    };
    Some((other, fv[(i + 2) % 4]))
}

fn is_wall(level: TopologyLevel<'_>, a: u32, b: u32) -> Option<bool> {
    let e = level.find_edge(a, b)? as usize;
    Some(Crease::is_infinite(level.edge_sharpness(e)))
}

/// The cubic B-spline basis and its derivative at `t`.
pub(crate) fn bspline_basis(t: f64) -> ([f64; 4], [f64; 4]) {
    let t2 = t * t;
    let t3 = t2 * t;
    let u = 1.0 - t;
    (
        [
            u * u * u / 6.0,
            (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0,
            (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0,
            t3 / 6.0,
        ],
        [
            -u * u / 2.0,
            (3.0 * t2 - 4.0 * t) / 2.0,
            (-3.0 * t2 + 2.0 * t + 1.0) / 2.0,
            t2 / 2.0,
        ],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bspline_basis_partition_of_unity_and_derivative() {
        for &t in &[0.0, 0.1, 0.5, 0.93, 1.0] {
            let (b, d) = bspline_basis(t);
            assert!((b.iter().sum::<f64>() - 1.0).abs() < 1e-15);
            assert!(d.iter().sum::<f64>().abs() < 1e-15);
            let h = 1e-6;
            let (bp, _) = bspline_basis(t + h);
            let (bm, _) = bspline_basis(t - h);
            for k in 0..4 {
                assert!(((bp[k] - bm[k]) / (2.0 * h) - d[k]).abs() < 1e-8);
            }
        }
        // Interpolation property of the reflection: with P0 = 2 P1 − P2 the curve starts at P1.
        let (b, _) = bspline_basis(0.0);
        let (p1, p2) = (3.0, 7.0);
        let p0 = 2.0 * p1 - p2;
        assert!((b[0] * p0 + b[1] * p1 + b[2] * p2 - p1).abs() < 1e-15);
    }
}
