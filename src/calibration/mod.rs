//! This machine's split calibration (docs/design.md, "Sequential and
//! parallel"): from which body count each stage pays for splitting its
//! work, measured by `kessler calibrate` and used by split policy `Auto`.

mod measure;
mod stored;

pub use measure::{LADDER, NOT_FOUND, PASSES, calibrate, threads_to_measure};
pub use stored::{Calibration, auto_split_from, load_calibration, machine_auto_split};
