//! splineskin in WebAssembly: the library behind a small C ABI over linear memory, for a page
//! or Node to call without a server.
//!
//! Built for `wasm32-unknown-unknown` (see `docs/webassembly.md`). Data crosses the boundary
//! through buffers this module owns: the caller asks for an input buffer of `n` bytes
//! ([`splineskin_input`] returns its address in linear memory), writes UTF-8 into it, calls a
//! function, and reads the result from [`splineskin_output`] (`f64`s) or the message of a
//! failure from [`splineskin_message`] / [`splineskin_message_len`] (UTF-8). No Rust code here
//! dereferences a raw pointer: the buffers are `Vec`s whose addresses are handed out.
//!
//! The editor's page runs in a Web Worker through [`editor`]'s one export, answering the same
//! requests as `splineskin serve`.
//!
//! ```text
//! JS: p = splineskin_input(n); write bytes at p; k = splineskin_deform_scene(n, pose)
//!     k ≥ 0: read 2k f64 at splineskin_output()      k < 0: read the message
//! ```

pub mod editor;
#[cfg(all(target_arch = "wasm32", target_feature = "atomics"))]
pub mod threads;

use std::cell::RefCell;

use kurbo::{Affine, Point};
use splineskin::scene::{Compat, PoseOptions, PosedDrawing, Scene};

thread_local! {
    static INPUT: RefCell<Vec<u8>> = const { RefCell::new(Vec::new()) };
    static OUTPUT: RefCell<Vec<f64>> = const { RefCell::new(Vec::new()) };
    static MESSAGE: RefCell<String> = const { RefCell::new(String::new()) };
    static TEXT: RefCell<String> = const { RefCell::new(String::new()) };
}

/// Makes the input buffer `len` bytes long (zeroed) and returns its address in linear memory.
#[allow(unsafe_code)]
#[no_mangle]
pub extern "C" fn splineskin_input(len: usize) -> usize {
    INPUT.with_borrow_mut(|b| {
        b.clear();
        b.resize(len, 0);
        b.as_mut_ptr() as usize
    })
}

/// The address of the output buffer (`f64`s, written by the last call that succeeded).
#[allow(unsafe_code)]
#[no_mangle]
pub extern "C" fn splineskin_output() -> usize {
    OUTPUT.with_borrow(|b| b.as_ptr() as usize)
}

/// The address of the last failure's message (UTF-8, [`splineskin_message_len`] bytes).
#[allow(unsafe_code)]
#[no_mangle]
pub extern "C" fn splineskin_message() -> usize {
    MESSAGE.with_borrow(|m| m.as_ptr() as usize)
}

/// The length in bytes of the last failure's message.
#[allow(unsafe_code)]
#[no_mangle]
pub extern "C" fn splineskin_message_len() -> usize {
    MESSAGE.with_borrow(|m| m.len())
}

/// Reads the scene in the input buffer's first `len` bytes (our JSON format, its drawing
/// inline as `svg_text`), builds its rig (its weights, fixed-ratio fit, or flexible G¹ when the
/// scene asks) and deforms it by its pose `pose` (an index into its poses). Writes the chain
/// points `x0, y0, x1, y1, …` (root user units) to the output buffer and returns their number,
/// or returns −1 with the message ([`splineskin_message`]).
#[allow(unsafe_code)]
#[no_mangle]
pub extern "C" fn splineskin_deform_scene(len: usize, pose: usize) -> i64 {
    call_on_input(len, |text| {
        let points = deform_scene(text, pose)?;
        OUTPUT.with_borrow_mut(|o| {
            o.clear();
            o.extend(points.iter().flat_map(|p| [p.x, p.y]));
        });
        Ok(points.len())
    })
}

/// As [`splineskin_deform_scene`], but writes the deformed SVG document (the scene's drawing
/// with the deformed path data, [`splineskin::drawing::svg_out::write_svg`]) as UTF-8 to the
/// text buffer ([`splineskin_text`]) and returns its length in bytes, or −1 with the message.
#[allow(unsafe_code)]
#[no_mangle]
pub extern "C" fn splineskin_deform_scene_svg(len: usize, pose: usize) -> i64 {
    call_on_input(len, |text| {
        let svg = deform_scene_svg(text, pose)?;
        let n = svg.len();
        TEXT.with_borrow_mut(|t| *t = svg);
        Ok(n)
    })
}

/// Runs `f` on the input buffer's first `len` bytes as UTF-8: its count on success, or −1 with
/// its message (or the decoding's) in the message buffer.
fn call_on_input(len: usize, f: impl FnOnce(&str) -> Result<usize, String>) -> i64 {
    let text = INPUT.with_borrow(|b| String::from_utf8(b[..len.min(b.len())].to_vec()));
    match text
        .map_err(|e| format!("the scene is not UTF-8: {e}"))
        .and_then(|text| f(&text))
    {
        Ok(n) => n as i64,
        Err(message) => {
            MESSAGE.with_borrow_mut(|m| *m = message);
            -1
        }
    }
}

/// The address of the text buffer (UTF-8, written by [`splineskin_deform_scene_svg`]).
#[allow(unsafe_code)]
#[no_mangle]
pub extern "C" fn splineskin_text() -> usize {
    TEXT.with_borrow(|t| t.as_ptr() as usize)
}

/// The deformed SVG document of scene `text` at its pose `pose` (callable natively too).
pub fn deform_scene_svg(text: &str, pose: usize) -> Result<String, String> {
    let (drawing, points) = deformed(text, pose)?;
    splineskin::drawing::svg_out::write_svg(&drawing, &points).map_err(|e| e.to_string())
}

/// The chain points of scene `text` (named `scene.json` in messages) deformed by its pose
/// `pose`, as [`splineskin_deform_scene`] computes them (callable natively too).
///
/// ```
/// use splineskin::examples::{DEMO_SCENE, DEMO_SVG};
/// // The bundled scene with its drawing inline.
/// let svg = serde_json::to_string(DEMO_SVG).unwrap();
/// let json = DEMO_SCENE.replacen("\"svg\": \"demo.svg\"", &format!("\"svg_text\": {svg}"), 1);
/// let points = splineskin_wasm::deform_scene(&json, 1).unwrap();
/// let scene = splineskin::examples::demo_scene();
/// assert_eq!(points.len(), scene.setup(Default::default()).unwrap().drawing.n_points());
/// assert!(splineskin_wasm::deform_scene("{", 0).unwrap_err().contains("scene.json"));
/// assert!(splineskin_wasm::deform_scene(&json, 9).unwrap_err().contains("pose 9"));
/// ```
pub fn deform_scene(text: &str, pose: usize) -> Result<Vec<Point>, String> {
    deformed(text, pose).map(|(_, points)| points)
}

/// The drawing of scene `text` (its junction kinds applied) and its chain points deformed by
/// pose `pose`.
fn deformed(text: &str, pose: usize) -> Result<(splineskin::drawing::Drawing, Vec<Point>), String> {
    let scene = Scene::from_json(text, "scene.json", None).map_err(|e| e.to_string())?;
    let transforms: Vec<Affine> = scene
        .pose(pose)
        .ok_or_else(|| {
            format!(
                "scene.json: pose {pose} does not exist (the scene has {}, numbered from 0)",
                scene.poses.len().max(1)
            )
        })?
        .transforms;
    // One thread: a page's WebAssembly has no threads unless it is built for them.
    let options = PoseOptions {
        compat: Compat::None,
        flexible: scene.flexible,
        parallel: false,
    };
    let posed = PosedDrawing::of_scene(&scene, options).map_err(|e| e.to_string())?;
    let mut points = vec![Point::ZERO; posed.setup().drawing.n_points()];
    posed
        .update(&transforms, &mut points)
        .map_err(|e| e.to_string())?;
    Ok((posed.setup().drawing.clone(), points))
}
