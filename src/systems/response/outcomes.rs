//! The response's outcomes: the shatters refused (the fragment floor, the
//! body budget, the ids) and every outcome written back.

use bevy::prelude::*;

use super::contact::{Motion, Outcome};
use super::matching::{ContactQuery, Matched};
use crate::components::BodyState;
use crate::physics::{box_volume, fragments_sound, smallest_fragment_edge};
use crate::resources::{NextBodyId, SimulationSettings};
use crate::systems::shatter::{PendingShatters, ShatterPair};

/// What a shatter may still make this update: the fragment floor, the body
/// budget and the ids, counted from `bodies` and `next_id` as shatters are
/// allowed (in the order the shatter stage hands ids out).
pub struct ShatterBudget<'a> {
    settings: &'a SimulationSettings,
    bodies: u64,
    next_id: NextBodyId,
}

impl<'a> ShatterBudget<'a> {
    /// The budget of an update that starts with `bodies` bodies and the
    /// next fresh id `next_id`.
    pub fn new(settings: &'a SimulationSettings, bodies: usize, next_id: NextBodyId) -> Self {
        Self {
            settings,
            bodies: bodies as u64,
            next_id,
        }
    }

    /// One body fewer (absorbed).
    pub fn absorbed(&mut self) {
        self.bodies = self.bodies.saturating_sub(1);
    }

    /// Whether `a` and `b` may shatter: not if their fragments would be
    /// below `min_fragment_size` or too light or small for a body
    /// ([`fragments_sound`]), make more bodies than `max_bodies`, or take
    /// an id past [`MAX_ID`](crate::resources::MAX_ID). If they may, the
    /// budget counts their fragments.
    pub fn allows(&mut self, a: &BodyState, b: &BodyState) -> bool {
        let settings = self.settings;
        let count = settings.shatter_fragments.max(2);
        let added = u64::from(count) - 2;
        let volume = box_volume(a.half_extents) + box_volume(b.half_extents);
        let edge = smallest_fragment_edge(volume, settings.fragment_sizes, count);
        let mass = f64::from(a.mass) + f64::from(b.mass);
        if edge < f64::from(settings.min_fragment_size)
            || !fragments_sound(volume, mass, settings.fragment_sizes, count)
            || self.bodies + added > settings.max_bodies
            || !self.next_id.has_room_for(u64::from(count))
        {
            return false;
        }
        self.bodies += added;
        self.next_id.0 += u64::from(count);
        true
    }
}

/// The budget ([`ShatterBudget`]) in pair order: turns the shatters it
/// does not allow into what the pair does when it may not shatter (a
/// bounce: `unshattered` gives it for the pair of that index). Returns the
/// number refused.
pub fn refuse_shatters(
    matched: &[Matched],
    outcomes: &mut [Outcome],
    settings: &SimulationSettings,
    bodies: usize,
    next_id: NextBodyId,
    unshattered: impl Fn(usize) -> Outcome,
) -> usize {
    let mut budget = ShatterBudget::new(settings, bodies, next_id);
    let mut refused = 0;
    for (index, ((_, [a, b]), outcome)) in matched.iter().zip(outcomes.iter_mut()).enumerate() {
        if *outcome == Outcome::Shatter && !budget.allows(a, b) {
            *outcome = unshattered(index);
            refused += 1;
        }
    }
    refused
}

/// Where a shattering pair's fragments are made (discrete detection):
/// where the bodies are, with no time left in the update.
fn shatter_pair((entities, states): &Matched) -> ShatterPair {
    ShatterPair {
        entities: *entities,
        bodies: *states,
        rest: 0.0,
    }
}

/// Writes the outcomes back: new motions into the bodies (without marking
/// them changed: see the components' change-detection rule), shatters into
/// `pending` (where [`shatter_pair`] places them). Returns the number of
/// bounces and separations.
pub(super) fn apply_outcomes(
    matched: &[Matched],
    outcomes: Vec<Outcome>,
    bodies: &mut ContactQuery,
    pending: &mut PendingShatters,
) -> usize {
    let mut responses = 0;
    for (pair, outcome) in matched.iter().zip(outcomes) {
        let entities = &pair.0;
        let motions = match outcome {
            Outcome::Ignore => continue,
            Outcome::Shatter => {
                pending.0.push(shatter_pair(pair));
                continue;
            }
            Outcome::Bounce(ma, mb) | Outcome::Separate(ma, mb) => [ma, mb],
        };
        responses += 1;
        for (entity, motion) in entities.iter().zip(motions) {
            if let Some(motion) = motion {
                write_motion(bodies, *entity, motion);
            }
        }
    }
    responses
}

/// Writes `motion` into the body `entity` (without marking it changed:
/// see the components' change-detection rule).
pub(super) fn write_motion(bodies: &mut ContactQuery, entity: Entity, motion: Motion) {
    if let Ok(mut body) = bodies.get_mut(entity) {
        body.position.bypass_change_detection().0 = motion.position;
        body.velocity.bypass_change_detection().0 = motion.velocity;
    }
}
