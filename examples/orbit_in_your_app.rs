//! Kessler's simulation inside your own Bevy app.
//!
//! A plain headless app adds [`SimulationPlugins`], spawns a planet and a
//! ring of satellites with Kessler's components, steps the simulation once
//! per app update and reads the world back each time. One satellite goes
//! the wrong way round the ring: it meets the next head-on, both shatter,
//! and their fragments, their orbital speed gone, fall onto the planet,
//! which absorbs them (re-entries). The other eleven go round unharmed,
//! their energy constant.
//!
//! ```sh
//! cargo run --release --no-default-features --example orbit_in_your_app
//! ```

use std::f64::consts::TAU;

use bevy::prelude::*;
use kessler::components::{Absorbs, BodyState, GravityRole, Mass, NonInteracting, Position, Spherical, Velocity};
use kessler::execution::{Execution, ExecutionMode};
use kessler::maths::sin_cos;
use kessler::physics::Totals;
use kessler::resources::{NextBodyId, SimulationSettings};
use kessler::systems::{CollisionStats, SimulationFault, SimulationPlugins, UpdateCount, run_updates};

/// How many simulation updates the app runs before it exits.
const UPDATES: u64 = 80;
/// The planet: its mass and its radius, in the simulation's units.
const PLANET_MASS: f32 = 4000.0;
const PLANET_RADIUS: f32 = 100.0;
/// The satellites' ring: its radius and how many satellites it holds.
const RING_RADIUS: f32 = 400.0;
const SATELLITES: usize = 12;
/// The gravitational constant: the default setting's.
const G: f32 = SimulationSettings::DEFAULT.gravitational_constant;

fn main() {
    // The stages run their kernels in parallel on two worker threads; the
    // results are bit for bit those of `ExecutionMode::Sequential`.
    let execution = Execution::new(ExecutionMode::Parallel, 2).expect("two threads");
    app(execution).run();
}

/// The whole app. (`pub` only so that `tests/library.rs` can run it too.)
pub fn app(execution: Execution) -> App {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, SimulationPlugins))
        // The one resource the stages need that the plugins cannot make up:
        // how to run them (sequential or parallel, and on how many threads).
        .insert_resource(execution)
        // The physics settings: the defaults (G = 6.674, one time unit an
        // update, shattering from an impact speed of 3); change any field,
        // e.g. `SimulationSettings { shatter_threshold: 20.0, ..default() }`.
        .insert_resource(SimulationSettings::default())
        .add_systems(Startup, spawn_bodies)
        // Kessler's update is a schedule of its own, `SimulationUpdate`,
        // which `run_updates` runs (timed, and stopping at a fault). Here it
        // runs once per app update; a real-time app could run it from
        // `FixedUpdate` instead.
        .add_systems(Update, (step_simulation, report).chain());
    app
}

/// Spawns the planet and the satellites. Each body is a [`BodyState`]'s
/// bundle (id, position, velocity, mass, size) with a fresh id from
/// [`NextBodyId`], so that the ids the shatters hand out to fragments never
/// clash with ours; a body that is no adopter also carries its
/// [`GravityRole`].
fn spawn_bodies(mut commands: Commands, mut ids: ResMut<NextBodyId>) {
    // The planet pulls (a gravity source) and is not pulled; it is a ball
    // (`Spherical`) that collisions never move (`NonInteracting`, which is what
    // `interacts: false` means) and that absorbs whatever falls on it. The
    // bundle leaves its role (no adopter) and these markers to us.
    let planet = BodyState::new_box(
        ids.allocate(),
        Vec3::ZERO,
        Vec3::ZERO,
        PLANET_MASS,
        Vec3::splat(PLANET_RADIUS),
        GravityRole::Source,
        false,
    );
    commands.spawn((planet.bundle(), planet.role, NonInteracting, Spherical, Absorbs));

    // Cubes of edge 2 and mass 1 on a circular orbit: speed sqrt(G M / r).
    let speed = (G * PLANET_MASS / RING_RADIUS).sqrt();
    for k in 0..=SATELLITES {
        // The last one sits halfway between the first two and goes the
        // other way round.
        let (turn, direction) = match k {
            SATELLITES => (0.5 / SATELLITES as f64, -1.0),
            _ => (k as f64 / SATELLITES as f64, 1.0),
        };
        // Kessler's `sin_cos` (from `libm`), not the platform's: the same
        // bits on every machine, so the run is too.
        let (sin, cos) = sin_cos(turn * TAU);
        let (sin, cos) = (sin as f32, cos as f32);
        let satellite = BodyState::new_box(
            ids.allocate(),
            RING_RADIUS * Vec3::new(cos, sin, 0.0),
            direction * speed * Vec3::new(-sin, cos, 0.0),
            1.0,
            Vec3::ONE,
            GravityRole::Adopter,
            true,
        );
        commands.spawn(satellite.bundle());
    }
}

/// Runs one simulation update.
fn step_simulation(world: &mut World) {
    run_updates(world, 1);
}

/// Reads the world after each update: the satellites' and fragments'
/// totals and energy, and what the collisions did; ends the app after
/// [`UPDATES`] updates.
fn report(
    bodies: Query<(&Mass, &Velocity, &Position), Without<NonInteracting>>,
    stats: Res<CollisionStats>,
    fault: Res<SimulationFault>,
    updates: Res<UpdateCount>,
    mut exit: MessageWriter<AppExit>,
) {
    let totals = Totals::of(bodies.iter().map(|(mass, velocity, _)| (mass.0, velocity.0)));
    let energy: f64 = bodies.iter().map(|(m, v, p)| orbital_energy(m.0, v.0, p.0)).sum();
    println!(
        "update {:>2}: {:>2} bodies in orbit, mass {:.1}, energy {:.3}, shatters {}, re-entries {}",
        updates.0, totals.bodies, totals.mass, energy, stats.shatters_total, stats.reentries_total,
    );
    // A run stops (every later update is skipped) if its state can no
    // longer be computed, e.g. a value overflowed.
    if let Some(message) = fault.message() {
        println!("{message}");
    }
    if updates.0 >= UPDATES {
        exit.write(AppExit::Success);
    }
}

/// A body's orbital energy in the planet's field: kinetic plus potential,
/// `m v² / 2 - G M m / r` (the bodies do not pull one another: they are
/// adopters, not sources). The sum stays constant along the orbits; a
/// shatter loses some of it.
pub fn orbital_energy(mass: f32, velocity: Vec3, position: Vec3) -> f64 {
    let (m, v, r) = (f64::from(mass), velocity.as_dvec3(), position.as_dvec3());
    0.5 * m * v.length_squared() - f64::from(G * PLANET_MASS) * m / r.length()
}
