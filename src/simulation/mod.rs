//! A simulation without a window: a Bevy app (MinimalPlugins) holding the
//! bodies, stepped on demand. The command line, tests and benchmarks use it.

mod headless_run;
mod spawn;
mod timeline;

use bevy::prelude::*;
pub use headless_run::{HeadlessError, HeadlessReport, Outputs, run_headless};
pub use spawn::{spawn_bodies, spawn_owned_bodies};
pub use timeline::{Timeline, TimelineRow, row_updates};

use crate::components::{BodyId, BodyState, BodyStateQuery, Mass, Position, Velocity};
use crate::execution::Execution;
use crate::input::InputError;
use crate::physics::Totals;
use crate::record::StateHash;
use crate::resources::{NextBodyId, SimulationSettings};
use crate::scenario::{Event, Scenario};
use crate::systems::{
    Absorbed, CollisionStats, SimulationFault, SimulationPlugins, SortedBoxes, StageTimings, UpdateCount,
    first_non_finite, run_updates,
};
use crate::timed_events::{
    EventLog, EventQueue, EventsPlugin, Pending, install_events, record_event, run_start_events,
};

/// Whether `scenario` has events at update 0, which belong to its start.
fn starts_with_events(scenario: &Scenario) -> bool {
    scenario.events.iter().any(|e| e.update() == 0)
}

/// A headless simulation.
pub struct Simulation {
    app: App,
}

impl Simulation {
    /// A simulation of `bodies` (ids must be unique) with `settings`.
    pub fn new(bodies: &[BodyState], settings: SimulationSettings, execution: Execution) -> Self {
        let mut sim = Self::without_bodies(settings, execution);
        spawn_bodies(sim.app.world_mut(), bodies);
        sim
    }

    /// The app with no bodies yet.
    fn without_bodies(settings: SimulationSettings, execution: Execution) -> Self {
        let mut app = App::new();
        app.add_plugins((MinimalPlugins, SimulationPlugins, EventsPlugin))
            .insert_resource(settings)
            .insert_resource(execution);
        app.finish();
        app.cleanup();
        Self { app }
    }

    /// The bodies and settings of `scenario`; fresh ids continue from its
    /// `next_id` (a snapshot's).
    pub fn from_scenario(scenario: &Scenario, execution: Execution) -> Result<Self, InputError> {
        let bodies = scenario.bodies()?;
        let mut sim = Self::without_bodies(scenario.settings(), execution);
        spawn_owned_bodies(sim.app.world_mut(), bodies);
        let mut next = sim.app.world_mut().resource_mut::<NextBodyId>();
        next.0 = next.0.max(scenario.next_id());
        install_events(sim.app.world_mut(), scenario);
        // The events of update 0 belong to the start (as the window applies
        // them when it makes the scene), and the start they leave is
        // checked as the scenario's own bodies are.
        run_start_events(sim.app.world_mut()).map_err(|e| InputError::new(&scenario.origin, e))?;
        Ok(sim)
    }

    /// Checks the start of `scenario` as a run makes it: its bodies, and
    /// where it has events at update 0, the state they leave (a `Spawn` of
    /// bodies at one point is a pile-up at the start). Cheap where it has
    /// none: the bodies alone are made.
    pub fn check_start(scenario: &Scenario) -> Result<(), InputError> {
        if starts_with_events(scenario) {
            Self::check_start_events(scenario)
        } else {
            scenario.bodies().map(drop)
        }
    }

    /// Checks the state the events of update 0 leave, where `scenario` has
    /// any, as [`check_start`](Self::check_start) does; nothing where it
    /// has none (for a scenario whose bodies are known to be sound: a
    /// running scene's session).
    pub fn check_start_events(scenario: &Scenario) -> Result<(), InputError> {
        if !starts_with_events(scenario) {
            return Ok(());
        }
        let execution = Execution::all_cores(crate::execution::ExecutionMode::Parallel)
            .map_err(|e| InputError::new(&scenario.origin, e.to_string()))?;
        Self::from_scenario(scenario, execution).map(drop)
    }

    /// Updates run so far.
    pub fn updates(&self) -> u64 {
        self.app.world().resource::<UpdateCount>().0
    }

    /// What the events did so far.
    pub fn event_log(&self) -> &EventLog {
        self.app.world().resource::<EventLog>()
    }

    /// The events still to come, counted from now (a snapshot's).
    pub fn pending_events(&self, bodies: &[BodyState]) -> Pending {
        self.app
            .world()
            .resource::<EventQueue>()
            .pending(self.updates(), bodies, self.next_body_id())
    }

    /// `scenario`, the one this run started from, with every event of the
    /// run (its own and those recorded): replayed, it reaches this run's
    /// states.
    pub fn session(&self, scenario: &Scenario) -> Scenario {
        self.app.world().resource::<EventQueue>().session(scenario)
    }

    /// Records `event` at the update the run is at and applies it at once,
    /// as the window's tools do.
    pub fn record_event(&mut self, event: Event) {
        record_event(self.app.world_mut(), event);
    }

    /// The id the next fresh body (a fragment) will get.
    pub fn next_body_id(&self) -> u64 {
        self.app.world().resource::<NextBodyId>().0
    }

    /// The physics settings in force.
    pub fn settings(&self) -> &SimulationSettings {
        self.app.world().resource::<SimulationSettings>()
    }

    /// Runs `updates` simulation updates, fewer if the run stops at a
    /// fault (see [`fault`](Self::fault)).
    pub fn step(&mut self, updates: u64) {
        run_updates(self.app.world_mut(), updates);
    }

    /// Why the run stopped, as one line naming the update; `None` while it
    /// runs. The stages check every update's drift; call
    /// [`check_state`](Self::check_state) before using the final state.
    pub fn fault(&self) -> Option<String> {
        self.app.world().resource::<SimulationFault>().message()
    }

    /// Checks that every body's position and velocity are finite now
    /// (what the last update's collisions left, which the next update's
    /// drift would otherwise check); records a fault if not. Returns
    /// [`fault`](Self::fault).
    pub fn check_state(&mut self) -> Option<String> {
        let world = self.app.world_mut();
        let found = first_non_finite(world.query::<(&BodyId, &Position, &Velocity)>().iter(world));
        if let Some(found) = found {
            let update = world.resource::<UpdateCount>().0;
            let mut fault = world.resource_mut::<SimulationFault>();
            fault.stop(found);
            fault.date(update);
        }
        self.fault()
    }

    /// Runs `updates` updates in about `reports` batches, telling `progress`
    /// the number done after each (so a progress display costs nothing
    /// measurable).
    pub fn step_reporting(&mut self, updates: u64, reports: u64, mut progress: impl FnMut(u64)) {
        let batch = (updates / reports.max(1)).max(1);
        let mut done = 0;
        while done < updates && self.fault().is_none() {
            let n = batch.min(updates - done);
            self.step(n);
            done += n;
            progress(done);
        }
    }

    /// Hands back the buffers the sort stage keeps between updates (about
    /// 32 bytes a body), for a run that makes no more updates: its state
    /// and its next update's results are the same without them, the next
    /// sort only allocates them again.
    pub fn release_buffers(&mut self) {
        self.app.world_mut().insert_resource(SortedBoxes::default());
    }

    /// Every body's state, sorted by id.
    pub fn snapshot(&mut self) -> Vec<BodyState> {
        BodyState::all_in(self.app.world_mut())
    }

    /// The hash of the state now (its bodies and next id).
    pub fn state_hash(&mut self) -> StateHash {
        let next_id = self.next_body_id();
        let world = self.app.world_mut();
        let mut query = world.query::<BodyStateQuery>();
        StateHash::of(query.iter(world).map(BodyState::from_components), next_id)
    }

    /// The same hash as [`state_hash`](Self::state_hash), reading each body
    /// where it lies, in id order: 16–36 bytes a body (ids, entities and
    /// the order) where that one takes a 67-byte copy, but a lookup a body
    /// makes it about twice as slow. For a run's end, where memory peaks.
    pub fn state_hash_in_place(&mut self) -> StateHash {
        let next_id = self.next_body_id();
        let world = self.app.world_mut();
        let mut query = world.query::<(Entity, BodyStateQuery)>();
        let bodies: Vec<(u64, Entity)> = query.iter(world).map(|(entity, body)| (body.id.0, entity)).collect();
        let world = &*world;
        StateHash::of_indexed(
            bodies.len(),
            next_id,
            |i| bodies[i].0,
            |i| {
                let (_, body) = query
                    .get_manual(world, bodies[i].1)
                    .expect("the query just listed this entity");
                BodyState::from_components(body)
            },
        )
    }

    /// Mass, kinetic energy and momentum of all bodies now.
    pub fn totals(&mut self) -> Totals {
        let world = self.app.world_mut();
        Totals::of(world.query::<(&Mass, &Velocity)>().iter(world).map(|(m, v)| (m.0, v.0)))
    }

    /// Number of bodies now.
    pub fn body_count(&mut self) -> usize {
        let world = self.app.world_mut();
        world.query::<&BodyId>().iter(world).len()
    }

    /// What collisions did in the last update, and shatters so far.
    pub fn collision_stats(&self) -> CollisionStats {
        *self.app.world().resource::<CollisionStats>()
    }

    /// The mass and momentum absorbing bodies took since the start.
    pub fn absorbed(&self) -> Absorbed {
        *self.app.world().resource::<Absorbed>()
    }

    /// How long the stages and updates took.
    pub fn timings(&self) -> &StageTimings {
        self.app.world().resource::<StageTimings>()
    }

    /// The timings, to reset them.
    pub fn timings_mut(&mut self) -> Mut<'_, StageTimings> {
        self.app.world_mut().resource_mut::<StageTimings>()
    }

    /// The physics and stage switches, to change them between updates.
    pub fn settings_mut(&mut self) -> Mut<'_, SimulationSettings> {
        self.app.world_mut().resource_mut::<SimulationSettings>()
    }

    /// The execution, to switch mode or threads between updates.
    pub fn execution_mut(&mut self) -> Mut<'_, Execution> {
        self.app.world_mut().resource_mut::<Execution>()
    }

    /// The app, for anything else.
    pub fn app_mut(&mut self) -> &mut App {
        &mut self.app
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::components::GravityRole;
    use crate::execution::ExecutionMode;

    /// A state that overflows stops the run at that update, in both modes,
    /// naming the body; nothing writes it.
    #[test]
    fn an_overflow_stops_the_run_naming_the_update_and_the_body() {
        let body = |id, x: f32, v: f32| {
            BodyState::new_box(
                BodyId(id),
                Vec3::new(x, 0.0, 0.0),
                Vec3::new(v, 0.0, 0.0),
                1.0,
                Vec3::ONE,
                GravityRole::Adopter,
                true,
            )
        };
        // Not a valid scenario (its speed is past the limits); made here
        // directly. The position grows by 1e38 an update: 3.4e38 is the most
        // an f32 holds, so update 4 overflows.
        let bodies = [body(4, 0.0, 1.0), body(9, 0.0, 1.0e38), body(7, 50.0, 1.0)];
        for mode in [ExecutionMode::Sequential, ExecutionMode::Parallel] {
            let execution = Execution::new(mode, 2).unwrap().fine_grained();
            // Found where updates end: the fast body's path crosses the
            // others', which swept detection would bounce it off.
            let settings = SimulationSettings {
                collision_detection: crate::resources::CollisionDetection::Discrete,
                ..SimulationSettings::default()
            };
            let mut sim = Simulation::new(&bodies, settings, execution);
            sim.step(2);
            assert_eq!(sim.fault(), None, "2e38 is still finite");
            sim.step(10);
            let fault = sim.fault().expect("the fourth update overflows");
            assert!(
                fault.starts_with("update 4: body 9 has a non-finite position (inf, 0, 0)"),
                "{mode:?}: {fault}"
            );
            assert!(fault.ends_with("the simulation stopped"), "{fault}");
            let world = sim.app_mut().world();
            assert_eq!(world.resource::<UpdateCount>().0, 4, "no update after the fault");
            let state = sim.snapshot();
            assert!(
                crate::record::write_csv(&state, Vec::new()).is_err(),
                "the dump writes it"
            );
        }
    }
}
