//! The components that make an entity a simulated body (docs/design.md,
//! "The world").
//!
//! Units are the scenario's own: lengths in "units", time in "steps" scaled by
//! the scenario's `time_step`, mass in "mass units". A body's position is its
//! own [`Position`] component, not a Bevy `Transform`: `Transform` requires a
//! `GlobalTransform` and a `TransformTreeChanged`, about 128 bytes per body
//! with change ticks, where the simulation needs 12 (see ARCHITECTURE.md,
//! "Memory").
//!
//! # Change detection
//!
//! One rule, everywhere: the motion components — [`Position`],
//! [`PreviousPosition`] and [`Velocity`] — are rewritten by the stages every
//! update and are **never marked changed** (the stages write them through
//! `bypass_change_detection`). Marking them would cost a tick write per body
//! per update and tell a reader nothing: every body moves every update. So
//! `Changed<Position>` and its kin never fire for a body; a reader that needs
//! to know whether the bodies moved compares the update count instead (the
//! window's instance upload does). The other components are set when a body
//! is spawned and never written afterwards; `Added<BodyId>` finds new bodies.

use bevy::prelude::*;
use serde::{Deserialize, Serialize};

/// Stable identity of a body: explicit scenario bodies get 0, 1, 2… in file
/// order, then generated ones; fragments get fresh ids. Ids are never reused.
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct BodyId(pub u64);

/// Where the center of the body's box is, in length units. Never marked
/// changed (see the module's change-detection rule).
#[derive(Component, Clone, Copy, Debug, Default, PartialEq)]
pub struct Position(pub Vec3);

/// Linear velocity in length units per unit of time. Never marked changed.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq)]
pub struct Velocity(pub Vec3);

/// Mass in mass units; always finite and > 0.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct Mass(pub f32);

/// Half the edge lengths of the body's axis-aligned box, in units; every
/// component > 0. A "unit cube" has half-extents 1 (edge 2).
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct HalfExtents(pub Vec3);

/// Position before the last integration step, in units. The collision
/// response uses it to find the axes on which two boxes were still apart.
/// Never marked changed.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq)]
pub struct PreviousPosition(pub Vec3);

/// Whether a body attracts others, is attracted, both, or neither.
///
/// Stored only where it is not [`Adopter`](Self::Adopter): a body without
/// the component is an adopter, as most bodies are (every debris cube), so
/// they pay nothing for it (a byte and 8 of change ticks each, 9 MB at a
/// million bodies). Read it with [`GravityRole::of`] from an
/// `Option<&GravityRole>`; a [`BodyState`](super::BodyState) spawned with
/// [`spawn_states`](super::spawn_states) gets it where it needs it.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum GravityRole {
    /// Attracts adopters; not attracted itself.
    Source,
    /// Attracted by every source; attracts nothing.
    #[default]
    Adopter,
    /// Attracts and is attracted (an n-body participant).
    SourceAndAdopter,
    /// Neither: moves only by its own velocity.
    Inert,
}

impl GravityRole {
    /// The role of a body whose stored component is `stored`: none stored
    /// means [`Adopter`](Self::Adopter).
    #[inline]
    pub fn of(stored: Option<&Self>) -> Self {
        stored.copied().unwrap_or(Self::Adopter)
    }

    /// True for every role but [`Adopter`](Self::Adopter): the roles a body
    /// carries as a component.
    pub fn is_stored(self) -> bool {
        self != Self::Adopter
    }

    /// True when this body's mass pulls on adopters.
    pub fn is_source(self) -> bool {
        matches!(self, Self::Source | Self::SourceAndAdopter)
    }

    /// True when this body is pulled by sources.
    pub fn is_adopter(self) -> bool {
        matches!(self, Self::Adopter | Self::SourceAndAdopter)
    }

    /// The name used in scenario files and CSV dumps.
    pub fn name(self) -> &'static str {
        match self {
            Self::Source => "Source",
            Self::Adopter => "Adopter",
            Self::SourceAndAdopter => "SourceAndAdopter",
            Self::Inert => "Inert",
        }
    }
}

/// Marker: the body collides as a ball, not a box. Its radius is its
/// [`HalfExtents`] (equal on all three axes), so the broad phase sees the
/// ball's bounding box and the response tests the ball itself. Only
/// non-interacting bodies (planets, moons) are balls; a body without the
/// marker is a box. Bodies are mostly boxes, so the marker lives only on the
/// few balls and costs the rest nothing.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Spherical;

/// Marker: a non-interacting body (a planet) that absorbs what falls on
/// it: an interacting body that touches it is removed in that update's
/// response, its mass and momentum counted as absorbed (re-entry), where a
/// body without the marker bounces it off. Few bodies carry it, so it
/// costs the rest nothing.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Absorbs;

/// Marker: a non-interacting body (`interacts: false` in a scenario file;
/// the planet, a wall): collisions never move or shatter it; the other body
/// bounces off (or is absorbed, where it carries [`Absorbs`]). Gravity
/// still moves it if it is an adopter, and its own velocity still moves it
/// (a moving wall). Few bodies carry it, so it costs the rest nothing: each
/// component a body has costs it 8 bytes of change ticks besides its own.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NonInteracting;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roles_split_into_source_and_adopter() {
        let flags = |r: GravityRole| (r.is_source(), r.is_adopter());
        assert_eq!(flags(GravityRole::Source), (true, false));
        assert_eq!(flags(GravityRole::Adopter), (false, true));
        assert_eq!(flags(GravityRole::SourceAndAdopter), (true, true));
        assert_eq!(flags(GravityRole::Inert), (false, false));
    }

    #[test]
    fn a_body_without_a_role_is_an_adopter_and_only_adopters_go_unstored() {
        assert_eq!(GravityRole::of(None), GravityRole::Adopter);
        for role in [GravityRole::Source, GravityRole::SourceAndAdopter, GravityRole::Inert] {
            assert_eq!(GravityRole::of(Some(&role)), role);
            assert!(role.is_stored());
        }
        assert!(!GravityRole::Adopter.is_stored());
    }
}
