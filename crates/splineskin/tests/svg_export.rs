//! SVG export: round trips through import, preservation of everything that is not geometry,
//! deformed geometry landing in each element's own coordinates, and errors.

use kurbo::{Affine, Point, Vec2};
use splineskin::drawing::svg_in::{read_svg, read_svg_file, ImportOptions, SvgError};
use splineskin::drawing::svg_out::write_svg;
use splineskin::drawing::Drawing;

/// Round-trip tolerance relative to the drawing's diagonal: export writes shortest round-trip
/// `f64`s in each element's local coordinates and import reads them back through the same
/// transforms, so only a few `f64` roundings (≈ 1e-16 relative each) separate the two.
const ROUND_TRIP_RELATIVE: f64 = 1e-9;

/// Tolerance on coordinates after a deformation, relative to the diagonal: re-import reads the
/// written numbers as `f32` (usvg), ≈ 6e-8 relative to coordinates of the order of the
/// diagonal, composed with `f32` transforms.
const F32_RELATIVE: f64 = 1e-6;

const FIXTURES: [&str; 7] = [
    "nested_transforms.svg",
    "viewbox_aspect.svg",
    "shapes.svg",
    "commands.svg",
    "use.svg",
    "styled.svg",
    "degenerate.svg",
];

fn fixture_path(name: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/svg")
        .join(name)
}

fn fixture(name: &str) -> (String, Drawing) {
    let path = fixture_path(name);
    let text = std::fs::read_to_string(&path).unwrap();
    let drawing =
        read_svg_file(&path, &ImportOptions::default()).unwrap_or_else(|e| panic!("{name}: {e}"));
    (text, drawing)
}

fn reimport(text: &str, name: &str) -> Drawing {
    read_svg(text, &ImportOptions::default())
        .unwrap_or_else(|e| panic!("{name}: exported text does not import: {e}\n{text}"))
}

/// Same paths, closedness, curve counts, and points within `tol`.
fn assert_same_chains(
    expected: &[Vec<Point>],
    expected_closed: &[bool],
    got: &Drawing,
    tol: f64,
    what: &str,
) {
    assert_eq!(got.paths.len(), expected.len(), "{what}: number of paths");
    for (i, (path, (want, closed))) in got
        .paths
        .iter()
        .zip(expected.iter().zip(expected_closed))
        .enumerate()
    {
        assert_eq!(path.closed, *closed, "{what}: path {i} closedness");
        assert_eq!(
            path.points.len(),
            want.len(),
            "{what}: path {i} curve count"
        );
        for (k, (a, b)) in path.points.iter().zip(want).enumerate() {
            assert!(
                (*a - *b).hypot() <= tol,
                "{what}: path {i} point {k}: {a:?} vs {b:?}"
            );
        }
    }
}

fn chains(d: &Drawing) -> (Vec<Vec<Point>>, Vec<bool>) {
    (
        d.paths.iter().map(|p| p.points.clone()).collect(),
        d.paths.iter().map(|p| p.closed).collect(),
    )
}

#[test]
fn svg_export_round_trip_of_every_fixture() {
    for name in FIXTURES {
        let (_, drawing) = fixture(name);
        let out = write_svg(&drawing, &drawing.flat_points()).unwrap();
        let again = reimport(&out, name);
        let (points, closed) = chains(&drawing);
        let tol = ROUND_TRIP_RELATIVE * drawing.diagonal();
        assert_same_chains(&points, &closed, &again, tol, name);
        // Joint kinds are re-derived from the same points.
        for (a, b) in drawing.paths.iter().zip(&again.paths) {
            assert_eq!(a.joints, b.joints, "{name}");
        }
        // A second round trip stays as close (errors do not accumulate beyond f64 noise).
        let out2 = write_svg(&again, &again.flat_points()).unwrap();
        assert_same_chains(&points, &closed, &reimport(&out2, name), tol, name);
    }
}

/// The document as a list of nodes, geometry removed: element names (geometry tags as
/// `path`) with their attributes minus geometric ones (and minus the `style="fill:none"`
/// export adds to an element whose fill has no area at rest), text, comments and PIs.
fn without_geometry(text: &str) -> Vec<String> {
    const GEOMETRY_TAGS: [&str; 7] = [
        "path", "rect", "circle", "ellipse", "line", "polyline", "polygon",
    ];
    const GEOMETRY_ATTRIBUTES: [&str; 15] = [
        "d", "x", "y", "width", "height", "rx", "ry", "cx", "cy", "r", "x1", "y1", "x2", "y2",
        "points",
    ];
    let doc = roxmltree::Document::parse_with_options(
        text,
        roxmltree::ParsingOptions {
            allow_dtd: true,
            ..Default::default()
        },
    )
    .unwrap();
    doc.descendants()
        .map(|n| match n.node_type() {
            roxmltree::NodeType::Element => {
                let tag = n.tag_name().name();
                let geometry = GEOMETRY_TAGS.contains(&tag);
                let mut attrs: Vec<String> = n
                    .attributes()
                    .filter(|a| {
                        !(geometry
                            && a.namespace().is_none()
                            && (GEOMETRY_ATTRIBUTES.contains(&a.name())
                                || (a.name() == "style" && a.value() == "fill:none")))
                    })
                    .map(|a| format!("{:?}:{}={:?}", a.namespace(), a.name(), a.value()))
                    .collect();
                attrs.sort();
                let tag = if geometry { "path" } else { tag };
                format!("<{:?}:{tag} {}>", n.tag_name().namespace(), attrs.join(" "))
            }
            roxmltree::NodeType::Text => format!("text {:?}", n.text()),
            roxmltree::NodeType::Comment => format!("comment {:?}", n.text()),
            roxmltree::NodeType::PI => format!("pi {:?}", n.pi()),
            roxmltree::NodeType::Root => "root".to_string(),
        })
        .collect()
}

#[test]
fn svg_export_keeps_every_non_geometry_node_and_attribute() {
    for name in FIXTURES.iter().filter(|&&n| n != "use.svg") {
        let (text, drawing) = fixture(name);
        let moved: Vec<Point> = drawing
            .flat_points()
            .iter()
            .map(|&p| p + Vec2::new(3.0, -2.0))
            .collect();
        let out = write_svg(&drawing, &moved).unwrap();
        assert_eq!(without_geometry(&text), without_geometry(&out), "{name}");
    }
}

#[test]
fn svg_export_keeps_styles_gradients_and_text_verbatim() {
    let (text, drawing) = fixture("styled.svg");
    let moved: Vec<Point> = drawing
        .flat_points()
        .iter()
        .map(|&p| p + Vec2::new(1.0, 1.0))
        .collect();
    let out = write_svg(&drawing, &moved).unwrap();
    let between = |s: &str, from: &str, to: &str| -> String {
        let a = s.find(from).unwrap();
        let b = a + s[a..].find(to).unwrap() + to.len();
        s[a..b].to_string()
    };
    // Prolog, style sheet, gradients and text: byte for byte.
    assert_eq!(
        between(&text, "<?xml", "<svg"),
        between(&out, "<?xml", "<svg")
    );
    for (from, to) in [
        ("<svg", ">"),
        ("<style", "</style>"),
        ("<defs>", "</defs>"),
        ("<text", "</text>"),
        ("<!-- the hill", "-->"),
    ] {
        assert_eq!(between(&text, from, to), between(&out, from, to), "{from}");
    }
    // Shapes became paths keeping their other attributes in place.
    assert!(
        out.contains(r##"<path id="background" fill="url(#sky)" d="M1 1 C"##),
        "{out}"
    );
    assert!(
        out.contains(r#"<path class="outline" id="sun" style="fill:url(#sun)" d="M101 21 C"#),
        "{out}"
    );
    assert!(out.contains(r#"data-note="keep &amp; me"/>"#));
    assert!(!out.contains("<rect") && !out.contains("<circle"));
}

#[test]
fn svg_export_use_becomes_group_with_deformed_copy() {
    let (text, drawing) = fixture("use.svg");
    let shift = Vec2::new(0.5, 0.25);
    let moved: Vec<Point> = drawing.flat_points().iter().map(|&p| p + shift).collect();
    let out = write_svg(&drawing, &moved).unwrap();
    // The use elements that were instantiated are gone, replaced by groups carrying their
    // attributes and transform.
    assert!(!out.contains("<use id=\"u"), "{out}");
    assert!(
        out.contains(r#"<g id="u1" fill="red" transform="translate(10 20)">"#),
        "{out}"
    );
    assert!(
        out.contains(r#"<g id="u2" transform="rotate(45 100 100) translate(100 100)">"#),
        "{out}"
    );
    assert!(
        out.contains(r#"<g id="u3" opacity="0.5" transform="translate(50 150)">"#),
        "{out}"
    );
    assert!(
        out.contains(r#"<g id="u4" transform="translate(150 10) matrix(2 0 0 4 0 0)">"#),
        "{out}"
    );
    // Inside the copies, ids are removed (only the originals in <defs> keep theirs) and the
    // nested use became a group too.
    assert_eq!(out.matches("id=\"leaf\"").count(), 1);
    assert_eq!(out.matches("id=\"pair\"").count(), 1);
    assert!(
        out.contains(r#"<g class="inner" transform="translate(12 0)">"#),
        "{out}"
    );
    // The defs are untouched.
    let defs = |s: &str| s[s.find("<defs>").unwrap()..s.find("</defs>").unwrap()].to_string();
    assert_eq!(defs(&text), defs(&out));
    // Re-import: every instance moved by `shift`.
    let again = reimport(&out, "use.svg");
    let (points, closed) = chains(&drawing);
    let shifted: Vec<Vec<Point>> = points
        .iter()
        .map(|c| c.iter().map(|&p| p + shift).collect())
        .collect();
    assert_same_chains(
        &shifted,
        &closed,
        &again,
        F32_RELATIVE * drawing.diagonal(),
        "use.svg",
    );
}

#[test]
fn svg_export_deformation_lands_in_local_coordinates() {
    // A rotation of all points about the drawing's centre: whatever transforms sit between the
    // root and each element, re-importing the export gives the rotated points.
    for name in FIXTURES {
        let (_, drawing) = fixture(name);
        let centre = drawing.control_bounds().unwrap().center();
        let motion = Affine::rotate_about(0.3, centre) * Affine::scale(1.1);
        let moved: Vec<Point> = drawing.flat_points().iter().map(|&p| motion * p).collect();
        let out = write_svg(&drawing, &moved).unwrap();
        let again = reimport(&out, name);
        let expected: Vec<Vec<Point>> = drawing
            .paths
            .iter()
            .map(|p| p.points.iter().map(|&q| motion * q).collect())
            .collect();
        let closed: Vec<bool> = drawing.paths.iter().map(|p| p.closed).collect();
        let tol = F32_RELATIVE * 1.1 * (drawing.diagonal() + centre.to_vec2().hypot());
        assert_same_chains(&expected, &closed, &again, tol, name);
    }
}

#[test]
fn svg_export_output_renders() {
    let (_, drawing) = fixture("shapes.svg");
    let out = write_svg(&drawing, &drawing.flat_points()).unwrap();
    let png = splineskin::render::render_png(&out, 100).unwrap();
    let pixmap = resvg::tiny_skia::Pixmap::decode_png(&png).unwrap();
    assert_eq!((pixmap.width(), pixmap.height()), (100, 100));
    // The orange rect at (10..50, 10..30) of a 200-unit viewBox: pixel (15, 10).
    let p = pixmap.pixel(15, 10).unwrap();
    assert_eq!((p.red(), p.green(), p.blue()), (255, 165, 0));
}

#[test]
fn svg_export_errors() {
    let (_, drawing) = fixture("shapes.svg");
    let mut points = drawing.flat_points();
    match write_svg(&drawing, &points[1..]) {
        Err(SvgError::PointCount {
            expected,
            found,
            file,
        }) => {
            assert_eq!((expected, found), (points.len(), points.len() - 1));
            assert!(file.ends_with("shapes.svg"));
        }
        other => panic!("{other:?}"),
    }
    points[5].x = f64::INFINITY;
    match write_svg(&drawing, &points) {
        Err(SvgError::NonFinitePoint { element, index, .. }) => {
            assert_eq!(index, 5);
            assert_eq!(element, "rect#plain (line 2)");
        }
        other => panic!("{other:?}"),
    }
    let mut fewer = drawing.clone();
    fewer.paths.pop();
    let n = fewer.n_points();
    assert!(matches!(
        write_svg(&fewer, &drawing.flat_points()[..n]),
        Err(SvgError::SourceMismatch { .. })
    ));
}

#[test]
fn svg_export_expands_a_use_of_an_svg_element() {
    // The use's x/y translate the copy; its width/height size the nested viewport, whose
    // viewBox maps 0..10 onto it (SVG 2, §5.6.1).
    let text = "<svg xmlns='http://www.w3.org/2000/svg' viewBox='0 0 100 100'>\
                <defs><svg id='inner' viewBox='0 0 10 10' width='50' height='50'>\
                <path d='M0 0 L10 10'/></svg></defs>\
                <use href='#inner' x='20' y='30' width='20' height='20'/><path d='M0 0 L2 2'/></svg>";
    let drawing = read_svg(text, &ImportOptions::default()).unwrap();
    assert_eq!(drawing.paths.len(), 2);
    let ends = |i: usize| {
        let p = &drawing.paths[i].points;
        (p[0], p[p.len() - 1])
    };
    let (a, b) = ends(0);
    assert!((a - Point::new(20.0, 30.0)).hypot() < 1e-9, "{a:?}");
    assert!((b - Point::new(40.0, 50.0)).hypot() < 1e-9, "{b:?}");
    let moved: Vec<Point> = drawing
        .flat_points()
        .iter()
        .map(|&p| p + Vec2::new(3.0, -1.0))
        .collect();
    let out = write_svg(&drawing, &moved).unwrap();
    let again = reimport(&out, "use-of-svg");
    for (p, q) in again.flat_points().iter().zip(&moved) {
        assert!((*p - *q).hypot() < 1e-4, "{p:?} vs {q:?}\n{out}");
    }
}

#[test]
fn svg_export_keeps_namespace_prefixes() {
    let text = "<s:svg xmlns:s='http://www.w3.org/2000/svg' viewBox='0 0 9 9'>\
                <s:rect id='r' width='2' height='1'></s:rect><s:path d='M0 0 L1 1'/></s:svg>";
    let drawing = read_svg(text, &ImportOptions::default()).unwrap();
    let out = write_svg(&drawing, &drawing.flat_points()).unwrap();
    assert!(out.starts_with("<s:svg xmlns:s='http://www.w3.org/2000/svg' viewBox='0 0 9 9'><s:path id='r' d=\"M0 0 C"), "{out}");
    assert!(out.contains("Z\"></s:path><s:path d='M0 0 C"), "{out}");
    let again = reimport(&out, "prefixed");
    assert_eq!(again.n_curves(), drawing.n_curves());
}

/// `ViewBoxRule`: `Fit` is `FitTo` the art's bounds ([`art_bounds`], exact curve bounds: a
/// circle's are its centre ± r, not its control points'), hidden art counts, clip geometry
/// does not, `FitTo` takes a union given from outside (an animation's), and a non-finite one is
/// refused naming it.
#[test]
fn svg_export_view_box_fit_is_the_union_with_the_art() {
    use splineskin::drawing::svg_out::{art_bounds, write_svg_view_box, ViewBoxRule};
    let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10">
  <clipPath id="c"><rect x="-50" y="-50" width="200" height="200"/></clipPath>
  <circle cx="5" cy="5" r="2" clip-path="url(#c)"/>
  <rect x="1" y="1" width="1" height="1" display="none"/>
</svg>"#;
    let drawing = read_svg(svg, &ImportOptions::default()).unwrap();
    // Everything moves by (9, -4): the circle spans x 12 … 16, y -1 … 3; the hidden square
    // x 10 … 11, y -3 … -2; the clip rectangle (not art) x 49 … 249.
    let moved: Vec<Point> = drawing
        .flat_points()
        .iter()
        .map(|&p| p + Vec2::new(9.0, -4.0))
        .collect();
    let r = art_bounds(&drawing, &moved).unwrap().unwrap();
    let expected = [10.0, -3.0, 16.0, 3.0];
    for (found, want) in [r.x0, r.y0, r.x1, r.y1].into_iter().zip(expected) {
        assert!((found - want).abs() < 1e-12, "{r:?}");
    }
    let fit = write_svg_view_box(&drawing, &moved, ViewBoxRule::Fit).unwrap();
    assert_eq!(
        fit,
        write_svg_view_box(&drawing, &moved, ViewBoxRule::FitTo(r)).unwrap()
    );
    let view_box = |text: &str| {
        let at = text.find("viewBox=\"").unwrap() + 9;
        text[at..at + text[at..].find('"').unwrap()]
            .split(' ')
            .map(|v| v.parse::<f64>().unwrap())
            .collect::<Vec<_>>()
    };
    // x 0 … 16, y -3 … 10.
    let found = view_box(&fit);
    for (f, w) in found.iter().zip([0.0, -3.0, 16.0, 13.0]) {
        assert!((f - w).abs() < 1e-12, "{found:?}");
    }
    // A union from outside: the rest points, fitted to a larger box, write that box.
    let rest = drawing.flat_points();
    let wide = kurbo::Rect::new(-20.0, 0.0, 10.0, 40.0);
    let text = write_svg_view_box(&drawing, &rest, ViewBoxRule::FitTo(wide)).unwrap();
    assert_eq!(view_box(&text), [-20.0, 0.0, 30.0, 40.0]);
    // Inside the viewBox: the document is written as `Keep` writes it.
    let inside = kurbo::Rect::new(1.0, 1.0, 2.0, 2.0);
    assert_eq!(
        write_svg_view_box(&drawing, &rest, ViewBoxRule::FitTo(inside)).unwrap(),
        write_svg(&drawing, &rest).unwrap()
    );
    let nan = kurbo::Rect::new(0.0, 0.0, f64::NAN, 1.0);
    let err = write_svg_view_box(&drawing, &rest, ViewBoxRule::FitTo(nan)).unwrap_err();
    assert!(
        matches!(err, SvgError::NonFinitePoint { index: 1, .. }),
        "{err}"
    );
    assert!(err.to_string().contains("viewBox to fit"), "{err}");
}
