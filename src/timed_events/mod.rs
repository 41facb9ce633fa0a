//! Timed events (docs/design.md, "Events"): the scenario's `events` and
//! those the window's tools record, applied between updates through one
//! path, so that a recorded session replays exactly. The file format is
//! the scenario's (`scenario/events.rs`); this module keeps the run's
//! events in order ([`EventQueue`]) and applies them (`apply.rs`).

mod apply;
mod queue;

use bevy::prelude::*;

pub use apply::impactor;
pub use queue::{EventLog, EventQueue, Pending, Queued, apply_due_events};

use crate::components::BodyState;
use crate::resources::SimulationSettings;
use crate::scenario::{Scenario, check_start};
use crate::systems::BetweenUpdates;

/// Applies the due events in [`BetweenUpdates`].
pub struct EventsPlugin;

impl Plugin for EventsPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<EventQueue>()
            .init_resource::<EventLog>()
            .add_systems(BetweenUpdates, apply_due_events);
    }
}

/// Applies the events of update 0, which belong to the start, and checks
/// the start they leave as a scenario's own bodies are checked
/// ([`check_start`]): a `Spawn` of bodies at one point at update 0 is a
/// pile-up at the start, as the same bodies in `bodies` are. `Err`: what
/// is wrong, in words.
pub fn run_start_events(world: &mut World) -> Result<(), String> {
    crate::systems::run_due_events(world);
    if world.resource::<EventLog>().applied == 0 {
        return Ok(());
    }
    let settings = world.resource::<SimulationSettings>().clone();
    check_start(&BodyState::all_in(world), &settings).map_err(|e| format!("with the events of update 0 applied, {e}"))
}

/// Makes `scenario`'s events the run's, none applied yet (at a scene's
/// start, its update count at 0).
pub fn install_events(world: &mut World, scenario: &Scenario) {
    let queue = EventQueue::of(scenario);
    world.insert_resource(queue.next_at());
    world.insert_resource(queue);
    world.insert_resource(EventLog::default());
}

/// Records `event`, made by a tool at the update the run is at, and
/// applies it at once (it is due before the next update, so the state is
/// the one a replay reaches).
pub fn record_event(world: &mut World, event: crate::scenario::Event) {
    let mut queue = world.resource_mut::<EventQueue>();
    queue.record(event);
    let next = queue.next_at();
    world.insert_resource(next);
    crate::systems::run_due_events(world);
}
