//! SVG import, then the SVG and Lottie writers on whatever the importer accepts.
//!
//! Input: three bytes choosing a finite pose (an angle, a scale and a shear, applied about the
//! drawing's centre), then the SVG text. For an accepted drawing the pose is applied to every
//! chain point and to the element maps; the SVG written must read back to the same paths with
//! the same points (within single precision, which the importer reads in), and the Lottie
//! written must be JSON with only finite numbers and no `null`.
#![no_main]

use kurbo::{Affine, Point, Rect};
use libfuzzer_sys::fuzz_target;
use splineskin::drawing::follow::{ElementMaps, FollowOptions};
use splineskin::drawing::lottie::{write_lottie, LottieOptions};
use splineskin::drawing::svg_out::{write_svg_following, ViewBoxRule};
use splineskin::drawing::{read_svg, ImportOptions};

fuzz_target!(|data: &[u8]| {
    if data.len() < 3 {
        return;
    }
    let Ok(text) = std::str::from_utf8(&data[3..]) else {
        return;
    };
    let Ok(drawing) = read_svg(text, &ImportOptions::default()) else {
        return;
    };
    let rest = drawing.flat_points();
    let Some(bounds) = rest.iter().fold(None, |r: Option<Rect>, &p| {
        Some(r.map_or(Rect::from_points(p, p), |r| r.union_pt(p)))
    }) else {
        return;
    };
    let pose = pose(data[0], data[1], data[2], bounds.center());
    let points: Vec<Point> = rest.iter().map(|&p| pose * p).collect();
    if points.iter().any(|p| !p.is_finite()) {
        return;
    }
    let Ok(maps) = ElementMaps::from_map(&drawing, &mut |p| pose * p, &FollowOptions::default())
    else {
        return;
    };
    if let Ok(out) = write_svg_following(&drawing, &points, &maps, ViewBoxRule::Keep) {
        check_reads_back(&out, &drawing, &points);
    }
    let frames = [rest.clone(), points];
    let all_maps = [
        ElementMaps::from_map(&drawing, &mut |p| p, &FollowOptions::default()).unwrap(),
        maps,
    ];
    let options = LottieOptions::default();
    if let Ok(lottie) = write_lottie(&drawing, &frames, &[0.0, 1.0], 30.0, Some(&all_maps), &options)
    {
        let value: serde_json::Value =
            serde_json::from_str(&lottie.json).expect("the Lottie written is JSON");
        check_lottie_values(&value);
        for key in ["v", "fr", "ip", "op", "w", "h", "layers"] {
            assert!(value.get(key).is_some(), "Lottie without {key}");
        }
    }
});

/// A rotation by `a` (of 256 turns), a scale `2^((s − 128)/16)` and a shear `(h − 128)/64`
/// about `centre`.
fn pose(a: u8, s: u8, h: u8, centre: Point) -> Affine {
    let angle = f64::from(a) * std::f64::consts::TAU / 256.0;
    let scale = 2f64.powf((f64::from(s) - 128.0) / 16.0);
    let shear = (f64::from(h) - 128.0) / 64.0;
    Affine::translate(centre.to_vec2())
        * Affine::rotate(angle)
        * Affine::new([scale, 0.0, shear * scale, scale, 0.0, 0.0])
        * Affine::translate(-centre.to_vec2())
}

/// The SVG written reads back to the same paths, each with the same points within single
/// precision (relative to the coordinates' magnitude and the drawing's size).
fn check_reads_back(out: &str, drawing: &splineskin::drawing::Drawing, points: &[Point]) {
    let again = read_svg(out, &ImportOptions::default())
        .unwrap_or_else(|e| panic!("our own SVG does not read back: {e}\n{out}"));
    assert_eq!(again.paths.len(), drawing.paths.len(), "paths\n{out}");
    for (a, b) in again.paths.iter().zip(&drawing.paths) {
        assert_eq!(a.points.len(), b.points.len(), "points of a path\n{out}");
    }
    let magnitude = points
        .iter()
        .fold(0.0f64, |m, p| m.max(p.x.abs()).max(p.y.abs()));
    let tolerance = 1e-5 * magnitude;
    if !(magnitude < 1e30) {
        return;
    }
    for (p, q) in again.flat_points().iter().zip(points) {
        assert!((*p - *q).hypot() <= tolerance, "{p:?} read back for {q:?}\n{out}");
    }
}

/// No `null` (what serde_json writes for a non-finite number) anywhere in the document.
fn check_lottie_values(value: &serde_json::Value) {
    match value {
        serde_json::Value::Null => panic!("null in the Lottie written"),
        serde_json::Value::Array(items) => items.iter().for_each(check_lottie_values),
        serde_json::Value::Object(map) => map.values().for_each(check_lottie_values),
        _ => {}
    }
}
