//! The events of a run, applied and to come: the scenario's, and those the
//! window's tools record (docs/design.md, "Events").

use bevy::prelude::*;

use super::apply::apply;
use crate::scenario::{Event, Scenario};
use crate::systems::{NextEventAt, SimulationFault};

/// One event of the run.
#[derive(Clone, Debug, PartialEq)]
pub struct Queued {
    /// The event.
    pub event: Event,
    /// Its place in the scenario's `events`; `None` for one a tool
    /// recorded.
    pub place: Option<usize>,
}

impl Queued {
    /// The event as messages name it: `events[3] (Remove at update 500)`,
    /// `a recorded Remove at update 500`.
    pub fn described(&self) -> String {
        let (kind, update) = (self.event.kind(), self.event.update());
        match self.place {
            Some(i) => format!("events[{i}] ({kind} at update {update})"),
            None => format!("a recorded {kind} at update {update}"),
        }
    }
}

/// Every event of the run in the order they happen (by update; within one
/// update in file order, then as recorded), and how many have happened.
#[derive(Resource, Clone, Debug, Default)]
pub struct EventQueue {
    events: Vec<Queued>,
    /// How many of `events` have been applied or skipped.
    done: usize,
    /// The ids of the scenario's explicit bodies, by index (a Spawn's
    /// `Shell` orbits one).
    around: Vec<u64>,
}

/// What the events did so far.
#[derive(Resource, Clone, Debug, Default, PartialEq, Eq)]
pub struct EventLog {
    /// Events that happened.
    pub applied: u64,
    /// Events skipped (their body gone, or what they would make refused).
    pub skipped: u64,
    /// The first skipped event and why, said once.
    pub first_skipped: Option<String>,
    /// The last skipped event and why (the window says it when a tool's
    /// event is skipped).
    pub last_skipped: Option<String>,
}

impl EventQueue {
    /// The events of `scenario`, none applied yet.
    pub fn of(scenario: &Scenario) -> Self {
        let mut events: Vec<Queued> = scenario
            .events
            .iter()
            .enumerate()
            .map(|(i, event)| Queued {
                event: event.clone(),
                place: Some(i),
            })
            .collect();
        // Stable: file order within one update.
        events.sort_by_key(|q| q.event.update());
        Self {
            events,
            done: 0,
            around: scenario.explicit_bodies().map(|(id, _)| id).collect(),
        }
    }

    /// When the next event is due (`u64::MAX`: none).
    pub fn next_at(&self) -> NextEventAt {
        NextEventAt(self.events.get(self.done).map_or(u64::MAX, |q| q.event.update()))
    }

    /// Records `event` (a tool's), after every event of its update or
    /// before it.
    pub fn record(&mut self, event: Event) {
        let at = self.events[self.done..].partition_point(|q| q.event.update() <= event.update()) + self.done;
        self.events.insert(at, Queued { event, place: None });
    }

    /// Every event, applied and to come, in the order they happen.
    pub fn all(&self) -> impl Iterator<Item = &Queued> {
        self.events.iter()
    }

    /// `scenario` (the run's start) with every event of the run, in the
    /// order they happen.
    pub fn session(&self, scenario: &Scenario) -> Scenario {
        Scenario {
            events: self.events.iter().map(|q| q.event.clone()).collect(),
            ..scenario.clone()
        }
    }

    /// The events still to come after `updates` updates, each counted
    /// from then (what a snapshot taken then holds).
    pub fn pending(&self, updates: u64) -> Vec<Event> {
        self.events[self.done..]
            .iter()
            .map(|q| q.event.at(q.event.update().saturating_sub(updates)))
            .collect()
    }

    /// Back to the state after `updates` updates, before that update's
    /// events: the scenario's events from then on are to come again, and
    /// recorded ones from then on are dropped (the window's rewind).
    pub fn rewind(&mut self, updates: u64) {
        self.events.retain(|q| q.place.is_some() || q.event.update() < updates);
        self.done = self.events.partition_point(|q| q.event.update() < updates);
    }
}

/// Applies the events due after the updates run so far, in order, in
/// [`BetweenUpdates`](crate::systems::BetweenUpdates); counts those
/// skipped and keeps the first, with why, for the summary to name once.
pub fn apply_due_events(world: &mut World) {
    let updates = world.resource::<SimulationFault>().updates;
    let around = world.resource::<EventQueue>().around.clone();
    loop {
        let queue = world.resource::<EventQueue>();
        let Some(next) = queue
            .events
            .get(queue.done)
            .filter(|q| q.event.update() <= updates)
            .cloned()
        else {
            break;
        };
        let result = apply(world, &next.event, &around);
        world.resource_mut::<EventQueue>().done += 1;
        let mut log = world.resource_mut::<EventLog>();
        match result {
            Ok(()) => log.applied += 1,
            Err(why) => {
                log.skipped += 1;
                let message = format!("{} was skipped: {why}", next.described());
                if log.first_skipped.is_none() {
                    log.first_skipped = Some(message.clone());
                }
                log.last_skipped = Some(message);
            }
        }
    }
    let next = world.resource::<EventQueue>().next_at();
    world.insert_resource(next);
}
