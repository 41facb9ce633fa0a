//! Running one benchmark run headless and averaging its stage timings.

use super::config::Run;
use crate::Simulation;
use crate::execution::{AutoSplit, ExecutionError, ExecutionMode, SplitPolicy, WorkerPool};
use crate::input::{ExecutionOptions, InputError};
use crate::scenario::Scenario;
use crate::systems::{STAGE_COUNT, SimulationSystems};

/// Mean timings of one run, in nanoseconds per update.
#[derive(Clone, Debug, PartialEq)]
pub struct RunResult {
    /// Position of the run in the config, from 1.
    pub run: usize,
    /// Generated bodies the config asked for.
    pub bodies: u64,
    /// Bodies after the warm-up update.
    pub bodies_start: usize,
    /// Bodies after the last update.
    pub bodies_end: usize,
    /// Updates measured.
    pub updates: u64,
    /// Sequential or parallel.
    pub mode: ExecutionMode,
    /// Threads the stages ran on (1 in sequential mode).
    pub threads: usize,
    /// From which body count stages split (meaningless in sequential mode).
    pub split: SplitPolicy,
    /// Which pool ran the parallel steps.
    pub pool: WorkerPool,
    /// Mean time of a whole update.
    pub update_ns: f64,
    /// Mean time of each stage, indexed by stage (0 for a stage that was
    /// off).
    pub stage_ns: [f64; STAGE_COUNT],
}

impl RunResult {
    /// Mean time of `stage`.
    pub fn stage(&self, stage: SimulationSystems) -> f64 {
        self.stage_ns[stage as usize]
    }
}

/// Why a run could not be measured.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The worker pool could not be made.
    #[error(transparent)]
    Execution(#[from] ExecutionError),
    /// The scenario's bodies could not be made.
    #[error(transparent)]
    Scenario(#[from] InputError),
    /// The simulation stopped at a fault (the line names the update).
    #[error("{0}")]
    Stopped(String),
}

/// How runs execute where they do not say: the command line's execution
/// options (`kessler bench --split …`) and the per-stage counts of `Auto`.
#[derive(Clone, Debug, Default)]
pub struct RunDefaults {
    /// The options of runs that set none.
    pub execution: ExecutionOptions,
    /// What `Auto` uses.
    pub auto: AutoSplit,
}

/// Runs `run` on `scenario` (already scaled to the run's size, with its
/// seed and shatter settings): one warm-up update that is not measured,
/// then `run.updates` measured updates; `progress` is told how many
/// measured updates are done, now and then.
pub fn measure(
    index: usize,
    scenario: &Scenario,
    run: &Run,
    defaults: &RunDefaults,
    mut progress: impl FnMut(u64),
) -> Result<RunResult, RunError> {
    let options = run.execution.or(defaults.execution);
    let execution = options.build(defaults.auto.clone())?;
    let threads = execution.threads_used();
    let mut sim = Simulation::from_scenario(scenario, execution)?;
    {
        let mut settings = sim.settings_mut();
        settings.stages = run.stages;
    }
    sim.step(1);
    sim.timings_mut().reset();
    let bodies_start = sim.body_count();
    sim.step_reporting(run.updates, 100, &mut progress);
    if let Some(fault) = sim.check_state() {
        return Err(RunError::Stopped(fault));
    }
    let bodies_end = sim.body_count();
    let timings = sim.timings();
    Ok(RunResult {
        run: index,
        bodies: run.bodies,
        bodies_start,
        bodies_end,
        updates: run.updates,
        mode: options.mode(),
        threads,
        split: options.split(),
        pool: options.pool(),
        update_ns: timings.update.mean_ns,
        // A stage that was off ran no samples: its mean stays 0.
        stage_ns: SimulationSystems::ALL.map(|stage| timings.stage(stage).mean_ns),
    })
}

/// The pass with the median update time among `passes` of one run (the
/// lower median for an even count), stage times and all: a robust choice
/// on a machine whose speed wanders between passes.
pub fn median_pass(mut passes: Vec<RunResult>) -> Option<RunResult> {
    passes.sort_by(|a, b| a.update_ns.total_cmp(&b.update_ns));
    let middle = passes.len().checked_sub(1)? / 2;
    Some(passes.swap_remove(middle))
}

/// The unit tests' result: run 1 of one update at `bodies` bodies in
/// `mode` on `threads` threads of Kessler's pool, taking `update_ns`,
/// shared evenly among the stages.
#[cfg(test)]
pub fn test_result(bodies: u64, mode: ExecutionMode, threads: usize, split: SplitPolicy, update_ns: f64) -> RunResult {
    RunResult {
        run: 1,
        bodies,
        bodies_start: bodies as usize,
        bodies_end: bodies as usize,
        updates: 1,
        mode,
        threads,
        split,
        pool: WorkerPool::Kessler,
        update_ns,
        stage_ns: [update_ns / STAGE_COUNT as f64; STAGE_COUNT],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pass(update_ns: f64, gravity_ns: f64) -> RunResult {
        let mut result = test_result(10, ExecutionMode::Parallel, 2, SplitPolicy::Auto, update_ns);
        result.stage_ns = [0.0; STAGE_COUNT];
        result.stage_ns[SimulationSystems::Gravity as usize] = gravity_ns;
        result
    }

    #[test]
    fn median_pass_is_the_middle_update_time_with_its_own_stages() {
        let passes = vec![
            pass(9.0, 1.0),
            pass(3.0, 2.0),
            pass(5.0, 3.0),
            pass(100.0, 4.0),
            pass(4.0, 5.0),
        ];
        assert_eq!(median_pass(passes), Some(pass(5.0, 3.0)));
        assert_eq!(median_pass(vec![pass(8.0, 1.0), pass(2.0, 2.0)]), Some(pass(2.0, 2.0)));
        assert_eq!(median_pass(Vec::new()), None);
    }
}
