//! The events of a run, applied and to come: the scenario's, and those the
//! window's tools record (docs/design.md, "Events").

use bevy::prelude::*;

use super::apply::apply;
use crate::components::BodyState;
use crate::scenario::{Event, Generator, Scenario};
use crate::systems::{NextEventAt, UpdateCount};

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
    /// How [`Self::described`] starts for an event a tool recorded.
    pub const RECORDED: &str = "a recorded ";

    /// The event as messages name it: `events[3] (Remove at update 500)`,
    /// `a recorded Remove at update 500`.
    pub fn described(&self) -> String {
        let (kind, update) = (self.event.kind(), self.event.update());
        match self.place {
            Some(i) => format!("events[{i}] ({kind} at update {update})"),
            None => format!("{}{kind} at update {update}", Self::RECORDED),
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

/// The events still to come, as a snapshot holds them
/// ([`EventQueue::pending`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Pending {
    /// The events, counted from the snapshot's start.
    pub events: Vec<Event>,
    /// Those left out, each named with why the run skips it.
    pub left_out: Vec<String>,
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

    /// Drops the last event applied if a tool recorded it (one that was
    /// skipped: it did nothing, so a session need not hold it).
    pub fn forget_last_applied_recorded(&mut self) {
        if let Some(last) = self.done.checked_sub(1)
            && self.events[last].place.is_none()
        {
            self.events.remove(last);
            self.done = last;
        }
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
    /// from then, as a snapshot of `bodies` (sorted by id; `next_id` the
    /// next fresh id) holds them: a `Shell`'s `around` names its source by
    /// its place among `bodies`, and an event the run is certain to skip
    /// (its body is gone, ids are never used again; a planet's breakup) is
    /// left out, with why, so that the snapshot loads and continues as the
    /// run does.
    pub fn pending(&self, updates: u64, bodies: &[BodyState], next_id: u64) -> Pending {
        let mut pending = Pending::default();
        for queued in &self.events[self.done..] {
            let mut event = queued.event.at(queued.event.update().saturating_sub(updates));
            match self.as_in_snapshot(&mut event, bodies, next_id) {
                Ok(()) => pending.events.push(event),
                Err(why) => pending.left_out.push(format!("{}: {why}", queued.described())),
            }
        }
        pending
    }

    /// `event` as a snapshot of `bodies` holds it (see [`Self::pending`]),
    /// or why the run will skip it.
    fn as_in_snapshot(&self, event: &mut Event, bodies: &[BodyState], next_id: u64) -> Result<(), String> {
        let place = |id: u64| bodies.binary_search_by_key(&id, |b| b.id.0).ok();
        if let Event::Spawn(spawn) = event {
            for (j, generator) in spawn.generators.iter_mut().enumerate() {
                if let Generator::Shell(shell) = generator {
                    let id = self.around.get(shell.around).copied().unwrap_or(u64::MAX);
                    shell.around =
                        place(id).ok_or_else(|| format!("generators[{j}] (Shell) orbits body {id}, which is gone"))?;
                }
            }
            return Ok(());
        }
        let Some(id) = event.body() else {
            return Ok(());
        };
        match place(id) {
            Some(i) if matches!(event, Event::Breakup(_)) && !bodies[i].interacts => Err(format!(
                "body {id} does not interact (a planet): only interacting bodies break up"
            )),
            None if id < next_id => Err(format!(
                "there is no body {id} (it shattered, re-entered or was removed)"
            )),
            _ => Ok(()),
        }
    }

    /// Back to the state after `updates` updates and the scenario's events
    /// of that update, before any recorded there (a checkpoint's): the
    /// scenario's later events are to come again, and the recorded ones
    /// from then on are dropped (the window's rewind).
    pub fn rewind(&mut self, updates: u64) {
        self.events.retain(|q| q.place.is_some() || q.event.update() < updates);
        self.done = self.events.partition_point(|q| q.event.update() <= updates);
    }
}

/// Applies the events due after the updates run so far, in order, in
/// [`BetweenUpdates`](crate::systems::BetweenUpdates); counts those
/// skipped and keeps the first, with why, for the summary to name once.
pub fn apply_due_events(world: &mut World) {
    let updates = world.resource::<UpdateCount>().0;
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
