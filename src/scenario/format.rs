//! The scenario file format's bodies and generators (docs/design.md,
//! "Scenario files") — a stable contract: field names and defaults must
//! not change. The whole file is `contents.rs`; the events are
//! `events.rs`.

use serde::{Deserialize, Serialize, Serializer};

use super::field_checks;
use crate::components::{BodyState, GravityRole};

/// One explicitly placed body.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, rename = "Body")]
pub struct Body {
    /// The body's id (snapshots); default: its place in the list.
    #[serde(
        default,
        deserialize_with = "field_checks::id",
        skip_serializing_if = "Option::is_none",
        serialize_with = "given"
    )]
    pub id: Option<u64>,
    /// Center of the box; required.
    #[serde(deserialize_with = "field_checks::position")]
    pub position: [f32; 3],
    /// Ignored, kept so that older files load: snapshots once wrote where
    /// the body was an update ago, but every update's drift sets that
    /// before anything reads it. Still checked (finite, at most 1e30), and
    /// never written.
    #[serde(
        default,
        deserialize_with = "field_checks::previous_position",
        skip_serializing_if = "Option::is_none",
        serialize_with = "given"
    )]
    pub previous_position: Option<[f32; 3]>,
    /// Default (0, 0, 0).
    #[serde(default, deserialize_with = "field_checks::velocity")]
    pub velocity: [f32; 3],
    /// A box's half extents; default (1, 1, 1): a unit cube, edge 2. Not
    /// with `shape: Sphere`, whose size is its radius.
    #[serde(
        default,
        deserialize_with = "field_checks::optional_half_extents",
        skip_serializing_if = "Option::is_none",
        serialize_with = "given"
    )]
    pub half_extents: Option<[f32; 3]>,
    /// `Box` (default) or `Sphere(radius: R)`, for non-interacting bodies.
    #[serde(default, skip_serializing_if = "Shape::is_box")]
    pub shape: Shape,
    /// Default 1.
    #[serde(default = "defaults::mass", deserialize_with = "field_checks::mass")]
    pub mass: f32,
    /// Default `Adopter`.
    #[serde(default)]
    pub role: GravityRole,
    /// Default true; false makes a non-interacting body (collisions never
    /// move or shatter it; others bounce off it).
    #[serde(default = "defaults::interacts")]
    pub interacts: bool,
    /// Default false; true, on a body that does not interact (a planet),
    /// absorbs every interacting body that touches it: the body is removed
    /// and its mass and momentum counted as absorbed (re-entry).
    #[serde(default, skip_serializing_if = "is_false")]
    pub absorbs: bool,
}

/// Whether a flag is off (left out of a snapshot then).
fn is_false(flag: &bool) -> bool {
    !flag
}

/// What an explicit body collides as.
#[derive(Clone, Copy, Debug, Default, PartialEq, Deserialize, Serialize)]
pub enum Shape {
    /// An axis-aligned box of the body's `half_extents`.
    #[default]
    Box,
    /// A ball: planets and moons, which do not interact.
    Sphere {
        /// The ball's radius, finite and > 0.
        #[serde(deserialize_with = "field_checks::radius")]
        radius: f32,
    },
}

impl Shape {
    /// Whether this is the default, a box.
    pub fn is_box(&self) -> bool {
        matches!(self, Self::Box)
    }
}

/// Writes an optional field that is there as its value alone, as files
/// write it (`id: 4`, not `id: Some(4)`).
pub(super) fn given<T: Serialize, S: Serializer>(value: &Option<T>, out: S) -> Result<S::Ok, S::Error> {
    match value {
        Some(value) => value.serialize(out),
        None => out.serialize_none(),
    }
}

impl Body {
    /// The body's state with id `id` (its `previous_position` is ignored:
    /// the first drift sets it).
    pub fn state(&self, id: u64) -> BodyState {
        let position = bevy::math::Vec3::from_array(self.position);
        BodyState {
            previous: position,
            spherical: matches!(self.shape, Shape::Sphere { .. }),
            absorbs: self.absorbs,
            ..BodyState::new_box(
                crate::components::BodyId(id),
                position,
                bevy::math::Vec3::from_array(self.velocity),
                self.mass,
                bevy::math::Vec3::from_array(self.box_half_extents()),
                self.role,
                self.interacts,
            )
        }
    }

    /// The body `state` is, with its id (as a snapshot writes it).
    pub fn from_state(state: &BodyState) -> Self {
        // A ball's size is its radius; a box's, its half extents.
        let (half_extents, shape) = if state.spherical {
            (
                None,
                Shape::Sphere {
                    radius: state.half_extents.x,
                },
            )
        } else {
            (Some(state.half_extents.to_array()), Shape::Box)
        };
        Self {
            id: Some(state.id.0),
            position: state.position.to_array(),
            previous_position: None,
            velocity: state.velocity.to_array(),
            half_extents,
            shape,
            mass: state.mass,
            role: state.role,
            interacts: state.interacts,
            absorbs: state.absorbs,
        }
    }

    /// The body's shape, size and place in words, for messages: `a Sphere
    /// of radius 430 at (0, 0, 0)`, `a box of half extents (1, 1, 1) at …`.
    pub fn described(&self) -> String {
        let [x, y, z] = self.position;
        match self.shape {
            Shape::Sphere { radius } => format!("a Sphere of radius {radius} at ({x}, {y}, {z})"),
            Shape::Box => {
                let [hx, hy, hz] = self.box_half_extents();
                format!("a box of half extents ({hx}, {hy}, {hz}) at ({x}, {y}, {z})")
            }
        }
    }

    /// Half the edge lengths of the body's box: a ball's bounding box, or
    /// the given ones (default a unit cube).
    pub fn box_half_extents(&self) -> [f32; 3] {
        match self.shape {
            Shape::Box => self.half_extents.unwrap_or_else(defaults::half_extents),
            Shape::Sphere { radius } => [radius; 3],
        }
    }
}

/// Seeded random bodies. Each generator draws from its own random stream,
/// derived from the scenario seed and its position in the list.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
pub enum Generator {
    /// The thesis cloud: bodies uniform in a box, velocity components uniform
    /// in `[-max_speed, max_speed)`, none starting inside a non-interacting body.
    Cloud(Cloud),
    /// A debris shell: near-circular orbits around one source body.
    Shell(Shell),
}

impl Generator {
    /// What each of its bodies is made of.
    pub fn template(&self) -> &Template {
        match self {
            Self::Cloud(c) => &c.body,
            Self::Shell(s) => &s.body,
        }
    }
}

/// See [`Generator::Cloud`].
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Cloud {
    /// Bodies to make.
    #[serde(deserialize_with = "field_checks::count")]
    pub count: u64,
    /// Center of the box that positions are drawn from.
    #[serde(deserialize_with = "field_checks::center")]
    pub center: [f32; 3],
    /// Half the size of the box that positions are drawn from.
    #[serde(deserialize_with = "field_checks::half_size")]
    pub half_size: [f32; 3],
    /// Velocity components are uniform in `[-max_speed, max_speed)`.
    #[serde(default, deserialize_with = "field_checks::max_speed")]
    pub max_speed: f32,
    /// What each generated body is made of (default: unit cube, mass 1, adopter).
    #[serde(default)]
    pub body: Template,
}

/// See [`Generator::Shell`].
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Shell {
    /// Bodies to make.
    #[serde(deserialize_with = "field_checks::count")]
    pub count: u64,
    /// Index (in `bodies`) of the source to orbit.
    #[serde(deserialize_with = "field_checks::around")]
    pub around: usize,
    /// Smallest orbit radius.
    #[serde(deserialize_with = "field_checks::inner_radius")]
    pub inner_radius: f32,
    /// Largest orbit radius, at least `inner_radius`.
    #[serde(deserialize_with = "field_checks::outer_radius")]
    pub outer_radius: f32,
    /// Largest tilt of an orbit plane from the source's equator (the x–z
    /// plane), in degrees; 90 gives orbits in every direction.
    #[serde(default, deserialize_with = "field_checks::inclination")]
    pub inclination: f32,
    /// Relative spread of the orbital speed around circular speed (0.05: ±5 %).
    #[serde(default, deserialize_with = "field_checks::speed_jitter")]
    pub speed_jitter: f32,
    /// Share of bodies orbiting the other way round (head-on crossings).
    #[serde(default, deserialize_with = "field_checks::retrograde_fraction")]
    pub retrograde_fraction: f32,
    /// What each generated body is made of (default: unit cube, mass 1, adopter).
    #[serde(default)]
    pub body: Template,
}

/// What every generated body is made of: a `Body` without position and velocity.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct Template {
    /// As [`Body::half_extents`].
    #[serde(default = "defaults::half_extents", deserialize_with = "field_checks::half_extents")]
    pub half_extents: [f32; 3],
    /// As [`Body::mass`].
    #[serde(default = "defaults::mass", deserialize_with = "field_checks::mass")]
    pub mass: f32,
    /// As [`Body::role`].
    #[serde(default)]
    pub role: GravityRole,
    /// As [`Body::interacts`].
    #[serde(default = "defaults::interacts")]
    pub interacts: bool,
}

impl Default for Template {
    fn default() -> Self {
        Self {
            half_extents: defaults::half_extents(),
            mass: defaults::mass(),
            role: GravityRole::default(),
            interacts: defaults::interacts(),
        }
    }
}

/// Defaults of omitted body and generator fields.
mod defaults {
    pub fn half_extents() -> [f32; 3] {
        [1.0; 3]
    }
    pub fn mass() -> f32 {
        1.0
    }
    pub fn interacts() -> bool {
        true
    }
}
