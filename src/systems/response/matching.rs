//! Discrete detection's matching: which overlapping pairs the response
//! takes this update, each interacting body in at most one, in pair order,
//! and which bodies touch an absorber.

use bevy::platform::collections::HashSet;
use bevy::prelude::*;

use super::contact::touches;
use crate::components::{BodyData, BodyState};
use crate::systems::sweep::Pair;

/// Every body, as one that the response can move.
pub(super) type ContactQuery<'w, 's> = Query<'w, 's, BodyData>;

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
