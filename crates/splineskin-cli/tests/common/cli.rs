//! Running the `splineskin` binary under test and reading what it left behind.

use std::ffi::OsStr;
use std::path::Path;
use std::process::{Command, Output};

/// Runs `splineskin args…` in `dir` (the test process's own folder when `None`).
pub fn run_in<S: AsRef<OsStr>>(dir: Option<&Path>, args: &[S]) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_splineskin"));
    command.args(args);
    if let Some(dir) = dir {
        command.current_dir(dir);
    }
    command.output().expect("run splineskin")
}

/// Runs `splineskin args…` in the test process's own folder (paths given absolute).
pub fn splineskin(args: &[&str]) -> Output {
    run_in(None, args)
}

/// Runs `splineskin args…` in `dir`.
pub fn run(dir: &Path, args: &[&str]) -> Output {
    run_in(Some(dir), args)
}

/// The run's stderr, lossily decoded.
pub fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Asserts that the run succeeded (its stderr is the message otherwise) and returns its stdout.
pub fn ok(out: &Output) -> String {
    assert!(out.status.success(), "failed: {}", stderr(out));
    String::from_utf8(out.stdout.clone()).unwrap()
}

/// Asserts that the run failed with exit status 1 and did not panic; returns its stderr.
pub fn failed(out: &Output) -> String {
    assert_eq!(out.status.code(), Some(1), "expected exit status 1");
    let stderr = stderr(out);
    assert!(!stderr.contains("panicked"), "{stderr}");
    stderr
}

/// Runs `splineskin defop eval OP --handles HANDLES -o OUT`.
pub fn defop_eval(op: &Path, handles: &Path, out: &Path) -> Output {
    splineskin(&[
        "defop",
        "eval",
        s(op),
        "--handles",
        s(handles),
        "-o",
        s(out),
    ])
}

/// The entries of `dir` whose names mark an interrupted atomic write (`.NAME.tmp-*`).
pub fn temporaries(dir: &Path) -> Vec<std::fs::DirEntry> {
    std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().contains(".tmp-"))
        .collect()
}

/// `path` as UTF-8 (the tests' folders are).
pub fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// Runs `splineskin` in `dir` with the arguments of `line` split at whitespace (for argument
/// lists without spaces: `"subdiv compare scene.json -o cmp.png"`).
pub fn run_line(dir: &Path, line: &str) -> Output {
    run(dir, &line.split_whitespace().collect::<Vec<_>>())
}

/// The JSON object on each line of `stdout` (`--json` output), read as `T`.
pub fn json_lines<T: serde::de::DeserializeOwned>(stdout: &str) -> Vec<T> {
    stdout
        .lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{e}: {l}")))
        .collect()
}

/// [`run_line`] that must succeed ([`ok`]): its stdout.
pub fn run_ok(dir: &Path, line: &str) -> String {
    ok(&run_line(dir, line))
}

/// What is wrong with a run `out` in `dir` that had to fail cleanly, each problem labelled by
/// `name`, the arguments and stderr: it succeeded (then nothing else is checked); it panicked
/// or its stderr does not start with `error`; its stderr lacks one of `expect`; `dir` holds
/// `output` or a temporary of its atomic write (`.OUTPUT.tmp-*`).
pub fn failure_problems(
    name: &str,
    args: &[&str],
    out: &Output,
    dir: &Path,
    expect: &[&str],
    output: &str,
) -> Vec<String> {
    let stderr = stderr(out);
    let label = format!("{name} ({})\nstderr: {stderr}", args.join(" "));
    if out.status.success() {
        return vec![format!("{label}: succeeded")];
    }
    let mut problems = Vec::new();
    if stderr.contains("panicked") {
        problems.push(format!("{label}: panicked"));
    }
    if !stderr.starts_with("error") {
        problems.push(format!("{label}: no error line"));
    }
    for want in expect {
        if !stderr.contains(want) {
            problems.push(format!("{label}: stderr lacks {want:?}"));
        }
    }
    for entry in std::fs::read_dir(dir).unwrap().flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        if name == output || name.starts_with(&format!(".{output}.tmp-")) {
            problems.push(format!("{label}: left {name} behind"));
        }
    }
    problems
}

/// Asserts that none of `n_cases` cases reported a problem, listing them all otherwise.
pub fn assert_no_problems(problems: &[String], n_cases: usize) {
    assert!(
        problems.is_empty(),
        "{} problems in {n_cases} cases:\n\n{}",
        problems.len(),
        problems.join("\n\n")
    );
}

/// The whitespace-separated words of `line`: an argument list written as one string.
pub fn words(line: &str) -> Vec<&str> {
    line.split_whitespace().collect()
}

/// Runs `args` in `dir`, asserts that the run succeeded, and returns its stderr (warnings).
pub fn ok_stderr(dir: &Path, args: &[&str]) -> String {
    let out = run(dir, args);
    let stderr = stderr(&out);
    assert!(out.status.success(), "{args:?} failed: {stderr}");
    stderr
}
