//! Shared helpers of the integration tests: where the external data lives, and readers of it.
#![allow(dead_code)]

use std::path::PathBuf;

/// `../shared/data` relative to the repository root, if present. Tests that need it print
/// why they are skipped when it is missing (CI always has it: `.ci/run` fails without it).
pub fn data_root() -> Option<PathBuf> {
    let root = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data"));
    if root.is_dir() {
        Some(root)
    } else {
        eprintln!("skipped: ../shared/data not found next to the repository");
        None
    }
}
pub mod authors_outputs;
pub mod reference_igl;
pub mod scene_compare;
