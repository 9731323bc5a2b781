//! Validation of the raw attributes before usvg sees them: usvg and svgtypes silently truncate
//! bad numbers, transforms, points, viewBoxes and lengths; here they are errors naming the
//! element, the attribute and what was expected.
//!
//! Path data is the exception: browsers draw a `d` up to its first error (SVG 2, §9.5.4
//! "Error handling in path data"), and so do usvg and svgtypes. A `d` with an error is then
//! drawn up to it as they draw it, with a warning naming the element and the error's offset
//! ([`validate_document`]'s answer), rather than refusing the whole file.

use std::str::FromStr;

use super::{MAX_COORDINATE, MAX_QUOTED_VALUE};
use crate::document::{node_label, SvgError};

/// Attributes holding a `<length>` (or `auto` where allowed), per element.
pub(super) fn length_attributes(tag: &str) -> &'static [&'static str] {
    match tag {
        "rect" => &["x", "y", "width", "height", "rx", "ry"],
        "circle" => &["cx", "cy", "r"],
        "ellipse" => &["cx", "cy", "rx", "ry"],
        "line" => &["x1", "y1", "x2", "y2"],
        "use" | "svg" | "symbol" => &["x", "y", "width", "height"],
        _ => &[],
    }
}

/// Checks every geometry-relevant attribute of every SVG element: `transform`, `d`, `points`,
/// shape and `use` lengths, `viewBox` and `preserveAspectRatio`. Answers the warnings of what
/// is drawn other than written: path data drawn up to its first error (module doc).
pub(super) fn validate_document(
    doc: &roxmltree::Document,
    origin: &str,
) -> Result<Vec<String>, SvgError> {
    let mut warnings = Vec::new();
    for node in doc
        .descendants()
        .filter(|n| crate::document::is_svg_element(*n))
    {
        let tag = node.tag_name().name();
        let fail = |attribute: &str, value: &str, expected: String| SvgError::InvalidAttribute {
            file: origin.to_string(),
            element: node_label(doc, node),
            attribute: attribute.to_string(),
            value: shorten(value),
            expected,
        };
        for attr in node.attributes().filter(|a| a.namespace().is_none()) {
            let (name, value) = (attr.name(), attr.value());
            let result = match name {
                "transform" => check_transform(value),
                "d" if tag == "path" => check_path_data(value).map(|stop| {
                    if let Some((offset, error)) = stop {
                        warnings.push(format!(
                            "{origin}: {}: path data d=\"{}\" drawn up to its first error, at \
                             byte {offset} ({error}), as browsers draw it",
                            node_label(doc, node),
                            shorten(value)
                        ));
                    }
                }),
                "points" if tag == "polyline" || tag == "polygon" => check_points(value),
                "viewBox" if matches!(tag, "svg" | "symbol" | "marker" | "pattern" | "view") => {
                    check_view_box(value)
                }
                "preserveAspectRatio" => svgtypes::AspectRatio::from_str(value)
                    .map(|_| ())
                    .map_err(|e| {
                        format!("[defer] <align> [meet|slice], e.g. \"xMidYMid meet\" ({e})")
                    }),
                _ if length_attributes(tag).contains(&name) => check_length(name, value),
                _ => Ok(()),
            };
            result.map_err(|expected| fail(name, value, expected))?;
        }
    }
    for warning in &warnings {
        tracing::warn!("{warning}");
    }
    Ok(warnings)
}

pub(super) fn shorten(value: &str) -> String {
    if value.chars().count() <= MAX_QUOTED_VALUE {
        value.to_string()
    } else {
        let mut s: String = value.chars().take(MAX_QUOTED_VALUE).collect();
        s.push('…');
        s
    }
}

pub(super) fn check_number(v: f64, what: &str) -> Result<(), String> {
    if !v.is_finite() {
        Err(format!("finite numbers in {what} (found {v})"))
    } else if v.abs() > MAX_COORDINATE {
        Err(format!(
            "numbers within ±{MAX_COORDINATE:e} in {what} (found {v:e})"
        ))
    } else {
        Ok(())
    }
}

pub(super) fn check_transform(value: &str) -> Result<(), String> {
    const EXPECTED: &str = "a transform list (matrix, translate, scale, rotate, skewX, skewY)";
    for token in svgtypes::TransformListParser::from(value) {
        use svgtypes::TransformListToken as T;
        let numbers: Vec<f64> = match token.map_err(|e| format!("{EXPECTED} ({e})"))? {
            T::Matrix { a, b, c, d, e, f } => vec![a, b, c, d, e, f],
            T::Translate { tx, ty } => vec![tx, ty],
            T::Scale { sx, sy } => vec![sx, sy],
            T::Rotate { angle } => vec![angle],
            T::SkewX { angle } | T::SkewY { angle } => vec![angle],
        };
        if let Some(v) = numbers.into_iter().find(|v| !v.is_finite()) {
            return Err(format!("{EXPECTED} with finite numbers (found {v})"));
        }
    }
    // The product within MAX_COORDINATE too: beyond it usvg's f32 copy of the transform can
    // overflow, and usvg then drops the element silently (the document would have "no paths").
    let t = svgtypes::Transform::from_str(value).map_err(|e| format!("{EXPECTED} ({e})"))?;
    if [t.a, t.b, t.c, t.d, t.e, t.f]
        .iter()
        .all(|v| v.is_finite() && v.abs() <= MAX_COORDINATE)
    {
        Ok(())
    } else {
        Err(format!(
            "{EXPECTED} whose product has finite coefficients within ±{MAX_COORDINATE:e}"
        ))
    }
}

/// Checks the numbers of path data up to its first error, if any, and answers where that error
/// is (byte offset) and what it is: `Ok(None)` when the whole of it is valid. Browsers, usvg
/// and svgtypes draw the segments before the error (module doc).
pub(super) fn check_path_data(value: &str) -> Result<Option<(usize, String)>, String> {
    const WHAT: &str = "path data";
    for segment in svgtypes::PathParser::from(value) {
        use svgtypes::PathSegment as S;
        let segment = match segment {
            Ok(segment) => segment,
            Err(e) => return Ok(Some((error_offset(&e, value), e.to_string()))),
        };
        let numbers: &[f64] = match &segment {
            S::MoveTo { x, y, .. } | S::LineTo { x, y, .. } | S::SmoothQuadratic { x, y, .. } => {
                &[*x, *y]
            }
            S::HorizontalLineTo { x, .. } => &[*x],
            S::VerticalLineTo { y, .. } => &[*y],
            S::CurveTo {
                x1,
                y1,
                x2,
                y2,
                x,
                y,
                ..
            } => &[*x1, *y1, *x2, *y2, *x, *y],
            S::SmoothCurveTo { x2, y2, x, y, .. } => &[*x2, *y2, *x, *y],
            S::Quadratic { x1, y1, x, y, .. } => &[*x1, *y1, *x, *y],
            S::EllipticalArc {
                rx,
                ry,
                x_axis_rotation,
                x,
                y,
                ..
            } => &[*rx, *ry, *x_axis_rotation, *x, *y],
            S::ClosePath { .. } => &[],
        };
        for &v in numbers {
            check_number(v, WHAT)?;
        }
    }
    Ok(None)
}

/// The byte offset in `value` an svgtypes error points at (its positions count characters
/// from 1); the end of `value` when it names none.
fn error_offset(error: &svgtypes::Error, value: &str) -> usize {
    use svgtypes::Error as E;
    match *error {
        E::UnexpectedData(p)
        | E::InvalidNumber(p)
        | E::InvalidChar(_, p)
        | E::InvalidString(_, p) => value
            .char_indices()
            .nth(p.saturating_sub(1))
            .map_or(value.len(), |(at, _)| at),
        _ => value.len(),
    }
}

pub(super) fn check_points(value: &str) -> Result<(), String> {
    let mut count = 0usize;
    for number in svgtypes::NumberListParser::from(value) {
        let v = number.map_err(|e| format!("a list of x,y coordinates ({e})"))?;
        check_number(v, "points")?;
        count += 1;
    }
    if count % 2 == 1 {
        return Err(format!(
            "an even number of coordinates (x,y pairs); found {count}"
        ));
    }
    Ok(())
}

pub(super) fn check_view_box(value: &str) -> Result<(), String> {
    const EXPECTED: &str =
        "four numbers \"min-x min-y width height\" with positive width and height";
    let vb = svgtypes::ViewBox::from_str(value).map_err(|e| format!("{EXPECTED} ({e})"))?;
    for v in [vb.x, vb.y, vb.w, vb.h] {
        check_number(v, "viewBox")?;
    }
    if vb.w > 0.0 && vb.h > 0.0 {
        Ok(())
    } else {
        Err(EXPECTED.to_string())
    }
}

pub(super) fn check_length(name: &str, value: &str) -> Result<(), String> {
    let auto_allowed = matches!(name, "rx" | "ry" | "width" | "height");
    if auto_allowed && value.trim() == "auto" {
        return Ok(());
    }
    let length = svgtypes::Length::from_str(value)
        .map_err(|e| format!("a length such as \"10\", \"2.5px\" or \"50%\" ({e})"))?;
    check_number(length.number, "a length")
}
