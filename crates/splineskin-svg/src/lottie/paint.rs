//! Fills and strokes as Lottie style items (`fl`, `gf`, `st`, `gs`), in root user space.
//!
//! An element's paint is in its local coordinates; the export writes geometry in root user
//! space, so widths, dash lengths and gradient geometry are mapped by the element's local →
//! root map `M`. A similarity (rotation, uniform scale, reflection, translation) maps them
//! exactly: lengths scale by `√|det M|`. Any other map is approximated (lengths by that mean
//! scale, a gradient by its mapped end points) and named in a warning.

use kurbo::{Affine, Point};
use serde_json::{json, Value};

use super::Warnings;
use crate::svg_in::affine;

/// A Lottie style item and, for a gradient, its end points (`s`, `e`, root user space, at
/// rest), which the writer keyframes through the element's maps.
///
/// A fill gradient that a Lottie gradient cannot draw in root user space (an elliptical radial
/// gradient, a sheared linear one) is written in its own space instead: `space` is then the map
/// `G` from gradient units to root user space, the style's geometry is in gradient units, and
/// the writer puts the fill in a group whose transform is `G` (following the element's maps)
/// over the paths mapped by `G⁻¹` — exact, since Lottie's group transform is a general affine
/// map.
pub(super) struct Style {
    pub value: Value,
    pub ends: Option<[Point; 2]>,
    pub space: Option<Affine>,
}

/// Relative difference of a map's two singular values above which it is not a similarity.
const SIMILARITY_TOLERANCE: f64 = 1e-9;

/// The Lottie fill of a usvg fill, or `None` (with a warning) for what Lottie cannot fill with.
/// `carried`: the maps that carry its paint from rest to each frame (root user space), if
/// known; a gradient Lottie cannot draw in root space at rest or at any of them is drawn in
/// its own space ([`Style::space`]).
pub(super) fn fill(
    fill: &usvg::Fill,
    map: Affine,
    carried: Option<&[Affine]>,
    label: &str,
    warnings: &mut Warnings,
) -> Option<Style> {
    let mut style = painted(
        fill.paint(),
        ["fl", "gf"],
        "fill",
        true,
        map,
        label,
        warnings,
    )?;
    if let (usvg::Paint::LinearGradient(_) | usvg::Paint::RadialGradient(_), Some(ends)) =
        (fill.paint(), style.ends)
    {
        let m = gradient_map(fill.paint(), map);
        let at_every_frame = carried
            .unwrap_or(&[])
            .iter()
            .all(|&a| expressible(fill.paint(), a * m, ends.map(|p| a * p)));
        if !expressible(fill.paint(), m, ends) || !at_every_frame {
            // Drawn in the gradient's own space (the writer's group transform maps it).
            let (mut value, ends) = gradient(fill.paint(), None, true, label, "fill", warnings)?;
            value["ty"] = json!("gf");
            value["nm"] = json!("gradient fill");
            style = Style {
                value,
                ends: Some(ends),
                space: Some(m),
            };
        }
    }
    Some(with_fill_settings(style, fill))
}

/// `style` with the opacity and fill rule of `fill`.
fn with_fill_settings(mut style: Style, fill: &usvg::Fill) -> Style {
    style.value["o"] = json!({"a": 0, "k": 100.0 * f64::from(fill.opacity().get())});
    style.value["r"] = json!(match fill.rule() {
        usvg::FillRule::NonZero => 1,
        usvg::FillRule::EvenOdd => 2,
    });
    style
}

/// The Lottie fill of a usvg fill in root user space whatever its gradient (approximated, with
/// a warning, where Lottie's gradients cannot draw it there).
pub(super) fn fill_in_root_space(
    fill: &usvg::Fill,
    map: Affine,
    label: &str,
    warnings: &mut Warnings,
) -> Option<Style> {
    let style = painted(
        fill.paint(),
        ["fl", "gf"],
        "fill",
        false,
        map,
        label,
        warnings,
    )?;
    Some(with_fill_settings(style, fill))
}

/// The Lottie stroke of a usvg stroke, or `None` (with a warning) for what Lottie cannot
/// stroke with.
pub(super) fn stroke(
    stroke: &usvg::Stroke,
    map: Affine,
    label: &str,
    warnings: &mut Warnings,
) -> Option<Style> {
    let scale = mean_scale(map);
    if !is_similarity(map) {
        warnings.add(format!(
            "{label}: its stroke is under a non-uniform transform; written with the mean \
             scale {scale} (widths along and across differ in the source)"
        ));
    }
    let opacity = 100.0 * f64::from(stroke.opacity().get());
    let cap = match stroke.linecap() {
        usvg::LineCap::Butt => 1,
        usvg::LineCap::Round => 2,
        usvg::LineCap::Square => 3,
    };
    let join = match stroke.linejoin() {
        usvg::LineJoin::Miter | usvg::LineJoin::MiterClip => 1,
        usvg::LineJoin::Round => 2,
        usvg::LineJoin::Bevel => 3,
    };
    let mut style = painted(
        stroke.paint(),
        ["st", "gs"],
        "stroke",
        false,
        map,
        label,
        warnings,
    )?;
    let value = &mut style.value;
    value["o"] = json!({"a": 0, "k": opacity});
    value["w"] = json!({"a": 0, "k": scale * f64::from(stroke.width().get())});
    value["lc"] = json!(cap);
    value["lj"] = json!(join);
    value["ml"] = json!(f64::from(stroke.miterlimit().get()));
    if let Some(dashes) = stroke.dasharray() {
        let mut d: Vec<Value> = dashes
            .iter()
            .enumerate()
            .map(|(k, &len)| {
                // Names unique within the stroke: lottie-web makes a property of each name
                // and draws nothing of the layer when two dashes share one.
                let (n, nm) = if k % 2 == 0 {
                    ("d", format!("dash {}", k / 2))
                } else {
                    ("g", format!("gap {}", k / 2))
                };
                json!({"n": n, "nm": nm, "v": {"a": 0, "k": scale * f64::from(len)}})
            })
            .collect();
        d.push(json!({
            "n": "o",
            "nm": "offset",
            "v": {"a": 0, "k": scale * f64::from(stroke.dashoffset())}
        }));
        value["d"] = json!(d);
        warnings.player(format!(
            "{label}: rlottie (1.3.8) places its stroke's dashes elsewhere along the path than \
             browsers and the other players do"
        ));
    }
    Some(style)
}

/// The style item of `paint` used for `what` ("fill" or "stroke"): of type `types[0]` with
/// its colour, or `types[1]` with its gradient (and the gradient's end points). `quiet`: no
/// warning about gradient geometry Lottie cannot draw (the caller handles it).
fn painted(
    paint: &usvg::Paint,
    types: [&str; 2],
    what: &str,
    quiet: bool,
    map: Affine,
    label: &str,
    warnings: &mut Warnings,
) -> Option<Style> {
    Some(match paint {
        usvg::Paint::Color(c) => Style {
            value: json!({"ty": types[0], "nm": what, "c": {"a": 0, "k": color(*c)}}),
            ends: None,
            space: None,
        },
        paint => {
            let (mut value, ends) = gradient(paint, Some(map), quiet, label, what, warnings)?;
            value["ty"] = json!(types[1]);
            value["nm"] = json!(format!("gradient {what}"));
            Style {
                value,
                ends: Some(ends),
                space: None,
            }
        }
    })
}

/// The geometry and colours of a gradient paint (`t`, `s`, `e`, `h`, `a`, `g`), in root user
/// space, and its end points `s`, `e`; `None` with a warning for a pattern.
///
/// `map`: the element's local → root map, or `None` for the geometry in the gradient's own
/// units (its transform not applied either: see [`Style::space`]). `quiet`: no warning about
/// geometry Lottie cannot draw (the caller handles it).
fn gradient(
    paint: &usvg::Paint,
    map: Option<Affine>,
    quiet: bool,
    label: &str,
    what: &str,
    warnings: &mut Warnings,
) -> Option<(Value, [Point; 2])> {
    let to_root =
        |transform: usvg::Transform| map.map_or(Affine::IDENTITY, |m| m * affine(transform));
    let (base, mut out, ends) = match paint {
        usvg::Paint::LinearGradient(g) => {
            let m = to_root(g.transform());
            let s = m * Point::new(f64::from(g.x1()), f64::from(g.y1()));
            let e = m * Point::new(f64::from(g.x2()), f64::from(g.y2()));
            if !keeps_stripes_square(
                m,
                e - s,
                Point::new(f64::from(g.x2() - g.x1()), f64::from(g.y2() - g.y1())).to_vec2(),
            ) && !quiet
            {
                warnings.add(format!(
                    "{label}: its {what} gradient is sheared by its transform (its stripes are \
                     not square to its axis), which Lottie cannot draw: written through its \
                     mapped end points"
                ));
            }
            (&**g as &usvg::BaseGradient, json!({"t": 1}), [s, e])
        }
        usvg::Paint::RadialGradient(g) => {
            let m = to_root(g.transform());
            let c = Point::new(f64::from(g.cx()), f64::from(g.cy()));
            let r = f64::from(g.r().get());
            let f = Point::new(f64::from(g.fx()), f64::from(g.fy()));
            let s = m * c;
            let e = m * (c + kurbo::Vec2::new(r, 0.0));
            // The focal point as Lottie's highlight: its distance from the centre as a
            // percentage of the radius, at an angle from the start → end direction.
            let (fm, radius) = (m * f, (e - s).hypot());
            let offset = fm - s;
            let h = if radius > 0.0 {
                100.0 * offset.hypot() / radius
            } else {
                0.0
            };
            let a = (offset.y.atan2(offset.x) - (e - s).y.atan2((e - s).x)).to_degrees();
            if !is_similarity(m) && !quiet {
                warnings.add(format!(
                    "{label}: its {what} gradient is elliptical (non-uniform transform); \
                     Lottie's radial gradients are circular: written with the radius along x"
                ));
            }
            if g.fr().get() > 0.0 {
                warnings.add(format!(
                    "{label}: its {what} gradient's focal radius is not written"
                ));
            }
            let highlight = json!({"t": 2, "h": {"a": 0, "k": h}, "a": {"a": 0, "k": a}});
            (&**g as &usvg::BaseGradient, highlight, [s, e])
        }
        usvg::Paint::Pattern(p) => {
            warnings.add(format!(
                "{label}: its {what} is a pattern ({}), which Lottie has no equivalent for: not \
                 written",
                p.id()
            ));
            return None;
        }
        usvg::Paint::Color(_) => unreachable!("colours are written by the callers"),
    };
    if base.spread_method() != usvg::SpreadMethod::Pad {
        warnings.add(format!(
            "{label}: its {what} gradient repeats or reflects, which Lottie cannot: written padded"
        ));
    }
    let stops = base.stops();
    let mut colours = Vec::with_capacity(4 * stops.len());
    for s in stops {
        colours.push(f64::from(s.offset().get()));
        colours.extend(color(s.color()).into_iter().take(3));
    }
    if stops.iter().any(|s| s.opacity().get() < 1.0) {
        warnings.player(format!(
            "{label}: rlottie (1.3.8) blends its {what} gradient's stop opacities otherwise than \
             browsers and the other players: the colours between stops differ"
        ));
        for s in stops {
            colours.push(f64::from(s.offset().get()));
            colours.push(f64::from(s.opacity().get()));
        }
    }
    out["s"] = json!({"a": 0, "k": xy(ends[0])});
    out["e"] = json!({"a": 0, "k": xy(ends[1])});
    out["g"] = json!({"p": stops.len(), "k": {"a": 0, "k": colours}});
    Some((out, ends))
}

/// The map from a gradient's own units to root user space: the element's local → root map
/// `map` after the gradient's transform.
fn gradient_map(paint: &usvg::Paint, map: Affine) -> Affine {
    match paint {
        usvg::Paint::LinearGradient(g) => map * affine(g.transform()),
        usvg::Paint::RadialGradient(g) => map * affine(g.transform()),
        _ => map,
    }
}

/// Whether a Lottie gradient in root user space draws `paint` under `m` (its
/// [`gradient_map`]) exactly: a radial one under a similarity, a linear one whose stripes stay
/// square to its axis; `ends` are its end points mapped.
fn expressible(paint: &usvg::Paint, m: Affine, ends: [Point; 2]) -> bool {
    match paint {
        usvg::Paint::RadialGradient(_) => is_similarity(m),
        usvg::Paint::LinearGradient(g) => keeps_stripes_square(
            m,
            ends[1] - ends[0],
            kurbo::Vec2::new(f64::from(g.x2() - g.x1()), f64::from(g.y2() - g.y1())),
        ),
        _ => true,
    }
}

/// A colour as Lottie's `[r, g, b, 1]` in `[0, 1]`.
fn color(c: usvg::Color) -> [f64; 4] {
    [
        f64::from(c.red) / 255.0,
        f64::from(c.green) / 255.0,
        f64::from(c.blue) / 255.0,
        1.0,
    ]
}

fn xy(p: Point) -> [f64; 2] {
    [p.x, p.y]
}

/// Whether a linear gradient along `axis` (its own coordinates) still has stripes square to its
/// axis under `m`, whose image of `axis` is `mapped`: Lottie draws a linear gradient's stripes
/// square to its axis, SVG draws the image of the square ones.
fn keeps_stripes_square(m: Affine, mapped: kurbo::Vec2, axis: kurbo::Vec2) -> bool {
    let [a, b, c, d, _, _] = m.as_coeffs();
    let stripe = kurbo::Vec2::new(-axis.y, axis.x);
    let image = kurbo::Vec2::new(a * stripe.x + c * stripe.y, b * stripe.x + d * stripe.y);
    let scale = mapped.hypot() * image.hypot();
    scale == 0.0 || mapped.dot(image).abs() <= SIMILARITY_TOLERANCE * scale
}

/// `√|det M|`: the factor a similarity scales lengths by.
fn mean_scale(m: Affine) -> f64 {
    m.determinant().abs().sqrt()
}

/// Whether the linear part of `m` is a rotation or reflection times a uniform scale: its two
/// columns orthogonal and of equal length (relative to their size).
fn is_similarity(m: Affine) -> bool {
    let [a, b, c, d, _, _] = m.as_coeffs();
    let (n1, n2) = (a * a + b * b, c * c + d * d);
    let scale = n1.max(n2);
    scale == 0.0
        || ((n1 - n2).abs() <= SIMILARITY_TOLERANCE * scale
            && (a * c + b * d).abs() <= SIMILARITY_TOLERANCE * scale)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn similarity_test_tells_uniform_from_stretched_maps() {
        assert!(is_similarity(Affine::rotate(0.3) * Affine::scale(2.5)));
        assert!(is_similarity(
            Affine::FLIP_X * Affine::translate((3.0, 4.0))
        ));
        assert!(!is_similarity(Affine::scale_non_uniform(1.0, 1.01)));
        assert!(!is_similarity(Affine::skew(0.1, 0.0)));
        assert!((mean_scale(Affine::rotate(1.0) * Affine::scale(3.0)) - 3.0).abs() < 1e-15);
        // A horizontal gradient stretched along its axes keeps square stripes; a diagonal one
        // does not.
        let stretch = Affine::scale_non_uniform(3.0, 1.0);
        let x = kurbo::Vec2::new(1.0, 0.0);
        assert!(keeps_stripes_square(stretch, kurbo::Vec2::new(3.0, 0.0), x));
        let diagonal = kurbo::Vec2::new(1.0, 1.0);
        assert!(!keeps_stripes_square(
            stretch,
            kurbo::Vec2::new(3.0, 1.0),
            diagonal
        ));
    }
}
