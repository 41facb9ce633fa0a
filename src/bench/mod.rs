//! Benchmark mode (docs/design.md, "Benchmark mode"): runs from a config
//! file, measured headless (or, for `Render` runs, in the window), written
//! as CSV with per-pass rows, an overhead report, the crossover, a machine
//! report and a plot.

mod config;
mod crossover;
mod dispatch;
mod machine;
mod memory;
mod outputs;
mod plot;
mod render;
mod report;
mod run;

pub use config::*;
pub use crossover::*;
pub use dispatch::*;
pub use machine::*;
pub use memory::*;
pub use outputs::*;
pub use plot::*;
pub use render::*;
pub use report::*;
pub use run::*;
