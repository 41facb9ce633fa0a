//! The sweep stage ([`SweepPlugin`]), the second half of the broad phase:
//! in each cell of the sort's grid (`systems/sort/`), each box scans
//! forward while the next box starts before it ends on x, and confirms y
//! and z (`sweep_pairs.rs`). Touching counts as overlap. A pair found in
//! several cells is reported only by the cell holding the lower corner of
//! the pair's y–z intersection, so every pair comes out exactly once. A
//! big box (the planet) joins the cells it covers and scans only the boxes
//! inside its x-slab there, so the cost stays near-linear.
//!
//! In parallel, contiguous ranges of cells are swept by their own chunk
//! and the pairs are concatenated in cell order: the same pairs in the
//! same order as one sequential pass. Writes [`OverlappingPairs`].

mod sweep_pairs;

use bevy::prelude::*;

pub use sweep_pairs::{id_pairs, sweep_and_prune, sweep_sorted};

use crate::components::BodyId;
use crate::resources::SimulationSettings;
use crate::systems::sort::{BodyColumns, BoxSource, BroadPhaseQuery, SortedBoxes};
use crate::systems::{Fault, SimulationFault, SimulationSystems, SimulationUpdate, Stage};

/// Two overlapping bodies: ids `a < b` and their entities.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pair {
    /// The lower id.
    pub a: BodyId,
    /// The higher id.
    pub b: BodyId,
    /// The entity of `a`.
    pub entity_a: Entity,
    /// The entity of `b`.
    pub entity_b: Entity,
}

/// The broad phase's output: overlapping pairs of this update, sorted by
/// `(a, b)`; empty while collision detection is off.
#[derive(Resource, Clone, Debug, Default)]
pub struct OverlappingPairs(pub Vec<Pair>);

/// Finds [`OverlappingPairs`] in [`SimulationSystems::Sweep`].
pub struct SweepPlugin;

impl Plugin for SweepPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<OverlappingPairs>()
            .add_systems(SimulationUpdate, sweep.in_set(SimulationSystems::Sweep));
    }
}

fn sweep(
    settings: Res<SimulationSettings>,
    mut stage: Stage,
    mut pairs: ResMut<OverlappingPairs>,
    sorted: Res<SortedBoxes>,
    bodies: BroadPhaseQuery,
    mut fault: ResMut<SimulationFault>,
) {
    pairs.0.clear();
    if !settings.stages.collisions {
        return;
    }
    let clock = stage.start(SimulationSystems::Sweep);
    // Only the ids and entities are read here: the boxes are the sort's.
    let columns = BodyColumns::<false>::new(bodies.contiguous_iter().expect("body components are table-stored"));
    // The sort stage ran on these bodies just before (nothing spawns or
    // despawns between the two stages).
    debug_assert_eq!(sorted.len(), columns.len(), "the sort saw other bodies");
    let index_pairs = match sweep_sorted(&sorted, clock.execution(columns.len())) {
        Ok(pairs) => pairs,
        Err(e) => {
            fault.stop(Fault::PileUp(e));
            Vec::new()
        }
    };
    pairs.0.extend(index_pairs.iter().map(|&(i, j)| {
        let (first, second) = (columns.body(i as usize), columns.body(j as usize));
        let ((a, entity_a), (b, entity_b)) = if first < second {
            (first, second)
        } else {
            (second, first)
        };
        Pair {
            a,
            b,
            entity_a,
            entity_b,
        }
    }));
    pairs.0.sort_unstable_by_key(|p| (p.a, p.b));
    clock.finish();
}
