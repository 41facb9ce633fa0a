//! The simulation stages, one plugin per stage, and the schedule that orders
//! them.

mod broad_phase;
mod gravity;
mod integrate;
mod response;
mod schedule;
mod shatter;

pub use broad_phase::*;
pub use gravity::*;
pub use integrate::*;
pub use response::*;
pub use schedule::*;
pub use shatter::*;

use bevy::app::{PluginGroup, PluginGroupBuilder};

/// Every simulation stage and the schedule they run in.
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
