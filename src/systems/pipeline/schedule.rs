//! The simulation update: its schedule, the stage order, and the driver that
//! runs it a number of times.

use std::time::Instant;

use bevy::ecs::schedule::{LogLevel, ScheduleBuildSettings, ScheduleLabel, SingleThreadedExecutor};
use bevy::prelude::*;

use super::{SimulationFault, SimulationSystems, StageTimings, UpdateCount, no_fault};
use crate::execution::Execution;
use crate::resources::{NextBodyId, SimulationSettings};

/// One fixed simulation update. Run it with [`run_updates`] (headless) or
/// from a frame-rate independent clock (the window).
#[derive(ScheduleLabel, Clone, Debug, PartialEq, Eq, Hash)]
pub struct SimulationUpdate;

/// What happens between two updates: the scenario's events
/// (docs/design.md, "Events"), added by the events' plugin. It runs only
/// when [`NextEventAt`] says an event is due, so a run without events
/// pays one comparison an update.
#[derive(ScheduleLabel, Clone, Debug, PartialEq, Eq, Hash)]
pub struct BetweenUpdates;

/// The number of updates after which the next event is due
/// ([`BetweenUpdates`] runs then, before the next update); `u64::MAX`:
/// none.
#[derive(Resource, Clone, Copy, Debug, PartialEq, Eq)]
pub struct NextEventAt(pub u64);

impl Default for NextEventAt {
    fn default() -> Self {
        Self(u64::MAX)
    }
}

/// Creates the [`SimulationUpdate`] schedule with its stage order, and the
/// resources every stage shares. Stage plugins add their systems to the sets.
pub struct SchedulePlugin;

impl Plugin for SchedulePlugin {
    fn build(&self, app: &mut App) {
        let mut schedule = Schedule::new(SimulationUpdate);
        // The stages are a chain; parallelism lives inside each stage.
        schedule.set_executor(SingleThreadedExecutor::new());
        // Two systems touching the same data in no defined order would make
        // the result depend on the schedule's whims: refuse to build.
        schedule.set_build_settings(ScheduleBuildSettings {
            ambiguity_detection: LogLevel::Error,
            ..default()
        });
        // The stage order, from the stage list.
        for pair in SimulationSystems::ALL.windows(2) {
            schedule.configure_sets(pair[0].before(pair[1]));
        }
        // After a fault, no stage runs (the state cannot be trusted).
        for stage in SimulationSystems::ALL {
            schedule.configure_sets(stage.run_if(no_fault));
        }
        let mut between = Schedule::new(BetweenUpdates);
        between.set_executor(SingleThreadedExecutor::new());
        app.add_schedule(schedule)
            .add_schedule(between)
            .init_resource::<NextEventAt>()
            .init_resource::<SimulationFault>()
            .init_resource::<UpdateCount>()
            .init_resource::<SimulationSettings>()
            .init_resource::<StageTimings>()
            .init_resource::<NextBodyId>();
    }
}

/// Runs the events due now ([`BetweenUpdates`]), if any: those of the
/// updates run so far. The window calls it when a tool records an event,
/// so that the event shows before the next update.
pub fn run_due_events(world: &mut World) {
    if world.resource::<UpdateCount>().0 >= world.resource::<NextEventAt>().0 {
        world.run_schedule(BetweenUpdates);
    }
}

/// Runs `updates` simulation updates on `world`, timing each as a whole,
/// and stops early at a [`SimulationFault`]. The events of an update run
/// once it has run ([`BetweenUpdates`]; those of update 0 ran when the
/// scene was made), so that a run that stops after update N shows N's
/// events, as a window paused there does once a tool acts. In parallel
/// mode the updates run inside the worker pool ([`Execution::install`]).
pub fn run_updates(world: &mut World, updates: u64) {
    let execution = world.resource::<Execution>().clone();
    execution.install(|| {
        for _ in 0..updates {
            if world.resource::<SimulationFault>().fault.is_some() {
                return;
            }
            world.resource_mut::<UpdateCount>().0 += 1;
            let start = Instant::now();
            world.run_schedule(SimulationUpdate);
            world.resource_mut::<StageTimings>().update.record(start.elapsed());
            let update = world.resource::<UpdateCount>().0;
            world.resource_mut::<SimulationFault>().date(update);
            if world.resource::<SimulationFault>().fault.is_none() {
                run_due_events(world);
            }
        }
    });
}
