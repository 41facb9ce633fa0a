//! [`SortPlugin`]: the sort stage of the broad phase, reading the bodies' table
//! columns in place and writing [`SortedBoxes`].

use bevy::prelude::*;

use super::broad_phase::{BodyColumns, BoxSource, BroadPhaseQuery, SortedBoxes, sort_boxes};
use crate::resources::{CollisionDetection, SimulationSettings};
use crate::systems::{SimulationSystems, SimulationUpdate, Stage};

/// Files the bodies' boxes by grid cell and orders them on x in
/// [`SimulationSystems::Sort`].
pub struct SortPlugin;

impl Plugin for SortPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<SortedBoxes>()
            .add_systems(SimulationUpdate, sort.in_set(SimulationSystems::Sort));
    }
}

fn sort(settings: Res<SimulationSettings>, mut stage: Stage, mut sorted: ResMut<SortedBoxes>, bodies: BroadPhaseQuery) {
    if !settings.collisions {
        sorted.clear();
        return;
    }
    let clock = stage.start(SimulationSystems::Sort);
    let tables = bodies.contiguous_iter().expect("body components are table-stored");
    if settings.collision_detection == CollisionDetection::Swept {
        let columns = BodyColumns::<true>::new(tables);
        sort_boxes(&columns, clock.execution(columns.len()), &mut sorted);
    } else {
        let columns = BodyColumns::<false>::new(tables);
        sort_boxes(&columns, clock.execution(columns.len()), &mut sorted);
    }
    clock.finish();
}
