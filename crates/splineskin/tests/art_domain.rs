//! The art-shaped domain (`domain.shape = "art"`, our scenes' default): a pin's influence stays
//! in the part of the art it is on.
//!
//! * **Parts stay apart.** On drawings of several parts (our own, and OpenMoji animals with
//!   legs, read from `test-art/node_modules`), one limb's pin is dragged by a tenth of the
//!   drawing's size while the body and another limb are pinned; an unpinned limb next to the
//!   dragged one, joined to it only through the pinned body, moves at most
//!   [`UNPINNED_RATIO`] as far as the dragged pin with the default weights (bounded
//!   biharmonic, as `splineskin deform` and `rig` use), and the dragged limb's foot follows
//!   its pin (at least [`FOLLOW_RATIO`] of its move). The same scenes with the enclosing domain
//!   (the padded box: what every drawing of several shapes got before) break the first bound,
//!   which shows the check can fail.
//! * **Invariants.** On the same rigs the identity pose reproduces the drawing and one rigid
//!   map on every pin gives that map of it, to 1e-9 of the diagonal.
//! * **The domain.** Separate shapes make separate parts, a part without a pin is left out,
//!   real holes (either fill rule) are holes, strokes count at their width, and the domain of a
//!   drawing scaled by 10^±6 and moved far from the origin is the same domain, scaled.
//!
//! Without `test-art/node_modules` the OpenMoji cases print that they skipped and pass, except
//! when `CI` is set: then they fail.

use std::path::PathBuf;

use kurbo::{Affine, Point, Vec2};
use splineskin::domain::{Boundary, Domain, DomainOptions, DomainShape};
use splineskin::drawing::{read_svg, Drawing, ImportOptions};
use splineskin::scene::{Compat, Scene};
use splineskin::spline_fit::SplineRig;

/// Largest displacement of an unpinned limb next to a dragged one, as a fraction of the
/// dragged pin's: 1/4 (issue 33; the padded box gave 0.8–0.9).
const UNPINNED_RATIO: f64 = 0.25;

/// Smallest displacement of the dragged limb's foot, as a fraction of its pin's: 3/4.
const FOLLOW_RATIO: f64 = 0.75;

/// Accuracy of the identity and rigid invariants, relative to the diagonal.
const INVARIANT: f64 = 1e-9;

/// One case: a drawing, its pins (the last one dragged by `drag`), the rest point of the
/// unpinned limb's foot and of the dragged limb's foot.
struct Case {
    name: &'static str,
    svg: String,
    pins: Vec<Point>,
    drag: Vec2,
    unpinned_foot: Point,
    dragged_foot: Point,
}

/// Our own animal: a body (ellipse) and three legs drawn as separate rectangles that overlap
/// it, outlined by strokes, and a separate bird above it with no pin.
fn own_animal() -> Case {
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100">
      <ellipse cx="50" cy="40" rx="32" ry="14" fill="#c84" stroke="#000" stroke-width="1.5"/>
      <rect x="24" y="44" width="7" height="40" fill="#c84" stroke="#000" stroke-width="1.5"/>
      <rect x="37" y="46" width="7" height="38" fill="#c84" stroke="#000" stroke-width="1.5"/>
      <rect x="66" y="44" width="7" height="40" fill="#c84" stroke="#000" stroke-width="1.5"/>
      <path d="M40 8 q5 -4 10 0 q5 -4 10 0" fill="none" stroke="#000" stroke-width="1.5"/>
    </svg>"##;
    Case {
        name: "own animal",
        svg: svg.to_string(),
        pins: vec![
            Point::new(50.0, 38.0),
            Point::new(69.5, 80.0),
            Point::new(27.5, 80.0),
        ],
        drag: Vec2::new(10.0, 0.0),
        unpinned_foot: Point::new(37.0, 84.0),
        dragged_foot: Point::new(24.0, 84.0),
    }
}

/// The OpenMoji animals, when the package is installed: the giraffe as issue 33 tried it (head,
/// body and rear foot pinned, the middle foot dragged; the front foot free), and the zebra (body
/// and rear foot pinned, the front foot dragged; the inner hind foot free).
fn openmoji_animals() -> Option<Vec<Case>> {
    let folder = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../test-art/node_modules/openmoji/color/svg");
    let read = |file: &str| std::fs::read_to_string(folder.join(file)).ok();
    let (Some(giraffe), Some(zebra)) = (read("1F992.svg"), read("1F993.svg")) else {
        let why = format!("{} is missing: run `npm ci` in test-art", folder.display());
        assert!(std::env::var_os("CI").is_none(), "{why}");
        eprintln!("skipped: the OpenMoji cases ({why})");
        return None;
    };
    Some(vec![
        Case {
            name: "OpenMoji giraffe 1F992",
            svg: giraffe,
            pins: vec![
                Point::new(17.0, 18.0),
                Point::new(40.0, 38.0),
                Point::new(56.3, 60.0),
                Point::new(44.9, 61.0),
            ],
            drag: Vec2::new(8.0, 0.0),
            unpinned_foot: Point::new(29.8763, 66.2708),
            dragged_foot: Point::new(43.75, 66.3),
        },
        Case {
            name: "OpenMoji zebra 1F993",
            svg: zebra,
            pins: vec![
                Point::new(40.0, 35.0),
                Point::new(54.0, 59.0),
                Point::new(30.5, 58.0),
            ],
            drag: Vec2::new(-7.0, 0.0),
            unpinned_foot: Point::new(45.0, 60.5),
            dragged_foot: Point::new(30.5, 61.0),
        },
    ])
}

/// The case's scene (BBW, the last pin dragged) with the domain `shape`, set up.
fn rig(case: &Case, shape: DomainShape) -> (Drawing, SplineRig, Vec<Point>) {
    let handles: Vec<serde_json::Value> = case
        .pins
        .iter()
        .map(|p| serde_json::json!({ "position": [p.x, p.y] }))
        .collect();
    let scene = serde_json::json!({
        "splineskin_scene": 1,
        "svg_text": case.svg,
        "handles": handles,
        "weights": { "family": "bbw" },
        "domain": { "shape": shape.name() },
    });
    let scene = Scene::from_json(&scene.to_string(), case.name, None).expect("scene");
    let setup = scene.setup(Compat::None).expect("setup");
    if shape == DomainShape::Art {
        let domain = setup.domain.as_ref().expect("a mesh family has a domain");
        assert!(
            matches!(domain.boundary, Boundary::Art { .. }),
            "{}: {:?}",
            case.name,
            domain.boundary
        );
    }
    let rig = SplineRig::precompute(&setup.drawing, &*setup.weights, &setup.options).expect("rig");
    let rest = setup.drawing.flat_points();
    (setup.drawing, rig, rest)
}

/// How far the chain point nearest `at` (at rest) moves under `pose`.
fn displacement(rig: &SplineRig, rest: &[Point], pose: &[Affine], at: Point) -> f64 {
    let mut out = vec![Point::ZERO; rest.len()];
    rig.update(pose, &mut out).expect("update");
    let k = (0..rest.len())
        .min_by(|&a, &b| (rest[a] - at).hypot().total_cmp(&(rest[b] - at).hypot()))
        .expect("points");
    (out[k] - rest[k]).hypot()
}

/// The unpinned foot's and the dragged foot's displacement, as fractions of the drag.
fn ratios(case: &Case, shape: DomainShape) -> (f64, f64) {
    let (_, rig, rest) = rig(case, shape);
    let mut pose = vec![Affine::IDENTITY; case.pins.len()];
    *pose.last_mut().expect("pins") = Affine::translate(case.drag);
    let moved = case.drag.hypot();
    (
        displacement(&rig, &rest, &pose, case.unpinned_foot) / moved,
        displacement(&rig, &rest, &pose, case.dragged_foot) / moved,
    )
}

fn check_parts_stay_apart(case: &Case) {
    let (unpinned, dragged) = ratios(case, DomainShape::Art);
    let (unpinned_box, _) = ratios(case, DomainShape::Enclosing);
    eprintln!(
        "{}: unpinned limb {unpinned:.4}x the drag (enclosing domain: {unpinned_box:.3}x), \
         dragged foot {dragged:.3}x",
        case.name
    );
    assert!(
        unpinned <= UNPINNED_RATIO,
        "{}: unpinned limb {unpinned}",
        case.name
    );
    assert!(
        dragged >= FOLLOW_RATIO,
        "{}: dragged foot {dragged}",
        case.name
    );
    assert!(
        unpinned_box > UNPINNED_RATIO,
        "{}: the enclosing domain should leak ({unpinned_box})",
        case.name
    );
}

fn check_invariants(case: &Case) {
    let (drawing, rig, rest) = rig(case, DomainShape::Art);
    let diagonal = drawing.diagonal();
    let rigid = Affine::translate((3.0, -2.0)) * Affine::rotate(0.4);
    for (what, map) in [("identity", Affine::IDENTITY), ("rigid", rigid)] {
        let pose = vec![map; case.pins.len()];
        let mut out = vec![Point::ZERO; rest.len()];
        rig.update(&pose, &mut out).expect("update");
        let worst = out
            .iter()
            .zip(&rest)
            .map(|(o, r)| (*o - map * *r).hypot())
            .fold(0.0, f64::max);
        assert!(
            worst <= INVARIANT * diagonal,
            "{}: {what} off by {worst:e}",
            case.name
        );
    }
}

#[test]
fn art_domain_keeps_an_unpinned_limb_still_on_our_drawing() {
    let case = own_animal();
    check_parts_stay_apart(&case);
    check_invariants(&case);
}

#[test]
fn art_domain_keeps_an_unpinned_limb_still_on_openmoji_animals() {
    let Some(cases) = openmoji_animals() else {
        return;
    };
    for case in &cases {
        check_parts_stay_apart(case);
        check_invariants(case);
    }
}

/// The domain of `svg` with point handles `pins`, art-shaped.
fn art_domain(svg: &str, pins: &[Point]) -> Domain {
    let drawing = read_svg(svg, &ImportOptions::default()).expect("svg");
    let options = DomainOptions::default().with_shape(DomainShape::Art);
    Domain::build(&drawing, pins, &[], &options).expect("domain")
}

#[test]
fn art_domain_separates_shapes_and_leaves_unpinned_ones_out() {
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 40">
      <circle cx="10" cy="20" r="8"/>
      <circle cx="50" cy="20" r="8"/>
      <circle cx="90" cy="20" r="8"/>
    </svg>"##;
    let two = art_domain(svg, &[Point::new(10.0, 20.0), Point::new(50.0, 20.0)]);
    assert_eq!(
        two.boundary,
        Boundary::Art {
            parts: 2,
            unpinned: 1
        }
    );
    assert_eq!(two.boundary_loops.len(), 2);
    assert_eq!(two.n_holes(), 0);
    // Nothing between the circles, nothing of the third one.
    for v in &two.mesh.vertices {
        assert!(v.x < 25.0 || (v.x > 35.0 && v.x < 65.0), "vertex at {v:?}");
    }
    // Each part is its circle grown by the margin and a cell and a half, to a few percent.
    let diagonal = (96f64).hypot(16.0);
    let grown = 8.0 + 0.01 * diagonal + 1.5 * diagonal / 500.0;
    let expected = 2.0 * std::f64::consts::PI * grown * grown;
    assert!(
        (two.area / expected - 1.0).abs() < 0.02,
        "{} vs {expected}",
        two.area
    );
    // Shapes that overlap are one part.
    let touching = r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 40">
      <circle cx="10" cy="20" r="8"/><rect x="15" y="18" width="30" height="4"/>
      <circle cx="50" cy="20" r="8"/>
    </svg>"##;
    let one = art_domain(touching, &[Point::new(10.0, 20.0), Point::new(50.0, 20.0)]);
    assert_eq!(
        one.boundary,
        Boundary::Art {
            parts: 1,
            unpinned: 0
        }
    );
}

#[test]
fn art_domain_keeps_real_holes_under_either_fill_rule_and_strokes_at_their_width() {
    // A ring drawn as two subpaths: opposite directions (a hole under both rules), and the same
    // direction under evenodd (a hole) and nonzero (filled).
    let ring = |rule: &str, inner: &str| {
        format!(
            r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100">
            <path fill-rule="{rule}" d="M10 10 H90 V90 H10 Z {inner}"/></svg>"##
        )
    };
    let same = "M30 30 H70 V70 H30 Z";
    let opposite = "M30 30 V70 H70 V30 Z";
    let pin = [Point::new(20.0, 50.0)];
    for (rule, inner, holes) in [
        ("nonzero", opposite, 1),
        ("evenodd", same, 1),
        ("evenodd", opposite, 1),
        ("nonzero", same, 0),
    ] {
        let domain = art_domain(&ring(rule, inner), &pin);
        assert_eq!(domain.n_holes(), holes, "{rule}, {inner}");
    }
    // A thick stroke alone: the domain is as wide as the stroke (plus the margin).
    let stroke = r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100">
      <path d="M10 50 H90" fill="none" stroke="#000" stroke-width="20"/></svg>"##;
    let domain = art_domain(stroke, &[Point::new(50.0, 50.0)]);
    let (lo, hi) = domain
        .mesh
        .vertices
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v.y), hi.max(v.y))
        });
    // Diagonal 80: margin 0.8, a cell and a half 0.24.
    assert!((hi - lo - 22.08).abs() < 0.3, "{lo} {hi}");
}

#[test]
fn art_domain_is_the_same_at_any_scale_and_far_from_the_origin() {
    // Two discs joined by a line, as a drawing without a source document (every path filled
    // and drawn), mapped point by point: the same drawing at every scale and place.
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg">
      <circle cx="10" cy="20" r="8"/><circle cx="50" cy="20" r="8"/>
      <circle cx="22" cy="60" r="5"/><path d="M10 20 L50 24"/></svg>"##;
    let mut reference = read_svg(svg, &ImportOptions::default()).expect("svg");
    reference.source = None;
    let pin = Point::new(10.0, 20.0);
    let options = DomainOptions::default().with_shape(DomainShape::Art);
    let at = |map: Affine| {
        let mut drawing = reference.clone();
        for path in &mut drawing.paths {
            path.points.iter_mut().for_each(|p| *p = map * *p);
        }
        Domain::build(&drawing, &[map * pin], &[], &options).expect("domain")
    };
    let base = at(Affine::IDENTITY);
    assert_eq!(
        base.boundary,
        Boundary::Art {
            parts: 1,
            unpinned: 1
        }
    );
    assert_eq!(base.attachments.len(), 1);
    for (scale, shift) in [
        (1e-6, 0.0),
        (1e6, 0.0),
        (1.0, 1e6),
        (1e-6, 1e3),
        (1e6, -1e9),
    ] {
        let map = Affine::translate((shift, shift)) * Affine::scale(scale);
        let domain = at(map);
        assert_eq!(domain.boundary, base.boundary, "{scale} {shift}");
        let area = domain.area / (scale * scale);
        assert!(
            (area / base.area - 1.0).abs() < 1e-6,
            "{scale} {shift}: {area} vs {}",
            base.area
        );
        let n = domain.mesh.n_vertices() as f64;
        let n0 = base.mesh.n_vertices() as f64;
        assert!((n / n0 - 1.0).abs() < 0.02, "{scale} {shift}: {n} vs {n0}");
        // The unpinned disc is attached to the same place.
        let anchor = domain.mesh.vertices[domain.attachments[0].vertex];
        let anchor0 = map * base.mesh.vertices[base.attachments[0].vertex];
        assert!(
            (anchor - anchor0).hypot() <= 0.02 * scale * 40.0,
            "{scale} {shift}: {anchor:?} vs {anchor0:?}"
        );
    }
}

#[test]
fn art_domain_ties_a_pin_beside_the_art_to_it() {
    // A stem (a stroke) and a pin 13 units to its left, another on the stem: one part, and
    // dragging the pin beside the stem bends the stem near it.
    let case = Case {
        name: "pin beside a stem",
        svg: r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 200">
          <path d="M50 190 C40 140 60 80 50 30" fill="none" stroke="#000" stroke-width="4"/>
        </svg>"##
            .to_string(),
        pins: vec![Point::new(50.0, 150.0), Point::new(35.0, 60.0)],
        drag: Vec2::new(20.0, 0.0),
        unpinned_foot: Point::new(50.0, 190.0),
        dragged_foot: Point::new(50.0, 30.0),
    };
    let (drawing, _, _) = rig(&case, DomainShape::Art);
    let domain = Domain::build(
        &drawing,
        &case.pins,
        &[],
        &DomainOptions::default().with_shape(DomainShape::Art),
    )
    .expect("domain");
    assert_eq!(
        domain.boundary,
        Boundary::Art {
            parts: 1,
            unpinned: 0
        }
    );
    let (_, top) = ratios(&case, DomainShape::Art);
    assert!(top > 0.5, "the stem's top moves {top}x the drag");
}
