//! `splineskin animate -o NAME.svg` carries what is not a curve through the animation, as the
//! frames folder does frame by frame: the text's `transform`, the `gradientTransform` and
//! `patternTransform` of the user-space paint servers' copies, and a fixed-orientation
//! marker's `orient` are animated, and at every frame their animated values (the
//! `animateTransform` parts recomposed `T·R·SkewX·S`) equal what the frames folder's file of
//! that frame holds (the best-fit affine maps of that frame's pose) to [`RELATIVE`].
//!
//! Pixels: resvg plays no SMIL, so the animated document is frozen at frame `k` (each
//! animation removed and its `k`-th value written into the attribute it animates) and
//! rendered; it must match the PNG of frame `k` from the frames folder: at most
//! [`MAX_DIFFERENT`] of the pixels differ by more than [`ANTI_ALIASING`]. Frozen with the paths
//! alone (text and paint left at the first frame, as before they were animated), it must not.
//! Set `ANIMATE_TEST_OUT=DIR` to keep the pictures.

mod common;

use std::path::Path;

use common::test_dir::TestDir;
use kurbo::Affine;
use splineskin::weight_map::RgbaImage;

/// Our drawing: a plate filled with a user-space gradient and outlined, a label, a band filled
/// with a pattern that inherits its tiles from a template (so its copy has no children), and a
/// stroke with a fixed-orientation marker.
const SVG: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 200 120" width="400" height="240">
  <defs>
    <linearGradient id="grad" gradientUnits="userSpaceOnUse" x1="20" y1="0" x2="180" y2="0">
      <stop offset="0" stop-color="#c33"/><stop offset="0.5" stop-color="#fd4"/>
      <stop offset="1" stop-color="#36c"/>
    </linearGradient>
    <pattern id="tiles" patternUnits="userSpaceOnUse" width="8" height="8">
      <rect width="4" height="8" fill="#285"/>
    </pattern>
    <pattern id="stripes" href="#tiles" patternTransform="rotate(20)"/>
    <marker id="arrow" orient="30" markerWidth="12" markerHeight="12" refX="0" refY="3"
            markerUnits="userSpaceOnUse">
      <path d="M0 0 L10 3 L0 6 Z" fill="#80c"/>
    </marker>
  </defs>
  <rect id="plate" x="20" y="30" width="160" height="50" fill="url(#grad)" stroke="black"/>
  <text id="label" x="45" y="62" font-size="22" fill="black">Splines</text>
  <rect id="band" x="30" y="86" width="140" height="14" fill="url(#stripes)"/>
  <path id="wire" d="M40 18 C70 8 130 8 160 18" fill="none" stroke="#444" marker-end="url(#arrow)"/>
</svg>"##;

/// The animation: pins at both ends of the plate, both turned by 200° and moved where a turn
/// of the whole drawing by 200° about its middle (100, 55) takes them, then back (rest, pose,
/// rest over 2 s at 5 fps: 11 frames). The pose is rigid; the frames between are not (each
/// pin's move is interpolated along a line, its turn by angle), and the label's angle crosses
/// ±180°, so it must be unwrapped. `--viewbox fit` keeps the turned art in the pictures.
const ARGS: &[&str] = &[
    "drawing.svg",
    "--pin",
    "30,55",
    "--pin",
    "170,55",
    "--weights",
    "shepard",
    "--rotate",
    "0:200",
    "--rotate",
    "1:200",
    "--move",
    "0:135.778,23.941",
    "--move",
    "1:-135.778,-23.941",
    "--fps",
    "5",
    "--viewbox",
    "fit",
];

/// The written animated values and the frames' maps agree to 1e-9 relative (numbers are
/// written in their shortest round-trip form; only the decomposition's rounding remains).
const RELATIVE: f64 = 1e-9;

/// Largest channel difference (of 255) still counted as anti-aliasing.
const ANTI_ALIASING: u8 = 48;

/// Largest fraction of pixels allowed to differ beyond [`ANTI_ALIASING`]: 0.5 %.
const MAX_DIFFERENT: f64 = 0.005;

/// Size of the drawing (its viewBox diagonal), the scale of translations.
const DIAGONAL: f64 = 233.2380757938;

fn animate(dir: &Path, output: &str, extra: &[&str]) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_splineskin"))
        .current_dir(dir)
        .arg("animate")
        .args(ARGS)
        .args(["-o", output])
        .args(extra)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn parse(text: &str) -> roxmltree::Document<'_> {
    roxmltree::Document::parse(text).unwrap_or_else(|e| panic!("{e}"))
}

fn by_id<'a, 'i>(doc: &'a roxmltree::Document<'i>, id: &str) -> roxmltree::Node<'a, 'i> {
    doc.descendants()
        .find(|n| n.attribute("id") == Some(id))
        .unwrap_or_else(|| panic!("no element #{id}"))
}

fn numbers(text: &str) -> Vec<f64> {
    text.split([' ', ',', '(', ')'])
        .filter(|s| !s.is_empty() && *s != "matrix")
        .map(|s| s.parse().unwrap_or_else(|e| panic!("{s}: {e}")))
        .collect()
}

/// `matrix(a b c d e f)`, the only form the writer gives these attributes.
fn matrix(text: &str) -> Affine {
    assert!(text.starts_with("matrix("), "{text}");
    let n = numbers(text);
    assert_eq!(n.len(), 6, "{text}");
    Affine::new([n[0], n[1], n[2], n[3], n[4], n[5]])
}

/// The element a paint or marker property of `node` names in its inline style.
fn style_url<'a, 'i>(
    doc: &'a roxmltree::Document<'i>,
    node: roxmltree::Node<'a, 'i>,
    property: &str,
) -> roxmltree::Node<'a, 'i> {
    let style = node.attribute("style").unwrap_or("");
    let value = style
        .split(';')
        .find_map(|d| d.split_once(':').filter(|(k, _)| k.trim() == property))
        .unwrap_or_else(|| panic!("no {property} in style {style:?}"))
        .1;
    let id = value
        .trim()
        .strip_prefix("url(#")
        .unwrap()
        .trim_end_matches(')');
    by_id(doc, id)
}

/// The animation elements of `doc` that animate `target`'s attribute `attribute`: children
/// without `href`, or elements naming it by `href`, in document order.
fn animations<'a, 'i>(
    doc: &'a roxmltree::Document<'i>,
    target: roxmltree::Node<'a, 'i>,
    attribute: &str,
) -> Vec<roxmltree::Node<'a, 'i>> {
    let id = target.attribute("id");
    doc.descendants()
        .filter(|n| matches!(n.tag_name().name(), "animate" | "animateTransform"))
        .filter(|n| n.attribute("attributeName") == Some(attribute))
        .filter(|n| match n.attribute("href") {
            Some(h) => id.is_some() && h.strip_prefix('#') == id,
            None => n.parent_element() == Some(target),
        })
        .collect()
}

/// The `k`-th of the `values` of `animation`.
fn value_at<'a>(animation: roxmltree::Node<'a, '_>, k: usize) -> &'a str {
    animation
        .attribute("values")
        .unwrap()
        .split(';')
        .nth(k)
        .unwrap_or_else(|| panic!("no value {k}"))
}

/// The map the `animateTransform`s of `target`'s `attribute` give at frame `k`: each part
/// recomposed (translate replacing, the others summed onto the right, as SMIL does).
fn animated_map(
    doc: &roxmltree::Document,
    target: roxmltree::Node,
    attribute: &str,
    k: usize,
) -> Affine {
    let list = animations(doc, target, attribute);
    let kinds: Vec<&str> = list.iter().map(|a| a.attribute("type").unwrap()).collect();
    assert_eq!(
        kinds,
        ["translate", "rotate", "skewX", "scale"],
        "{attribute}"
    );
    let mut map = Affine::IDENTITY;
    for a in list {
        let n = numbers(value_at(a, k));
        let part = match a.attribute("type").unwrap() {
            "translate" => Affine::translate((n[0], n.get(1).copied().unwrap_or(0.0))),
            "rotate" => Affine::rotate(n[0].to_radians()),
            "skewX" => Affine::skew(n[0].to_radians().tan(), 0.0),
            _ => Affine::scale_non_uniform(n[0], n.get(1).copied().unwrap_or(n[0])),
        };
        map = match a.attribute("additive") {
            Some("sum") => map * part,
            _ => part,
        };
    }
    map
}

/// Largest difference of two maps relative to their size: linear parts against the larger
/// linear coefficient, translations against that times the drawing's size plus the larger
/// translation.
fn relative_difference(a: Affine, b: Affine) -> f64 {
    let (ca, cb) = (a.as_coeffs(), b.as_coeffs());
    let lin = cb[..4].iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let tr = cb[4].abs().max(cb[5].abs());
    let d: Vec<f64> = (0..6).map(|k| (ca[k] - cb[k]).abs()).collect();
    let dl = d[..4].iter().fold(0.0f64, |m, v| m.max(*v)) / lin;
    let dt = d[4].max(d[5]) / (lin * DIAGONAL + tr);
    dl.max(dt)
}

/// `animated` frozen at frame `k`: every animation removed, and (all of them, or only the
/// paths' `d` when `paths_only`) its `k`-th value written into the attribute it animates.
fn freeze(animated: &str, k: usize, paths_only: bool) -> String {
    let doc = parse(animated);
    let mut edits: Vec<(usize, usize, String)> = Vec::new();
    let mut done: Vec<(roxmltree::NodeId, String)> = Vec::new();
    for a in doc.descendants() {
        let kind = a.tag_name().name();
        if !matches!(kind, "animate" | "animateTransform") {
            continue;
        }
        edits.push((a.range().start, a.range().end, String::new()));
        let target = match a.attribute("href") {
            Some(h) => by_id(&doc, h.strip_prefix('#').unwrap()),
            None => a.parent_element().unwrap(),
        };
        let attribute = a.attribute("attributeName").unwrap();
        if (paths_only && attribute != "d") || done.contains(&(target.id(), attribute.into())) {
            continue;
        }
        done.push((target.id(), attribute.to_string()));
        let value = match kind {
            "animate" => value_at(a, k).to_string(),
            _ => {
                let c = animated_map(&doc, target, attribute, k).as_coeffs();
                format!(
                    "matrix({} {} {} {} {} {})",
                    c[0], c[1], c[2], c[3], c[4], c[5]
                )
            }
        };
        let at = target
            .attributes()
            .find(|x| x.name() == attribute)
            .unwrap_or_else(|| panic!("the animated {attribute} has a value at rest"))
            .range_value();
        edits.push((at.start, at.end, value));
    }
    edits.sort_by_key(|e| std::cmp::Reverse(e.0));
    let mut out = animated.to_string();
    for (from, to, text) in edits {
        out.replace_range(from..to, &text);
    }
    out
}

/// The fraction of pixels differing by more than [`ANTI_ALIASING`] in some channel.
fn different(a: &RgbaImage, b: &RgbaImage) -> f64 {
    assert_eq!((a.width, a.height), (b.width, b.height));
    let n = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .filter(|(p, q)| {
            p.iter()
                .zip(q.iter())
                .any(|(x, y)| x.abs_diff(*y) > ANTI_ALIASING)
        })
        .count();
    n as f64 / a.pixels.len() as f64
}

#[test]
fn animated_svg_carries_text_paint_and_markers_as_the_frames_do() {
    let dir = TestDir::new("splineskin-animate-follows-");
    std::fs::write(dir.join("drawing.svg"), SVG).unwrap();
    animate(&dir, "anim.svg", &[]);
    animate(&dir, "frames", &["--png"]);
    let animated = std::fs::read_to_string(dir.join("anim.svg")).unwrap();
    let doc = parse(&animated);
    let n_frames = 11;
    let label = by_id(&doc, "label");
    let plate_paint = style_url(&doc, by_id(&doc, "plate"), "fill");
    let band_paint = style_url(&doc, by_id(&doc, "band"), "fill");
    let marker = style_url(&doc, by_id(&doc, "wire"), "marker-end");
    // The pattern copy inherits its tiles: it stays childless, its animation names it.
    assert!(!band_paint.children().any(|c| c.is_element()));
    let orient = animations(&doc, marker, "orient");
    assert_eq!(orient.len(), 1);
    // The label's angle in every frame, unwrapped: it turns past 180° and back without a jump.
    let rotate = animations(&doc, label, "transform")[1];
    let angles: Vec<f64> = (0..n_frames)
        .map(|k| numbers(value_at(rotate, k))[0])
        .collect();
    assert!(angles.iter().any(|a| a.abs() > 180.0), "{angles:?}");
    assert!(
        angles.windows(2).all(|w| (w[1] - w[0]).abs() < 90.0),
        "{angles:?}"
    );

    let mut worst = 0.0f64;
    for k in 0..n_frames {
        let frame_text =
            std::fs::read_to_string(dir.join(format!("frames/frame-{k:04}.svg"))).unwrap();
        let frame = parse(&frame_text);
        let pairs = [
            (
                animated_map(&doc, label, "transform", k),
                matrix(by_id(&frame, "label").attribute("transform").unwrap()),
            ),
            (
                animated_map(&doc, plate_paint, "gradientTransform", k),
                matrix(
                    style_url(&frame, by_id(&frame, "plate"), "fill")
                        .attribute("gradientTransform")
                        .unwrap(),
                ),
            ),
            (
                animated_map(&doc, band_paint, "patternTransform", k),
                matrix(
                    style_url(&frame, by_id(&frame, "band"), "fill")
                        .attribute("patternTransform")
                        .unwrap(),
                ),
            ),
        ];
        for (i, (a, b)) in pairs.iter().enumerate() {
            let d = relative_difference(*a, *b);
            assert!(d <= RELATIVE, "frame {k}, map {i}: {a:?} vs {b:?} ({d:e})");
            worst = worst.max(d);
        }
        // At rest (first and last frames) every map is the identity: look at the turned ones.
        let orient_k: f64 = value_at(orient[0], k).parse().unwrap();
        // A frame turned by less than the writer's smallest turn keeps the original marker.
        let wire = by_id(&frame, "wire");
        let expected: f64 = match wire.attribute("style").unwrap_or("").contains("marker-end") {
            true => style_url(&frame, wire, "marker-end")
                .attribute("orient")
                .unwrap(),
            false => "30",
        }
        .parse()
        .unwrap();
        let turn = (orient_k - expected).rem_euclid(360.0);
        assert!(
            turn.min(360.0 - turn) < 1e-9,
            "frame {k}: orient {orient_k} vs {expected}"
        );
    }
    eprintln!("largest relative difference of animated and frame maps: {worst:e}");

    // Pixels, in the frames turned most and an intermediate one.
    let keep = std::env::var_os("ANIMATE_TEST_OUT").map(std::path::PathBuf::from);
    for k in [2, 5] {
        let expected = RgbaImage::decode_png(
            &std::fs::read(dir.join(format!("frames/frame-{k:04}.png"))).unwrap(),
        )
        .unwrap();
        let size = expected.width.max(expected.height);
        let frozen = freeze(&animated, k, false);
        let paths_only = freeze(&animated, k, true);
        let render = |svg: &str| {
            RgbaImage::decode_png(&splineskin::render::render_png(svg, size).unwrap()).unwrap()
        };
        let (shown, stale) = (render(&frozen), render(&paths_only));
        if let Some(out) = &keep {
            std::fs::create_dir_all(out).unwrap();
            std::fs::write(out.join(format!("frozen-{k}.svg")), &frozen).unwrap();
            std::fs::write(
                out.join(format!("frozen-{k}.png")),
                splineskin::render::render_png(&frozen, size).unwrap(),
            )
            .unwrap();
            std::fs::copy(
                dir.join(format!("frames/frame-{k:04}.png")),
                out.join(format!("frame-{k}.png")),
            )
            .unwrap();
            std::fs::write(
                out.join(format!("paths-only-{k}.png")),
                splineskin::render::render_png(&paths_only, size).unwrap(),
            )
            .unwrap();
        }
        let (good, bad) = (different(&shown, &expected), different(&stale, &expected));
        eprintln!(
            "frame {k}: {:.3} % of pixels differ (paths only: {:.2} %)",
            good * 100.0,
            bad * 100.0
        );
        assert!(good <= MAX_DIFFERENT, "frame {k}: {good}");
        assert!(
            bad > 4.0 * MAX_DIFFERENT,
            "frame {k}: paths alone differ by only {bad}"
        );
    }
}
