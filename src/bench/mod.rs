//! Benchmark mode (docs/design.md, "Benchmark mode"): runs from a config
//! file, measured headless, written as CSV with an overhead report and a
//! plot.

mod config;
mod memory;
mod outputs;
mod plot;
mod report;
mod run;

pub use config::*;
pub use memory::*;
pub use outputs::*;
pub use plot::*;
pub use report::*;
pub use run::*;
