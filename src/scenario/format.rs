//! The scenario file format (DESIGN §4) — a stable contract: field names and
//! defaults must not change.

use serde::Deserialize;

use super::checked;
use crate::components::GravityRole;

/// A whole scenario: physics parameters, explicit bodies and generators.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, rename = "Scenario")]
pub struct Scenario {
    #[serde(default = "defaults::name")]
    pub name: String,
    #[serde(
        default = "defaults::gravitational_constant",
        deserialize_with = "checked::gravitational_constant"
    )]
    pub gravitational_constant: f32,
    #[serde(default = "defaults::time_step", deserialize_with = "checked::time_step")]
    pub time_step: f32,
    #[serde(default, deserialize_with = "checked::softening")]
    pub softening: f32,
    #[serde(
        default = "defaults::shatter_threshold",
        deserialize_with = "checked::shatter_threshold"
    )]
    pub shatter_threshold: f32,
    #[serde(
        default = "defaults::shatter_fragments",
        deserialize_with = "checked::shatter_fragments"
    )]
    pub shatter_fragments: u32,
    #[serde(default = "defaults::seed")]
    pub seed: u64,
    #[serde(default)]
    pub bodies: Vec<Body>,
    #[serde(default)]
    pub generators: Vec<Generator>,
}

/// One explicitly placed body.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, rename = "Body")]
pub struct Body {
    #[serde(deserialize_with = "checked::position")]
    pub position: [f32; 3],
    #[serde(default, deserialize_with = "checked::velocity")]
    pub velocity: [f32; 3],
    #[serde(default = "defaults::half_extents", deserialize_with = "checked::half_extents")]
    pub half_extents: [f32; 3],
    #[serde(default = "defaults::mass", deserialize_with = "checked::mass")]
    pub mass: f32,
    #[serde(default)]
    pub role: GravityRole,
    #[serde(default = "defaults::interacts")]
    pub interacts: bool,
}

/// Seeded random bodies. Each generator draws from its own random stream,
/// derived from the scenario seed and its position in the list.
#[derive(Clone, Debug, PartialEq, Deserialize)]
pub enum Generator {
    /// The thesis cloud: bodies uniform in a box, velocity components uniform
    /// in `[-max_speed, max_speed)`, none starting inside a non-interacting body.
    Cloud(Cloud),
    /// A debris shell: near-circular orbits around one source body.
    Shell(Shell),
}

/// See [`Generator::Cloud`].
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Cloud {
    #[serde(deserialize_with = "checked::count")]
    pub count: u64,
    #[serde(deserialize_with = "checked::center")]
    pub center: [f32; 3],
    /// Half the size of the box that positions are drawn from.
    #[serde(deserialize_with = "checked::half_size")]
    pub half_size: [f32; 3],
    #[serde(default, deserialize_with = "checked::max_speed")]
    pub max_speed: f32,
    /// What each generated body is made of (default: unit cube, mass 1, adopter).
    #[serde(default)]
    pub body: Template,
}

/// See [`Generator::Shell`].
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Shell {
    #[serde(deserialize_with = "checked::count")]
    pub count: u64,
    /// Index (in `bodies`) of the source to orbit.
    pub around: usize,
    #[serde(deserialize_with = "checked::inner_radius")]
    pub inner_radius: f32,
    #[serde(deserialize_with = "checked::outer_radius")]
    pub outer_radius: f32,
    /// Largest tilt of an orbit plane from the source's equator (the x–z
    /// plane), in degrees; 90 gives orbits in every direction.
    #[serde(default, deserialize_with = "checked::inclination")]
    pub inclination: f32,
    /// Relative spread of the orbital speed around circular speed (0.05: ±5 %).
    #[serde(default, deserialize_with = "checked::speed_jitter")]
    pub speed_jitter: f32,
    /// Share of bodies orbiting the other way round (head-on crossings).
    #[serde(default, deserialize_with = "checked::retrograde_fraction")]
    pub retrograde_fraction: f32,
    /// What each generated body is made of (default: unit cube, mass 1, adopter).
    #[serde(default)]
    pub body: Template,
}

/// What every generated body is made of: a `Body` without position and velocity.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Template {
    #[serde(default = "defaults::half_extents", deserialize_with = "checked::half_extents")]
    pub half_extents: [f32; 3],
    #[serde(default = "defaults::mass", deserialize_with = "checked::mass")]
    pub mass: f32,
    #[serde(default)]
    pub role: GravityRole,
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

mod defaults {
    pub fn name() -> String {
        "Unnamed scenario".to_owned()
    }
    pub fn gravitational_constant() -> f32 {
        6.674
    }
    pub fn time_step() -> f32 {
        1.0
    }
    pub fn shatter_threshold() -> f32 {
        3.0
    }
    pub fn shatter_fragments() -> u32 {
        5
    }
    pub fn seed() -> u64 {
        1
    }
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
