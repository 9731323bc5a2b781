//! Simple polygons: signed area, simplicity, containment and distances — what choosing and
//! checking a domain boundary needs. A polygon is a slice of vertices, closed implicitly (the
//! last vertex joins the first).

use kurbo::{Point, Rect};

use super::DomainError;

/// Signed area by the shoelace formula, `½ Σ_k p_k × p_{k+1}`: positive for a counter-clockwise
/// polygon (in a y-up frame; in SVG's y-down frame the same vertex list looks clockwise on
/// screen — only the sign convention of the formula matters here).
///
/// ```
/// use kurbo::Point;
/// use splineskin_core::domain::polygon::signed_area;
/// let square = [(0., 0.), (2., 0.), (2., 2.), (0., 2.)].map(Point::from);
/// assert_eq!(signed_area(&square), 4.0);
/// ```
pub fn signed_area(poly: &[Point]) -> f64 {
    let n = poly.len();
    if n < 3 {
        return 0.0;
    }
    // Relative to the first vertex, which keeps the terms small far from the origin.
    let o = poly[0];
    let mut twice = 0.0;
    for k in 1..n - 1 {
        twice += (poly[k] - o).cross(poly[k + 1] - o);
    }
    0.5 * twice
}

/// The closed polygon `poly` simplified by Douglas–Peucker to within `tolerance`: vertices
/// dropped where the kept ones pass within `tolerance` of them. The loop is cut at its first
/// vertex and the vertex farthest from it, each half simplified alone. A result with fewer
/// than 3 vertices is not a polygon: `poly` is returned whole instead.
pub(crate) fn simplify_closed(poly: &[Point], tolerance: f64) -> Vec<Point> {
    let n = poly.len();
    if n < 4 {
        return poly.to_vec();
    }
    let far = (1..n)
        .max_by(|&a, &b| {
            (poly[a] - poly[0])
                .hypot2()
                .total_cmp(&(poly[b] - poly[0]).hypot2())
        })
        .unwrap_or(n / 2);
    let mut keep = vec![false; n];
    keep[0] = true;
    keep[far] = true;
    let mut stack = vec![(0, far), (far, n)];
    while let Some((a, b)) = stack.pop() {
        let (pa, pb) = (poly[a], poly[b % n]);
        let worst = (a + 1..b)
            .map(|k| (segment_distance(poly[k], pa, pb).0, k))
            .max_by(|x, y| x.0.total_cmp(&y.0));
        if let Some((d, k)) = worst {
            if d > tolerance {
                keep[k] = true;
                stack.push((a, k));
                stack.push((k, b));
            }
        }
    }
    let out: Vec<Point> = (0..n).filter(|&k| keep[k]).map(|k| poly[k]).collect();
    if out.len() < 3 {
        poly.to_vec()
    } else {
        out
    }
}

/// Whether any two edges of the closed polygons `loops` share a point, other than consecutive
/// edges of one loop at their common vertex (a sweep over x, as [`self_intersection`]).
pub(crate) fn loops_cross(loops: &[Vec<Point>]) -> bool {
    let mut edges: Vec<(Point, Point, usize, usize)> = Vec::new();
    for (l, poly) in loops.iter().enumerate() {
        let n = poly.len();
        edges.extend((0..n).map(|k| (poly[k], poly[(k + 1) % n], l, k)));
    }
    let len = |l: usize| loops[l].len();
    let adjacent = |e: &(Point, Point, usize, usize), f: &(Point, Point, usize, usize)| {
        e.2 == f.2 && ((e.3 + 1) % len(e.2) == f.3 || (f.3 + 1) % len(f.2) == e.3)
    };
    edges.sort_by(|e, f| e.0.x.min(e.1.x).total_cmp(&f.0.x.min(f.1.x)));
    let mut active: Vec<usize> = Vec::new();
    for k in 0..edges.len() {
        let e = edges[k];
        let x0 = e.0.x.min(e.1.x);
        active.retain(|&l| edges[l].0.x.max(edges[l].1.x) >= x0);
        for &l in &active {
            let f = edges[l];
            if !adjacent(&e, &f) && segments_intersect(e.0, e.1, f.0, f.1) {
                return true;
            }
        }
        active.push(k);
    }
    false
}

/// `(b − a) × (c − a)`: positive when `a, b, c` turn counter-clockwise.
#[inline]
pub(crate) fn orient(a: Point, b: Point, c: Point) -> f64 {
    (b - a).cross(c - a)
}

/// Whether the closed segments `a b` and `c d` share a point (crossing, touching or
/// overlapping).
pub(crate) fn segments_intersect(a: Point, b: Point, c: Point, d: Point) -> bool {
    let d1 = orient(c, d, a);
    let d2 = orient(c, d, b);
    let d3 = orient(a, b, c);
    let d4 = orient(a, b, d);
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    let on = |p: Point, q: Point, r: Point| {
        // r on segment p q, given collinear.
        r.x >= p.x.min(q.x) && r.x <= p.x.max(q.x) && r.y >= p.y.min(q.y) && r.y <= p.y.max(q.y)
    };
    (d1 == 0.0 && on(c, d, a))
        || (d2 == 0.0 && on(c, d, b))
        || (d3 == 0.0 && on(a, b, c))
        || (d4 == 0.0 && on(a, b, d))
}

/// Distance from `p` to the segment `a b`, and the parameter `s ∈ [0, 1]` of the nearest point
/// `a + s (b − a)`.
pub(crate) fn segment_distance(p: Point, a: Point, b: Point) -> (f64, f64) {
    let ab = b - a;
    let len2 = ab.hypot2();
    let s = if len2 > 0.0 {
        ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ((p - a.lerp(b, s)).hypot(), s)
}

/// The first pair of edges `(k, l)`, `k < l`, of the closed polygon that intersect other than
/// at the vertex shared by neighbours (edge `k` runs from vertex `k` to `k + 1 mod n`), or
/// `None` if the polygon is simple. Neighbouring edges folding back onto each other count as
/// intersecting. A sweep over x (edges sorted by their left end): `O(n log n)` plus the pairs
/// whose x-ranges overlap.
pub(crate) fn self_intersection(poly: &[Point]) -> Option<(usize, usize)> {
    let n = poly.len();
    if n < 3 {
        return None;
    }
    let edge = |k: usize| (poly[k], poly[(k + 1) % n]);
    let adjacent = |k: usize, l: usize| (k + 1) % n == l || (l + 1) % n == k;
    let mut order: Vec<usize> = (0..n).collect();
    let min_x = |k: usize| {
        let (a, b) = edge(k);
        a.x.min(b.x)
    };
    order.sort_by(|&k, &l| min_x(k).total_cmp(&min_x(l)));
    let mut active: Vec<usize> = Vec::new();
    let mut found: Option<(usize, usize)> = None;
    for &k in &order {
        let (a, b) = edge(k);
        let x0 = a.x.min(b.x);
        active.retain(|&l| {
            let (c, d) = edge(l);
            c.x.max(d.x) >= x0
        });
        for &l in &active {
            let (c, d) = edge(l);
            let hit = if adjacent(k, l) {
                if n == 3 {
                    // A triangle's edges are all adjacent: degenerate only if collinear.
                    orient(poly[0], poly[1], poly[2]) == 0.0
                } else {
                    // Sharing one vertex: a problem only when collinear and folding back.
                    let (shared, p, q) = if (k + 1) % n == l {
                        (b, a, d)
                    } else {
                        (a, b, c)
                    };
                    orient(p, shared, q) == 0.0 && (p - shared).dot(q - shared) > 0.0
                }
            } else {
                segments_intersect(a, b, c, d)
            };
            if hit {
                let pair = (k.min(l), k.max(l));
                found = Some(found.map_or(pair, |f| f.min(pair)));
            }
        }
        active.push(k);
    }
    found
}

/// A polygon (or several: an outer boundary and holes) prepared for many even–odd containment
/// queries: its edges bucketed into horizontal bands, so a query visits only the edges of its
/// band.
#[derive(Clone, Debug)]
pub(crate) struct PolygonIndex {
    edges: Vec<(Point, Point)>,
    y0: f64,
    band: f64,
    offsets: Vec<u32>,
    items: Vec<u32>,
}

impl PolygonIndex {
    /// Indexes the closed polygons `loops` (each closed implicitly).
    pub(crate) fn new(loops: &[&[Point]]) -> PolygonIndex {
        let mut edges = Vec::new();
        for poly in loops {
            let n = poly.len();
            for k in 0..n {
                edges.push((poly[k], poly[(k + 1) % n]));
            }
        }
        let (y0, y1) = edges
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |r, e| {
                (r.0.min(e.0.y.min(e.1.y)), r.1.max(e.0.y.max(e.1.y)))
            });
        let n_bands = edges.len().clamp(1, 1 << 16);
        let band = ((y1 - y0) / n_bands as f64).max(f64::MIN_POSITIVE);
        let band_of = |y: f64| (((y - y0) / band).floor().max(0.0) as usize).min(n_bands - 1);
        let mut pairs: Vec<(u32, u32)> = Vec::new();
        for (k, e) in edges.iter().enumerate() {
            for b in band_of(e.0.y.min(e.1.y))..=band_of(e.0.y.max(e.1.y)) {
                pairs.push((b as u32, k as u32));
            }
        }
        pairs.sort_unstable();
        let mut offsets = vec![0u32; n_bands + 1];
        for &(b, _) in &pairs {
            offsets[b as usize + 1] += 1;
        }
        for b in 0..n_bands {
            offsets[b + 1] += offsets[b];
        }
        PolygonIndex {
            edges,
            y0,
            band,
            offsets,
            items: pairs.into_iter().map(|(_, k)| k).collect(),
        }
    }

    /// Whether `p` is inside by the even–odd rule (crossings of the ray to `+x`; each edge
    /// counted half-open in y so that vertices are not counted twice). Points exactly on an
    /// edge may go either way.
    pub(crate) fn contains(&self, p: Point) -> bool {
        let n_bands = self.offsets.len() - 1;
        let fb = ((p.y - self.y0) / self.band).floor();
        if !(fb >= 0.0 && fb < n_bands as f64 + 1.0) {
            return false;
        }
        let b = (fb as usize).min(n_bands - 1);
        let mut inside = false;
        for &k in &self.items[self.offsets[b] as usize..self.offsets[b + 1] as usize] {
            let (a, c) = self.edges[k as usize];
            if (a.y > p.y) != (c.y > p.y) {
                let x = a.x + (p.y - a.y) / (c.y - a.y) * (c.x - a.x);
                if p.x < x {
                    inside = !inside;
                }
            }
        }
        inside
    }

    /// The edges' bounding box.
    pub(crate) fn bounds(&self) -> Rect {
        self.edges.iter().fold(
            Rect::from_points(self.edges[0].0, self.edges[0].0),
            |r, e| r.union_pt(e.0).union_pt(e.1),
        )
    }

    /// The indexed edges (all loops, in order).
    pub(crate) fn edges(&self) -> &[(Point, Point)] {
        &self.edges
    }
}

/// Checks a cage polygon: finite vertices, at least 3 of them, no edge of length `≤ coincident`,
/// simple (`self_intersection`) and counter-clockwise (positive [`signed_area`]) — the rules of
/// [`crate::domain::DomainOptions::cage`], shared by the domain, mean value coordinates and
/// scenes.
///
/// ```
/// use kurbo::Point;
/// use splineskin_core::domain::{polygon::check_cage, DomainError};
/// let square = [(0., 0.), (1., 0.), (1., 1.), (0., 1.)].map(Point::from);
/// assert_eq!(check_cage(&square, 0.0), Ok(()));
/// let mut clockwise = square;
/// clockwise.reverse();
/// assert!(matches!(check_cage(&clockwise, 0.0), Err(DomainError::CageClockwise { .. })));
/// ```
pub fn check_cage(c: &[Point], coincident: f64) -> Result<(), DomainError> {
    if let Some(vertex) = c.iter().position(|p| !(p.x.is_finite() && p.y.is_finite())) {
        return Err(DomainError::CageNonFinite { vertex });
    }
    if c.len() < 3 {
        return Err(DomainError::CageTooFewVertices {
            n_vertices: c.len(),
        });
    }
    for edge in 0..c.len() {
        if (c[(edge + 1) % c.len()] - c[edge]).hypot() <= coincident {
            return Err(DomainError::CageDegenerateEdge { edge });
        }
    }
    if let Some((first, second)) = self_intersection(c) {
        return Err(DomainError::CageSelfIntersecting { first, second });
    }
    let signed_area = signed_area(c);
    if signed_area < 0.0 {
        return Err(DomainError::CageClockwise { signed_area });
    }
    Ok(())
}

/// The closed polygon with its small self-overlapping loops cut off: while two edges `k < l`
/// intersect (`self_intersection`), the shorter of the two vertex runs between them (by
/// vertex count) is replaced by the intersection point. `None` when the polygon stays
/// non-simple after `max_cuts` cuts, or when the loops cut off hold more than
/// `max_area_fraction` of the polygon's area (in absolute area of the removed loops, against
/// `|signed_area|` of the input): then the crossing is not a small blemish but the shape.
///
/// Drawn outlines often have such blemishes: a closing curve that overshoots its start and
/// crosses back, a tiny twisted loop at a cusp.
///
/// ```
/// use kurbo::Point;
/// use splineskin_core::domain::polygon::{without_small_loops, signed_area};
/// // A 10 × 10 square whose closing edges overshoot its first corner: the edge from (−1, 2)
/// // to (2, −1) crosses the first edge at (1, 0), leaving a loop of area 0.5 below it.
/// let poly = [(0., 0.), (10., 0.), (10., 10.), (0., 10.), (-1., 2.), (2., -1.)].map(Point::from);
/// let cut = without_small_loops(&poly, 8, 0.01).unwrap();
/// assert_eq!(cut.len(), 5);
/// assert!((signed_area(&cut) - 104.0).abs() < 1e-12);
/// // The same loop is too big when only 0.1 % of the area may be cut off.
/// assert!(without_small_loops(&poly, 8, 1e-3).is_none());
/// ```
pub fn without_small_loops(
    poly: &[Point],
    max_cuts: usize,
    max_area_fraction: f64,
) -> Option<Vec<Point>> {
    let total = signed_area(poly).abs();
    let mut cut_area = 0.0;
    let mut p = poly.to_vec();
    for _ in 0..=max_cuts {
        let Some((k, l)) = self_intersection(&p) else {
            return (cut_area <= max_area_fraction * total).then_some(p);
        };
        let n = p.len();
        let x = crossing_point(p[k], p[(k + 1) % n], p[l], p[(l + 1) % n]);
        // Inner run: vertices k+1 ..= l; outer run: l+1 ..= k (wrapping).
        let inner = l - k;
        let outer = n - inner;
        let (kept, loop_run): (Vec<Point>, Vec<Point>) = if inner <= outer {
            let mut kept: Vec<Point> = p[..=k].to_vec();
            kept.push(x);
            kept.extend_from_slice(&p[l + 1..]);
            let mut run = vec![x];
            run.extend_from_slice(&p[k + 1..=l]);
            (kept, run)
        } else {
            let mut kept = vec![x];
            kept.extend_from_slice(&p[k + 1..=l]);
            let mut run = vec![x];
            run.extend_from_slice(&p[l + 1..]);
            run.extend_from_slice(&p[..=k]);
            (kept, run)
        };
        cut_area += signed_area(&loop_run).abs();
        if kept.len() < 3 || cut_area > max_area_fraction * total {
            return None;
        }
        p = kept;
    }
    None
}

/// A point common to the intersecting segments `a b` and `c d`: their crossing, or for
/// touching or overlapping segments an end point lying on the other segment.
fn crossing_point(a: Point, b: Point, c: Point, d: Point) -> Point {
    let r = b - a;
    let s = d - c;
    let denom = r.cross(s);
    if denom != 0.0 {
        let t = ((c - a).cross(s) / denom).clamp(0.0, 1.0);
        return a + r * t;
    }
    [a, b, c, d]
        .into_iter()
        .min_by(|&p, &q| {
            let dp = segment_distance(p, a, b).0 + segment_distance(p, c, d).0;
            let dq = segment_distance(q, a, b).0 + segment_distance(q, c, d).0;
            dp.total_cmp(&dq)
        })
        .unwrap_or(a)
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::test_support::pts;

    #[test]
    fn polygon_area_sign_follows_orientation() {
        let mut sq = pts(&[(1., 1.), (4., 1.), (4., 3.), (1., 3.)]);
        assert_eq!(signed_area(&sq), 6.0);
        sq.reverse();
        assert_eq!(signed_area(&sq), -6.0);
    }

    #[test]
    fn polygon_self_intersection_found() {
        let bowtie = pts(&[(0., 0.), (2., 2.), (2., 0.), (0., 2.)]);
        assert_eq!(self_intersection(&bowtie), Some((0, 2)));
        let square = pts(&[(0., 0.), (2., 0.), (2., 2.), (0., 2.)]);
        assert_eq!(self_intersection(&square), None);
        // A spike folding back onto its previous edge.
        let spike = pts(&[(0., 0.), (2., 0.), (1., 0.), (1., 2.)]);
        assert!(self_intersection(&spike).is_some());
        // Touching at a vertex (figure eight through a shared point).
        let eight = pts(&[(0., 0.), (1., 1.), (2., 0.), (2., 2.), (1., 1.), (0., 2.)]);
        assert!(self_intersection(&eight).is_some());
        // Collinear triangle.
        assert!(self_intersection(&pts(&[(0., 0.), (1., 0.), (2., 0.)])).is_some());
    }

    #[test]
    fn polygon_index_contains_matches_brute_force() {
        // A comb-shaped polygon with a square hole.
        let outer = pts(&[
            (0., 0.),
            (10., 0.),
            (10., 10.),
            (7., 10.),
            (7., 3.),
            (5., 3.),
            (5., 10.),
            (0., 10.),
        ]);
        let hole = pts(&[(1., 5.), (3., 5.), (3., 7.), (1., 7.)]);
        let idx = PolygonIndex::new(&[&outer, &hole]);
        for (p, inside) in [
            ((6.0, 2.0), true),
            ((6.0, 5.0), false),
            ((8.5, 9.5), true),
            ((2.0, 6.0), false),
            ((2.0, 4.0), true),
            ((-1.0, 5.0), false),
            ((5.0, 11.0), false),
        ] {
            assert_eq!(idx.contains(Point::from(p)), inside, "{p:?}");
        }
    }
}
