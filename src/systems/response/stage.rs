//! The response stage: bounce, push-back, separate, or mark for
//! shattering (docs/design.md, "Response").
//!
//! Pairs are taken in sorted order (with swept detection, in the order of
//! their first touch) and each interacting body takes part in at most one
//! response per update (a greedy matching); the rest wait for the next
//! update while they still overlap. Non-interacting bodies are never
//! changed by a response, so they may meet any number of bodies at once.
//! The matched pairs are disjoint, so their responses are computed in
//! parallel with the same result.

use bevy::math::DVec3;
use bevy::platform::collections::HashSet;
use bevy::prelude::*;

use super::contact::{ContactBody, Outcome, respond, touches};
use super::swept::{Meeting, contact_states, first_contact, respond_swept};
use crate::components::{
    Absorbs, BodyId, BodyState, GravityRole, HalfExtents, Immovable, Mass, Position, PreviousPosition, Spherical,
    Velocity,
};
use crate::execution::StageExecution;
use crate::resources::{CollisionDetection, NextBodyId, SimulationSettings};
use crate::systems::shatter::{PendingShatters, Reentering, ShatterPair, box_volume, smallest_fragment_edge};
use crate::systems::sweep::{OverlappingPairs, Pair};
use crate::systems::{SimulationSystems, SimulationUpdate, Stage};

/// Counts of what collisions did, for summaries and the HUD.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CollisionStats {
    /// Overlapping pairs found this update.
    pub pairs: usize,
    /// Pairs responded to this update (bounces and separations).
    pub responses: usize,
    /// Pairs that shattered this update.
    pub shatters: usize,
    /// Pairs that shattered since the start.
    pub shatters_total: u64,
    /// Pairs that met fast enough to shatter this update but bounced: their
    /// fragments would have been below `min_fragment_size`, there would
    /// have been more than `max_bodies` bodies, or a fragment's id would
    /// have passed [`MAX_ID`](crate::resources::MAX_ID).
    pub refused_shatters: usize,
    /// Refused shatters since the start.
    pub refused_total: u64,
    /// Bodies absorbed this update (re-entries: see [`Absorbs`]).
    pub reentries: usize,
    /// Bodies absorbed since the start.
    pub reentries_total: u64,
}

/// What absorbing bodies took since the start: the mass and momentum of
/// every body they absorbed, so that the bodies' totals and these still
/// add up to what the shatters and bounces keep (summed in f64 in the
/// order the bodies were absorbed).
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq)]
pub struct Absorbed {
    /// Mass absorbed.
    pub mass: f64,
    /// Momentum absorbed, `Σ m·v` at the touch.
    pub momentum: DVec3,
}

/// The floor, the budget and the ids: turns the shatters that would make
/// fragments below `min_fragment_size`, more bodies than `max_bodies`
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
        if edge < f64::from(settings.min_fragment_size)
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

/// Responds to [`OverlappingPairs`] in [`SimulationSystems::Response`].
pub struct ResponsePlugin;

impl Plugin for ResponsePlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<CollisionStats>()
            .init_resource::<Absorbed>()
            .add_systems(SimulationUpdate, respond_to_pairs.in_set(SimulationSystems::Response));
    }
}

/// A [`crate::components::BodyStateQuery`] that can move the body.
type ContactQuery<'w, 's> = Query<
    'w,
    's,
    (
        &'static BodyId,
        &'static mut Position,
        &'static PreviousPosition,
        &'static mut Velocity,
        &'static Mass,
        &'static HalfExtents,
        &'static GravityRole,
        Has<Immovable>,
        Has<Spherical>,
        Has<Absorbs>,
    ),
>;

/// A pair the matching accepted: its entities, and each body as the kernel
/// sees it and as a shatter would take it.
pub type Matched = ([Entity; 2], [BodyState; 2]);

fn body_state(query: &ContactQuery, entity: Entity) -> Option<BodyState> {
    query.get(entity).ok().map(BodyState::from_components)
}

/// Re-entries: every interacting body that touches an absorber (a ball
/// itself, not its bounding box's corners: [`touches`]), once, in pair
/// order, with its state; they take part in nothing else this update
/// (`busy` holds them).
fn find_reentries(pairs: &[Pair], bodies: &ContactQuery, busy: &mut HashSet<Entity>) -> Vec<(Entity, BodyState)> {
    let mut absorbed = Vec::new();
    for pair in pairs {
        let entities = [pair.entity_a, pair.entity_b];
        let (Some(a), Some(b)) = (body_state(bodies, entities[0]), body_state(bodies, entities[1])) else {
            continue;
        };
        if !(a.absorbs || b.absorbs) || !touches(&(&a).into(), &(&b).into()) {
            continue;
        }
        for (k, absorber) in [(1, a), (0, b)] {
            let other = if k == 0 { a } else { b };
            if absorber.absorbs && other.interacts && busy.insert(entities[k]) {
                absorbed.push((entities[k], other));
            }
        }
    }
    absorbed
}

/// The greedy matching: pairs in sorted order, each interacting body in at
/// most one of them; non-interacting bodies never get busy. Bodies already
/// in `busy` (absorbed) take part in none.
fn match_pairs(pairs: &[Pair], bodies: &ContactQuery, busy: &mut HashSet<Entity>) -> Vec<Matched> {
    let mut matched = Vec::new();
    for pair in pairs {
        let entities = [pair.entity_a, pair.entity_b];
        let (Some(a), Some(b)) = (body_state(bodies, entities[0]), body_state(bodies, entities[1])) else {
            continue;
        };
        let states = [a, b];
        let taken = |k: usize| states[k].interacts && busy.contains(&entities[k]);
        if (!a.interacts && !b.interacts) || a.absorbs || b.absorbs || taken(0) || taken(1) {
            continue;
        }
        for (entity, state) in entities.iter().zip(&states) {
            if state.interacts {
                busy.insert(*entity);
            }
        }
        matched.push((entities, states));
    }
    matched
}

/// What the swept matching hands on: the re-entries, the matched pairs
/// and when each met.
type SweptMatching = (Vec<(Entity, BodyState)>, Vec<Matched>, Vec<Meeting>);

/// Swept detection's matching: every pair's first touch ([`first_contact`],
/// split as `stage` says), then the pairs that touch in the order of that
/// touch (ties in pair order), each interacting body in at most one
/// response: absorbed by an absorber it meets (a re-entry), or matched
/// with the other body. Bodies in `busy` take part in none.
fn swept_matching(
    pairs: &[Pair],
    bodies: &ContactQuery,
    busy: &mut HashSet<Entity>,
    stage: StageExecution<'_>,
) -> SweptMatching {
    let candidates: Vec<Matched> = pairs
        .iter()
        .filter_map(|pair| {
            let entities = [pair.entity_a, pair.entity_b];
            Some((
                entities,
                [body_state(bodies, entities[0])?, body_state(bodies, entities[1])?],
            ))
        })
        .collect();
    let meetings: Vec<Option<Meeting>> = stage
        .map_chunks(candidates.as_slice(), |chunk: &[Matched]| {
            chunk
                .iter()
                .map(|(_, [a, b])| first_contact(&a.into(), &b.into()))
                .collect::<Vec<_>>()
        })
        .concat();
    let mut order: Vec<(f64, usize, Meeting)> = meetings
        .iter()
        .enumerate()
        .filter_map(|(index, meeting)| meeting.map(|m| (m.time(), index, m)))
        .collect();
    order.sort_unstable_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
    let (mut absorbed, mut matched, mut met) = (Vec::new(), Vec::new(), Vec::new());
    for (_, index, meeting) in order {
        let (entities, [a, b]) = candidates[index];
        if a.absorbs || b.absorbs {
            for (k, absorber) in [(1, a), (0, b)] {
                let other = if k == 0 { a } else { b };
                if absorber.absorbs && other.interacts && busy.insert(entities[k]) {
                    absorbed.push((entities[k], other));
                }
            }
            continue;
        }
        let states = [a, b];
        if (0..2).any(|k| states[k].interacts && busy.contains(&entities[k])) {
            continue;
        }
        for (entity, state) in entities.iter().zip(&states) {
            if state.interacts {
                busy.insert(*entity);
            }
        }
        matched.push((entities, states));
        met.push(meeting);
    }
    (absorbed, matched, met)
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
fn apply_outcomes(
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

#[expect(
    clippy::too_many_arguments,
    reason = "a system: the pairs, the bodies, and what limits and records their outcomes"
)]
fn respond_to_pairs(
    settings: Res<SimulationSettings>,
    mut stage: Stage,
    pairs: Res<OverlappingPairs>,
    mut pending: ResMut<PendingShatters>,
    mut reentering: ResMut<Reentering>,
    mut absorbed: ResMut<Absorbed>,
    mut stats: ResMut<CollisionStats>,
    next_id: Res<NextBodyId>,
    mut busy: Local<HashSet<Entity>>,
    absorbers: Query<(), With<Absorbs>>,
    mut bodies: ContactQuery,
) {
    let clock = stage.start(SimulationSystems::Response);
    pending.0.clear();
    reentering.0.clear();
    if !(settings.collisions && settings.collision_response) {
        *stats = CollisionStats {
            shatters_total: stats.shatters_total,
            refused_total: stats.refused_total,
            reentries_total: stats.reentries_total,
            ..CollisionStats::default()
        };
        return;
    }
    busy.clear();
    let dt = settings.time_step;
    let body_count = bodies.iter().len();
    let (reentries, matched, meetings) = if settings.collision_detection == CollisionDetection::Swept {
        swept_matching(&pairs.0, &bodies, &mut busy, clock.execution(body_count))
    } else {
        // Without an absorber (the thesis scene), no pass over the pairs for one.
        let reentries = if absorbers.is_empty() {
            Vec::new()
        } else {
            find_reentries(&pairs.0, &bodies, &mut busy)
        };
        let matched = match_pairs(&pairs.0, &bodies, &mut busy);
        (reentries, matched, Vec::new())
    };
    for (entity, body) in &reentries {
        let mass = f64::from(body.mass);
        absorbed.mass += mass;
        absorbed.momentum += body.velocity.as_dvec3() * mass;
        reentering.0.push(*entity);
    }
    // Fewer than two fragments cannot keep volume: then nothing shatters.
    let threshold = if settings.shatter_fragments >= 2 {
        settings.shatter_threshold
    } else {
        f32::INFINITY
    };
    let body_count = body_count - reentries.len();
    // One pair's outcome: by its meeting with swept detection, else by today's rule.
    let outcome = |index: usize, threshold: f32| {
        let (_, [a, b]) = &matched[index];
        let (a, b): (ContactBody, ContactBody) = (a.into(), b.into());
        match meetings.get(index) {
            Some(&meeting) => respond_swept(&a, &b, meeting, threshold, dt),
            None => respond(&a, &b, threshold, dt),
        }
    };
    let mut outcomes: Vec<Outcome> = clock
        .execution(body_count)
        .map_chunks(0..matched.len(), |range| {
            range.map(|index| outcome(index, threshold)).collect::<Vec<_>>()
        })
        .concat();
    let refused = refuse_shatters(&matched, &mut outcomes, &settings, body_count, *next_id, |index| {
        outcome(index, f32::INFINITY)
    });
    let responses = apply_outcomes(&matched, (outcomes, &meetings, dt), &mut bodies, &mut pending);
    *stats = CollisionStats {
        pairs: pairs.0.len(),
        responses,
        shatters: pending.0.len(),
        shatters_total: stats.shatters_total + pending.0.len() as u64,
        refused_shatters: refused,
        refused_total: stats.refused_total + refused as u64,
        reentries: reentries.len(),
        reentries_total: stats.reentries_total + reentries.len() as u64,
    };
    clock.finish();
}
