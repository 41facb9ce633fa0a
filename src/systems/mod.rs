//! The simulation stages, one plugin per stage, and the schedule that orders
//! them.

mod gravity;
mod integrate;
mod schedule;

pub use gravity::*;
pub use integrate::*;
pub use schedule::*;

use bevy::app::{PluginGroup, PluginGroupBuilder};

/// Every simulation stage and the schedule they run in.
pub struct SimulationPlugins;

impl PluginGroup for SimulationPlugins {
    fn build(self) -> PluginGroupBuilder {
        PluginGroupBuilder::start::<Self>()
            .add(SchedulePlugin)
            .add(GravityPlugin)
            .add(IntegratePlugin)
    }
}
