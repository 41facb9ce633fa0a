//! Reading an input file as text: the one place that opens what a user
//! names as input.
//!
//! Only regular files of at most [`MAX_INPUT_BYTES`] are read. A FIFO would
//! block until something writes into it, and a device like `/dev/zero`
//! never ends; both are refused at once, without reading, as is a folder.
//! The file is opened without blocking and checked through the open handle,
//! so a name swapped for a FIFO between a check and the open cannot hang
//! the program either.

use std::fs::File;
use std::io::Read;
use std::path::Path;

use serde::de::DeserializeOwned;

use super::{InputError, parse_ron};

/// The largest input file read: 1 GiB. A snapshot takes about 250 bytes a
/// body, so this holds about four million bodies, twice what the window
/// simulates; a larger file would need more memory to read in than to
/// simulate.
pub const MAX_INPUT_BYTES: u64 = 1 << 30;

/// The text of the file at `path`; the error names the file.
pub fn read_text(path: &Path) -> Result<String, InputError> {
    read_bounded(path, MAX_INPUT_BYTES).map_err(|e| cannot_read(path, &e))
}

/// The text of the file at `path`, or `None` if there is no such file
/// (for files that are optional, like the settings).
pub fn read_text_if_present(path: &Path) -> Result<Option<String>, InputError> {
    match read_bounded(path, MAX_INPUT_BYTES) {
        Ok(text) => Ok(Some(text)),
        Err(Refused::Io(e)) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(cannot_read(path, &e)),
    }
}

/// Why a file was not read.
#[derive(Debug, thiserror::Error)]
enum Refused {
    #[error("cannot read the file: {0}")]
    Io(#[from] std::io::Error),
    #[error("is {0}, not a regular file; inputs are read from regular files only")]
    NotRegular(&'static str),
    #[error("is larger than {} MiB, the most an input file may hold", .0 >> 20)]
    TooLarge(u64),
    /// A byte that is not UTF-8, at 1-based line and column (the column
    /// counts the characters before it on its line).
    #[error("byte 0x{byte:02x} is not UTF-8 text; input files are UTF-8 (save the file as UTF-8)")]
    NotUtf8 { byte: u8, line: usize, column: usize },
}

/// What kind of file system node `file_type` is, for a message ("a FIFO
/// (named pipe)", "a directory", "a file", ...).
pub fn node_kind(file_type: std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if file_type.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if file_type.is_char_device() {
            return "a character device";
        }
        if file_type.is_block_device() {
            return "a block device";
        }
        if file_type.is_socket() {
            return "a socket";
        }
    }
    if file_type.is_file() {
        "a file"
    } else if file_type.is_dir() {
        "a directory"
    } else if file_type.is_symlink() {
        "a symbolic link"
    } else {
        "not a regular file"
    }
}

/// Opens `path` for reading without waiting for a writer (a FIFO's open
/// would block otherwise).
fn open_without_blocking(path: &Path) -> std::io::Result<File> {
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NONBLOCK);
    }
    options.open(path)
}

/// The text of the regular file at `path`, if it holds at most `limit`
/// bytes.
fn read_bounded(path: &Path, limit: u64) -> Result<String, Refused> {
    let file = open_without_blocking(path)?;
    let metadata = file.metadata()?;
    if !metadata.is_file() {
        return Err(Refused::NotRegular(node_kind(metadata.file_type())));
    }
    if metadata.len() > limit {
        return Err(Refused::TooLarge(limit));
    }
    // A file that grows while it is read stops at the limit too.
    let mut bytes = Vec::new();
    file.take(limit + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(Refused::TooLarge(limit));
    }
    String::from_utf8(bytes).map_err(|e| not_utf8(e.as_bytes(), e.utf8_error().valid_up_to()))
}

/// Where in `bytes` the first byte that is not UTF-8 (at `at`) is.
fn not_utf8(bytes: &[u8], at: usize) -> Refused {
    // Everything before `at` is valid UTF-8.
    let before = std::str::from_utf8(&bytes[..at]).unwrap_or_default();
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    Refused::NotUtf8 {
        byte: bytes[at],
        line: before.matches('\n').count() + 1,
        column: before[line_start..].chars().count() + 1,
    }
}

/// Makes a FIFO at `path`, for tests of special files.
#[cfg(all(test, unix))]
pub(crate) fn make_fifo(path: &Path) {
    let made = std::process::Command::new("mkfifo").arg(path).status().unwrap();
    assert!(made.success(), "mkfifo {}", path.display());
}

fn cannot_read(path: &Path, e: &Refused) -> InputError {
    InputError {
        location: match *e {
            Refused::NotUtf8 { line, column, .. } => Some((line, column)),
            _ => None,
        },
        ..InputError::new(path.display().to_string(), e.to_string())
    }
}

/// The file at `path` parsed as RON (see [`parse_ron`]).
pub fn load_ron<T: DeserializeOwned>(path: &Path, extensions: ron::extensions::Extensions) -> Result<T, InputError> {
    parse_ron(&read_text(path)?, &path.display().to_string(), extensions)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_file_is_named_unless_it_may_be_missing() {
        let missing = Path::new("no/such/file.ron");
        let e = read_text(missing).unwrap_err();
        assert_eq!(e.origin, "no/such/file.ron");
        assert!(e.message.starts_with("cannot read the file"), "{e}");
        assert_eq!(read_text_if_present(missing), Ok(None));
        let dir = tempfile::tempdir().unwrap();
        let e = read_text_if_present(dir.path()).unwrap_err();
        assert!(e.message.contains("a directory"), "a folder is not a missing file: {e}");
    }

    #[cfg(unix)]
    #[test]
    fn special_files_are_refused_at_once_without_reading() {
        // Reading either would hang (a FIFO without a writer) or never end.
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("f.ron");
        make_fifo(&fifo);
        let e = read_text(&fifo).unwrap_err();
        assert!(e.message.contains("is a FIFO (named pipe), not a regular file"), "{e}");
        let e = read_text(Path::new("/dev/zero")).unwrap_err();
        assert!(e.message.contains("is a character device"), "{e}");
    }

    #[test]
    fn a_byte_that_is_not_utf8_is_located() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("latin1.ron");
        // `é` in Latin-1 on line 2, after `  name: "caf`.
        std::fs::write(&path, b"Scenario(\n  name: \"caf\xe9\",\n)").unwrap();
        let e = read_text(&path).unwrap_err();
        assert_eq!(e.location, Some((2, 13)), "{e}");
        assert!(
            e.to_string().ends_with(
                "latin1.ron:2:13: byte 0xe9 is not UTF-8 text; input files are UTF-8 (save the file as UTF-8)"
            ),
            "{e}"
        );
        // Characters before it on its line count once each.
        std::fs::write(&path, "é\u{1F600}".bytes().chain([0xff]).collect::<Vec<u8>>()).unwrap();
        assert_eq!(read_text(&path).unwrap_err().location, Some((1, 3)));
    }

    #[test]
    fn files_above_the_limit_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("big.ron");
        std::fs::write(&path, "x".repeat(1000)).unwrap();
        assert_eq!(read_bounded(&path, 1000).unwrap().len(), 1000);
        let e = read_bounded(&path, 999).unwrap_err();
        assert!(matches!(e, Refused::TooLarge(999)), "{e}");
    }
}
