//! A uniform grid of buckets over a rectangle, each bucket listing the items (triangles, edges)
//! whose extent overlaps its cell: the spatial index of point location ([`super::MeshWeights`])
//! and of the proximity tests of the domain builder.
//!
//! Cells are squares of side `cell`; cell `(ix, iy)` covers
//! `[x0 + ix·cell, x0 + (ix+1)·cell) × [y0 + iy·cell, y0 + (iy+1)·cell)`. Points outside the
//! grid are clamped to the nearest cell. Buckets are stored CSR-style (one offset array, one
//! item array), so a grid of `n` registrations costs `n + n_cells + 1` integers.

use kurbo::{Point, Rect};

/// Largest number of cells of a grid: 4 Mi (`2²²`). A finer requested cell size is enlarged
/// until the grid fits, so memory stays bounded whatever the geometry.
pub const MAX_CELLS: usize = 1 << 22;

/// A uniform bucket grid (see the module documentation).
#[derive(Clone, Debug)]
pub(crate) struct BucketGrid {
    origin: Point,
    cell: f64,
    nx: usize,
    ny: usize,
    offsets: Vec<u32>,
    items: Vec<u32>,
}

impl BucketGrid {
    /// A grid over `bounds` (non-empty, finite) with cells of side about `cell` (enlarged so that
    /// there are at most [`MAX_CELLS`] cells), registering item `k` in every cell that
    /// `cells_of(k, …)` reports. `cells_of` receives an emitter of cell rectangles: every cell
    /// overlapping an emitted rectangle gets the item.
    pub(crate) fn build(
        bounds: Rect,
        cell: f64,
        n_items: usize,
        mut cells_of: impl FnMut(usize, &mut dyn FnMut(Rect)),
    ) -> BucketGrid {
        let w = bounds.width().max(0.0);
        let h = bounds.height().max(0.0);
        let mut cell = if cell.is_finite() && cell > 0.0 {
            cell
        } else {
            w.max(h).max(f64::MIN_POSITIVE)
        };
        let dims = |cell: f64| {
            let nx = ((w / cell).floor() as usize).saturating_add(1);
            let ny = ((h / cell).floor() as usize).saturating_add(1);
            (nx, ny)
        };
        let (mut nx, mut ny) = dims(cell);
        while nx.saturating_mul(ny) > MAX_CELLS {
            cell *= 2.0;
            (nx, ny) = dims(cell);
        }
        let mut grid = BucketGrid {
            origin: bounds.origin(),
            cell,
            nx,
            ny,
            offsets: Vec::new(),
            items: Vec::new(),
        };
        let mut pairs: Vec<(u32, u32)> = Vec::new();
        for k in 0..n_items {
            let mut emit = |r: Rect| {
                let (x0, y0) = grid.cell_of(Point::new(r.x0, r.y0));
                let (x1, y1) = grid.cell_of(Point::new(r.x1, r.y1));
                for iy in y0..=y1 {
                    for ix in x0..=x1 {
                        pairs.push(((iy * grid.nx + ix) as u32, k as u32));
                    }
                }
            };
            cells_of(k, &mut emit);
        }
        pairs.sort_unstable();
        pairs.dedup();
        let n_cells = nx * ny;
        let mut offsets = vec![0u32; n_cells + 1];
        for &(c, _) in &pairs {
            offsets[c as usize + 1] += 1;
        }
        for c in 0..n_cells {
            offsets[c + 1] += offsets[c];
        }
        grid.items = pairs.into_iter().map(|(_, k)| k).collect();
        grid.offsets = offsets;
        grid
    }

    /// Emits rectangles covering the segment `a b` piecewise (pieces no longer than a cell), so
    /// that a long oblique segment is registered only in the cells along it, not in its whole
    /// bounding box.
    pub(crate) fn segment_pieces(cell: f64, a: Point, b: Point, emit: &mut dyn FnMut(Rect)) {
        let len = (b - a).hypot();
        let n = if cell > 0.0 && len.is_finite() {
            ((len / cell).ceil() as usize).clamp(1, 1 << 16)
        } else {
            1
        };
        let mut prev = a;
        for k in 1..=n {
            let next = if k == n {
                b
            } else {
                a.lerp(b, k as f64 / n as f64)
            };
            emit(Rect::from_points(prev, next));
            prev = next;
        }
    }

    /// Side of a cell.
    pub(crate) fn cell_size(&self) -> f64 {
        self.cell
    }

    /// Number of cells along x and y.
    pub(crate) fn dims(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }

    /// The cell containing `p`, clamped into the grid.
    #[inline]
    pub(crate) fn cell_of(&self, p: Point) -> (usize, usize) {
        let fx = ((p.x - self.origin.x) / self.cell).floor();
        let fy = ((p.y - self.origin.y) / self.cell).floor();
        // NaN clamps to 0 through the `as` cast.
        let ix = (fx.max(0.0) as usize).min(self.nx - 1);
        let iy = (fy.max(0.0) as usize).min(self.ny - 1);
        (ix, iy)
    }

    /// The items registered in cell `(ix, iy)` (in range).
    #[inline]
    pub(crate) fn bucket(&self, ix: usize, iy: usize) -> &[u32] {
        let c = iy * self.nx + ix;
        &self.items[self.offsets[c] as usize..self.offsets[c + 1] as usize]
    }

    /// Calls `f` with the bucket of every cell overlapping `r`.
    pub(crate) fn for_cells_in(&self, r: Rect, mut f: impl FnMut(&[u32])) {
        let (x0, y0) = self.cell_of(Point::new(r.x0, r.y0));
        let (x1, y1) = self.cell_of(Point::new(r.x1, r.y1));
        for iy in y0..=y1 {
            for ix in x0..=x1 {
                f(self.bucket(ix, iy));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_registers_segment_only_along_it() {
        let bounds = Rect::new(0.0, 0.0, 10.0, 10.0);
        let seg = [Point::new(0.5, 0.5), Point::new(9.5, 9.5)];
        let g = BucketGrid::build(bounds, 1.0, 1, |_, emit| {
            BucketGrid::segment_pieces(1.0, seg[0], seg[1], emit)
        });
        assert_eq!(g.dims(), (11, 11));
        // On the diagonal: present; far from it: absent.
        assert_eq!(g.bucket(5, 5), &[0]);
        assert!(g.bucket(0, 9).is_empty());
        assert!(g.bucket(9, 0).is_empty());
        let n_cells_with: usize = (0..11)
            .flat_map(|y| (0..11).map(move |x| (x, y)))
            .filter(|&(x, y)| !g.bucket(x, y).is_empty())
            .count();
        assert!(n_cells_with <= 3 * 10, "{n_cells_with}");
    }

    #[test]
    fn grid_clamps_points_outside_and_caps_cells() {
        let bounds = Rect::new(0.0, 0.0, 1.0, 1.0);
        let g = BucketGrid::build(bounds, 1e-9, 0, |_, _| {});
        let (nx, ny) = g.dims();
        assert!(nx * ny <= MAX_CELLS);
        assert_eq!(g.cell_of(Point::new(-5.0, 7.0)), (0, ny - 1));
        assert_eq!(g.cell_of(Point::new(f64::NAN, 0.0)).0, 0);
    }
}
