//! A folder of numbered frame files (`frame-0000.svg`, …), written whole or not at all: the
//! frames go into a temporary folder beside it, which is then renamed into place. An existing
//! folder is replaced only if it holds nothing but frame files of the kinds being written (an
//! earlier run's output); otherwise it is an error and nothing is touched.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};

/// The name of frame `f` with extension `ext`: `frame-0000.svg`, … (at least four digits).
pub fn frame_name(f: usize, ext: &str) -> String {
    format!("frame-{f:04}.{ext}")
}

/// Whether `name` is a frame file with one of `extensions` ([`frame_name`]).
fn is_frame_file(name: &str, extensions: &[&str]) -> bool {
    let Some(rest) = name.strip_prefix("frame-") else {
        return false;
    };
    let Some((digits, ext)) = rest.split_once('.') else {
        return false;
    };
    !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()) && extensions.contains(&ext)
}

/// Writes `bytes` to a new file `path` and syncs it.
pub fn write_synced(path: &Path, bytes: &[u8]) -> Result<()> {
    use std::io::Write;
    let mut file = std::fs::File::create(path)
        .with_context(|| format!("{}: cannot create", path.display()))?;
    file.write_all(bytes)
        .and_then(|()| file.sync_all())
        .with_context(|| format!("{}: cannot write", path.display()))
}

/// Makes `dir` the folder that `fill` writes (given the temporary folder to write into), frames
/// of `extensions` only (module documentation). On any error the temporary folder is removed
/// and `dir` is as it was.
pub fn replace_frames_folder(
    dir: &Path,
    extensions: &[&str],
    fill: impl FnOnce(&Path) -> Result<()>,
) -> Result<()> {
    let name = dir
        .file_name()
        .with_context(|| format!("{}: not a folder name", dir.display()))?
        .to_string_lossy()
        .into_owned();
    let parent = match dir.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    if dir.exists() {
        check_only_frames(dir, extensions)?;
    }
    let tmp = parent.join(format!(".{name}.tmp-{}", std::process::id()));
    let old = parent.join(format!(".{name}.old-{}", std::process::id()));
    let result = (|| -> Result<()> {
        std::fs::create_dir(&tmp).with_context(|| format!("{}: cannot create", tmp.display()))?;
        fill(&tmp)?;
        if dir.exists() {
            std::fs::rename(dir, &old).with_context(|| {
                format!("{}: cannot move the earlier frames aside", dir.display())
            })?;
        }
        std::fs::rename(&tmp, dir).with_context(|| format!("{}: cannot write", dir.display()))?;
        Ok(())
    })();
    if result.is_err() {
        let _ = std::fs::remove_dir_all(&tmp);
        if old.exists() && !dir.exists() {
            let _ = std::fs::rename(&old, dir);
        }
    }
    if old.exists() {
        let _ = std::fs::remove_dir_all(&old);
    }
    result
}

/// Refuses `dir` unless it is a folder of frame files with `extensions` only.
fn check_only_frames(dir: &Path, extensions: &[&str]) -> Result<()> {
    let kinds = extensions
        .iter()
        .map(|e| format!("frame-*.{e}"))
        .collect::<Vec<_>>()
        .join("/");
    if !dir.is_dir() {
        bail!(
            "{}: exists and is not a folder (expected a new folder, or one holding only {kinds} files)",
            dir.display()
        );
    }
    for entry in
        std::fs::read_dir(dir).with_context(|| format!("{}: cannot read", dir.display()))?
    {
        let entry = entry.with_context(|| format!("{}: cannot read", dir.display()))?;
        let file = entry.file_name().to_string_lossy().into_owned();
        let is_file = entry
            .file_type()
            .with_context(|| format!("{}: cannot read {file}", dir.display()))?
            .is_file();
        if !(is_frame_file(&file, extensions) && is_file) {
            bail!(
                "{}: exists and holds {file}, which is not a frame; choose another folder \
                 (a folder holding only {kinds} files is replaced)",
                dir.display()
            );
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_files_are_recognised_by_name_and_kind() {
        assert!(is_frame_file("frame-0012.svg", &["svg", "png"]));
        assert!(!is_frame_file("frame-0012.obj", &["svg", "png"]));
        assert!(!is_frame_file("frame-.svg", &["svg"]));
        assert!(!is_frame_file("notes.txt", &["svg"]));
        assert_eq!(frame_name(7, "obj"), "frame-0007.obj");
    }
}
