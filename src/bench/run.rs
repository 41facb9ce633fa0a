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
