//! Scene files: ours (`splineskin_scene`) and the paper authors' `*-deformation.json`
//! (`Scene::from_json` tells them apart), then the scene's setup on what parses (drawing,
//! handles, weights are not solved: only reading is fuzzed here).
#![no_main]

use libfuzzer_sys::fuzz_target;
use splineskin::scene::Scene;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    // No base folder: a scene naming an SVG file is refused, as for text from the network.
    let _ = Scene::from_json(text, "fuzz.json", None);
});
