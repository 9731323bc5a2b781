//! Text in renders and text as outlines.
//!
//! - PNG renders draw text (DejaVu Sans, shipped in the binary): the bundled fish rendered
//!   with and without its label differs exactly inside the label's plate.
//! - Outlines ([`TextMode::Outlines`]): the drawing imported with its text as glyph outlines
//!   and written back at rest renders like the original text (at most [`MAX_DIFFERENT`] of the
//!   pixels differ beyond anti-aliasing, and at most [`MAX_INK_DIFFERENT`] of the text's own
//!   pixels), for the fish and for a document using transforms, spans of several paints,
//!   strokes, opacity, decorations, clip paths, `use` and hidden layers.
//! - The outlines are curves of the drawing like any other: a rig reproduces them at the
//!   identity and under one rigid map on every handle to 1e-9 of each path's own diagonal, and
//!   under a bend they follow the skinning map.
//!
//! Set `TEXT_TEST_OUT=DIR` to keep the pictures.

#[path = "common/measure.rs"]
mod measure;

use kurbo::{Affine, ParamCurve, Point, Rect, Vec2};
use measure::diagonal;
use splineskin::drawing::svg_out::write_svg;
use splineskin::drawing::text_outlines::text_to_outlines;
use splineskin::drawing::{read_svg, Drawing, ImportOptions, TextMode};
use splineskin::naive::skin_point;
use splineskin::scene::{Compat, Scene};
use splineskin::spline_fit::SplineRig;
use splineskin::weights::WeightField;

/// The bundled fish, whose plate carries the label "splineskin".
const FISH: &str = include_str!("../assets/demo.svg");

/// The fish's label plate (`rect#plate`), in its user units (= pixels at [`FISH_SIZE`]).
const PLATE: Rect = Rect::new(210.0, 354.0, 390.0, 388.0);

/// Render size of the fish: its viewport is 600 × 400, so one pixel per user unit.
const FISH_SIZE: u32 = 600;

/// Largest channel difference (of 255) still counted as anti-aliasing.
const ANTI_ALIASING: u8 = 48;

/// Largest fraction of all pixels allowed to differ beyond [`ANTI_ALIASING`]: 0.5 %.
const MAX_DIFFERENT: f64 = 0.005;

/// Largest fraction of the text's own pixels (those that differ between the document rendered
/// with and without its text) allowed to differ beyond [`ANTI_ALIASING`]: 2 %. Far tighter
/// than [`MAX_DIFFERENT`], which a missing label would meet (it covers < 0.5 % of the fish).
const MAX_INK_DIFFERENT: f64 = 0.02;

/// Relative tolerance of the identity and rigid invariants: 1e-9 of each path's diagonal.
const INVARIANT: f64 = 1e-9;

fn pixels(name: &str, svg: &str, size: u32) -> tiny_skia::Pixmap {
    let png = splineskin::render::render_png(svg, size).expect("render");
    let pixmap = tiny_skia::Pixmap::decode_png(&png).expect("decode");
    if let Ok(dir) = std::env::var("TEXT_TEST_OUT") {
        std::fs::create_dir_all(&dir).unwrap();
        pixmap.save_png(format!("{dir}/{name}.png")).unwrap();
    }
    pixmap
}

/// The pixels (x, y) where two renders differ by more than `threshold` in some channel.
fn differing(a: &tiny_skia::Pixmap, b: &tiny_skia::Pixmap, threshold: u8) -> Vec<(u32, u32)> {
    assert_eq!((a.width(), a.height()), (b.width(), b.height()));
    let w = a.width();
    a.pixels()
        .iter()
        .zip(b.pixels())
        .enumerate()
        .filter(|(_, (x, y))| {
            let (x, y) = (x.demultiply(), y.demultiply());
            [
                x.red().abs_diff(y.red()),
                x.green().abs_diff(y.green()),
                x.blue().abs_diff(y.blue()),
                x.alpha().abs_diff(y.alpha()),
            ]
            .iter()
            .any(|&d| d > threshold)
        })
        .map(|(i, _)| (i as u32 % w, i as u32 / w))
        .collect()
}

/// `svg` without its `<text …>…</text>` elements (none nested, none self-closing here).
fn without_text(svg: &str) -> String {
    let mut out = svg.to_string();
    while let Some(start) = out.find("<text") {
        let end = out[start..].find("</text>").expect("end tag") + start + "</text>".len();
        out.replace_range(start..end, "");
    }
    out
}

#[test]
fn png_renders_draw_the_fish_label_inside_its_plate() {
    let with = pixels("fish-with-text", FISH, FISH_SIZE);
    let without = pixels("fish-without-text", &without_text(FISH), FISH_SIZE);
    let ink = differing(&with, &without, 0);
    let outside: Vec<_> = ink
        .iter()
        .filter(|&&(x, y)| !PLATE.contains(Point::new(f64::from(x) + 0.5, f64::from(y) + 0.5)))
        .collect();
    let plate_pixels = PLATE.area();
    eprintln!(
        "label: {} pixels differ ({:.1} % of the plate), {} outside it",
        ink.len(),
        100.0 * ink.len() as f64 / plate_pixels,
        outside.len()
    );
    assert!(
        outside.is_empty(),
        "text drawn outside the plate: {outside:?}"
    );
    // Ten 18-unit glyphs cover about 9 % of the plate (measured); a dot or a missing label
    // would not reach 5 %.
    assert!(
        ink.len() as f64 > 0.05 * plate_pixels,
        "only {} text pixels",
        ink.len()
    );
    // Dark pixels (the label's colour #6b3414) inside the text's box, none before.
    let dark = |p: &tiny_skia::Pixmap| {
        p.pixels()
            .iter()
            .filter(|c| c.red() < 150 && c.green() < 100)
            .count()
    };
    let crop = |p: &tiny_skia::Pixmap| {
        let mut c = tiny_skia::Pixmap::new(150, 24).unwrap();
        c.draw_pixmap(
            -225,
            -360,
            p.as_ref(),
            &tiny_skia::PixmapPaint::default(),
            tiny_skia::Transform::identity(),
            None,
        );
        c
    };
    assert!(dark(&crop(&with)) > 200, "{}", dark(&crop(&with)));
    assert_eq!(dark(&crop(&without)), 0);
}

/// Imports `svg` with its text as outlines, writes it back at rest, and compares the render
/// with that of the original (module doc). Returns the imported drawing.
fn check_outlines_at_rest(name: &str, svg: &str, size: u32) -> Drawing {
    let options = ImportOptions::default().with_text(TextMode::Outlines);
    let drawing = read_svg(svg, &options).expect("read with outlines");
    let out = write_svg(&drawing, &drawing.flat_points()).expect("write");
    assert!(!out.contains("<text"), "{name}: text left in\n{out}");
    let original = pixels(&format!("{name}-text"), svg, size);
    let outlined = pixels(&format!("{name}-outlines"), &out, size);
    let bare = pixels(&format!("{name}-no-text"), &without_text(svg), size);
    let text_ink = differing(&original, &bare, 0).len();
    let diff = differing(&original, &outlined, ANTI_ALIASING).len();
    let n = f64::from(size * size);
    eprintln!(
        "{name}: {diff} pixels differ ({:.3} % of the picture, {:.2} % of the text's {text_ink})",
        100.0 * diff as f64 / n,
        100.0 * diff as f64 / text_ink as f64
    );
    assert!(text_ink > 100, "{name}: no text drawn ({text_ink} pixels)");
    assert!(
        diff as f64 <= MAX_DIFFERENT * n,
        "{name}: {diff} pixels differ"
    );
    assert!(
        diff as f64 <= MAX_INK_DIFFERENT * text_ink as f64,
        "{name}: {diff} of the text's {text_ink} pixels differ"
    );
    drawing
}

#[test]
fn fish_label_as_outlines_renders_like_the_text() {
    let drawing = check_outlines_at_rest("fish", FISH, FISH_SIZE);
    let source = drawing.source.as_ref().unwrap();
    let label: Vec<usize> = (0..drawing.paths.len())
        .filter(|&i| source.element_label(i) == "path#label (line 35)")
        .collect();
    // "splineskin": s p(2) l i(2) n e(2) s k i(2) n → 14 closed outlines.
    assert_eq!(label.len(), 14, "{label:?}");
    assert!(label.iter().all(|&i| drawing.paths[i].closed));
    // Written back as one path in place of the text, paint kept, layout attributes gone.
    let out = write_svg(&drawing, &drawing.flat_points()).unwrap();
    let line = out.lines().find(|l| l.contains("id=\"label\"")).unwrap();
    assert!(
        line.trim_start().starts_with("<path id=\"label\""),
        "{line}"
    );
    assert!(
        line.contains("fill=\"#6b3414\"") && line.contains("fill:#6b3414"),
        "{line}"
    );
    assert!(
        !line.contains(" x=") && !line.contains("font-size"),
        "{line}"
    );
}

/// Text in many settings: a transform, spans of three paints, a stroke drawn under the fill,
/// opacity, an underline, a `use` of a text, a text as a clip path, a hidden layer (checked as
/// written, hidden) and a CSS-styled text.
const MANY: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" viewBox="0 0 200 200" width="200" height="200">
  <style>.css { fill: #208040; font-weight: bold }</style>
  <defs>
    <text id="word" x="0" y="0" font-size="20" fill="purple">used</text>
    <clipPath id="clip"><text x="110" y="190" font-size="40" font-weight="bold">Clip</text></clipPath>
    <linearGradient id="grad" gradientUnits="userSpaceOnUse" x1="10" y1="0" x2="190" y2="0">
      <stop offset="0" stop-color="red"/><stop offset="1" stop-color="blue"/>
    </linearGradient>
  </defs>
  <rect x="0" y="0" width="200" height="200" fill="#f0f0f0"/>
  <text x="10" y="30" font-size="24" font-family="Helvetica, Arial, sans-serif">Plain <tspan fill="red">red</tspan> <tspan fill="blue" font-style="italic">blue</tspan></text>
  <text x="20" y="60" font-size="22" transform="rotate(12 20 60)" fill="url(#grad)" stroke="black" stroke-width="1.5" paint-order="stroke" text-decoration="underline">Turned</text>
  <g opacity="0.6"><text x="10" y="110" font-size="26" fill="orange" stroke="navy" stroke-width="0.8" stroke-dasharray="2 1">Faded</text></g>
  <use xlink:href="#word" x="120" y="110"/>
  <rect x="100" y="150" width="100" height="50" fill="teal" clip-path="url(#clip)"/>
  <text class="css" x="10" y="150" font-size="20" style="font-style: italic">Styled</text>
  <g display="none"><text x="10" y="180" font-size="20">Hidden</text></g>
</svg>"##;

#[test]
fn text_in_many_settings_as_outlines_renders_like_the_text() {
    let drawing = check_outlines_at_rest("many", MANY, 200);
    let out = write_svg(&drawing, &drawing.flat_points()).unwrap();
    // Spans of several paints: a group of paths; the clip text: one path in the clip path.
    assert!(
        out.contains("<g font-family") || out.contains("<g>"),
        "{out}"
    );
    assert!(out.contains("fill:url(#grad)"), "{out}");
    assert!(out.contains("paint-order:stroke"), "{out}");
    assert!(out.contains("stroke-dasharray:2 1"), "{out}");
    let clip = &out[out.find("<clipPath").unwrap()..out.find("</clipPath>").unwrap()];
    assert!(
        clip.contains("<path d=\"M") && !clip.contains("<g"),
        "{clip}"
    );
    // The hidden text is outlined too, and stays hidden.
    let hidden = &out[out.find("<g display=\"none\">").unwrap()..];
    assert!(
        hidden.starts_with("<g display=\"none\"><path d=\"M"),
        "{hidden}"
    );
    // Shown, the hidden outlines render like the hidden text shown.
    let show = |s: &str| s.replace("display=\"none\"", "");
    let a = pixels("many-hidden-text", &show(MANY), 200);
    let b = pixels("many-hidden-outlines", &show(&out), 200);
    let diff = differing(&a, &b, ANTI_ALIASING).len();
    assert!(diff as f64 <= MAX_DIFFERENT * 40_000.0, "{diff}");
}

/// The fish's scene with its text outlined: setup, rig and pose "swish".
fn fish_scene() -> (Scene, splineskin::scene::Setup, SplineRig) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/demo-scene.json");
    let mut scene = Scene::load(&path).expect("scene");
    scene.svg_text = text_to_outlines(&scene.svg_text, &scene.svg_origin).expect("outlines");
    let setup = scene.setup(Compat::None).expect("setup");
    let rig = SplineRig::precompute(&setup.drawing, &*setup.weights, &setup.options).expect("rig");
    (scene, setup, rig)
}

/// Largest distance between `a` and `b` over each path, relative to the path's rest diagonal.
fn worst_relative(drawing: &Drawing, a: &[Point], b: &[Point]) -> (f64, usize) {
    let mut offset = 0;
    let mut worst = (0.0, 0);
    for (i, path) in drawing.paths.iter().enumerate() {
        let n = path.points.len();
        let d = diagonal(&path.points);
        let e = (offset..offset + n)
            .map(|k| (a[k] - b[k]).hypot())
            .fold(0.0, f64::max)
            / d;
        if e > worst.0 {
            worst = (e, i);
        }
        offset += n;
    }
    worst
}

fn label_paths(drawing: &Drawing) -> Vec<usize> {
    let source = drawing.source.as_ref().unwrap();
    (0..drawing.paths.len())
        .filter(|&i| source.element_label(i).starts_with("path#label"))
        .collect()
}

#[test]
fn outlined_text_follows_the_fit_like_any_path() {
    let (scene, setup, rig) = fish_scene();
    let drawing = &setup.drawing;
    let label = label_paths(drawing);
    assert_eq!(label.len(), 14);
    let rest = drawing.flat_points();
    let n = scene.handles.len();
    let mut out = vec![Point::ZERO; rig.n_points()];

    rig.update(&vec![Affine::IDENTITY; n], &mut out).unwrap();
    let (e, i) = worst_relative(drawing, &rest, &out);
    eprintln!("identity: worst {e:.2e} of path {i}'s diagonal");
    assert!(
        e <= INVARIANT,
        "identity: path {i} moved {e:e} of its diagonal"
    );

    let rigid = Affine::translate(Vec2::new(40.0, -25.0))
        * Affine::rotate_about(0.5, Point::new(300.0, 200.0));
    rig.update(&vec![rigid; n], &mut out).unwrap();
    let mapped: Vec<Point> = rest.iter().map(|&p| rigid * p).collect();
    let (e, i) = worst_relative(drawing, &mapped, &out);
    eprintln!("rigid: worst {e:.2e} of path {i}'s diagonal");
    assert!(
        e <= INVARIANT,
        "rigid: path {i} off by {e:e} of its diagonal"
    );

    // A bend: the outlines follow the skinning map. Each label curve, sampled, against the
    // skinned rest curve at the same parameters: within 25 % of its path's diagonal plus 1 %
    // of the drawing's (the corpus criterion of the fit), and moved (the plate moves).
    let (_, swish) = scene.pose_by_key("swish").unwrap();
    rig.update(&swish.transforms, &mut out).unwrap();
    let mut w = vec![0.0; setup.weights.n_handles()];
    let field: &dyn WeightField = &*setup.weights;
    let drawing_diagonal = drawing.diagonal();
    let mut offset = 0;
    let (mut worst, mut worst_units, mut least_move) = (0.0f64, 0.0f64, f64::INFINITY);
    for (i, path) in drawing.paths.iter().enumerate() {
        let m = path.points.len();
        if label.contains(&i) {
            let d = diagonal(&path.points);
            for j in 0..path.n_curves() {
                let fitted = kurbo::CubicBez::new(
                    out[offset + 3 * j],
                    out[offset + 3 * j + 1],
                    out[offset + 3 * j + 2],
                    out[offset + 3 * j + 3],
                );
                let rest_curve = path.curve(j);
                for s in 0..=8 {
                    let t = f64::from(s) / 8.0;
                    let target = skin_point(field, &swish.transforms, rest_curve.eval(t), &mut w);
                    let miss = (fitted.eval(t) - target).hypot();
                    worst = worst.max(miss / (0.25 * d + 0.01 * drawing_diagonal));
                    worst_units = worst_units.max(miss);
                    least_move = least_move.min((fitted.eval(t) - rest_curve.eval(t)).hypot());
                }
            }
        }
        offset += m;
    }
    eprintln!(
        "swish: worst label miss {worst_units:.3} units ({worst:.3} of the allowance); \
         least move {least_move:.2} units"
    );
    assert!(worst <= 1.0, "a label curve misses its skinned target");
    assert!(least_move > 1.0, "the label did not move with the plate");
    if std::env::var("TEXT_TEST_OUT").is_ok() {
        let svg = write_svg(drawing, &out).unwrap();
        pixels("fish-swish-outlines", &svg, FISH_SIZE);
    }
}
