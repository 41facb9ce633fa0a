//! Runs the simulation from the frame loop at the chosen updates per second,
//! applying the live settings first.

use std::time::{Duration, Instant};

use bevy::prelude::*;

use super::sandbox_settings::SandboxSettings;
use super::scene::SandboxState;
use super::update_clock::{UpdateClock, updates_within_budget};
use crate::execution::Execution;
use crate::resources::SimulationSettings;
use crate::systems::{SimulationFault, StageTimings, run_updates};
use crate::ui::sets::SandboxSystems;

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
    // A run that stopped pauses, with the reason where errors show.
    if let Some(message) = world.resource::<SimulationFault>().message() {
        let message = format!("{message}: restart the scene");
        let mut state = world.resource_mut::<SandboxState>();
        if state.error.as_ref() != Some(&message) {
            warn!("{message}");
            state.paused = true;
            state.error = Some(message);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::components::{BodyId, BodyState, GravityRole};
    use crate::execution::ExecutionMode;
    use crate::scenario::Scenario;
    use crate::simulation::spawn_bodies;
    use crate::systems::SimulationPlugins;

    /// A run that stops at a fault pauses with the message where the panel
    /// shows errors, and says it once.
    #[test]
    fn a_fault_pauses_the_window_with_the_message() {
        let mut app = App::new();
        let settings = SandboxSettings::default();
        app.add_plugins((MinimalPlugins, SimulationPlugins))
            .insert_resource(Execution::new(ExecutionMode::Sequential, 1).unwrap())
            .insert_resource(SimulationSettings {
                time_step: 4.0,
                ..SimulationSettings::default()
            })
            .insert_resource(SandboxState::new(Scenario::builtin_default(), &settings))
            .insert_resource(settings)
            .init_resource::<UpdateClock>()
            .add_systems(Update, drive_simulation);
        // 1e38 a time unit for 4 time units: past f32's 3.4e38 in one update.
        let body = BodyState::new_box(
            BodyId(3),
            Vec3::ZERO,
            Vec3::new(0.0, 1e38, 0.0),
            1.0,
            Vec3::ONE,
            GravityRole::Adopter,
            true,
        );
        spawn_bodies(app.world_mut(), &[body]);
        {
            let mut state = app.world_mut().resource_mut::<SandboxState>();
            state.paused = true;
            state.step_requested = true;
        }
        app.update();
        let state = app.world().resource::<SandboxState>();
        assert!(state.paused);
        let error = state.error.clone().expect("the message is shown");
        assert!(
            error.starts_with("update 1: body 3 has a non-finite position (0, inf, 0)")
                && error.ends_with("the simulation stopped: restart the scene"),
            "{error}"
        );
        // Unpaused, nothing runs and nothing changes.
        app.world_mut().resource_mut::<SandboxState>().paused = false;
        app.update();
        app.update();
        let world = app.world();
        assert_eq!(world.resource::<SimulationFault>().updates, 1);
        assert_eq!(world.resource::<SandboxState>().error.as_ref(), Some(&error));
    }
}
