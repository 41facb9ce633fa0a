//! The simulation stages, one plugin per stage, and what they run in.
//!
//! Every stage is a folder named after it — `gravity`, `integrate`,
//! `sort`, `sweep`, `response`, `shatter` — of one shape: its `mod.rs`
//! holds the plugin and the thin system that times itself and calls the
//! stage's kernels, which lie beside it and are plain functions, testable
//! without an App. Each stage system takes its [`StageClocks`] and names itself
//! once, in [`StageClocks::start`]. `pipeline/` holds what every stage runs in:
//! the stage list, the schedule chained from it, the stage clock, the
//! timings and the run's fault. [`SimulationPlugins`] adds them all.

mod gravity;
mod integrate;
mod pipeline;
mod response;
mod shatter;
mod sort;
mod sweep;

use bevy::app::{PluginGroup, PluginGroupBuilder};

pub use gravity::{
    GravityInUse, GravityPlugin, GravitySource, Kernel, Octree, Pull, PullScratch, Roles, collect_sources,
    gravity_kernel, prepare_pull,
};
pub use integrate::{Drift, IntegratePlugin, integrate_kernel};
pub use pipeline::{
    BetweenUpdates, Fault, NextEventAt, STAGE_COUNT, STAGES, SchedulePlugin, SimulationFault, SimulationSystems,
    SimulationUpdate, StageTimings, Timing, UpdateCount, first_non_finite, run_due_events, run_updates,
};
pub use response::{Absorbed, CollisionStats, ContactBody, ResponsePlugin, respond};
// The stages' own: shared between the stage folders, not the library's.
pub(crate) use pipeline::StageClocks;
pub use shatter::ShatterPlugin;
pub use sort::{SortPlugin, SortedBoxes, sort_boxes};
pub use sweep::{OverlappingPairs, Pair, SweepPlugin, id_pairs, sweep_and_prune};

/// Every simulation stage and the schedule they run in. Needs an
/// [`Execution`](crate::execution::Execution) resource.
pub struct SimulationPlugins;

impl PluginGroup for SimulationPlugins {
    fn build(self) -> PluginGroupBuilder {
        PluginGroupBuilder::start::<Self>()
            .add(SchedulePlugin)
            .add(GravityPlugin)
            .add(IntegratePlugin)
            .add(SortPlugin)
            .add(SweepPlugin)
            .add(ResponsePlugin)
            .add(ShatterPlugin)
    }
}

#[cfg(test)]
mod tests {
    use bevy::prelude::*;

    use super::*;
    use crate::execution::{Execution, ExecutionMode};

    fn simulation_app() -> App {
        let mut app = App::new();
        app.add_plugins((MinimalPlugins, SimulationPlugins))
            .insert_resource(Execution::new(ExecutionMode::Sequential, 1).unwrap());
        app
    }

    /// Whether the update schedule builds.
    fn build(app: &mut App) -> bool {
        let world = app.world_mut();
        let mut schedule = world
            .resource_mut::<Schedules>()
            .remove(SimulationUpdate)
            .expect("the schedule exists");
        schedule.initialize(world).is_ok()
    }

    #[test]
    fn the_stages_are_ordered_and_two_unordered_writers_are_refused() {
        let mut app = simulation_app();
        assert!(build(&mut app), "the stages' systems are unambiguous");
        let mut app = simulation_app();
        let touch = |mut pairs: ResMut<OverlappingPairs>| pairs.0.clear();
        app.add_systems(SimulationUpdate, (touch, touch));
        assert!(!build(&mut app), "ambiguity detection is off");
    }
}
