//! Reading what users hand in — scenario files, benchmark configs, settings
//! files — with errors that name the file, the line and the field.

mod checked;
mod error;
mod file;
mod limits;
mod ron_text;

pub use checked::*;
pub use error::*;
pub use file::*;
pub use limits::*;
pub use ron_text::*;
