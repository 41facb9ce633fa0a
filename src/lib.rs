//! Kessler: thousands to a million bodies orbiting a planet under gravity,
//! colliding and shattering — every stage sequential or parallel, with
//! bit-identical results. See `ARCHITECTURE.md` for a map of the folders.

pub mod bench;
pub mod cli;
pub mod components;
pub mod dump;
pub mod resources;
pub mod rng;
pub mod scenario;
pub mod simulation;
pub mod systems;
#[cfg(feature = "gui")]
pub mod ui;

pub use simulation::Simulation;
