//! The art's own shape as the boundary of a domain ([`super::DomainShape::Art`]): the region the
//! drawing paints, grown by a margin, as closed polygons, with its real holes, one outline per
//! part that holds a handle.
//!
//! **Painted.** A square grid of cell side `c` (the domain's curve sample spacing) covers the
//! drawing. A cell is *painted* when its centre is
//!
//! * inside the fill of a filled element, under the element's own fill rule (`nonzero`: winding
//!   number ≠ 0; `evenodd`: odd), its subpaths flattened to within `c/8`, an open one closed by a
//!   line as SVG fills it;
//! * within `max(w/2, c/√2)` of a drawn path (`w` the stroke width in root units, 0 when it is
//!   not stroked): strokes at their width, and every drawn curve at least through the cells it
//!   crosses, so that an unfilled hairline is part of the art too;
//! * the cell of a point handle, or within `c/√2` of a bone; a point handle off the art is
//!   tied to it by the cells within `c/√2` of the segment to the nearest painted cell centre
//!   (a pin placed beside the art moves the art nearest to it, rather than nothing).
//!
//! A drawn path is one whose [`crate::drawing::PathRole`] is visible (hidden layers, clip paths,
//! masks and unpainted paths paint nothing); without a source document every path is drawn and
//! filled (SVG's default paint). When nothing at all is drawn, every path counts as drawn.
//!
//! **Grown.** With `d(x)` the distance from a cell centre `x` to the nearest painted centre
//! ([`super::distance::distance_to_marked`]), the region is `d < m + 1.5 c` (`m` the margin): the
//! margin, plus a cell and a half so that the art's own edges lie inside whatever the margin.
//! Its outline is the level set `d = m + 1.5 c`, traced by marching squares over the cell centres, each
//! crossing placed on its grid edge by linear interpolation of `d` (clamped to the middle 60 %
//! of the edge, so that two vertices are never closer than 0.28 `c`), then simplified to within
//! half a cell (Douglas–Peucker; as traced if that made two outlines cross). Inside centres that share
//! a grid edge are connected; across a diagonal only (a saddle) they are not, and the outline
//! separates them.
//!
//! **Parts.** The connected sets of inside centres are the art's *parts*: shapes that touch or
//! overlap, or come within about `2(m + 1.5 c)` of each other, are one part; parts separated by
//! background are not connected. Only parts holding a handle (a point handle or a bone) are
//! kept. An unpinned part is left out of the domain and *attached* to it
//! ([`super::Attachment`]): every point of the part takes the weights of the one boundary vertex
//! of the pinned art nearest to the part, so that the part moves as one piece with the art it
//! lies next to (constant weights: the fit reproduces its skinned target exactly).

use kurbo::{BezPath, PathEl, Point, Rect, Shape};

use super::distance::distance_to_marked;
use super::polygon::{loops_cross, segment_distance, self_intersection, simplify_closed};
use crate::drawing::Drawing;

/// Largest number of grid cells: 4 Mi. A finer grid is coarsened until it fits.
const MAX_CELLS: usize = 1 << 22;

/// Growth beyond the margin, in cells: 1.5, so that every cell painted (its whole square, where
/// the art or a handle lies) and its eight neighbours are inside, whatever the margin.
const GROWTH_CELLS: f64 = 1.5;

/// Tolerance of the outlines' simplification, in cells: 0.5 (the traced outline has a vertex
/// on every grid edge it crosses; straight and gently curved runs keep far fewer).
const SIMPLIFY_CELLS: f64 = 0.5;

/// Crossings are placed within `[EDGE_CLAMP, 1 − EDGE_CLAMP]` of their grid edge.
const EDGE_CLAMP: f64 = 0.2;

/// The traced region ([`trace`]).
#[derive(Clone, Debug)]
pub(super) struct ArtRegion {
    /// Closed polygons: the parts' outlines counter-clockwise (positive signed area), their
    /// holes clockwise.
    pub loops: Vec<Vec<Point>>,
    /// Parts kept (each holds a handle).
    pub n_parts: usize,
    /// Parts left out (no handle).
    pub n_unpinned: usize,
    /// The outlines of each part left out (its outer outline and holes).
    pub unpinned: Vec<Vec<Vec<Point>>>,
}

/// The painted region of `drawing`, grown by `margin` (drawing units), on a grid of cell side
/// about `cell`, with the parts that hold one of `points` or `bones` (module documentation);
/// the outlines simplified to within `max(cell / 2, tolerance)`.
pub(super) fn trace(
    drawing: &Drawing,
    points: &[Point],
    bones: &[[Point; 2]],
    margin: f64,
    (cell, tolerance): (f64, f64),
) -> ArtRegion {
    let paint = Paint::of(drawing);
    let grid = Grid::over(drawing, &paint, points, bones, margin, cell);
    let mut painted = vec![false; grid.n_cols * grid.n_rows];
    grid.paint_fills(drawing, &paint, &mut painted);
    grid.paint_lines(drawing, &paint, bones, &mut painted);
    grid.bridge_handles(points, &mut painted);
    let distance = distance_to_marked(&painted, grid.n_cols, grid.n_rows);
    let level = margin / grid.cell + GROWTH_CELLS;
    let field: Vec<f64> = distance.iter().map(|d| d - level).collect();
    let mut inside: Vec<bool> = field.iter().map(|&f| f < 0.0).collect();
    grid.clear_border(&mut inside);
    let parts = Parts::label(&inside, grid.n_cols, grid.n_rows);
    let pinned = parts.pinned(&grid, points, bones);
    let mut loops = Vec::new();
    let mut unpinned_of: Vec<Vec<Vec<Point>>> = vec![Vec::new(); parts.n];
    let tolerance = tolerance.max(SIMPLIFY_CELLS * grid.cell);
    for (part, outline) in simplified(grid.outlines(&field, &inside, &parts), tolerance) {
        if pinned[part] {
            loops.push(outline);
        } else {
            unpinned_of[part].push(outline);
        }
    }
    let n_parts = pinned.iter().filter(|&&p| p).count();
    ArtRegion {
        loops,
        n_parts,
        n_unpinned: pinned.len() - n_parts,
        unpinned: unpinned_of.into_iter().filter(|l| !l.is_empty()).collect(),
    }
}

/// The outlines simplified to within `tolerance` (Douglas–Peucker), or as traced when
/// simplifying makes two of them cross.
fn simplified(outlines: Vec<(usize, Vec<Point>)>, tolerance: f64) -> Vec<(usize, Vec<Point>)> {
    let simple: Vec<(usize, Vec<Point>)> = outlines
        .iter()
        .map(|(part, l)| (*part, simplify_closed(l, tolerance)))
        .collect();
    let loops: Vec<Vec<Point>> = simple.iter().map(|(_, l)| l.clone()).collect();
    let degenerate = loops.iter().any(|l| self_intersection(l).is_some());
    if degenerate || loops_cross(&loops) {
        outlines
    } else {
        simple
    }
}

/// What each path paints: whether it is drawn, filled (and by which rule, per element) and its
/// stroke's half width in root units.
struct Paint {
    /// Per path: drawn at all.
    drawn: Vec<bool>,
    /// Per path: filled.
    filled: Vec<bool>,
    /// Per path: the `evenodd` rule.
    even_odd: Vec<bool>,
    /// Per path: half the stroke width (0 without a stroke).
    half_width: Vec<f64>,
    /// Per path: its element (paths of one element fill together), or a key of its own.
    group: Vec<usize>,
}

impl Paint {
    fn of(drawing: &Drawing) -> Paint {
        let n = drawing.paths.len();
        let mut paint = Paint {
            drawn: vec![true; n],
            filled: vec![true; n],
            even_odd: vec![false; n],
            half_width: vec![0.0; n],
            group: (0..n).map(|i| usize::MAX - i).collect(),
        };
        let Some(source) = drawing.source.as_ref() else {
            return paint;
        };
        for i in 0..n {
            let Some(e) = source.element_of_path(i) else {
                continue;
            };
            let element = &source.elements[e];
            paint.group[i] = e;
            paint.drawn[i] = element.role.is_drawn();
            paint.filled[i] = element.paint.filled && !element.zero_area_fill;
            paint.even_odd[i] = element.paint.even_odd;
            let scale = element.local_to_root.determinant().abs().sqrt();
            paint.half_width[i] = element
                .paint
                .stroke_width
                .map_or(0.0, |w| 0.5 * w * scale)
                .max(0.0);
        }
        if !paint.drawn.iter().any(|&d| d) {
            paint.drawn.iter_mut().for_each(|d| *d = true);
        }
        paint
    }
}

/// The grid: cell centres `origin + ((col + ½) c, (row + ½) c)`.
struct Grid {
    origin: Point,
    cell: f64,
    n_cols: usize,
    n_rows: usize,
}

impl Grid {
    /// A grid over the drawn curves, handles and bones, with room around them for the margin,
    /// the strokes and a border of outside cells.
    fn over(
        drawing: &Drawing,
        paint: &Paint,
        points: &[Point],
        bones: &[[Point; 2]],
        margin: f64,
        cell: f64,
    ) -> Grid {
        let mut bounds: Option<Rect> = None;
        let mut add = |r: Rect| bounds = Some(bounds.map_or(r, |b| b.union(r)));
        let mut widest = 0.0f64;
        for (i, path) in drawing.paths.iter().enumerate() {
            if paint.drawn[i] && path.n_curves() > 0 {
                widest = widest.max(paint.half_width[i]);
                (0..path.n_curves()).for_each(|j| add(path.curve(j).bounding_box()));
            }
        }
        points
            .iter()
            .chain(bones.iter().flatten())
            .for_each(|&p| add(Rect::from_points(p, p)));
        let bounds = bounds.unwrap_or_default();
        let mut cell = cell;
        let room = |cell: f64| margin + widest + 4.0 * cell;
        let count = |cell: f64| {
            let r = bounds.inflate(room(cell), room(cell));
            (
                (r.width() / cell).ceil() as usize + 1,
                (r.height() / cell).ceil() as usize + 1,
            )
        };
        let (mut n_cols, mut n_rows) = count(cell);
        while n_cols.saturating_mul(n_rows) > MAX_CELLS {
            cell *= 1.25;
            (n_cols, n_rows) = count(cell);
        }
        let r = bounds.inflate(room(cell), room(cell));
        Grid {
            origin: Point::new(r.x0, r.y0),
            cell,
            n_cols,
            n_rows,
        }
    }

    fn centre(&self, col: usize, row: usize) -> Point {
        Point::new(
            self.origin.x + (col as f64 + 0.5) * self.cell,
            self.origin.y + (row as f64 + 0.5) * self.cell,
        )
    }

    /// The cell holding `p` (clamped to the grid).
    fn cell_of(&self, p: Point) -> (usize, usize) {
        let at = |v: f64, n: usize| (v / self.cell).floor().clamp(0.0, (n - 1) as f64) as usize;
        (
            at(p.x - self.origin.x, self.n_cols),
            at(p.y - self.origin.y, self.n_rows),
        )
    }

    /// Marks the cells whose centre a filled element covers, element by element.
    fn paint_fills(&self, drawing: &Drawing, paint: &Paint, painted: &mut [bool]) {
        // The filled paths by element, in document order.
        let mut filled: Vec<usize> = (0..drawing.paths.len())
            .filter(|&i| paint.drawn[i] && paint.filled[i] && drawing.paths[i].n_curves() > 0)
            .collect();
        filled.sort_by_key(|&i| (paint.group[i], i));
        let mut crossings: Vec<Vec<(f64, i32)>> = vec![Vec::new(); self.n_rows];
        let mut rows: Vec<usize> = Vec::new();
        for element in filled.chunk_by(|&i, &j| paint.group[i] == paint.group[j]) {
            for &i in element {
                self.flattened(&drawing.paths[i], true, |a, b| {
                    self.row_crossings(a, b, &mut crossings, &mut rows)
                });
            }
            let even_odd = paint.even_odd[element[0]];
            for &row in &rows {
                let xs = &mut crossings[row];
                self.fill_row(row, xs, even_odd, painted);
                xs.clear();
            }
            rows.clear();
        }
    }

    /// Marks the cells of `row` whose centre the crossings `xs` (x, ±1) put inside, under the
    /// `evenodd` rule or `nonzero`.
    fn fill_row(&self, row: usize, xs: &mut [(f64, i32)], even_odd: bool, painted: &mut [bool]) {
        xs.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut winding = 0;
        for pair in xs.windows(2) {
            winding += pair[0].1;
            let inside = if even_odd {
                winding % 2 != 0
            } else {
                winding != 0
            };
            if !inside {
                continue;
            }
            // Columns whose centre x lies in [pair[0].0, pair[1].0).
            let col_of = |x: f64| ((x - self.origin.x) / self.cell - 0.5).ceil().max(0.0);
            let first = col_of(pair[0].0) as usize;
            let end = (col_of(pair[1].0) as usize).min(self.n_cols);
            for cell in &mut painted[row * self.n_cols + first.min(end)..row * self.n_cols + end] {
                *cell = true;
            }
        }
    }

    /// Calls `segment(a, b)` for the lines of `path` flattened to within `c/8` (closed by a
    /// line from its end to its start when `close`).
    fn flattened(
        &self,
        path: &crate::drawing::Path,
        close: bool,
        mut segment: impl FnMut(Point, Point),
    ) {
        let mut bez = BezPath::new();
        bez.move_to(path.points[0]);
        for j in 0..path.n_curves() {
            let c = path.curve(j);
            bez.curve_to(c.p1, c.p2, c.p3);
        }
        if close {
            bez.close_path();
        }
        let (mut start, mut last) = (path.points[0], path.points[0]);
        kurbo::flatten(&bez, self.cell / 8.0, |el| {
            let to = match el {
                PathEl::MoveTo(p) => {
                    (start, last) = (p, p);
                    return;
                }
                PathEl::LineTo(p) => p,
                PathEl::ClosePath => start,
                _ => return,
            };
            segment(last, to);
            last = to;
        });
    }

    /// Adds to each row the signed crossing (x, ±1) of the segment `a b` with its centre line
    /// (half-open in y, so that a vertex on the line counts once).
    fn row_crossings(
        &self,
        a: Point,
        b: Point,
        crossings: &mut [Vec<(f64, i32)>],
        rows: &mut Vec<usize>,
    ) {
        if a.y == b.y || !(a.y.is_finite() && b.y.is_finite()) {
            return;
        }
        let dir = if b.y > a.y { 1 } else { -1 };
        let (lo, hi) = if a.y < b.y { (a, b) } else { (b, a) };
        let row_of = |y: f64| (y - self.origin.y) / self.cell - 0.5;
        let first = row_of(lo.y).ceil().max(0.0) as usize;
        let end = (row_of(hi.y).ceil().max(0.0) as usize).min(self.n_rows);
        for (row, xs) in crossings.iter_mut().enumerate().take(end).skip(first) {
            let y = self.centre(0, row).y;
            if y >= lo.y && y < hi.y {
                if xs.is_empty() {
                    rows.push(row);
                }
                let t = (y - lo.y) / (hi.y - lo.y);
                xs.push((lo.x + t * (hi.x - lo.x), dir));
            }
        }
    }

    /// Marks the cells near every drawn path (its stroke) and near every bone.
    fn paint_lines(
        &self,
        drawing: &Drawing,
        paint: &Paint,
        bones: &[[Point; 2]],
        painted: &mut [bool],
    ) {
        let least = self.cell * std::f64::consts::FRAC_1_SQRT_2;
        for (i, path) in drawing.paths.iter().enumerate() {
            if paint.drawn[i] && path.n_curves() > 0 {
                let radius = paint.half_width[i].max(least);
                self.flattened(path, false, |a, b| {
                    self.paint_segment(a, b, radius, painted)
                });
            }
        }
        for b in bones {
            self.paint_segment(b[0], b[1], least, painted);
        }
    }

    /// Marks the cells whose centre is within `radius` of the segment `a b`.
    fn paint_segment(&self, a: Point, b: Point, radius: f64, painted: &mut [bool]) {
        let r = Rect::from_points(a, b).inflate(radius, radius);
        let (c0, r0) = self.cell_of(Point::new(r.x0, r.y0));
        let (c1, r1) = self.cell_of(Point::new(r.x1, r.y1));
        for row in r0..=r1 {
            for col in c0..=c1 {
                if segment_distance(self.centre(col, row), a, b).0 <= radius {
                    painted[row * self.n_cols + col] = true;
                }
            }
        }
    }

    /// Marks every point handle's cell, and ties a handle off the art to it: the cells within
    /// `c/√2` of the segment from the handle to the nearest painted cell centre (so that a
    /// pin placed beside the art moves the art nearest to it).
    fn bridge_handles(&self, points: &[Point], painted: &mut [bool]) {
        let least = self.cell * std::f64::consts::FRAC_1_SQRT_2;
        let centre = |k: usize| self.centre(k % self.n_cols, k / self.n_cols);
        // Every bridge goes to the art as painted, before any bridge or handle cell.
        let bridges: Vec<(Point, Option<usize>)> = points
            .iter()
            .filter(|&&p| {
                let (col, row) = self.cell_of(p);
                !painted[row * self.n_cols + col]
            })
            .map(|&p| {
                let nearest = (0..painted.len()).filter(|&k| painted[k]).min_by(|&a, &b| {
                    (centre(a) - p)
                        .hypot2()
                        .total_cmp(&(centre(b) - p).hypot2())
                });
                (p, nearest)
            })
            .collect();
        for (p, nearest) in bridges {
            if let Some(k) = nearest {
                self.paint_segment(p, centre(k), least, painted);
            }
            let (col, row) = self.cell_of(p);
            painted[row * self.n_cols + col] = true;
        }
    }

    /// Sets the grid's outermost ring of cells outside, so that every outline closes.
    fn clear_border(&self, inside: &mut [bool]) {
        let (w, h) = (self.n_cols, self.n_rows);
        for col in 0..w {
            inside[col] = false;
            inside[(h - 1) * w + col] = false;
        }
        for row in 0..h {
            inside[row * w] = false;
            inside[row * w + w - 1] = false;
        }
    }

    /// The outlines of the inside centres by marching squares, each with its part: loops with
    /// the inside on their left (outer outlines counter-clockwise, holes clockwise).
    fn outlines(&self, field: &[f64], inside: &[bool], parts: &Parts) -> Vec<(usize, Vec<Point>)> {
        let w = self.n_cols;
        let node = |row: usize, col: usize| row * w + col;
        // Grid edges: 2·node for the edge to the right of a node, 2·node + 1 for the one below.
        let crossing = |a: usize, b: usize| -> Point {
            let (pa, pb) = (self.centre(a % w, a / w), self.centre(b % w, b / w));
            let (fa, fb) = (field[a], field[b]);
            let t = (fa / (fa - fb)).clamp(EDGE_CLAMP, 1.0 - EDGE_CLAMP);
            pa.lerp(pb, t)
        };
        let mut next = vec![usize::MAX; 2 * inside.len()];
        let mut position = vec![Point::ZERO; 2 * inside.len()];
        let mut part_of = vec![usize::MAX; 2 * inside.len()];
        for row in 0..self.n_rows - 1 {
            for col in 0..w - 1 {
                let corners = [
                    node(row, col),
                    node(row, col + 1),
                    node(row + 1, col + 1),
                    node(row + 1, col),
                ];
                let edges = [
                    2 * corners[0],
                    2 * corners[1] + 1,
                    2 * corners[3],
                    2 * corners[0] + 1,
                ];
                let is_in = corners.map(|k| inside[k]);
                let crossed: Vec<usize> =
                    (0..4).filter(|&e| is_in[e] != is_in[(e + 1) % 4]).collect();
                let mut link = |e: usize, f: usize, corner: usize| {
                    let (ea, eb) = (edges[e], edges[f]);
                    let pa = crossing_of(&crossing, corners, e);
                    let pb = crossing_of(&crossing, corners, f);
                    let q = self.centre(corners[corner] % w, corners[corner] / w);
                    let (from, to, p_from, p_to) = if (pb - pa).cross(q - pa) > 0.0 {
                        (ea, eb, pa, pb)
                    } else {
                        (eb, ea, pb, pa)
                    };
                    next[from] = to;
                    position[from] = p_from;
                    position[to] = p_to;
                    part_of[from] = parts.label[corners[corner]];
                };
                match crossed.len() {
                    2 => {
                        let corner = (0..4).find(|&k| is_in[k]).unwrap_or(0);
                        link(crossed[0], crossed[1], corner);
                    }
                    4 => {
                        // A saddle: cut off each inside corner on its own.
                        for corner in (0..4).filter(|&k| is_in[k]) {
                            link((corner + 3) % 4, corner, corner);
                        }
                    }
                    _ => {}
                }
            }
        }
        let mut loops = Vec::new();
        let mut seen = vec![false; next.len()];
        for start in 0..next.len() {
            if next[start] == usize::MAX || seen[start] {
                continue;
            }
            let mut poly = Vec::new();
            let mut e = start;
            while !seen[e] && next[e] != usize::MAX {
                seen[e] = true;
                poly.push(position[e]);
                e = next[e];
            }
            if e == start && poly.len() >= 3 {
                loops.push((part_of[start], poly));
            }
        }
        loops
    }
}

/// The crossing on square edge `e` (0 top, 1 right, 2 bottom, 3 left) of the square with
/// corners `corners` (top-left, top-right, bottom-right, bottom-left), from its inside end.
fn crossing_of(crossing: &impl Fn(usize, usize) -> Point, corners: [usize; 4], e: usize) -> Point {
    let (a, b) = (corners[e], corners[(e + 1) % 4]);
    // `crossing` interpolates from its first argument; both orders give the same point up to
    // rounding, so take the lower node first to make neighbouring squares agree bit for bit.
    if a < b {
        crossing(a, b)
    } else {
        crossing(b, a)
    }
}

/// Connected sets of inside centres (sharing a grid edge).
struct Parts {
    /// Per centre, its part (`usize::MAX` outside).
    label: Vec<usize>,
    n: usize,
}

impl Parts {
    fn label(inside: &[bool], w: usize, h: usize) -> Parts {
        let mut label = vec![usize::MAX; inside.len()];
        let mut n = 0;
        let mut stack = Vec::new();
        for start in 0..inside.len() {
            if !inside[start] || label[start] != usize::MAX {
                continue;
            }
            label[start] = n;
            stack.push(start);
            while let Some(k) = stack.pop() {
                let (row, col) = (k / w, k % w);
                let neighbours = [
                    (col > 0).then(|| k - 1),
                    (col + 1 < w).then(|| k + 1),
                    (row > 0).then(|| k - w),
                    (row + 1 < h).then(|| k + w),
                ];
                for m in neighbours.into_iter().flatten() {
                    if inside[m] && label[m] == usize::MAX {
                        label[m] = n;
                        stack.push(m);
                    }
                }
            }
            n += 1;
        }
        Parts { label, n }
    }

    /// Per part, whether a point handle or a bone end lies in one of its cells.
    fn pinned(&self, grid: &Grid, points: &[Point], bones: &[[Point; 2]]) -> Vec<bool> {
        let mut pinned = vec![false; self.n];
        for &p in points.iter().chain(bones.iter().flatten()) {
            let (col, row) = grid.cell_of(p);
            if let Some(flag) = pinned.get_mut(self.label[row * grid.n_cols + col]) {
                *flag = true;
            }
        }
        pinned
    }
}
