//! The response's outcomes: the shatters allowed (their fragments made) or
//! refused (the fragment floor, the body budget, the ids), and every
//! outcome written back.

use bevy::prelude::*;

use super::contact::{Motion, Outcome};
use super::matching::{ContactQuery, Matched};
use crate::components::{BodyId, BodyState};
use crate::physics::{box_volume, fragments_for, fragments_sound, smallest_fragment_edge};
use crate::resources::{NextBodyId, SimulationSettings};
use crate::systems::shatter::PendingShatters;

/// What a shatter may still make this update: the fragment floor, the body
/// budget, the ids and the memory, counted from `bodies` and `next_id` as
/// shatters are allowed (in pair order, which is the order of the
/// fragments' ids).
pub struct ShatterBudget<'a> {
    settings: &'a SimulationSettings,
    bodies: u64,
    next_id: NextBodyId,
    /// The most bodies the run's memory holds, if a limit is known.
    memory: Option<u64>,
    /// The bodies the update would have had when a shatter passed
    /// `memory`: then it makes no more fragments, and the run stops.
    outgrown: Option<u64>,
}

impl<'a> ShatterBudget<'a> {
    /// The budget of an update that starts with `bodies` bodies and the
    /// next fresh id `next_id`, in memory that holds at most `memory`
    /// bodies.
    pub fn new(settings: &'a SimulationSettings, bodies: usize, next_id: NextBodyId, memory: Option<u64>) -> Self {
        Self {
            settings,
            bodies: bodies as u64,
            next_id,
            memory,
            outgrown: None,
        }
    }

    /// The bodies the update would have had past the memory, if a shatter
    /// would have outgrown it (the fragments are not made).
    pub fn outgrown(&self) -> Option<u64> {
        self.outgrown
    }

    /// One body fewer (absorbed).
    pub fn absorbed(&mut self) {
        self.bodies = self.bodies.saturating_sub(1);
    }

    /// The fragments of `a` and `b` where they meet, with the next fresh
    /// ids, if they may shatter ([`Self::allows`]); the budget counts them.
    pub fn shatter(&mut self, a: &BodyState, b: &BodyState) -> Option<Vec<BodyState>> {
        if self.outgrown.is_some() || !self.allows(a, b) {
            return None;
        }
        // Counted as `count` bodies (the power law may make fewer).
        let after = self.bodies + u64::from(self.settings.shatter_fragments.max(2)) - 2;
        if self.memory.is_some_and(|most| after > most) {
            // Stopped before the allocation that would fail.
            self.outgrown = Some(after);
            return None;
        }
        let made = fragments_for(a, b, self.settings, BodyId(self.next_id.0));
        self.bodies = after;
        self.next_id.0 += made.len() as u64;
        Some(made)
    }

    /// The next fresh id.
    pub fn next_id(&self) -> NextBodyId {
        self.next_id
    }

    /// The fresh ids handed out since the next was `first`.
    pub fn ids_since(&self, first: NextBodyId) -> u64 {
        self.next_id.0 - first.0
    }

    /// Whether `a` and `b` may shatter: not if their fragments would be
    /// below `min_fragment_size` or too light or small for a body
    /// ([`fragments_sound`]), make more bodies than `max_bodies`, or take
    /// an id past [`MAX_ID`](crate::resources::MAX_ID).
    fn allows(&self, a: &BodyState, b: &BodyState) -> bool {
        let settings = self.settings;
        let count = settings.shatter_fragments.max(2);
        let added = u64::from(count) - 2;
        let volume = box_volume(a.half_extents) + box_volume(b.half_extents);
        let edge = smallest_fragment_edge(volume, settings.fragment_sizes, count);
        let mass = f64::from(a.mass) + f64::from(b.mass);
        edge >= f64::from(settings.min_fragment_size)
            && fragments_sound(volume, mass, settings.fragment_sizes, count)
            && self.bodies + added <= settings.max_bodies
            && self.next_id.has_room_for(u64::from(count))
    }
}

/// The budget ([`ShatterBudget`]) in pair order: the shatters it allows
/// get their fragments in `pending`, the ones it does not turn into what
/// the pair does when it may not shatter (a bounce: `unshattered` gives it
/// for the pair of that index). Returns the number refused.
pub fn shatter_or_refuse(
    matched: &[Matched],
    outcomes: &mut [Outcome],
    mut budget: ShatterBudget<'_>,
    pending: &mut PendingShatters,
    unshattered: impl Fn(usize) -> Outcome,
) -> usize {
    let first = budget.next_id();
    let mut refused = 0;
    for (index, ((_, [a, b]), outcome)) in matched.iter().zip(outcomes.iter_mut()).enumerate() {
        if *outcome == Outcome::Shatter {
            match budget.shatter(a, b) {
                Some(made) => pending.fragments.extend(made),
                // Past the memory: left a shatter, and the run stops.
                None if budget.outgrown().is_some() => {}
                None => {
                    *outcome = unshattered(index);
                    refused += 1;
                }
            }
        }
    }
    pending.ids = budget.ids_since(first);
    pending.outgrown = budget.outgrown();
    refused
}

/// Writes the outcomes back: new motions into the bodies (without marking
/// them changed: see the components' change-detection rule), the shattered
/// bodies into `pending`. Returns the number of bounces and separations.
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
                pending.pairs += 1;
                pending.shattered.extend(entities);
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
