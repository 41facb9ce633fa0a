//! Physical parameters and stage switches of the running simulation.

use bevy::prelude::*;

use super::GravityMethod;

/// The physics of one simulation: set from the scenario, some changeable live.
#[derive(Resource, Clone, Debug, PartialEq)]
pub struct SimulationSettings {
    /// Gravitational constant `G` (scenario units; the thesis used 6.674).
    pub gravitational_constant: f32,
    /// Simulated time per update, `dt`.
    pub time_step: f32,
    /// Softening length `ε`: gravity uses `(r² + ε²)^{3/2}`; 0 means none.
    pub softening: f32,
    /// Direct sum, Barnes–Hut tree, or `Auto` (the default): the one that
    /// suits the number of sources.
    pub gravity_method: GravityMethod,
    /// Impact speed `|v1 − v2|` from which two interacting bodies shatter.
    pub shatter_threshold: f32,
    /// Fragments spawned per shatter; always ≥ 2.
    pub shatter_fragments: u32,
    /// Fragments' speed away from their center of mass, as a share of the
    /// impact speed (the thesis's "Streuung"), 0 to 10.
    pub fragment_spread: f32,
    /// Edge length below which fragments are not made: a collision whose
    /// fragments would be smaller bounces instead. 0: no floor (the thesis).
    /// Shattering keeps volume, so fragments never outnumber the
    /// shattering bodies' volume over this edge cubed.
    pub min_fragment_size: f32,
    /// Most bodies there may be: a shatter that would exceed it bounces
    /// instead.
    pub max_bodies: u64,
    /// Seed of every random choice the simulation makes (fragment spread).
    pub seed: u64,
    /// Gravity stage on/off. Off: adopters keep their velocity.
    pub gravity: bool,
    /// Broad phase on/off. Off: no pairs, so no responses.
    pub collisions: bool,
    /// Bounce and shatter on/off. Off: pairs are found but not acted on.
    pub collision_response: bool,
}

impl SimulationSettings {
    /// The thesis's physics with every stage on: the defaults of scenario
    /// files and of the window's settings.
    pub const DEFAULT: Self = Self {
        gravitational_constant: 6.674,
        time_step: 1.0,
        softening: 0.0,
        gravity_method: GravityMethod::Auto,
        shatter_threshold: 3.0,
        shatter_fragments: 5,
        fragment_spread: 0.2,
        min_fragment_size: 1.0,
        max_bodies: 1_000_000,
        seed: 1,
        gravity: true,
        collisions: true,
        collision_response: true,
    };
}

impl Default for SimulationSettings {
    fn default() -> Self {
        Self::DEFAULT
    }
}
