//! Putting bodies into a world: all at once, or a batch at a time so that a
//! million are never held twice; either way the same world, and the next
//! fresh id past them.

use bevy::prelude::*;

use crate::components::{BodyState, insert_markers, spawn_states, spawn_with_roles};
use crate::resources::NextBodyId;

/// Spawns `bodies` (ids must be unique and unused) and sets the next fresh
/// id past the highest; returns that id.
pub fn spawn_bodies(world: &mut World, bodies: &[BodyState]) -> u64 {
    let next = next_fresh_id(bodies);
    spawn_states(world, bodies);
    world.insert_resource(NextBodyId(next));
    next
}

/// The next fresh id: past the highest of `bodies`.
fn next_fresh_id(bodies: &[BodyState]) -> u64 {
    bodies.iter().map(|b| b.id.0 + 1).max().unwrap_or(0)
}

/// Bodies moved into the world at a time by [`spawn_owned_bodies`].
const SPAWN_BATCH: usize = 1 << 16;

/// Spawns `bodies` as [`spawn_bodies`] does, handing their memory back a
/// batch at a time as they move into the world, so that a million bodies
/// are never held twice (64 bytes a body). The world comes out the same:
/// every body spawned in order first (with its role where it is no
/// adopter: [`spawn_with_roles`], a batch at a time), then the markers of
/// non-interacting bodies, balls and absorbers inserted in order (each moves
/// its body to another table, and the last row of the first into its
/// place), as [`spawn_states`] does in one call.
pub fn spawn_owned_bodies(world: &mut World, mut bodies: Vec<BodyState>) -> u64 {
    let next = next_fresh_id(&bodies);
    let mut marked = Vec::new();
    // The first bodies last, so that each batch comes off the end.
    bodies.reverse();
    while !bodies.is_empty() {
        let mut batch = bodies.split_off(bodies.len().saturating_sub(SPAWN_BATCH));
        batch.reverse();
        let entities = spawn_with_roles(world, &batch);
        marked.extend(
            entities
                .into_iter()
                .zip(&batch)
                .filter(|(_, body)| body.has_markers())
                .map(|(entity, &body)| (entity, body)),
        );
        bodies.shrink_to_fit();
    }
    for (entity, body) in marked {
        insert_markers(world, entity, &body);
    }
    // After the bodies, as in `spawn_bodies`: in a world that does not have
    // the resource yet, inserting it makes an entity too, and the
    // archetypes must come in the same order.
    world.insert_resource(NextBodyId(next));
    next
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::components::{Absorbs, BodyId, GravityRole, NonInteracting, Spherical};

    /// Bodies moved into the world in batches make the same world as in
    /// one call, past one batch and with balls, absorbers, non-interacting
    /// colliders and every gravity role among them:
    /// the same bodies in the same tables in the same order, so that sums
    /// in query order (the timeline's totals) keep their bits. Only the
    /// bodies that are no adopters store their role, and every role reads
    /// back as given.
    #[test]
    fn bodies_spawned_in_batches_make_the_same_world() {
        let role = |k: u64| match k % 1_000 {
            1 => GravityRole::Source,
            2 => GravityRole::SourceAndAdopter,
            3 => GravityRole::Inert,
            _ => GravityRole::Adopter,
        };
        let bodies: Vec<BodyState> = (0..SPAWN_BATCH as u64 + 4_500)
            .map(|k| BodyState {
                spherical: k % 9_001 == 5,
                absorbs: k == 70_000,
                interacts: k != 70_000 && k % 7_919 != 3,
                ..BodyState::new_box(
                    BodyId(k * 3 + 1),
                    Vec3::new(k as f32, 0.5 * k as f32, -(k as f32)),
                    Vec3::new(1.0 / (k + 1) as f32, 0.25, k as f32 * 1e-3),
                    1.0 + (k % 17) as f32,
                    Vec3::splat(0.5),
                    role(k),
                    true,
                )
            })
            .collect();
        let listed = |world: &mut World| -> Vec<(u64, bool, bool, bool, Option<GravityRole>)> {
            world
                .query::<(
                    &BodyId,
                    Has<Spherical>,
                    Has<Absorbs>,
                    Has<NonInteracting>,
                    Option<&GravityRole>,
                )>()
                .iter(world)
                .map(|(id, ball, absorber, non_interacting, role)| {
                    (id.0, ball, absorber, non_interacting, role.copied())
                })
                .collect()
        };
        let (mut whole, mut batched) = (World::new(), World::new());
        assert_eq!(
            spawn_bodies(&mut whole, &bodies),
            spawn_owned_bodies(&mut batched, bodies.clone())
        );
        let order = listed(&mut whole);
        assert!(order.iter().any(|&(_, ball, ..)| ball) && order.iter().any(|&(_, _, absorber, ..)| absorber));
        assert!(
            order
                .iter()
                .filter(|&&(.., non_interacting, _)| non_interacting)
                .count()
                > 2
        );
        for &(id, .., stored) in &order {
            let given = role((id - 1) / 3);
            assert_eq!(GravityRole::of(stored.as_ref()), given, "body {id}");
            assert_eq!(stored.is_some(), given != GravityRole::Adopter, "body {id}");
        }
        assert_eq!(
            order.iter().filter(|&&(.., stored)| stored.is_some()).count(),
            bodies.iter().filter(|b| b.role != GravityRole::Adopter).count()
        );
        assert!(
            order.windows(2).any(|pair| pair[0].0 > pair[1].0),
            "the markers moved rows out of id order"
        );
        assert_eq!(listed(&mut batched), order);
    }
}
