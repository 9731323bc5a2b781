//! Shared helpers of the command-line tests.

// Where the external test data lives, and how a test skips without it: one file for both
// crates' tests.
#[path = "../../../splineskin/tests/common/external_data.rs"]
pub mod external_data;
pub mod test_dir;
