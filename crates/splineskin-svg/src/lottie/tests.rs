use kurbo::{Affine, Point, Vec2};
use serde_json::Value;

use super::gradient_space::LottieParts;
use super::*;
use crate::follow::{ElementMaps, FollowOptions};
use crate::svg_in::{read_svg, ImportOptions};

const ART: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" width="200" height="100" viewBox="0 0 100 50">
  <defs>
    <linearGradient id="sky" x1="0" y1="0" x2="10" y2="0" gradientUnits="userSpaceOnUse">
      <stop offset="0" stop-color="#ff0000"/><stop offset="1" stop-color="#0000ff" stop-opacity="0.5"/>
    </linearGradient>
    <pattern id="dots" width="4" height="4" patternUnits="userSpaceOnUse"><circle cx="2" cy="2" r="1"/></pattern>
  </defs>
  <path id="wave" d="M10 10 C20 0 30 20 40 10 S60 0 70 10" fill="none" stroke="#102030"
        stroke-width="2" stroke-linecap="round" stroke-linejoin="bevel" stroke-dasharray="3 1"/>
  <g transform="scale(2)" opacity="0.5">
    <rect id="box" x="5" y="12" width="10" height="8" fill="url(#sky)" stroke="#00ff00" fill-rule="evenodd"/>
  </g>
  <circle id="dotted" cx="80" cy="30" r="8" fill="url(#dots)"/>
</svg>"##;

/// The drawing of `ART`, and frames turning it about a point by up to `turn` radians over
/// `n` frames (a motion linear interpolation cannot follow exactly).
fn turning(n: usize, turn: f64) -> (Drawing, Vec<Vec<Point>>) {
    let drawing = read_svg(ART, &ImportOptions::default()).unwrap();
    let rest = drawing.flat_points();
    let frames = (0..n)
        .map(|k| {
            let m = Affine::rotate_about(turn * k as f64 / (n - 1) as f64, Point::new(50.0, 25.0));
            rest.iter().map(|&p| m * p).collect()
        })
        .collect();
    (drawing, frames)
}

/// `n` times `k / fps`.
fn times(n: usize, fps: f64) -> Vec<f64> {
    (0..n).map(|k| k as f64 / fps).collect()
}

/// The points of `drawing` moved by `motion(k)`, for frames `k = 0..n`.
fn moved(drawing: &Drawing, n: usize, motion: impl Fn(usize) -> Affine) -> Vec<Vec<Point>> {
    let rest = drawing.flat_points();
    (0..n)
        .map(|k| rest.iter().map(|&p| motion(k) * p).collect())
        .collect()
}

/// The element maps of `drawing` following `motion(k)`, for frames `k = 0..n`.
fn following(drawing: &Drawing, n: usize, motion: impl Fn(usize) -> Affine) -> Vec<ElementMaps> {
    (0..n)
        .map(|k| {
            let m = motion(k);
            ElementMaps::from_map(drawing, &mut |p| m * p, &FollowOptions::default()).unwrap()
        })
        .collect()
}

/// `drawing` written through `frames` at `fps` (frame `k` at `k / fps`) with the default
/// options and `maps`.
fn written(
    drawing: &Drawing,
    frames: &[Vec<Point>],
    fps: f64,
    maps: Option<&[ElementMaps]>,
) -> LottieExport {
    let t = times(frames.len(), fps);
    write_lottie(drawing, frames, &t, fps, maps, &LottieOptions::default()).unwrap()
}

/// Every shape item (`"ty": "sh"`) of the document, in document order (depth first).
/// The numbers of a JSON array (whole numbers are written as integers).
fn numbers(v: &Value) -> Vec<f64> {
    v.as_array()
        .expect("an array")
        .iter()
        .map(|x| x.as_f64().expect("a number"))
        .collect()
}

fn shapes(v: &Value, out: &mut Vec<Value>) {
    match v {
        Value::Object(o) => {
            if o.get("ty") == Some(&Value::from("sh")) {
                out.push(v.clone());
            }
            for x in o.values() {
                shapes(x, out);
            }
        }
        Value::Array(a) => a.iter().for_each(|x| shapes(x, out)),
        _ => {}
    }
}

/// The control points a player draws for a shape at frame `t`: the keyframes around `t`
/// interpolated linearly (the export's easing), tangents made absolute, closed shapes closed.
fn played(shape: &Value, t: f64) -> Vec<Point> {
    let ks = &shape["ks"];
    let bezier = if ks["a"] == 0 {
        ks["k"].clone()
    } else {
        let keys = ks["k"].as_array().unwrap();
        let time = |k: &Value| k["t"].as_f64().unwrap();
        let j = keys.iter().rposition(|k| time(k) <= t).unwrap();
        if j + 1 == keys.len() {
            keys[j]["s"][0].clone()
        } else {
            let (a, b) = (&keys[j]["s"][0], &keys[j + 1]["s"][0]);
            let u = (t - time(&keys[j])) / (time(&keys[j + 1]) - time(&keys[j]));
            let mut out = a.clone();
            for field in ["v", "i", "o"] {
                for (k, p) in out[field].as_array_mut().unwrap().iter_mut().enumerate() {
                    for d in 0..2 {
                        let (x, y) = (
                            a[field][k][d].as_f64().unwrap(),
                            b[field][k][d].as_f64().unwrap(),
                        );
                        p[d] = Value::from(x + u * (y - x));
                    }
                }
            }
            out
        }
    };
    let pt = |field: &str, k: usize| {
        Point::new(
            bezier[field][k][0].as_f64().unwrap(),
            bezier[field][k][1].as_f64().unwrap(),
        )
    };
    let n = bezier["v"].as_array().unwrap().len();
    let closed = bezier["c"].as_bool().unwrap();
    let mut points = vec![pt("v", 0)];
    let segments = if closed { n } else { n - 1 };
    for k in 0..segments {
        let (a, b) = (k, (k + 1) % n);
        points.push(pt("v", a) + pt("o", a).to_vec2());
        points.push(pt("v", b) + pt("i", b).to_vec2());
        points.push(pt("v", b));
    }
    points
}

#[test]
fn lottie_shapes_follow_the_deformation_within_the_tolerance() {
    let (drawing, frames) = turning(41, 0.8);
    let diagonal = drawing.diagonal();
    for tolerance in [1e-3, 1e-4] {
        let options = LottieOptions::default().with_tolerance(tolerance);
        let out = write_lottie(
            &drawing,
            &frames,
            &times(frames.len(), 20.0),
            20.0,
            None,
            &options,
        )
        .unwrap();
        let doc: Value = serde_json::from_str(&out.json).unwrap();
        let mut found = Vec::new();
        shapes(&doc, &mut found);
        assert_eq!(found.len(), drawing.paths.len());
        assert!(
            out.keyframes < out.every_frame_keyframes && out.keyframes > 2 * found.len(),
            "{tolerance}: {} of {}",
            out.keyframes,
            out.every_frame_keyframes
        );
        // Shapes are listed topmost first: the last path of the document is the first shape.
        let offsets: Vec<usize> = drawing.path_ranges().map(|r| r.start).collect();
        for (f, frame) in frames.iter().enumerate() {
            for (s, shape) in found.iter().enumerate() {
                let pi = drawing.paths.len() - 1 - s;
                let want = &frame[offsets[pi]..offsets[pi] + drawing.paths[pi].points.len()];
                let got = played(shape, f as f64);
                assert_eq!(got.len(), want.len(), "path {pi}");
                let gap = got
                    .iter()
                    .zip(want)
                    .map(|(a, b)| (*a - *b).hypot())
                    .fold(0.0, f64::max);
                assert!(
                    gap <= tolerance * diagonal * (1.0 + 1e-9),
                    "{tolerance}: frame {f}, path {pi}: {gap:e}"
                );
            }
        }
    }
    // Tolerance 0 keeps every frame of every path that moves.
    let out = write_lottie(
        &drawing,
        &frames,
        &times(frames.len(), 20.0),
        20.0,
        None,
        &LottieOptions::default().with_tolerance(0.0),
    )
    .unwrap();
    assert_eq!(out.keyframes, out.every_frame_keyframes);
}

#[test]
fn lottie_paint_is_the_documents() {
    let (drawing, frames) = turning(3, 0.1);
    let out = written(&drawing, &frames, 24.0, None);
    let doc: Value = serde_json::from_str(&out.json).unwrap();
    assert_eq!(
        (doc["w"].as_f64(), doc["h"].as_f64()),
        (Some(200.0), Some(100.0))
    );
    // The viewBox 0 0 100 50 drawn at 200 × 100: scale 200 %.
    assert_eq!(doc["layers"][0]["ks"]["s"]["k"][0], 200.0);
    let items = doc["layers"][0]["shapes"].as_array().unwrap();
    // Topmost first: the circle (its pattern fill not written), the half-opaque group with
    // the rect, then the wave.
    assert_eq!(items.len(), 3);
    let wave = &items[2]["it"];
    let stroke = &wave[1];
    assert_eq!(stroke["ty"], "st");
    assert_eq!(
        numbers(&stroke["c"]["k"]),
        [16.0 / 255.0, 32.0 / 255.0, 48.0 / 255.0, 1.0]
    );
    assert_eq!(
        (
            stroke["w"]["k"].as_f64(),
            stroke["lc"].as_i64(),
            stroke["lj"].as_i64()
        ),
        (Some(2.0), Some(2), Some(3))
    );
    let dashes: Vec<(String, f64)> = stroke["d"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| {
            (
                d["n"].as_str().unwrap().to_string(),
                d["v"]["k"].as_f64().unwrap(),
            )
        })
        .collect();
    assert_eq!(
        dashes,
        [("d".into(), 3.0), ("g".into(), 1.0), ("o".into(), 0.0)]
    );
    // Each dash's own name: lottie-web draws nothing of a layer whose dashes share one.
    let names: Vec<&str> = stroke["d"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| d["nm"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["dash 0", "gap 0", "offset"]);
    assert_eq!(
        wave.as_array().unwrap().len(),
        3,
        "path, stroke, transform: no fill"
    );
    let group = &items[1];
    assert_eq!(group["ty"], "gr");
    let group_items = group["it"].as_array().unwrap();
    assert_eq!(group_items.last().unwrap()["o"]["k"], 50.0);
    let rect = &group_items[0]["it"];
    // Under scale(2): the stroke's width 1 becomes 2, the gradient's end (10, 0) becomes (20, 0).
    let (rect_stroke, rect_fill) = (&rect[1], &rect[2]);
    assert_eq!(rect_stroke["w"]["k"], 2.0);
    assert_eq!(
        (rect_fill["ty"].as_str(), rect_fill["r"].as_i64()),
        (Some("gf"), Some(2))
    );
    assert_eq!(numbers(&rect_fill["e"]["k"]), [20.0, 0.0]);
    assert_eq!(rect_fill["g"]["p"], 2);
    assert_eq!(
        numbers(&rect_fill["g"]["k"]["k"]),
        [0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.5]
    );
    let circle = items[0]["it"].as_array().unwrap();
    assert_eq!(
        circle.len(),
        2,
        "path and transform: the pattern fill is not written"
    );
    let warned = |needle: &str| out.warnings.iter().any(|w| w.contains(needle));
    assert!(warned("pattern (dots)"), "{:?}", out.warnings);
    // Written, but drawn otherwise by rlottie: the wave's dashes, the box's stop opacity. The
    // half-opaque group holds one shape: no overlap to draw otherwise.
    let noted = |needle: &str| out.player_notes.iter().any(|n| n.contains(needle));
    assert!(
        noted("path#wave (line 8): rlottie (1.3.8) places its stroke's dashes"),
        "{:?}",
        out.player_notes
    );
    assert!(
        noted("rect#box (line 11): rlottie (1.3.8) blends its fill gradient's stop opacities"),
        "{:?}",
        out.player_notes
    );
    assert_eq!(out.player_notes.len(), 2, "{:?}", out.player_notes);
    assert!(
        warned("gradient is written at rest (no element maps"),
        "{:?}",
        out.warnings
    );
}

#[test]
fn lottie_rejects_bad_frames_and_options() {
    let (drawing, frames) = turning(3, 0.1);
    let options = LottieOptions::default();
    let err = |frames: &[Vec<Point>], fps: f64, options: &LottieOptions| {
        write_lottie(
            &drawing,
            frames,
            &times(frames.len(), 10.0),
            fps,
            None,
            options,
        )
        .unwrap_err()
        .to_string()
    };
    assert!(err(&frames[..1], 10.0, &options).contains("1 frame(s) given"));
    assert!(err(&frames, 0.0, &options).contains("frame rate 0"));
    assert!(err(&frames, f64::NAN, &options).contains("frame rate NaN"));
    assert!(err(&frames, 10.0, &options.clone().with_tolerance(-1.0)).contains("tolerance -1"));
    let mut short = frames.clone();
    short[1].pop();
    assert!(err(&short, 10.0, &options).contains("frame 1 has"));
    let mut nan = frames.clone();
    nan[2][4] = Point::new(f64::NAN, 0.0);
    assert!(err(&nan, 10.0, &options).contains("frame 2, point 4 is not finite"));
    let bare = Drawing {
        paths: drawing.paths.clone(),
        source: None,
    };
    assert!(matches!(
        write_lottie(&bare, &frames, &times(3, 10.0), 10.0, None, &options),
        Err(LottieError::NoSource)
    ));
    // Far from the origin and scaled down: the same keyframes (the tolerance is relative).
    let far = |frames: &[Vec<Point>]| -> Vec<Vec<Point>> {
        frames
            .iter()
            .map(|f| {
                f.iter()
                    .map(|&p| (p.to_vec2() * 1e-6 + Vec2::new(1e6, -1e6)).to_point())
                    .collect()
            })
            .collect()
    };
    let (drawing_far, _) = (
        Drawing {
            paths: drawing
                .paths
                .iter()
                .map(|p| {
                    let mut p = p.clone();
                    p.points
                        .iter_mut()
                        .for_each(|q| *q = (q.to_vec2() * 1e-6 + Vec2::new(1e6, -1e6)).to_point());
                    p
                })
                .collect(),
            source: drawing.source.clone(),
        },
        (),
    );
    let (_, turning_frames) = turning(21, 0.8);
    let t = times(21, 10.0);
    let a = write_lottie(&drawing, &turning_frames, &t, 10.0, None, &options).unwrap();
    let b = write_lottie(
        &drawing_far,
        &far(&turning_frames),
        &t,
        10.0,
        None,
        &options,
    )
    .unwrap();
    assert!(write_lottie(&drawing, &turning_frames, &t[1..], 10.0, None, &options).is_err());
    assert_eq!(a.keyframes, b.keyframes);
}

#[test]
fn lottie_gradients_follow_their_elements() {
    let n = 5;
    let (drawing, frames) = turning(n, 0.8);
    let rotation =
        |k: usize| Affine::rotate_about(0.8 * k as f64 / (n - 1) as f64, Point::new(50.0, 25.0));
    let maps = following(&drawing, n, rotation);
    let out = written(&drawing, &frames, 10.0, Some(&maps));
    assert!(
        !out.warnings.iter().any(|w| w.contains("at rest")),
        "{:?}",
        out.warnings
    );
    let doc: Value = serde_json::from_str(&out.json).unwrap();
    let fill = &doc["layers"][0]["shapes"][1]["it"][0]["it"][2];
    assert_eq!(fill["ty"], "gf");
    // The gradient's end (20, 0) at rest, turned with its element at each kept keyframe.
    let keys = fill["e"]["k"].as_array().unwrap();
    assert!(keys.len() >= 2 && fill["e"]["a"] == 1);
    for key in keys {
        let f = key["t"].as_f64().unwrap() as usize;
        let want = rotation(f) * Point::new(20.0, 0.0);
        let got = Point::new(key["s"][0].as_f64().unwrap(), key["s"][1].as_f64().unwrap());
        assert!(
            (got - want).hypot() < 1e-9,
            "frame {f}: {got:?} vs {want:?}"
        );
    }
    let wrong = write_lottie(
        &drawing,
        &frames,
        &times(n, 10.0),
        10.0,
        Some(&maps[1..]),
        &LottieOptions::default(),
    );
    assert!(wrong
        .unwrap_err()
        .to_string()
        .contains("4 element maps for 5 frames"));
}

#[test]
fn lottie_transform_parts_round_trip_general_maps() {
    for g in [
        Affine::new([2.0, 0.5, -0.3, 1.2, 7.0, -4.0]),
        Affine::rotate(2.9) * Affine::scale_non_uniform(0.2, -3.0) * Affine::skew(0.4, 0.0),
        Affine::FLIP_Y * Affine::translate((1e6, -2e6)),
    ] {
        let back = LottieParts::of(g).affine();
        let scale = g.as_coeffs().iter().fold(1.0f64, |m, v| m.max(v.abs()));
        for (a, b) in back.as_coeffs().iter().zip(g.as_coeffs()) {
            assert!((a - b).abs() <= 1e-12 * scale, "{g:?} -> {back:?}");
        }
    }
}

/// An elliptical radial gradient (stretched by its transform, then turning with its element)
/// is drawn in its own space: a group whose transform is the gradient's map at each frame, over
/// the path mapped back by it, so that the player draws the deformed path and the gradient's
/// true ellipse; nothing is approximated, so no warning.
#[test]
fn lottie_elliptical_gradient_fill_is_drawn_in_its_own_space() {
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100" viewBox="0 0 100 100">
      <radialGradient id="glow" cx="0" cy="0" r="10" gradientUnits="userSpaceOnUse"
          gradientTransform="translate(50 50) rotate(30) scale(1 3)">
        <stop offset="0" stop-color="#ffee00"/><stop offset="1" stop-color="#0044ff"/>
      </radialGradient>
      <path id="blob" d="M20 50 C20 20 80 20 80 50 C80 80 20 80 20 50 Z" fill="url(#glow)" stroke="#000"/>
    </svg>"##;
    let drawing = read_svg(svg, &ImportOptions::default()).unwrap();
    let n = 9;
    let motion = |k: usize| {
        let u = k as f64 / (n - 1) as f64;
        Affine::translate((10.0 * u, 0.0)) * Affine::rotate_about(1.2 * u, Point::new(50.0, 50.0))
    };
    let frames = moved(&drawing, n, motion);
    let maps = following(&drawing, n, motion);
    let out = written(&drawing, &frames, 8.0, Some(&maps));
    assert!(
        !out.warnings.iter().any(|w| w.contains("elliptical")),
        "{:?}",
        out.warnings
    );
    let doc: Value = serde_json::from_str(&out.json).unwrap();
    let element = &doc["layers"][0]["shapes"][0]["it"];
    let group = element
        .as_array()
        .unwrap()
        .iter()
        .find(|i| i["nm"] == "fill in gradient space")
        .expect("the fill has its gradient-space group");
    let items = group["it"].as_array().unwrap();
    let (shape, fill, transform) = (&items[0], &items[1], &items[2]);
    assert_eq!(fill["ty"], "gf");
    // In gradient units: the centre at the origin, the end on the unit circle of radius 10.
    assert_eq!(numbers(&fill["s"]["k"]), [0.0, 0.0]);
    assert_eq!(numbers(&fill["e"]["k"]), [10.0, 0.0]);
    // At every frame (most between keyframes), the group transform the player interpolates
    // applied to the vertices it interpolates is the deformed path within the tolerance, and the
    // gradient's ellipse is where the frame's map puts it.
    let gradient = Affine::translate((50.0, 50.0))
        * Affine::rotate(30f64.to_radians())
        * Affine::scale_non_uniform(1.0, 3.0);
    let tolerance = 1e-3 * drawing.diagonal() + 1e-9;
    let value = |p: &Value, f: f64| -> Vec<f64> {
        if p["a"] == 0 {
            return match &p["k"] {
                Value::Array(a) => a.iter().map(|v| v.as_f64().unwrap()).collect(),
                v => vec![v.as_f64().unwrap()],
            };
        }
        let keys = p["k"].as_array().unwrap();
        let time = |k: &Value| k["t"].as_f64().unwrap();
        let j = keys.iter().rposition(|k| time(k) <= f).unwrap();
        let s = |k: &Value| -> Vec<f64> {
            k["s"]
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_f64().unwrap())
                .collect()
        };
        if j + 1 == keys.len() {
            return s(&keys[j]);
        }
        let u = (f - time(&keys[j])) / (time(&keys[j + 1]) - time(&keys[j]));
        s(&keys[j])
            .iter()
            .zip(s(&keys[j + 1]))
            .map(|(a, b)| a + u * (b - a))
            .collect()
    };
    for k in 0..n {
        let f = k as f64;
        let parts = LottieParts {
            position: value(&transform["p"], f).try_into().unwrap(),
            scale: value(&transform["s"], f).try_into().unwrap(),
            rotation: value(&transform["r"], f)[0],
            skew: value(&transform["sk"], f)[0],
        };
        let shown = parts.affine();
        let drawn: Vec<Point> = played(shape, f).iter().map(|&p| shown * p).collect();
        for (p, q) in drawn.iter().zip(&frames[k]) {
            assert!((*p - *q).hypot() <= tolerance, "frame {k}: {p:?} vs {q:?}");
        }
        let truth = motion(k) * gradient;
        for q in [Point::ZERO, Point::new(10.0, 0.0), Point::new(0.0, 10.0)] {
            assert!(
                (shown * q - truth * q).hypot() <= tolerance,
                "frame {k}: gradient at {q:?}"
            );
        }
    }
    // Control: the same fill without its group would be a circle, not the ellipse (y stretched
    // by 3).
    assert!((gradient * Point::new(0.0, 10.0) - gradient * Point::ZERO).hypot() > 25.0);
}

/// A clipped group is a layer of its own, masked by the clip path's shapes (deformed and
/// keyframed as any path), between the layers of what is drawn above and below it; a group's
/// opacity over it becomes the layer's.
#[test]
fn lottie_clip_paths_become_layer_masks() {
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100" viewBox="0 0 100 100">
      <clipPath id="porthole"><circle cx="50" cy="50" r="20"/></clipPath>
      <rect id="below" x="0" y="0" width="100" height="100" fill="#88ccff"/>
      <g opacity="0.5">
        <g id="clipped" clip-path="url(#porthole)">
          <rect id="inside" x="20" y="20" width="60" height="60" fill="#ff8800"/>
        </g>
      </g>
      <path id="above" d="M10 90 L90 90" stroke="#000" stroke-width="4"/>
    </svg>"##;
    let drawing = read_svg(svg, &ImportOptions::default()).unwrap();
    let n = 6;
    let frames = moved(&drawing, n, |k| {
        Affine::rotate_about(0.6 * k as f64 / (n - 1) as f64, Point::new(50.0, 50.0))
    });
    let out = written(&drawing, &frames, 10.0, None);
    // Nothing approximated: the group with opacity holds the clipped group alone.
    assert!(out.warnings.is_empty(), "{:?}", out.warnings);
    let doc: Value = serde_json::from_str(&out.json).unwrap();
    let layers = doc["layers"].as_array().unwrap();
    assert_eq!(layers.len(), 3, "above, clipped, below");
    let names: Vec<&str> = layers.iter().map(|l| l["nm"].as_str().unwrap()).collect();
    assert_eq!(names[1], "clipped");
    assert!(
        layers[0].get("masksProperties").is_none() && layers[2].get("masksProperties").is_none()
    );
    let clipped = &layers[1];
    assert_eq!(clipped["hasMask"], true);
    assert_eq!(clipped["ks"]["o"]["k"], 50.0, "the group's opacity");
    let masks = clipped["masksProperties"].as_array().unwrap();
    assert_eq!(masks.len(), 1);
    assert_eq!(masks[0]["mode"], "a");
    // The mask is the clip circle, deformed: at every frame (between keyframes too) within the
    // tolerance of the frame's clip path.
    let source = drawing.source.as_deref().unwrap();
    let clip_path = (0..drawing.paths.len())
        .find(|&p| source.path_role(p) == PathRole::ClipPath)
        .expect("the clip circle is imported");
    let range = drawing.path_ranges().nth(clip_path).unwrap();
    let tolerance = 1e-3 * drawing.diagonal() + 1e-9;
    let mask_shape = serde_json::json!({"ks": masks[0]["pt"]});
    for (k, frame) in frames.iter().enumerate() {
        let shown = played(&mask_shape, k as f64);
        for (p, q) in shown.iter().zip(&frame[range.clone()]) {
            assert!((*p - *q).hypot() <= tolerance, "frame {k}: {p:?} vs {q:?}");
        }
    }
    // The clipped content is in its layer, the others in theirs.
    let mut inside = Vec::new();
    shapes(&clipped["shapes"], &mut inside);
    assert_eq!(inside.len(), 1);
    let mut above = Vec::new();
    shapes(&layers[0]["shapes"], &mut above);
    assert_eq!(above.len(), 1);
}

/// A gradient in `objectBoundingBox` units (SVG's default) follows the deformed element's
/// bounding box, as SVG draws it: stretched to twice its width, a round radial gradient on a
/// square becomes an ellipse, drawn in its own space with the box map at each frame.
#[test]
fn lottie_bounding_box_gradients_follow_the_deformed_box() {
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100" viewBox="0 0 100 100">
      <radialGradient id="spot"><stop offset="0" stop-color="#fff"/><stop offset="1" stop-color="#00f"/></radialGradient>
      <path id="tile" d="M10 10 H50 V50 H10 Z" fill="url(#spot)"/>
    </svg>"##;
    let drawing = read_svg(svg, &ImportOptions::default()).unwrap();
    let n = 5;
    let stretch = |k: usize| {
        Affine::translate((10.0, 0.0))
            * Affine::scale_non_uniform(1.0 + k as f64 / (n - 1) as f64, 1.0)
            * Affine::translate((-10.0, 0.0))
    };
    let frames = moved(&drawing, n, stretch);
    let out = written(&drawing, &frames, 10.0, None);
    assert!(out.warnings.is_empty(), "{:?}", out.warnings);
    let doc: Value = serde_json::from_str(&out.json).unwrap();
    let group = doc["layers"][0]["shapes"][0]["it"]
        .as_array()
        .unwrap()
        .iter()
        .find(|i| i["nm"] == "fill in gradient space")
        .expect("the stretched gradient is drawn in its own space")
        .clone();
    let transform = &group["it"].as_array().unwrap().last().unwrap().clone();
    // At the last frame the box is 80 × 40 from (10, 10): the gradient's unit circle maps onto
    // the ellipse inscribed in it (the centre (0.5, 0.5), radius 0.5 in box units).
    let keys = transform["s"]["k"].as_array().unwrap();
    let last = keys.last().unwrap();
    let scale: Vec<f64> = last["s"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert!(
        (scale[0] - 8000.0).abs() < 1e-6 && (scale[1] - 4000.0).abs() < 1e-6,
        "{scale:?}"
    );
    let p: Vec<f64> = transform["p"]["k"].as_array().unwrap().last().unwrap()["s"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert!(
        (p[0] - 10.0).abs() < 1e-9 && (p[1] - 10.0).abs() < 1e-9,
        "{p:?}"
    );
    // Control: the element's own map (none here) would have left it round at rest size.
    assert_eq!(numbers(&keys[0]["s"]), [4000.0, 4000.0]);
}

#[test]
fn lottie_names_every_text_it_leaves_out() {
    // Text is not animated (it is not a curve of the drawing): each outermost <text> is named,
    // with or without the fonts (usvg lays text out only with them).
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 50">
      <path id="wave" d="M10 10 C20 0 30 20 40 10" fill="none" stroke="#000"/>
      <text id="label" x="5" y="40">fish <tspan>tail</tspan></text>
      <g><text x="50" y="40">no id</text></g></svg>"##;
    let drawing = read_svg(svg, &ImportOptions::default()).unwrap();
    let rest = drawing.flat_points();
    let out = written(&drawing, &[rest.clone(), rest], 10.0, None);
    let texts: Vec<&String> = out
        .warnings
        .iter()
        .filter(|w| w.starts_with("text "))
        .collect();
    assert_eq!(texts.len(), 2, "{:?}", out.warnings);
    assert!(texts[0].starts_with("text label: not written"), "{texts:?}");
}

/// The coordinates' rounding stays within its share of the tolerance: a power of ten `g` with
/// `√2 g` at most the budget, to the nearest such, at any scale.
#[test]
fn lottie_coordinates_round_within_their_budget_at_any_scale() {
    assert_eq!(super::quantum_digits(0.0583), Some(2));
    assert_eq!(super::quantum_digits(0.0), None);
    assert_eq!(super::quantum_digits(f64::NAN), None);
    for scale in [1e-6, 1e-3, 1.0, 1e3, 1e6] {
        let budget = 0.0583 * scale;
        let digits = super::quantum_digits(budget).expect("digits");
        let g = 10f64.powi(-digits);
        assert!(std::f64::consts::SQRT_2 * g <= budget, "{scale}: {g}");
        assert!(
            std::f64::consts::SQRT_2 * 10.0 * g > budget,
            "{scale}: {g} is not the largest"
        );
        for x in [
            219.99999999999997,
            -5.522842407226534,
            1234.5678,
            1e6 + 0.123456,
        ] {
            let x = x * scale;
            let r = super::rounded(x, Some(digits));
            assert!(
                (r - x).abs() <= 0.5 * g * (1.0 + 1e-9),
                "{x} -> {r} (unit {g})"
            );
        }
    }
    assert_eq!(super::rounded(219.99999999999997, Some(2)), 220.0);
    assert_eq!(super::rounded(1234.5, Some(-2)), 1200.0);
    assert_eq!(super::rounded(0.1 + 0.2, None), 0.1 + 0.2);
}

#[test]
fn lottie_notes_what_some_players_draw_otherwise() {
    // A half-opaque group of two overlapping shapes, and a fill gradient sheared by its
    // transform (drawn in its own space through a skewed group).
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100">
      <defs><linearGradient id="g" x1="0" y1="0" x2="1" y2="0" gradientTransform="skewX(30)">
        <stop offset="0" stop-color="#f00"/><stop offset="1" stop-color="#00f"/></linearGradient></defs>
      <g id="pair" opacity="0.5"><rect x="10" y="10" width="40" height="40" fill="#00f"/>
        <rect x="30" y="30" width="40" height="40" fill="#f00"/></g>
      <rect id="sheared" x="10" y="70" width="80" height="20" fill="url(#g)"/></svg>"##;
    let drawing = read_svg(svg, &ImportOptions::default()).unwrap();
    let frames = moved(&drawing, 3, |k| Affine::translate((k as f64, 0.0)));
    let maps = following(&drawing, 3, |k| Affine::translate((k as f64, 0.0)));
    let out = written(&drawing, &frames, 24.0, Some(&maps));
    let noted = |needle: &str| out.player_notes.iter().any(|n| n.contains(needle));
    assert!(
        noted("pair: rlottie (1.3.8) and ThorVG (1.1.3) apply the group's opacity"),
        "{:?}",
        out.player_notes
    );
    assert!(
        noted("rect#sheared (line 6): rlottie (1.3.8) ignores the skew"),
        "{:?}",
        out.player_notes
    );
    // A control: the same shapes, opaque and with a plain gradient, need no note.
    let plain = svg
        .replace(r#" opacity="0.5""#, "")
        .replace(r#" gradientTransform="skewX(30)""#, "");
    let drawing = read_svg(&plain, &ImportOptions::default()).unwrap();
    let maps = following(&drawing, 3, |k| Affine::translate((k as f64, 0.0)));
    let out = written(&drawing, &frames, 24.0, Some(&maps));
    assert!(out.player_notes.is_empty(), "{:?}", out.player_notes);
}

#[test]
fn lottie_writes_a_path_that_stays_put_once() {
    // Two paths; only the first moves. The second is one static value (`"a": 0`), not a
    // keyframe per frame, and counts one keyframe in the total.
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100">
      <path id="moving" d="M10 10 C20 0 30 20 40 10" stroke="#000" fill="none"/>
      <path id="still" d="M10 60 C20 50 30 70 40 60" stroke="#000" fill="none"/></svg>"##;
    let drawing = read_svg(svg, &ImportOptions::default()).unwrap();
    let rest = drawing.flat_points();
    let n_first = drawing.paths[0].points.len();
    let frames: Vec<Vec<Point>> = (0..10)
        .map(|k| {
            let turn = Affine::rotate_about(0.05 * k as f64, Point::new(25.0, 10.0));
            rest.iter()
                .enumerate()
                .map(|(i, &p)| if i < n_first { turn * p } else { p })
                .collect()
        })
        .collect();
    let out = written(&drawing, &frames, 24.0, None);
    let doc: Value = serde_json::from_str(&out.json).unwrap();
    let mut found = Vec::new();
    shapes(&doc, &mut found);
    assert_eq!(found.len(), 2);
    let by_name = |name: &str| found.iter().find(|s| s["nm"] == name).unwrap().clone();
    let (moving, still) = (by_name("path 0"), by_name("path 1"));
    assert_eq!(still["ks"]["a"], 0, "the still path is written once");
    assert_eq!(moving["ks"]["a"], 1, "the moving one is keyframed");
    let moving_keys = moving["ks"]["k"].as_array().unwrap().len();
    assert_eq!(out.keyframes, moving_keys + 1);
    assert_eq!(out.every_frame_keyframes, 20);
    // And it is drawn where it is at every frame.
    let at_rest: Vec<Point> = played(&still, 0.0);
    assert_eq!(at_rest, played(&still, 9.0));
}
