//! Automatic pin placement: point handles spread over a drawing's filled shapes, so that a
//! drawing can be rigged without choosing handles by hand (`splineskin rig`).
//!
//! **The rule** ([`place_pins`]), deterministic (no randomness; ties go to the first cell in
//! row-major order):
//!
//! 1. **Candidates.** A square grid of cell size `c = L / grid_cells` (`L` the longer side of
//!    the drawing's control-point box) is laid over the drawing. A cell centre is *inside the
//!    art* when it is inside one element's fill by parity: an odd number of the edges of the
//!    element's subpaths (each flattened to within `c/8`, an open one closed by a line from
//!    its end to its start, as SVG fills it) cross the row to its left. An odd crossing count
//!    is an odd winding number, which is inside under **both** SVG fill rules (`nonzero` and
//!    `evenodd`), so a pin never lands in a hole whichever rule the element uses; only regions
//!    a `nonzero` element covers twice (overlapping subpaths of the same direction) are passed
//!    over. Elements are told apart by the drawing's source ([`Drawing::source`]); without one
//!    every path is its own shape. The drawing does not record paint, so every element counts
//!    as filled (SVG's default paint), also one drawn with `fill="none"`: in practice such
//!    outlines and strokes lie on or around the drawing's coloured fills.
//! 2. **Main pieces, inset.** The inside cells form *pieces* (4-connected sets of cells);
//!    only pieces of at least `piece_fraction` times the largest piece's area take pins, so
//!    that a figure's pins are not spent on small details set apart from it (a bubble, a
//!    caption's frame). Each inside cell's *depth* is the Euclidean distance from its centre
//!    to the nearest cell centre outside the art (the grid's border counts as outside). Pins
//!    are taken only from cells of main pieces whose depth is at least
//!    `min(INSET_CELLS · c, d_max / 2)` (`d_max` the largest depth there), so that they sit
//!    inside shapes rather than on their edges.
//! 3. **No shape at all.** A drawing with no inside cell (only straight strokes, or shapes
//!    smaller than a cell) takes its candidates on its curves instead: points every `c` of parameter
//!    length along every curve (`⌈chord length / c⌉` per curve).
//! 4. **Farthest points.** The given pins come first, kept exactly. If there are none, the
//!    first pin is the deepest candidate (the middle of the thickest shape). Each next pin is
//!    the candidate farthest (Euclidean) from every pin so far.
//! 5. **How many.** [`PinCount::Exactly`] stops at that many pins (the given ones included).
//!    [`PinCount::Auto`] stops once every candidate lies within the *cover distance* of a pin,
//!    with at least `min_pins` and at most `max_pins` pins (the given ones count). The cover
//!    distance is `cover_depths · d_max`: a compact shape (a disc: `d_max` is its radius) is
//!    covered by the fewest pins, a long or branching one (a bar, a figure with limbs) takes
//!    more. A drawing of curves (rule 3) has no depth: its cover distance is
//!    `cover_fraction · D` (`D` the diagonal of the control-point box).
//!
//! Automatic pins are rounded to a decimal step of at most `c/100` (e.g. `0.01` on a
//! 72-unit icon), so that scenes stay readable.
//!
//! **Spread.** Farthest-point sampling picks the `k`-th pin at distance `r_k` from all
//! earlier ones, with `r_k` non-increasing, so the smallest distance between any two
//! automatic pins (and from them to the given ones) is the last `r_k`, which is at least the
//! largest distance from a candidate to its nearest pin (the covering radius). Since `k` discs
//! of that radius cover the candidates, `k π r² ≥ A` for candidates filling an area `A`:
//! the smallest pairwise distance is at least `√(A / (k π))`, less a cell's discretisation.

use kurbo::{BezPath, ParamCurve, PathEl, Point};

use crate::domain::distance::distance_to_marked;
use crate::drawing::Drawing;

/// Default number of grid cells along the longer side of the drawing's box: 256 (pins within
/// 0.4 % of the drawing's size of where a finer grid would put them; about 65 000 cells, a few
/// milliseconds).
pub const DEFAULT_GRID_CELLS: usize = 256;

/// Largest accepted `grid_cells`: 4096 (16 million cells).
pub const MAX_GRID_CELLS: usize = 4096;

/// Inset of pins from the edges of shapes, in grid cells: 2 (see the module documentation).
pub const INSET_CELLS: f64 = 2.0;

/// Default cover distance of [`PinCount::Auto`] on shapes, in largest depths: 1 (every point
/// of the art as near a pin as the middle of its thickest part is to its edge: three pins on a
/// disc, six on the bundled fish: its middle, both tail tips, nose, dorsal and anal fins).
pub const DEFAULT_COVER_DEPTHS: f64 = 1.0;

/// Default cover distance of [`PinCount::Auto`] on a drawing of curves, as a fraction of the
/// diagonal: 0.2.
pub const DEFAULT_COVER_FRACTION: f64 = 0.2;

/// Default smallest piece that takes pins: 0.2 of the largest piece's area. Pieces are the
/// connected parts of the art; a fifth leaves out a drawing's details set apart from its
/// figure (the bundled fish's bubbles and name plate, 0.1 % and 9 % of the fish) and keeps
/// figures of comparable size (two characters side by side).
pub const DEFAULT_PIECE_FRACTION: f64 = 0.2;

/// Default fewest pins of [`PinCount::Auto`]: 3 (with two, everything between them can only
/// stretch along one line).
pub const DEFAULT_MIN_PINS: usize = 3;

/// Default most pins of [`PinCount::Auto`]: 6 (enough to pose a figure's trunk and limbs, few
/// enough that bounded biharmonic weights stay fast to solve).
pub const DEFAULT_MAX_PINS: usize = 6;

/// Most pins [`place_pins`] places: 256 (each pin is a handle with a weight function).
pub const MAX_PINS: usize = 256;

/// How many pins [`place_pins`] returns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PinCount {
    /// As many as needed to cover the art ([`PinOptions::cover_fraction`]), within
    /// [`PinOptions::min_pins`]`..=`[`PinOptions::max_pins`].
    Auto,
    /// Exactly this many, the given pins included.
    Exactly(usize),
}

/// Options of [`place_pins`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct PinOptions {
    /// How many pins. Default: [`PinCount::Auto`].
    pub count: PinCount,
    /// Grid cells along the longer side of the drawing's box. Default: [`DEFAULT_GRID_CELLS`].
    pub grid_cells: usize,
    /// [`PinCount::Auto`]'s cover distance on shapes, in largest depths (module
    /// documentation, rule 5). Default: [`DEFAULT_COVER_DEPTHS`].
    pub cover_depths: f64,
    /// [`PinCount::Auto`]'s cover distance on a drawing of curves, a fraction of the diagonal.
    /// Default: [`DEFAULT_COVER_FRACTION`].
    pub cover_fraction: f64,
    /// [`PinCount::Auto`]'s fewest pins. Default: [`DEFAULT_MIN_PINS`].
    pub min_pins: usize,
    /// [`PinCount::Auto`]'s most pins. Default: [`DEFAULT_MAX_PINS`].
    pub max_pins: usize,
    /// Smallest piece that takes pins, as a fraction of the largest piece's area (module
    /// documentation, rule 2). Default: [`DEFAULT_PIECE_FRACTION`].
    pub piece_fraction: f64,
}

impl Default for PinOptions {
    fn default() -> Self {
        PinOptions {
            count: PinCount::Auto,
            grid_cells: DEFAULT_GRID_CELLS,
            cover_depths: DEFAULT_COVER_DEPTHS,
            cover_fraction: DEFAULT_COVER_FRACTION,
            min_pins: DEFAULT_MIN_PINS,
            max_pins: DEFAULT_MAX_PINS,
            piece_fraction: DEFAULT_PIECE_FRACTION,
        }
    }
}

impl PinOptions {
    /// Sets [`PinOptions::count`].
    pub fn with_count(mut self, count: PinCount) -> Self {
        self.count = count;
        self
    }

    /// Sets [`PinOptions::grid_cells`].
    pub fn with_grid_cells(mut self, cells: usize) -> Self {
        self.grid_cells = cells;
        self
    }

    /// Sets [`PinOptions::cover_depths`].
    pub fn with_cover_depths(mut self, depths: f64) -> Self {
        self.cover_depths = depths;
        self
    }

    /// Sets [`PinOptions::cover_fraction`].
    pub fn with_cover_fraction(mut self, fraction: f64) -> Self {
        self.cover_fraction = fraction;
        self
    }

    /// Sets [`PinOptions::piece_fraction`].
    pub fn with_piece_fraction(mut self, fraction: f64) -> Self {
        self.piece_fraction = fraction;
        self
    }

    /// Sets [`PinOptions::min_pins`] and [`PinOptions::max_pins`].
    pub fn with_pin_range(mut self, min_pins: usize, max_pins: usize) -> Self {
        self.min_pins = min_pins;
        self.max_pins = max_pins;
        self
    }
}

/// Why pins could not be placed.
#[derive(Debug, thiserror::Error, PartialEq)]
#[non_exhaustive]
pub enum PinError {
    /// The drawing has no curve with any extent.
    #[error(
        "nothing to pin: the drawing has no curves with any extent (expected at least one \
         path, e.g. a <path>, <rect> or <circle> with a size)"
    )]
    NothingToPin,
    /// A given pin is not a finite point.
    #[error("pin {index} at ({x:?}, {y:?}) is not a finite point")]
    NonFinite {
        /// Its index among the given pins.
        index: usize,
        /// Its x.
        x: f64,
        /// Its y.
        y: f64,
    },
    /// Fewer pins asked for than given, none at all, or more than [`MAX_PINS`].
    #[error("{count} pins asked for with {given} given: expected a count from {} to {MAX_PINS}", (*given).max(1))]
    Count {
        /// The count asked for.
        count: usize,
        /// The number of given pins.
        given: usize,
    },
    /// The options are out of range.
    #[error("invalid pin options: {what}")]
    Options {
        /// Which option and what was expected.
        what: String,
    },
    /// The drawing has fewer distinct candidate points than the pins asked for.
    #[error(
        "only {placed} distinct pins fit on the drawing at this grid ({asked} asked for; \
         expected fewer pins or a finer grid)"
    )]
    TooFewCandidates {
        /// Pins asked for.
        asked: usize,
        /// Pins placed before the candidates ran out.
        placed: usize,
    },
}

/// The pins of `drawing`: `given` first (kept exactly), then automatic ones by the rule of the
/// module documentation, as many as `options.count` says. Units are the drawing's (root user
/// units for a drawing read from SVG).
///
/// Errors: [`PinError::NothingToPin`] for a drawing without extent, [`PinError::NonFinite`]
/// for a given pin that is NaN or infinite, [`PinError::Count`] for a count of 0, below
/// `given.len()` or above [`MAX_PINS`], [`PinError::Options`] for options out of range,
/// [`PinError::TooFewCandidates`] when the drawing runs out of distinct points.
///
/// ```
/// use kurbo::Point;
/// use splineskin::drawing::{read_svg, ImportOptions};
/// use splineskin::scene::pins::{place_pins, PinCount, PinOptions};
///
/// // A 100 × 20 bar with a 40 × 20 block beside it.
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg">
///   <rect width="100" height="20"/><rect x="140" width="40" height="20"/></svg>"#;
/// let drawing = read_svg(svg, &ImportOptions::default())?;
/// let options = PinOptions::default().with_count(PinCount::Exactly(3));
/// let pins = place_pins(&drawing, &[], &options)?;
/// assert_eq!(pins.len(), 3);
/// // Every pin is inside one of the two rectangles, at least one in each.
/// let in_bar = |p: &Point| p.x > 0.0 && p.x < 100.0 && p.y > 0.0 && p.y < 20.0;
/// let in_block = |p: &Point| p.x > 140.0 && p.x < 180.0 && p.y > 0.0 && p.y < 20.0;
/// assert!(pins.iter().all(|p| in_bar(p) || in_block(p)));
/// assert!(pins.iter().any(in_bar) && pins.iter().any(in_block));
///
/// // A given pin is kept exactly, first; the others are placed around it.
/// let given = [Point::new(10.0, 10.0)];
/// let pins = place_pins(&drawing, &given, &options)?;
/// assert_eq!(pins[0], given[0]);
/// assert_eq!(pins.len(), 3);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn place_pins(
    drawing: &Drawing,
    given: &[Point],
    options: &PinOptions,
) -> Result<Vec<Point>, PinError> {
    check_options(options)?;
    for (index, p) in given.iter().enumerate() {
        if !(p.x.is_finite() && p.y.is_finite()) {
            return Err(PinError::NonFinite {
                index,
                x: p.x,
                y: p.y,
            });
        }
    }
    let (target, min_pins, max_pins) = match options.count {
        PinCount::Exactly(n) => {
            if n == 0 || n < given.len() || n > MAX_PINS {
                return Err(PinError::Count {
                    count: n,
                    given: given.len(),
                });
            }
            (Some(n), n, n)
        }
        PinCount::Auto => (
            None,
            options.min_pins.max(given.len()),
            options.max_pins.max(given.len()),
        ),
    };
    let grid = Grid::of(drawing, options.grid_cells).ok_or(PinError::NothingToPin)?;
    let candidates = candidates(drawing, &grid, options.piece_fraction);
    if candidates.points.is_empty() {
        return Err(PinError::NothingToPin);
    }
    let cover = match candidates.max_depth {
        Some(depth) => options.cover_depths * depth,
        None => options.cover_fraction * grid.diagonal,
    };
    let mut pins = given.to_vec();
    // Squared distance of every candidate to its nearest pin.
    let mut nearest = vec![f64::INFINITY; candidates.points.len()];
    for &p in given {
        update_nearest(&candidates.points, &mut nearest, p);
    }
    let step = rounding_step(grid.cell);
    while pins.len() < max_pins {
        let next = if pins.is_empty() {
            candidates.deepest
        } else {
            arg_max(&nearest)
        };
        let farthest = nearest[next];
        if farthest == 0.0 {
            // Every candidate is a pin already.
            if target.is_some() {
                return Err(PinError::TooFewCandidates {
                    asked: max_pins,
                    placed: pins.len(),
                });
            }
            break;
        }
        if pins.len() >= min_pins && farthest.sqrt() <= cover {
            break;
        }
        let p = candidates.points[next];
        let p = Point::new(round_to(p.x, step), round_to(p.y, step));
        pins.push(p);
        update_nearest(&candidates.points, &mut nearest, p);
    }
    Ok(pins)
}

fn check_options(options: &PinOptions) -> Result<(), PinError> {
    let invalid = |what: String| Err(PinError::Options { what });
    if !(1..=MAX_GRID_CELLS).contains(&options.grid_cells) {
        return invalid(format!(
            "grid_cells = {} (expected 1 to {MAX_GRID_CELLS})",
            options.grid_cells
        ));
    }
    for (name, value) in [
        ("cover_depths", options.cover_depths),
        ("cover_fraction", options.cover_fraction),
    ] {
        if !(value.is_finite() && value > 0.0) {
            return invalid(format!("{name} = {value} (expected a positive number)"));
        }
    }
    if !(options.piece_fraction.is_finite() && (0.0..=1.0).contains(&options.piece_fraction)) {
        return invalid(format!(
            "piece_fraction = {} (expected a number from 0 to 1)",
            options.piece_fraction
        ));
    }
    if options.min_pins == 0 || options.min_pins > options.max_pins || options.max_pins > MAX_PINS {
        return invalid(format!(
            "min_pins = {}, max_pins = {} (expected 1 ≤ min_pins ≤ max_pins ≤ {MAX_PINS})",
            options.min_pins, options.max_pins
        ));
    }
    Ok(())
}

/// The candidate grid: cell centres `origin + ((c + ½) cell, (r + ½) cell)`.
struct Grid {
    origin: Point,
    cell: f64,
    n_cols: usize,
    n_rows: usize,
    diagonal: f64,
}

impl Grid {
    /// The grid over `drawing`'s control-point box; `None` when the box has no extent.
    fn of(drawing: &Drawing, grid_cells: usize) -> Option<Grid> {
        let bounds = drawing.control_bounds()?;
        let longer = bounds.width().max(bounds.height());
        if !(longer > 0.0 && longer.is_finite()) {
            return None;
        }
        let cell = longer / grid_cells as f64;
        let cells = |side: f64| ((side / cell).ceil() as usize).clamp(1, grid_cells);
        Some(Grid {
            origin: Point::new(bounds.x0, bounds.y0),
            cell,
            n_cols: cells(bounds.width()),
            n_rows: cells(bounds.height()),
            diagonal: bounds.width().hypot(bounds.height()),
        })
    }

    fn centre(&self, col: usize, row: usize) -> Point {
        Point::new(
            self.origin.x + (col as f64 + 0.5) * self.cell,
            self.origin.y + (row as f64 + 0.5) * self.cell,
        )
    }
}

/// Where pins may go, the first pin's index, and the largest depth (drawing units; `None` for
/// curve samples).
struct Candidates {
    points: Vec<Point>,
    deepest: usize,
    max_depth: Option<f64>,
}

/// The inset inside cells of `grid` (rules 1–2), or curve samples (rule 3).
fn candidates(drawing: &Drawing, grid: &Grid, piece_fraction: f64) -> Candidates {
    let inside = inside_mask(drawing, grid);
    if inside.iter().any(|&b| b) {
        let depth = depth(&inside, grid.n_cols, grid.n_rows);
        let main = main_pieces(&inside, grid.n_cols, grid.n_rows, piece_fraction);
        let max_depth = depth
            .iter()
            .zip(&main)
            .filter(|(_, &m)| m)
            .map(|(&d, _)| d)
            .fold(0.0, f64::max);
        let inset = (INSET_CELLS * INSET_CELLS).min(max_depth * max_depth / 4.0);
        let mut points = Vec::new();
        let mut deepest = (0, f64::NEG_INFINITY);
        for row in 0..grid.n_rows {
            for col in 0..grid.n_cols {
                let d = depth[row * grid.n_cols + col];
                if main[row * grid.n_cols + col] && d * d >= inset {
                    if d > deepest.1 {
                        deepest = (points.len(), d);
                    }
                    points.push(grid.centre(col, row));
                }
            }
        }
        return Candidates {
            points,
            deepest: deepest.0,
            max_depth: Some(max_depth * grid.cell),
        };
    }
    let mut points = Vec::new();
    for path in &drawing.paths {
        for j in 0..path.n_curves() {
            let curve = path.curve(j);
            let chord: f64 = [
                curve.p1 - curve.p0,
                curve.p2 - curve.p1,
                curve.p3 - curve.p2,
            ]
            .iter()
            .map(|v| v.hypot())
            .sum();
            let n = ((chord / grid.cell).ceil() as usize).clamp(1, MAX_GRID_CELLS);
            points.extend((0..n).map(|k| curve.eval(k as f64 / n as f64)));
        }
        if !path.closed {
            if let Some(&last) = path.points.last() {
                points.push(last);
            }
        }
    }
    // The first pin of a drawing of curves: the sample nearest the middle of its box.
    let middle = grid.origin
        + kurbo::Vec2::new(
            grid.n_cols as f64 * grid.cell / 2.0,
            grid.n_rows as f64 * grid.cell / 2.0,
        );
    let deepest = arg_max(
        &points
            .iter()
            .map(|p| -(*p - middle).hypot2())
            .collect::<Vec<_>>(),
    );
    Candidates {
        points,
        deepest,
        max_depth: None,
    }
}

/// The cells of `inside` in its main pieces: the 4-connected sets of inside cells with at least
/// `fraction` times as many cells as the largest one.
fn main_pieces(inside: &[bool], n_cols: usize, n_rows: usize, fraction: f64) -> Vec<bool> {
    const NONE: usize = usize::MAX;
    let mut piece = vec![NONE; inside.len()];
    let mut sizes = Vec::new();
    let mut stack = Vec::new();
    for start in 0..inside.len() {
        if !inside[start] || piece[start] != NONE {
            continue;
        }
        let label = sizes.len();
        let mut size = 0usize;
        piece[start] = label;
        stack.push(start);
        while let Some(k) = stack.pop() {
            size += 1;
            let (row, col) = (k / n_cols, k % n_cols);
            let neighbours = [
                (col > 0).then(|| k - 1),
                (col + 1 < n_cols).then(|| k + 1),
                (row > 0).then(|| k - n_cols),
                (row + 1 < n_rows).then(|| k + n_cols),
            ];
            for n in neighbours.into_iter().flatten() {
                if inside[n] && piece[n] == NONE {
                    piece[n] = label;
                    stack.push(n);
                }
            }
        }
        sizes.push(size);
    }
    let largest = sizes.iter().copied().max().unwrap_or(0) as f64;
    piece
        .iter()
        .map(|&p| p != NONE && sizes[p] as f64 >= fraction * largest)
        .collect()
}

/// `n_rows × n_cols` flags, row-major: whether each cell centre is inside the art (rule 1).
fn inside_mask(drawing: &Drawing, grid: &Grid) -> Vec<bool> {
    let mut inside = vec![false; grid.n_cols * grid.n_rows];
    let tolerance = grid.cell / 8.0;
    // Paths grouped by element (each path alone without a source).
    let mut groups: Vec<(usize, Vec<usize>)> = Vec::new();
    for i in 0..drawing.paths.len() {
        let key = drawing
            .source
            .as_ref()
            .and_then(|s| s.element_of_path(i))
            .map_or(usize::MAX - i, |e| e);
        match groups.last_mut() {
            Some((k, members)) if *k == key => members.push(i),
            _ => match groups.iter_mut().find(|(k, _)| *k == key) {
                Some((_, members)) => members.push(i),
                None => groups.push((key, vec![i])),
            },
        }
    }
    let mut crossings: Vec<Vec<f64>> = vec![Vec::new(); grid.n_rows];
    for (_, members) in &groups {
        for row in &mut crossings {
            row.clear();
        }
        for &i in members {
            let path = &drawing.paths[i];
            let mut bez = BezPath::new();
            bez.move_to(path.points[0]);
            for j in 0..path.n_curves() {
                let c = path.curve(j);
                bez.curve_to(c.p1, c.p2, c.p3);
            }
            bez.close_path();
            let mut start = path.points[0];
            let mut last = start;
            kurbo::flatten(&bez, tolerance, |el| {
                let to = match el {
                    PathEl::MoveTo(p) => {
                        start = p;
                        last = p;
                        return;
                    }
                    PathEl::LineTo(p) => p,
                    PathEl::ClosePath => start,
                    // flatten emits lines only.
                    _ => return,
                };
                edge_crossings(grid, last, to, &mut crossings);
                last = to;
            });
        }
        for (row, xs) in crossings.iter_mut().enumerate() {
            if xs.is_empty() {
                continue;
            }
            xs.sort_by(f64::total_cmp);
            let mut k = 0;
            for col in 0..grid.n_cols {
                let x = grid.centre(col, row).x;
                while k < xs.len() && xs[k] < x {
                    k += 1;
                }
                if k % 2 == 1 {
                    inside[row * grid.n_cols + col] = true;
                }
            }
        }
    }
    inside
}

/// Adds to `crossings[row]` the x where segment `a`–`b` crosses the row's centre line, for
/// every row it crosses (half-open in y, so a vertex on a line is counted once).
fn edge_crossings(grid: &Grid, a: Point, b: Point, crossings: &mut [Vec<f64>]) {
    if a.y == b.y {
        return;
    }
    let (lo, hi) = if a.y < b.y { (a, b) } else { (b, a) };
    // Rows whose centre y satisfies lo.y <= y < hi.y.
    let row_of = |y: f64| (y - grid.origin.y) / grid.cell - 0.5;
    let first = row_of(lo.y).ceil().max(0.0);
    let end = row_of(hi.y).ceil().min(grid.n_rows as f64);
    let mut row = first;
    while row < end {
        let r = row as usize;
        let y = grid.centre(0, r).y;
        if y >= lo.y && y < hi.y {
            let t = (y - lo.y) / (hi.y - lo.y);
            crossings[r].push(lo.x + t * (hi.x - lo.x));
        }
        row += 1.0;
    }
}

/// Per cell, the Euclidean distance (in cells) from its centre to the nearest centre of a
/// cell outside the art, the grid's surroundings counting as outside; 0 outside
/// ([`distance_to_marked`] of the outside cells, on the grid padded by a ring of outside cells).
fn depth(inside: &[bool], n_cols: usize, n_rows: usize) -> Vec<f64> {
    let (w, h) = (n_cols + 2, n_rows + 2);
    let mut outside = vec![true; w * h];
    for row in 0..n_rows {
        for col in 0..n_cols {
            outside[(row + 1) * w + col + 1] = !inside[row * n_cols + col];
        }
    }
    let padded = distance_to_marked(&outside, w, h);
    let mut depth = vec![0.0; n_cols * n_rows];
    for row in 0..n_rows {
        for col in 0..n_cols {
            depth[row * n_cols + col] = padded[(row + 1) * w + col + 1];
        }
    }
    depth
}

fn update_nearest(points: &[Point], nearest: &mut [f64], pin: Point) {
    for (d, p) in nearest.iter_mut().zip(points) {
        *d = d.min((*p - pin).hypot2());
    }
}

/// The index of the largest value (the first of equal ones).
fn arg_max(values: &[f64]) -> usize {
    let mut best = 0;
    for (k, &v) in values.iter().enumerate() {
        if v > values[best] {
            best = k;
        }
    }
    best
}

/// The largest power of ten at most `cell / 100`.
fn rounding_step(cell: f64) -> f64 {
    10f64.powf((cell / 100.0).log10().floor())
}

/// `v` rounded to a multiple of `step` (a power of ten), as the nearest `f64` to the decimal,
/// so that it prints short (`0.3`, not `0.30000000000000004`).
fn round_to(v: f64, step: f64) -> f64 {
    if step < 1.0 {
        let inverse = (1.0 / step).round();
        (v * inverse).round() / inverse
    } else {
        (v / step).round() * step
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::{read_svg, ImportOptions};

    fn drawing(body: &str) -> Drawing {
        let svg = format!(r#"<svg xmlns="http://www.w3.org/2000/svg">{body}</svg>"#);
        read_svg(&svg, &ImportOptions::default()).unwrap()
    }

    fn exactly(n: usize) -> PinOptions {
        PinOptions::default().with_count(PinCount::Exactly(n))
    }

    fn min_pairwise(pins: &[Point]) -> f64 {
        let mut d = f64::INFINITY;
        for (a, p) in pins.iter().enumerate() {
            for q in &pins[a + 1..] {
                d = d.min((*p - *q).hypot());
            }
        }
        d
    }

    /// The spread bound of the module documentation: `k` pins on candidates filling at least
    /// `area` are at least `√(area / (k π)) − c/√2 − 2·step` apart (`c` the cell, `step` the
    /// rounding).
    fn spread_bound(area: f64, k: usize, cell: f64) -> f64 {
        (area / (k as f64 * std::f64::consts::PI)).sqrt()
            - cell / std::f64::consts::SQRT_2
            - 2.0 * rounding_step(cell)
    }

    #[test]
    fn pins_spread_over_a_square_by_the_covering_bound() {
        let d = drawing(r#"<rect width="100" height="100"/>"#);
        let cell = 100.0 / DEFAULT_GRID_CELLS as f64;
        // Candidates fill the square eroded by the inset and one cell of discretisation.
        let side = 100.0 - 2.0 * (INSET_CELLS + 1.0) * cell;
        for k in [2, 3, 5, 8, 13] {
            let pins = place_pins(&d, &[], &exactly(k)).unwrap();
            assert_eq!(pins.len(), k);
            let bound = spread_bound(side * side, k, cell);
            let spread = min_pairwise(&pins);
            assert!(spread >= bound, "{k} pins {spread} apart, bound {bound}");
            for p in &pins {
                assert!(
                    p.x > 0.0 && p.x < 100.0 && p.y > 0.0 && p.y < 100.0,
                    "{p:?}"
                );
            }
        }
        // The first pin is the deepest point: the middle.
        let pins = place_pins(&d, &[], &exactly(1)).unwrap();
        assert!(
            (pins[0] - Point::new(50.0, 50.0)).hypot() <= cell,
            "{pins:?}"
        );
    }

    #[test]
    fn pins_stay_out_of_holes_under_either_fill_rule() {
        // A ring: outer circle r = 50, hole r = 30, about (50, 50); the hole drawn in the same
        // direction (a nonzero fill would cover it, evenodd would not) and in the opposite
        // one (a hole under both rules).
        let same = "M0 50 A50 50 0 1 1 100 50 A50 50 0 1 1 0 50 Z \
                    M20 50 A30 30 0 1 1 80 50 A30 30 0 1 1 20 50 Z";
        let opposite = "M0 50 A50 50 0 1 1 100 50 A50 50 0 1 1 0 50 Z \
                        M20 50 A30 30 0 1 0 80 50 A30 30 0 1 0 20 50 Z";
        for (d, rule) in [(same, "evenodd"), (opposite, "nonzero")] {
            let drawing = drawing(&format!(r#"<path fill-rule="{rule}" d="{d}"/>"#));
            let pins = place_pins(&drawing, &[], &exactly(6)).unwrap();
            for p in &pins {
                let r = (*p - Point::new(50.0, 50.0)).hypot();
                assert!(r > 30.0 && r < 50.0, "{rule}: pin {p:?} at radius {r}");
            }
            // Ring area inset by the inset and a cell on both sides.
            let cell = 100.0 / DEFAULT_GRID_CELLS as f64;
            let e = (INSET_CELLS + 1.0) * cell;
            let area = std::f64::consts::PI * ((50.0 - e).powi(2) - (30.0 + e).powi(2));
            assert!(min_pairwise(&pins) >= spread_bound(area, 6, cell));
        }
    }

    #[test]
    fn pins_land_on_every_separate_shape_when_enough() {
        // Three equal squares far apart: three pins, one in each.
        let d = drawing(
            r#"<rect width="10" height="10"/><rect x="100" width="10" height="10"/>
               <rect x="50" y="80" width="10" height="10"/>"#,
        );
        let pins = place_pins(&d, &[], &exactly(3)).unwrap();
        for x0 in [0.0, 100.0, 50.0] {
            assert_eq!(
                pins.iter().filter(|p| p.x > x0 && p.x < x0 + 10.0).count(),
                1,
                "{pins:?}"
            );
        }
    }

    #[test]
    fn pins_pass_over_small_pieces_set_apart() {
        // A 100 × 100 square and a 10 × 10 one (1 % of its area) apart: however many pins are
        // asked for, none on the small one, unless the fraction lets it in.
        let d =
            drawing(r#"<rect width="100" height="100"/><rect x="150" width="10" height="10"/>"#);
        let small = |p: &Point| p.x > 140.0;
        let pins = place_pins(&d, &[], &exactly(12)).unwrap();
        assert!(!pins.iter().any(small), "{pins:?}");
        let all = exactly(12).with_piece_fraction(0.0);
        let pins = place_pins(&d, &[], &all).unwrap();
        assert!(pins.iter().any(small), "{pins:?}");
    }

    #[test]
    fn pins_keep_given_ones_exactly_and_first() {
        let d = drawing(r#"<rect width="100" height="40"/>"#);
        // Given pins need not be on the art; they are kept bit for bit.
        let given = [Point::new(0.1 + 0.2, 7.0), Point::new(-20.0, 1e-3)];
        let pins = place_pins(&d, &given, &exactly(4)).unwrap();
        assert_eq!(&pins[..2], &given);
        assert_eq!(pins.len(), 4);
        for p in &pins[2..] {
            assert!(p.x > 0.0 && p.x < 100.0 && p.y > 0.0 && p.y < 40.0, "{p:?}");
            // Farther from the given pins than the first automatic pin would be without them
            // (it would be the middle, 50 from the first given pin).
            assert!(given.iter().all(|g| (*p - *g).hypot() > 10.0), "{p:?}");
        }
        // Exactly the given number: nothing added.
        assert_eq!(place_pins(&d, &given, &exactly(2)).unwrap(), given.to_vec());
    }

    #[test]
    fn pins_auto_count_follows_the_shape() {
        let disc = drawing(r#"<circle cx="50" cy="50" r="50"/>"#);
        let pins = place_pins(&disc, &[], &PinOptions::default()).unwrap();
        assert_eq!(pins.len(), DEFAULT_MIN_PINS, "{pins:?}");
        // A long thin bar needs more to be covered within its half-width.
        let bar = drawing(r#"<rect width="400" height="20"/>"#);
        let pins = place_pins(&bar, &[], &PinOptions::default()).unwrap();
        assert!(pins.len() > DEFAULT_MIN_PINS, "{pins:?}");
        assert!(pins.len() <= DEFAULT_MAX_PINS);
    }

    #[test]
    fn pins_fill_open_paths_as_svg_does() {
        // An open path is filled as if closed by a line back to its start: the lens between
        // the curve and its chord (y from 0 to 30).
        let d = drawing(r#"<path d="M0 0 C30 40 70 40 100 0"/>"#);
        let pins = place_pins(&d, &[], &exactly(3)).unwrap();
        for p in &pins {
            assert!(p.x > 0.0 && p.x < 100.0 && p.y > 0.0 && p.y < 30.0, "{p:?}");
        }
    }

    #[test]
    fn pins_on_curves_when_nothing_encloses_an_area() {
        // Two straight strokes: no area, so the pins go on the lines.
        let d = drawing(
            r#"<path fill="none" stroke="black" d="M0 0 L100 0"/>
               <line x1="0" y1="10" x2="100" y2="60" stroke="black"/>"#,
        );
        let pins = place_pins(&d, &[], &exactly(4)).unwrap();
        for p in &pins {
            let on_first = p.y.abs() < 1e-9 && (0.0..=100.0).contains(&p.x);
            let on_second = (p.y - (10.0 + 0.5 * p.x)).abs() < 1e-2 && (0.0..=100.0).contains(&p.x);
            assert!(on_first || on_second, "{p:?} is off the lines");
        }
        // Farthest points on lines: the far ends are taken.
        for end in [
            Point::new(100.0, 0.0),
            Point::new(0.0, 0.0),
            Point::new(100.0, 60.0),
        ] {
            assert!(pins.iter().any(|p| (*p - end).hypot() < 1e-2), "{pins:?}");
        }
    }

    #[test]
    fn pins_refuse_bad_input_naming_it() {
        let empty = Drawing::default();
        assert_eq!(
            place_pins(&empty, &[], &PinOptions::default()),
            Err(PinError::NothingToPin)
        );
        let d = drawing(r#"<rect width="10" height="10"/>"#);
        let e = place_pins(&d, &[Point::new(1.0, f64::NAN)], &exactly(2)).unwrap_err();
        assert!(matches!(e, PinError::NonFinite { index: 0, .. }), "{e}");
        let two = [Point::new(1.0, 1.0), Point::new(2.0, 2.0)];
        let e = place_pins(&d, &two, &exactly(1)).unwrap_err();
        assert_eq!(
            e.to_string(),
            "1 pins asked for with 2 given: expected a count from 2 to 256"
        );
        let e = place_pins(&d, &[], &exactly(0)).unwrap_err();
        assert!(e.to_string().contains("from 1 to"), "{e}");
        let e = place_pins(&d, &[], &PinOptions::default().with_grid_cells(0)).unwrap_err();
        assert!(e.to_string().contains("grid_cells = 0"), "{e}");
        // A 2 × 2 grid holds 4 candidates at most.
        let coarse = exactly(5).with_grid_cells(2);
        assert_eq!(
            place_pins(&d, &[], &coarse),
            Err(PinError::TooFewCandidates {
                asked: 5,
                placed: 4
            })
        );
    }

    #[test]
    fn pins_depth_is_the_distance_to_the_outside() {
        // One row of 5 inside cells: every depth is 1 (the rows above and below are outside).
        let d = depth(&[true; 5], 5, 1);
        assert_eq!(d, vec![1.0; 5]);
        let inside: Vec<bool> = (0..25).map(|_| true).collect();
        let d = depth(&inside, 5, 5);
        assert_eq!(d[12], 3.0);
        assert_eq!(d[0], 1.0);
        assert_eq!(d[6], 2.0);
    }
}
