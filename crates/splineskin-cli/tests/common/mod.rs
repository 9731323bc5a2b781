//! Shared helpers of the command-line tests.

pub mod test_dir;
