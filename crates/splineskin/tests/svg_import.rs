//! SVG import: coordinates, shapes, commands, `use`, degenerate input and errors, on the
//! fixtures in `tests/fixtures/svg/` and inline documents.

mod common;

use common::test_dir::TestDir;
use kurbo::{Affine, CubicBez, ParamCurve, Point, Rect, Size};
use splineskin::drawing::svg_in::{read_svg, read_svg_file, ImportOptions, SvgError};
use splineskin::drawing::{Drawing, JointKind};

/// Tolerance on coordinates that went through usvg's `f32` transforms, relative to the size of
/// the fixtures (≈ 200 units): a few f32 ulps (6e-8 each) of coordinates and transform
/// coefficients composed over up to four levels stay below 1e-6 of 200.
const F32_TOLERANCE: f64 = 200.0 * 1e-6;

/// Radial error bound of kurbo's arc approximation (≤ 90° per cubic, arms 4/3·tan(θ/4)):
/// 2.73e-4 of the radius, the classic quarter-circle figure (0.0273 %).
const ARC_RELATIVE_ERROR: f64 = 2.73e-4;

/// Slack for usvg's `f32` storage of arc points, relative to the radius.
const F32_RELATIVE: f64 = 1e-6;

/// Tolerance of results that are exact up to a few f64 roundings of values ≈ 100.
const EXACT: f64 = 1e-12;

fn fixture_path(name: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/svg")
        .join(name)
}

fn fixture(name: &str) -> Drawing {
    read_svg_file(&fixture_path(name), &ImportOptions::default())
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn inline(body: &str) -> Result<Drawing, SvgError> {
    read_svg(
        &format!("<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 100 100\">{body}</svg>"),
        &ImportOptions::default(),
    )
}

fn assert_close(a: Point, b: Point, tol: f64, what: &str) {
    assert!(
        (a - b).hypot() <= tol,
        "{what}: {a:?} vs {b:?} (distance {})",
        (a - b).hypot()
    );
}

/// The on-curve points of a path (every third chain point).
fn on_curve(points: &[Point]) -> Vec<Point> {
    points.iter().step_by(3).copied().collect()
}

fn label(d: &Drawing, i: usize) -> String {
    d.source.as_ref().unwrap().element_label(i)
}

#[test]
fn svg_import_nested_transforms_compose_to_root_user_space() {
    let d = fixture("nested_transforms.svg");
    assert_eq!(d.paths.len(), 3);
    let outer = Affine::translate((30.0, 20.0)) * Affine::rotate(30f64.to_radians());
    let tri = &d.paths[0];
    assert!(tri.closed);
    assert_eq!(tri.n_curves(), 3);
    let expected =
        [(0.0, 0.0), (40.0, 0.0), (20.0, 30.0), (0.0, 0.0)].map(|p| outer * Point::from(p));
    for (got, want) in on_curve(&tri.points).iter().zip(expected) {
        assert_close(*got, want, F32_TOLERANCE, "tri");
    }
    let wave_ts =
        outer * Affine::scale_non_uniform(2.0, 0.5) * Affine::new([1.0, 0.2, -0.3, 1.0, 5.0, 6.0]);
    let wave = [(0.0, 0.0), (10.0, -20.0), (20.0, 20.0), (30.0, 0.0)];
    assert_eq!(d.paths[1].points.len(), 4);
    for (got, want) in d.paths[1].points.iter().zip(wave) {
        assert_close(*got, wave_ts * Point::from(want), F32_TOLERANCE, "wave");
    }
    let box_ts = Affine::translate((30.0, 20.0)) * Affine::skew(15f64.to_radians().tan(), 0.0);
    let corners = [
        (100.0, 10.0),
        (130.0, 10.0),
        (130.0, 30.0),
        (100.0, 30.0),
        (100.0, 10.0),
    ];
    for (got, want) in on_curve(&d.paths[2].points).iter().zip(corners) {
        assert_close(*got, box_ts * Point::from(want), F32_TOLERANCE, "box");
    }
    assert_eq!(label(&d, 1), "path#wave (line 8)");
}

#[test]
fn svg_import_excludes_root_transform_and_view_box_mapping() {
    let d = fixture("viewbox_aspect.svg");
    let source = d.source.as_ref().unwrap();
    assert_eq!(source.view_box(), Rect::new(-50.0, -20.0, 50.0, 20.0));
    assert_eq!(source.size(), Size::new(300.0, 200.0));
    // No transform between the root and the elements: coordinates are exactly the attributes.
    assert_eq!(d.paths[0].points[0], Point::new(-40.0, -15.0));
    assert_eq!(d.paths[0].points[3], Point::new(40.0, 15.0));
    assert_eq!(d.paths[1].points[0], Point::new(14.0, 5.0));
}

/// Largest relative radial error of the cubics of a closed path approximating a circle.
fn max_radial_error(points: &[Point], centre: Point, r: f64) -> f64 {
    let mut worst: f64 = 0.0;
    for c in points.windows(4).step_by(3) {
        let cubic = CubicBez::new(c[0], c[1], c[2], c[3]);
        for k in 0..=64 {
            let p = cubic.eval(f64::from(k) / 64.0);
            worst = worst.max(((p - centre).hypot() - r).abs() / r);
        }
    }
    worst
}

#[test]
fn svg_import_basic_shapes() {
    let d = fixture("shapes.svg");
    let counts: Vec<(usize, bool)> = d.paths.iter().map(|p| (p.n_curves(), p.closed)).collect();
    assert_eq!(
        counts,
        vec![
            (4, true),  // rect
            (8, true),  // rounded rect: 4 sides and 4 quarter arcs
            (4, true),  // circle: 4 quarter arcs
            (4, true),  // ellipse
            (1, false), // line
            (3, false), // polyline
            (10, true), // polygon: 9 sides and the closing one
        ]
    );
    let rect = on_curve(&d.paths[0].points);
    assert_eq!(
        rect,
        [(10., 10.), (50., 10.), (50., 30.), (10., 30.), (10., 10.)].map(Point::from)
    );
    // Sides between corners have their control points on their ends.
    assert_eq!(d.paths[0].points[1], Point::new(10.0, 10.0), "rect c1");
    assert_eq!(d.paths[0].points[2], Point::new(50.0, 10.0), "rect c2");
    let line = [(80., 60.), (80., 60.), (180., 100.), (180., 100.)];
    for (got, want) in d.paths[4].points.iter().zip(line) {
        assert_close(*got, Point::from(want), EXACT, "line");
    }
    // Elevated exactly (up to f64 rounding) when asked: controls at 1/3 and 2/3.
    let thirds = read_svg_file(
        &fixture_path("shapes.svg"),
        &ImportOptions::default().with_corner_lines_at_ends(false),
    )
    .unwrap();
    assert_close(
        thirds.paths[0].points[1],
        Point::new(10.0 + 40.0 / 3.0, 10.0),
        EXACT,
        "rect c1",
    );
    let line = [
        (80., 60.),
        (80. + 100. / 3., 60. + 40. / 3.),
        (80. + 200. / 3., 60. + 80. / 3.),
        (180., 100.),
    ];
    for (got, want) in thirds.paths[4].points.iter().zip(line) {
        assert_close(*got, Point::from(want), EXACT, "line");
    }
    let circle_error = max_radial_error(&d.paths[2].points, Point::new(150.0, 30.0), 15.0);
    assert!(
        circle_error <= ARC_RELATIVE_ERROR + F32_RELATIVE,
        "{circle_error}"
    );
    // The rounded corners start where the straight sides end.
    let rounded = on_curve(&d.paths[1].points);
    assert_eq!(rounded[0], Point::new(68.0, 10.0));
    assert_eq!(rounded[1], Point::new(102.0, 10.0));
    assert_close(rounded[2], Point::new(110.0, 15.0), 1e-5, "corner");
    // Polygon joints: corners of a star, none smooth.
    assert!(d.paths[6].joints.iter().all(|&k| k != JointKind::C1));
}

#[test]
fn svg_import_relative_and_smooth_commands() {
    let d = fixture("commands.svg");
    assert_eq!(d.paths.len(), 5);
    let (abs, rel) = (&d.paths[0], &d.paths[1]);
    assert_eq!(abs.n_curves(), 10); // L H V C S Q T, the half arc as 2 cubics, closing line
    assert!(abs.closed && rel.closed);
    assert_eq!(abs.points.len(), rel.points.len());
    for (a, r) in abs.points.iter().zip(&rel.points) {
        assert_close(*a, *r, 1e-9, "absolute vs relative");
    }
    let p = &abs.points;
    // S reflects the previous second control (40, 30) about (40, 20).
    assert_eq!(p[13], Point::new(40.0, 10.0));
    // T reflects the previous quadratic control (60, 30) about (70, 20): q = (80, 10).
    assert_close(
        p[19],
        Point::new(70.0 + 20.0 / 3.0, 20.0 - 20.0 / 3.0),
        1e-5,
        "T c1",
    );
    assert_close(
        p[20],
        Point::new(90.0 - 20.0 / 3.0, 20.0 - 20.0 / 3.0),
        1e-5,
        "T c2",
    );
    // The arc: half a circle of radius 5 about (90, 25).
    let arc_error = max_radial_error(&p[21..28], Point::new(90.0, 25.0), 5.0);
    assert!(
        arc_error <= ARC_RELATIVE_ERROR + F32_RELATIVE,
        "{arc_error}"
    );
    // Several subpaths of one element: open, closed, then `m` relative to the closed start.
    let two: Vec<(usize, bool)> = d.paths[2..]
        .iter()
        .map(|p| (p.n_curves(), p.closed))
        .collect();
    assert_eq!(two, vec![(1, false), (3, true), (1, false)]);
    assert_eq!(d.paths[4].points[0], Point::new(25.0, 55.0));
    assert_eq!(label(&d, 4), "path#two (line 4)");
}

#[test]
fn svg_import_arc_error_within_stated_bound_against_exact_arc() {
    // Large radii take more cubics; every one stays within 2.7e-4 r of the exact ellipse.
    for r in [1.0, 10.0, 1000.0, 1e5] {
        let d = read_svg(
            &format!(
                "<svg xmlns='http://www.w3.org/2000/svg' viewBox='0 0 10 10'>\
                 <path d='M{r} 0 A{r} {r} 0 1 0 0 {r}'/></svg>"
            ),
            &ImportOptions::default(),
        )
        .unwrap();
        let p = &d.paths[0];
        assert!(p.n_curves() >= 3, "270° needs at least 3 cubics of ≤ 90°");
        let error = max_radial_error(&p.points, Point::ORIGIN, r);
        assert!(
            error <= ARC_RELATIVE_ERROR + F32_RELATIVE,
            "r = {r}: {error}"
        );
        assert!(
            error * r <= 0.1 + F32_RELATIVE * r,
            "absolute error ≤ 0.1 units: {}",
            error * r
        );
    }
}

#[test]
fn svg_import_use_instances_map_to_their_use() {
    let d = fixture("use.svg");
    let labels: Vec<String> = (0..d.paths.len()).map(|i| label(&d, i)).collect();
    assert_eq!(
        labels,
        vec![
            "path#leaf (line 4) in use#u1 (line 13)",
            "path#leaf (line 4) in use#u2 (line 14)",
            "rect (line 6) in use#u3 (line 15)",
            "path#leaf (line 4) in use (line 7) in use#u3 (line 15)",
            "line (line 10) in use#u4 (line 16)",
            "path#plain (line 17)",
        ]
    );
    let leaf = [(0.0, 0.0), (5.0, -10.0), (15.0, -10.0), (20.0, 0.0)].map(Point::from);
    for (k, want) in leaf.iter().enumerate() {
        assert_close(
            d.paths[0].points[k],
            *want + kurbo::Vec2::new(10.0, 20.0),
            1e-9,
            "u1",
        );
        let u2 = Affine::rotate_about(45f64.to_radians(), Point::new(100.0, 100.0))
            * Affine::translate((100.0, 100.0));
        assert_close(d.paths[1].points[k], u2 * *want, F32_TOLERANCE, "u2");
        assert_close(
            d.paths[3].points[k],
            *want + kurbo::Vec2::new(62.0, 155.0),
            1e-9,
            "nested",
        );
    }
    assert_eq!(d.paths[2].points[0], Point::new(50.0, 155.0));
    // The symbol's viewBox 0 0 10 10 stretched onto 20 × 40 at (150, 10).
    assert_eq!(d.paths[4].points[0], Point::new(150.0, 10.0));
    assert_eq!(d.paths[4].points[3], Point::new(170.0, 50.0));
    assert_eq!(d.source.as_ref().unwrap().n_elements(), 6);
}

#[test]
fn svg_import_degenerate_input_is_kept_or_skipped() {
    let d = fixture("degenerate.svg");
    let summary: Vec<(String, usize, bool)> = (0..d.paths.len())
        .map(|i| (label(&d, i), d.paths[i].n_curves(), d.paths[i].closed))
        .collect();
    assert_eq!(
        summary,
        vec![
            // zero-length segment kept as a (point) curve
            ("path#zero-length (line 2)".to_string(), 2, false),
            // a curve of four identical points kept
            ("path#duplicates (line 3)".to_string(), 2, false),
            ("path#control-on-end (line 4)".to_string(), 1, false),
            // M50 50 M60 60: the first move is replaced; the trailing M80 80 is skipped
            ("path#lone-moves (line 5)".to_string(), 1, false),
            // M5 5 Z is skipped, the second subpath kept
            ("path#lone-close (line 6)".to_string(), 2, true),
            // duplicated ids: both elements are imported and told apart
            ("path#dup (line 7)".to_string(), 1, false),
            ("path#dup (line 8)".to_string(), 1, false),
        ]
    );
    assert!(d.paths[0].points[..4]
        .iter()
        .all(|&p| p == Point::new(10.0, 10.0)));
    assert_eq!(d.paths[2].points[1], d.paths[2].points[0]);
    assert_eq!(d.paths[3].points[0], Point::new(60.0, 60.0));
    assert_eq!(d.paths[6].points[0], Point::new(0.0, 95.0));
}

#[test]
fn svg_import_only_degenerate_subpaths_is_no_paths() {
    assert!(matches!(
        inline("<path d='M1 1 Z M2 2'/>"),
        Err(SvgError::NoPaths { .. })
    ));
    assert!(matches!(
        inline("<path d=''/>"),
        Err(SvgError::NoPaths { .. })
    ));
    assert!(matches!(inline("<g/>"), Err(SvgError::NoPaths { .. })));
}

#[test]
fn svg_import_skips_what_is_not_rendered_or_not_ours() {
    let d = inline(
        "<defs><marker id='m' markerWidth='4' markerHeight='4'><path d='M0 0 L2 2'/></marker>\
         <clipPath id='c'><rect width='50' height='50'/><use href='#hidden'/></clipPath></defs>\
         <path id='hidden' display='none' d='M0 0 L9 9'/>\
         <path id='main' d='M0 0 L10 0 L20 10' marker-mid='url(#m)' clip-path='url(#c)' stroke='black'/>\
         <path id='ghost' d='M0 50 L10 50' fill='none'/>",
    )
    .unwrap();
    // Marker contents are not imported. The hidden path is (deformed, so that unhiding shows
    // it posed; the clip's `use` of it adds no second copy); clip-path geometry comes before
    // the element it clips; an invisible (unpainted) path is geometry too. Each has its role.
    let labels: Vec<String> = (0..d.paths.len()).map(|i| label(&d, i)).collect();
    assert_eq!(
        labels,
        vec![
            "path#hidden (line 1)",
            "rect (line 1)",
            "path#main (line 1)",
            "path#ghost (line 1)"
        ]
    );
    use splineskin::drawing::PathRole as R;
    let roles: Vec<R> = (0..d.paths.len()).map(|i| d.path_role(i)).collect();
    assert_eq!(roles, [R::Hidden, R::ClipPath, R::Visible, R::Unpainted]);
}

#[test]
fn svg_import_errors_name_file_element_and_expectation() {
    let opts = ImportOptions::default();
    assert!(matches!(
        read_svg("  \n", &opts),
        Err(SvgError::Empty { .. })
    ));
    match read_svg(
        "<svg xmlns='http://www.w3.org/2000/svg'>\n<path d='M0 0'>\n</svg>",
        &opts,
    ) {
        Err(SvgError::Xml { line, column, .. }) => assert_eq!((line, column), (3, 1)),
        other => panic!("{other:?}"),
    }
    match read_svg("<html><path d='M0 0 L1 1'/></html>", &opts) {
        Err(e @ SvgError::NoSvgRoot { .. }) => assert!(e.to_string().contains("<html>")),
        other => panic!("{other:?}"),
    }
    let cases = [
        ("<path d='M0 0 L1e300 1'/>", "path (line 1)", "d"),
        ("<path d='M0 0 L1 1 L1e300 3 X'/>", "path (line 1)", "d"),
        (
            "<rect width='10' height='1e10'/>",
            "rect (line 1)",
            "height",
        ),
    ];
    for (body, element_label, attribute_name) in cases {
        match inline(body) {
            Err(e @ SvgError::InvalidAttribute { .. }) => {
                let SvgError::InvalidAttribute {
                    element,
                    attribute,
                    expected,
                    ..
                } = &e
                else {
                    unreachable!()
                };
                assert_eq!(element, element_label, "{body}");
                assert_eq!(attribute, attribute_name, "{body}");
                assert!(!expected.is_empty());
                assert!(e.to_string().starts_with("<svg text>: "), "{e}");
            }
            other => panic!("{body}: {other:?}"),
        }
    }
    // A length that does not parse ("inf") is ignored as browsers ignore it: the circle has no
    // radius, nothing is left to draw, and the refusal says why.
    match inline("<circle r='inf'/>") {
        Err(e @ SvgError::NoPaths { .. }) => {
            let SvgError::NoPaths { why, .. } = &e else {
                unreachable!()
            };
            assert_eq!(why.len(), 1, "{e}");
            assert!(
                why[0].contains("circle (line 1): attribute r=\"inf\" ignored"),
                "{e}"
            );
        }
        other => panic!("{other:?}"),
    }
    match inline("<g transform='scale(1e6)'><path id='far' d='M0 0 L1e4 0'/></g>") {
        Err(SvgError::CoordinateOutOfRange { element, value, .. }) => {
            assert_eq!(element, "path#far (line 1)");
            // The first point past the limit: the line's first control, 1/3 of the way.
            assert!((value - 1e10 / 3.0).abs() < 1.0, "{value}");
        }
        other => panic!("{other:?}"),
    }
}

/// Path data with an error is drawn up to it, as browsers draw it (SVG 2 §9.5.4): the same
/// curves as the data cut at the error, a warning naming the element and the byte; a file
/// whose only path stops before its first segment has nothing drawn and says why.
#[test]
fn svg_import_draws_path_data_up_to_its_first_error_as_browsers_do() {
    let svg = |d: &str| {
        format!(
            "<svg xmlns='http://www.w3.org/2000/svg' viewBox='0 0 100 100'>\
             <path id='ok' d='M10 10 L90 10 L90 40 Z'/><path id='cut' d='{d}'/></svg>"
        )
    };
    let opts = ImportOptions::default();
    // Each with the data cut before the segment in error, and where the error is: its bad
    // token ("" for the end of the data).
    for (bad, good, error) in [
        (
            "M10 50 L90 50 L90 90 L 40 x 5 Z",
            "M10 50 L90 50 L90 90",
            "x",
        ),
        (
            "M10 50 C20 60 30 60 40 50 S 60 40 70 nope",
            "M10 50 C20 60 30 60 40 50",
            "nope",
        ),
        (
            "M10 50 L90 50 L90 90 Z M 5 5 L",
            "M10 50 L90 50 L90 90 Z M 5 5",
            "",
        ),
        ("m10 50 h80 v40 h-20 #", "m10 50 h80 v40 h-20", "#"),
    ] {
        let read = read_svg(&svg(bad), &opts).unwrap_or_else(|e| panic!("{bad}: {e}"));
        let cut = read_svg(&svg(good), &opts).expect("the cut data reads");
        assert_eq!(read.paths, cut.paths, "{bad}");
        let warnings = splineskin::drawing::import_warnings(&svg(bad), "cut.svg");
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        let at = if error.is_empty() {
            bad.len()
        } else {
            bad.find(error).expect("the error")
        };
        assert!(
            warnings[0].starts_with("cut.svg: path#cut (line 1): path data"),
            "{}",
            warnings[0]
        );
        assert!(
            warnings[0].contains(&format!("byte {at} ")),
            "{bad}: {}",
            warnings[0]
        );
    }
    assert!(splineskin::drawing::import_warnings(&svg("M1 1 L2 2"), "f.svg").is_empty());
    let nothing = "<svg xmlns='http://www.w3.org/2000/svg'><path id='p' d='M0 0 L nan 1'/></svg>";
    match read_svg(nothing, &opts) {
        Err(e @ SvgError::NoPaths { .. }) => {
            let message = e.to_string();
            assert!(message.contains("no paths"), "{message}");
            assert!(message.contains("path#p (line 1): path data"), "{message}");
            assert!(message.contains("at byte 7"), "{message}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn svg_import_size_cap() {
    let big = " ".repeat(splineskin::drawing::svg_in::MAX_SVG_BYTES + 1);
    assert!(matches!(
        read_svg(&big, &ImportOptions::default()),
        Err(SvgError::TooLarge { .. })
    ));
}

#[test]
fn svg_import_file_errors_name_the_file() {
    let path = fixture_path("does-not-exist.svg");
    let err = read_svg_file(&path, &ImportOptions::default()).unwrap_err();
    assert!(err.to_string().contains("does-not-exist.svg"), "{err}");
    let dir = TestDir::new("splineskin-svg-import-");
    let bad = dir.join("bad.svg");
    std::fs::write(
        &bad,
        "<svg xmlns='http://www.w3.org/2000/svg'><path d='M0 0 L'/></svg>",
    )
    .unwrap();
    let err = read_svg_file(&bad, &ImportOptions::default()).unwrap_err();
    assert!(
        err.to_string().starts_with(&bad.display().to_string()),
        "{err}"
    );
    std::fs::write(&bad, [0xff, 0xfe, 0x00]).unwrap();
    assert!(matches!(
        read_svg_file(&bad, &ImportOptions::default()),
        Err(SvgError::NotUtf8 { .. })
    ));
}

#[test]
fn svg_import_keeps_existing_and_synthetic_ids_apart() {
    // An element whose id looks like our synthetic ones still maps correctly.
    let d =
        inline("<path id='splineskin-0' d='M0 0 L1 0'/><path d='M0 1 L1 1'/><path d='M0 2 L1 2'/>")
            .unwrap();
    let ys: Vec<f64> = d.paths.iter().map(|p| p.points[0].y).collect();
    assert_eq!(ys, vec![0.0, 1.0, 2.0]);
    assert_eq!(label(&d, 0), "path#splineskin-0 (line 1)");
}

#[test]
fn svg_import_junction_options_are_applied() {
    let body = "<path d='M0 0 L10 0 L10 10'/>";
    let d = inline(body).unwrap();
    assert_eq!(d.paths[0].joints[1], JointKind::FixedAngle);
    let opts = ImportOptions::default().with_junctions(
        splineskin::drawing::JunctionOptions::default().with_keep_right_angles(false),
    );
    let text = format!("<svg xmlns='http://www.w3.org/2000/svg' viewBox='0 0 9 9'>{body}</svg>");
    let d = read_svg(&text, &opts).unwrap();
    assert_eq!(d.paths[0].joints[1], JointKind::C0);
}

#[test]
fn svg_import_edge_documents() {
    // A byte-order mark before the document.
    let bom = "\u{feff}<svg xmlns='http://www.w3.org/2000/svg' viewBox='0 0 9 9'><path d='M0 0 L1 1'/></svg>";
    assert_eq!(
        read_svg(bom, &ImportOptions::default())
            .unwrap()
            .paths
            .len(),
        1
    );
    // A path that is a single point repeated: kept as one degenerate curve, or dropped by usvg
    // as having no extent; either way no panic.
    match inline("<path d='M5 5 L5 5'/>") {
        Ok(d) => assert_eq!(d.paths[0].n_curves(), 1),
        Err(e) => assert!(matches!(e, SvgError::NoPaths { .. }), "{e}"),
    }
    // A prefixed SVG root and prefixed shapes.
    let prefixed = "<s:svg xmlns:s='http://www.w3.org/2000/svg' viewBox='0 0 9 9'>\
                    <s:rect id='r' width='2' height='1'/></s:svg>";
    let d = read_svg(prefixed, &ImportOptions::default()).unwrap();
    assert_eq!(d.paths[0].n_curves(), 4);
    // A symbol without viewBox used twice.
    let d = inline(
        "<symbol id='s'><path d='M0 0 L1 0'/></symbol>\
         <use href='#s' x='10'/><use href='#s' x='20' y='1'/>",
    )
    .unwrap();
    let starts: Vec<Point> = d.paths.iter().map(|p| p.points[0]).collect();
    assert_eq!(starts, vec![Point::new(10.0, 0.0), Point::new(20.0, 1.0)]);
    // Recursive use: skipped (as usvg does), the rest imported.
    let d = inline("<g id='g'><use href='#g'/><path d='M0 0 L3 0'/></g>").unwrap();
    assert_eq!(d.paths.len(), 1);
}

/// The lenient fixtures (what chromium draws although not strictly valid): each is read, with
/// a warning per thing read other than written, and the geometry chromium draws
/// (browser-tests/lenient.test.mjs compares the pictures).
#[test]
fn svg_import_reads_what_browsers_draw() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/lenient");
    let read = |name: &str| {
        read_svg_file(&dir.join(name), &ImportOptions::default())
            .unwrap_or_else(|e| panic!("{name}: {e}"))
    };
    let warnings = |d: &splineskin::drawing::Drawing| d.source.as_ref().unwrap().warnings.clone();
    let bounds = |d: &splineskin::drawing::Drawing, i: usize| {
        d.paths[i].points.iter().fold(
            kurbo::Rect::from_points(d.paths[i].points[0], d.paths[i].points[0]),
            |r, &p| r.union_pt(p),
        )
    };
    // Invalid values ignored: x="inherit" is x = 0; width="bogus" draws no rect; an unparsable
    // transform is none.
    let d = read("invalid-values.svg");
    let w = warnings(&d);
    assert_eq!(w.len(), 7, "{w:#?}");
    assert!(w[0].contains("svg (line 1): attribute width=\"44mmx\" ignored (not a length)"));
    assert_eq!(bounds(&d, 0), kurbo::Rect::new(0.0, 10.0, 40.0, 40.0));
    assert_eq!(
        d.paths.len(),
        5,
        "the rect of width=\"bogus\" draws nothing"
    );
    assert_eq!(bounds(&d, 1), kurbo::Rect::new(55.0, 15.0, 90.0, 40.0));
    // CSS units: rem of the root's font-size 20, viewport units of its 200 × 100.
    let d = read("css-units.svg");
    assert_eq!(bounds(&d, 0), kurbo::Rect::new(20.0, 10.0, 80.0, 50.0));
    let circle = bounds(&d, 1);
    assert!((circle.center().x - 120.0).abs() < 1e-9 && (circle.width() - 60.0).abs() < 1e-9);
    assert_eq!(bounds(&d, 2), kurbo::Rect::new(150.0, 20.0, 170.0, 40.0));
    assert_eq!(bounds(&d, 3).x1, 190.0);
    // Q (a quarter millimetre), vi and vb (as vw and vh), ic (1 em of the element's font size,
    // inherited: 20 from the root, 10 in the group; units without regard to case).
    let d = read("print-and-font-units.svg");
    // (The import reads in single precision: 1e-6 of the 200-unit drawing.)
    let (q, close) = (96.0 / 101.6, 2e-4);
    let a = bounds(&d, 0);
    assert!(
        (a.x0 - 40.0 * q).abs() < close && (a.width() - 40.0).abs() < close,
        "{a:?}"
    );
    assert!((a.height() - 30.0).abs() < close, "{a:?}");
    assert!((bounds(&d, 1).width() - 40.0).abs() < close);
    assert_eq!(bounds(&d, 2), kurbo::Rect::new(100.0, 70.0, 120.0, 90.0));
    let w = warnings(&d);
    assert!(
        w.iter()
            .any(|w| w.contains("attribute x=\"40Q\" read as x=\"37.7952755")),
        "{w:#?}"
    );
    assert!(
        w.iter()
            .any(|w| w.contains("width=\"2IC\" read as width=\"20\" (1ic taken as 1 em = 10")),
        "{w:#?}"
    );
    // points: the odd coordinate dropped; the list in error draws nothing.
    let d = read("points.svg");
    assert_eq!(d.paths.len(), 2);
    assert_eq!(d.paths[0].n_curves(), 2);
    assert!(warnings(&d)[1].contains("read as points=\"\" (an error in the list"));
    // A use of a nested svg: two copies, the second scaled to 30 units.
    let d = read("use-nested-svg.svg");
    assert_eq!(d.paths.len(), 5);
    let (a, b) = (bounds(&d, 0), bounds(&d, 2));
    assert!(
        (a.width() - 32.0).abs() < 1e-9 && (b.width() - 24.0).abs() < 1e-9,
        "{a:?} {b:?}"
    );
    assert!(warnings(&d).is_empty());
    // Entities expanded, in the namespace, a style and an element.
    let d = read("entities.svg");
    assert_eq!(d.paths.len(), 2);
    let source = d.source.as_ref().unwrap();
    assert!(source
        .text
        .contains("style=\"fill:#E5332A;stroke:#1D1D1B;stroke-width:2\""));
    assert!(source.elements[1].paint.filled);
    assert_eq!(warnings(&d).len(), 1);
}
