//! Kessler: thousands to a million bodies orbiting a planet under Newtonian
//! gravity, colliding, bouncing and shattering into debris — the Kessler
//! syndrome, step by step, as Bevy plugins. Every stage runs sequentially
//! or in parallel, switchable at run time, and both give **bit-identical**
//! results. The same crate builds the `kessler` program (the sandbox
//! window, headless runs, benchmarks, ensembles); this page is for using
//! the simulation in an app of your own.
//!
//! # Getting started
//!
//! Add [`SimulationPlugins`](systems::SimulationPlugins) to an app, insert
//! an [`Execution`](execution::Execution) (sequential, or parallel on a
//! number of threads: the one resource the plugins need and cannot make
//! up), spawn bodies, and run [`run_updates`](systems::run_updates) as
//! often as you want the simulation to advance. Kessler's update is a
//! schedule of its own, [`SimulationUpdate`](systems::SimulationUpdate), of
//! fixed time step: nothing runs it until you do, from `Update`,
//! `FixedUpdate` or a loop of your own. [`prelude`] brings what this
//! takes in one import.
//!
//! ```
//! use bevy::prelude::*;
//! use kessler::prelude::*;
//!
//! let mut app = App::new();
//! app.add_plugins((MinimalPlugins, SimulationPlugins))
//!     .insert_resource(Execution::new(ExecutionMode::Parallel, 2).unwrap())
//!     // One simulation update per app update.
//!     .add_systems(Update, |world: &mut World| run_updates(world, 1));
//!
//! // A planet (a gravity source that collisions never move) and a
//! // satellite on a circular orbit around it: speed √(G·M/r), G = 6.674.
//! let world = app.world_mut();
//! let mut ids = world.resource_mut::<NextBodyId>();
//! let (planet, satellite) = (ids.allocate(), ids.allocate());
//! let (mass, radius) = (4000.0, 400.0);
//! let speed = (6.674_f32 * mass / radius).sqrt();
//! let planet = BodyState::new_box(planet, Vec3::ZERO, Vec3::ZERO, mass, Vec3::splat(50.0), GravityRole::Source, false);
//! world.spawn((planet.bundle(), GravityRole::Source, NonInteracting));
//! let satellite = BodyState::new_box(
//!     satellite,
//!     Vec3::new(radius, 0.0, 0.0),
//!     Vec3::new(0.0, speed, 0.0),
//!     1.0,
//!     Vec3::ONE,
//!     GravityRole::Adopter,
//!     true,
//! );
//! world.spawn(satellite.bundle());
//!
//! for _ in 0..100 {
//!     app.update();
//! }
//! let world = app.world_mut();
//! let mut satellites = world.query_filtered::<&Position, Without<NonInteracting>>();
//! let r = satellites.single(world).unwrap().0.length();
//! assert!((r - radius).abs() < 0.5, "the orbit stays round: {r}");
//! ```
//!
//! A fuller example — a ring of satellites, a head-on collision, its
//! fragments falling onto the planet, the world read back every update —
//! is `examples/orbit_in_your_app.rs`:
//! `cargo run --example orbit_in_your_app --no-default-features`.
//!
//! **Features.** `gui` (on by default) is the sandbox window: the renderer,
//! egui and cameras. A library user wants `default-features = false`,
//! which leaves Bevy's ECS, app, time and tasks and no rendering.
//!
//! # Bodies
//!
//! A body is an entity with the components of
//! [`BodyBundle`](components::BodyBundle) — id, position, previous
//! position, velocity, mass, half-extents (every body is a box) — its
//! [`GravityRole`](components::GravityRole) where it is no adopter (a body
//! without one is attracted and attracts nothing, as debris is) and, on
//! the few that are one, the markers [`NonInteracting`](components::NonInteracting)
//! (collisions never move it: a planet), [`Spherical`](components::Spherical)
//! (a ball) and [`Absorbs`](components::Absorbs) (removes what falls on
//! it). [`BodyState`](components::BodyState) is a body as plain data, and
//! [`BodyState::bundle`](components::BodyState::bundle) spawns it (the role
//! and the markers are yours to add, or
//! [`spawn_states`](components::spawn_states) adds them). Ids must be unique: take them from
//! [`NextBodyId`](resources::NextBodyId), from which fragments take theirs
//! too. Kessler keeps its own [`Position`](components::Position), not a
//! `Transform`, and never marks the motion components changed (see
//! [`components`]); to draw bodies, copy positions to whatever you draw.
//! Units are free: `G` and the time step tie them together.
//!
//! # Settings and results
//!
//! The physics settings are one resource,
//! [`SimulationSettings`](resources::SimulationSettings) (`G`, time step,
//! integrator, gravity method, collision detection, shatter threshold,
//! fragments…), with the stage switches in its `stages`, and it may change
//! between updates. What an update did is in resources:
//! [`UpdateCount`](systems::UpdateCount) (the updates run so far),
//! [`CollisionStats`](systems::CollisionStats) (pairs, shatters,
//! re-entries), [`Absorbed`](systems::Absorbed),
//! [`StageTimings`](systems::StageTimings) and
//! [`SimulationFault`](systems::SimulationFault) (why a run stopped, if it
//! did: a value overflowed; after a fault no stage runs). [`Totals`](physics::Totals) sums mass, kinetic energy and
//! momentum over any bodies.
//!
//! # One update
//!
//! Six stages, each a plugin of the group, in this order: gravity (the
//! velocity kick, summed directly or through a Barnes–Hut tree),
//! integrate (the drift), sort and sweep (the broad phase: each body's box,
//! by default swept along its path over the update), response (when each
//! pair first touched: bounce, absorb, or mark to shatter) and shatter
//! (fragments that keep mass and momentum).
//!
//! # Determinism
//!
//! A run is a function of its bodies (in the order they were spawned), its
//! settings and the number of updates, and of nothing else: the same bits
//! in sequential and parallel mode, on any number of threads, on any
//! processor and operating system, in debug and release builds. Parallel
//! work runs on a pool of exactly the [`Execution`](execution::Execution)'s
//! threads (Kessler's own by default, not Bevy's task pools), and the
//! functions that decide the state come from [`maths`] (portable `libm`),
//! never the platform's C library — use them for your own initial states
//! too.
//!
//! # Without writing an app
//!
//! [`Simulation`] wraps such an app: bodies or a scenario file
//! ([`scenario::Scenario`]) in, `step`, then snapshots, totals, the state
//! hash. The command line, the tests and the benchmarks use it.
//!
//! # Modules
//!
//! - [`components`], [`resources`]: a body's components; the settings and
//!   shared resources.
//! - [`systems`]: the stages, their plugins and the schedule they run in.
//! - [`execution`]: sequential or parallel, the worker pool, the rules a
//!   kernel follows to stay bit-identical.
//! - [`physics`], [`maths`]: what is not a stage (fragments, totals); the
//!   portable functions.
//! - [`scenario`], [`timed_events`], [`record`]: scenario files, the
//!   events applied between updates, and what a run writes (dump, state
//!   hash, timeline).
//!
//! The rest serves the `kessler` program. `ARCHITECTURE.md` maps the source
//! tree and says why it is built the way it is; `docs/design.md` describes
//! the physics, the algorithms and the contracts (scenario format, command
//! line, CSV headers), and what is bit-identical.

// Functions stay under 100 lines (clippy.toml sets the threshold).
#![warn(clippy::too_many_lines)]

pub mod bench;
pub mod calibration;
pub mod cli;
pub mod components;
pub mod ensemble;
pub mod execution;
pub mod input;
pub mod maths;
pub mod memory;
pub mod output;
pub mod physics;
pub mod prelude;
pub mod record;
pub mod resources;
pub mod scenario;
pub mod simulation;
pub mod systems;
pub mod timed_events;
#[cfg(feature = "gui")]
pub mod ui;

pub use simulation::Simulation;

/// Whether this build has the window (the `gui` feature).
pub const WINDOW_BUILD: bool = cfg!(feature = "gui");
