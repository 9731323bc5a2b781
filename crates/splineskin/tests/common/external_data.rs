//! Where the tests' external data lives, and what a test does when it is missing.
//!
//! Two kinds of data are never copied into the repository:
//!
//! * `../shared/data` next to the checkout: the paper authors' drawings and solver outputs,
//!   libigl and OpenSubdiv references ([`shared_data`]);
//! * `test-art/node_modules`: real SVG art made by others, npm packages that `.ci/run` installs
//!   with `npm ci` ([`test_art`]).
//!
//! A test whose data is missing **skips**: it prints `skipped: <test>: <why>` to stderr and, when
//! the environment variable [`SKIP_LOG_VAR`] names a file, appends the same line to it, so that
//! `.ci/run` can count and list the skipped tests after `cargo test` (whose output hides what
//! passing tests print). When the environment variable `CI` is set, missing data is an error
//! instead: the test panics, so CI cannot pass by skipping.
//!
//! This file is shared by the tests of `splineskin` and `splineskin-cli` (the latter include it
//! with `#[path]`).
#![allow(dead_code)]

use std::io::Write;
use std::path::{Path, PathBuf};

/// Environment variable naming a file to which every skip appends one line
/// (`<test binary>::<test>\t<why>`); `.ci/run` sets it.
pub const SKIP_LOG_VAR: &str = "SPLINESKIN_SKIP_LOG";

/// `../shared/data` relative to the repository root, if present; else the test skips (see the
/// module doc: with `CI` set, this panics).
pub fn shared_data() -> Option<PathBuf> {
    folder_or_skip(
        "../shared/data",
        "../shared/data not found next to the repository",
    )
}

/// `test-art/node_modules` of the repository, if `npm ci` has been run there; else the test
/// skips (see the module doc: with `CI` set, this panics).
pub fn test_art() -> Option<PathBuf> {
    folder_or_skip(
        "test-art/node_modules",
        "test-art/node_modules not found: run `npm ci` in test-art/ to install the art",
    )
}

/// The folder `relative` to the repository root if it exists; else [`skip`] because `why`.
fn folder_or_skip(relative: &str, why: &str) -> Option<PathBuf> {
    let folder = repository_root().join(relative);
    if folder.is_dir() {
        Some(folder)
    } else {
        skip(why);
        None
    }
}

/// The `*.json` files of `vectorskinning/authors-solver-outputs` in `data_root` (the shared
/// data), sorted by name: the paper authors' solver outputs, one case each.
pub fn authors_solver_outputs(data_root: &Path) -> Vec<PathBuf> {
    let dir = data_root.join("vectorskinning/authors-solver-outputs");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("authors-solver-outputs")
        .map(|e| e.expect("dir entry").path())
        .filter(|f| f.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    files
}

/// Each of [`authors_solver_outputs`] read as `T`.
pub fn read_authors_solver_outputs<T: serde::de::DeserializeOwned>(data_root: &Path) -> Vec<T> {
    authors_solver_outputs(data_root)
        .iter()
        .map(|f| {
            let text = std::fs::read_to_string(f).expect("read case");
            serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", f.display()))
        })
        .collect()
}

/// The repository's root folder (both crates live in `crates/<name>`).
pub fn repository_root() -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    root.canonicalize().unwrap_or(root)
}

/// Whether missing data is an error (the environment variable `CI` is set, to anything).
pub fn is_ci() -> bool {
    std::env::var_os("CI").is_some()
}

/// Records that the calling test skips because `why`: panics when [`is_ci`]; else prints the
/// reason to stderr and appends it to the file named by [`SKIP_LOG_VAR`], if set. The test is
/// named by its thread (libtest names each test's thread after the test) and its test binary.
pub fn skip(why: &str) {
    let thread = std::thread::current();
    let test = format!(
        "{}::{}",
        env!("CARGO_CRATE_NAME"),
        thread.name().unwrap_or("<unnamed test>")
    );
    if is_ci() {
        panic!("{test}: {why}; CI is set, so missing test data is an error, not a skip");
    }
    eprintln!("skipped: {test}: {why}");
    if let Some(log) = std::env::var_os(SKIP_LOG_VAR) {
        // One write per line on a file opened for appending: lines of tests running in
        // parallel do not interleave.
        let line = format!("{test}\t{why}\n");
        let written = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(&log)
            .and_then(|mut f| f.write_all(line.as_bytes()));
        if let Err(e) = written {
            panic!(
                "cannot append to the skip log {}: {e}",
                Path::new(&log).display()
            );
        }
    }
}
