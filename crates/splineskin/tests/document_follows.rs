//! Everything in a document follows the deformation: hidden layers, clip paths and masks are
//! imported, deformed and written back, and a filled element without fill area at rest keeps
//! showing no fill.
//!
//! Rendering checks (resvg, as pixels): under a rigid pose (the same rotation + translation on
//! every handle, through a real rig), the deformed document rendered must match the input
//! rendered under that rigid map (its content wrapped in a `<g transform>`): at most
//! [`MAX_DIFFERENT`] of the pixels may differ by more than [`ANTI_ALIASING`] in a channel. The
//! rig reproduces a common affine map exactly up to rounding, so only anti-aliasing of
//! edges rounded differently remains; a clip or mask left at rest fails by far (tens of
//! percent of the art's pixels). Set `DOCUMENT_TEST_OUT=DIR` to keep the pictures.

use kurbo::{Affine, Point, Vec2};
use splineskin::drawing::svg_out::write_svg;
use splineskin::drawing::{read_svg, Drawing, ImportOptions, PathRole};
use splineskin::spline_fit::{FitOptions, SplineRig};
use splineskin::weights::shepard::{Shepard, ShepardOptions};

/// Largest channel difference (of 255) still counted as anti-aliasing.
const ANTI_ALIASING: u8 = 48;

/// Largest fraction of pixels allowed to differ beyond [`ANTI_ALIASING`]: 0.5 %.
const MAX_DIFFERENT: f64 = 0.005;

/// Render size (longest side, pixels).
const RENDER_SIZE: u32 = 240;

/// The rigid map of the tests: 25° about (50, 50), then 6 units right.
fn rigid() -> Affine {
    Affine::translate(Vec2::new(6.0, 0.0))
        * Affine::rotate_about(25f64.to_radians(), Point::new(50.0, 50.0))
}

/// Deforms `drawing` by `pose` on three Shepard handles through a spline rig.
fn deform(drawing: &Drawing, pose: Affine) -> Vec<Point> {
    let handles = [(20.0, 30.0), (80.0, 40.0), (50.0, 85.0)].map(Point::from);
    let field = Shepard::new(&handles, ShepardOptions::default());
    let rig = SplineRig::precompute(drawing, &field, &FitOptions::default()).expect("precompute");
    let mut out = vec![Point::ZERO; rig.n_points()];
    rig.update(&[pose; 3], &mut out).expect("update");
    out
}

/// The input with its root content wrapped in `<g transform="matrix(t)">`.
fn wrapped(svg: &str, t: Affine) -> String {
    let open = svg.find('>').expect("root start tag") + 1;
    let close = svg.rfind("</svg>").expect("root end tag");
    let c = t.as_coeffs();
    format!(
        "{}<g transform=\"matrix({} {} {} {} {} {})\">{}</g>{}",
        &svg[..open],
        c[0],
        c[1],
        c[2],
        c[3],
        c[4],
        c[5],
        &svg[open..close],
        &svg[close..]
    )
}

fn pixels(svg: &str) -> tiny_skia::Pixmap {
    let png = splineskin::render::render_png(svg, RENDER_SIZE).expect("render");
    tiny_skia::Pixmap::decode_png(&png).expect("decode")
}

/// Fraction of pixels differing beyond [`ANTI_ALIASING`], and the fraction of non-white
/// pixels of `a` (so that a test can tell its art is there at all).
fn difference(name: &str, a: &str, b: &str) -> (f64, f64) {
    let (pa, pb) = (pixels(a), pixels(b));
    assert_eq!((pa.width(), pa.height()), (pb.width(), pb.height()));
    if let Ok(dir) = std::env::var("DOCUMENT_TEST_OUT") {
        std::fs::create_dir_all(&dir).unwrap();
        pa.save_png(format!("{dir}/{name}-expected.png")).unwrap();
        pb.save_png(format!("{dir}/{name}-deformed.png")).unwrap();
    }
    let (mut diff, mut ink) = (0usize, 0usize);
    for (x, y) in pa.pixels().iter().zip(pb.pixels()) {
        let (x, y) = (x.demultiply(), y.demultiply());
        let d = [
            x.red().abs_diff(y.red()),
            x.green().abs_diff(y.green()),
            x.blue().abs_diff(y.blue()),
            x.alpha().abs_diff(y.alpha()),
        ];
        if d.iter().any(|&v| v > ANTI_ALIASING) {
            diff += 1;
        }
        if x.red() < 250 || x.green() < 250 || x.blue() < 250 {
            ink += 1;
        }
    }
    let n = pa.pixels().len() as f64;
    (diff as f64 / n, ink as f64 / n)
}

/// Reads `svg`, deforms it rigidly through a rig, and checks the render against the input
/// rendered under the same map, after `unhide` (applied to both texts).
fn check_rigid(name: &str, svg: &str, unhide: impl Fn(&str) -> String) -> Drawing {
    let drawing = read_svg(svg, &ImportOptions::default()).expect("read");
    let points = deform(&drawing, rigid());
    let out = write_svg(&drawing, &points).expect("write");
    let expected = wrapped(&unhide(svg), rigid());
    let (diff, ink) = difference(name, &expected, &unhide(&out));
    eprintln!(
        "{name}: {:.3} % of pixels differ, {:.1} % ink",
        100.0 * diff,
        100.0 * ink
    );
    assert!(ink > 0.02, "{name}: the art is not in view ({ink})");
    assert!(
        diff <= MAX_DIFFERENT,
        "{name}: {diff} of the pixels differ\n{out}"
    );
    drawing
}

fn svg(body: &str) -> String {
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 100 100\" width=\"100\" \
         height=\"100\">{body}</svg>"
    )
}

const HIDDEN: &str = "<style>.off { display: none }</style>\
    <rect x='10' y='10' width='30' height='20' fill='teal'/>\
    <g display='none'><path d='M50 20 C70 10 80 30 70 45 Z' fill='orange'/></g>\
    <circle class='off' cx='30' cy='65' r='12' fill='purple'/>\
    <path style='display:none' d='M55 60 L85 60 L70 85 Z' fill='crimson'/>\
    <rect visibility='hidden' x='60' y='5' width='10' height='10' fill='blue'/>";

/// Every way of hiding, shown: the attribute, the CSS class and the inline style.
fn unhide(text: &str) -> String {
    text.replace("display='none'", "display='inline'")
        .replace("display: none", "display: inline")
        .replace("display:none", "display:inline")
}

#[test]
fn hidden_layers_are_imported_with_their_role() {
    let drawing = read_svg(&svg(HIDDEN), &ImportOptions::default()).unwrap();
    let roles: Vec<PathRole> = (0..drawing.paths.len())
        .map(|i| drawing.path_role(i))
        .collect();
    assert_eq!(
        roles,
        [
            PathRole::Visible,
            PathRole::Hidden,
            PathRole::Hidden,
            PathRole::Hidden,
            PathRole::Unpainted
        ]
    );
    assert!(drawing.is_drawn(0) && !drawing.is_drawn(1));
    // A document that hides nothing reads as before.
    let plain = read_svg(
        &svg("<path d='M0 0 L9 9 L0 9'/>"),
        &ImportOptions::default(),
    )
    .unwrap();
    assert_eq!(plain.path_role(0), PathRole::Visible);
}

#[test]
fn hidden_layers_unhidden_after_a_rigid_pose_match() {
    let d = check_rigid("hidden", &svg(HIDDEN), unhide);
    assert_eq!(d.paths.len(), 5);
    // Still hidden in the output as it was in the input.
    check_rigid("hidden-as-is", &svg(HIDDEN), str::to_string);
}

const CLIPPED: &str = "<defs>\
    <clipPath id='band'><rect x='10' y='35' width='80' height='30' transform='rotate(5 50 50)'/></clipPath>\
    <clipPath id='disc' clipPathUnits='objectBoundingBox'><circle cx='0.5' cy='0.5' r='0.45'/></clipPath>\
    <mask id='fade'><rect x='0' y='0' width='100' height='100' fill='white'/>\
      <path d='M30 30 L70 30 L50 70 Z' fill='black'/></mask>\
    </defs>\
    <g transform='translate(2 3)'>\
      <rect x='5' y='5' width='90' height='90' fill='navy' clip-path='url(#band)'/>\
      <rect x='20' y='20' width='40' height='30' fill='gold' clip-path='url(#disc)'/>\
    </g>\
    <rect x='40' y='40' width='50' height='50' fill='green' mask='url(#fade)'/>";

#[test]
fn clip_paths_and_masks_follow_a_rigid_pose() {
    let d = check_rigid("clip-mask", &svg(CLIPPED), str::to_string);
    let roles: Vec<PathRole> = (0..d.paths.len()).map(|i| d.path_role(i)).collect();
    assert_eq!(
        roles.iter().filter(|r| **r == PathRole::ClipPath).count(),
        2,
        "{roles:?}"
    );
    assert_eq!(
        roles.iter().filter(|r| **r == PathRole::Mask).count(),
        2,
        "{roles:?}"
    );
}

#[test]
fn a_clip_shared_in_one_coordinate_system_is_deformed_once() {
    let body = "<clipPath id='c'><rect x='20' y='20' width='60' height='60'/></clipPath>\
        <rect x='10' y='10' width='50' height='50' fill='red' clip-path='url(#c)'/>\
        <rect x='40' y='40' width='50' height='50' fill='blue' clip-path='url(#c)'/>";
    let d = check_rigid("shared-clip", &svg(body), str::to_string);
    assert_eq!(d.paths.len(), 3, "one clip rectangle, imported once");
}

#[test]
fn zero_area_fill_stays_invisible() {
    // Straight segments back and forth, and a line: filled by default, but with no area.
    let body = "<path d='M10 50 L90 50 L50 50' stroke='black' stroke-width='2'/>\
        <line x1='10' y1='20' x2='90' y2='20' stroke='black' stroke-width='2'/>\
        <path d='M10 80 L90 80 L50 95 Z' fill='olive'/>";
    let drawing = read_svg(&svg(body), &ImportOptions::default()).unwrap();
    // Bend it: the lines' rest fill area is 0, their bent one is not.
    let points: Vec<Point> = drawing
        .flat_points()
        .iter()
        .map(|p| Point::new(p.x, p.y + 0.004 * (p.x - 50.0).powi(2)))
        .collect();
    let out = write_svg(&drawing, &points).unwrap();
    assert_eq!(out.matches("style=\"fill:none\"").count(), 2, "{out}");
    assert!(
        out.contains("fill='olive'") && !out.contains("fill='olive' style"),
        "{out}"
    );
}
