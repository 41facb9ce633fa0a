//! Scenario files (docs/design.md, "Scenario files"): the format, its
//! checks, the generators, loading, and the built-in scenes.

mod builtin;
pub mod checked;
mod fields;
mod format;
pub mod generators;
mod load;
mod scale;
mod snapshot;
mod start;

pub use builtin::*;
pub use checked::{MAX_BODIES, MAX_FRAGMENTS};
pub use format::*;
pub use scale::NoGenerators;
pub use snapshot::*;
