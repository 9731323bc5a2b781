//! Animated SVG export: the document of [`super::svg_out`] with each deformed element's `d`
//! animated by SMIL, one value per frame.
//!
//! Every imported element is written as [`super::svg_out::write_svg`] writes it for the first
//! frame (its `d` is frame 0, so a renderer without SMIL, such as resvg, shows the first
//! frame), and gets as its first child
//!
//! ```text
//! <animate attributeName="d" dur="Ds" repeatCount="indefinite" calcMode="linear"
//!          keyTimes="0;t₁/D;…;1" values="d₀;d₁;…;d_{N−1}"/>
//! ```
//!
//! with `D` the last frame's time. Every value has the same commands (`M`, one `C` per cubic,
//! `Z` as in the source) because the deformation moves points and never changes the
//! structure, so browsers interpolate between frames linearly, point by point. Numbers are
//! written in the shortest form that reads back to the same `f64`, as in the static export.

use std::fmt::Write as _;

use kurbo::{Affine, Point};

use super::svg_out::{
    art_bounds_at, chain_offsets, element_path_data, export_geometry_root, push_path_data,
    root_attributes, ViewBoxRule,
};
use super::{Drawing, SvgError};

/// Why an animated document could not be written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum AnimateError {
    /// The frames or their times are not a valid animation (the message says what was
    /// expected).
    #[error("cannot animate: {what}")]
    InvalidFrames {
        /// What is wrong.
        what: String,
    },
    /// A frame's points could not be written (wrong count, not finite, …).
    #[error("frame {frame}: {source}")]
    Frame {
        /// The frame index.
        frame: usize,
        /// The writer's error, naming the file and element.
        source: Box<SvgError>,
    },
    /// The document could not be rewritten.
    #[error(transparent)]
    Svg(#[from] Box<SvgError>),
}

/// Writes `drawing` animated through `frames` (each `drawing.n_points()` points laid out like
/// [`Drawing::flat_points`]) at `times` (seconds: the first 0, strictly increasing, one per
/// frame, at least two frames), looping forever.
///
/// Errors: [`AnimateError::InvalidFrames`] for fewer than two frames, times not starting at 0
/// or not increasing or not one per frame; [`AnimateError::Frame`] naming the frame for the
/// errors of [`super::svg_out::write_svg`].
///
/// ```
/// use kurbo::Vec2;
/// use splineskin::drawing::svg_animate::write_animated_svg;
/// use splineskin::drawing::svg_in::{read_svg, ImportOptions};
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10">
///   <path d="M0 0 C1 1 2 1 3 0"/></svg>"#;
/// let drawing = read_svg(svg, &ImportOptions::default()).unwrap();
/// let rest = drawing.flat_points();
/// let moved: Vec<_> = rest.iter().map(|&p| p + Vec2::new(0.0, 2.0)).collect();
/// let out = write_animated_svg(&drawing, &[rest, moved], &[0.0, 0.5]).unwrap();
/// assert!(out.contains(r#"<path d="M0 0 C1 1 2 1 3 0"><animate attributeName="d" dur="0.5s""#));
/// assert!(out.contains(r#"keyTimes="0;1" values="M0 0 C1 1 2 1 3 0;M0 2 C1 3 2 3 3 2"/></path>"#));
/// ```
pub fn write_animated_svg(
    drawing: &Drawing,
    frames: &[Vec<Point>],
    times: &[f64],
) -> Result<String, AnimateError> {
    write_animated_svg_view_box(drawing, frames, times, ViewBoxRule::Keep)
}

/// [`write_animated_svg`] with the root viewBox chosen by `view_box` ([`ViewBoxRule`]), one
/// for the whole animation: [`ViewBoxRule::Fit`] grows it to the union of the input's viewBox
/// and the art's bounding box over every frame ([`super::svg_out::art_bounds`] of each), so
/// that the animation does not crop any frame and does not jump.
///
/// ```
/// use kurbo::Vec2;
/// use splineskin::drawing::svg_animate::write_animated_svg_view_box;
/// use splineskin::drawing::svg_in::{read_svg, ImportOptions};
/// use splineskin::drawing::svg_out::ViewBoxRule;
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10">
///   <path d="M1 1 C2 2 3 2 4 1"/></svg>"#;
/// let drawing = read_svg(svg, &ImportOptions::default()).unwrap();
/// let rest = drawing.flat_points();
/// let left: Vec<_> = rest.iter().map(|&p| p + Vec2::new(-3.0, 0.0)).collect();
/// let right: Vec<_> = rest.iter().map(|&p| p + Vec2::new(8.0, 0.0)).collect();
/// let frames = [rest, left, right];
/// let out = write_animated_svg_view_box(&drawing, &frames, &[0.0, 1.0, 2.0], ViewBoxRule::Fit)
///     .unwrap();
/// // x from -2 (frame 1) to 12 (frame 2), y from the input's 0 to 10.
/// assert!(out.contains(r#"viewBox="-2 0 14 10""#), "{out}");
/// ```
pub fn write_animated_svg_view_box(
    drawing: &Drawing,
    frames: &[Vec<Point>],
    times: &[f64],
    view_box: ViewBoxRule,
) -> Result<String, AnimateError> {
    let invalid = |what: String| AnimateError::InvalidFrames { what };
    if frames.len() < 2 {
        return Err(invalid(format!(
            "{} frames (expected at least 2)",
            frames.len()
        )));
    }
    if times.len() != frames.len() {
        return Err(invalid(format!(
            "{} times for {} frames (expected one per frame)",
            times.len(),
            frames.len()
        )));
    }
    if times[0] != 0.0 {
        return Err(invalid(format!(
            "the first frame is at {} s (expected 0)",
            times[0]
        )));
    }
    if let Some(f) = (1..times.len()).find(|&f| !(times[f] > times[f - 1] && times[f].is_finite()))
    {
        return Err(invalid(format!(
            "frame {f} is at {} s, not after frame {}'s {} s (times must increase)",
            times[f],
            f - 1,
            times[f - 1]
        )));
    }
    let duration = times[times.len() - 1];
    let mut key_times = String::new();
    for (f, &t) in times.iter().enumerate() {
        if f > 0 {
            key_times.push(';');
        }
        // The last is exactly 1, as SMIL requires for linear animation.
        let fraction = if f + 1 == times.len() {
            1.0
        } else {
            t / duration
        };
        let _ = write!(key_times, "{fraction}");
    }
    let at = |frame: usize| {
        move |source: SvgError| AnimateError::Frame {
            frame,
            source: Box::new(source),
        }
    };
    let offsets = chain_offsets(drawing, &frames[0]).map_err(at(0))?;
    for (f, points) in frames.iter().enumerate().skip(1) {
        chain_offsets(drawing, points).map_err(at(f))?;
    }
    let head = format!(
        "<animate attributeName=\"d\" dur=\"{duration}s\" repeatCount=\"indefinite\" \
         calcMode=\"linear\" keyTimes=\"{key_times}\" values=\""
    );
    match &drawing.source {
        Some(source) => {
            let first = element_path_data(drawing, &frames[0], &offsets, source).map_err(at(0))?;
            let mut children: Vec<String> = first
                .iter()
                .map(|d| {
                    let mut c = head.clone();
                    c.push_str(d);
                    c
                })
                .collect();
            for (f, points) in frames.iter().enumerate().skip(1) {
                let data = element_path_data(drawing, points, &offsets, source).map_err(at(f))?;
                for (c, d) in children.iter_mut().zip(&data) {
                    c.push(';');
                    c.push_str(d);
                }
            }
            for (c, d) in children.iter_mut().zip(&first) {
                if d.is_empty() {
                    c.clear();
                } else {
                    c.push_str("\"/>");
                }
            }
            let view_box = match view_box {
                ViewBoxRule::Fit => frames
                    .iter()
                    .filter_map(|points| art_bounds_at(drawing, points, &offsets))
                    .reduce(|a, b| a.union(b))
                    .map_or(ViewBoxRule::Keep, ViewBoxRule::FitTo),
                rule => rule,
            };
            let root = root_attributes(drawing, &frames[0], &offsets, source, view_box)
                .map_err(|e| AnimateError::Svg(Box::new(e)))?;
            export_geometry_root(source, first, children, None, root)
                .map_err(|e| AnimateError::Svg(Box::new(e)))
        }
        None => {
            let mut children = vec![head; drawing.paths.len()];
            for (f, points) in frames.iter().enumerate() {
                for ((c, path), &offset) in children.iter_mut().zip(&drawing.paths).zip(&offsets) {
                    if f > 0 {
                        c.push(';');
                    }
                    let chain = &points[offset..offset + path.points.len()];
                    push_path_data(c, path, chain, Affine::IDENTITY, true);
                }
            }
            for c in &mut children {
                c.push_str("\"/>");
            }
            Ok(super::svg_out::write_standalone(
                drawing, &frames[0], &offsets, &children,
            ))
        }
    }
}
