//! Deformation-operator files (`.defop`, binary): an operator that is read is written back
//! and must give the same bytes.
#![no_main]

use libfuzzer_sys::fuzz_target;
use splineskin::defop::OperatorFile;

fuzz_target!(|data: &[u8]| {
    let Ok(file) = OperatorFile::from_bytes(data, "fuzz.defop") else {
        return;
    };
    let again = OperatorFile::from_bytes(&file.to_bytes(), "written.defop")
        .expect("our own operator file reads back");
    assert_eq!(again.to_bytes(), file.to_bytes());
});
