//! Kessler as a library: the app of `examples/orbit_in_your_app.rs` (a
//! plain Bevy app with Kessler's plugins and bodies of its own) run here,
//! sequentially and in parallel, and its physics checked; every physics
//! setting through `Simulation`, each changing what it should.

#[path = "../examples/orbit_in_your_app.rs"]
#[expect(dead_code, reason = "the example's `main` and constants are not all used here")]
mod example;

use bevy::prelude::*;
use kessler::Simulation;
use kessler::components::{BodyId, BodyState, Mass, NonInteracting, Position, Velocity};
use kessler::execution::{Execution, ExecutionMode};
use kessler::record::StateHash;
use kessler::resources::SimulationSettings;
use kessler::scenario::Scenario;
use kessler::systems::{Absorbed, CollisionStats, SimulationFault};

/// Every update the example runs.
const UPDATES: u64 = 80;

/// The example's app after `UPDATES` updates.
fn run(execution: Execution) -> App {
    let mut app = example::app(execution);
    app.finish();
    app.cleanup();
    for _ in 0..UPDATES {
        app.update();
    }
    assert_eq!(app.world().resource::<SimulationFault>().message(), None);
    app
}

/// Every body that is not the planet: id, position, velocity and mass, in
/// id order.
fn bodies(app: &mut App) -> Vec<(u64, Vec3, Vec3, f32)> {
    let world = app.world_mut();
    let mut query = world.query_filtered::<(&BodyId, &Position, &Velocity, &Mass), Without<NonInteracting>>();
    let mut bodies: Vec<_> = query.iter(world).map(|(id, p, v, m)| (id.0, p.0, v.0, m.0)).collect();
    bodies.sort_by_key(|b| b.0);
    bodies
}

/// The example's story: the wrong-way satellite and the one it meets
/// shatter, their fragments fall onto the planet and are absorbed; the
/// other eleven satellites keep their orbits (radius and energy) and the
/// mass is all there, in orbit or absorbed.
#[test]
fn the_example_shatters_two_satellites_and_keeps_the_others_orbits() {
    let mut app = run(Execution::new(ExecutionMode::Sequential, 1).unwrap());
    let stats = *app.world().resource::<CollisionStats>();
    assert_eq!((stats.shatters_total, stats.reentries_total), (1, 5), "{stats:?}");
    let absorbed = app.world().resource::<Absorbed>().mass;
    let left = bodies(&mut app);
    let mass: f64 = left.iter().map(|b| f64::from(b.3)).sum::<f64>() + absorbed;
    assert!((mass - 13.0).abs() < 1e-5, "mass kept: {mass}");
    assert_eq!(left.len(), 11, "{left:?}");
    // The ring's circular energy per unit mass: -G M / (2 r).
    let circular = example::orbital_energy(1.0, Vec3::ZERO, Vec3::new(400.0, 0.0, 0.0)) / 2.0;
    for &(id, position, velocity, mass) in &left {
        assert!(id <= 12, "body {id} is a fragment");
        let radius = position.length();
        assert!((radius - 400.0).abs() < 0.1, "body {id}: radius {radius}");
        let energy = example::orbital_energy(mass, velocity, position);
        assert!(
            (energy / circular - 1.0).abs() < 1e-5,
            "body {id}: energy {energy}, circular {circular}"
        );
    }
}

/// The same app in parallel, cut as fine as it goes, ends in the same
/// bits as in sequence.
#[test]
fn the_example_runs_bit_identically_in_parallel() {
    let bits = |execution| -> Vec<(u64, [[u32; 3]; 2], u32)> {
        let bodies = bodies(&mut run(execution));
        bodies
            .into_iter()
            .map(|(id, p, v, m)| (id, [p, v].map(|x| x.to_array().map(f32::to_bits)), m.to_bits()))
            .collect()
    };
    let sequential = bits(Execution::new(ExecutionMode::Sequential, 1).unwrap());
    let parallel = bits(Execution::new(ExecutionMode::Parallel, 2).unwrap().fine_grained());
    assert_eq!(parallel, sequential);
}

// Each physics setting through the library's `Simulation`: it changes what
// it should, and what older files hold changes nothing.

/// A run whose sort buffers are handed back midway goes on to the same
/// state, bit for bit, in both modes; the state's hash read in the
/// world is the hash of its snapshot.
#[test]
fn handing_back_the_buffers_changes_nothing() {
    let text = "Scenario(generators: [Cloud(count: 600, center: (0, 0, 0), half_size: (14, 14, 14), \
                max_speed: 3.0)])";
    let scenario = Scenario::parse(text, "t").unwrap();
    for mode in [ExecutionMode::Sequential, ExecutionMode::Parallel] {
        let start = |_| Simulation::from_scenario(&scenario, Execution::new(mode, 2).unwrap().fine_grained()).unwrap();
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
fn run_scene(text: &str, updates: u64) -> (Vec<BodyState>, u64, u64) {
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
    let listed: Vec<&str> = kessler::resources::settings().iter().map(|s| s.key).collect();
    assert_eq!(keys, listed, "one row a setting of the list, in its order");
    for effect in EFFECTS {
        let default = format!("Scenario({})", effect.scene);
        let changed = format!("Scenario({}: {}, {})", effect.key, effect.changed, effect.scene);
        // The file sets this setting and no other.
        let settings = Scenario::parse(&changed, "t").unwrap().settings();
        for s in kessler::resources::settings() {
            let differs = settings.shown(s.key) != SimulationSettings::DEFAULT.shown(s.key);
            assert_eq!(differs, s.key == effect.key, "{}: sets {}", effect.key, s.key);
        }
        let (default, _, _) = run_scene(&default, 3);
        let (changed, _, _) = run_scene(&changed, 3);
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
    let (plain, _, _) = run_scene(&format!("Scenario({MEETING})"), 3);
    let given = MEETING.replace("velocity: (2", "previous_position: (-1e30, 7, 0), velocity: (2");
    assert_ne!(given, MEETING);
    let (given, _, _) = run_scene(&format!("Scenario({given})"), 3);
    assert_eq!(bits(&plain), bits(&given));
}

/// A shatter whose fragments' ids would take the next id past
/// `MAX_ID` bounces instead, counted as refused; one that just fits
/// shatters, and the next id ends at `MAX_ID`.
#[test]
fn no_shatter_hands_out_an_id_past_the_bound() {
    use kessler::resources::MAX_ID;
    for (room, bodies, refused, next) in [(5, 5, 0, MAX_ID), (4, 2, 1, MAX_ID - 4)] {
        let text = format!("Scenario(next_id: {}, {MEETING})", MAX_ID - room);
        let (state, refused_total, next_id) = run_scene(&text, 3);
        assert_eq!(
            (state.len(), refused_total, next_id),
            (bodies, refused, next),
            "{room} ids of room"
        );
        assert!(state.iter().all(|b| b.id.0 < MAX_ID));
    }
}
