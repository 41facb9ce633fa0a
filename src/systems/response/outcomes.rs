//! The response's outcomes: the shatters refused (the fragment floor, the
//! body budget, the ids) and every outcome written back.

use bevy::prelude::*;

use super::contact::Outcome;
use super::matching::{ContactQuery, Matched};
use super::swept::{Meeting, contact_states};
use crate::physics::{box_volume, fragments_sound, smallest_fragment_edge};
use crate::resources::{NextBodyId, SimulationSettings};
use crate::systems::shatter::{PendingShatters, ShatterPair};

/// The floor, the budget and the ids: turns the shatters that would make
/// fragments below `min_fragment_size` or too light or small for a body
/// ([`fragments_sound`]), more bodies than `max_bodies`
/// (counting from `bodies`), or an id past [`MAX_ID`](crate::resources::MAX_ID) (counting from
/// `next_id`) — in pair order, as the shatter stage hands ids out — into
/// what the pair does when it may not shatter (a bounce: `unshattered`
/// gives it for the pair of that index). Returns the number refused.
pub fn refuse_shatters(
    matched: &[Matched],
    outcomes: &mut [Outcome],
    settings: &SimulationSettings,
    bodies: usize,
    next_id: NextBodyId,
    unshattered: impl Fn(usize) -> Outcome,
) -> usize {
    let count = settings.shatter_fragments.max(2);
    let added = u64::from(count) - 2;
    let mut bodies = bodies as u64;
    let mut next_id = next_id;
    let mut refused = 0;
    for (index, ((_, [a, b]), outcome)) in matched.iter().zip(outcomes.iter_mut()).enumerate() {
        if *outcome != Outcome::Shatter {
            continue;
        }
        let volume = box_volume(a.half_extents) + box_volume(b.half_extents);
        let edge = smallest_fragment_edge(volume, settings.fragment_sizes, count);
        let mass = f64::from(a.mass) + f64::from(b.mass);
        if edge < f64::from(settings.min_fragment_size)
            || !fragments_sound(volume, mass, settings.fragment_sizes, count)
            || bodies + added > settings.max_bodies
            || !next_id.has_room_for(u64::from(count))
        {
            *outcome = unshattered(index);
            refused += 1;
        } else {
            bodies += added;
            next_id.0 += u64::from(count);
        }
    }
    refused
}

/// Where a shattering pair's fragments are made: with swept detection (a
/// meeting for each pair), the bodies where they met and the time left for
/// the fragments to move on; else where they are, with none left.
fn shatter_pair(index: usize, (entities, states): &Matched, meetings: &[Meeting], dt: f32) -> ShatterPair {
    let Some(&meeting) = meetings.get(index) else {
        return ShatterPair {
            entities: *entities,
            bodies: *states,
            rest: 0.0,
        };
    };
    let ([pa, pb], rest) = contact_states(&(&states[0]).into(), &(&states[1]).into(), meeting, dt);
    let mut bodies = *states;
    (bodies[0].position, bodies[1].position) = (pa, pb);
    ShatterPair {
        entities: *entities,
        bodies,
        rest,
    }
}

/// Writes the outcomes back: new motions into the bodies (without marking
/// them changed: see the components' change-detection rule), shatters into
/// `pending` (where [`shatter_pair`] places them). Returns the number of
/// bounces and separations.
pub(super) fn apply_outcomes(
    matched: &[Matched],
    (outcomes, meetings, dt): (Vec<Outcome>, &[Meeting], f32),
    bodies: &mut ContactQuery,
    pending: &mut PendingShatters,
) -> usize {
    let mut responses = 0;
    for (index, (pair, outcome)) in matched.iter().zip(outcomes).enumerate() {
        let entities = &pair.0;
        let motions = match outcome {
            Outcome::Ignore => continue,
            Outcome::Shatter => {
                pending.0.push(shatter_pair(index, pair, meetings, dt));
                continue;
            }
            Outcome::Bounce(ma, mb) | Outcome::Separate(ma, mb) => [ma, mb],
        };
        responses += 1;
        for (entity, motion) in entities.iter().zip(motions) {
            if let (Some(motion), Ok((_, mut position, _, mut velocity, ..))) = (motion, bodies.get_mut(*entity)) {
                position.bypass_change_detection().0 = motion.position;
                velocity.bypass_change_detection().0 = motion.velocity;
            }
        }
    }
    responses
}
