//! Writing what the program produces — dumps, benchmark results, plots,
//! settings, screenshots — without ever leaving half a file, and checking
//! before any work that it can be written.

mod appended;
mod atomic;
mod check;
mod csv;
mod figure;
mod message;
mod png_image;

pub use appended::AppendedFile;
pub use atomic::{Staged, WriteError, commit_all, create_temporary, stage, through_link, write_atomically};
pub use check::{
    Existing, Output, OutputError, OutputProblem, check_distinct, check_extension, check_new, check_not_inputs,
    check_outputs, check_replaceable, check_series_folder, probe, same_file,
};
pub use csv::{Cells, CsvRow, CsvTable, header, line, write_csv};
pub use figure::{
    FONT, Figure, Labels, PALETTE, PLOT_SIZE, PlotError, figure_png, figure_svg, grouped, legend_upper_left, page,
};
pub use message::printable;
pub use png_image::write_png;
