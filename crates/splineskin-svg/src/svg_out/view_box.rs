//! The root `viewBox` of an exported drawing: whether the deformed art leaves it
//! ([`art_outside_view_box`]), the art's bounding box ([`art_bounds`]), and what export does about
//! it ([`ViewBoxRule`]: keep it, or grow it and `width`/`height` in proportion).

use kurbo::{Point, Rect};

use splineskin_core::drawing::source::SvgSource;
use splineskin_core::drawing::{Drawing, Path};

use super::chain_offsets;
use crate::document::{number, push_numbers, SvgError};

/// What export does with the root `viewBox` when the deformed art leaves it.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
#[non_exhaustive]
pub enum ViewBoxRule {
    /// Keep the input's viewBox (art outside it is cropped by viewers). The default.
    #[default]
    Keep,
    /// Grow the viewBox to the union of the input's and the deformed art's bounding box
    /// ([`art_bounds`]: the paths [`art_outside_view_box`] looks at), and `width`/`height` in
    /// proportion (same units; percentages are kept), so that the drawing keeps its scale on
    /// screen.
    Fit,
    /// As [`ViewBoxRule::Fit`], with the art's bounding box given: the viewBox becomes the
    /// union of the input's and this rectangle (root user units). An animation passes the
    /// union of [`art_bounds`] over its frames, so that every frame has the same viewBox and
    /// holds the art of all of them.
    FitTo(Rect),
}

/// A path whose deformed curves leave the document's viewBox.
#[derive(Clone, Debug, PartialEq)]
pub struct OutsideViewBox {
    /// Index into [`Drawing::paths`].
    pub path_index: usize,
    /// The element it comes from (`tag#id (line n)`).
    pub element: String,
    /// How far its curves' bounding box reaches beyond the viewBox, in root user units (the
    /// largest overshoot over the four sides; strokes not counted).
    pub distance: f64,
}

/// Whether path `i` counts for the viewBox: drawn or hidden art (what shows, or shows once its
/// layer is unhidden); not clip geometry, mask content or unpainted paths.
fn counts_for_view_box(drawing: &Drawing, i: usize) -> bool {
    matches!(
        drawing.path_role(i),
        splineskin_core::drawing::PathRole::Visible | splineskin_core::drawing::PathRole::Hidden
    )
}

/// The exact bounding box of path `path`'s curves through `points` (its chain points).
fn curves_bounds(path: &Path, points: &[Point]) -> Rect {
    use kurbo::ParamCurveExtrema;
    let mut r = Rect::from_points(points[0], points[0]);
    for j in 0..path.n_curves() {
        let c = kurbo::CubicBez::new(
            points[3 * j],
            points[3 * j + 1],
            points[3 * j + 2],
            points[3 * j + 3],
        );
        r = r.union(c.bounding_box());
    }
    r
}

/// The paths of `drawing` (art only: drawn or hidden, see [`ViewBoxRule::Fit`]) whose curves
/// through the deformed `points` (laid out like [`Drawing::flat_points`]) reach outside the
/// document's viewBox, with how far. Empty for a drawing without a source document.
///
/// Errors: [`SvgError::PointCount`], [`SvgError::NonFinitePoint`].
///
/// ```
/// use kurbo::Vec2;
/// use splineskin_svg::svg_in::{read_svg, ImportOptions};
/// use splineskin_svg::svg_out::art_outside_view_box;
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10">
///   <rect id="box" x="1" y="1" width="2" height="2"/></svg>"#;
/// let drawing = read_svg(svg, &ImportOptions::default()).unwrap();
/// let moved: Vec<_> = drawing.flat_points().iter().map(|&p| p + Vec2::new(8.5, 0.0)).collect();
/// let outside = art_outside_view_box(&drawing, &moved).unwrap();
/// assert_eq!(outside[0].element, "rect#box (line 2)");
/// assert!((outside[0].distance - 1.5).abs() < 1e-12);
/// ```
pub fn art_outside_view_box(
    drawing: &Drawing,
    points: &[Point],
) -> Result<Vec<OutsideViewBox>, SvgError> {
    let offsets = chain_offsets(drawing, points)?;
    let Some(source) = &drawing.source else {
        return Ok(Vec::new());
    };
    let vb = source.view_box;
    let mut out = Vec::new();
    for (i, path) in drawing.paths.iter().enumerate() {
        if !counts_for_view_box(drawing, i) {
            continue;
        }
        let r = curves_bounds(path, &points[offsets[i]..offsets[i] + path.points.len()]);
        let distance = [vb.x0 - r.x0, r.x1 - vb.x1, vb.y0 - r.y0, r.y1 - vb.y1]
            .into_iter()
            .fold(0.0f64, f64::max);
        if distance > 0.0 {
            out.push(OutsideViewBox {
                path_index: i,
                element: source.element_label(i),
                distance,
            });
        }
    }
    Ok(out)
}

/// The union of the exact bounding boxes of the art paths of `drawing` (drawn or hidden, not
/// clip geometry, mask content or unpainted paths; strokes not counted) through `points` (laid
/// out like [`Drawing::flat_points`]), in root user units; `None` when the drawing has no art
/// path. For an animation, the union of this over its frames is what [`ViewBoxRule::FitTo`]
/// takes.
///
/// Errors: [`SvgError::PointCount`], [`SvgError::NonFinitePoint`].
///
/// ```
/// use kurbo::{Rect, Vec2};
/// use splineskin_svg::svg_in::{read_svg, ImportOptions};
/// use splineskin_svg::svg_out::art_bounds;
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10">
///   <rect x="1" y="1" width="2" height="2"/><circle cx="5" cy="5" r="1"/></svg>"#;
/// let drawing = read_svg(svg, &ImportOptions::default()).unwrap();
/// let moved: Vec<_> = drawing.flat_points().iter().map(|&p| p + Vec2::new(8.0, 0.0)).collect();
/// let r = art_bounds(&drawing, &moved).unwrap().unwrap();
/// let expected = Rect::new(9.0, 1.0, 14.0, 6.0);
/// assert!((r.x0 - expected.x0).abs() + (r.x1 - expected.x1).abs() < 1e-12, "{r:?}");
/// assert!((r.y0 - expected.y0).abs() + (r.y1 - expected.y1).abs() < 1e-12, "{r:?}");
/// ```
pub fn art_bounds(drawing: &Drawing, points: &[Point]) -> Result<Option<Rect>, SvgError> {
    let offsets = chain_offsets(drawing, points)?;
    Ok(art_bounds_at(drawing, points, &offsets))
}

/// [`art_bounds`] with the chain offsets checked already.
pub(crate) fn art_bounds_at(
    drawing: &Drawing,
    points: &[Point],
    offsets: &[usize],
) -> Option<Rect> {
    let mut bounds: Option<Rect> = None;
    for (i, path) in drawing.paths.iter().enumerate() {
        if counts_for_view_box(drawing, i) {
            let r = curves_bounds(path, &points[offsets[i]..offsets[i] + path.points.len()]);
            bounds = Some(bounds.map_or(r, |b| b.union(r)));
        }
    }
    bounds
}

/// The attributes `rule` sets on the root element of the export of `points` (none for
/// [`ViewBoxRule::Keep`], or when the art stays inside the viewBox).
///
/// Errors: [`SvgError::NonFinitePoint`] for a [`ViewBoxRule::FitTo`] rectangle that is not
/// finite (its corner counted as point 0 or 1).
pub(crate) fn root_attributes(
    drawing: &Drawing,
    points: &[Point],
    offsets: &[usize],
    source: &SvgSource,
    rule: ViewBoxRule,
) -> Result<Vec<(&'static str, String)>, SvgError> {
    Ok(match rule {
        ViewBoxRule::Keep => Vec::new(),
        ViewBoxRule::Fit => match art_bounds_at(drawing, points, offsets) {
            Some(bounds) => fitted_root(source, bounds),
            None => Vec::new(),
        },
        ViewBoxRule::FitTo(bounds) => {
            if let Some(index) = [bounds.origin(), Point::new(bounds.x1, bounds.y1)]
                .iter()
                .position(|p| !p.is_finite())
            {
                return Err(SvgError::NonFinitePoint {
                    file: source.origin.clone(),
                    element: "the corners of the viewBox to fit".to_string(),
                    index,
                });
            }
            fitted_root(source, bounds)
        }
    })
}

/// The root attributes of [`ViewBoxRule::FitTo`]`(bounds)` (`bounds` finite): none when
/// `bounds` lies inside the viewBox.
fn fitted_root(source: &SvgSource, bounds: Rect) -> Vec<(&'static str, String)> {
    let vb = source.view_box;
    let r = vb.union(bounds.abs());
    if r == vb {
        return Vec::new();
    }
    let mut set = vec![("viewBox", {
        let mut s = String::new();
        push_numbers(&mut s, &[r.x0, r.y0, r.width(), r.height()]);
        s
    })];
    let Ok(doc) = crate::document::parse_xml(&source.text, &source.origin) else {
        return set;
    };
    let root = doc.root_element();
    // width and height grow in proportion, in their own units; absent ones are the viewBox's
    // size (usvg's resolution), written in user units.
    for (name, old, new, size) in [
        ("width", vb.width(), r.width(), source.size.width),
        ("height", vb.height(), r.height(), source.size.height),
    ] {
        use svgtypes::LengthUnit as U;
        match root.attribute(name) {
            Some(v) => {
                let Ok(length) = <svgtypes::Length as std::str::FromStr>::from_str(v) else {
                    continue;
                };
                let unit = match length.unit {
                    U::None => "",
                    U::Px => "px",
                    U::In => "in",
                    U::Cm => "cm",
                    U::Mm => "mm",
                    U::Pt => "pt",
                    U::Pc => "pc",
                    U::Em => "em",
                    U::Ex => "ex",
                    U::Percent => continue,
                };
                set.push((name, format!("{}{unit}", number(length.number * new / old))));
            }
            None => set.push((name, number(size * new / old))),
        }
    }
    set
}
