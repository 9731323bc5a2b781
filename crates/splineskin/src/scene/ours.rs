//! Our scene format (JSON), version 1.
//!
//! ```json
//! {
//!   "splineskin_scene": 1,
//!   "svg": "drawing.svg",
//!   "handles": [ { "position": [120, 80] }, { "position": [300, 90] } ],
//!   "weights": { "family": "shepard", "exponent": 2 },
//!   "arc_length": false,
//!   "junctions": [ { "path": 0, "joint": 3, "kind": "C1" } ],
//!   "poses": [
//!     { "name": "wave", "transforms": [ { "rotate": 20 }, { "translate": [40, -10], "scale": 1.2 } ] }
//!   ]
//! }
//! ```
//!
//! | key | meaning |
//! |---|---|
//! | `splineskin_scene` | format version, `1` (required: it marks the format) |
//! | `svg` / `svg_text` | the SVG file (relative to the scene's folder) or the document inline; exactly one |
//! | `handles` | point handles: `position` = rest position in the SVG's user units (viewBox) |
//! | `weights` | `family`: `shepard` (`exponent`, default 2), or the mesh families `harmonic`, `biharmonic`, `bbw` (computed on a triangulation of the drawing's domain, [`crate::domain`]); `mvc` is recognised but not implemented yet |
//! | `arc_length` | integrate with respect to arc length rather than length-weighted `t` (default false) |
//! | `junctions` | overrides: path index (subpaths in document order), joint index (joint `k` starts curve `k`), `kind` ∈ `C0`, `C1`, `G1`, `angle` |
//! | `pose` / `poses` | one pose (a list of transforms, one per handle) or a list of `{name?, transforms}` |
//!
//! A transform is one of
//! * `[a, b, c, d, e, f]`: the SVG matrix mapping `(x, y)` to `(a x + c y + e, b x + d y + f)`;
//! * `{"a": …, "b": …, "c": …, "d": …, "e": …, "f": …}`: the same, by name;
//! * `{"translate": [dx, dy], "rotate": degrees, "scale": s | [sx, sy]}` (each optional): scale,
//!   then rotate **about the handle's rest position**, then translate.

use std::path::Path as FsPath;

use kurbo::{Affine, Vec2};
use serde::Deserialize;

use super::{
    check_affine, check_point, json_error, Engine, JunctionOverride, Pose, Scene, SceneError,
    SceneFormat, WeightSpec, MAX_SCENE_BYTES,
};
use crate::drawing::JointKind;
use crate::spline_fit::Measure;

/// The format version this library writes and reads.
pub const SCENE_VERSION: u32 = 1;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    splineskin_scene: u32,
    #[serde(default)]
    svg: Option<String>,
    #[serde(default)]
    svg_text: Option<String>,
    handles: Vec<HandleFile>,
    #[serde(default)]
    weights: Option<WeightsFile>,
    #[serde(default)]
    arc_length: bool,
    #[serde(default)]
    engine: Option<String>,
    #[serde(default)]
    junctions: Vec<JunctionFile>,
    #[serde(default)]
    pose: Option<Vec<TransformFile>>,
    #[serde(default)]
    poses: Option<Vec<PoseFile>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct HandleFile {
    position: [f64; 2],
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct WeightsFile {
    family: String,
    #[serde(default)]
    exponent: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct JunctionFile {
    path: usize,
    joint: usize,
    kind: JointKind,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PoseFile {
    #[serde(default)]
    name: Option<String>,
    transforms: Vec<TransformFile>,
}

#[derive(Deserialize)]
#[serde(untagged)]
enum TransformFile {
    Matrix([f64; 6]),
    Named(NamedTransform),
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct NamedTransform {
    a: Option<f64>,
    b: Option<f64>,
    c: Option<f64>,
    d: Option<f64>,
    e: Option<f64>,
    f: Option<f64>,
    translate: Option<[f64; 2]>,
    rotate: Option<f64>,
    scale: Option<ScaleFile>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(untagged)]
enum ScaleFile {
    Uniform(f64),
    NonUniform([f64; 2]),
}

impl TransformFile {
    fn affine(
        &self,
        pivot: kurbo::Point,
        origin: &str,
        element: &str,
    ) -> Result<Affine, SceneError> {
        let invalid = |message: String| SceneError::Invalid {
            origin: origin.to_string(),
            element: element.to_string(),
            message,
        };
        match self {
            TransformFile::Matrix(m) => Ok(Affine::new(*m)),
            TransformFile::Named(n) => {
                let matrix = [n.a, n.b, n.c, n.d, n.e, n.f];
                let has_matrix = matrix.iter().any(Option::is_some);
                let has_parts = n.translate.is_some() || n.rotate.is_some() || n.scale.is_some();
                if has_matrix && has_parts {
                    return Err(invalid(
                        "give either the matrix a..f or translate/rotate/scale, not both".into(),
                    ));
                }
                if has_matrix {
                    let m: Option<Vec<f64>> = matrix.iter().copied().collect();
                    let m =
                        m.ok_or_else(|| invalid("a matrix needs all of a, b, c, d, e, f".into()))?;
                    return Ok(Affine::new([m[0], m[1], m[2], m[3], m[4], m[5]]));
                }
                let (sx, sy) = match n.scale {
                    None => (1.0, 1.0),
                    Some(ScaleFile::Uniform(s)) => (s, s),
                    Some(ScaleFile::NonUniform([sx, sy])) => (sx, sy),
                };
                let t = n.translate.unwrap_or([0.0, 0.0]);
                let about = Vec2::new(pivot.x, pivot.y);
                Ok(Affine::translate(about + Vec2::new(t[0], t[1]))
                    * Affine::rotate(n.rotate.unwrap_or(0.0).to_radians())
                    * Affine::scale_non_uniform(sx, sy)
                    * Affine::translate(-about))
            }
        }
    }
}

pub(crate) fn parse(
    text: &str,
    origin: &str,
    base_dir: Option<&FsPath>,
) -> Result<Scene, SceneError> {
    let file: SceneFile = serde_json::from_str(text).map_err(|e| {
        if !text.contains("\"splineskin_scene\"") {
            SceneError::Json {
                origin: origin.to_string(),
                message: "not a scene: expected our format (with \"splineskin_scene\": 1) or the paper authors' (with \"gInputSVGText\")".into(),
            }
        } else {
            json_error(origin, e)
        }
    })?;
    let invalid = |element: &str, message: String| SceneError::Invalid {
        origin: origin.to_string(),
        element: element.to_string(),
        message,
    };
    if file.splineskin_scene != SCENE_VERSION {
        return Err(invalid(
            "splineskin_scene",
            format!(
                "version {} is not supported (expected {SCENE_VERSION})",
                file.splineskin_scene
            ),
        ));
    }
    let (svg_text, svg_origin) = match (file.svg, file.svg_text) {
        (Some(_), Some(_)) => {
            return Err(invalid(
                "svg",
                "give either svg or svg_text, not both".into(),
            ))
        }
        (None, None) => {
            return Err(invalid(
                "svg",
                "missing: give svg (a file) or svg_text".into(),
            ))
        }
        (None, Some(text)) => (text, format!("{origin} (svg_text)")),
        (Some(name), None) => {
            let path = match base_dir {
                Some(dir) => dir.join(&name),
                None => FsPath::new(&name).to_path_buf(),
            };
            // The message names the scene and its `svg` field as well as the file: a missing
            // drawing is an error in the scene.
            let unreadable = |e: std::io::Error| {
                invalid(
                    "svg",
                    format!(
                        "cannot read the drawing {}: {e} (expected an SVG file; a relative \
                         name is taken from the scene's folder)",
                        path.display()
                    ),
                )
            };
            let meta = std::fs::metadata(&path).map_err(unreadable)?;
            if meta.len() > MAX_SCENE_BYTES {
                return Err(SceneError::TooLarge {
                    path,
                    size: meta.len(),
                    limit: MAX_SCENE_BYTES,
                });
            }
            let text = std::fs::read_to_string(&path).map_err(unreadable)?;
            (text, path.display().to_string())
        }
    };
    let handles = file
        .handles
        .iter()
        .enumerate()
        .map(|(i, h)| check_point(h.position, origin, format!("handles[{i}].position")))
        .collect::<Result<Vec<_>, _>>()?;
    let weights = match &file.weights {
        Some(w) => WeightSpec::parse(&w.family, w.exponent, origin)?,
        None => WeightSpec::parse("shepard", None, origin)?,
    };
    let engine = Engine::parse(file.engine.as_deref().unwrap_or("ours"), origin)?;
    let junctions = file
        .junctions
        .iter()
        .enumerate()
        .map(|(i, j)| {
            if j.kind == JointKind::End {
                Err(invalid(
                    &format!("junctions[{i}].kind"),
                    "'end' cannot be imposed (expected C0, C1, G1 or angle)".into(),
                ))
            } else {
                Ok(JunctionOverride {
                    path: j.path,
                    joint: j.joint,
                    kind: j.kind,
                })
            }
        })
        .collect::<Result<Vec<_>, _>>()?;
    let pose_files: Vec<(Option<String>, &Vec<TransformFile>)> = match (&file.pose, &file.poses) {
        (Some(_), Some(_)) => {
            return Err(invalid(
                "pose",
                "give either pose or poses, not both".into(),
            ))
        }
        (Some(p), None) => vec![(None, p)],
        (None, Some(ps)) => ps.iter().map(|p| (p.name.clone(), &p.transforms)).collect(),
        (None, None) => Vec::new(),
    };
    let mut poses = Vec::with_capacity(pose_files.len());
    for (k, (name, transforms)) in pose_files.into_iter().enumerate() {
        if transforms.len() != handles.len() {
            return Err(invalid(
                &format!("poses[{k}]"),
                format!(
                    "{} transforms for {} handles (one per handle expected)",
                    transforms.len(),
                    handles.len()
                ),
            ));
        }
        let transforms = transforms
            .iter()
            .zip(&handles)
            .enumerate()
            .map(|(i, (t, &h))| {
                let element = format!("poses[{k}].transforms[{i}]");
                check_affine(t.affine(h, origin, &element)?, origin, element)
            })
            .collect::<Result<Vec<_>, _>>()?;
        poses.push(Pose { name, transforms });
    }
    Ok(Scene {
        origin: origin.to_string(),
        svg_text,
        svg_origin,
        handles,
        weights,
        engine,
        measure: Measure::from_arc_length(file.arc_length),
        junctions,
        authors_joints: None,
        poses,
        format: SceneFormat::Ours,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use kurbo::Point;

    const SVG: &str = "<svg xmlns='http://www.w3.org/2000/svg'><path d='M0 0 C1 1 2 1 3 0'/></svg>";

    fn scene(extra: &str) -> Result<Scene, SceneError> {
        let json = format!(
            r#"{{"splineskin_scene": 1, "svg_text": "{SVG}", "handles": [{{"position": [10, 20]}}]{extra}}}"#
        );
        parse(&json, "test", None)
    }

    #[test]
    fn scene_transform_about_handle() {
        let s = scene(r#", "pose": [{"rotate": 90, "translate": [1, 0]}]"#).unwrap();
        let t = s.poses[0].transforms[0];
        // The handle itself only translates.
        assert!((t * Point::new(10.0, 20.0) - Point::new(11.0, 20.0)).hypot() < 1e-12);
        // A point 1 to the right of it turns to 1 below it (y down in SVG: +90° maps x to y).
        assert!((t * Point::new(11.0, 20.0) - Point::new(11.0, 21.0)).hypot() < 1e-12);
    }

    #[test]
    fn scene_matrix_forms_agree() {
        let a = scene(r#", "pose": [[1, 2, 3, 4, 5, 6]]"#).unwrap();
        let b = scene(r#", "pose": [{"a": 1, "b": 2, "c": 3, "d": 4, "e": 5, "f": 6}]"#).unwrap();
        assert_eq!(a.poses, b.poses);
        assert_eq!(
            a.poses[0].transforms[0].as_coeffs(),
            [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]
        );
    }

    #[test]
    fn scene_errors_name_the_element() {
        let e = scene(r#", "pose": [[1, 2, 3, 4, 5, 6], [1, 0, 0, 1, 0, 0]]"#).unwrap_err();
        assert!(e.to_string().contains("poses[0]"), "{e}");
        let e = scene(r#", "pose": [[1e308, 0, 0, 1, 0, 0]]"#).unwrap_err();
        assert!(e.to_string().contains("poses[0].transforms[0]"), "{e}");
        let e = scene(r#", "weights": {"family": "magic"}"#).unwrap_err();
        assert!(
            e.to_string().contains("unknown weight family 'magic'"),
            "{e}"
        );
        let e = scene(r#", "junctions": [{"path": 0, "joint": 1, "kind": "C3"}]"#).unwrap_err();
        assert!(e.to_string().contains("test"), "{e}");
        let e = parse("{}", "x.json", None).unwrap_err();
        assert!(e.to_string().contains("not a scene"), "{e}");
        let e = parse(
            "{\"splineskin_scene\": 1, \"svg\": \"missing.svg\", \"handles\": []}",
            "x.json",
            None,
        )
        .unwrap_err();
        assert!(e.to_string().contains("missing.svg"), "{e}");
    }

    #[test]
    fn scene_not_implemented_family_loads_but_is_reported() {
        let s = scene(r#", "weights": {"family": "mvc"}"#).unwrap();
        let e = s.check_supported().unwrap_err();
        assert!(e.to_string().contains("weight function 'mvc'"), "{e}");
        let s = scene(r#", "weights": {"family": "bbw"}"#).unwrap();
        assert_eq!(s.weights, WeightSpec::Mesh(crate::scene::MeshFamily::Bbw));
        assert!(s.check_supported().is_ok());
    }
}
