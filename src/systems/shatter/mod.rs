//! The shatter stage ([`ShatterPlugin`]): the bodies the response shattered
//! are removed and the fragments it made (`physics::fragments`;
//! docs/design.md, "Shatter") are added, and the bodies an absorber took are
//! removed. The response gives fragments fresh ids in pair order, so the
//! result does not depend on how it was executed.

use bevy::ecs::system::SystemParam;
use bevy::prelude::*;

use crate::components::BodyState;
use crate::resources::{MemoryBudget, NextBodyId};
use crate::systems::{Fault, SimulationFault, SimulationSystems, SimulationUpdate, StageClocks};

/// What the response shattered this update, for the shatter stage.
#[derive(Resource, Clone, Debug, Default)]
pub struct PendingShatters {
    /// Pairs that shattered.
    pub pairs: usize,
    /// The bodies that shattered, to remove, in pair order.
    pub shattered: Vec<Entity>,
    /// The fragments to add, in the order of their fresh ids, where they
    /// end the update (with swept detection they move on from where their
    /// pair met and meet what their paths reach: `response/time_order.rs`).
    pub fragments: Vec<BodyState>,
    /// Fresh ids handed out: to these fragments and to any an absorber
    /// took in the update they were made in.
    pub ids: u64,
    /// The bodies the update would have had when a shatter would have
    /// outgrown the run's memory ([`MemoryBudget`]): its fragments were
    /// not made, and this stage stops the run.
    pub outgrown: Option<u64>,
}

impl PendingShatters {
    /// Nothing to shatter.
    pub fn clear(&mut self) {
        self.pairs = 0;
        self.shattered.clear();
        self.fragments.clear();
        self.ids = 0;
        self.outgrown = None;
    }
}

/// Bodies the response found touching an absorber this update, in pair
/// order, for this stage to remove.
#[derive(Resource, Clone, Debug, Default)]
pub struct Reentering(pub Vec<Entity>);

/// The stage's queue, which the response fills: the pairs to shatter and
/// the bodies to remove.
#[derive(SystemParam)]
pub struct ShatterQueue<'w> {
    /// The pairs to shatter, in pair order.
    pub pending: ResMut<'w, PendingShatters>,
    /// The bodies an absorber took, in pair order.
    pub reentering: ResMut<'w, Reentering>,
}

/// The run's memory, and where a run that would outgrow it stops.
#[derive(SystemParam)]
struct Room<'w> {
    budget: Res<'w, MemoryBudget>,
    fault: ResMut<'w, SimulationFault>,
}

/// Replaces shattered pairs by fragments in [`SimulationSystems::Shatter`].
pub struct ShatterPlugin;

impl Plugin for ShatterPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<PendingShatters>()
            .init_resource::<Reentering>()
            .init_resource::<MemoryBudget>()
            .add_systems(SimulationUpdate, shatter.in_set(SimulationSystems::Shatter));
    }
}

fn shatter(
    mut clocks: StageClocks,
    queue: ShatterQueue,
    mut next_id: ResMut<NextBodyId>,
    room: Room,
    mut commands: Commands,
) {
    let clock = clocks.start(SimulationSystems::Shatter);
    let ShatterQueue {
        mut pending,
        mut reentering,
    } = queue;
    let Room { budget, mut fault } = room;
    for entity in reentering.0.drain(..) {
        commands.entity(entity).despawn();
    }
    if let Some(after) = pending.outgrown
        && let Some(limit) = budget.limit
    {
        // The response stopped making fragments before the allocation that
        // would fail.
        pending.clear();
        fault.stop(Fault::OutOfMemory { bodies: after, limit });
        return;
    }
    for entity in pending.shattered.drain(..) {
        commands.entity(entity).despawn();
    }
    next_id.0 += pending.ids;
    debug_assert!(
        pending.fragments.iter().all(|f| !f.has_markers()),
        "fragments are interacting boxes: no markers to insert"
    );
    // A pair's fragments share one role (`fragments_for`); where it is no
    // adopter's (a self-gravitating cluster's), they carry it. Spawned in
    // id order, in runs of one kind (one batch of bundles each; the
    // fragments' buffer is kept for the next update).
    for run in pending
        .fragments
        .chunk_by(|a, b| a.role.is_stored() == b.role.is_stored())
    {
        if run[0].role.is_stored() {
            commands.spawn_batch(run.iter().map(|f| (f.bundle(), f.role)).collect::<Vec<_>>());
        } else {
            commands.spawn_batch(run.iter().map(BodyState::bundle).collect::<Vec<_>>());
        }
    }
    pending.clear();
    clock.finish();
}
