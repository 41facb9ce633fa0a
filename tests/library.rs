//! Kessler as a library: the app of `examples/orbit_in_your_app.rs` (a
//! plain Bevy app with Kessler's plugins and bodies of its own) run here,
//! sequentially and in parallel, and its physics checked.

#[path = "../examples/orbit_in_your_app.rs"]
#[expect(dead_code, reason = "the example's `main` and constants are not all used here")]
mod example;

use bevy::prelude::*;
use kessler::components::{BodyId, Immovable, Mass, Position, Velocity};
use kessler::execution::{Execution, ExecutionMode};
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
    let mut query = world.query_filtered::<(&BodyId, &Position, &Velocity, &Mass), Without<Immovable>>();
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
