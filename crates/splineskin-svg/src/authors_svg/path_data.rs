//! The authors' path-data conversion, step by step as their editor does it: absolute
//! segments, `f32` rounding, JavaScript's number formatting and `||`, the snapping pen,
//! quadratics and arcs to cubics ([`super::read_authors_paths`] documents the steps).

use kurbo::Point;
use svgtypes::{PathParser, PathSegment};

use super::*;

/// A segment of `d` after step 1 (absolute coordinates), with where it came from.
#[derive(Clone, Copy, Debug)]
pub(super) struct AbsSegment {
    kind: AbsKind,
    /// 0-based index among the parsed segments of `d`.
    index: usize,
    /// The command letter as written.
    command: char,
}

/// The absolute segment kinds of SVG path data.
#[derive(Clone, Copy, Debug)]
pub(super) enum AbsKind {
    Move(Point),
    Line(Point),
    Horizontal(f64),
    Vertical(f64),
    Cubic(Point, Point, Point),
    SmoothCubic(Point, Point),
    Quadratic(Point, Point),
    SmoothQuadratic(Point),
    Arc(ArcTo),
    Close,
}

/// The parameters of an elliptical arc segment (`A`), its end point absolute.
#[derive(Clone, Copy, Debug)]
pub(super) struct ArcTo {
    rx: f64,
    ry: f64,
    /// The x-axis rotation, in degrees.
    rotation_degrees: f64,
    large_arc: bool,
    sweep: bool,
    to: Point,
}

/// Steps 1–5 for one element's `d`, appending its chains to `out`.
pub(super) fn read_element(
    d: &str,
    element: &PathElement,
    out: &mut Vec<AuthorsPath>,
) -> Result<(), AuthorsSvgError> {
    let mut segments = to_absolute(d).map_err(|source| AuthorsSvgError::PathData {
        element: element.clone(),
        source,
    })?;
    if segments.is_empty() {
        tracing::warn!("{element}: no path data; skipped, as the authors' editor does");
        return Ok(());
    }
    if drop_redundant_closes(&mut segments) {
        round_segments_to_f32(&mut segments);
    }
    let mut pen = SnapPen::default();
    let mut chain: Vec<Point> = Vec::new();
    for segment in &segments {
        let not_finite = || AuthorsSvgError::NotFinite {
            element: element.clone(),
            segment: segment.index,
            command: segment.command,
        };
        match pen.convert(segment.kind) {
            Converted::Move(p) => {
                finish_chain(std::mem::take(&mut chain), element, out);
                chain.push(round_to_f32(p).ok_or_else(not_finite)?);
            }
            Converted::Cubics(cubics) => {
                for c in cubics {
                    for p in c {
                        chain.push(round_to_f32(p).ok_or_else(not_finite)?);
                    }
                }
            }
        }
    }
    finish_chain(chain, element, out);
    Ok(())
}

/// Appends a finished chain, or skips (with a warning) a subpath without any segment, as the
/// editor's `append_path` does.
pub(super) fn finish_chain(chain: Vec<Point>, element: &PathElement, out: &mut Vec<AuthorsPath>) {
    if chain.is_empty() {
        return;
    }
    if chain.len() < 4 {
        tracing::warn!(
            "{element}: subpath at {:?} has no segment; skipped, as the authors' editor does",
            chain[0]
        );
        return;
    }
    let closed = chain[0] == chain[chain.len() - 1];
    out.push(AuthorsPath {
        points: chain,
        closed,
        element: element.index,
    });
}

/// Rounds both coordinates to `float32` and back; `None` if either is not finite then.
pub(super) fn round_to_f32(p: Point) -> Option<Point> {
    let q = Point::new(f32_round(p.x), f32_round(p.y));
    q.is_finite().then_some(q)
}

/// `v` rounded to `float32` and widened back (infinite beyond the `float32` range).
pub(super) fn f32_round(v: f64) -> f64 {
    f64::from(v as f32)
}

/// `v + origin` for a relative coordinate, `v` itself for an absolute one.
pub(super) fn offset(v: f64, origin: f64, abs: bool) -> f64 {
    if abs {
        v
    } else {
        v + origin
    }
}

/// The command letter of a parsed segment.
pub(super) fn command_letter(segment: &PathSegment) -> char {
    let (upper, abs) = match *segment {
        PathSegment::MoveTo { abs, .. } => ('M', abs),
        PathSegment::LineTo { abs, .. } => ('L', abs),
        PathSegment::HorizontalLineTo { abs, .. } => ('H', abs),
        PathSegment::VerticalLineTo { abs, .. } => ('V', abs),
        PathSegment::CurveTo { abs, .. } => ('C', abs),
        PathSegment::SmoothCurveTo { abs, .. } => ('S', abs),
        PathSegment::Quadratic { abs, .. } => ('Q', abs),
        PathSegment::SmoothQuadratic { abs, .. } => ('T', abs),
        PathSegment::EllipticalArc { abs, .. } => ('A', abs),
        PathSegment::ClosePath { abs } => ('Z', abs),
    };
    if abs {
        upper
    } else {
        upper.to_ascii_lowercase()
    }
}

/// Step 1: parses `d` and makes every segment absolute, accumulating the pen in `f64` (Snap's
/// `toAbsolute`).
pub(super) fn to_absolute(d: &str) -> Result<Vec<AbsSegment>, svgtypes::Error> {
    let mut out = Vec::new();
    let mut pen = Point::ZERO;
    let mut start = Point::ZERO;
    for (index, parsed) in PathParser::from(d).enumerate() {
        let parsed = parsed?;
        let command = command_letter(&parsed);
        let at =
            |x: f64, y: f64, abs: bool| Point::new(offset(x, pen.x, abs), offset(y, pen.y, abs));
        let kind = match parsed {
            PathSegment::MoveTo { abs, x, y } => AbsKind::Move(at(x, y, abs)),
            PathSegment::LineTo { abs, x, y } => AbsKind::Line(at(x, y, abs)),
            PathSegment::HorizontalLineTo { abs, x } => AbsKind::Horizontal(offset(x, pen.x, abs)),
            PathSegment::VerticalLineTo { abs, y } => AbsKind::Vertical(offset(y, pen.y, abs)),
            PathSegment::CurveTo {
                abs,
                x1,
                y1,
                x2,
                y2,
                x,
                y,
            } => AbsKind::Cubic(at(x1, y1, abs), at(x2, y2, abs), at(x, y, abs)),
            PathSegment::SmoothCurveTo { abs, x2, y2, x, y } => {
                AbsKind::SmoothCubic(at(x2, y2, abs), at(x, y, abs))
            }
            PathSegment::Quadratic { abs, x1, y1, x, y } => {
                AbsKind::Quadratic(at(x1, y1, abs), at(x, y, abs))
            }
            PathSegment::SmoothQuadratic { abs, x, y } => AbsKind::SmoothQuadratic(at(x, y, abs)),
            PathSegment::EllipticalArc {
                abs,
                rx,
                ry,
                x_axis_rotation,
                large_arc,
                sweep,
                x,
                y,
            } => AbsKind::Arc(ArcTo {
                rx,
                ry,
                rotation_degrees: x_axis_rotation,
                large_arc,
                sweep,
                to: at(x, y, abs),
            }),
            PathSegment::ClosePath { .. } => AbsKind::Close,
        };
        pen = end_point(kind, pen, start);
        if let AbsKind::Move(p) = kind {
            start = p;
        }
        out.push(AbsSegment {
            kind,
            index,
            command,
        });
    }
    Ok(out)
}

/// Where the pen is after `kind`, drawn from `pen` in a subpath starting at `start`.
pub(super) fn end_point(kind: AbsKind, pen: Point, start: Point) -> Point {
    match kind {
        AbsKind::Move(p)
        | AbsKind::Line(p)
        | AbsKind::Cubic(_, _, p)
        | AbsKind::SmoothCubic(_, p)
        | AbsKind::Quadratic(_, p)
        | AbsKind::SmoothQuadratic(p)
        | AbsKind::Arc(ArcTo { to: p, .. }) => p,
        AbsKind::Horizontal(x) => Point::new(x, pen.y),
        AbsKind::Vertical(y) => Point::new(pen.x, y),
        AbsKind::Close => start,
    }
}

/// Step 2: removes every `Z` whose preceding end point equals its subpath's start in
/// `float32`. Returns whether any was removed.
pub(super) fn drop_redundant_closes(segments: &mut Vec<AbsSegment>) -> bool {
    let same_in_f32 =
        |a: Point, b: Point| f32_round(a.x) == f32_round(b.x) && f32_round(a.y) == f32_round(b.y);
    let n_before = segments.len();
    let mut pen = Point::ZERO;
    let mut start = Point::ZERO;
    segments.retain(|segment| {
        if matches!(segment.kind, AbsKind::Close) && same_in_f32(pen, start) {
            return false;
        }
        pen = end_point(segment.kind, pen, start);
        if let AbsKind::Move(p) = segment.kind {
            start = p;
        }
        true
    });
    segments.len() != n_before
}

/// Step 3: rounds every number of every segment to `float32` (the browser's rewrite of `d`).
pub(super) fn round_segments_to_f32(segments: &mut [AbsSegment]) {
    let r = |p: Point| Point::new(f32_round(p.x), f32_round(p.y));
    for segment in segments {
        segment.kind = match segment.kind {
            AbsKind::Move(p) => AbsKind::Move(r(p)),
            AbsKind::Line(p) => AbsKind::Line(r(p)),
            AbsKind::Horizontal(x) => AbsKind::Horizontal(f32_round(x)),
            AbsKind::Vertical(y) => AbsKind::Vertical(f32_round(y)),
            AbsKind::Cubic(a, b, p) => AbsKind::Cubic(r(a), r(b), r(p)),
            AbsKind::SmoothCubic(b, p) => AbsKind::SmoothCubic(r(b), r(p)),
            AbsKind::Quadratic(a, p) => AbsKind::Quadratic(r(a), r(p)),
            AbsKind::SmoothQuadratic(p) => AbsKind::SmoothQuadratic(r(p)),
            AbsKind::Arc(arc) => AbsKind::Arc(ArcTo {
                rx: f32_round(arc.rx),
                ry: f32_round(arc.ry),
                rotation_degrees: f32_round(arc.rotation_degrees),
                to: r(arc.to),
                ..arc
            }),
            AbsKind::Close => AbsKind::Close,
        };
    }
}

/// JavaScript's `a || b` for a number `a` that may be `null` (`None`): `b` when `a` is
/// `null`, `0` or `NaN`.
pub(super) fn js_or(a: Option<f64>, b: f64) -> f64 {
    match a {
        Some(v) if v != 0.0 && !v.is_nan() => v,
        _ => b,
    }
}

/// What one segment becomes in step 4.
pub(super) enum Converted {
    /// A moveto: a new chain starts at this point.
    Move(Point),
    /// Cubics `[c₁, c₂, end]` continuing from the pen.
    Cubics(Vec<[Point; 3]>),
}

/// The state of Snap's `path2curve` (its `attrs`): pen, reflection point for `S`, last
/// quadratic control for `T`, subpath start.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct SnapPen {
    /// Current point.
    pen: Point,
    /// Second control point of the last cubic, each coordinate already `c || pen` (Snap's
    /// `bx`, `by`).
    reflect: Point,
    /// Last quadratic control point (`qx`, `qy`), `None` when the last segment was not `Q`/`T`.
    quad: (Option<f64>, Option<f64>),
    /// Start of the current subpath (`X`, `Y`).
    start: Point,
}

impl SnapPen {
    /// Converts one absolute segment (Snap's `processPath`) and advances the state.
    fn convert(&mut self, kind: AbsKind) -> Converted {
        if !matches!(kind, AbsKind::Quadratic(..) | AbsKind::SmoothQuadratic(_)) {
            self.quad = (None, None);
        }
        let p0 = self.pen;
        let line = |to: Point| vec![[p0, to, to]];
        let cubics = match kind {
            AbsKind::Move(p) => {
                self.start = p;
                self.pen = p;
                // Snap reads the missing control of a moveto as NaN, hence the pen.
                self.reflect = p;
                return Converted::Move(p);
            }
            AbsKind::Line(p) => line(p),
            AbsKind::Horizontal(x) => line(Point::new(x, p0.y)),
            AbsKind::Vertical(y) => line(Point::new(p0.x, y)),
            AbsKind::Close => line(self.start),
            AbsKind::Cubic(a, b, p) => vec![[a, b, p]],
            AbsKind::SmoothCubic(b, p) => {
                let a = Point::new(
                    p0.x + (p0.x - js_or(Some(self.reflect.x), p0.x)),
                    p0.y + (p0.y - js_or(Some(self.reflect.y), p0.y)),
                );
                vec![[a, b, p]]
            }
            AbsKind::Quadratic(c, p) => {
                self.quad = (Some(c.x), Some(c.y));
                vec![quadratic_to_cubic(p0, c, p)]
            }
            AbsKind::SmoothQuadratic(p) => {
                let c = Point::new(
                    p0.x + (p0.x - js_or(self.quad.0, p0.x)),
                    p0.y + (p0.y - js_or(self.quad.1, p0.y)),
                );
                self.quad = (Some(c.x), Some(c.y));
                vec![quadratic_to_cubic(p0, c, p)]
            }
            AbsKind::Arc(arc) => arc_to_cubics(p0, arc),
        };
        if let Some(&[_, b, p]) = cubics.last() {
            self.pen = p;
            self.reflect = Point::new(js_or(Some(b.x), p.x), js_or(Some(b.y), p.y));
        }
        Converted::Cubics(cubics)
    }
}

/// Snap's `q2c`: the cubic of the quadratic `p0, c, p` (degree elevation, evaluated as Snap
/// writes it).
pub(super) fn quadratic_to_cubic(p0: Point, c: Point, p: Point) -> [Point; 3] {
    [
        Point::new(
            ONE_THIRD * p0.x + TWO_THIRDS * c.x,
            ONE_THIRD * p0.y + TWO_THIRDS * c.y,
        ),
        Point::new(
            ONE_THIRD * p.x + TWO_THIRDS * c.x,
            ONE_THIRD * p.y + TWO_THIRDS * c.y,
        ),
        p,
    ]
}

/// JavaScript's `Number(x.toFixed(9))`: `x` rounded to [`ARC_ASIN_DECIMALS`] decimals, ties
/// away from zero (Rust's formatting rounds ties to even).
pub(super) fn js_to_fixed_9(x: f64) -> f64 {
    if !x.is_finite() || x.abs() >= JS_TO_FIXED_LIMIT {
        return x;
    }
    let scaled = x.abs() * TIE_SCALE; // exact: a power of two
    let is_tie = scaled.fract() == 0.0 && scaled % 2.0 == 1.0;
    if !is_tie {
        return format!("{x:.ARC_ASIN_DECIMALS$}").parse().unwrap_or(x);
    }
    // |x| = j / 2^10 with j odd: |x|·10⁹ = j·5⁹ / 2, rounded up in magnitude.
    let j = scaled as u128; // exact: an integer below 2^80
    let n = (j * FIVE_POW_DECIMALS).div_ceil(2);
    let sign = if x < 0.0 { "-" } else { "" };
    let text = format!(
        "{sign}{}.{:0width$}",
        n / TEN_POW_DECIMALS,
        n % TEN_POW_DECIMALS,
        width = ARC_ASIN_DECIMALS
    );
    text.parse().unwrap_or(x)
}

/// Rotation of `(x, y)` by `rad` as Snap's `a2c` writes it.
pub(super) fn snap_rotate(x: f64, y: f64, rad: f64) -> Point {
    Point::new(x * rad.cos() - y * rad.sin(), x * rad.sin() + y * rad.cos())
}

/// The end angles and centre of an arc piece in `a2c`'s recursion.
#[derive(Clone, Copy, Debug)]
pub(super) struct ArcPiece {
    f1: f64,
    f2: f64,
    cx: f64,
    cy: f64,
}

/// Snap 0.2.0's `a2c`: the cubics of the arc `arc` from `p0` to `arc.to` (SVG arc parameters,
/// rotation in degrees), in the arc's rotated frame until the final rotation back.
pub(super) fn arc_to_cubics(p0: Point, arc: ArcTo) -> Vec<[Point; 3]> {
    use std::f64::consts::PI;
    let ArcTo {
        rx,
        ry,
        rotation_degrees,
        large_arc,
        sweep,
        to,
    } = arc;
    // `+angle || 0`
    let rad = PI / 180.0 * js_or(Some(rotation_degrees), 0.0);
    let a = snap_rotate(p0.x, p0.y, -rad);
    let b = snap_rotate(to.x, to.y, -rad);
    let (x1, y1, x2, y2) = (a.x, a.y, b.x, b.y);
    let x = (x1 - x2) / 2.0;
    let y = (y1 - y2) / 2.0;
    let (mut rx, mut ry) = (rx, ry);
    let h = (x * x) / (rx * rx) + (y * y) / (ry * ry);
    if h > 1.0 {
        let h = h.sqrt();
        rx *= h;
        ry *= h;
    }
    let rx2 = rx * rx;
    let ry2 = ry * ry;
    let k_sign = if large_arc == sweep { -1.0 } else { 1.0 };
    let k = k_sign
        * ((rx2 * ry2 - rx2 * y * y - ry2 * x * x) / (rx2 * y * y + ry2 * x * x))
            .abs()
            .sqrt();
    let cx = k * rx * y / ry + (x1 + x2) / 2.0;
    let cy = k * -ry * x / rx + (y1 + y2) / 2.0;
    let mut f1 = js_to_fixed_9((y1 - cy) / ry).asin();
    let mut f2 = js_to_fixed_9((y2 - cy) / ry).asin();
    if x1 < cx {
        f1 = PI - f1;
    }
    if x2 < cx {
        f2 = PI - f2;
    }
    if f1 < 0.0 {
        f1 += PI * 2.0;
    }
    if f2 < 0.0 {
        f2 += PI * 2.0;
    }
    if sweep && f1 > f2 {
        f1 -= PI * 2.0;
    }
    if !sweep && f2 > f1 {
        f2 -= PI * 2.0;
    }
    let mut flat = Vec::new();
    arc_pieces(
        Point::new(x1, y1),
        Point::new(x2, y2),
        rx,
        ry,
        sweep,
        ArcPiece { f1, f2, cx, cy },
        &mut flat,
    );
    // Rotate back to the drawing's frame.
    flat.iter()
        .map(|c| c.map(|p| snap_rotate(p.x, p.y, rad)))
        .collect()
}

/// The recursive part of `a2c`: appends to `out` the cubics of the piece from `start` (angle
/// `f1`) to `end` (angle `f2`), first splitting off pieces of [`ARC_PIECE_MAX_ANGLE`].
///
/// Terminates: `f1` and `f2` lie in `[−2π, 3π]`, and each level moves `f1` by 120° towards
/// `f2` (a NaN angle difference stops at once).
pub(super) fn arc_pieces(
    start: Point,
    end: Point,
    rx: f64,
    ry: f64,
    sweep: bool,
    piece: ArcPiece,
    out: &mut Vec<[Point; 3]>,
) {
    let ArcPiece { f1, mut f2, cx, cy } = piece;
    let (x1, y1) = (start.x, start.y);
    let (mut x2, mut y2) = (end.x, end.y);
    let mut rest = Vec::new();
    if (f2 - f1).abs() > ARC_PIECE_MAX_ANGLE {
        let (f2_old, end_old) = (f2, Point::new(x2, y2));
        let direction = if sweep && f2 > f1 { 1.0 } else { -1.0 };
        f2 = f1 + ARC_PIECE_MAX_ANGLE * direction;
        x2 = cx + rx * f2.cos();
        y2 = cy + ry * f2.sin();
        let next = ArcPiece {
            f1: f2,
            f2: f2_old,
            cx,
            cy,
        };
        arc_pieces(Point::new(x2, y2), end_old, rx, ry, sweep, next, &mut rest);
    }
    let df = f2 - f1;
    let (c1, s1, c2, s2) = (f1.cos(), f1.sin(), f2.cos(), f2.sin());
    let t = (df / 4.0).tan();
    let hx = 4.0 / 3.0 * rx * t;
    let hy = 4.0 / 3.0 * ry * t;
    let m2 = Point::new(x1 + hx * s1, y1 - hy * c1);
    let m2 = Point::new(2.0 * x1 - m2.x, 2.0 * y1 - m2.y);
    let m3 = Point::new(x2 + hx * s2, y2 - hy * c2);
    out.push([m2, m3, Point::new(x2, y2)]);
    out.extend(rest);
}
