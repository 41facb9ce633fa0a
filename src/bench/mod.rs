//! Benchmark mode (docs/design.md, "Benchmark mode"): runs from a config
//! file, measured headless (or, for `Render` runs, in the window), written
//! as CSV with per-pass rows, an overhead report, the crossover, a machine
//! report and a plot.

mod config;
mod crossover;
mod dispatch;
mod machine;
mod measured_run;
mod outputs;
mod passes;
mod peak_memory;
mod plot;
mod render;
mod report;
mod threads;
mod threads_plot;

pub use crate::output::{Labels, PLOT_SIZE, PlotError};
pub use config::{BenchConfig, BenchRun, MAX_REPEAT, RenderRun, Run, ThreadsRun};
pub use crossover::{Crossover, Wins, crossovers};
pub use dispatch::empty_step_ns;
pub use machine::{REFERENCES, Reference, machine_report, plot_footer, this_cpu, utc_now};
#[cfg(test)]
pub use measured_run::test_result;
pub use measured_run::{RunDefaults, RunError, RunResult, measure, median_pass};
pub use outputs::{BenchOutputError, BenchOutputs, Finished, GrowingOutputs};
pub use passes::{PassError, PassProgress, empty_step_rows, measure_passes};
pub use peak_memory::{peak_memory, reset_peak_memory};
pub use plot::{png, svg};
pub use render::{FrameReport, RenderRow, RenderRunError, WINDOW_WARMUP_FRAMES, child_args, measure_render};
pub use report::{
    CONTRACT_STAGE_COLUMNS, OverheadRow, PassRow, column_ns, columns_in_stage_order, empty_step_row, overhead_rows,
    stage_columns, times_by_stage,
};
pub use threads::{ThreadsRow, thread_rows};
pub use threads_plot::{threads_png, threads_svg};
