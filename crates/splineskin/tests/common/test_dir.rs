//! A temporary folder for one test, removed when the test passes and kept when it fails.
//!
//! The command-line crate's tests read this same file (a `#[path]` module in their
//! `tests/common/mod.rs`).

use std::ops::Deref;
use std::path::Path;

use tempfile::TempDir;

/// A fresh folder under the system's temporary folder, named `prefix` and a random suffix.
///
/// Dropped, it is removed with everything in it, unless the thread is panicking (a failed
/// assertion): then it is kept for inspection and its path printed to stderr. It derefs to
/// its [`Path`], so `dir.join("x")` works and `&dir` passes as a `&Path`.
pub struct TestDir(TempDir);

impl TestDir {
    /// A new, empty folder `prefix…`, the prefix naming the test (`"splineskin-compare-cli-"`).
    pub fn new(prefix: &str) -> Self {
        let dir = tempfile::Builder::new()
            .prefix(prefix)
            .tempdir()
            .unwrap_or_else(|e| panic!("cannot create a temporary folder {prefix}…: {e}"));
        Self(dir)
    }
}

impl Deref for TestDir {
    type Target = Path;

    fn deref(&self) -> &Path {
        self.0.path()
    }
}

impl AsRef<Path> for TestDir {
    fn as_ref(&self) -> &Path {
        self.0.path()
    }
}

impl Drop for TestDir {
    fn drop(&mut self) {
        if std::thread::panicking() {
            // `TempDir`'s own drop runs after this one and now leaves the folder in place.
            self.0.disable_cleanup(true);
            eprintln!("test failed: kept {}", self.0.path().display());
        }
    }
}
