//! Watertight art under a bend (issue 15), as pixels: a drawing of our own with two filled
//! regions side by side (their common side drawn by both paths) and an outline stroked along
//! one region's edge, bent by a non-rigid pose through a rig with shared-curve fitting
//! ([`FitOptions::share_curves`]) and rendered with resvg: no pixel of the background shows
//! between the two regions or between a region and its outline, and no fill shows outside
//! its outline. The same with sharing off
//! shows the gap between the regions (the test can fail). Set `SHARED_TEST_OUT=DIR` to keep the pictures.

use kurbo::{Affine, ParamCurve, ParamCurveDeriv, Point, Vec2};
use splineskin::drawing::svg_out::write_svg;
use splineskin::drawing::{read_svg, Drawing, ImportOptions};
use splineskin::spline_fit::{FitOptions, SplineRig};
use splineskin::weights::shepard::{Shepard, ShepardOptions};

/// Render size (longest side, pixels) of the 100-unit viewBox.
const RENDER_SIZE: u32 = 400;

/// Outline stroke width (drawing units).
const STROKE: f64 = 1.0;

/// Channel value (of 255) above which all three channels make a pixel the white background
/// showing through (the art's colours each have a channel below 80; anti-aliased seams
/// between them stay far from white).
const BACKGROUND_LEVEL: u8 = 200;

/// Samples per shared curve.
const SAMPLES: usize = 64;

/// A round region (smooth all round) and a region beside it that runs along its right half,
/// reversed, with corners where it leaves the round one; an outline stroked along the round
/// region's left half (an open path: free where the round region is smooth).
const SVG: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100" width="100" height="100">
  <path d="M30 50 C30 34 40 25 50 25 C60 25 70 34 70 50 C70 66 60 75 50 75 C40 75 30 66 30 50 Z" fill="#c00000"/>
  <path d="M50 25 L90 25 L90 75 L50 75 C60 75 70 66 70 50 C70 34 60 25 50 25 Z" fill="#0040c0"/>
  <path d="M50 75 C40 75 30 66 30 50 C30 34 40 25 50 25" fill="none" stroke="#000" stroke-width="1"/>
</svg>"##;

/// Deforms the drawing by a bend: the left handle fixed, the middle one lifted and turned,
/// the right one turned the other way.
fn deform(drawing: &Drawing, share: bool) -> Vec<Point> {
    let handles = [(10.0, 55.0), (50.0, 30.0), (90.0, 55.0)].map(Point::from);
    let field = Shepard::new(&handles, ShepardOptions::default());
    let fit = FitOptions::default().with_share_curves(share);
    let rig = SplineRig::precompute(drawing, &field, &fit).expect("precompute");
    let pose = [
        Affine::IDENTITY,
        Affine::translate(Vec2::new(0.0, -12.0)) * Affine::rotate_about(-0.6, handles[1]),
        Affine::rotate_about(0.5, handles[2]),
    ];
    let mut out = vec![Point::ZERO; rig.n_points()];
    rig.update(&pose, &mut out).expect("update");
    out
}

/// Whether the pixel under drawing point `p` (viewBox 0 0 100 100 at `RENDER_SIZE`) is the
/// white background ([`splineskin::render::render_png`] paints white first).
fn is_background(pixmap: &tiny_skia::Pixmap, p: Point) -> bool {
    let s = f64::from(RENDER_SIZE) / 100.0;
    let (x, y) = ((p.x * s).floor(), (p.y * s).floor());
    if x < 0.0 || y < 0.0 || x >= f64::from(pixmap.width()) || y >= f64::from(pixmap.height()) {
        return true;
    }
    pixmap.pixel(x as u32, y as u32).is_some_and(|c| {
        let c = c.demultiply();
        c.red().min(c.green()).min(c.blue()) > BACKGROUND_LEVEL
    })
}

/// Pixels for which `bad` holds met along the deformed curve `c` at parameters in `ts`,
/// stepping along its normal `(−y', x')` from `from` to `to` drawing units.
fn count_along(
    pixmap: &tiny_skia::Pixmap,
    c: kurbo::CubicBez,
    ts: std::ops::Range<f64>,
    (from, to): (f64, f64),
    bad: impl Fn(&tiny_skia::Pixmap, Point) -> bool,
) -> usize {
    let px = 100.0 / f64::from(RENDER_SIZE);
    let mut n = 0;
    for k in 0..=SAMPLES {
        let t = ts.start + (ts.end - ts.start) * k as f64 / SAMPLES as f64;
        let d = c.deriv().eval(t).to_vec2();
        let normal = Vec2::new(-d.y, d.x) / d.hypot();
        let mut s = from;
        while s <= to {
            if bad(pixmap, c.eval(t) + normal * s) {
                n += 1;
            }
            s += 0.5 * px;
        }
    }
    n
}

/// Whether the pixel under `p` is the round region's red (a sliver of fill showing outside
/// its outline).
fn is_fill(pixmap: &tiny_skia::Pixmap, p: Point) -> bool {
    let s = f64::from(RENDER_SIZE) / 100.0;
    let (x, y) = ((p.x * s).floor(), (p.y * s).floor());
    if x < 0.0 || y < 0.0 {
        return false;
    }
    pixmap.pixel(x as u32, y as u32).is_some_and(|c| {
        let c = c.demultiply();
        c.red() > 150 && c.green() < 80 && c.blue() < 80
    })
}

/// The background pixels seen between the regions and between the regions and the outline,
/// after the bend with sharing on or off.
fn gaps(drawing: &Drawing, share: bool) -> (usize, usize) {
    let out = deform(drawing, share);
    let svg = write_svg(drawing, &out).expect("write");
    let png = splineskin::render::render_png(&svg, RENDER_SIZE).expect("render");
    let pixmap = tiny_skia::Pixmap::decode_png(&png).expect("decode");
    if let Ok(dir) = std::env::var("SHARED_TEST_OUT") {
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(format!("{dir}/shared-{share}.png"), &png).unwrap();
    }
    let curve = |path: usize, j: usize| {
        let offset = drawing.path_ranges().nth(path).expect("path index").start;
        let p = &out[offset + 3 * j..offset + 3 * j + 4];
        kurbo::CubicBez::new(p[0], p[1], p[2], p[3])
    };
    let px = 100.0 / f64::from(RENDER_SIZE);
    // The common side (the round region's curves 1 and 2), away from the cusps where the
    // other region leaves it tangentially: round region on one side, the other region on
    // the other, two pixels each way.
    let seam = (-2.0 * px, 2.0 * px);
    let between = count_along(&pixmap, curve(0, 1), 0.5..1.0, seam, is_background)
        + count_along(&pixmap, curve(0, 2), 0.0..0.5, seam, is_background);
    // The outline's two arcs: no background from its centre line to two pixels past its
    // inner edge (the side of the normal, into the round region), and no fill from one to
    // four pixels past its outer edge.
    let edge = 0.5 * STROKE;
    let mut outline = 0;
    for j in 0..2 {
        let c = curve(2, j);
        outline += count_along(&pixmap, c, 0.0..1.0, (0.0, edge + 2.0 * px), is_background);
        outline += count_along(
            &pixmap,
            c,
            0.0..1.0,
            (-edge - 4.0 * px, -edge - px),
            is_fill,
        );
    }
    (between, outline)
}

#[test]
fn shared_edges_leave_no_gap_under_a_bend() {
    let drawing = read_svg(SVG, &ImportOptions::default()).expect("read");
    assert_eq!(drawing.paths.len(), 3);
    let (between, outline) = gaps(&drawing, true);
    let (between_apart, outline_apart) = gaps(&drawing, false);
    eprintln!(
        "background pixels between the regions / under the outline: shared {between} / \
         {outline}, fitted apart {between_apart} / {outline_apart}"
    );
    assert_eq!((between, outline), (0, 0));
    // Fitted apart, the two regions part along their common side: the check sees the gap.
    // (Under this bend the outline fitted apart stays within a pixel of its fill, so its
    // count is printed, not asserted.)
    assert!(between_apart > 0);
}
