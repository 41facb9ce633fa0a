//! The checked fields of scenario files: each a `deserialize_with` reader
//! named after its field, built on the shared checks of
//! [`crate::input`], so that an error names the line, the field and the rule.

use serde::Deserialize;
use serde::de::{Deserializer, Error};

use crate::input::{body_count, f32_where, vec3_where, whole_between};
use crate::resources::GravityMethod;

/// Most bodies one scenario may create: about 200 bytes each in memory, so
/// this bounds a run to a few GiB.
pub const MAX_BODIES: u64 = 20_000_000;

/// Most fragments one shatter may create.
pub const MAX_FRAGMENTS: u32 = 1000;

macro_rules! checked_f32 {
    ($($name:ident: $rule:literal, |$v:ident| $ok:expr;)*) => {$(
        #[doc = concat!("`", stringify!($name), "`: ", $rule, ".")]
        pub fn $name<'de, D: Deserializer<'de>>(d: D) -> Result<f32, D::Error> {
            f32_where(d, stringify!($name), $rule, |$v| $ok)
        }
    )*};
}

macro_rules! checked_vec3 {
    ($($name:ident: $rule:literal, |$v:ident| $ok:expr;)*) => {$(
        #[doc = concat!("`", stringify!($name), "`: every component ", $rule, ".")]
        pub fn $name<'de, D: Deserializer<'de>>(d: D) -> Result<[f32; 3], D::Error> {
            vec3_where(d, stringify!($name), $rule, |$v| $ok)
        }
    )*};
}

// The bounds on magnitudes (docs/design.md, "Scenario files"). They are
// chosen so that everything one update computes stays finite in f32
// (at most 3.4e38) for any values within them:
// - a drift v·dt is at most 1e9 · 1e3 = 1e12;
// - the pull of one source, G·m / d², is at most 1e6 · 1e12 / (2e-6)² =
//   2.5e29, and a kick 2.5e32: bodies that do not overlap are at least two
//   minimum sizes apart (overlapping sources are checked pair by pair when
//   the bodies are made);
// - a Shell's orbital speed √(G·m / r) is at most 1e12;
// - masses, halved and mixed by collisions, stay above f32's smallest
//   normal number for dozens of shatter generations.
// A run that still overflows later (bodies falling into one another without
// softening) stops with a message naming the update and the body.

/// Largest coordinate, speed, size or softening length: 1e9.
pub const MAX_LENGTH: f32 = 1e9;
/// Smallest half extent, radius: 1e-6.
pub const MIN_SIZE: f32 = 1e-6;
/// Smallest and largest mass.
pub const MASS_RANGE: (f32, f32) = (1e-30, 1e12);
/// Largest gravitational constant.
pub const MAX_GRAVITATIONAL_CONSTANT: f32 = 1e6;
/// Largest time step.
pub const MAX_TIME_STEP: f32 = 1e3;

checked_f32! {
    gravitational_constant: "finite, from 0 to 1e6", |v| (0.0..=MAX_GRAVITATIONAL_CONSTANT).contains(&v);
    time_step: "finite, > 0 and at most 1e3", |v| v > 0.0 && v <= MAX_TIME_STEP;
    softening: "finite, from 0 to 1e9", |v| (0.0..=MAX_LENGTH).contains(&v);
    shatter_threshold: "finite and >= 0", |v| v >= 0.0;
    fragment_spread: "finite and between 0 and 10", |v| (0.0..=10.0).contains(&v);
    mass: "finite, from 1e-30 to 1e12", |v| (MASS_RANGE.0..=MASS_RANGE.1).contains(&v);
    max_speed: "finite, from 0 to 1e9", |v| (0.0..=MAX_LENGTH).contains(&v);
    inner_radius: "finite, from 1e-6 to 1e9", |v| (MIN_SIZE..=MAX_LENGTH).contains(&v);
    outer_radius: "finite, from 1e-6 to 1e9", |v| (MIN_SIZE..=MAX_LENGTH).contains(&v);
    inclination: "finite and between 0 and 180 degrees", |v| (0.0..=180.0).contains(&v);
    speed_jitter: "finite and between 0 and 1", |v| (0.0..=1.0).contains(&v);
    retrograde_fraction: "finite and between 0 and 1", |v| (0.0..=1.0).contains(&v);
    radius: "finite, from 1e-6 to 1e9", |v| (MIN_SIZE..=MAX_LENGTH).contains(&v);
    min_fragment_size: "finite and >= 0", |v| v >= 0.0;
}

checked_vec3! {
    position: "finite, from -1e9 to 1e9", |v| v.abs() <= MAX_LENGTH;
    velocity: "finite, from -1e9 to 1e9", |v| v.abs() <= MAX_LENGTH;
    center: "finite, from -1e9 to 1e9", |v| v.abs() <= MAX_LENGTH;
    half_extents: "finite, from 1e-6 to 1e9", |v| (MIN_SIZE..=MAX_LENGTH).contains(&v);
    half_size: "finite, from 0 to 1e9", |v| (0.0..=MAX_LENGTH).contains(&v);
}

/// `previous_position` where given: every component finite, from -1e9 to
/// 1e9.
pub fn previous_position<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[f32; 3]>, D::Error> {
    vec3_where(d, "previous_position", "finite, from -1e9 to 1e9", |v| {
        v.abs() <= MAX_LENGTH
    })
    .map(Some)
}

/// A body's `half_extents` where given: every component finite and > 0.
pub fn optional_half_extents<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[f32; 3]>, D::Error> {
    half_extents(d).map(Some)
}

/// `shatter_fragments`: between 2 and [`MAX_FRAGMENTS`] (0 or 1 fragments
/// would not conserve volume, or divide by zero).
pub fn shatter_fragments<'de, D: Deserializer<'de>>(d: D) -> Result<u32, D::Error> {
    whole_between(d, "shatter_fragments", 2, MAX_FRAGMENTS)
}

/// `gravity`: `Direct`, or `Tree(theta: θ)` with θ from 0 to
/// [`MAX_THETA`](crate::resources::MAX_THETA).
pub fn gravity<'de, D: Deserializer<'de>>(d: D) -> Result<GravityMethod, D::Error> {
    let method = GravityMethod::deserialize(d)
        .map_err(|e| D::Error::custom(format!("field `gravity`: {e} (write `Direct` or `Tree(theta: 0.5)`)")))?;
    method
        .check()
        .map_err(|problem| D::Error::custom(format!("field `gravity`: {problem}")))
}

/// `max_bodies`: from 1 to [`MAX_BODIES`].
pub fn max_bodies<'de, D: Deserializer<'de>>(d: D) -> Result<u64, D::Error> {
    whole_between(d, "max_bodies", 1, MAX_BODIES)
}

/// A generator's `count`: at most [`MAX_BODIES`].
pub fn count<'de, D: Deserializer<'de>>(d: D) -> Result<u64, D::Error> {
    body_count(d, "count", MAX_BODIES)
}
