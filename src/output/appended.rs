//! CSV files that grow row by row as results come in: created new (never
//! over an existing file) with their row type's header, each row flushed as
//! it is added, so an interrupted run keeps every row written so far.

use std::fs::File;
use std::io::{self, Write};
use std::marker::PhantomData;
use std::path::{Path, PathBuf};

use super::{CsvRow, WriteError, header, line};

/// A new CSV file that rows of type `R` are appended to.
#[derive(Debug)]
pub struct AppendedFile<R> {
    path: PathBuf,
    file: File,
    rows: PhantomData<R>,
}

impl<R: CsvRow> AppendedFile<R> {
    /// Creates `path`, which must not exist, and writes `R`'s header as its
    /// first line.
    pub fn create(path: &Path) -> Result<Self, WriteError> {
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
            rows: PhantomData,
        };
        appended.append_line(&header::<R>())?;
        Ok(appended)
    }

    /// Adds `row`, and hands it to the operating system.
    pub fn append(&mut self, row: &R) -> Result<(), WriteError> {
        let text = line(row).map_err(|source| WriteError {
            path: self.path.clone(),
            source,
        })?;
        self.append_line(&text)
    }

    /// Adds `text` and a line end.
    fn append_line(&mut self, text: &str) -> Result<(), WriteError> {
        let write = |file: &mut File| -> io::Result<()> {
            file.write_all(format!("{text}\n").as_bytes())?;
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

    #[derive(Debug)]
    struct Pair(u8, u8);
    crate::csv_row!(Pair, |p| { a: p.0, b: p.1 });

    #[test]
    fn rows_are_in_the_file_as_soon_as_appended_and_existing_files_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("rows.csv");
        let mut file = AppendedFile::<Pair>::create(&path).unwrap();
        file.append(&Pair(1, 2)).unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "a,b\n1,2\n");
        let again = AppendedFile::<Pair>::create(&path).unwrap_err();
        assert_eq!(again.source.kind(), io::ErrorKind::AlreadyExists);
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "a,b\n1,2\n", "untouched");
    }
}
