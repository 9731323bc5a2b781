//! Shared helpers of the command-line tests.
#![allow(dead_code)]

pub mod cli;
// Where the external test data lives, how a test skips without it, and the per-test output
// folders: one file each for both crates' tests.
#[path = "../../../splineskin/tests/common/external_data.rs"]
pub mod external_data;
#[path = "../../../splineskin/tests/common/measure.rs"]
pub mod measure;
#[path = "../../../splineskin/tests/common/test_dir.rs"]
pub mod test_dir;
