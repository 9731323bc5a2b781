//! The fitted cage's frames as a USD text layer (`.usda`): one `Mesh` prim with
//! `subdivisionScheme = "catmullClark"`, the cage's faces and tags, and `points` sampled at one
//! time code per frame.
//!
//! | USD attribute | from |
//! |---|---|
//! | `faceVertexCounts`, `faceVertexIndices` | the cage's faces, in order |
//! | `points.timeSamples` | frame `k` at time code `t_k · fps` (`timeCodesPerSecond = fps`) |
//! | `creaseIndices`, `creaseLengths`, `creaseSharpnesses` | every `t crease` edge as a chain of two vertices with its sharpness |
//! | `cornerIndices`, `cornerSharpnesses` | `t corner` tags |
//! | `holeIndices` | `t hole` faces |
//! | `interpolateBoundary = "edgeAndCorner"`, `triangleSubdivisionRule = "catmullClark"` | the options this crate refines with ([`crate`]) |
//! | `extent.timeSamples` | each frame's bounding box |
//!
//! OpenSubdiv (USD's own subdivision) then gives every frame's limit surface exactly as this
//! crate does. Numbers are written in Rust's shortest round-trip form of the `f32` USD stores.

use std::fmt::Write;

use super::super::cage::{Cage, Point3};
use super::{check_frames, extent_f32, HandoffError, UpAxis};

/// The frames of an animated cage.
#[derive(Clone, Copy, Debug)]
pub struct CageFrames<'a> {
    /// The cage (faces and tags; its positions are the rest pose).
    pub cage: &'a Cage,
    /// Every frame's time, seconds, increasing.
    pub times: &'a [f64],
    /// Every frame's vertex positions (`cage.n_vertices()` each).
    pub positions: &'a [Vec<Point3>],
    /// Frames per second: USD's `timeCodesPerSecond` and `framesPerSecond`.
    pub fps: f64,
    /// The mesh prim's name (made a valid USD identifier: other characters become `_`).
    pub name: &'a str,
    /// The stage's up axis.
    pub up: UpAxis,
}

/// The USD text layer of `frames` (module documentation).
///
/// ```
/// use splineskin_subdiv::handoff::{write_usda, CageFrames, UpAxis};
/// use splineskin_subdiv::parse_obj;
///
/// let cage = parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nt crease 2/1/0 1 2 3\n", "quad.obj")?;
/// let moved: Vec<[f64; 3]> = cage.positions().iter().map(|p| [p[0], p[1] + 0.5, p[2]]).collect();
/// let frames = [cage.positions().to_vec(), moved];
/// let usda = write_usda(&CageFrames {
///     cage: &cage, times: &[0.0, 0.5], positions: &frames, fps: 2.0, name: "quad", up: UpAxis::Y,
/// })?;
/// assert!(usda.starts_with("#usda 1.0"));
/// assert!(usda.contains("uniform token subdivisionScheme = \"catmullClark\""));
/// assert!(usda.contains("1: [(0.0, 0.5, 0.0), (1.0, 0.5, 0.0), (1.0, 1.5, 0.0), (0.0, 1.5, 0.0)]"));
/// assert!(usda.contains("float[] creaseSharpnesses = [3.0]"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_usda(frames: &CageFrames) -> Result<String, HandoffError> {
    let cage = frames.cage;
    check_frames(frames.times, frames.positions, cage.n_vertices())?;
    if !(frames.fps > 0.0 && frames.fps.is_finite()) {
        return Err(HandoffError::Frames {
            what: format!("{} frames per second; expected a positive rate", frames.fps),
        });
    }
    let codes: Vec<f64> = frames
        .times
        .iter()
        .map(|t| time_code(*t, frames.fps))
        .collect();
    let mut out = String::new();
    write_stage_header(&mut out, frames, &codes);
    let name = identifier(frames.name);
    let _ = writeln!(out, "def Mesh \"{name}\"\n{{");
    write_topology(&mut out, cage);
    write_samples(
        &mut out,
        "point3f[] points",
        &codes,
        frames.positions,
        points,
    );
    write_samples(&mut out, "float3[] extent", &codes, frames.positions, |p| {
        let (lo, hi) = extent_f32(p.iter().map(|q| q.map(|c| c as f32)));
        format!("[{}, {}]", tuple(lo), tuple(hi))
    });
    write_tags(&mut out, cage);
    out.push_str("}\n");
    Ok(out)
}

fn write_stage_header(out: &mut String, frames: &CageFrames, codes: &[f64]) {
    let fps = frames.fps;
    let up = match frames.up {
        UpAxis::Y => "Y",
        UpAxis::Z => "Z",
    };
    let _ = write!(
        out,
        "#usda 1.0\n(\n    defaultPrim = \"{}\"\n    doc = \"splineskin: a Catmull-Clark cage fitted so that its limit surface follows the skinned surface, baked per frame\"\n    startTimeCode = {}\n    endTimeCode = {}\n    timeCodesPerSecond = {fps}\n    framesPerSecond = {fps}\n    upAxis = \"{up}\"\n)\n\n",
        identifier(frames.name),
        codes[0],
        codes[codes.len() - 1],
    );
}

fn write_topology(out: &mut String, cage: &Cage) {
    let counts: Vec<String> = cage.face_sizes().map(|n| n.to_string()).collect();
    let indices: Vec<String> = cage.face_vertices().iter().map(|v| v.to_string()).collect();
    let _ = writeln!(out, "    int[] faceVertexCounts = [{}]", counts.join(", "));
    let _ = writeln!(
        out,
        "    int[] faceVertexIndices = [{}]",
        indices.join(", ")
    );
    out.push_str("    uniform token orientation = \"rightHanded\"\n");
    out.push_str("    uniform token subdivisionScheme = \"catmullClark\"\n");
    out.push_str("    uniform token interpolateBoundary = \"edgeAndCorner\"\n");
    out.push_str("    uniform token triangleSubdivisionRule = \"catmullClark\"\n");
}

/// `name.timeSamples = { code: value, … }`, with frame 0 also as the default value (what a
/// reader without time sees).
fn write_samples(
    out: &mut String,
    name: &str,
    codes: &[f64],
    frames: &[Vec<Point3>],
    value: impl Fn(&[Point3]) -> String,
) {
    let _ = writeln!(out, "    {name} = {}", value(&frames[0]));
    let _ = writeln!(out, "    {name}.timeSamples = {{");
    for (code, frame) in codes.iter().zip(frames) {
        let _ = writeln!(out, "        {code}: {},", value(frame));
    }
    out.push_str("    }\n");
}

fn write_tags(out: &mut String, cage: &Cage) {
    let tags = cage.tags();
    let list = |items: Vec<String>| items.join(", ");
    if !tags.creases.is_empty() {
        let indices = tags
            .creases
            .iter()
            .flat_map(|c| c.vertices)
            .map(|v| v.to_string());
        let lengths = tags.creases.iter().map(|_| "2".to_string());
        let sharp = tags
            .creases
            .iter()
            .map(|c| format!("{:?}", c.sharpness as f32));
        let _ = writeln!(
            out,
            "    int[] creaseIndices = [{}]",
            list(indices.collect())
        );
        let _ = writeln!(
            out,
            "    int[] creaseLengths = [{}]",
            list(lengths.collect())
        );
        let _ = writeln!(
            out,
            "    float[] creaseSharpnesses = [{}]",
            list(sharp.collect())
        );
    }
    if !tags.corners.is_empty() {
        let indices = tags.corners.iter().map(|c| c.vertex.to_string());
        let sharp = tags
            .corners
            .iter()
            .map(|c| format!("{:?}", c.sharpness as f32));
        let _ = writeln!(
            out,
            "    int[] cornerIndices = [{}]",
            list(indices.collect())
        );
        let _ = writeln!(
            out,
            "    float[] cornerSharpnesses = [{}]",
            list(sharp.collect())
        );
    }
    if !tags.holes.is_empty() {
        let holes = tags.holes.iter().map(|f| f.to_string());
        let _ = writeln!(out, "    int[] holeIndices = [{}]", list(holes.collect()));
    }
}

/// Time `t` (seconds) in frames, `t · fps`, snapped to the whole frame it is within `1e-9` of
/// (frame `f` is at `f / fps` seconds, which times `fps` may miss `f` by an ulp).
fn time_code(t: f64, fps: f64) -> f64 {
    let code = t * fps;
    if (code - code.round()).abs() < 1e-9 {
        code.round()
    } else {
        code
    }
}

fn points(frame: &[Point3]) -> String {
    let items: Vec<String> = frame.iter().map(|p| tuple(p.map(|c| c as f32))).collect();
    format!("[{}]", items.join(", "))
}

fn tuple(p: [f32; 3]) -> String {
    format!("({:?}, {:?}, {:?})", p[0], p[1], p[2])
}

/// `name` as a USD prim name: letters, digits and `_`, not starting with a digit; `Cage` if
/// nothing is left.
fn identifier(name: &str) -> String {
    let mut id: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    if id.is_empty() {
        id.push_str("Cage");
    } else if id.starts_with(|c: char| c.is_ascii_digit()) {
        id.insert(0, '_');
    }
    id
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identifiers_are_valid_prim_names() {
        assert_eq!(identifier("tube-scene"), "tube_scene");
        assert_eq!(identifier("3d"), "_3d");
        assert_eq!(identifier(""), "Cage");
        assert_eq!(identifier("é"), "_");
    }
}
