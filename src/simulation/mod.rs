//! A simulation without a window: a Bevy app (MinimalPlugins) holding the
//! bodies, stepped on demand. The command line, tests and benchmarks use it.

mod headless_run;
mod timeline;

use bevy::prelude::*;
pub use headless_run::{HeadlessError, HeadlessReport, Outputs, run_headless};
pub use timeline::{Timeline, TimelineRow, row_updates};

use crate::components::{
    BodyId, BodyState, BodyStateQuery, Mass, Position, Velocity, insert_markers, spawn_states, spawn_with_roles,
};
use crate::execution::Execution;
use crate::input::InputError;
use crate::physics::Totals;
use crate::record::StateHash;
use crate::resources::{NextBodyId, SimulationSettings};
use crate::scenario::{Event, Scenario};
use crate::systems::{
    Absorbed, CollisionStats, SimulationFault, SimulationPlugins, SortedBoxes, StageTimings, UpdateCount,
    first_non_finite, run_due_events, run_updates,
};
use crate::timed_events::{EventLog, EventQueue, EventsPlugin, Pending, install_events, record_event};

/// Spawns `bodies` (ids must be unique and unused) and sets the next fresh
/// id past the highest; returns that id.
pub fn spawn_bodies(world: &mut World, bodies: &[BodyState]) -> u64 {
    let next = next_fresh_id(bodies);
    spawn_states(world, bodies);
    world.insert_resource(NextBodyId(next));
    next
}

/// The next fresh id: past the highest of `bodies`.
fn next_fresh_id(bodies: &[BodyState]) -> u64 {
    bodies.iter().map(|b| b.id.0 + 1).max().unwrap_or(0)
}

/// Bodies moved into the world at a time by [`spawn_owned_bodies`].
const SPAWN_BATCH: usize = 1 << 16;

/// Spawns `bodies` as [`spawn_bodies`] does, handing their memory back a
/// batch at a time as they move into the world, so that a million bodies
/// are never held twice (64 bytes a body). The world comes out the same:
/// every body spawned in order first (with its role where it is no
/// adopter: [`spawn_with_roles`], a batch at a time), then the markers of
/// immovable colliders, balls and absorbers inserted in order (each moves
/// its body to another table, and the last row of the first into its
/// place), as [`spawn_states`] does in one call.
pub fn spawn_owned_bodies(world: &mut World, mut bodies: Vec<BodyState>) -> u64 {
    let next = next_fresh_id(&bodies);
    let mut marked = Vec::new();
    // The first bodies last, so that each batch comes off the end.
    bodies.reverse();
    while !bodies.is_empty() {
        let mut batch = bodies.split_off(bodies.len().saturating_sub(SPAWN_BATCH));
        batch.reverse();
        let entities = spawn_with_roles(world, &batch);
        marked.extend(
            entities
                .into_iter()
                .zip(&batch)
                .filter(|(_, body)| body.has_markers())
                .map(|(entity, &body)| (entity, body)),
        );
        bodies.shrink_to_fit();
    }
    for (entity, body) in marked {
        insert_markers(world, entity, &body);
    }
    // After the bodies, as in `spawn_bodies`: in a world that does not have
    // the resource yet, inserting it makes an entity too, and the
    // archetypes must come in the same order.
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
        // them when it makes the scene).
        run_due_events(sim.app.world_mut());
        Ok(sim)
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
        let world = self.app.world_mut();
        let mut query = world.query::<BodyStateQuery>();
        let mut bodies: Vec<BodyState> = query.iter(world).map(BodyState::from_components).collect();
        bodies.sort_unstable_by_key(|b| b.id);
        bodies
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
        let bodies: Vec<(u64, Entity)> = query.iter(world).map(|(entity, body)| (body.0.0, entity)).collect();
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
    use crate::components::{Absorbs, GravityRole, Immovable, Spherical};
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

    /// Bodies moved into the world in batches make the same world as in
    /// one call, past one batch and with balls, absorbers, immovable
    /// colliders and every gravity role among them:
    /// the same bodies in the same tables in the same order, so that sums
    /// in query order (the timeline's totals) keep their bits. Only the
    /// bodies that are no adopters store their role, and every role reads
    /// back as given.
    #[test]
    fn bodies_spawned_in_batches_make_the_same_world() {
        let role = |k: u64| match k % 1_000 {
            1 => GravityRole::Source,
            2 => GravityRole::SourceAndAdopter,
            3 => GravityRole::Inert,
            _ => GravityRole::Adopter,
        };
        let bodies: Vec<BodyState> = (0..SPAWN_BATCH as u64 + 4_500)
            .map(|k| BodyState {
                spherical: k % 9_001 == 5,
                absorbs: k == 70_000,
                interacts: k != 70_000 && k % 7_919 != 3,
                ..BodyState::new_box(
                    BodyId(k * 3 + 1),
                    Vec3::new(k as f32, 0.5 * k as f32, -(k as f32)),
                    Vec3::new(1.0 / (k + 1) as f32, 0.25, k as f32 * 1e-3),
                    1.0 + (k % 17) as f32,
                    Vec3::splat(0.5),
                    role(k),
                    true,
                )
            })
            .collect();
        let listed = |world: &mut World| -> Vec<(u64, bool, bool, bool, Option<GravityRole>)> {
            world
                .query::<(
                    &BodyId,
                    Has<Spherical>,
                    Has<Absorbs>,
                    Has<Immovable>,
                    Option<&GravityRole>,
                )>()
                .iter(world)
                .map(|(id, ball, absorber, immovable, role)| (id.0, ball, absorber, immovable, role.copied()))
                .collect()
        };
        let (mut whole, mut batched) = (World::new(), World::new());
        assert_eq!(
            spawn_bodies(&mut whole, &bodies),
            spawn_owned_bodies(&mut batched, bodies.clone())
        );
        let order = listed(&mut whole);
        assert!(order.iter().any(|&(_, ball, ..)| ball) && order.iter().any(|&(_, _, absorber, ..)| absorber));
        assert!(order.iter().filter(|&&(.., immovable, _)| immovable).count() > 2);
        for &(id, .., stored) in &order {
            let given = role((id - 1) / 3);
            assert_eq!(GravityRole::of(stored.as_ref()), given, "body {id}");
            assert_eq!(stored.is_some(), given != GravityRole::Adopter, "body {id}");
        }
        assert_eq!(
            order.iter().filter(|&&(.., stored)| stored.is_some()).count(),
            bodies.iter().filter(|b| b.role != GravityRole::Adopter).count()
        );
        assert!(
            order.windows(2).any(|pair| pair[0].0 > pair[1].0),
            "the markers moved rows out of id order"
        );
        assert_eq!(listed(&mut batched), order);
    }

    /// A run whose sort buffers are handed back midway goes on to the same
    /// state, bit for bit, in both modes; the state's hash read in the
    /// world is the hash of its snapshot.
    #[test]
    fn handing_back_the_buffers_changes_nothing() {
        let text = "Scenario(generators: [Cloud(count: 600, center: (0, 0, 0), half_size: (14, 14, 14), \
                    max_speed: 3.0)])";
        let scenario = Scenario::parse(text, "t").unwrap();
        for mode in [ExecutionMode::Sequential, ExecutionMode::Parallel] {
            let start =
                |_| Simulation::from_scenario(&scenario, Execution::new(mode, 2).unwrap().fine_grained()).unwrap();
            let (mut kept, mut released) = (start(()), start(()));
            kept.step(30);
            released.step(10);
            released.release_buffers();
            released.step(20);
            assert!(kept.collision_stats().shatters_total > 0, "{mode:?}: nothing collided");
            assert_eq!(bits(&released.snapshot()), bits(&kept.snapshot()), "{mode:?}");
            let hash = released.state_hash();
            assert_eq!(hash, kept.state_hash(), "{mode:?}");
            assert_eq!(hash, released.state_hash_in_place(), "{mode:?}");
            assert_eq!(
                hash,
                StateHash::of_slice(&released.snapshot(), released.next_body_id()),
                "{mode:?}"
            );
        }
    }

    /// Runs `text` (a scenario) `updates` updates sequentially: the end
    /// state, the shatters refused and the next id.
    fn run(text: &str, updates: u64) -> (Vec<BodyState>, u64, u64) {
        let scenario = Scenario::parse(text, "t").unwrap_or_else(|e| panic!("{e}\n{text}"));
        let execution = Execution::new(ExecutionMode::Sequential, 1).unwrap();
        let mut sim = Simulation::from_scenario(&scenario, execution).unwrap();
        sim.step(updates);
        assert_eq!(sim.check_state(), None, "{text}");
        (sim.snapshot(), sim.collision_stats().refused_total, sim.next_body_id())
    }

    /// Every bit of the end state, body by body.
    fn bits(bodies: &[BodyState]) -> Vec<(u64, [[u32; 3]; 3], u32)> {
        bodies
            .iter()
            .map(|b| {
                let v = [b.position, b.velocity, b.half_extents].map(|v| v.to_array().map(f32::to_bits));
                (b.id.0, v, b.mass.to_bits())
            })
            .collect()
    }

    /// Sources in a cloud, pulling one another (no collisions: none
    /// interacts); more than one of them, so that a tree groups them.
    const PULLING: &str = "generators: [Cloud(count: 40, center: (0, 0, 0), half_size: (60, 60, 60), \
                           max_speed: 0.5, body: (role: SourceAndAdopter, interacts: false))]";
    /// Two unit cubes meeting head-on at 4 (past the default threshold, 3)
    /// in the first update; no sources, so no gravity.
    const MEETING: &str = "bodies: [Body(position: (-1.5, 0, 0), velocity: (2, 0, 0)), \
                           Body(position: (1.5, 0, 0), velocity: (-2, 0, 0.1))]";

    /// Two unit cubes 11 apart, each at 10 units an update towards the
    /// other: between two updates' ends they pass through each other.
    const CROSSING: &str = "bodies: [Body(position: (-5.5, 0, 0), velocity: (10, 0, 0)), \
                            Body(position: (5.5, 0, 0), velocity: (-10, 0, 0))]";

    /// One row a physics setting: a value away from its default, the scene
    /// in which it shows, and what it changes there.
    struct Effect {
        key: &'static str,
        changed: &'static str,
        scene: &'static str,
        /// What the change does, as the two end states (default, changed)
        /// show it.
        what: &'static str,
        shows: fn(&[BodyState], &[BodyState]) -> bool,
    }

    fn moved(default: &[BodyState], changed: &[BodyState]) -> bool {
        bits(default) != bits(changed)
    }

    fn counted(default: &[BodyState], changed: &[BodyState]) -> bool {
        default.len() != changed.len()
    }

    /// The table: every setting of the list, in its order. Each changes the
    /// state of a few updates of a small scene; none is a field that does
    /// nothing.
    const EFFECTS: &[Effect] = &[
        Effect {
            key: "gravitational_constant",
            changed: "1.0",
            scene: PULLING,
            what: "the pulls",
            shows: moved,
        },
        Effect {
            key: "time_step",
            changed: "0.5",
            scene: PULLING,
            what: "how far each update moves",
            shows: moved,
        },
        Effect {
            key: "integrator",
            changed: "SemiImplicitEuler",
            scene: PULLING,
            what: "where the pulls are summed and how far each update moves",
            shows: moved,
        },
        Effect {
            key: "softening",
            changed: "10.0",
            scene: PULLING,
            what: "the pulls of near sources",
            shows: moved,
        },
        Effect {
            key: "gravity",
            changed: "Tree(theta: 2.0)",
            scene: PULLING,
            what: "the pulls, summed through the tree",
            shows: moved,
        },
        Effect {
            key: "collision_detection",
            changed: "Discrete",
            scene: CROSSING,
            what: "a pair that passes through each other within an update: no collision",
            shows: moved,
        },
        Effect {
            key: "shatter_threshold",
            changed: "100.0",
            scene: MEETING,
            what: "a bounce instead of a shatter",
            shows: counted,
        },
        Effect {
            key: "shatter_fragments",
            changed: "8",
            scene: MEETING,
            what: "the fragments a shatter makes",
            shows: counted,
        },
        Effect {
            key: "fragment_sizes",
            changed: "PowerLaw(exponent: 1.71)",
            scene: MEETING,
            what: "the fragments' sizes",
            shows: moved,
        },
        Effect {
            key: "fragment_spread",
            changed: "1.0",
            scene: MEETING,
            what: "the fragments' speeds",
            shows: moved,
        },
        Effect {
            key: "min_fragment_size",
            changed: "1.5",
            scene: MEETING,
            what: "a bounce: fragments of 1.47 are below the floor",
            shows: counted,
        },
        Effect {
            key: "max_bodies",
            changed: "4",
            scene: MEETING,
            what: "a bounce: 5 fragments are past the budget",
            shows: counted,
        },
        Effect {
            key: "seed",
            changed: "2",
            scene: MEETING,
            what: "the fragments' spread",
            shows: moved,
        },
    ];

    /// Every physics setting changes what it should: a scene run with its
    /// default and with another value ends in different states. A setting
    /// added to the list without a row here fails this test.
    #[test]
    fn every_physics_setting_changes_the_run() {
        let keys: Vec<&str> = EFFECTS.iter().map(|e| e.key).collect();
        let listed: Vec<&str> = crate::resources::settings().iter().map(|s| s.key).collect();
        assert_eq!(keys, listed, "one row a setting of the list, in its order");
        for effect in EFFECTS {
            let default = format!("Scenario({})", effect.scene);
            let changed = format!("Scenario({}: {}, {})", effect.key, effect.changed, effect.scene);
            // The file sets this setting and no other.
            let settings = Scenario::parse(&changed, "t").unwrap().settings();
            for s in crate::resources::settings() {
                let differs = settings.shown(s.key) != SimulationSettings::DEFAULT.shown(s.key);
                assert_eq!(differs, s.key == effect.key, "{}: sets {}", effect.key, s.key);
            }
            let (default, _, _) = run(&default, 3);
            let (changed, _, _) = run(&changed, 3);
            assert!(
                (effect.shows)(&default, &changed),
                "{} changes nothing it should ({}): {} bodies, then {}",
                effect.key,
                effect.what,
                default.len(),
                changed.len()
            );
        }
    }

    /// `previous_position`, which older snapshots wrote, still loads and
    /// changes nothing: the first update's drift sets it before anything
    /// reads it.
    #[test]
    fn a_previous_position_is_accepted_and_ignored() {
        let (plain, _, _) = run(&format!("Scenario({MEETING})"), 3);
        let given = MEETING.replace("velocity: (2", "previous_position: (-1e30, 7, 0), velocity: (2");
        assert_ne!(given, MEETING);
        let (given, _, _) = run(&format!("Scenario({given})"), 3);
        assert_eq!(bits(&plain), bits(&given));
    }

    /// A shatter whose fragments' ids would take the next id past
    /// `MAX_ID` bounces instead, counted as refused; one that just fits
    /// shatters, and the next id ends at `MAX_ID`.
    #[test]
    fn no_shatter_hands_out_an_id_past_the_bound() {
        use crate::resources::MAX_ID;
        for (room, bodies, refused, next) in [(5, 5, 0, MAX_ID), (4, 2, 1, MAX_ID - 4)] {
            let text = format!("Scenario(next_id: {}, {MEETING})", MAX_ID - room);
            let (state, refused_total, next_id) = run(&text, 3);
            assert_eq!(
                (state.len(), refused_total, next_id),
                (bodies, refused, next),
                "{room} ids of room"
            );
            assert!(state.iter().all(|b| b.id.0 < MAX_ID));
        }
    }
}
