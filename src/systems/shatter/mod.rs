//! The shatter stage ([`ShatterPlugin`]): pairs marked by the response are
//! removed and replaced by fragments (`physics::fragments`; docs/design.md,
//! "Shatter"), and the bodies an absorber took are removed. Fragments get
//! fresh ids in pair order, so the result does not depend on how the
//! response was executed.

use bevy::ecs::system::SystemParam;
use bevy::prelude::*;

use crate::components::{BodyId, BodyState};
use crate::physics::{fragments_for, move_on};
use crate::resources::{MemoryBudget, NextBodyId, SimulationSettings};
use crate::systems::{Fault, SimulationFault, SimulationSystems, SimulationUpdate, StageClocks};

/// Two bodies to shatter, in pair order, for the shatter stage.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShatterPair {
    /// The two bodies' entities, to despawn.
    pub entities: [Entity; 2],
    /// Their state at the impact (with swept detection, where they met).
    pub bodies: [BodyState; 2],
    /// The time left in the update after the impact, for which the
    /// fragments move on from where they are made (swept detection; 0 for
    /// discrete, which finds pairs where the update ends).
    pub rest: f32,
}

/// Pairs the response marked for shattering this update, in pair order.
#[derive(Resource, Clone, Debug, Default)]
pub struct PendingShatters(pub Vec<ShatterPair>);

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

/// What bounds the bodies a shatter may make: the run's memory, the bodies
/// there are, and where a run that would outgrow it stops.
#[derive(SystemParam)]
struct Room<'w, 's> {
    budget: Res<'w, MemoryBudget>,
    bodies: Query<'w, 's, (), With<BodyId>>,
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
    settings: Res<SimulationSettings>,
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
    let Room {
        budget,
        bodies,
        mut fault,
    } = room;
    for entity in reentering.0.drain(..) {
        commands.entity(entity).despawn();
    }
    let count = settings.shatter_fragments;
    // Only an update that shatters can outgrow the memory.
    let shatters = pending.0.len() as u64;
    let after = || {
        (bodies.iter().len() as u64)
            .saturating_sub(2 * shatters)
            .saturating_add(shatters * u64::from(count))
    };
    if shatters > 0
        && let Some(limit) = budget.limit
        && let after = after()
        && after > limit.bodies()
    {
        // Stopped before the allocation that would fail.
        pending.0.clear();
        fault.stop(Fault::OutOfMemory { bodies: after, limit });
        return;
    }
    for pair in pending.0.drain(..) {
        for entity in pair.entities {
            commands.entity(entity).despawn();
        }
        let [a, b] = &pair.bodies;
        let mut made = fragments_for(a, b, &settings, BodyId(next_id.0));
        if pair.rest > 0.0 {
            move_on(&mut made, pair.rest);
        }
        next_id.0 += made.len() as u64;
        debug_assert!(
            made.iter().all(|f| !f.has_markers()),
            "fragments are interacting boxes: no markers to insert"
        );
        // A pair's fragments share one role (`fragments_for`); where it is
        // no adopter's (a self-gravitating cluster's), they carry it.
        debug_assert!(made.windows(2).all(|f| f[0].role == f[1].role));
        if made.first().is_some_and(|f| f.role.is_stored()) {
            commands.spawn_batch(made.into_iter().map(|f| (f.bundle(), f.role)));
        } else {
            commands.spawn_batch(made.into_iter().map(|f| f.bundle()));
        }
    }
    clock.finish();
}
