//! What an app that runs Kessler's simulation usually needs, in one
//! import: `use kessler::prelude::*;` — the plugins and how to run them,
//! the execution, the settings, the bodies' components and how to spawn
//! them, and what an update reports.

pub use crate::Simulation;
pub use crate::components::{
    Absorbs, BodyBundle, BodyId, BodyState, GravityRole, HalfExtents, Mass, NonInteracting, Position, PreviousPosition,
    Spherical, Velocity, spawn_states,
};
pub use crate::execution::{Execution, ExecutionMode, SplitPolicy, WorkerPool};
pub use crate::physics::Totals;
pub use crate::resources::{
    CollisionDetection, FragmentSizes, GravityMethod, Integrator, NextBodyId, SimulationSettings, Stages,
};
pub use crate::scenario::Scenario;
pub use crate::systems::{
    Absorbed, CollisionStats, SimulationFault, SimulationPlugins, SimulationUpdate, StageTimings, UpdateCount,
    run_updates,
};
