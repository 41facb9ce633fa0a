//! Atomic file writes: a temporary file beside the target, synced to disk,
//! then renamed over it — the target is always either the old file or the
//! whole new one. A command with several outputs stages them all first and
//! renames them only once every one is written ([`Staged`]).
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

/// A file written in full into a temporary file beside its target and
/// synced, not yet in place: [`Staged::commit`] renames it over the target;
/// dropped uncommitted, it is removed and the target is left as it was.
/// Staging every output of a command first and committing them only when
/// all are written ([`commit_all`]) means a command whose outputs cannot
/// all be written writes none of them.
#[derive(Debug)]
#[must_use = "a staged file is removed unless it is committed"]
pub struct Staged {
    /// The temporary file, while it is there.
    tmp: Option<PathBuf>,
    /// The target.
    path: PathBuf,
}

/// Writes `path`'s new contents through `write` into a new temporary file
/// in the same folder, synced: the target is not touched yet. The
/// temporary file is removed on failure.
pub fn stage(path: &Path, write: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> Result<Staged, WriteError> {
    let failed = |source| WriteError {
        path: path.to_owned(),
        source,
    };
    let (tmp, file) = create_temporary(path).map_err(failed)?;
    // From here on, dropping `staged` removes the temporary file.
    let staged = Staged {
        tmp: Some(tmp),
        path: path.to_owned(),
    };
    let result = (|| {
        let mut out = BufWriter::new(file);
        write(&mut out)?;
        out.into_inner().map_err(io::IntoInnerError::into_error)?.sync_all()
    })();
    result.map(|()| staged).map_err(failed)
}

impl Staged {
    /// Puts the file in place: the target is now the whole new file (or,
    /// if the rename fails, still the old one). Only a regular file is
    /// replaced: something else at the target (a FIFO, a device, a
    /// symbolic link, a folder), even one put there after the command's
    /// checks, is left alone and the write fails.
    pub fn commit(mut self) -> Result<(), WriteError> {
        let Some(tmp) = self.tmp.take() else {
            return Ok(());
        };
        replaceable(&self.path)
            .and_then(|()| std::fs::rename(&tmp, &self.path))
            .map_err(|source| {
                let _ = std::fs::remove_file(&tmp);
                WriteError {
                    path: self.path.clone(),
                    source,
                }
            })
    }

    /// Puts the file in place only where nothing is at the target: an
    /// output that never overwrites (a film's pictures). Linked, not
    /// renamed, so that the check and the placing are one step.
    pub fn commit_new(mut self) -> Result<(), WriteError> {
        let Some(tmp) = self.tmp.take() else {
            return Ok(());
        };
        let placed = std::fs::hard_link(&tmp, &self.path);
        let _ = std::fs::remove_file(&tmp);
        placed.map_err(|source| WriteError {
            path: self.path.clone(),
            source: if source.kind() == io::ErrorKind::AlreadyExists {
                io::Error::new(
                    io::ErrorKind::AlreadyExists,
                    "exists already; this output never overwrites",
                )
            } else {
                source
            },
        })
    }
}

/// The file a user's own file at `path` is written to: the file a
/// symbolic link there names (a dotfiles setup keeps its link), else
/// `path`.
pub fn through_link(path: &Path) -> Result<PathBuf, WriteError> {
    match path.symlink_metadata() {
        Ok(m) if m.file_type().is_symlink() => {
            let named = std::fs::read_link(path).map_err(|source| WriteError {
                path: path.to_owned(),
                source,
            })?;
            // A relative link is relative to the link's folder.
            Ok(path.parent().unwrap_or(Path::new("")).join(named))
        }
        _ => Ok(path.to_owned()),
    }
}

/// `Ok` where nothing or a regular file is at `path`: what an output may
/// replace.
fn replaceable(path: &Path) -> io::Result<()> {
    match path.symlink_metadata() {
        Ok(found) if !found.is_file() => Err(io::Error::new(
            io::ErrorKind::AlreadyExists,
            format!(
                "{} is there; outputs replace regular files only",
                crate::input::node_kind(found.file_type())
            ),
        )),
        _ => Ok(()),
    }
}

impl Drop for Staged {
    fn drop(&mut self) {
        if let Some(tmp) = self.tmp.take() {
            let _ = std::fs::remove_file(tmp);
        }
    }
}

/// Puts every staged file in place, in order. Only the renames are left
/// by then, which fail only if the file system changes under the command
/// (the folders were checked writable before any work); should one fail,
/// the files after it are removed and their targets left as they were.
pub fn commit_all(staged: Vec<Staged>) -> Result<(), WriteError> {
    staged.into_iter().try_for_each(Staged::commit)
}

/// Writes to `path` through `write`, into a new temporary file in the same
/// folder that is synced and then renamed, so that `path` is either the old
/// file or the whole new one. The temporary file is removed on failure.
pub fn write_atomically(path: &Path, write: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> Result<(), WriteError> {
    stage(path, write)?.commit()
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
    fn staged_files_are_put_in_place_together_or_not_at_all() {
        let dir = tempfile::tempdir().unwrap();
        let [one, two, three] = ["one.csv", "two.csv", "three.ron"].map(|name| dir.path().join(name));
        for path in [&one, &two, &three] {
            std::fs::write(path, "precious").unwrap();
        }
        // The third fails: the first two, already staged, are dropped.
        let staged: Result<Vec<Staged>, WriteError> = [&one, &two, &three]
            .into_iter()
            .enumerate()
            .map(|(i, path)| {
                stage(path, |w| {
                    if i == 2 {
                        Err(io::Error::other("boom"))
                    } else {
                        w.write_all(b"new")
                    }
                })
            })
            .collect();
        assert!(staged.unwrap_err().to_string().ends_with("three.ron: boom"));
        for path in [&one, &two, &three] {
            assert_eq!(std::fs::read_to_string(path).unwrap(), "precious");
        }
        assert_eq!(
            std::fs::read_dir(dir.path()).unwrap().count(),
            3,
            "temporary files left behind"
        );
        // All three written: nothing is in place before the commit.
        let staged: Vec<Staged> = [&one, &two, &three]
            .into_iter()
            .map(|path| stage(path, |w| w.write_all(b"new")).unwrap())
            .collect();
        assert_eq!(std::fs::read_to_string(&one).unwrap(), "precious");
        commit_all(staged).unwrap();
        for path in [&one, &two, &three] {
            assert_eq!(std::fs::read_to_string(path).unwrap(), "new");
        }
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 3);
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
