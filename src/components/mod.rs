//! ECS components.

mod body;
mod body_state;

pub use body::{
    Absorbs, BodyId, GravityRole, HalfExtents, Mass, NonInteracting, Position, PreviousPosition, Spherical, Velocity,
};
pub use body_state::{BodyBundle, BodyData, BodyState, BodyStateQuery, insert_markers, spawn_states, spawn_with_roles};
