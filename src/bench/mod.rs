//! Benchmark mode (DESIGN §7): runs from a config file, measured headless,
//! written as CSV with a plot.

mod config;
mod memory;
mod plot;
mod report;
mod run;

pub use config::*;
pub use memory::*;
pub use plot::*;
pub use report::*;
pub use run::*;
