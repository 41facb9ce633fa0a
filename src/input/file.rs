//! Reading an input file as text: the one place that opens what a user
//! names as input.

use std::path::Path;

use serde::de::DeserializeOwned;

use super::{InputError, parse_ron};

/// The text of the file at `path`; the error names the file.
pub fn read_text(path: &Path) -> Result<String, InputError> {
    std::fs::read_to_string(path).map_err(|e| cannot_read(path, &e))
}

/// The text of the file at `path`, or `None` if there is no such file
/// (for files that are optional, like the settings).
pub fn read_text_if_present(path: &Path) -> Result<Option<String>, InputError> {
    match std::fs::read_to_string(path) {
        Ok(text) => Ok(Some(text)),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(cannot_read(path, &e)),
    }
}

fn cannot_read(path: &Path, e: &std::io::Error) -> InputError {
    InputError::new(path.display().to_string(), format!("cannot read the file: {e}"))
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
        assert!(
            read_text_if_present(dir.path()).is_err(),
            "a folder is not a missing file"
        );
    }
}
