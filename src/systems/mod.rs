//! The simulation stages, one plugin per stage, and what they run in.
//!
//! Every stage is a folder named after it — `gravity`, `integrate`,
//! `sort`, `sweep`, `response`, `shatter` — of one shape: its `mod.rs`
//! holds the plugin and the thin system that times itself and calls the
//! stage's kernels, which lie beside it and are plain functions, testable
//! without an App. Each stage system takes a [`Stage`] and names itself
//! once, in [`Stage::start`]. `pipeline/` holds what every stage runs in:
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
    GROUP_SIZE, GravityColumns, GravityInUse, GravityPlugin, GravitySource, Kernel, LEAF_SIZE, Octree, Pull,
    PullScratch, REGION_SIZE, Roles, SourceColumns, acceleration_at, add_pulls, collect_sources, gravity_kernel,
    half_drift, prepare_pull, pull_factor,
};
pub use integrate::{Drift, IntegrateColumns, IntegratePlugin, integrate_kernel};
pub use pipeline::{
    BetweenUpdates, Fault, MIN_PAIR_LIMIT, NextEventAt, PAIRS_PER_BOX, STAGE_COUNT, STAGES, SchedulePlugin,
    SimulationFault, SimulationSystems, SimulationUpdate, Stage, StageClock, StageInfo, StageTimings, Timing,
    TooManyPairs, UpdateCount, first_non_finite, no_fault, pair_limit, run_due_events, run_updates,
};
pub use response::{
    Absorbed, CollisionStats, ContactBody, Matched, Meeting, Motion, Outcome, ResponsePlugin, apart_axes,
    collision_axes, contact_states, elastic, first_contact, refuse_shatters, respond, respond_swept, respond_to_ball,
};
pub use shatter::{PendingShatters, Reentering, ShatterPair, ShatterPlugin};
pub use sort::{BodyColumns, BoxSource, BroadPhaseQuery, SortPlugin, SortedBoxes, TableColumns, sort_boxes, swept_box};
pub use sweep::{OverlappingPairs, Pair, SweepPlugin, id_pairs, sweep_and_prune, sweep_sorted};

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
