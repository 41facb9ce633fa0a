//! The checks of a scenario's events that span fields (the parser has
//! checked each value): a Spawn with something to spawn, its bodies' shapes
//! and shells, a direction that is one, and the bodies events name where
//! the file already tells whether they exist (docs/design.md, "Events").

use std::collections::HashMap;

use super::contents::Scenario;
use super::events::{Event, Spawn};
use super::field_checks::MAX_BODIES;
use super::format::{Body, Generator};
use super::load::shape_problem;
use crate::input::InputError;

impl Scenario {
    /// Checks every event; the first problem names `events[i].field`.
    pub(super) fn check_events(&self) -> Result<(), InputError> {
        if self.events.is_empty() {
            return Ok(());
        }
        let explicit: HashMap<u64, &Body> = self.explicit_bodies().collect();
        let mut spawned: u64 = 0;
        for (i, event) in self.events.iter().enumerate() {
            let problem = match event {
                Event::Spawn(spawn) => {
                    spawned = spawned.saturating_add(spawn_count(spawn));
                    self.spawn_problem(spawn)
                }
                Event::Fire(fire) if fire.from == Some([0.0; 3]) => Some((
                    "from".to_owned(),
                    "must not be (0, 0, 0): it is the direction the impactor comes from".to_owned(),
                )),
                _ => None,
            };
            let problem = problem.or_else(|| {
                let id = event.body()?;
                let field = if matches!(event, Event::Fire(_)) {
                    "target"
                } else {
                    "body"
                };
                self.body_problem(id, &explicit, matches!(event, Event::Breakup(_)))
                    .map(|p| (field.to_owned(), p))
            });
            if let Some((field, problem)) = problem {
                return Err(InputError::new(
                    &self.origin,
                    format!("field `events[{i}].{field}`: {problem}"),
                ));
            }
        }
        let total = self.body_count().saturating_add(spawned);
        // Past the bound without spawns, the generators' check says so.
        if spawned > 0 && total > MAX_BODIES && self.body_count() <= MAX_BODIES {
            return Err(InputError::new(
                &self.origin,
                format!(
                    "field `events`: {total} bodies in all, with those the events spawn, would not fit in memory (at \
                     most {MAX_BODIES})"
                ),
            ));
        }
        Ok(())
    }

    /// What is wrong with an event naming body `id`: an id below `next_id`
    /// that no body has at the start (such ids are never handed out
    /// again), or, for a breakup, a body there that does not interact.
    /// `explicit`: the explicit bodies by id.
    fn body_problem(&self, id: u64, explicit: &HashMap<u64, &Body>, breaks_up: bool) -> Option<String> {
        let first_generated = self.first_generated_id();
        let interacts = match explicit.get(&id) {
            Some(body) => Some(body.interacts),
            None if id >= first_generated => self.generator_of(id - first_generated).map(|t| t.interacts),
            None => None,
        };
        match interacts {
            Some(interacts) => (breaks_up && !interacts)
                .then(|| format!("body {id} does not interact (a planet): only interacting bodies break up")),
            None => (id < self.next_id()).then(|| {
                format!(
                    "there is no body {id} at the start, and no body will get that id (fresh ids start at {})",
                    self.next_id()
                )
            }),
        }
    }

    /// What the generated body at `offset` (from the first generated id) is
    /// made of.
    fn generator_of(&self, mut offset: u64) -> Option<&super::format::Template> {
        for generator in &self.generators {
            if offset < generator.count() {
                return Some(generator.template());
            }
            offset -= generator.count();
        }
        None
    }

    /// A Spawn's problem: nothing to spawn, an `id` given, a body's shape,
    /// a shell's radii or source; the field (below the event) and what.
    fn spawn_problem(&self, spawn: &Spawn) -> Option<(String, String)> {
        if spawn.bodies.is_empty() && spawn.generators.is_empty() {
            return Some((
                "bodies".to_owned(),
                "a Spawn needs at least one body or generator".to_owned(),
            ));
        }
        for (j, body) in spawn.bodies.iter().enumerate() {
            if body.id.is_some() {
                return Some((
                    format!("bodies[{j}].id"),
                    "a spawned body gets a fresh id: leave out `id`".to_owned(),
                ));
            }
            if let Some((field, problem)) = shape_problem(body) {
                return Some((format!("bodies[{j}].{field}"), problem.to_owned()));
            }
        }
        for (j, generator) in spawn.generators.iter().enumerate() {
            if let Generator::Shell(shell) = generator
                && let Err((field, problem)) = self.check_shell(shell)
            {
                return Some((format!("generators[{j}].{field}"), problem));
            }
        }
        None
    }
}

/// Bodies a Spawn makes.
fn spawn_count(spawn: &Spawn) -> u64 {
    spawn
        .generators
        .iter()
        .map(Generator::count)
        .fold(spawn.bodies.len() as u64, u64::saturating_add)
}
