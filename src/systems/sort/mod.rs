//! The sort stage ([`SortPlugin`]), the first half of the broad phase:
//! sweep and prune over a y–z grid finds every pair of overlapping boxes
//! (docs/design.md, "Broad phase"); this stage files the boxes, the sweep
//! stage (`systems/sweep/`) finds the pairs.
//!
//! A single sweep along x degrades when many boxes share an x range (a dense
//! cloud of a million cubes puts hundreds in every box's x range), so the
//! sweep runs per cell of a grid over y and z. The sort (`sorted_boxes.rs`,
//! `filing.rs`, `ordering.rs`) files the boxes under every cell their y–z
//! extent covers, into one array, by a counting sort that reads the bodies'
//! columns in order, twice (count, then place), and never gathers at
//! random; then each cell's boxes are put in order by their lower x bound
//! where they lie (ties by input order, so the order is one fixed
//! permutation), and the sweep reads each cell in one piece, in order.
//!
//! In parallel, contiguous ranges of boxes are counted, and then placed,
//! by their own chunk: within a cell, each chunk's boxes get the slots
//! after those of the chunks before it, which is input order again, so
//! the filing is the same array as one sequential pass. Contiguous ranges
//! of cells are then ordered by their own chunk.
//!
//! Up to 25 000 boxes, between two such fresh sorts, last update's filing
//! is repaired on its grid instead (`repair.rs`): each cell's boxes read
//! again by index (from a copy of the boxes in input order, on two
//! threads each thread's own), those that cover the same cells as before
//! kept in order, the rest filed afresh and merged in; the same filing on
//! that grid.
//!
//! The boxes come from a [`BoxSource`] (`boxes.rs`): a slice, or the
//! bodies' table columns in place — each body's box where the update
//! ends, or swept along its path through the update.

pub(in crate::systems) mod boxes;
mod filing;
mod grid;
mod ordering;
mod repair;
mod sorted_boxes;

use bevy::prelude::*;

pub use boxes::{BodyColumns, BoxSource, BroadPhaseQuery};
pub use grid::Grid;
pub use sorted_boxes::{SortedBoxes, sort_boxes};

use crate::resources::{CollisionDetection, SimulationSettings};
use crate::systems::{SimulationSystems, SimulationUpdate, StageClocks};

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
    mut clocks: StageClocks,
    mut sorted: ResMut<SortedBoxes>,
    bodies: BroadPhaseQuery,
) {
    if !settings.stages.collisions {
        sorted.clear();
        return;
    }
    let clock = clocks.start(SimulationSystems::Sort);
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
