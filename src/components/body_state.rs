//! A body as plain data, and the bundle that spawns it.

use bevy::prelude::*;

use super::{BodyId, GravityRole, HalfExtents, Interacts, Mass, Position, PreviousPosition, Velocity};

/// Everything a body is made of, in one bundle.
#[derive(Bundle, Clone, Debug)]
#[expect(missing_docs, reason = "each field is its component, documented there")]
pub struct BodyBundle {
    pub id: BodyId,
    pub position: Position,
    pub previous_position: PreviousPosition,
    pub velocity: Velocity,
    pub mass: Mass,
    pub half_extents: HalfExtents,
    pub role: GravityRole,
    pub interacts: Interacts,
}

/// A body's state as plain data: what scenarios create, fragments are born
/// as, and dumps print.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyState {
    /// See [`BodyId`].
    pub id: BodyId,
    /// See [`Position`].
    pub position: Vec3,
    /// See [`Velocity`].
    pub velocity: Vec3,
    /// See [`Mass`].
    pub mass: f32,
    /// See [`HalfExtents`].
    pub half_extents: Vec3,
    /// See [`GravityRole`].
    pub role: GravityRole,
    /// See [`Interacts`].
    pub interacts: bool,
}

impl BodyState {
    /// A body's state from its components.
    pub fn from_components(
        id: &BodyId,
        position: &Position,
        velocity: &Velocity,
        mass: &Mass,
        half_extents: &HalfExtents,
        role: &GravityRole,
        interacts: &Interacts,
    ) -> Self {
        Self {
            id: *id,
            position: position.0,
            velocity: velocity.0,
            mass: mass.0,
            half_extents: half_extents.0,
            role: *role,
            interacts: interacts.0,
        }
    }

    /// The bundle that spawns this body, at rest in its own previous position.
    pub fn bundle(&self) -> BodyBundle {
        BodyBundle {
            id: self.id,
            position: Position(self.position),
            previous_position: PreviousPosition(self.position),
            velocity: Velocity(self.velocity),
            mass: Mass(self.mass),
            half_extents: HalfExtents(self.half_extents),
            role: self.role,
            interacts: Interacts(self.interacts),
        }
    }
}
