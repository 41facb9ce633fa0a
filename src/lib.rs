//! Kessler: thousands to a million bodies orbiting a planet under gravity,
//! colliding and shattering — every stage sequential or parallel, with
//! bit-identical results. ARCHITECTURE.md maps the folders;
//! docs/design.md describes the physics, the algorithms and the contracts.

pub mod bench;
pub mod calibration;
pub mod cli;
pub mod components;
pub mod draw_method;
pub mod dump;
pub mod ensemble;
pub mod events;
pub mod execution;
pub mod heap;
pub mod input;
pub mod maths;
pub mod memory_limit;
pub mod output;
pub mod resources;
pub mod rng;
pub mod scenario;
pub mod simulation;
pub mod state_hash;
pub mod systems;
pub mod timeline;
#[cfg(feature = "gui")]
pub mod ui;
pub mod user_files;

pub use simulation::Simulation;

/// Whether this build has the window (the `gui` feature).
pub const WINDOW_BUILD: bool = cfg!(feature = "gui");
