//! Measuring a config's headless runs: every run `repeat` times, pass
//! after pass through all runs — so that a slow spell of the machine falls
//! on several runs rather than on all passes of one — keeping each run's
//! median pass; and the bare cost of a parallel step on each pool.

use super::config::{BenchConfig, Run};
use super::dispatch::empty_step_ns;
use super::measured_run::{RunDefaults, RunError, RunResult, measure, median_pass};
use super::outputs::GrowingOutputs;
use super::peak_memory::{peak_memory, reset_peak_memory};
use super::report::{OverheadRow, empty_step_row};
use crate::execution::{Execution, ExecutionError, ExecutionMode, WorkerPool, available_threads};
use crate::output::WriteError;
use crate::scenario::Scenario;

/// What is told of the measuring as it goes (the command line's progress
/// bar).
pub trait PassProgress {
    /// Run `index` (from 0 in the config) starts its pass `pass`, in `mode`.
    fn start(&mut self, index: usize, pass: u64, run: &Run, mode: ExecutionMode);
    /// `done` measured updates of the current run.
    fn advance(&self, done: u64);
    /// The run ended with `result`, the process's peak memory then.
    fn finish(&mut self, run: &Run, result: &RunResult, peak_memory: Option<u64>);
}

/// Why the passes stopped.
#[derive(Debug, thiserror::Error)]
pub enum PassError {
    /// Run `index` (from 0 in the config) could not be measured.
    #[error("{error}")]
    Run {
        /// The run.
        index: usize,
        /// Why.
        error: RunError,
    },
    /// A result could not be written.
    #[error(transparent)]
    Write(#[from] WriteError),
}

/// Measures every headless run of `config` (on its scenario `sized` to
/// it) `config.repeat` times. Every pass is written as it ends; a run's
/// median when its last pass ends. Returns the medians and every run's
/// passes.
pub fn measure_passes(
    config: &BenchConfig,
    sized: &[Scenario],
    defaults: &RunDefaults,
    growing: &mut GrowingOutputs,
    progress: &mut impl PassProgress,
) -> Result<(Vec<RunResult>, Vec<Vec<RunResult>>), PassError> {
    let passes = u64::from(config.repeat);
    let runs: Vec<(usize, &Run)> = config.update_runs().collect();
    let mut measured: Vec<Vec<RunResult>> = vec![Vec::new(); runs.len()];
    let mut medians = Vec::new();
    for pass in 1..=passes {
        for (k, &(i, run)) in runs.iter().enumerate() {
            progress.start(i, pass, run, run.execution.or(defaults.execution).mode());
            reset_peak_memory();
            let result = measure(i + 1, &sized[i], run, defaults, |done| progress.advance(done))
                .map_err(|error| PassError::Run { index: i, error })?;
            progress.finish(run, &result, peak_memory());
            growing.add_pass(pass, &result)?;
            measured[k].push(result);
            if pass == passes {
                let median = median_pass(measured[k].clone()).expect("at least one pass");
                growing.add_result(&median)?;
                medians.push(median);
            }
        }
    }
    Ok((medians, measured))
}

/// The bare cost of a parallel step as overhead rows: on Bevy's
/// `ComputeTaskPool` (with the threads it has), and on Kessler's pool with
/// 1, 2, Bevy's count (the same threads side by side) and every hardware
/// thread; `each` is told every measurement `(threads, pool, split ns,
/// whole ns)`.
pub fn empty_step_rows(mut each: impl FnMut(usize, WorkerPool, f64, f64)) -> Result<Vec<OverheadRow>, ExecutionError> {
    let bevy_threads = Execution::new(ExecutionMode::Parallel, available_threads())?
        .with_pool(WorkerPool::Bevy)
        .threads_used();
    let mut kessler_threads = vec![1, 2, bevy_threads, available_threads()];
    kessler_threads.sort_unstable();
    kessler_threads.dedup();
    kessler_threads
        .into_iter()
        .map(|threads| (threads, WorkerPool::Kessler))
        .chain(std::iter::once((bevy_threads, WorkerPool::Bevy)))
        .map(|(threads, pool)| {
            let (split, whole) = empty_step_ns(threads, pool)?;
            each(threads, pool, split, whole);
            Ok(empty_step_row(threads, pool, split, whole))
        })
        .collect()
}
