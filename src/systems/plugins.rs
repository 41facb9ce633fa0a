//! [`SimulationPlugins`]: the schedule and every stage.

use bevy::app::{PluginGroup, PluginGroupBuilder};

use super::{GravityPlugin, IntegratePlugin, ResponsePlugin, SchedulePlugin, ShatterPlugin, SortPlugin, SweepPlugin};

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
