//! Animated SVG export: the document of [`crate::svg_out`] with each deformed element's `d`
//! animated by SMIL, one value per frame.
//!
//! Every imported element is written as [`crate::svg_out::write_svg`] writes it for the first
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
//!
//! [`write_animated_svg_following`] also animates what is not a curve, frame by frame as
//! [`crate::svg_out::write_svg_following`] places it for one pose: the `transform` of text and
//! images, the `gradientTransform`/`patternTransform` of each element's copy of a user-space
//! paint server (as `animateTransform` elements, [`crate::smil`]), and the `orient` of
//! fixed-orientation markers.

use std::fmt::Write as _;

use kurbo::{Affine, Point};

use crate::follow::ElementMaps;
use crate::smil::Timing;
use crate::svg_out::{
    art_bounds_at, chain_offsets, element_path_data, export_geometry_animated,
    export_geometry_root, push_path_data, root_attributes, Follow, ViewBoxRule,
};
use crate::SvgError;
use splineskin_core::drawing::Drawing;

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
/// errors of [`crate::svg_out::write_svg`].
///
/// ```
/// use kurbo::Vec2;
/// use splineskin_svg::svg_animate::write_animated_svg;
/// use splineskin_svg::svg_in::{read_svg, ImportOptions};
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
/// and the art's bounding box over every frame ([`crate::svg_out::art_bounds`] of each), so
/// that the animation does not crop any frame and does not jump.
///
/// ```
/// use kurbo::Vec2;
/// use splineskin_svg::svg_animate::write_animated_svg_view_box;
/// use splineskin_svg::svg_in::{read_svg, ImportOptions};
/// use splineskin_svg::svg_out::ViewBoxRule;
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
    write_animated_svg_with(
        drawing,
        frames,
        times,
        &AnimatedSvgOptions::default().with_view_box(view_box),
    )
}

/// [`write_animated_svg_view_box`], with everything that is not a curve carried through the
/// animation by `maps` (one [`ElementMaps`] per frame, each computed for this drawing and that
/// frame's pose): what [`crate::svg_out::write_svg_following`] writes for one pose, animated.
///
/// - `<text>` and `<image>`: their `transform` attribute is the first frame's (as
///   `write_svg_following` writes it: `matrix(P⁻¹ A₀ P)` then their own transform), and their
///   first content is four `animateTransform` of it whose composition at frame `f` is
///   `P⁻¹ A_f P · O` (`A_f` the element's best-fit map in frame `f`, `P` its parent's map to
///   root user space, `O` its own transform), decomposed as [`crate::smil`] says.
/// - user-space gradients and patterns: each element's copy of its paint server has the first
///   frame's `gradientTransform`/`patternTransform` `M₀ · G` and animates it through
///   `M_f · G` in the same way (`M_f` the element's map in its local coordinates, `G` the
///   server's own transform); elements whose maps agree in every frame share a copy.
/// - fixed-orientation markers: the copy's `orient` is animated by an `<animate>` through the
///   element's rotation in each frame (angles unwrapped: no spin between frames).
/// - stroke widths, when the maps were computed with
///   [`FollowOptions::scale_strokes`](crate::follow::FollowOptions): an `<animate>` of
///   `stroke-width` beside the element's `d`.
///
/// Every animation has the paths' `dur`, `keyTimes` and `calcMode`, so all parts of a frame
/// are shown together; between frames the browser interpolates each part linearly (the
/// translation, angle, skew and scale of a map, as it interpolates each point of a path). A
/// drawing without a source document is written as by [`write_animated_svg_view_box`].
///
/// Errors: those of [`write_animated_svg_view_box`]; [`AnimateError::Svg`] with
/// [`SvgError::SourceMismatch`] when `maps` are not one per frame of this drawing.
///
/// ```
/// use kurbo::{Affine, Point};
/// use splineskin_svg::follow::{ElementMaps, FollowOptions};
/// use splineskin_svg::svg_animate::write_animated_svg_following;
/// use splineskin_svg::svg_out::ViewBoxRule;
/// use splineskin_svg::{read_svg, ImportOptions};
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10">
///   <rect width="4" height="2"/><text x="1" y="8">hi</text></svg>"#;
/// let drawing = read_svg(svg, &ImportOptions::default()).unwrap();
/// let poses = [Affine::IDENTITY, Affine::rotate(0.5)];
/// let frames: Vec<Vec<Point>> = poses
///     .iter()
///     .map(|&t| drawing.flat_points().iter().map(|&p| t * p).collect())
///     .collect();
/// let maps: Vec<ElementMaps> = poses
///     .iter()
///     .map(|&t| ElementMaps::from_map(&drawing, &mut |p| t * p, &FollowOptions::default()))
///     .collect::<Result<_, _>>()
///     .unwrap();
/// let out =
///     write_animated_svg_following(&drawing, &frames, &[0.0, 1.0], &maps, ViewBoxRule::Keep)
///         .unwrap();
/// // The text turns by 0 then 0.5 rad (28.6…°), composed after a translation.
/// assert!(out.contains(r#"type="translate" additive="replace""#), "{out}");
/// let rotate = r#"type="rotate" additive="sum" dur="1s" repeatCount="indefinite" calcMode="linear" keyTimes="0;1" values="0;"#;
/// let at = out.find(rotate).unwrap() + rotate.len();
/// let turn: f64 = out[at..at + out[at..].find('"').unwrap()].parse().unwrap();
/// assert!((turn - 0.5f64.to_degrees()).abs() < 1e-9, "{turn}");
/// ```
pub fn write_animated_svg_following(
    drawing: &Drawing,
    frames: &[Vec<Point>],
    times: &[f64],
    maps: &[ElementMaps],
    view_box: ViewBoxRule,
) -> Result<String, AnimateError> {
    let options = AnimatedSvgOptions::default()
        .with_view_box(view_box)
        .with_follow(Some(maps));
    write_animated_svg_with(drawing, frames, times, &options)
}

/// How [`write_animated_svg_with`] writes an animation: the input's viewBox kept and nothing
/// carried by default, set one by one.
///
/// ```
/// use splineskin_svg::svg_animate::AnimatedSvgOptions;
/// use splineskin_svg::svg_out::ViewBoxRule;
/// let options = AnimatedSvgOptions::default().with_view_box(ViewBoxRule::Fit);
/// assert!(options.follow.is_none());
/// ```
#[derive(Clone, Copy, Debug, Default)]
#[non_exhaustive]
pub struct AnimatedSvgOptions<'a> {
    /// The root viewBox, one for the whole animation (see [`write_animated_svg_view_box`]).
    pub view_box: ViewBoxRule,
    /// One [`ElementMaps`] per frame, carrying what is not a curve (see
    /// [`write_animated_svg_following`]).
    pub follow: Option<&'a [ElementMaps]>,
}

impl<'a> AnimatedSvgOptions<'a> {
    /// Sets [`AnimatedSvgOptions::view_box`].
    pub fn with_view_box(mut self, view_box: ViewBoxRule) -> Self {
        self.view_box = view_box;
        self
    }

    /// Sets [`AnimatedSvgOptions::follow`].
    pub fn with_follow(mut self, maps: Option<&'a [ElementMaps]>) -> Self {
        self.follow = maps;
        self
    }
}

/// Writes `drawing` animated through `frames` at `times` as [`write_animated_svg`] does, as
/// `options` say: the one writer the other `write_animated_svg*` functions name a case of.
///
/// ```
/// use kurbo::Vec2;
/// use splineskin_svg::svg_animate::{write_animated_svg_with, AnimatedSvgOptions};
/// use splineskin_svg::svg_in::{read_svg, ImportOptions};
/// use splineskin_svg::svg_out::ViewBoxRule;
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10"><path d="M1 1 C2 2 3 2 4 1"/></svg>"#;
/// let drawing = read_svg(svg, &ImportOptions::default())?;
/// let rest = drawing.flat_points();
/// let right: Vec<_> = rest.iter().map(|&p| p + Vec2::new(8.0, 0.0)).collect();
/// let options = AnimatedSvgOptions::default().with_view_box(ViewBoxRule::Fit);
/// let out = write_animated_svg_with(&drawing, &[rest, right], &[0.0, 1.0], &options)?;
/// assert!(out.contains(r#"viewBox="0 0 12 10""#), "{out}");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_animated_svg_with(
    drawing: &Drawing,
    frames: &[Vec<Point>],
    times: &[f64],
    options: &AnimatedSvgOptions<'_>,
) -> Result<String, AnimateError> {
    let (view_box, maps) = (options.view_box, options.follow);
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
    let timing = Timing {
        attributes: format!(
            " dur=\"{duration}s\" repeatCount=\"indefinite\" calcMode=\"linear\" \
             keyTimes=\"{key_times}\""
        ),
        n_frames: frames.len(),
    };
    let head = format!(
        "<animate attributeName=\"d\"{} values=\"",
        timing.attributes
    );
    match &drawing.source {
        Some(source) => {
            let first =
                element_path_data(drawing, &frames[0], &offsets, source, &[]).map_err(at(0))?;
            let mut children: Vec<String> = first
                .iter()
                .map(|d| {
                    let mut c = head.clone();
                    c.push_str(d);
                    c
                })
                .collect();
            for (f, points) in frames.iter().enumerate().skip(1) {
                let data =
                    element_path_data(drawing, points, &offsets, source, &[]).map_err(at(f))?;
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
            match maps {
                Some(maps) => {
                    let follow = Follow {
                        drawing,
                        frames: maps,
                        timing: Some(&timing),
                        paint_marker: None,
                    };
                    export_geometry_animated(source, first, children, root, follow)
                }
                None => export_geometry_root(source, first, children, None, root),
            }
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
            Ok(crate::svg_out::write_standalone(
                drawing, &frames[0], &offsets, &children,
            ))
        }
    }
}

#[cfg(test)]
mod tests {
    use kurbo::{Affine, Point};

    use super::*;
    use crate::follow::{ElementMaps, FollowOptions};
    use crate::{read_svg, ImportOptions};

    /// A drawing of ours: a plate with a user-space gradient that has its own transform, and a
    /// label with its own transform inside a transformed group.
    const SVG: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 60">
      <linearGradient id="g" gradientUnits="userSpaceOnUse" x1="0" x2="80"
          gradientTransform="translate(3 1) rotate(5)">
        <stop offset="0" stop-color="red"/><stop offset="1" stop-color="blue"/></linearGradient>
      <rect x="10" y="10" width="80" height="40" fill="url(#g)"/>
      <g transform="translate(5 3) scale(1.5)">
        <text x="10" y="22" font-size="8" transform="rotate(10 20 20)">label</text></g>
    </svg>"##;

    /// Frame `f`'s point map: a turn by 60°·f about (50, 30) after a bend (so that the
    /// best-fit maps are not the turn itself); 9 frames turn through 480°.
    fn map(f: usize, p: Point) -> Point {
        let bent = Point::new(p.x, p.y + 0.002 * f as f64 * (p.x - 50.0).powi(2));
        Affine::rotate_about((60.0 * f as f64).to_radians(), Point::new(50.0, 30.0)) * bent
    }

    /// The map the `animateTransform`s inside `node` animating `attribute` give at frame `f`.
    fn recomposed(node: roxmltree::Node, attribute: &str, f: usize) -> (Affine, f64) {
        let mut a = Affine::IDENTITY;
        let mut angle = 0.0;
        let mut kinds = Vec::new();
        for n in node
            .children()
            .filter(|n| n.has_tag_name("animateTransform"))
        {
            assert_eq!(n.attribute("attributeName"), Some(attribute));
            let value = n.attribute("values").unwrap().split(';').nth(f).unwrap();
            let v: Vec<f64> = value.split(' ').map(|x| x.parse().unwrap()).collect();
            let kind = n.attribute("type").unwrap();
            kinds.push(kind);
            let part = match kind {
                "translate" => Affine::translate((v[0], v[1])),
                "rotate" => {
                    angle = v[0];
                    Affine::rotate(v[0].to_radians())
                }
                "skewX" => Affine::skew(v[0].to_radians().tan(), 0.0),
                _ => Affine::scale_non_uniform(v[0], v[1]),
            };
            a = match n.attribute("additive") {
                Some("sum") => a * part,
                _ => part,
            };
        }
        assert_eq!(kinds, ["translate", "rotate", "skewX", "scale"]);
        (a, angle)
    }

    fn assert_close(a: Affine, b: Affine, size: f64, what: &str) {
        let (ca, cb) = (a.as_coeffs(), b.as_coeffs());
        let lin = cb[..4].iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for k in 0..6 {
            let scale = if k < 4 { lin } else { lin * size + cb[k].abs() };
            assert!(
                (ca[k] - cb[k]).abs() <= 1e-9 * scale,
                "{what}: {a:?} vs {b:?}"
            );
        }
    }

    #[test]
    fn svg_animate_following_recomposes_each_frames_element_maps() {
        let drawing = read_svg(SVG, &ImportOptions::default()).unwrap();
        let n_frames = 9;
        let times: Vec<f64> = (0..n_frames).map(|f| 0.25 * f as f64).collect();
        let frames: Vec<Vec<Point>> = (0..n_frames)
            .map(|f| drawing.flat_points().iter().map(|&p| map(f, p)).collect())
            .collect();
        let maps: Vec<ElementMaps> = (0..n_frames)
            .map(|f| ElementMaps::from_map(&drawing, &mut |p| map(f, p), &FollowOptions::default()))
            .collect::<Result<_, _>>()
            .unwrap();
        let out = write_animated_svg_following(&drawing, &frames, &times, &maps, ViewBoxRule::Keep)
            .unwrap();
        let doc = roxmltree::Document::parse(&out).unwrap();
        let source = drawing.source.as_ref().unwrap();
        let text_offset = source.text.find("<text").unwrap();
        let text = doc.descendants().find(|n| n.has_tag_name("text")).unwrap();
        let copy = doc
            .descendants()
            .find(|n| n.has_tag_name("linearGradient") && n.attribute("id") != Some("g"))
            .unwrap();
        let parent = Affine::translate((5.0, 3.0)) * Affine::scale(1.5);
        let own = Affine::rotate_about(10f64.to_radians(), Point::new(20.0, 20.0));
        let gradient = Affine::translate((3.0, 1.0)) * Affine::rotate(5f64.to_radians());
        let mut angles = Vec::new();
        for (f, m) in maps.iter().enumerate() {
            let a = m.carried_map(text_offset).unwrap();
            let (shown, angle) = recomposed(text, "transform", f);
            assert_close(shown, parent.inverse() * a * parent * own, 60.0, "text");
            angles.push(angle);
            let (shown, _) = recomposed(copy, "gradientTransform", f);
            let expected = m.element_map(0).unwrap() * gradient;
            assert_close(shown, expected, 100.0, "gradient");
        }
        // 0°, 60°, … 480° plus the bend's and the label's own turn: unwrapped, never a jump.
        for w in angles.windows(2) {
            assert!((w[1] - w[0] - 60.0).abs() < 15.0, "{angles:?}");
        }
        assert!(angles[n_frames - 1] > 400.0, "{angles:?}");
        // A renderer without SMIL shows the first frame: the static attributes are frame 0's.
        let still = Affine::new(
            text.attribute("transform").unwrap()["matrix(".len()..]
                .split([' ', ')'])
                .take(6)
                .map(|x| x.parse().unwrap())
                .collect::<Vec<f64>>()
                .try_into()
                .unwrap(),
        );
        assert_close(
            still,
            recomposed(text, "transform", 0).0 * own.inverse(),
            60.0,
            "still",
        );
        assert!(text
            .attribute("transform")
            .unwrap()
            .ends_with(") rotate(10 20 20)"));
    }

    #[test]
    fn svg_animate_following_refuses_maps_of_another_length() {
        let drawing = read_svg(SVG, &ImportOptions::default()).unwrap();
        let rest = drawing.flat_points();
        let maps =
            vec![ElementMaps::from_map(&drawing, &mut |p| p, &FollowOptions::default()).unwrap()];
        let err = write_animated_svg_following(
            &drawing,
            &[rest.clone(), rest],
            &[0.0, 1.0],
            &maps,
            ViewBoxRule::Keep,
        )
        .unwrap_err();
        assert!(
            err.to_string().contains("1 element maps for 2 frames"),
            "{err}"
        );
    }
}
