//! Runs the simulation from the frame loop at the chosen updates per second,
//! applying the live settings first: a change of a live physics setting in
//! the panel is recorded as a `Set` event (docs/design.md, "Events"), so
//! that a saved session replays it.

use std::time::{Duration, Instant};

use bevy::prelude::*;

use super::output_failures::OutputFailures;
use super::sandbox_settings::SandboxSettings;
use super::scene::SandboxState;
use super::update_clock::{UpdateClock, updates_within_budget};
use crate::execution::Execution;
use crate::input::ExecutionOptions;
use crate::resources::SimulationSettings;
use crate::scenario::{Event, Set};
use crate::systems::{SimulationFault, StageTimings, UpdateCount, run_updates};
use crate::timed_events::record_event;
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
        app.init_resource::<UpdateClock>()
            .init_resource::<OutputFailures>()
            .add_systems(
                Update,
                (apply_live_settings, drive_simulation, show_set_events)
                    .chain()
                    .in_set(SandboxSystems::Simulate),
            )
            .add_systems(Last, stopped_at_close);
    }
}

/// Applies the live settings (execution, stage switches) to the
/// simulation resources, changing only what differs, and records the live
/// physics settings the panel changed as a `Set` event at the update the
/// run is at.
fn apply_live_settings(world: &mut World) {
    let settings = world.resource::<SandboxSettings>().clone();
    if ExecutionOptions::of(world.resource::<Execution>()) != settings.execution.resolved()
        && let Err(e) = settings.execution.apply_to(&mut world.resource_mut::<Execution>())
    {
        warn!("threads: {e}");
    }
    let physics = world.resource::<SimulationSettings>().clone();
    let mut wanted = physics.clone();
    settings.apply_physics(&mut wanted);
    if physics == wanted {
        return;
    }
    let update = world.resource::<UpdateCount>().0;
    if let Some(set) = Set::between(update, &physics, &wanted) {
        record_event(world, Event::Set(set));
    }
    // The stage switches, which are not events.
    let mut physics = world.resource_mut::<SimulationSettings>();
    if *physics != wanted {
        *physics = wanted;
    }
}

/// After the frame's updates: the panel shows the live physics settings a
/// `Set` event of the scenario changed (so that it does not take them
/// back as a change of its own).
fn show_set_events(physics: Res<SimulationSettings>, mut settings: ResMut<SandboxSettings>) {
    if physics.is_changed() {
        let mut shown = settings.clone();
        shown.adopt_live(&physics);
        if shown != *settings {
            *settings = shown;
        }
    }
}

/// Runs the updates this frame owes, within [`SIMULATION_BUDGET`]; the
/// rest are dropped and counted. The clock is set from the panel first
/// (rate, speed, pause, a step); a new scene starts owing no fraction.
fn drive_simulation(world: &mut World, mut scene: Local<u64>) {
    let real = *world.resource::<Time<Real>>();
    let settings = world.resource::<SandboxSettings>();
    let (updates_per_second, speed) = (settings.updates_per_second, settings.speed);
    let mut state = world.resource_mut::<SandboxState>();
    let paused = state.paused;
    let step = std::mem::take(&mut state.step_requested) && paused;
    let rebuilt = std::mem::replace(&mut *scene, state.generation) != state.generation;
    let mut clock = world.resource_mut::<UpdateClock>();
    clock.set_rate(updates_per_second, speed);
    clock.set_paused(paused);
    if rebuilt {
        clock.forget_fraction();
    }
    if step {
        clock.step();
    }
    let owed = clock.owed(&real);
    let last_cost = Duration::from_nanos(world.resource::<StageTimings>().update.last_ns);
    let planned = updates_within_budget(owed, last_cost, SIMULATION_BUDGET);
    let start = Instant::now();
    let mut ran = 0;
    while ran < planned && (ran == 0 || start.elapsed() < SIMULATION_BUDGET) {
        run_updates(world, 1);
        ran += 1;
    }
    // The frame's updates are run: the workers' polling would only take
    // the cores the drawing needs now.
    world.resource::<Execution>().rest();
    world
        .resource_mut::<UpdateClock>()
        .record(real.delta_secs_f64(), owed, ran);
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

/// At the close: a run whose simulation is stopped (a fault the scene was
/// not restarted or rewound from) ends as a stopped headless run does,
/// saying why; its state, half an update, is written nowhere.
fn stopped_at_close(
    mut exits: MessageReader<AppExit>,
    fault: Res<SimulationFault>,
    state: Res<SandboxState>,
    failures: Res<OutputFailures>,
) {
    if exits.read().next().is_none() {
        return;
    }
    if let Some(message) = fault.message() {
        failures.closed_stopped(format!(
            "{}: {message}; the state at the close, half an update, was not written",
            state.scenario.origin
        ));
    }
}

#[cfg(test)]
mod tests {
    use bevy::time::TimeUpdateStrategy;

    use super::*;
    use crate::components::{BodyId, BodyState, GravityRole};
    use crate::execution::ExecutionMode;
    use crate::scenario::Scenario;
    use crate::simulation::spawn_bodies;
    use crate::systems::{SimulationPlugins, SimulationUpdate};

    /// A frame runs the updates that fit in its budget and drops the rest,
    /// counted; none are carried over to the next frame.
    #[test]
    fn a_frame_drops_the_updates_that_do_not_fit_its_budget() {
        let mut app = App::new();
        let settings = SandboxSettings {
            updates_per_second: 600,
            ..SandboxSettings::default()
        };
        // Frames of 250 ms at 600 UPS owe 150 updates each, 1 ms apiece:
        // 150 ms, three times the budget.
        let frame = Duration::from_millis(250);
        let slow_update = || std::thread::sleep(Duration::from_millis(1));
        app.add_plugins((MinimalPlugins, SimulationPlugins))
            .insert_resource(Execution::new(ExecutionMode::Sequential, 1).unwrap())
            .insert_resource(SandboxState::new(Scenario::builtin_default(), &settings))
            .insert_resource(settings)
            .insert_resource(TimeUpdateStrategy::ManualDuration(frame))
            .init_resource::<UpdateClock>()
            .add_systems(SimulationUpdate, slow_update)
            .add_systems(Update, drive_simulation);
        // The first frame only starts the real clock.
        for _ in 0..3 {
            app.update();
        }
        let world = app.world();
        let clock = world.resource::<UpdateClock>();
        let (ran, dropped) = (clock.updates_total, clock.dropped_total);
        assert_eq!(ran + dropped, 300, "{ran} ran, {dropped} dropped");
        assert!((2..=2 * 51).contains(&ran), "{ran} ran in two frames of a 50 ms budget");
        assert_eq!(world.resource::<UpdateCount>().0, ran);
    }

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
        assert_eq!(world.resource::<UpdateCount>().0, 1);
        assert_eq!(world.resource::<SandboxState>().error.as_ref(), Some(&error));
    }

    /// A live physics setting changed in the panel is recorded as a `Set`
    /// at the update the run is at, and applied; a `Set` of the scenario
    /// shows in the panel and is not taken back.
    #[test]
    fn a_live_change_in_the_panel_is_recorded_as_a_set_event() {
        let scenario = Scenario::parse(
            "Scenario(bodies: [Body(position: (0, 0, 0))], events: [Set(update: 3, fragment_spread: 0.5)])",
            "set.ron",
        )
        .unwrap();
        let settings = SandboxSettings::default();
        let mut app = App::new();
        app.add_plugins((MinimalPlugins, SimulationPlugins, crate::timed_events::EventsPlugin))
            .insert_resource(Execution::new(ExecutionMode::Sequential, 1).unwrap())
            .insert_resource(scenario.settings())
            .insert_resource(SandboxState::new(scenario.clone(), &settings))
            .insert_resource(settings)
            .add_plugins(DrivePlugin);
        spawn_bodies(app.world_mut(), &scenario.bodies().unwrap());
        crate::timed_events::install_events(app.world_mut(), &scenario);
        app.world_mut().resource_mut::<SandboxState>().paused = true;
        for _ in 0..2 {
            app.world_mut().resource_mut::<SandboxState>().step_requested = true;
            app.update();
        }
        app.world_mut()
            .resource_mut::<SandboxSettings>()
            .physics
            .shatter_threshold = 7.5;
        app.update();
        let world = app.world();
        assert_eq!(world.resource::<SimulationSettings>().shatter_threshold, 7.5);
        let recorded: Vec<_> = world
            .resource::<crate::timed_events::EventQueue>()
            .all()
            .filter(|q| q.place.is_none())
            .map(|q| q.event.clone())
            .collect();
        let [Event::Set(set)] = recorded.as_slice() else {
            panic!("{recorded:?}")
        };
        assert_eq!(
            (set.update, set.settings.keys.as_slice()),
            (2, ["shatter_threshold"].as_slice())
        );
        // The scenario's own Set, at update 3, reaches the panel.
        for _ in 0..2 {
            app.world_mut().resource_mut::<SandboxState>().step_requested = true;
            app.update();
        }
        let world = app.world();
        assert_eq!(world.resource::<SimulationSettings>().fragment_spread, 0.5);
        assert_eq!(world.resource::<SandboxSettings>().physics.fragment_spread, 0.5);
        assert_eq!(
            world.resource::<crate::timed_events::EventQueue>().all().count(),
            2,
            "nothing taken back"
        );
    }
}
