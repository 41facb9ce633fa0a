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
use crate::resources::{CollisionDetection, MemoryBudget, SimulationSettings};
use crate::systems::pipeline::{Travel, pair_limit, swept_pair_limit};
use crate::systems::sort::{BodyColumns, BoxSource, BroadPhaseQuery, SortedBoxes, sort_boxes};
use crate::systems::{Fault, SimulationFault, SimulationSystems, SimulationUpdate, StageClocks};

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

/// How many pairs swept detection's sweep may find: past [`pair_limit`]
/// only once the boxes where the update ends were found not piled, then as
/// many as the last update needed (doubled as they grow), up to
/// [`swept_pair_limit`].
#[derive(Default)]
struct SweptAllowance {
    /// The pairs allowed (0: [`pair_limit`]).
    limit: usize,
    /// The boxes where the update ends, sorted to count their pairs.
    ends: SortedBoxes,
}

fn sweep(
    settings: Res<SimulationSettings>,
    mut clocks: StageClocks,
    mut pairs: ResMut<OverlappingPairs>,
    sorted: Res<SortedBoxes>,
    bodies: BroadPhaseQuery,
    (memory, mut allowance): (Option<Res<MemoryBudget>>, Local<SweptAllowance>),
    mut fault: ResMut<SimulationFault>,
) {
    pairs.0.clear();
    if !settings.stages.collisions {
        return;
    }
    let clock = clocks.start(SimulationSystems::Sweep);
    // Only the ids and entities are read here: the boxes are the sort's.
    let columns = BodyColumns::<false>::new(bodies.contiguous_iter().expect("body components are table-stored"));
    // The sort stage ran on these bodies just before (nothing spawns or
    // despawns between the two stages).
    debug_assert_eq!(sorted.len(), columns.len(), "the sort saw other bodies");
    let n = columns.len();
    let swept = settings.collision_detection == CollisionDetection::Swept;
    let most = swept_pair_limit(n, memory.and_then(|m| m.limit).map(|l| l.free_bytes));
    let mut limit = if swept {
        allowance.limit.clamp(pair_limit(n), most)
    } else {
        pair_limit(n)
    };
    let index_pairs = loop {
        match sweep_sorted(&sorted, clock.execution(n), limit) {
            Ok(pairs) => break pairs,
            Err(e) if swept && limit < most => {
                // Long swept boxes or bodies piled up? Where the update
                // ends, piled bodies overlap as much.
                sort_boxes(&columns, clock.execution(n), &mut allowance.ends);
                if let Err(piled) = sweep_sorted(&allowance.ends, clock.execution(n), pair_limit(n)) {
                    fault.stop(Fault::PileUp(piled));
                    break Vec::new();
                }
                limit = e.limit.saturating_mul(2).min(most);
                allowance.limit = limit;
            }
            Err(mut e) => {
                if swept {
                    let (distance, edge) = columns.longest_travel();
                    e.long_sweeps = Some(Travel { distance, edge });
                }
                fault.stop(Fault::PileUp(e));
                break Vec::new();
            }
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
