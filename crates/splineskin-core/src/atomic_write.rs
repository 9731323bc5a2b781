//! Writing files so that they are never seen half-written: each file's bytes go to a temporary
//! file in the same folder (`.NAME.tmp-PID`), are synced, and only then is the temporary
//! renamed over the destination (a rename within one file system replaces it at once). On
//! failure the temporaries are removed and the destinations not yet replaced are as they were.

use std::io::Write;
use std::path::{Path, PathBuf};

/// Writes `bytes` to `path` through a synced temporary file beside it and a rename.
/// A `path` without a file name is an [`std::io::ErrorKind::InvalidInput`] error.
///
/// ```
/// let dir = tempfile::tempdir().unwrap();
/// let path = dir.path().join("out.txt");
/// splineskin_core::atomic_write::write_atomically(&path, b"hello").unwrap();
/// assert_eq!(std::fs::read(&path).unwrap(), b"hello");
/// assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1, "no temporary left");
/// ```
pub fn write_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    write_all_atomically(&[(path, bytes)]).map_err(|e| e.source)
}

/// Why [`write_all_atomically`] failed: the file it could not write (an index into the list),
/// how many files before it were already in place, and the error.
#[derive(Debug)]
pub struct WriteAllError {
    /// The file that could not be written: an index into the list given.
    pub file: usize,
    /// How many files (the first ones of the list) were already renamed into place: 0 unless
    /// a rename failed after others succeeded (the disk vanishing between two renames).
    pub replaced: usize,
    /// The error.
    pub source: std::io::Error,
}

impl std::fmt::Display for WriteAllError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "file {} of the list: {}", self.file, self.source)
    }
}

impl std::error::Error for WriteAllError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        Some(&self.source)
    }
}

/// Writes several files as one: every file's bytes go to a synced temporary file beside it
/// first, and only when all of them are written are they renamed into place. A failure while
/// writing leaves every destination as it was (its temporaries removed); a rename failing
/// after others succeeded is reported with [`WriteAllError::replaced`].
///
/// ```
/// use splineskin_core::atomic_write::write_all_atomically;
/// let dir = tempfile::tempdir().unwrap();
/// let (a, b) = (dir.path().join("a.txt"), dir.path().join("b.txt"));
/// write_all_atomically(&[(&a, b"one"), (&b, b"two")]).unwrap();
/// assert_eq!(std::fs::read(&b).unwrap(), b"two");
/// // A file that cannot be written (its folder is missing): nothing is replaced.
/// let missing = dir.path().join("no-such-folder").join("c.txt");
/// let e = write_all_atomically(&[(&a, b"new"), (&missing, b"three")]).unwrap_err();
/// assert_eq!((e.file, e.replaced), (1, 0));
/// assert_eq!(std::fs::read(&a).unwrap(), b"one");
/// assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2, "no temporary left");
/// ```
pub fn write_all_atomically(files: &[(&Path, &[u8])]) -> Result<(), WriteAllError> {
    let mut temporaries = Vec::with_capacity(files.len());
    let remove_all = |temporaries: &[PathBuf]| {
        for t in temporaries {
            let _ = std::fs::remove_file(t);
        }
    };
    for (file, (path, bytes)) in files.iter().enumerate() {
        let written = temporary_beside(path).and_then(|tmp| {
            temporaries.push(tmp.clone());
            let mut f = std::fs::File::create(&tmp)?;
            f.write_all(bytes)?;
            f.sync_all()
        });
        if let Err(source) = written {
            remove_all(&temporaries);
            return Err(WriteAllError {
                file,
                replaced: 0,
                source,
            });
        }
    }
    for (file, ((path, _), tmp)) in files.iter().zip(&temporaries).enumerate() {
        if let Err(source) = std::fs::rename(tmp, path) {
            remove_all(&temporaries[file..]);
            return Err(WriteAllError {
                file,
                replaced: file,
                source,
            });
        }
    }
    Ok(())
}

/// A temporary file name in `path`'s folder: `.NAME.tmp-PID`; a `path` without a file name is
/// an [`std::io::ErrorKind::InvalidInput`] error.
fn temporary_beside(path: &Path) -> std::io::Result<PathBuf> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = path
        .file_name()
        .ok_or_else(|| std::io::Error::new(std::io::ErrorKind::InvalidInput, "not a file name"))?;
    Ok(dir.join(format!(
        ".{}.tmp-{}",
        name.to_string_lossy(),
        std::process::id()
    )))
}
