//! [`BroadPhasePlugin`]: the broad phase as a stage, reading the bodies'
//! table columns in place and writing [`OverlappingPairs`].

use std::time::Instant;

use bevy::prelude::*;

use super::{BodyColumns, SweepScratch, sweep_and_prune};
use crate::components::{BodyId, HalfExtents, Position};
use crate::execution::Execution;
use crate::resources::SimulationSettings;
use crate::systems::{SimulationSystems, SimulationUpdate, StageTimings};

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

/// Finds [`OverlappingPairs`] in [`SimulationSystems::BroadPhase`].
pub struct BroadPhasePlugin;

impl Plugin for BroadPhasePlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<OverlappingPairs>()
            .add_systems(SimulationUpdate, broad_phase.in_set(SimulationSystems::BroadPhase));
    }
}

fn broad_phase(
    settings: Res<SimulationSettings>,
    execution: Res<Execution>,
    mut timings: ResMut<StageTimings>,
    mut pairs: ResMut<OverlappingPairs>,
    mut scratch: Local<SweepScratch>,
    bodies: Query<(Entity, &BodyId, &Position, &HalfExtents)>,
) {
    pairs.0.clear();
    if !settings.collisions {
        return;
    }
    let start = Instant::now();
    let columns = BodyColumns::new(bodies.contiguous_iter().expect("body components are table-stored"));
    let index_pairs = sweep_and_prune(&columns, &execution, &mut scratch);
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
    timings.record(SimulationSystems::BroadPhase, start.elapsed());
}
