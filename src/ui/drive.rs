//! Runs the simulation from the frame loop at the chosen updates per second,
//! applying the live settings first.

use std::time::{Duration, Instant};

use bevy::prelude::*;

use super::clock::{UpdateClock, updates_within_budget};
use super::scene::SandboxState;
use super::sets::SandboxSystems;
use super::settings::SandboxSettings;
use crate::execution::Execution;
use crate::resources::SimulationSettings;
use crate::systems::{StageTimings, run_updates};

/// Longest a frame spends simulating before it drops the updates it still
/// owes (keeps the window responsive: at least about 20 frames per second
/// unless a single update is slower than this).
pub const SIMULATION_BUDGET: Duration = Duration::from_millis(50);

/// Runs the simulation at the chosen rate: the live settings first, then
/// the updates the clock owes.
pub struct DrivePlugin;

impl Plugin for DrivePlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<UpdateClock>().add_systems(
            Update,
            (apply_live_settings, drive_simulation)
                .chain()
                .in_set(SandboxSystems::Simulate),
        );
    }
}

/// Applies the live settings (execution, physics switches) to the
/// simulation resources, changing only what differs.
fn apply_live_settings(
    settings: Res<SandboxSettings>,
    mut execution: ResMut<Execution>,
    mut physics: ResMut<SimulationSettings>,
) {
    if execution.mode() != settings.mode {
        execution.set_mode(settings.mode);
    }
    if execution.split() != settings.split {
        execution.set_split(settings.split);
    }
    if execution.threads() != settings.threads
        && let Err(e) = execution.set_threads(settings.threads)
    {
        warn!("threads: {e}");
    }
    let mut wanted = physics.clone();
    settings.apply_physics(&mut wanted);
    if *physics != wanted {
        *physics = wanted;
    }
}

/// Runs the updates this frame owes, within [`SIMULATION_BUDGET`]; the
/// rest are dropped and counted. A new scene starts owing nothing.
fn drive_simulation(world: &mut World, mut scene: Local<u64>) {
    let elapsed = world.resource::<Time<Real>>().delta_secs_f64();
    let settings = world.resource::<SandboxSettings>();
    let rate = f64::from(settings.updates_per_second) * f64::from(settings.speed);
    let mut state = world.resource_mut::<SandboxState>();
    let paused = state.paused;
    let step = std::mem::take(&mut state.step_requested);
    let rebuilt = std::mem::replace(&mut *scene, state.generation) != state.generation;
    let mut clock = world.resource_mut::<UpdateClock>();
    if rebuilt {
        clock.reset_owed();
    }
    let owed = if paused {
        clock.reset_owed();
        u32::from(step)
    } else {
        clock.owed(elapsed, rate)
    };
    let last_cost = Duration::from_nanos(world.resource::<StageTimings>().update.last_ns);
    let planned = updates_within_budget(owed, last_cost, SIMULATION_BUDGET);
    let start = Instant::now();
    let mut ran = 0;
    while ran < planned && (ran == 0 || start.elapsed() < SIMULATION_BUDGET) {
        run_updates(world, 1);
        ran += 1;
    }
    world.resource_mut::<UpdateClock>().record(elapsed, owed, ran);
}
