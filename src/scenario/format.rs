//! The scenario file format (docs/design.md, "Scenario files") — a stable
//! contract: field names and defaults must not change.

use serde::Deserialize;

use super::checked;
use crate::components::GravityRole;
use crate::resources::GravityMethod;

/// A whole scenario: physics parameters, explicit bodies and generators.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, rename = "Scenario")]
pub struct Scenario {
    /// Where the scenario was read from, for messages (not part of the file).
    #[serde(skip)]
    pub origin: String,
    /// Shown in summaries and plot titles.
    #[serde(default = "defaults::name", deserialize_with = "checked::name")]
    pub name: String,
    /// `G`; default 6.674 (the thesis).
    #[serde(
        default = "defaults::gravitational_constant",
        deserialize_with = "checked::gravitational_constant"
    )]
    pub gravitational_constant: f32,
    /// Simulated time per update; default 1.
    #[serde(default = "defaults::time_step", deserialize_with = "checked::time_step")]
    pub time_step: f32,
    /// Gravity's softening length `ε`; default 0.
    #[serde(default = "defaults::softening", deserialize_with = "checked::softening")]
    pub softening: f32,
    /// `Auto` (default: `Direct` below
    /// [`AUTO_TREE_FROM`](crate::resources::AUTO_TREE_FROM) sources, else
    /// `Tree(theta: 0.5)`), `Direct` (every source for every adopter) or
    /// `Tree(theta: 0.5)` (Barnes–Hut, for thousands of sources).
    #[serde(default, deserialize_with = "checked::gravity")]
    pub gravity: GravityMethod,
    /// Impact speed from which two interacting bodies shatter; default 3.
    #[serde(
        default = "defaults::shatter_threshold",
        deserialize_with = "checked::shatter_threshold"
    )]
    pub shatter_threshold: f32,
    /// Fragments per shatter, 2 to 1000; default 5.
    #[serde(
        default = "defaults::shatter_fragments",
        deserialize_with = "checked::shatter_fragments"
    )]
    pub shatter_fragments: u32,
    /// Fragments' speed away from their center of mass, as a share of the
    /// impact speed (the thesis's "Streuung"), 0 to 10; default 0.2.
    #[serde(default = "defaults::fragment_spread", deserialize_with = "checked::fragment_spread")]
    pub fragment_spread: f32,
    /// Edge length below which a collision bounces instead of making
    /// fragments (the fragments' edge counts); default 0.5, 0 for none.
    #[serde(
        default = "defaults::min_fragment_size",
        deserialize_with = "checked::min_fragment_size"
    )]
    pub min_fragment_size: f32,
    /// Most bodies: a shatter that would exceed it bounces instead; default
    /// 1 000 000, at most 20 000 000.
    #[serde(default = "defaults::max_bodies", deserialize_with = "checked::max_bodies")]
    pub max_bodies: u64,
    /// Seed of the generators and of the fragments' spread; default 1.
    #[serde(default = "defaults::seed", deserialize_with = "checked::seed")]
    pub seed: u64,
    /// The first id fresh bodies (fragments) get; default: one past the
    /// highest id. Snapshots set it, so that a continued run hands out the
    /// same ids as the run it was saved from.
    #[serde(default, deserialize_with = "checked::next_id")]
    pub next_id: Option<u64>,
    /// Explicitly placed bodies: ids 0, 1, 2… in file order, or each its
    /// own `id` (all of them or none).
    #[serde(default)]
    pub bodies: Vec<Body>,
    /// Seeded random bodies, ids after the explicit ones.
    #[serde(default)]
    pub generators: Vec<Generator>,
}

/// One explicitly placed body.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, rename = "Body")]
pub struct Body {
    /// The body's id (snapshots); default: its place in the list.
    #[serde(default, deserialize_with = "checked::id")]
    pub id: Option<u64>,
    /// Center of the box; required.
    #[serde(deserialize_with = "checked::position")]
    pub position: [f32; 3],
    /// Where the body was an update ago (snapshots); default: `position`.
    #[serde(default, deserialize_with = "checked::previous_position")]
    pub previous_position: Option<[f32; 3]>,
    /// Default (0, 0, 0).
    #[serde(default, deserialize_with = "checked::velocity")]
    pub velocity: [f32; 3],
    /// A box's half extents; default (1, 1, 1): a unit cube, edge 2. Not
    /// with `shape: Sphere`, whose size is its radius.
    #[serde(default, deserialize_with = "checked::optional_half_extents")]
    pub half_extents: Option<[f32; 3]>,
    /// `Box` (default) or `Sphere(radius: R)`, for non-interacting bodies.
    #[serde(default)]
    pub shape: Shape,
    /// Default 1.
    #[serde(default = "defaults::mass", deserialize_with = "checked::mass")]
    pub mass: f32,
    /// Default `Adopter`.
    #[serde(default)]
    pub role: GravityRole,
    /// Default true; false makes an immovable collider.
    #[serde(default = "defaults::interacts")]
    pub interacts: bool,
}

/// What an explicit body collides as.
#[derive(Clone, Copy, Debug, Default, PartialEq, Deserialize)]
pub enum Shape {
    /// An axis-aligned box of the body's `half_extents`.
    #[default]
    Box,
    /// A ball: planets and moons, which do not interact.
    Sphere {
        /// The ball's radius, finite and > 0.
        #[serde(deserialize_with = "checked::radius")]
        radius: f32,
    },
}

impl Body {
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
    /// Bodies to make.
    #[serde(deserialize_with = "checked::count")]
    pub count: u64,
    /// Center of the box that positions are drawn from.
    #[serde(deserialize_with = "checked::center")]
    pub center: [f32; 3],
    /// Half the size of the box that positions are drawn from.
    #[serde(deserialize_with = "checked::half_size")]
    pub half_size: [f32; 3],
    /// Velocity components are uniform in `[-max_speed, max_speed)`.
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
    /// Bodies to make.
    #[serde(deserialize_with = "checked::count")]
    pub count: u64,
    /// Index (in `bodies`) of the source to orbit.
    #[serde(deserialize_with = "checked::around")]
    pub around: usize,
    /// Smallest orbit radius.
    #[serde(deserialize_with = "checked::inner_radius")]
    pub inner_radius: f32,
    /// Largest orbit radius, at least `inner_radius`.
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
    /// As [`Body::half_extents`].
    #[serde(default = "defaults::half_extents", deserialize_with = "checked::half_extents")]
    pub half_extents: [f32; 3],
    /// As [`Body::mass`].
    #[serde(default = "defaults::mass", deserialize_with = "checked::mass")]
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

/// Defaults of omitted fields; the physics ones are
/// [`SimulationSettings::DEFAULT`](crate::resources::SimulationSettings::DEFAULT)'s.
mod defaults {
    use crate::resources::SimulationSettings;

    const PHYSICS: SimulationSettings = SimulationSettings::DEFAULT;

    pub fn name() -> String {
        "Unnamed scenario".to_owned()
    }
    pub fn gravitational_constant() -> f32 {
        PHYSICS.gravitational_constant
    }
    pub fn time_step() -> f32 {
        PHYSICS.time_step
    }
    pub fn softening() -> f32 {
        PHYSICS.softening
    }
    pub fn shatter_threshold() -> f32 {
        PHYSICS.shatter_threshold
    }
    pub fn shatter_fragments() -> u32 {
        PHYSICS.shatter_fragments
    }
    pub fn fragment_spread() -> f32 {
        PHYSICS.fragment_spread
    }
    pub fn seed() -> u64 {
        PHYSICS.seed
    }
    pub fn min_fragment_size() -> f32 {
        PHYSICS.min_fragment_size
    }
    pub fn max_bodies() -> u64 {
        PHYSICS.max_bodies
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
