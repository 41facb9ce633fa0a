//! Every CSV Kessler writes goes through one row type per file: a
//! [`CsvRow`] names its columns and writes its cells, both from one list
//! ([`csv_row!`](crate::csv_row!)), so a header and its rows cannot disagree. Cells are
//! written with `Display` (floats in Rust's shortest round-trip form),
//! which is why this is a small writer of our own rather than the `csv`
//! crate: its floats are written otherwise, and the dump's bytes are a
//! contract. [`CsvTable`] reads a file back through the same type.

use std::fmt::Display;
use std::io::{self, Write};

/// The row type of one CSV file.
pub trait CsvRow {
    /// The header's column names, in order.
    fn columns() -> Vec<String>;

    /// Writes this row's cells, one per column, separated by commas, without
    /// the line end.
    fn write_cells(&self, out: &mut Cells<'_>) -> io::Result<()>;
}

/// Where a row writes its cells: it puts the commas between them and
/// counts them.
pub struct Cells<'a> {
    out: &'a mut dyn Write,
    written: usize,
}

impl Cells<'_> {
    /// Writes one cell.
    pub fn cell(&mut self, value: impl Display) -> io::Result<()> {
        if self.written > 0 {
            self.out.write_all(b",")?;
        }
        self.written += 1;
        write!(self.out, "{value}")
    }
}

/// The header line of `R`'s file (no line end).
pub fn header<R: CsvRow>() -> String {
    R::columns().join(",")
}

/// Writes `row` and a line end; an error if it wrote another number of
/// cells than `R` has columns (a bug, never written silently).
pub fn write_row<R: CsvRow>(out: &mut dyn Write, row: &R, columns: usize) -> io::Result<()> {
    let mut cells = Cells { out, written: 0 };
    row.write_cells(&mut cells)?;
    let written = cells.written;
    if written != columns {
        return Err(io::Error::other(format!(
            "a CSV row has {written} cells for {columns} columns"
        )));
    }
    out.write_all(b"\n")
}

/// One row as a line (no line end), for files that grow row by row.
pub fn line<R: CsvRow>(row: &R) -> io::Result<String> {
    let mut text = Vec::new();
    write_row(&mut text, row, R::columns().len())?;
    text.pop();
    String::from_utf8(text).map_err(io::Error::other)
}

/// Writes the header and every row.
pub fn write_csv<'a, R: CsvRow + 'a>(mut out: impl Write, rows: impl IntoIterator<Item = &'a R>) -> io::Result<()> {
    let columns = R::columns().len();
    writeln!(out, "{}", header::<R>())?;
    for row in rows {
        write_row(&mut out, row, columns)?;
    }
    out.flush()
}

/// Declares a row type's columns and cells in one list: `csv_row!(Type,
/// |row| { column: cell, ... })`, each cell an expression that `Display`s.
#[macro_export]
macro_rules! csv_row {
    ($row:ty, |$r:ident| { $($column:ident: $cell:expr),* $(,)? }) => {
        impl $crate::output::CsvRow for $row {
            fn columns() -> Vec<String> {
                vec![$(stringify!($column).to_owned()),*]
            }

            fn write_cells(&self, out: &mut $crate::output::Cells<'_>) -> std::io::Result<()> {
                let $r = self;
                $(out.cell($cell)?;)*
                Ok(())
            }
        }
    };
}

/// A CSV file read back by its row type: the header checked against the
/// type's columns, every row with a cell per column.
#[derive(Clone, Debug, PartialEq)]
pub struct CsvTable {
    columns: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl CsvTable {
    /// Reads `text` as a file of `R` rows: its header, then rows alone.
    pub fn parse<R: CsvRow>(text: &str) -> Result<Self, String> {
        let mut lines = text.lines();
        let columns = R::columns();
        let found = lines.next().ok_or("the file is empty")?;
        if found != header::<R>() {
            return Err(format!("header `{found}`, expected `{}`", header::<R>()));
        }
        let rows = lines
            .enumerate()
            .map(|(i, line)| {
                let cells: Vec<String> = line.split(',').map(str::to_owned).collect();
                if cells.len() == columns.len() {
                    Ok(cells)
                } else {
                    Err(format!(
                        "row {}: {} cells for {} columns",
                        i + 1,
                        cells.len(),
                        columns.len()
                    ))
                }
            })
            .collect::<Result<_, _>>()?;
        Ok(Self { columns, rows })
    }

    /// The rows, each a cell per column.
    pub fn rows(&self) -> &[Vec<String>] {
        &self.rows
    }

    /// The cells of `column`, one per row; `None` if there is no such
    /// column.
    pub fn column(&self, column: &str) -> Option<Vec<&str>> {
        let i = self.columns.iter().position(|c| c == column)?;
        Some(self.rows.iter().map(|r| r[i].as_str()).collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Point(u32, f32);
    crate::csv_row!(Point, |p| { id: p.0, x: p.1 });

    struct Broken;
    impl CsvRow for Broken {
        fn columns() -> Vec<String> {
            vec!["a".into(), "b".into()]
        }
        fn write_cells(&self, out: &mut Cells<'_>) -> io::Result<()> {
            out.cell(1)
        }
    }

    #[test]
    fn header_and_rows_come_from_one_list_and_read_back() {
        let mut text = Vec::new();
        write_csv(&mut text, &[Point(3, 0.1), Point(4, -2.0)]).unwrap();
        let text = String::from_utf8(text).unwrap();
        assert_eq!(text, "id,x\n3,0.1\n4,-2\n");
        let table = CsvTable::parse::<Point>(&text).unwrap();
        assert_eq!(table.column("x").unwrap(), ["0.1", "-2"]);
        assert!(
            CsvTable::parse::<Point>("id,y\n1,2\n")
                .unwrap_err()
                .contains("expected `id,x`")
        );
        assert!(
            CsvTable::parse::<Point>("id,x\n1\n")
                .unwrap_err()
                .contains("1 cells for 2")
        );
    }

    #[test]
    fn a_row_short_of_its_columns_is_an_error() {
        assert!(line(&Broken).is_err());
        assert_eq!(line(&Point(1, 2.5)).unwrap(), "1,2.5");
    }
}
