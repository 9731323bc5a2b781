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
//!
//! User-space gradients and patterns, fixed-orientation markers, images and stroke widths
//! (`write_svg_following`) get the same rendering check, and each also checks that the plain
//! writer (nothing carried) fails it. Text (drawn in the shipped DejaVu Sans) gets the same
//! rendering check, and its written `transform` is also compared with the rigid map
//! numerically. Under a bend, the maps are compared
//! with a direct least-squares solve over the same samples; the bundled fish's label is
//! checked against the deformation at the corners of its box in each of the scene's poses.

mod common;

use common::external_data;
use kurbo::{Affine, Point, Rect, Vec2};
use splineskin::drawing::follow::{best_fit_affine, ElementMaps, FollowOptions, REGION_GRID};
use splineskin::drawing::svg_out::{write_svg, write_svg_following, ViewBoxRule};
use splineskin::drawing::{read_svg, Drawing, ImportOptions, PathRole};
use splineskin::naive::skin_point;
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

/// The three Shepard handles of the tests.
fn field() -> Shepard {
    let handles = [(20.0, 30.0), (80.0, 40.0), (50.0, 85.0)].map(Point::from);
    Shepard::new(&handles, ShepardOptions::default())
}

/// Deforms `drawing` by `pose` on three Shepard handles through a spline rig.
fn deform(drawing: &Drawing, pose: Affine) -> Vec<Point> {
    deform_pose(drawing, &[pose; 3])
}

/// Deforms `drawing` by one transform per handle through a spline rig.
fn deform_pose(drawing: &Drawing, pose: &[Affine; 3]) -> Vec<Point> {
    let field = field();
    let rig = SplineRig::precompute(drawing, &field, &FitOptions::default()).expect("precompute");
    let mut out = vec![Point::ZERO; rig.n_points()];
    rig.update(pose, &mut out).expect("update");
    out
}

/// The element maps of the skinning map of the test handles under `pose`.
fn maps(drawing: &Drawing, pose: &[Affine; 3], options: &FollowOptions) -> ElementMaps {
    let field = field();
    let mut w = [0.0; 3];
    ElementMaps::from_map(
        drawing,
        &mut |p| skin_point(&field, pose, p, &mut w),
        options,
    )
    .expect("element maps")
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

/// The pass mark of a comparison of renders: the art in view (`ink`, the fraction of inked
/// pixels, over 2 %), and at most [`MAX_DIFFERENT`] of the pixels different (`diff`); `out`,
/// the SVG written, is shown on failure.
fn assert_same_render(name: &str, diff: f64, ink: f64, out: &str) {
    assert!(ink > 0.02, "{name}: the art is not in view ({ink})");
    assert!(
        diff <= MAX_DIFFERENT,
        "{name}: {diff} of the pixels differ\n{out}"
    );
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
    assert_same_render(name, diff, ink, &out);
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

// ---------------------------------------------------------------------------------------------
// Paint servers, markers, text and images carried by the best-fit affine map of each element.

/// Reads `svg`, deforms it by `pose` (the same map on every handle), writes it with its
/// element maps, and checks the render against the input rendered under that map. Also
/// checks that the plain writer (nothing carried) fails the same comparison, so the test can
/// tell carried from left at rest. Returns the drawing and the output.
fn check_carried(
    name: &str,
    svg: &str,
    pose: Affine,
    options: &FollowOptions,
) -> (Drawing, String) {
    let drawing = read_svg(svg, &ImportOptions::default()).expect("read");
    let points = deform(&drawing, pose);
    let element_maps = maps(&drawing, &[pose; 3], options);
    let out =
        write_svg_following(&drawing, &points, &element_maps, ViewBoxRule::Keep).expect("write");
    let expected = wrapped(svg, pose);
    let (diff, ink) = difference(name, &expected, &out);
    let plain = write_svg(&drawing, &points).expect("write");
    let (diff_plain, _) = difference(&format!("{name}-at-rest"), &expected, &plain);
    eprintln!(
        "{name}: {:.3} % of pixels differ ({:.3} % with nothing carried), {:.1} % ink",
        100.0 * diff,
        100.0 * diff_plain,
        100.0 * ink
    );
    assert_same_render(name, diff, ink, &out);
    assert!(
        diff_plain > 4.0 * MAX_DIFFERENT,
        "{name}: the test cannot tell: {diff_plain} differ with nothing carried"
    );
    (drawing, out)
}

const GRADIENTS: &str = "<defs>\
    <linearGradient id='lg' gradientUnits='userSpaceOnUse' x1='10' y1='10' x2='60' y2='30'>\
      <stop offset='0' stop-color='red'/><stop offset='0.5' stop-color='yellow'/>\
      <stop offset='1' stop-color='blue'/></linearGradient>\
    <radialGradient id='rg' gradientUnits='userSpaceOnUse' cx='65' cy='60' r='20' fx='58' fy='54' \
      gradientTransform='scale(1 1.15)'>\
      <stop offset='0' stop-color='white'/><stop offset='1' stop-color='darkgreen'/></radialGradient>\
    <linearGradient id='lg2' href='#lg' gradientTransform='rotate(60 35 60)'/>\
    </defs>\
    <rect x='10' y='10' width='50' height='30' fill='url(#lg)'/>\
    <circle cx='65' cy='70' r='22' fill='url(#rg)'/>\
    <path d='M15 60 C30 45 40 95 50 70' fill='none' stroke='url(#lg2)' stroke-width='7'/>\
    <g transform='translate(5 -3)'><rect x='66' y='10' width='20' height='35' fill='url(#lg)'/></g>";

#[test]
fn user_space_gradients_follow_a_rigid_pose() {
    let (_, out) = check_carried(
        "gradients",
        &svg(GRADIENTS),
        rigid(),
        &FollowOptions::default(),
    );
    // The original gradients are kept; each user got a copy (two rectangles in different
    // coordinates: different local maps, two copies of `lg`).
    assert_eq!(out.matches("<linearGradient").count(), 2 + 3, "{out}");
    assert_eq!(out.matches("<radialGradient").count(), 1 + 1, "{out}");
}

/// [`check_carried`] of the document around `body` under the [`rigid`] pose, whose art is
/// `n_paths` paths (what `body` defines, patterns or markers, is not imported as art); the
/// output SVG.
fn check_rigid_with_art_paths(name: &str, body: &str, n_paths: usize) -> String {
    let (drawing, out) = check_carried(name, &svg(body), rigid(), &FollowOptions::default());
    assert_eq!(
        drawing.paths.len(),
        n_paths,
        "{name}: content is not imported as art"
    );
    out
}

const PATTERN: &str = "<defs>\
    <pattern id='pt' patternUnits='userSpaceOnUse' width='12' height='12' patternTransform='rotate(20)'>\
      <rect width='6' height='6' fill='purple'/><circle cx='9' cy='9' r='2.5' fill='orange'/></pattern>\
    </defs>\
    <rect x='15' y='15' width='70' height='60' fill='url(#pt)' stroke='black'/>";

#[test]
fn user_space_patterns_follow_a_rigid_pose() {
    let out = check_rigid_with_art_paths("pattern", PATTERN, 1);
    assert_eq!(out.matches("<pattern").count(), 2, "{out}");
}

const MARKERS: &str = "<defs>\
    <marker id='star' viewBox='0 0 12 12' markerWidth='18' markerHeight='18' refX='6' refY='6' \
      orient='0' markerUnits='userSpaceOnUse'>\
      <path d='M6 0 L7.5 4.5 L12 6 L7.5 7.5 L6 12 L4.5 7.5 L0 6 L4.5 4.5 Z' fill='crimson'/></marker>\
    <marker id='tri' viewBox='0 0 10 10' refX='0' refY='5' markerWidth='5' markerHeight='5' \
      orient='30deg'><path d='M0 0 L10 5 L0 10 z' fill='navy'/></marker>\
    <marker id='dot' viewBox='0 0 10 10' refX='5' refY='5' markerWidth='4' markerHeight='4' \
      orient='auto'><rect width='10' height='4' fill='teal'/></marker>\
    </defs>\
    <path d='M20 20 L50 30 L80 20 L70 60' fill='none' stroke='black' stroke-width='2' \
      marker-start='url(#star)' marker-mid='url(#star)' style='marker-end:url(#tri)'/>\
    <g marker-mid='url(#dot)'><path d='M20 80 C30 75 35 65 45 65 S70 80 80 85' fill='none' \
      stroke='green' stroke-width='2' marker-end='url(#star)'/></g>";

#[test]
fn fixed_orient_markers_turn_with_a_rigid_pose() {
    let out = check_rigid_with_art_paths("markers", MARKERS, 2);
    // star: one copy per user whose turn differs (the same rigid turn: shared); tri: one; dot
    // (orient auto) none.
    assert_eq!(out.matches("<marker").count(), 3 + 2, "{out}");
    let doc = roxmltree::Document::parse(&out).unwrap();
    let orients: Vec<f64> = doc
        .descendants()
        .filter(|n| n.tag_name().name() == "marker" && n.attribute("orient") != Some("auto"))
        .map(|n| {
            n.attribute("orient")
                .unwrap()
                .trim_end_matches("deg")
                .parse()
                .unwrap()
        })
        .collect();
    // star 0 → 25, tri 30 → 55 (the rigid map turns by 25°).
    let expected = [0.0, 25.0, 30.0, 55.0];
    assert_eq!(orients.len(), 4, "{orients:?}");
    for (o, e) in orients.iter().zip(expected) {
        assert!((o - e).abs() < 1e-9, "{orients:?}");
    }
}

/// A `w × h` PNG of four coloured quadrants, as a `data:` URL.
fn png_data_url(w: u32, h: u32) -> String {
    let mut pixmap = tiny_skia::Pixmap::new(w, h).unwrap();
    for y in 0..h {
        for x in 0..w {
            let c = match (2 * x < w, 2 * y < h) {
                (true, true) => [220, 30, 30],
                (false, true) => [30, 160, 40],
                (true, false) => [30, 60, 220],
                (false, false) => [240, 200, 20],
            };
            let i = 4 * (y * w + x) as usize;
            pixmap.data_mut()[i..i + 4].copy_from_slice(&[c[0], c[1], c[2], 255]);
        }
    }
    let png = pixmap.encode_png().unwrap();
    const B64: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::from("data:image/png;base64,");
    for chunk in png.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                s.push(B64[((n >> (18 - 6 * k)) & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

fn image_body() -> String {
    format!(
        "<rect x='15' y='20' width='60' height='50' fill='none' stroke='black' stroke-width='2'/>\
         <g transform='translate(3 4)'><image x='20' y='25' width='48' height='38' \
         preserveAspectRatio='none' style='image-rendering:optimizeSpeed' href='{}'/></g>",
        png_data_url(8, 8)
    )
}

#[test]
fn images_follow_a_rigid_pose() {
    let (_, out) = check_carried(
        "image",
        &svg(&image_body()),
        rigid(),
        &FollowOptions::default(),
    );
    assert_eq!(out.matches("transform=\"matrix(").count(), 1, "{out}");
}

/// The transforms of a `transform` attribute, composed.
fn parse_transform(v: &str) -> Affine {
    let t: svgtypes::Transform = v.parse().expect("transform");
    Affine::new([t.a, t.b, t.c, t.d, t.e, t.f])
}

/// The `transform` attribute of the first element `tag` of `svg`.
fn transform_of(svg: &str, tag: &str, n: usize) -> Affine {
    let doc = roxmltree::Document::parse(svg).unwrap();
    let node = doc
        .descendants()
        .filter(|d| d.tag_name().name() == tag)
        .nth(n)
        .expect("element");
    parse_transform(node.attribute("transform").unwrap_or(""))
}

fn assert_close(a: Affine, b: Affine, tolerance: f64, what: &str) {
    let ok = a
        .as_coeffs()
        .iter()
        .zip(b.as_coeffs())
        .all(|(x, y)| (x - y).abs() <= tolerance * (1.0 + y.abs()));
    assert!(ok, "{what}: {a:?} vs {b:?}");
}

const TEXT: &str = "<rect x='10' y='30' width='60' height='30' fill='khaki'/>\
    <text x='15' y='50' font-size='12'>Hello</text>\
    <g transform='translate(5 5)'><text transform='rotate(10 30 80)' x='30' y='80' \
      text-anchor='middle'>Fish <tspan>label</tspan></text></g>\
    <defs><text id='unused' x='0' y='0'>not drawn</text></defs>";

#[test]
fn text_is_carried_by_the_rigid_map() {
    let doc = svg(TEXT);
    let drawing = read_svg(&doc, &ImportOptions::default()).unwrap();
    let pose = rigid();
    let element_maps = maps(&drawing, &[pose; 3], &FollowOptions::default());
    assert_eq!(
        element_maps.n_carried(),
        2,
        "the text in defs is not drawn, not carried"
    );
    let points = deform(&drawing, pose);
    let out = write_svg_following(&drawing, &points, &element_maps, ViewBoxRule::Keep).unwrap();
    // First text: its parent is the root, its new local → root map is the rigid map itself.
    assert_close(transform_of(&out, "text", 0), pose, 1e-12, "text 0");
    // Second: parent P = translate(5 5), own O = rotate(10 30 80): P · written = pose · P · O.
    let p = Affine::translate((5.0, 5.0));
    let o = Affine::rotate_about(10f64.to_radians(), Point::new(30.0, 80.0));
    assert_close(
        p * transform_of(&out, "text", 1),
        pose * p * o,
        1e-12,
        "text 1",
    );
    // The plain writer leaves text at rest.
    let plain = write_svg(&drawing, &points).unwrap();
    assert_close(
        transform_of(&plain, "text", 0),
        Affine::IDENTITY,
        0.0,
        "plain",
    );
}

#[test]
fn text_renders_carried_by_a_rigid_pose() {
    // Plain text, text in a transformed group with a text-anchor and a tspan, and a filled
    // shape: rendered with the shipped font, the carried text must land where the input's
    // text lands under the rigid map; left at rest (the plain writer), it must not.
    let (_, out) = check_carried("text", &svg(TEXT), rigid(), &FollowOptions::default());
    assert_eq!(out.matches("<text").count(), 3, "{out}");
}

/// Direct least squares in homogeneous coordinates: minimise Σ ω ‖A p̄ − q‖² over the pairs
/// (`rest`, `image`) with weights `w`, by the 3×3 normal equations (Σ ω p̄ p̄ᵀ) a_r =
/// Σ ω q_r p̄ for each output row r, solved by Cramer's rule.
fn direct_fit(rest: &[Point], image: &[Point], w: &[f64]) -> Affine {
    let mut n = [[0.0; 3]; 3];
    let mut rhs = [[0.0; 3]; 2];
    for ((p, q), &wk) in rest.iter().zip(image).zip(w) {
        let h = [p.x, p.y, 1.0];
        for r in 0..3 {
            for c in 0..3 {
                n[r][c] += wk * h[r] * h[c];
            }
            rhs[0][r] += wk * q.x * h[r];
            rhs[1][r] += wk * q.y * h[r];
        }
    }
    let det3 = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det3(n);
    let solve = |b: [f64; 3]| -> [f64; 3] {
        std::array::from_fn(|k| {
            let mut m = n;
            for r in 0..3 {
                m[r][k] = b[r];
            }
            det3(m) / d
        })
    };
    let (x, y) = (solve(rhs[0]), solve(rhs[1]));
    Affine::new([x[0], y[0], x[1], y[1], x[2], y[2]])
}

/// [`direct_fit`] of the map `f` over `samples`, all weights 1.
fn direct_fit_of_map(samples: &[Point], f: &mut dyn FnMut(Point) -> Point) -> Affine {
    let image: Vec<Point> = samples.iter().map(|&p| f(p)).collect();
    direct_fit(samples, &image, &vec![1.0; samples.len()])
}

#[test]
fn best_fit_affine_matches_normal_equations() {
    let rest: Vec<Point> = (0..40)
        .map(|k| {
            let t = k as f64;
            Point::new((t * 1.7).sin() * 3.0 + 10.0, (t * 0.9).cos() * 2.0 - 4.0)
        })
        .collect();
    let image: Vec<Point> = rest
        .iter()
        .map(|p| Point::new(p.x + 0.1 * p.y * p.y, p.y - 0.2 * p.x.sin()))
        .collect();
    let w: Vec<f64> = (0..40).map(|k| 1.0 + (k % 3) as f64).collect();
    let a = best_fit_affine(&rest, &image, &w).unwrap();
    let b = direct_fit(&rest, &image, &w);
    for (x, y) in a.as_coeffs().iter().zip(b.as_coeffs()) {
        assert!((x - y).abs() < 1e-9 * (1.0 + y.abs()), "{a:?} vs {b:?}");
    }
}

/// Centres of the `REGION_GRID`² grid over the rectangle, mapped by `t`.
fn grid_samples(x: f64, y: f64, w: f64, h: f64, t: Affine) -> Vec<Point> {
    let n = REGION_GRID;
    let mut out = Vec::new();
    for iy in 0..n {
        for ix in 0..n {
            let fx = (ix as f64 + 0.5) / n as f64;
            let fy = (iy as f64 + 0.5) / n as f64;
            out.push(t * Point::new(x + fx * w, y + fy * h));
        }
    }
    out
}

/// A bend: one handle moved by 15 % of the drawing and turned 30°, the others at rest.
fn bend() -> [Affine; 3] {
    let c = Point::new(50.0, 85.0);
    [
        Affine::IDENTITY,
        Affine::IDENTITY,
        Affine::translate((15.0, -6.0)) * Affine::rotate_about(30f64.to_radians(), c),
    ]
}

#[test]
fn under_a_bend_the_maps_are_the_least_squares_fits() {
    let body = format!(
        "{}<rect x='10' y='10' width='50' height='30' fill='url(#lg)'/>",
        image_body()
    ) + "<defs><linearGradient id='lg' gradientUnits='userSpaceOnUse' gradientTransform='translate(1 2)'>\
          <stop offset='0' stop-color='red'/><stop offset='1' stop-color='blue'/></linearGradient></defs>";
    let doc = svg(&body);
    let drawing = read_svg(&doc, &ImportOptions::default()).unwrap();
    let pose = bend();
    let element_maps = maps(&drawing, &pose, &FollowOptions::default());
    let field = field();
    let mut w = [0.0; 3];
    let mut f = |p: Point| skin_point(&field, &pose, p, &mut w);

    // The image: its rectangle in root space (parent translate(3 4)).
    let parent = Affine::translate((3.0, 4.0));
    let samples = grid_samples(20.0, 25.0, 48.0, 38.0, parent);
    let direct = direct_fit_of_map(&samples, &mut f);
    let image_offset = doc.find("<image").unwrap();
    let fitted = element_maps
        .carried_map(image_offset)
        .expect("image carried");
    assert_close(fitted, direct, 1e-9, "image map vs direct least squares");
    // A genuine bend: the map is no handle's transform and not rigid.
    let [a, b, c, d, _, _] = fitted.as_coeffs();
    assert!(
        (a - d).abs() + (b + c).abs() > 1e-3 || (a * d - b * c - 1.0).abs() > 1e-3,
        "{fitted:?}"
    );
    for t in pose {
        let gap: f64 = fitted
            .as_coeffs()
            .iter()
            .zip(t.as_coeffs())
            .map(|(x, y)| (x - y).abs())
            .sum();
        assert!(gap > 1e-2, "{fitted:?} is a handle's map");
    }
    let points = deform_pose(&drawing, &pose);
    let out = write_svg_following(&drawing, &points, &element_maps, ViewBoxRule::Keep).unwrap();
    assert_close(
        parent * transform_of(&out, "image", 0),
        direct * parent,
        1e-9,
        "written image transform",
    );

    // The filled rectangle: every grid centre of its box is inside it.
    let rect = drawing
        .source
        .as_ref()
        .unwrap()
        .element_of_path(drawing.paths.len() - 1)
        .unwrap();
    let samples = grid_samples(10.0, 10.0, 50.0, 30.0, Affine::IDENTITY);
    let direct = direct_fit_of_map(&samples, &mut f);
    assert_close(
        element_maps.element_map(rect).unwrap(),
        direct,
        1e-9,
        "rect map vs direct least squares",
    );
    // Its gradient copy: gradientTransform = A · G (the rect's local space is root space).
    let doc_out = roxmltree::Document::parse(&out).unwrap();
    let copy = doc_out
        .descendants()
        .filter(|n| n.tag_name().name() == "linearGradient")
        .nth(1)
        .expect("a copy");
    assert_eq!(copy.attribute("gradientUnits"), Some("userSpaceOnUse"));
    assert_close(
        parse_transform(copy.attribute("gradientTransform").unwrap()),
        direct * Affine::translate((1.0, 2.0)),
        1e-9,
        "gradient copy",
    );
    if let Ok(dir) = std::env::var("DOCUMENT_TEST_OUT") {
        std::fs::create_dir_all(&dir).unwrap();
        let png = splineskin::render::render_png(&out, 480).unwrap();
        std::fs::write(format!("{dir}/bend-carried.png"), png).unwrap();
        let png = splineskin::render::render_png(&doc, 480).unwrap();
        std::fs::write(format!("{dir}/bend-rest.png"), png).unwrap();
    }
}

#[test]
fn strokes_scale_with_the_map_only_when_asked() {
    let body = "<path d='M20 30 C40 10 60 50 80 30' fill='none' stroke='black' stroke-width='4'/>\
        <rect x='25' y='50' width='50' height='30' fill='none' stroke='maroon' stroke-width='3'/>";
    let scaled = Affine::translate((10.0, 5.0))
        * Affine::rotate_about(0.3, Point::new(50.0, 50.0))
        * Affine::scale_about(0.6, Point::new(50.0, 50.0));
    let on = FollowOptions::default().with_scale_strokes(true);
    let (_, out) = check_carried("scaled-strokes", &svg(body), scaled, &on);
    assert!(out.contains("stroke-width:2.4"), "{out}");
    // Off (the default): widths as they were.
    let drawing = read_svg(&svg(body), &ImportOptions::default()).unwrap();
    let points = deform(&drawing, scaled);
    let off = maps(&drawing, &[scaled; 3], &FollowOptions::default());
    let out = write_svg_following(&drawing, &points, &off, ViewBoxRule::Keep).unwrap();
    assert!(!out.contains("stroke-width:"), "{out}");
}

/// Largest distance between where the fish's label's map and the deformation itself put a
/// corner of the label's box, relative to the box's diagonal (90 × 18 units): 5 %. The
/// label's map is the least-squares affine map over its box, so it misses the deformation at
/// the corners by how much that bends across one word (1.3–3.3 % in the three poses); a label
/// left at rest misses by the pose's displacement there (more than its height in every pose).
const LABEL_FOLLOWS: f64 = 0.05;

#[test]
fn the_fish_label_follows_its_plate_in_every_pose() {
    use splineskin::examples::{DEMO_SCENE, DEMO_SVG};
    use splineskin::scene::{Compat, Scene};
    let assets = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/assets"));
    let scene = Scene::from_json(DEMO_SCENE, "demo-scene.json", Some(assets)).unwrap();
    let setup = scene.setup(Compat::None).unwrap();
    let drawing = &setup.drawing;
    let label_at = DEMO_SVG.find("<text").expect("the label");
    // The label's box: "splineskin" centred on x = 300, baseline 377, 18 units high.
    let corners = [
        (255.0, 362.6),
        (345.0, 362.6),
        (255.0, 380.6),
        (345.0, 380.6),
    ]
    .map(Point::from);
    for pose in &scene.poses {
        let mut w = vec![0.0; pose.transforms.len()];
        let mut f = |p| skin_point(&*setup.weights, &pose.transforms, p, &mut w);
        let maps = ElementMaps::from_map(drawing, &mut f, &FollowOptions::default()).unwrap();
        let label = maps.carried_map(label_at).expect("label carried");
        let gap = corners
            .iter()
            .map(|&q| (label * q - f(q)).hypot())
            .fold(0.0, f64::max);
        let at_rest = corners
            .iter()
            .map(|&q| (q - f(q)).hypot())
            .fold(0.0, f64::max);
        eprintln!(
            "{:?}: label corners {gap:.3} units from the deformation (left at rest: {at_rest:.3})",
            pose.name
        );
        let allowed = LABEL_FOLLOWS * 90f64.hypot(18.0);
        assert!(gap <= allowed, "{:?}: {gap}", pose.name);
        // Control: a label left at rest would be three times as far off, or more.
        assert!(at_rest > 3.0 * allowed, "{:?}: {at_rest}", pose.name);
    }
}

/// How close the carry operator's maps are to those of [`ElementMaps::from_map`], relative to
/// each map's size (its linear part's norm plus its translation over the drawing's diagonal):
/// the same least-squares fit summed in another order, so rounding only.
const CARRY_AGREES: f64 = 1e-9;

/// Checks the carry operator of `drawing` under `field` against the element maps at `poses`.
fn check_carry(
    drawing: &Drawing,
    field: &dyn splineskin::weights::WeightField,
    poses: &[Vec<Affine>],
    what: &str,
) {
    use splineskin::drawing::carry::CarryOperator;
    use splineskin::naive::skin_point_derivatives;
    let h = field.n_handles();
    let mut w = vec![0.0; h];
    let carry = CarryOperator::new(drawing, 6 * h, &mut |p, d| {
        skin_point_derivatives(field, p, d, &mut w)
    })
    .unwrap();
    assert_eq!(carry.n_carried(), 1, "{what}: its label");
    let diagonal = drawing
        .flat_points()
        .iter()
        .fold(
            kurbo::Rect::from_points(drawing.paths[0].points[0], drawing.paths[0].points[0]),
            |r, &p| r.union_pt(p),
        )
        .size()
        .to_vec2()
        .hypot();
    for pose in poses {
        let mut f = |p| skin_point(field, pose, p, &mut w);
        let maps = ElementMaps::from_map(drawing, &mut f, &FollowOptions::default()).unwrap();
        let expected: Vec<Affine> = maps.carried_maps().collect();
        let x: Vec<f64> = pose.iter().flat_map(|t| t.as_coeffs()).collect();
        let mut got = vec![Affine::IDENTITY; carry.n_carried()];
        carry.apply(&x, &mut got);
        for (a, b) in got.iter().zip(&expected) {
            let (a, b) = (a.as_coeffs(), b.as_coeffs());
            let linear = (0..4).map(|i| (a[i] - b[i]).abs()).fold(0.0, f64::max);
            let shift = (4..6).map(|i| (a[i] - b[i]).abs()).fold(0.0, f64::max) / diagonal;
            let size = (0..4).map(|i| b[i].abs()).fold(0.0, f64::max);
            eprintln!("{what}: carry operator off by {linear:.1e} (linear part), {shift:.1e} of the diagonal (translation)");
            assert!(
                linear <= CARRY_AGREES * size && shift <= CARRY_AGREES,
                "{what}: {a:?} vs {b:?}"
            );
        }
    }
}

#[test]
fn the_carry_operator_gives_the_element_maps_at_every_pose_and_scale() {
    use splineskin::examples::DEMO_SCENE;
    use splineskin::scene::{Compat, Scene};
    let assets = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/assets"));
    let scene = Scene::from_json(DEMO_SCENE, "demo-scene.json", Some(assets)).unwrap();
    let setup = scene.setup(Compat::None).unwrap();
    let poses: Vec<Vec<Affine>> = scene.poses.iter().map(|p| p.transforms.clone()).collect();
    check_carry(&setup.drawing, &*setup.weights, &poses, "the bundled fish");
    // A label 1e5 times larger and 3e8 units from the origin, and one 1e-6 times smaller, under
    // the test handles' bend and rigid map carried there.
    for (s, what) in [
        (
            Affine::translate((3e8, -2e8)) * Affine::scale(1e5),
            "a label far from the origin",
        ),
        (
            Affine::translate((3e-3, -2e-3)) * Affine::scale(1e-6),
            "a tiny label",
        ),
    ] {
        let at = |x: f64, y: f64| s * Point::new(x, y);
        let [a, b, c, t, corner] = [
            at(10.0, 10.0),
            at(60.0, 40.0),
            at(20.0, 70.0),
            at(20.0, 50.0),
            at(0.0, 0.0),
        ];
        let size = s.as_coeffs()[0];
        let svg = format!(
            "<svg xmlns='http://www.w3.org/2000/svg' viewBox='{} {} {} {}'>\
             <path d='M{} {} L{} {} L{} {} Z'/><text x='{}' y='{}' font-size='{}'>far</text></svg>",
            corner.x,
            corner.y,
            100.0 * size,
            100.0 * size,
            a.x,
            a.y,
            b.x,
            b.y,
            c.x,
            c.y,
            t.x,
            t.y,
            10.0 * size
        );
        let drawing = read_svg(&svg, &ImportOptions::default()).unwrap();
        let handles = [(20.0, 30.0), (80.0, 40.0), (50.0, 85.0)].map(|(x, y)| at(x, y));
        let field = Shepard::new(&handles, ShepardOptions::default());
        let conjugate = |t: &Affine| s * *t * s.inverse();
        let poses = [
            bend().iter().map(conjugate).collect(),
            vec![conjugate(&rigid()); 3],
        ];
        check_carry(&drawing, &field, &poses, what);
    }
}

// ---------------------------------------------------------------------------------------------
// Strokes drawn inside a non-uniform (or sheared) element transform.

/// A saltire of thin strokes inside `scale(4 1)` (its strokes 4 times wider across its
/// vertical than across its horizontal directions, as on flags drawn at unit size and scaled),
/// a stroked ellipse under a shear with a dash pattern, and a uniform control.
const STRETCHED_STROKES: &str = "<g transform='scale(4 1)'>\
      <path d='M4 18 L21 82 M4 82 L21 18' fill='none' stroke='navy' stroke-width='2.5' \
        stroke-linecap='square'/></g>\
    <g transform='translate(50 50) skewX(30) scale(1 0.6)'>\
      <ellipse rx='12' ry='20' fill='gold' stroke='crimson' stroke-width='3' \
        stroke-dasharray='6 3'/></g>\
    <circle cx='80' cy='20' r='8' fill='none' stroke='teal' stroke-width='3'/>";

/// Largest channel difference (of 255) between two renders, and the number of pixels that
/// differ by more than `level`.
fn largest_difference(a: &str, b: &str, level: u8) -> (u8, usize) {
    let (pa, pb) = (pixels(a), pixels(b));
    let mut largest = 0;
    let mut count = 0;
    for (x, y) in pa.pixels().iter().zip(pb.pixels()) {
        let d = [
            x.red().abs_diff(y.red()),
            x.green().abs_diff(y.green()),
            x.blue().abs_diff(y.blue()),
            x.alpha().abs_diff(y.alpha()),
        ];
        let m = d.into_iter().max().unwrap_or(0);
        largest = largest.max(m);
        count += usize::from(m > level);
    }
    (largest, count)
}

/// Largest channel difference allowed for "pixel-equal": 2 of 255 (the same picture drawn
/// through transforms that agree to rounding; an edge rounded the other way moves
/// anti-aliasing coverage by a level or two).
const PIXEL_EQUAL: u8 = 2;

/// Pixels allowed beyond [`PIXEL_EQUAL`] in "pixel-equal" renders: 3 of the 57 600 (an edge
/// pixel whose coverage falls the other side of a sample when a coordinate is written
/// `3.9999999999999996` instead of `4`).
const MAX_STRAY_PIXELS: usize = 3;

#[test]
fn strokes_in_a_stretched_frame_turn_with_every_pin() {
    let quarter = Affine::rotate_about(std::f64::consts::FRAC_PI_2, Point::new(50.0, 50.0));
    for (name, options) in [
        ("stretched-strokes", FollowOptions::default()),
        (
            "stretched-strokes-scaled",
            FollowOptions::default().with_scale_strokes(true),
        ),
    ] {
        let doc = svg(STRETCHED_STROKES);
        let (drawing, out) = check_carried(name, &doc, quarter, &options);
        let expected = wrapped(&doc, quarter);
        let (largest, count) = largest_difference(&expected, &out, PIXEL_EQUAL);
        let plain = write_svg(&drawing, &deform(&drawing, quarter)).unwrap();
        let (_, count_plain) = largest_difference(&expected, &plain, PIXEL_EQUAL);
        eprintln!(
            "{name}: {count} pixels differ by more than {PIXEL_EQUAL} (largest {largest}); \
             {count_plain} drawn in the element's own frame"
        );
        assert!(count <= MAX_STRAY_PIXELS, "{name}: {count}\n{out}");
        assert!(count_plain > 100 * MAX_STRAY_PIXELS, "the test cannot tell");
        // The saltire and the ellipse are drawn in a frame of their own; the circle is not.
        let element_maps = maps(&drawing, &[quarter; 3], &options);
        let framed: Vec<bool> = (0..3)
            .map(|k| element_maps.stroke_frame(k).is_some())
            .collect();
        assert_eq!(framed, [true, true, false]);
    }
}

#[test]
fn a_stretched_stroke_keeps_its_rest_path_data_under_a_rigid_pose() {
    // Drawn as F L with F the rigid map itself, the element's path data are its rest ones.
    let doc = svg(
        "<g transform='scale(4 1)'><path d='M4 18 L21 82' fill='none' \
        stroke='navy' stroke-width='2.5'/></g>",
    );
    let drawing = read_svg(&doc, &ImportOptions::default()).unwrap();
    let pose = rigid();
    let points = deform(&drawing, pose);
    let element_maps = maps(&drawing, &[pose; 3], &FollowOptions::default());
    let out = write_svg_following(&drawing, &points, &element_maps, ViewBoxRule::Keep).unwrap();
    let again = read_svg(&out, &ImportOptions::default()).unwrap();
    let d_of = |text: &str| {
        let at = text.find(" d=").expect("a path") + 3;
        let quote = text[at..].chars().next().unwrap();
        let value = &text[at + 1..];
        value[..value.find(quote).unwrap()].to_string()
    };
    let numbers = |d: String| -> Vec<f64> {
        d.split(|c: char| c.is_ascii_alphabetic() || c.is_whitespace())
            .filter_map(|v| v.parse().ok())
            .collect()
    };
    let d = numbers(d_of(&out));
    let ends = [d[0], d[1], d[d.len() - 2], d[d.len() - 1]];
    for (x, y) in ends.iter().zip([4.0, 18.0, 21.0, 82.0]) {
        assert!((x - y).abs() < 1e-9, "{out}");
    }
    // Read back (in single precision), it is where the pose put it.
    for (p, q) in again.flat_points().iter().zip(&points) {
        assert!((*p - *q).hypot() < 1e-5 * 100.0, "{p:?} vs {q:?}");
    }
}

#[test]
fn a_stretched_stroke_under_a_bend_keeps_its_rest_shape_turned() {
    // A bend: the stroke frame is the orthogonal factor of the element's map, placed at its
    // region's mean; the written transform is T L⁻¹ F L and the path lands on the deformed
    // points.
    let doc = svg(
        "<g transform='scale(4 1)'><path d='M4 18 C10 40 15 60 21 82' \
        fill='none' stroke='navy' stroke-width='2.5'/></g>",
    );
    let drawing = read_svg(&doc, &ImportOptions::default()).unwrap();
    let pose = [
        Affine::IDENTITY,
        Affine::rotate_about(0.6, Point::new(80.0, 40.0)),
        Affine::translate((10.0, -5.0)),
    ];
    let points = deform_pose(&drawing, &pose);
    let element_maps = maps(&drawing, &pose, &FollowOptions::default());
    let a = element_maps.element_map(0).unwrap();
    let f = element_maps.stroke_frame(0).expect("a stroke frame");
    let [fa, fb, fc, fd, _, _] = f.as_coeffs();
    // A rotation, by the angle of the rotation closest to the element's map (the region is a
    // line, flat to the fit: the map is a similarity, whose rotation is the best-fit one).
    assert!(
        (fa * fd - fb * fc - 1.0).abs() < 1e-12 && (fa - fd).abs() < 1e-12,
        "{f:?} of {a:?}"
    );
    let angle = fb.atan2(fa);
    assert!(
        (fb + fc).abs() < 1e-12 && angle.abs() > 0.02,
        "{f:?} of {a:?}"
    );
    assert!((angle - splineskin::drawing::follow::rotation_angle(a)).abs() < 1e-12);
    let out = write_svg_following(&drawing, &points, &element_maps, ViewBoxRule::Keep).unwrap();
    let again = read_svg(&out, &ImportOptions::default()).unwrap();
    let size = 100.0;
    for (p, q) in again.flat_points().iter().zip(&points) {
        assert!((*p - *q).hypot() < 1e-5 * size, "{p:?} vs {q:?}");
    }
    assert!(out.contains("<path transform=\"matrix(") || out.contains(" transform=\"matrix("));
}

/// Every flag of the `flag-icons` package (test-art) with a stroke inside a non-uniform
/// transform (45 of its 542; Scotland's saltire is `stroke-width=".6"` inside
/// `scale(128 160)`), turned a quarter by every pin through a rig: rendered as the input turned
/// ([`assert_same_render`]: fine detail such as a palm's hairline fronds re-rasterises a little
/// differently), and Scotland's pixel-equal (drawn in its own frame it is not: its stroke
/// widths swap).
#[test]
fn real_flags_with_stretched_strokes_turn_with_their_pins() {
    let Some(art) = external_data::test_art() else {
        return;
    };
    let mut files: Vec<_> = ["4x3", "1x1"]
        .iter()
        .flat_map(|f| std::fs::read_dir(art.join("flag-icons/flags").join(f)).unwrap())
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    assert!(files.len() > 500, "flag-icons has {} flags", files.len());
    let mut framed = 0;
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        let Ok(drawing) = read_svg(&text, &ImportOptions::default()) else {
            continue;
        };
        let source = drawing.source.as_ref().unwrap();
        let centre = source.view_box().center();
        let quarter = Affine::rotate_about(std::f64::consts::FRAC_PI_2, centre);
        let element_maps = maps_with_handles(&drawing, quarter);
        let n = source.elements.len();
        if !(0..n).any(|k| element_maps.stroke_frame(k).is_some()) {
            continue;
        }
        framed += 1;
        let points = deform_with_handles(&drawing, quarter);
        let out = write_svg_following(&drawing, &points, &element_maps, ViewBoxRule::Keep).unwrap();
        let name = file.strip_prefix(&art).unwrap().display().to_string();
        let expected = wrapped(&text, quarter);
        let (diff, ink) = difference(&name.replace('/', "-"), &expected, &out);
        eprintln!("{name}: {:.3} % of pixels differ", 100.0 * diff);
        assert_same_render(&name, diff, ink, &out);
        if name.ends_with("4x3/gb-sct.svg") {
            let (largest, count) = largest_difference(&expected, &out, PIXEL_EQUAL);
            let plain = write_svg(&drawing, &points).unwrap();
            let (_, count_plain) = largest_difference(&expected, &plain, PIXEL_EQUAL);
            eprintln!("{name}: {count} pixels differ (largest {largest}); {count_plain} unframed");
            assert!(count <= MAX_STRAY_PIXELS, "{name}: {count} pixels differ");
            assert!(count_plain > 100 * MAX_STRAY_PIXELS, "the test cannot tell");
        }
    }
    eprintln!(
        "{framed} of {} flags have a stroke in a stretched frame",
        files.len()
    );
    assert!(framed >= 40, "{framed} flags with a stroke frame");
}

/// Shepard handles at the corners and centre of `drawing`'s viewBox.
fn handles_over(drawing: &Drawing) -> Shepard {
    let b: Rect = drawing.source.as_ref().unwrap().view_box();
    let handles = [(b.x0, b.y0), (b.x1, b.y0), (b.x0, b.y1), (b.x1, b.y1)]
        .map(Point::from)
        .into_iter()
        .chain([b.center()])
        .collect::<Vec<_>>();
    Shepard::new(&handles, ShepardOptions::default())
}

/// `drawing` deformed through a rig on [`handles_over`] with `pose` on every handle.
fn deform_with_handles(drawing: &Drawing, pose: Affine) -> Vec<Point> {
    let field = handles_over(drawing);
    let rig = SplineRig::precompute(drawing, &field, &FitOptions::default()).expect("precompute");
    let mut out = vec![Point::ZERO; rig.n_points()];
    rig.update(&[pose; 5], &mut out).expect("update");
    out
}

/// The element maps of the skinning map of [`handles_over`] with `pose` on every handle.
fn maps_with_handles(drawing: &Drawing, pose: Affine) -> ElementMaps {
    let field = handles_over(drawing);
    let mut w = [0.0; 5];
    let mut f = |p| skin_point(&field, &[pose; 5], p, &mut w);
    ElementMaps::from_map(drawing, &mut f, &FollowOptions::default()).expect("element maps")
}

/// A thin stroke (an S-shaped line inside `scale(4 1)`, as a user draws one, pinned along
/// itself) under bends in every direction: its best-fit affine map is ill-conditioned across
/// the line (the region has little width), so its stroke frame must not be read from that
/// map's linear part alone. The frame is a rotation (a bend does not mirror the art) by about
/// the turn of the line's chord.
#[test]
fn a_thin_stretched_stroke_under_bends_is_framed_by_a_rotation_along_it() {
    let doc = svg(
        "<g transform='scale(4 1)'><path d='M6 15 C9 35 16 60 19 85' fill='none' \
        stroke='navy' stroke-width='2'/></g>",
    );
    let drawing = read_svg(&doc, &ImportOptions::default()).unwrap();
    let handles = [(24.0, 15.0), (50.0, 50.0), (76.0, 85.0)].map(Point::from);
    let field = Shepard::new(&handles, ShepardOptions::default());
    let rig = SplineRig::precompute(&drawing, &field, &FitOptions::default()).expect("precompute");
    let quarter = Affine::rotate_about(std::f64::consts::FRAC_PI_2, Point::new(50.0, 50.0));
    let rest = drawing.flat_points();
    let (r0, r1) = (rest[0], rest[rest.len() - 1]);
    let mut worst: f64 = 0.0;
    for k in 0..16 {
        let angle = f64::from(k) * std::f64::consts::TAU / 16.0;
        for (turn, drag) in [
            (Affine::IDENTITY, 20.0),
            (quarter, 20.0),
            (Affine::IDENTITY, 35.0),
        ] {
            let pull = Affine::translate(Vec2::new(angle.cos(), angle.sin()) * drag);
            let pose = [turn, turn, pull * turn];
            let mut points = vec![Point::ZERO; rig.n_points()];
            rig.update(&pose, &mut points).expect("update");
            let mut w = [0.0; 3];
            let mut f = |p| skin_point(&field, &pose, p, &mut w);
            let element_maps =
                ElementMaps::from_map(&drawing, &mut f, &FollowOptions::default()).unwrap();
            let f = element_maps.stroke_frame(0).expect("a stroke frame");
            let [fa, fb, fc, fd, _, _] = f.as_coeffs();
            assert!(
                (fa * fd - fb * fc - 1.0).abs() < 1e-12,
                "pull {k} × {drag}: a reflection {f:?} of {:?}",
                element_maps.element_map(0)
            );
            let (p0, p1) = (points[0], points[points.len() - 1]);
            let chord_turn = (p1 - p0).atan2() - (r1 - r0).atan2();
            let off = (fb.atan2(fa) - chord_turn).sin().abs().asin();
            worst = worst.max(off);
        }
    }
    eprintln!(
        "thin stretched stroke: its frame within {:.1}° of its chord's turn",
        worst.to_degrees()
    );
    assert!(worst < 20f64.to_radians(), "{}°", worst.to_degrees());
}
