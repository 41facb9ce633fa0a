//! The response's matching: which overlapping pairs it takes this update,
//! each interacting body in at most one (in pair order, or with swept
//! detection in the order of their first touch), and which bodies touch an
//! absorber.

use bevy::platform::collections::HashSet;
use bevy::prelude::*;

use super::contact::touches;
use super::swept::{Meeting, first_contact};
use crate::components::{
    Absorbs, BodyId, BodyState, GravityRole, HalfExtents, Immovable, Mass, Position, PreviousPosition, Spherical,
    Velocity,
};
use crate::execution::StageExecution;
use crate::systems::sweep::Pair;

/// A [`crate::components::BodyStateQuery`] that can move the body.
pub(super) type ContactQuery<'w, 's> = Query<
    'w,
    's,
    (
        &'static BodyId,
        &'static mut Position,
        &'static PreviousPosition,
        &'static mut Velocity,
        &'static Mass,
        &'static HalfExtents,
        Option<&'static GravityRole>,
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
pub(super) fn find_reentries(
    pairs: &[Pair],
    bodies: &ContactQuery,
    busy: &mut HashSet<Entity>,
) -> Vec<(Entity, BodyState)> {
    let mut absorbed = Vec::new();
    for pair in pairs {
        let entities = [pair.entity_a, pair.entity_b];
        let (Some(a), Some(b)) = (body_state(bodies, entities[0]), body_state(bodies, entities[1])) else {
            continue;
        };
        if (a.absorbs || b.absorbs) && touches(&(&a).into(), &(&b).into()) {
            absorb(entities, [a, b], busy, &mut absorbed);
        }
    }
    absorbed
}

/// A pair with an absorber that touches: its interacting body not yet
/// busy is absorbed (pushed onto `absorbed` with its state) and busy.
fn absorb(
    entities: [Entity; 2],
    [a, b]: [BodyState; 2],
    busy: &mut HashSet<Entity>,
    absorbed: &mut Vec<(Entity, BodyState)>,
) {
    for (k, absorber) in [(1, a), (0, b)] {
        let other = if k == 0 { a } else { b };
        if absorber.absorbs && other.interacts && busy.insert(entities[k]) {
            absorbed.push((entities[k], other));
        }
    }
}

/// Takes a pair for a response unless one of its interacting bodies is
/// busy already; its interacting bodies are busy then (non-interacting
/// ones never are). Whether it was taken.
fn take_pair(entities: [Entity; 2], states: &[BodyState; 2], busy: &mut HashSet<Entity>) -> bool {
    if (0..2).any(|k| states[k].interacts && busy.contains(&entities[k])) {
        return false;
    }
    for (entity, state) in entities.iter().zip(states) {
        if state.interacts {
            busy.insert(*entity);
        }
    }
    true
}

/// The greedy matching: pairs in sorted order, each interacting body in at
/// most one of them; non-interacting bodies never get busy. Bodies already
/// in `busy` (absorbed) take part in none.
pub(super) fn match_pairs(pairs: &[Pair], bodies: &ContactQuery, busy: &mut HashSet<Entity>) -> Vec<Matched> {
    let mut matched = Vec::new();
    for pair in pairs {
        let entities = [pair.entity_a, pair.entity_b];
        let (Some(a), Some(b)) = (body_state(bodies, entities[0]), body_state(bodies, entities[1])) else {
            continue;
        };
        let states = [a, b];
        if (!a.interacts && !b.interacts) || a.absorbs || b.absorbs || !take_pair(entities, &states, busy) {
            continue;
        }
        matched.push((entities, states));
    }
    matched
}

/// What the swept matching hands on: the re-entries, the matched pairs
/// and when each met.
pub(super) type SweptMatching = (Vec<(Entity, BodyState)>, Vec<Matched>, Vec<Meeting>);

/// Swept detection's matching: every pair's first touch ([`first_contact`],
/// split as `stage` says), then the pairs that touch in the order of that
/// touch (ties in pair order), each interacting body in at most one
/// response: absorbed by an absorber it meets (a re-entry), or matched
/// with the other body. Bodies in `busy` take part in none.
pub(super) fn swept_matching(
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
            absorb(entities, [a, b], busy, &mut absorbed);
            continue;
        }
        if !take_pair(entities, &[a, b], busy) {
            continue;
        }
        matched.push((entities, [a, b]));
        met.push(meeting);
    }
    (absorbed, matched, met)
}
