//! Lottie export: a deformed drawing's frames as a Lottie animation whose shapes are the same
//! cubic paths, keyframed.
//!
//! The deformation moves control points and never changes a path's structure, so every frame
//! of a path is the same list of cubics: one Lottie path shape (`"ty": "sh"`) per path of the
//! drawing, its vertices `v` the chain's on-curve points and its tangents `i`/`o` the
//! neighbouring control points relative to them:
//!
//! ```text
//! chain  p₀ c₁ c₂ p₁ c₃ c₄ p₂ …        v = [p₀, p₁, p₂, …]
//!                                      o[k] = c(after p_k) − p_k,   i[k] = c(before p_k) − p_k
//! ```
//!
//! (a closed chain drops its repeated last point and sets `"c": true`; the tangents at an open
//! chain's ends are zero). Players interpolate a shape's keyframes linearly, point by point
//! (the keyframes here have linear easing), so a keyframe is needed only where that
//! interpolation would stray from the deformation: [`keyframes`] keeps, per path, the fewest
//! frames for which every frame in between is within the tolerance of the interpolation of its
//! neighbouring kept frames. Since a Bézier curve is the convex combination of its control
//! points, a curve is then within the tolerance of the deformed one at those frames too.
//!
//! Paint comes from the source document as usvg resolved it ([`crate::svg_in`]): solid and
//! gradient fills and strokes (width, caps, joins, miter limit, dashes, opacity, fill rule),
//! group opacity as nested groups. Gradients follow their element: their end points are
//! keyframed through each frame's element maps ([`crate::follow`]), as the animated SVG moves
//! them. Everything is written in the root's user space (the drawing's coordinates), with one
//! layer transform for the root viewBox. What Lottie cannot express, or this export does not
//! write yet, is named in [`LottieExport::warnings`]: masks, filters, patterns, clip paths
//! inside clipped groups and holes in clip paths,
//! text and images, non-pad gradient spreads, strokes and stroke gradients under a non-uniform
//! transform (approximated), and gradients written at rest when no element maps are given.
//!
//! A clipped group becomes a layer of its own (Lottie masks whole layers), masked by its clip
//! path's shapes (mode add: their union), keyframed as any path; the content above and below
//! it goes into the layers around it, in order.
//!
//! A fill gradient Lottie cannot draw in root user space (a radial gradient stretched into an
//! ellipse, a linear one sheared by its transform: Lottie's are circular and square to their
//! axis) is drawn exactly in its own space instead: a group whose transform (position,
//! rotation, skew, scale) is the gradient's map at each frame, over the element's paths mapped
//! back by it; its keyframes are kept where the player's interpolation of the two, composed,
//! would stray from the deformation by more than the tolerance.
//!
//! **Size.** The tolerance is shared: nine tenths for the keyframes, one tenth for rounding
//! the paths' coordinates to the fewest decimals that keep every curve point within it
//! (`quantum_digits`: 2 decimals for the bundled fish). Whole numbers are written without
//! their `.0`. The fish's animation: 123 kB before, 79 kB after (143 keyframes for 140).
//!
//! **Players.** Whole numbers where players read integers (`w`, `h`, `ip`, `op`, `fr`), and
//! each object's `"ty"` first: rlottie reads a shape's keys in order and skips those before
//! its type (`players_json`). Each dash of a stroke has its own name: lottie-web draws
//! nothing of a layer whose dashes share one. What some players draw otherwise than browsers
//! (measured) is named in [`LottieExport::player_notes`].
//!
//! The JSON is built with `serde_json` values rather than `velato`'s schema types: we write
//! a dozen object kinds, velato's types have no defaults (every optional field spelled out at
//! each use), and the output is checked against the Lottie community's JSON schema by the
//! browser tests, which also play it in lottie-web.

mod gradient_space;
mod keyframes;
mod layers;
mod paint;

use kurbo::{Point, Rect};
use serde_json::{json, Value};

use crate::follow::ElementMaps;
use crate::svg_in::source_tree;
use crate::SvgError;
use layers::Runs;
use splineskin_core::drawing::source::{ElementKey, SvgSource};
use splineskin_core::drawing::{Drawing, Path, PathRole};

pub use keyframes::keyframes;

/// Default [`LottieOptions::tolerance`]: 1e-3 of the drawing's bounding-box diagonal.
pub const DEFAULT_TOLERANCE: f64 = 1e-3;

/// Options of [`write_lottie`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct LottieOptions {
    /// Largest distance between the deformation at a frame and the player's linear
    /// interpolation of the kept keyframes, as a fraction of the drawing's bounding-box
    /// diagonal. `0` keeps every frame. Default: [`DEFAULT_TOLERANCE`].
    pub tolerance: f64,
    /// The animation's name (`"nm"`).
    pub name: String,
}

impl Default for LottieOptions {
    fn default() -> Self {
        LottieOptions {
            tolerance: DEFAULT_TOLERANCE,
            name: "splineskin".into(),
        }
    }
}

impl LottieOptions {
    /// Sets [`LottieOptions::tolerance`].
    pub fn with_tolerance(mut self, tolerance: f64) -> Self {
        self.tolerance = tolerance;
        self
    }
    /// Sets [`LottieOptions::name`].
    pub fn with_name(mut self, name: impl Into<String>) -> Self {
        self.name = name.into();
        self
    }
}

/// A written Lottie animation.
#[derive(Clone, Debug)]
pub struct LottieExport {
    /// The Lottie JSON document.
    pub json: String,
    /// What the document does not express (one line each, naming the element).
    pub warnings: Vec<String>,
    /// What the document expresses but some players draw otherwise (one line each, naming the
    /// element and the players), as measured against browsers' drawing of the SVG frames:
    /// rlottie 1.3.8 places dashes elsewhere, blends gradient stop opacities otherwise and
    /// ignores a group's skew (`sk`, which fill gradients drawn in their own space use);
    /// rlottie and ThorVG apply a group's opacity to each of its shapes. lottie-web, Skottie
    /// and the dotLottie player (ThorVG) draw everything else written here as browsers do.
    pub player_notes: Vec<String>,
    /// Path keyframes written, over all paths.
    pub keyframes: usize,
    /// Path keyframes if every frame were kept (paths × frames).
    pub every_frame_keyframes: usize,
}

/// Why an animation could not be written as Lottie.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum LottieError {
    /// The frames, their rate or the options are not valid (the message says what was
    /// expected).
    #[error("cannot write Lottie: {what}")]
    Invalid {
        /// What is wrong.
        what: String,
    },
    /// The drawing has no SVG document behind it, so its paint is unknown.
    #[error("cannot write Lottie: the drawing has no SVG document to take its paint from")]
    NoSource,
    /// The source document could not be read again.
    #[error(transparent)]
    Svg(#[from] Box<SvgError>),
}

/// Writes `drawing` animated through `frames` (each [`Drawing::n_points`] points laid out like
/// [`Drawing::flat_points`]) at `times` (seconds, from 0, increasing), as a Lottie document
/// (module documentation) of frame rate `fps`: frame `k` at Lottie frame `times[k] · fps`, the
/// animation ending at the last.
///
/// Errors: [`LottieError::Invalid`] for fewer than two frames, times not one per frame, not
/// starting at 0 or not increasing, a frame of the wrong length or with a non-finite point, a
/// frame rate that is not positive and finite, or a tolerance that is negative or not finite; [`LottieError::NoSource`] for a drawing without its SVG
/// document.
///
/// ```
/// use kurbo::Vec2;
/// use splineskin_svg::lottie::{write_lottie, LottieOptions};
/// use splineskin_svg::svg_in::{read_svg, ImportOptions};
/// let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10">
///   <path d="M1 1 C2 3 4 3 5 1" fill="#f80" stroke="#000"/></svg>"##;
/// let drawing = read_svg(svg, &ImportOptions::default()).unwrap();
/// let rest = drawing.flat_points();
/// // A uniform motion: the two ends are the only keyframes needed.
/// let frames: Vec<Vec<_>> = (0..5)
///     .map(|k| rest.iter().map(|&p| p + Vec2::new(0.5 * k as f64, 0.0)).collect())
///     .collect();
/// let times = [0.0, 0.1, 0.2, 0.3, 0.4];
/// let out = write_lottie(&drawing, &frames, &times, 10.0, None, &LottieOptions::default())?;
/// assert_eq!((out.keyframes, out.every_frame_keyframes), (2, 5));
/// let doc: serde_json::Value = serde_json::from_str(&out.json).unwrap();
/// assert_eq!(doc["fr"], 10.0);
/// assert_eq!(doc["op"], 4.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_lottie(
    drawing: &Drawing,
    frames: &[Vec<Point>],
    times: &[f64],
    fps: f64,
    maps: Option<&[ElementMaps]>,
    options: &LottieOptions,
) -> Result<LottieExport, LottieError> {
    check(drawing, frames, times, fps, options)?;
    if maps.is_some_and(|m| m.len() != frames.len()) {
        return Err(LottieError::Invalid {
            what: format!(
                "{} element maps for {} frames (expected one per frame)",
                maps.map_or(0, |m| m.len()),
                frames.len()
            ),
        });
    }
    let source = drawing.source.as_deref().ok_or(LottieError::NoSource)?;
    let total = options.tolerance * drawing.diagonal();
    // The tolerance is shared: most of it for the keyframes, the rest for the coordinates'
    // rounding (module doc, "Size").
    let tolerance = (1.0 - QUANTUM_SHARE) * total;
    let offsets: Vec<usize> = drawing.path_ranges().map(|r| r.start).collect();
    let mut writer = Writer {
        drawing,
        source,
        frames,
        frame_numbers: times.iter().map(|t| t * fps).collect(),
        maps,
        offsets,
        tolerance,
        digits: quantum_digits(QUANTUM_SHARE * total),
        warnings: Warnings::default(),
        keyframes: 0,
        bbox_servers: std::collections::HashSet::new(),
    };
    let (tree, prepared) = source_tree(source).map_err(Box::new)?;
    writer.bbox_servers = bbox_servers(&source.text);
    let element_of_key: std::collections::HashMap<&ElementKey, usize> = source
        .elements
        .iter()
        .enumerate()
        .map(|(i, e)| (&e.key, i))
        .collect();
    let mut runs = Runs::default();
    if let Some(usvg::Node::Group(wrapper)) = tree.node_by_id(&prepared.wrapper_id) {
        let lookup = |id: &str| {
            prepared
                .ids
                .get(id)
                .and_then(|key| element_of_key.get(key))
                .copied()
        };
        writer.layer_runs(wrapper, &lookup, 1.0, &mut runs);
    }
    // Texts are named from the source: usvg's tree drops them without its text layout (the
    // WebAssembly build), and turns them into glyph groups no element matches with it.
    for id in text_ids(&source.text) {
        writer.warnings.add(text_not_written(&id));
    }
    runs.finish();
    let last_frame = times[times.len() - 1] * fps;
    let (w, h, layer_transform) = root_transform(source);
    let layers: Vec<Value> = runs
        .done
        .into_iter()
        .enumerate()
        .map(|(k, run)| {
            let mut ks = layer_transform.clone();
            ks["o"] = json!({"a": 0, "k": 100.0 * run.opacity});
            let mut layer = json!({
                "ddd": 0,
                "ind": k + 1,
                "ty": 4,
                "nm": run.name.clone().unwrap_or_else(|| options.name.clone()),
                "sr": 1,
                "ks": ks,
                "ao": 0,
                "shapes": run.shapes,
                "ip": 0,
                "op": frame_number(last_frame),
                "st": 0,
                "bm": 0
            });
            if !run.masks.is_empty() {
                layer["hasMask"] = json!(true);
                layer["masksProperties"] = json!(run.masks);
            }
            layer
        })
        .collect();
    let document = json!({
        "v": "5.12.0",
        "nm": options.name,
        "fr": frame_number(fps),
        "ip": 0,
        "op": frame_number(last_frame),
        // Whole pixels: rlottie refuses a size written as a float (600.0).
        "w": w as u64,
        "h": h as u64,
        "ddd": 0,
        "assets": [],
        "layers": layers
    });
    let json = players_json(&document);
    Ok(LottieExport {
        json,
        warnings: writer.warnings.0,
        player_notes: writer.warnings.1,
        keyframes: writer.keyframes,
        every_frame_keyframes: drawing.paths.len() * frames.len(),
    })
}

fn check(
    drawing: &Drawing,
    frames: &[Vec<Point>],
    times: &[f64],
    fps: f64,
    options: &LottieOptions,
) -> Result<(), LottieError> {
    let invalid = |what: String| Err(LottieError::Invalid { what });
    if frames.len() < 2 {
        return invalid(format!(
            "{} frame(s) given (expected at least two)",
            frames.len()
        ));
    }
    if times.len() != frames.len()
        || times[0] != 0.0
        || times.windows(2).any(|w| !(w[1] > w[0] && w[1].is_finite()))
    {
        return invalid(format!(
            "{} times for {} frames (expected one per frame, from 0, increasing)",
            times.len(),
            frames.len()
        ));
    }
    if !(fps.is_finite() && fps > 0.0) {
        return invalid(format!(
            "frame rate {fps} (expected a positive finite number)"
        ));
    }
    if !(options.tolerance.is_finite() && options.tolerance >= 0.0) {
        return invalid(format!(
            "tolerance {} (expected a finite number, 0 or more)",
            options.tolerance
        ));
    }
    let n = drawing.n_points();
    for (f, frame) in frames.iter().enumerate() {
        if frame.len() != n {
            return invalid(format!(
                "frame {f} has {} points (expected {n}, the drawing's)",
                frame.len()
            ));
        }
        if let Some(k) = frame
            .iter()
            .position(|p| !(p.x.is_finite() && p.y.is_finite()))
        {
            return invalid(format!("frame {f}, point {k} is not finite"));
        }
    }
    Ok(())
}

/// A frame number or rate as the players read it: an integer when it is whole (`96`, not
/// `96.0`: rlottie and Skottie read the composition's fields as integers), else the number.
fn frame_number(x: f64) -> Value {
    if x.fract() == 0.0 && x.abs() < 1e15 {
        json!(x as i64)
    } else {
        json!(x)
    }
}

/// `document` as JSON text with each object's `"ty"` first and its other keys after it, in
/// order, and whole numbers written as integers. rlottie reads a shape's type from the keys before the others and skips what it
/// does not yet know the type of: with `"ty"` last (the order of a sorted map) it draws
/// nothing. Every other player reads the keys in any order.
fn players_json(document: &Value) -> String {
    let mut out = String::new();
    write_ty_first(document, &mut out);
    out
}

fn write_ty_first(value: &Value, out: &mut String) {
    match value {
        Value::Object(map) => {
            out.push('{');
            let ty = map.get_key_value("ty");
            let rest = map.iter().filter(|(k, _)| k.as_str() != "ty");
            for (n, (key, v)) in ty.into_iter().chain(rest).enumerate() {
                if n > 0 {
                    out.push(',');
                }
                out.push_str(&Value::String(key.clone()).to_string());
                out.push(':');
                write_ty_first(v, out);
            }
            out.push('}');
        }
        Value::Array(items) => {
            out.push('[');
            for (n, v) in items.iter().enumerate() {
                if n > 0 {
                    out.push(',');
                }
                write_ty_first(v, out);
            }
            out.push(']');
        }
        // Whole numbers without their `.0` (and `-0` as `0`): a fifth of a path's text.
        Value::Number(n) => match n.as_f64() {
            Some(x) if n.is_f64() && x.fract() == 0.0 && x.abs() < 1e15 => {
                out.push_str(&(x as i64).to_string())
            }
            _ => out.push_str(&n.to_string()),
        },
        scalar => out.push_str(&scalar.to_string()),
    }
}

/// The document's size in whole pixels and the layer transform mapping the root viewBox onto
/// it (`preserveAspectRatio` `xMidYMid meet`, SVG's default).
fn root_transform(source: &SvgSource) -> (f64, f64, Value) {
    let w = source.size.width.round().max(1.0);
    let h = source.size.height.round().max(1.0);
    let vb: Rect = source.view_box;
    let s = if vb.width() > 0.0 && vb.height() > 0.0 {
        (w / vb.width()).min(h / vb.height())
    } else {
        1.0
    };
    let tx = (w - vb.width() * s) / 2.0 - vb.x0 * s;
    let ty = (h - vb.height() * s) / 2.0 - vb.y0 * s;
    let transform = json!({
        "a": {"a": 0, "k": [0.0, 0.0, 0.0]},
        "p": {"a": 0, "k": [tx, ty, 0.0]},
        "s": {"a": 0, "k": [100.0 * s, 100.0 * s, 100.0]},
        "r": {"a": 0, "k": 0.0},
        "o": {"a": 0, "k": 100.0}
    });
    (w, h, transform)
}

/// State of one export.
struct Writer<'a> {
    drawing: &'a Drawing,
    source: &'a SvgSource,
    frames: &'a [Vec<Point>],
    /// Each frame's Lottie frame number (time × frame rate).
    frame_numbers: Vec<f64>,
    /// Each frame's element maps, which gradients follow.
    maps: Option<&'a [ElementMaps]>,
    /// First point of each path in a frame.
    offsets: Vec<usize>,
    /// Of the keyframes, in drawing units.
    tolerance: f64,
    /// Decimal digits the paths' coordinates are rounded to ([`quantum_digits`]), or `None`
    /// to write them as computed.
    digits: Option<i32>,
    warnings: Warnings,
    keyframes: usize,
    /// Ids of the document's gradients in `objectBoundingBox` units: they follow the deformed
    /// element's bounding box, as SVG draws them, rather than its map.
    bbox_servers: std::collections::HashSet<String>,
}

/// The warning for a text the animation leaves out.
fn text_not_written(id: &str) -> String {
    let name = if id.is_empty() { "(without an id)" } else { id };
    format!("text {name}: not written (read the drawing with its text as outlines to animate it)")
}

/// The ids of the document's `<text>` elements (outermost ones; `""` for one without an id).
fn text_ids(text: &str) -> Vec<String> {
    let Some(doc) = parse_source(text) else {
        return Vec::new();
    };
    crate::document::outermost_texts(&doc)
        .map(|n| n.attribute("id").unwrap_or("").to_string())
        .collect()
}

/// The source document's text parsed as XML (DTDs allowed, as the import reads it), if it is.
fn parse_source(text: &str) -> Option<roxmltree::Document<'_>> {
    let options = roxmltree::ParsingOptions {
        allow_dtd: true,
        ..Default::default()
    };
    roxmltree::Document::parse_with_options(text, options).ok()
}

/// The ids of the gradients of SVG `text` whose `gradientUnits` (through `href` templates) are
/// `objectBoundingBox`, SVG's default.
fn bbox_servers(text: &str) -> std::collections::HashSet<String> {
    let Some(doc) = parse_source(text) else {
        return Default::default();
    };
    let ids: std::collections::HashMap<&str, roxmltree::Node> = doc
        .descendants()
        .filter_map(|n| n.attribute("id").map(|id| (id, n)))
        .collect();
    doc.descendants()
        .filter(|n| matches!(n.tag_name().name(), "linearGradient" | "radialGradient"))
        .filter(|n| {
            crate::svg_out::resources::through_href(*n, "gradientUnits", &ids)
                .is_none_or(|u| u.trim() != "userSpaceOnUse")
        })
        .filter_map(|n| n.attribute("id").map(str::to_string))
        .collect()
}

impl Writer<'_> {
    /// The Lottie items of one usvg node (a group's as [`Writer::group_items`] writes them).
    fn node_items(
        &mut self,
        node: &usvg::Node,
        lookup: &dyn Fn(&str) -> Option<usize>,
        out: &mut Vec<Value>,
    ) {
        let mut wrapper = Vec::new();
        self.children_items(std::slice::from_ref(node), lookup, &mut wrapper);
        out.extend(wrapper);
    }

    /// The Lottie items of a usvg group's children, topmost first (Lottie lists what is drawn
    /// last first; SVG the reverse).
    fn group_items(
        &mut self,
        group: &usvg::Group,
        lookup: &dyn Fn(&str) -> Option<usize>,
        out: &mut Vec<Value>,
    ) {
        self.children_items(group.children(), lookup, out);
    }

    /// The Lottie items of usvg nodes `children`, topmost first.
    fn children_items(
        &mut self,
        children: &[usvg::Node],
        lookup: &dyn Fn(&str) -> Option<usize>,
        out: &mut Vec<Value>,
    ) {
        for child in children.iter().rev() {
            match child {
                usvg::Node::Group(g) => {
                    let label = if g.id().is_empty() { "a group" } else { g.id() };
                    if g.clip_path().is_some() {
                        // Reached only inside a clipped group's layer (layer_runs).
                        self.warnings.add(format!(
                            "{label}: its clip path is not written: it is inside another clipped \
                             group, and Lottie masks whole layers (the content is drawn clipped by \
                             the outer one only)"
                        ));
                    }
                    self.warnings.unwritten_effects(g, label);
                    let opacity = f64::from(g.opacity().get());
                    if opacity < 1.0 {
                        let mut items = Vec::new();
                        self.group_items(g, lookup, &mut items);
                        if items.len() > 1 {
                            self.warnings.player(format!(
                                "{label}: rlottie (1.3.8) and ThorVG (1.1.3) apply the group's \
                                 opacity to each of its shapes, so where they overlap the group \
                                 is more opaque than in browsers"
                            ));
                        }
                        items.push(group_transform(opacity));
                        out.push(json!({"ty": "gr", "nm": label, "it": items}));
                    } else {
                        self.group_items(g, lookup, out);
                    }
                }
                usvg::Node::Path(p) => {
                    if let Some(element) = lookup(p.id()) {
                        if let Some(item) = self.path_group(p, element) {
                            out.push(item);
                        }
                    }
                }
                // Warned from the source (`text_ids`).
                usvg::Node::Text(_) => {}
                usvg::Node::Image(i) => {
                    self.warnings.add(format!("image {}: not written", i.id()));
                }
            }
        }
    }

    /// The group of one imported element: its paths keyframed, then its stroke and fill.
    fn path_group(&mut self, p: &usvg::Path, element: usize) -> Option<Value> {
        let e = &self.source.elements[element];
        if e.role != PathRole::Visible || !p.is_visible() {
            return None;
        }
        let label = e.label.clone();
        let map = e.local_to_root;
        let paths = e.paths.clone();
        let zero_area_fill = e.zero_area_fill;
        let fill_server = e.paint.fill_server.clone();
        let mut stroke = p
            .stroke()
            .and_then(|s| paint::stroke(s, map, &label, &mut self.warnings));
        let carried = self.paint_maps(element, fill_server.as_deref());
        let mut fill = if zero_area_fill {
            None
        } else {
            p.fill()
                .and_then(|f| paint::fill(f, map, carried.as_deref(), &label, &mut self.warnings))
        };
        // A fill drawn in its gradient's space has its own group, and the stroke then another.
        let space = fill.as_ref().and_then(|f| f.space);
        let fill_group = match (space, &fill) {
            (Some(m), Some(style)) => {
                let ends = style.ends.unwrap_or([Point::ZERO, Point::new(1.0, 0.0)]);
                let group = self.gradient_space_group(
                    element,
                    m,
                    ends,
                    style.value.clone(),
                    stroke.is_none(),
                );
                if group.is_none() {
                    // A frame whose element map is singular: drawn in root space after all.
                    fill = p.fill().and_then(|f| {
                        paint::fill_in_root_space(f, map, &label, &mut self.warnings)
                    });
                }
                group
            }
            _ => None,
        };
        let paint = self.source.elements[element].paint.clone();
        if let Some(style) = &mut stroke {
            self.follow_gradient(style, element, paint.stroke_server.as_deref());
        }
        if let Some(style) = &mut fill {
            self.follow_gradient(style, element, paint.fill_server.as_deref());
        }
        let mut items = Vec::new();
        let shapes = |writer: &mut Self| -> Vec<Value> {
            paths
                .clone()
                .map(|pi| {
                    let closed =
                        writer.drawing.paths[pi].closed && !writer.source.closed_without_z[pi];
                    writer.path_shape(pi, closed)
                })
                .collect()
        };
        if let Some(fill_group) = fill_group {
            let stroke_group = stroke.map(|style| {
                let mut it = shapes(self);
                it.push(style.value);
                it.push(group_transform(1.0));
                json!({"ty": "gr", "nm": "stroke", "it": it})
            });
            let groups = match p.paint_order() {
                usvg::PaintOrder::FillAndStroke => [stroke_group, Some(fill_group)],
                usvg::PaintOrder::StrokeAndFill => [Some(fill_group), stroke_group],
            };
            items.extend(groups.into_iter().flatten());
        } else {
            items = shapes(self);
            // Items listed first are drawn on top: SVG's default paint order puts the stroke
            // over the fill.
            let styles = match p.paint_order() {
                usvg::PaintOrder::FillAndStroke => [stroke, fill],
                usvg::PaintOrder::StrokeAndFill => [fill, stroke],
            };
            items.extend(styles.into_iter().flatten().map(|style| style.value));
        }
        items.push(group_transform(1.0));
        // `ln` becomes the group's id in SVG players: the element's own id where it has one.
        Some(json!({"ty": "gr", "nm": label, "ln": p.id(), "it": items}))
    }

    /// The path shape of drawing path `pi`, keyframed where needed.
    fn path_shape(&mut self, pi: usize, closed: bool) -> Value {
        let path = &self.drawing.paths[pi];
        let range = self.offsets[pi]..self.offsets[pi] + path.points.len();
        let per_frame: Vec<&[Point]> = self.frames.iter().map(|f| &f[range.clone()]).collect();
        let kept = keyframes(&per_frame, &self.frame_numbers, self.tolerance);
        self.keyframes += kept.len();
        let value = property(&kept, &self.frame_numbers, Kind::Shape, |f| {
            bezier(path, per_frame[f], closed, self.digits)
        });
        json!({"ty": "sh", "nm": format!("path {pi}"), "ks": value})
    }
}

/// The warnings of one export, each once: what the document does not express, and what it
/// expresses that some players draw otherwise ([`LottieExport::player_notes`]).
#[derive(Debug, Default)]
pub(super) struct Warnings(Vec<String>, Vec<String>);

impl Warnings {
    /// Adds `warning` unless it was given already.
    pub(super) fn add(&mut self, warning: String) {
        if !self.0.contains(&warning) {
            self.0.push(warning);
        }
    }

    /// Adds `note`, about a player that draws what is written otherwise, unless it was given
    /// already.
    pub(super) fn player(&mut self, note: String) {
        if !self.1.contains(&note) {
            self.1.push(note);
        }
    }

    /// What of group `g` (named `label`) is not written: its mask and its filters.
    pub(super) fn unwritten_effects(&mut self, g: &usvg::Group, label: &str) {
        if g.mask().is_some() {
            self.add(format!(
                "{label}: its mask is not written (the content is drawn unmasked)"
            ));
        }
        if !g.filters().is_empty() {
            self.add(format!("{label}: its filters are not written"));
        }
    }
}

/// What a keyframed property holds: a shape (keyframe values wrapped in an array, scalar
/// easing handles) or a vector (values as they are, one easing handle per dimension given
/// once).
#[derive(Clone, Copy)]
enum Kind {
    Shape,
    Vector,
    /// A number: static as it is, keyframe values as one-element arrays.
    Scalar,
}

/// A Lottie property whose value at frame `f` is `value(f)`: static (`"a": 0`) when only one
/// frame is kept, otherwise the kept frames as keyframes at their frame numbers with linear
/// easing, the last one holding.
fn property(
    kept: &[usize],
    frame_numbers: &[f64],
    kind: Kind,
    value: impl Fn(usize) -> Value,
) -> Value {
    if let [only] = kept {
        return json!({"a": 0, "k": value(*only)});
    }
    let (into, out) = match kind {
        Kind::Shape => (json!({"x": 1.0, "y": 1.0}), json!({"x": 0.0, "y": 0.0})),
        Kind::Vector | Kind::Scalar => (
            json!({"x": [1.0], "y": [1.0]}),
            json!({"x": [0.0], "y": [0.0]}),
        ),
    };
    let list: Vec<Value> = kept
        .iter()
        .enumerate()
        .map(|(j, &f)| {
            let v = match kind {
                Kind::Shape | Kind::Scalar => json!([value(f)]),
                Kind::Vector => value(f),
            };
            let mut key = json!({"t": frame_numbers[f], "s": v});
            if j + 1 < kept.len() {
                key["i"] = into.clone();
                key["o"] = out.clone();
            }
            key
        })
        .collect();
    json!({"a": 1, "k": list})
}

/// A group's transform item (`"ty": "tr"`, last in its group): identity, with `opacity`.
fn group_transform(opacity: f64) -> Value {
    json!({
        "ty": "tr",
        "a": {"a": 0, "k": [0.0, 0.0]},
        "p": {"a": 0, "k": [0.0, 0.0]},
        "s": {"a": 0, "k": [100.0, 100.0]},
        "r": {"a": 0, "k": 0.0},
        "o": {"a": 0, "k": 100.0 * opacity},
        "sk": {"a": 0, "k": 0.0},
        "sa": {"a": 0, "k": 0.0}
    })
}

/// Share of the export's tolerance given to rounding the paths' coordinates (the rest goes to
/// the keyframes): 0.1.
const QUANTUM_SHARE: f64 = 0.1;

/// The decimal digits to round coordinates to so that no point of a curve moves by more than
/// `budget`: a vertex and a tangent (relative to it) are each rounded by at most half a unit
/// of the last digit `g` per coordinate, so a control point by at most `√2 g`, and a curve
/// point (a convex combination of control points) too; `g` is the largest power of ten with
/// `√2 g ≤ budget`. Negative digits round to tens, hundreds…; `None` when nothing is to be
/// rounded (a zero budget: every frame kept exactly) or the digits would exceed what an `f64`
/// holds.
///
/// ```text
/// budget 0.058 (the fish: 0.1 of 1e-3 of its 583-unit diagonal)   → 2 digits (g = 0.01)
/// ```
fn quantum_digits(budget: f64) -> Option<i32> {
    if !(budget > 0.0 && budget.is_finite()) {
        return None;
    }
    let digits = (-(budget / std::f64::consts::SQRT_2).log10()).ceil() as i32;
    (digits <= 17).then_some(digits)
}

/// `x` rounded to `digits` decimal digits (module doc, "Size"), as the shortest number that
/// reads back to the rounded decimal.
fn rounded(x: f64, digits: Option<i32>) -> f64 {
    match digits {
        None => x,
        Some(d) if d >= 0 => format!("{x:.*}", d as usize).parse().unwrap_or(x),
        Some(d) => {
            let unit = 10f64.powi(-d);
            (x / unit).round() * unit
        }
    }
}

/// A Lottie bezier (`{c, v, i, o}`) of a chain with control points `points` (module
/// documentation), its coordinates rounded to `digits` ([`rounded`]). `closed`: the chain's
/// last point repeats its first and is dropped.
fn bezier(path: &Path, points: &[Point], closed: bool, digits: Option<i32>) -> Value {
    debug_assert_eq!(points.len(), path.points.len());
    let n_curves = (points.len() - 1) / 3;
    let n_vertices = if closed { n_curves } else { n_curves + 1 };
    let xy = |p: Point| [rounded(p.x, digits), rounded(p.y, digits)];
    let rel = |c: Point, p: Point| [rounded(c.x - p.x, digits), rounded(c.y - p.y, digits)];
    let mut v = Vec::with_capacity(n_vertices);
    let mut i = Vec::with_capacity(n_vertices);
    let mut o = Vec::with_capacity(n_vertices);
    for k in 0..n_vertices {
        let p = points[3 * k];
        v.push(xy(p));
        o.push(if 3 * k + 1 < points.len() {
            rel(points[3 * k + 1], p)
        } else {
            [0.0, 0.0]
        });
        i.push(if k > 0 {
            rel(points[3 * k - 1], p)
        } else if closed {
            rel(points[points.len() - 2], p)
        } else {
            [0.0, 0.0]
        });
    }
    json!({"c": closed, "v": v, "i": i, "o": o})
}

#[cfg(test)]
mod tests;
