//! Reading what users hand in — scenario files, benchmark configs, settings
//! files — with errors that name the file, the line and the field.

mod error;
pub(crate) mod execution_options;
mod limits;
mod read_file;
mod ron_text;
mod spelling;
mod struct_fields;
mod user_files;
mod value_checks;

pub use error::InputError;
pub use execution_options::{BENCH_EXECUTION_HEADING, EXECUTION_HEADING, ExecutionOptions};
pub use limits::{
    MAX_RUN_BODIES, MAX_UPDATES, jobs_arg, positive_count_arg, run_bodies_arg, threads_arg, updates_arg, ups_arg,
};
#[cfg(all(test, unix))]
pub(crate) use read_file::make_fifo;
pub use read_file::{MAX_INPUT_BYTES, load_ron, node_kind, read_text, read_text_if_present};
pub use ron_text::parse_ron;
pub use spelling::nearly;
pub use struct_fields::{ReadByHand, deserialize_by_hand, read_fields, require, unknown_field};
pub use user_files::{default_calibration_path, default_settings_path};
pub use value_checks::{
    FieldName, body_count, f32_where, read, shown_number, vec3_where, whole, whole_at_least, whole_between,
};
