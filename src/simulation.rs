//! A simulation without a window: a Bevy app (MinimalPlugins) holding the
//! bodies, stepped on demand. The command line, tests and benchmarks use it.

use bevy::prelude::*;

use crate::components::{BodyId, BodyState, BodyStateQuery, Mass, Position, Spherical, Velocity};
use crate::execution::Execution;
use crate::input::InputError;
use crate::resources::{NextBodyId, SimulationSettings};
use crate::scenario::Scenario;
use crate::systems::{
    CollisionStats, SimulationFault, SimulationPlugins, StageTimings, Totals, first_non_finite, run_updates,
};

/// Spawns `bodies` (ids must be unique and unused) and sets the next fresh
/// id past the highest; returns that id.
pub fn spawn_bodies(world: &mut World, bodies: &[BodyState]) -> u64 {
    let entities: Vec<Entity> = world.spawn_batch(bodies.iter().map(BodyState::bundle)).collect();
    for (entity, _) in entities.iter().zip(bodies).filter(|(_, b)| b.spherical) {
        world.entity_mut(*entity).insert(Spherical);
    }
    let next = bodies.iter().map(|b| b.id.0 + 1).max().unwrap_or(0);
    world.insert_resource(NextBodyId(next));
    next
}

/// A headless simulation.
pub struct Simulation {
    app: App,
}

impl Simulation {
    /// A simulation of `bodies` (ids must be unique) with `settings`.
    pub fn new(bodies: &[BodyState], settings: SimulationSettings, execution: Execution) -> Self {
        let mut app = App::new();
        app.add_plugins((MinimalPlugins, SimulationPlugins))
            .insert_resource(settings)
            .insert_resource(execution);
        app.finish();
        app.cleanup();
        spawn_bodies(app.world_mut(), bodies);
        Self { app }
    }

    /// The bodies and settings of `scenario`; fresh ids continue from its
    /// `next_id` (a snapshot's).
    pub fn from_scenario(scenario: &Scenario, execution: Execution) -> Result<Self, InputError> {
        let mut sim = Self::new(&scenario.bodies()?, scenario.settings(), execution);
        let mut next = sim.app.world_mut().resource_mut::<NextBodyId>();
        next.0 = next.0.max(scenario.next_id());
        Ok(sim)
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
            world.resource_mut::<SimulationFault>().stop(found);
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

    /// Every body's state, sorted by id.
    pub fn snapshot(&mut self) -> Vec<BodyState> {
        let world = self.app.world_mut();
        let mut query = world.query::<BodyStateQuery>();
        let mut bodies: Vec<BodyState> = query.iter(world).map(BodyState::from_components).collect();
        bodies.sort_unstable_by_key(|b| b.id);
        bodies
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
            let mut sim = Simulation::new(&bodies, SimulationSettings::default(), execution);
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
            assert_eq!(
                world.resource::<SimulationFault>().updates,
                4,
                "no update after the fault"
            );
            let state = sim.snapshot();
            assert!(
                crate::dump::write_csv(&state, Vec::new()).is_err(),
                "the dump writes it"
            );
        }
    }
}
