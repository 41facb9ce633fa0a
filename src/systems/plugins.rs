//! [`SimulationPlugins`]: the schedule and every stage.

use bevy::app::{PluginGroup, PluginGroupBuilder};

use super::{BroadPhasePlugin, GravityPlugin, IntegratePlugin, ResponsePlugin, SchedulePlugin, ShatterPlugin};

/// Every simulation stage and the schedule they run in. Needs an
/// [`Execution`](crate::execution::Execution) resource.
pub struct SimulationPlugins;

impl PluginGroup for SimulationPlugins {
    fn build(self) -> PluginGroupBuilder {
        PluginGroupBuilder::start::<Self>()
            .add(SchedulePlugin)
            .add(GravityPlugin)
            .add(IntegratePlugin)
            .add(BroadPhasePlugin)
            .add(ResponsePlugin)
            .add(ShatterPlugin)
    }
}
