//! Atomic file writes: a temporary file beside the target, synced to disk,
//! then renamed over it — the target is always either the old file or the
//! whole new one.
//!
//! Written here rather than with `tempfile::NamedTempFile::persist`: that
//! creates its files with mode 0600, so every dump and result would end up
//! readable by its owner only; `OpenOptions` as used here (like
//! `File::create`) honors the user's umask.

use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// A file could not be written.
#[derive(Debug, thiserror::Error)]
#[error("{}: {source}", path.display())]
pub struct WriteError {
    /// The file that was to be written.
    pub path: PathBuf,
    /// What the operating system said.
    pub source: io::Error,
}

/// Temporary files made by this process so far (part of their names).
static TEMPORARIES: AtomicU64 = AtomicU64::new(0);

/// Longest part of the target's name a temporary file's name keeps, so
/// that a long (but valid) target name still leaves room for the rest.
const NAME_KEPT: usize = 100;

/// Creates a new temporary file beside `path` (in its folder, named after
/// it), never over anything already there: its path and the open file.
pub fn create_temporary(path: &Path) -> io::Result<(PathBuf, std::fs::File)> {
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "not a file name"))?
        .to_string_lossy();
    let kept: String = name.chars().take(NAME_KEPT).collect();
    // `create_new`: never write through something already there; a name
    // left behind by a crashed process with the same id is skipped.
    loop {
        let tmp = dir.join(format!(
            ".{kept}.{}.{}.tmp",
            std::process::id(),
            TEMPORARIES.fetch_add(1, Ordering::Relaxed)
        ));
        match std::fs::OpenOptions::new().write(true).create_new(true).open(&tmp) {
            Ok(file) => return Ok((tmp, file)),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(e),
        }
    }
}

/// Writes to `path` through `write`, into a new temporary file in the same
/// folder that is synced and then renamed, so that `path` is either the old
/// file or the whole new one. The temporary file is removed on failure.
pub fn write_atomically(path: &Path, write: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> Result<(), WriteError> {
    let failed = |source| WriteError {
        path: path.to_owned(),
        source,
    };
    let (tmp, file) = create_temporary(path).map_err(failed)?;
    let result = (|| {
        let mut out = BufWriter::new(file);
        write(&mut out)?;
        out.into_inner().map_err(io::IntoInnerError::into_error)?.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.map_err(failed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn replaces_the_whole_file_or_leaves_it() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.csv");
        std::fs::write(&path, "old").unwrap();
        write_atomically(&path, |w| w.write_all(b"new")).unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
        let failed = write_atomically(&path, |_| Err(io::Error::other("boom"))).unwrap_err();
        assert!(failed.to_string().ends_with("out.csv: boom"), "{failed}");
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
        assert_eq!(
            std::fs::read_dir(dir.path()).unwrap().count(),
            1,
            "temporary file left behind"
        );
    }

    #[test]
    fn a_temporary_name_left_behind_is_skipped_not_written_through() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.csv");
        let next = TEMPORARIES.load(Ordering::Relaxed);
        // Stale names for this process's next few temporaries (other tests
        // may take some of the numbers meanwhile).
        let stale: Vec<PathBuf> = (next..next + 8)
            .map(|k| dir.path().join(format!(".out.csv.{}.{k}.tmp", std::process::id())))
            .collect();
        for file in &stale {
            std::fs::write(file, "stale").unwrap();
        }
        write_atomically(&path, |w| w.write_all(b"new")).unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
        assert!(stale.iter().all(|f| std::fs::read_to_string(f).unwrap() == "stale"));
    }
}
