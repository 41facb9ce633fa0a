//! Writing what the program produces — dumps, benchmark results, plots,
//! settings, screenshots — without ever leaving half a file, and checking
//! before any work that it can be written.

mod appended;
mod atomic;
mod check;
mod csv;
mod message;
mod png_image;

pub use appended::*;
pub use atomic::*;
pub use check::*;
pub use csv::{Cells, CsvRow, CsvTable, header, line, write_csv};
pub use message::*;
pub use png_image::*;
