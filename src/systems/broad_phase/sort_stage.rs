//! [`SortPlugin`]: the broad phase's first stage, reading the bodies' table
//! columns in place and writing [`SortedBoxes`].

use std::time::Instant;

use bevy::prelude::*;

use super::{BodyColumns, BoxSource, SortedBoxes, sort_boxes};
use crate::components::{BodyId, HalfExtents, Position};
use crate::execution::Execution;
use crate::resources::SimulationSettings;
use crate::systems::{SimulationSystems, SimulationUpdate, StageTimings};

/// The columns the broad phase reads: entity, id, position, half extents.
pub type BroadPhaseQuery<'w, 's> = Query<'w, 's, (Entity, &'static BodyId, &'static Position, &'static HalfExtents)>;

/// Files the bodies' boxes by grid cell and orders them on x in
/// [`SimulationSystems::Sort`].
pub struct SortPlugin;

impl Plugin for SortPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<SortedBoxes>()
            .add_systems(SimulationUpdate, sort.in_set(SimulationSystems::Sort));
    }
}

fn sort(
    settings: Res<SimulationSettings>,
    execution: Res<Execution>,
    mut timings: ResMut<StageTimings>,
    mut sorted: ResMut<SortedBoxes>,
    bodies: BroadPhaseQuery,
) {
    if !settings.collisions {
        sorted.clear();
        return;
    }
    let start = Instant::now();
    let columns = BodyColumns::new(bodies.contiguous_iter().expect("body components are table-stored"));
    let stage = execution.for_stage(SimulationSystems::Sort.name(), columns.len());
    sort_boxes(&columns, stage, &mut sorted);
    timings.record(SimulationSystems::Sort, start.elapsed());
}
