//! The routes about documents: the initial one, uploads, export and scene files (the crate's
//! documentation has the table of routes).

use std::sync::Arc;

use kurbo::{Affine, Point};
use splineskin::defop::MeshMap;
use splineskin::drawing::animated_image::AnimatedFormat;
use splineskin::drawing::follow::{ElementMaps, FollowOptions};
use splineskin::drawing::svg_out::{
    art_bounds, art_outside_view_box, write_svg_with, SvgOptions, ViewBoxRule,
};
use splineskin::naive::skin_point;
use splineskin::scene::ours_write::SvgRef;
use splineskin::scene::{place_pins, PinOptions, PoseOptions};
use splineskin::scene_animation::{AnimationRig, SceneAnimationError, ANIMATED_IMAGE_SIZE};

use crate::document::Document;
use crate::editor::{lock_puppet, Editor};
use crate::request::{ApiError, Request, Response, MAX_HANDLES};
use crate::rig_routes::{checked_scene, gone_rig};
use crate::store::{OperatorRig, Rig};
use crate::wire::{
    AnimationQuery, EditScene, ExportQuery, FoldWire, OutsideWire, PinsRequest, ViewBoxReport,
};

/// `GET /api/initial`.
pub(crate) fn initial(editor: &Editor) -> Result<Response, ApiError> {
    let document = editor
        .store()
        .initial()
        .ok_or_else(|| ApiError::new(404, "no initial document"))?;
    Response::json(&document.info)
}

/// `POST /api/open`.
pub(crate) fn open(editor: &Editor, request: &Request) -> Result<Response, ApiError> {
    let body = request.upload()?;
    let name = request
        .header("x-file-name")
        .map(percent_decode)
        .filter(|n| !n.is_empty())
        .unwrap_or_else(|| "upload".to_string());
    let document = Document::open(&name, body)?;
    let document = editor.store().add_document(document);
    Response::json(&document.info)
}

/// Decodes `%XX` escapes (the page sends file names with `encodeURIComponent`); anything
/// malformed is kept as it is.
pub(crate) fn percent_decode(s: &str) -> String {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' && i + 2 < bytes.len() {
            if let Some(b) = s
                .get(i + 1..i + 3)
                .and_then(|hex| u8::from_str_radix(hex, 16).ok())
            {
                out.push(b);
                i += 3;
                continue;
            }
        }
        out.push(bytes[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// `POST /api/documents/{id}/export` ([`ExportQuery`]: the query and the body's layout).
pub(crate) fn export(editor: &Editor, id: &str, request: &Request) -> Result<Response, ApiError> {
    let query: ExportQuery = request.query("export")?;
    let rule = view_box_rule("export", query.viewbox.as_deref())?;
    let body = request.upload()?;
    let document = editor.document(id)?;
    let deformation =
        match (&query.rig, &query.defop) {
            (None, None) => Deformation::Unknown,
            (Some(rig), None) => {
                let found = editor.store().rig(rig).ok_or_else(|| gone_rig(rig))?;
                check_built_on(&found.document, id, "rig", rig)?;
                Deformation::Skinning(found)
            }
            (None, Some(op)) => {
                let found = editor.store().defop(op).ok_or_else(|| gone_operator(op))?;
                check_built_on(&found.document, id, "operator", op)?;
                Deformation::Operator(found)
            }
            (Some(_), Some(_)) => return Err(ApiError::bad(
                "export: rig= and defop= both given (expected the one that deformed the drawing)",
            )),
        };
    let svg = {
        let n_bytes = 16 * document.drawing.n_points();
        let points = points_of(&document, &body[..n_bytes.min(body.len())])?;
        let tail = &body[n_bytes..];
        let maps = deformation.element_maps(&document, tail)?;
        let inserted = (!document.inserted.is_empty()).then_some(document.inserted.as_slice());
        let options = SvgOptions::default()
            .with_view_box(rule)
            .with_follow(maps.as_ref())
            .with_inserted(inserted);
        write_svg_with(&document.drawing, &points, &options)
            .map_err(|e| ApiError::bad(e.to_string()))?
    };
    Ok(Response::ok("image/svg+xml; charset=utf-8", svg))
}

/// The viewBox rule a query's `viewbox` names: `keep` (the default) or `fit`; `route` names
/// the route in the refusal.
fn view_box_rule(route: &str, viewbox: Option<&str>) -> Result<ViewBoxRule, ApiError> {
    match viewbox {
        None | Some("keep") => Ok(ViewBoxRule::Keep),
        Some("fit") => Ok(ViewBoxRule::Fit),
        Some(other) => Err(ApiError::bad(format!(
            "{route}: viewbox={other} (expected keep or fit)"
        ))),
    }
}

/// What deformed an exported drawing ([`ExportQuery`]).
enum Deformation {
    /// Not said: only the points are known.
    Unknown,
    /// A rig's weights, under the pose the body carries.
    Skinning(Arc<Rig>),
    /// A trained operator, at the configuration the body carries.
    Operator(Arc<OperatorRig>),
}

impl Deformation {
    /// The best-fit maps of the deformation over the document's elements, reading its pose or
    /// configuration from `tail` (the body after the points); `None` when it is not known.
    fn element_maps(
        &self,
        document: &Document,
        tail: &[u8],
    ) -> Result<Option<ElementMaps>, ApiError> {
        let name = &document.name;
        let expect = |per_handle: usize, n_handles: usize, what: &str| {
            let expected = 8 * per_handle * n_handles;
            if tail.len() == expected {
                Ok(f64s(tail))
            } else {
                Err(ApiError::bad(format!(
                    "{name}: export: {} bytes after the points (expected {what}: {expected} \
                     bytes, {per_handle} f64 for each of {n_handles} handles)",
                    tail.len()
                )))
            }
        };
        let options = FollowOptions::default();
        let bad = |e: &dyn std::fmt::Display| ApiError::bad(format!("{name}: export: {e}"));
        let maps = match self {
            Deformation::Unknown if tail.is_empty() => return Ok(None),
            Deformation::Unknown => {
                let n = document.drawing.n_points();
                return Err(ApiError::bad(format!(
                    "{name}: {} bytes of points for a drawing of {n} points (expected {}; a \
                     pose or configuration after the points needs rig= or defop= in the query)",
                    16 * n + tail.len(),
                    16 * n
                )));
            }
            Deformation::Skinning(rig) => {
                let puppet = lock_puppet(rig)?;
                let field = puppet
                    .weights()
                    .ok_or_else(|| ApiError::bad("the rig's weights are not computed"))?;
                let n_handles = field.n_handles();
                let values = expect(6, n_handles, "the pose")?;
                let pose: Vec<Affine> = values
                    .chunks_exact(6)
                    .map(|c| Affine::new(c.try_into().expect("6 values")))
                    .collect();
                if let Some(k) = pose.iter().position(|t| !t.is_finite()) {
                    return Err(ApiError::bad(format!(
                        "{name}: export: pose[{k}]: not finite"
                    )));
                }
                let mut w = vec![0.0; n_handles];
                let mut map = |p: Point| skin_point(field, &pose, p, &mut w);
                ElementMaps::from_map(&document.drawing, &mut map, &options).map_err(|e| bad(&e))?
            }
            Deformation::Operator(rig) => {
                let values = expect(2, rig.rig.n_handles(), "the configuration Q")?;
                let q: Vec<Point> = values
                    .chunks_exact(2)
                    .map(|c| Point::new(c[0], c[1]))
                    .collect();
                if let Some(k) = q.iter().position(|p| !p.is_finite()) {
                    return Err(ApiError::bad(format!("{name}: export: Q[{k}]: not finite")));
                }
                let map = MeshMap::from_operator(&rig.base.mesh, &rig.training.op, &q)
                    .map_err(|e| bad(&e))?;
                ElementMaps::from_map(&document.drawing, &mut |p| map.apply(p), &options)
                    .map_err(|e| bad(&e))?
            }
        };
        Ok(Some(maps))
    }
}

/// Refuses a rig or operator built on another document than the one exported.
fn check_built_on(built_on: &str, document: &str, what: &str, id: &str) -> Result<(), ApiError> {
    if built_on == document {
        Ok(())
    } else {
        Err(ApiError::bad(format!(
            "export: {what} {id} was built on document {built_on}, not {document}"
        )))
    }
}

pub(crate) fn gone_operator(id: &str) -> ApiError {
    ApiError::new(
        404,
        format!(
            "operator {id} is no longer kept (the editor keeps the latest few): train it again"
        ),
    )
}

/// `POST /api/documents/{id}/pins` ([`PinsRequest`]): pins placed over the drawing's art as
/// `splineskin rig` places them ([`place_pins`]: farthest points inside the filled shapes, as
/// many as cover the art), the page's own pins (rest positions) kept first and exactly.
pub(crate) fn pins(editor: &Editor, id: &str, request: &Request) -> Result<Response, ApiError> {
    let request: PinsRequest = request.json()?;
    let document = editor.document(id)?;
    let given: Vec<Point> = request
        .handles
        .iter()
        .map(|&[x, y]| Point::new(x, y))
        .collect();
    let options = PinOptions::default().with_pin_range(1, MAX_AUTO_PINS.max(given.len()));
    let pins = place_pins(&document.drawing, &given, &options)
        .map_err(|e| ApiError::bad(format!("{}: placing pins: {e}", document.name)))?;
    if pins.len() > MAX_HANDLES {
        return Err(ApiError::bad(format!(
            "{}: {} pins would be more than the {MAX_HANDLES} a rig takes",
            document.name,
            pins.len()
        )));
    }
    Response::json(
        &serde_json::json!({ "pins": pins.iter().map(|p| [p.x, p.y]).collect::<Vec<_>>() }),
    )
}

/// The most pins `POST /api/documents/{id}/pins` adds to cover a drawing: 12 (Puppet Warp
/// places a handful; a drawing needs more only for detailed posing, which the user adds).
pub const MAX_AUTO_PINS: usize = 12;

/// `POST /api/documents/{id}/outside`: which paths of the drawing through the posted points
/// leave the document's viewBox, the viewBox a `fit` export would write, and where the
/// drawing folds an outline over itself.
pub(crate) fn outside(editor: &Editor, id: &str, request: &Request) -> Result<Response, ApiError> {
    let body = request.upload()?;
    let document = editor.document(id)?;
    let report = {
        let points = points_of(&document, body)?;
        let bad = |e: splineskin::drawing::SvgError| ApiError::bad(e.to_string());
        let mut outside = art_outside_view_box(&document.drawing, &points).map_err(bad)?;
        outside.sort_by(|a, b| b.distance.total_cmp(&a.distance));
        let view_box = document.info.view_box;
        let input = document.drawing.source.as_ref().map_or_else(
            || {
                let [x, y, w, h] = view_box;
                kurbo::Rect::new(x, y, x + w, y + h)
            },
            |s| s.view_box(),
        );
        let fitted = match art_bounds(&document.drawing, &points).map_err(bad)? {
            Some(art) if !outside.is_empty() => input.union(art),
            _ => input,
        };
        ViewBoxReport {
            view_box,
            fitted: [fitted.x0, fitted.y0, fitted.width(), fitted.height()],
            outside: outside
                .into_iter()
                .map(|o| OutsideWire {
                    path: o.path_index,
                    element: o.element,
                    distance: o.distance,
                })
                .collect(),
            folds: document
                .folds
                .new_crossings(&document.drawing, &points)
                .into_iter()
                .map(|f| FoldWire {
                    path: f.path,
                    curves: [f.curves.0, f.curves.1],
                    at: [f.at.x, f.at.y],
                })
                .collect(),
        }
    };
    Response::json(&report)
}

/// The deformed points of a request body (`f64` LE `x0, y0, x1, y1, …`), as many as the
/// document's drawing has.
fn points_of(document: &Document, body: &[u8]) -> Result<Vec<Point>, ApiError> {
    let n = document.drawing.n_points();
    if body.len() != 16 * n {
        return Err(ApiError::bad(format!(
            "{}: {} bytes of points for a drawing of {n} points (expected {})",
            document.name,
            body.len(),
            16 * n
        )));
    }
    Ok(f64s(body)
        .chunks_exact(2)
        .map(|c| Point::new(c[0], c[1]))
        .collect())
}

/// Little-endian `f64`s (a trailing partial number is ignored: callers check the length).
fn f64s(bytes: &[u8]) -> Vec<f64> {
    bytes
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect()
}

/// `POST /api/documents/{id}/scene`.
pub(crate) fn save_scene(
    editor: &Editor,
    id: &str,
    request: &Request,
) -> Result<Response, ApiError> {
    let scene: EditScene = request.json()?;
    let document = editor.document(id)?;
    let json = checked_scene(&document, &scene)?
        .to_json(SvgRef::Inline(&document.svg_text))
        .map_err(|e| ApiError::bad(e.to_string()))?;
    Ok(Response::ok("application/json", json))
}

/// What `POST /api/documents/{id}/lottie` says of the file it sends (header
/// [`LOTTIE_HEADER`], JSON).
#[derive(Debug, serde::Serialize)]
pub struct LottieReport {
    /// Path keyframes written.
    pub keyframes: usize,
    /// Path keyframes with every frame keyed.
    pub every_frame_keyframes: usize,
    /// Bytes of the file sent.
    pub bytes: usize,
    /// Bytes it would have with every frame keyed.
    pub every_frame_bytes: usize,
    /// What Lottie cannot express, and what setting up the rig warned about.
    pub warnings: Vec<String>,
    /// The summary line `splineskin animate` prints.
    pub summary: String,
}

/// The header of a Lottie export's [`LottieReport`].
pub const LOTTIE_HEADER: &str = "x-splineskin-lottie";

/// `POST /api/documents/{id}/lottie`: the page's scene, its timeline played as
/// `splineskin animate SCENE -o anim.json` plays it.
pub(crate) fn lottie(editor: &Editor, id: &str, request: &Request) -> Result<Response, ApiError> {
    let scene: EditScene = request.json()?;
    let document = editor.document(id)?;
    let (json, report) = {
        let (read, animation) = animated_scene(&document, &scene, "Lottie export")?;
        let stem = std::path::Path::new(&document.name)
            .file_stem()
            .map_or("splineskin".into(), |s| s.to_string_lossy().into_owned());
        let options = splineskin::drawing::lottie::LottieOptions::default().with_name(stem);
        let made = splineskin::scene_animation::lottie_of_scene(
            &read,
            &animation,
            splineskin::scene::PoseOptions {
                flexible: scene.flexible,
                ..Default::default()
            },
            &options,
            &document.name,
        )
        .map_err(anyhow::Error::from)?;
        let mut warnings = made.rig_warnings.clone();
        warnings.extend(made.lottie.warnings.iter().map(|w| w.to_string()));
        warnings.extend(made.lottie.player_notes.iter().cloned());
        let report = LottieReport {
            keyframes: made.lottie.keyframes,
            every_frame_keyframes: made.lottie.every_frame_keyframes,
            bytes: made.lottie.json.len(),
            every_frame_bytes: made.every_frame_bytes,
            warnings,
            summary: made.summary(&options),
        };
        (made.lottie.json, report)
    };
    let header =
        ascii_json(&serde_json::to_string(&report).map_err(|e| ApiError::bad(e.to_string()))?);
    Ok(Response::ok("application/json", json).with_header(LOTTIE_HEADER, header))
}

/// The page's scene with its animation, read as a scene file is; refused (naming the
/// document and `what` was asked) for an operator family or a timeline without keyframes.
fn animated_scene(
    document: &Document,
    scene: &EditScene,
    what: &str,
) -> Result<(splineskin::scene::Scene, splineskin::animation::Animation), ApiError> {
    if crate::page_scene::defop_energy(&scene.weights.family).is_some() {
        return Err(ApiError::bad(format!(
            "{}: {what} plays a rig of weights; pick a weight family (the trained operators are \
             not exported as animations yet)",
            document.name
        )));
    }
    let read = checked_scene(document, scene)?;
    let Some(animation) = read.animation.clone() else {
        return Err(ApiError::bad(format!(
            "{}: the timeline has no keyframes (key the pose at two times or more)",
            document.name
        )));
    };
    Ok((read, animation))
}

/// `POST /api/documents/{id}/animation?format=svg|gif|apng[&viewbox=keep|fit]`
/// ([`AnimationQuery`]), body the page's [`EditScene`] with an `animation`: the animation as
/// `splineskin animate SCENE -o anim.svg|anim.gif|anim.png [--viewbox fit]` writes it
/// ([`SceneFrames`]: an animated SVG, or every frame rendered
/// [`ANIMATED_IMAGE_SIZE`] pixels on its longer side into a GIF or an animated PNG). A build
/// without fonts (WebAssembly) renders no text: header `x-splineskin-warning` says so when the
/// drawing has any.
pub(crate) fn animation(
    editor: &Editor,
    id: &str,
    request: &Request,
) -> Result<Response, ApiError> {
    let query: AnimationQuery = request.query("animation")?;
    let scene: EditScene = request.json()?;
    let document = editor.document(id)?;
    let format = match query.format.as_str() {
        "svg" => None,
        "gif" => Some(AnimatedFormat::Gif),
        "apng" => Some(AnimatedFormat::Apng),
        other => {
            return Err(ApiError::bad(format!(
                "animation: format '{other}' (expected svg, gif or apng)"
            )))
        }
    };
    let fit = view_box_rule("animation", query.viewbox.as_deref())? == ViewBoxRule::Fit;
    let (read, animation) = animated_scene(&document, &scene, "the animation export")?;
    let failed = |e: SceneAnimationError| ApiError::bad(e.to_string());
    let posing = PoseOptions {
        flexible: scene.flexible,
        ..Default::default()
    };
    let rig = AnimationRig::of_scene(&read, &animation, posing, &document.name).map_err(failed)?;
    let frames = rig.frames();
    let response = match format {
        None => {
            let svg = frames.animated_svg(fit, |_, _| {}).map_err(failed)?;
            Response::ok("image/svg+xml; charset=utf-8", svg)
        }
        Some(format) => {
            let rule = frames.view_box(fit).map_err(failed)?;
            let bytes = frames
                .animated_image(format, ANIMATED_IMAGE_SIZE, rule, |_, _, _| {})
                .map_err(failed)?;
            let kind = match format {
                AnimatedFormat::Gif => "image/gif",
                _ => "image/png",
            };
            Response::ok(kind, bytes)
        }
    };
    let has_text = document
        .drawing
        .source
        .as_ref()
        .is_some_and(|s| s.text.contains("<text"));
    Ok(
        if format.is_some() && has_text && !splineskin::fonts::HAS_FONTS {
            response.with_header(
            WARNING_HEADER,
            "this build has no fonts: the frames are rendered without their text (splineskin serve and the command line draw it)".to_string(),
        )
        } else {
            response
        },
    )
}

/// The header of an answer that carries a warning for the user (plain ASCII text).
pub const WARNING_HEADER: &str = "x-splineskin-warning";

/// JSON text with every character beyond ASCII written as `\uXXXX` escapes (UTF-16, as JSON
/// has them), so that it fits in an HTTP header.
pub(crate) fn ascii_json(json: &str) -> String {
    let mut out = String::with_capacity(json.len());
    for c in json.chars() {
        if c.is_ascii() {
            out.push(c);
        } else {
            let mut units = [0u16; 2];
            for unit in c.encode_utf16(&mut units) {
                out.push_str(&format!("\\u{unit:04x}"));
            }
        }
    }
    out
}
