//! Running one benchmark run headless and averaging its stage timings.

use super::config::Run;
use crate::Simulation;
use crate::resources::{Execution, ExecutionMode, available_threads};
use crate::scenario::Scenario;
use crate::systems::SimulationSystems;

/// Mean timings of one run, in nanoseconds per update.
#[derive(Clone, Debug, PartialEq)]
pub struct RunResult {
    /// Position of the run in the config, from 1.
    pub run: usize,
    pub bodies_start: usize,
    pub bodies_end: usize,
    pub updates: u64,
    pub mode: ExecutionMode,
    pub threads: usize,
    pub update_ns: f64,
    pub gravity_ns: f64,
    pub integrate_ns: f64,
    pub broad_phase_ns: f64,
    /// Response and shattering (DESIGN §2.4).
    pub response_ns: f64,
}

/// Runs `run` on `scenario` (already scaled to the run's size): one warm-up
/// update that is not measured, then `run.updates` measured updates;
/// `progress` is told how many measured updates are done, now and then.
pub fn measure(
    index: usize,
    scenario: &Scenario,
    origin: &str,
    run: &Run,
    mut progress: impl FnMut(u64),
) -> Result<RunResult, String> {
    let threads = run.threads.unwrap_or_else(available_threads);
    let execution = Execution::new(run.mode, threads).map_err(|e| e.to_string())?;
    let mut sim = Simulation::from_scenario(scenario, origin, execution).map_err(|e| e.to_string())?;
    {
        let mut settings = sim.settings_mut();
        settings.gravity = run.stages.gravity;
        settings.collisions = run.stages.collisions;
        settings.collision_response = run.stages.response;
    }
    sim.step(1);
    sim.timings_mut().reset();
    let bodies_start = sim.body_count();
    sim.step_reporting(run.updates, 100, &mut progress);
    let bodies_end = sim.body_count();
    let t = sim.timings();
    // A stage that was off ran no samples: its mean stays 0.
    let mean = |stage| t.stage(stage).mean_ns;
    Ok(RunResult {
        run: index,
        bodies_start,
        bodies_end,
        updates: run.updates,
        mode: run.mode,
        threads: if run.mode == ExecutionMode::Sequential {
            1
        } else {
            threads
        },
        update_ns: t.update.mean_ns,
        gravity_ns: mean(SimulationSystems::Gravity),
        integrate_ns: mean(SimulationSystems::Integrate),
        broad_phase_ns: mean(SimulationSystems::BroadPhase),
        response_ns: mean(SimulationSystems::Response) + mean(SimulationSystems::Shatter),
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

#[cfg(test)]
mod tests {
    use super::*;

    fn pass(update_ns: f64, gravity_ns: f64) -> RunResult {
        RunResult {
            run: 1,
            bodies_start: 10,
            bodies_end: 10,
            updates: 5,
            mode: ExecutionMode::Parallel,
            threads: 2,
            update_ns,
            gravity_ns,
            integrate_ns: 0.0,
            broad_phase_ns: 0.0,
            response_ns: 0.0,
        }
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
