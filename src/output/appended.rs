//! Files that grow row by row as results come in: created new (never over
//! an existing file), each row flushed as it is added, so an interrupted
//! run keeps every row written so far.

use std::fs::File;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

use super::WriteError;

/// A new file that rows are appended to.
#[derive(Debug)]
pub struct AppendedFile {
    path: PathBuf,
    file: File,
}

impl AppendedFile {
    /// Creates `path`, which must not exist, and writes `header` as its
    /// first line.
    pub fn create(path: &Path, header: &str) -> Result<Self, WriteError> {
        let file = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(path)
            .map_err(|source| WriteError {
                path: path.to_owned(),
                source,
            })?;
        let mut appended = Self {
            path: path.to_owned(),
            file,
        };
        appended.append(header)?;
        Ok(appended)
    }

    /// Adds `row` and a line end, and hands them to the operating system.
    pub fn append(&mut self, row: &str) -> Result<(), WriteError> {
        let write = |file: &mut File| -> io::Result<()> {
            file.write_all(format!("{row}\n").as_bytes())?;
            file.flush()
        };
        write(&mut self.file).map_err(|source| WriteError {
            path: self.path.clone(),
            source,
        })
    }

    /// The file's path.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_are_in_the_file_as_soon_as_appended_and_existing_files_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("rows.csv");
        let mut file = AppendedFile::create(&path, "a,b").unwrap();
        file.append("1,2").unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "a,b\n1,2\n");
        let again = AppendedFile::create(&path, "x").unwrap_err();
        assert_eq!(again.source.kind(), io::ErrorKind::AlreadyExists);
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "a,b\n1,2\n", "untouched");
    }
}
