//! Catmull–Clark cages as Wavefront OBJ with OpenSubdiv's `t crease`/`t corner` tags; a cage
//! that is accepted is written back and must read back the same.
#![no_main]

use libfuzzer_sys::fuzz_target;
use splineskin::subdiv::obj::{parse_obj, to_obj_string};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(cage) = parse_obj(text, "fuzz.obj") else {
        return;
    };
    let written = to_obj_string(&cage);
    let again = parse_obj(&written, "written.obj").expect("our own OBJ reads back");
    assert_eq!(again, cage, "{written}");
});
