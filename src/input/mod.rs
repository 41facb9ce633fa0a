//! Reading what users hand in — scenario files, benchmark configs, settings
//! files — with errors that name the file, the line and the field.

mod checked;
mod error;
mod file;
mod limits;
mod ron_text;

pub use checked::{
    FieldName, body_count, f32_where, read, shown_number, vec3_where, whole, whole_at_least, whole_between,
};
pub use error::InputError;
#[cfg(all(test, unix))]
pub(crate) use file::make_fifo;
pub use file::{MAX_INPUT_BYTES, load_ron, node_kind, read_text, read_text_if_present};
pub use limits::{
    MAX_RUN_BODIES, MAX_UPDATES, jobs_arg, positive_count_arg, run_bodies_arg, threads_arg, updates_arg, ups_arg,
};
pub use ron_text::parse_ron;
