//! The simulation update: its schedule, its stage order, and the driver
//! that runs it a number of times.

use std::time::Instant;

use bevy::ecs::schedule::{ScheduleLabel, SingleThreadedExecutor};
use bevy::prelude::*;

use crate::resources::{Execution, NextBodyId, SimulationSettings, StageTimings};

/// One fixed simulation update. Run it with [`run_updates`] (headless) or
/// from a frame-rate independent clock (the app).
#[derive(ScheduleLabel, Clone, Debug, PartialEq, Eq, Hash)]
pub struct SimulationUpdate;

/// The stages of one update (DESIGN §2), in the order they run.
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SimulationSystems {
    /// Accelerations of adopters from all sources, applied as the velocity
    /// kick `v += a·dt` of the semi-implicit Euler step.
    Gravity,
    /// The drift `p += v·dt` of the semi-implicit Euler step.
    Integrate,
    /// Sweep and prune: the overlapping pairs.
    BroadPhase,
    /// Bounce and push-back of colliding pairs.
    Response,
    /// Removal of shattered pairs and spawning of their fragments.
    Shatter,
}

impl SimulationSystems {
    /// Every stage, in update order.
    pub const ALL: [Self; 5] = [
        Self::Gravity,
        Self::Integrate,
        Self::BroadPhase,
        Self::Response,
        Self::Shatter,
    ];

    /// Short lower-case name (CSV columns, HUD).
    pub fn name(self) -> &'static str {
        match self {
            Self::Gravity => "gravity",
            Self::Integrate => "integrate",
            Self::BroadPhase => "broad_phase",
            Self::Response => "response",
            Self::Shatter => "shatter",
        }
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
        // The one place where the stage order is written.
        schedule.configure_sets(
            (
                SimulationSystems::Gravity,
                SimulationSystems::Integrate,
                SimulationSystems::BroadPhase,
                SimulationSystems::Response,
                SimulationSystems::Shatter,
            )
                .chain(),
        );
        app.add_schedule(schedule)
            .init_resource::<SimulationSettings>()
            .init_resource::<StageTimings>()
            .init_resource::<NextBodyId>();
    }
}

/// Runs `updates` simulation updates on `world`, timing each as a whole.
/// In parallel mode the updates run inside the worker pool
/// ([`Execution::install`]).
pub fn run_updates(world: &mut World, updates: u64) {
    let execution = world.resource::<Execution>().clone();
    execution.install(|| {
        for _ in 0..updates {
            let start = Instant::now();
            world.run_schedule(SimulationUpdate);
            world.resource_mut::<StageTimings>().update.record(start.elapsed());
        }
    });
}
