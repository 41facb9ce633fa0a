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

checked_f32! {
    gravitational_constant: "finite and >= 0", |v| v >= 0.0;
    time_step: "finite and > 0", |v| v > 0.0;
    softening: "finite and >= 0", |v| v >= 0.0;
    shatter_threshold: "finite and >= 0", |v| v >= 0.0;
    fragment_spread: "finite and between 0 and 10", |v| (0.0..=10.0).contains(&v);
    mass: "finite and > 0", |v| v > 0.0;
    max_speed: "finite and >= 0", |v| v >= 0.0;
    inner_radius: "finite and > 0", |v| v > 0.0;
    outer_radius: "finite and > 0", |v| v > 0.0;
    inclination: "finite and between 0 and 180 degrees", |v| (0.0..=180.0).contains(&v);
    speed_jitter: "finite and between 0 and 1", |v| (0.0..=1.0).contains(&v);
    retrograde_fraction: "finite and between 0 and 1", |v| (0.0..=1.0).contains(&v);
    radius: "finite and > 0", |v| v > 0.0;
    min_fragment_size: "finite and >= 0", |v| v >= 0.0;
}

checked_vec3! {
    position: "finite", |_v| true;
    velocity: "finite", |_v| true;
    center: "finite", |_v| true;
    half_extents: "finite and > 0", |v| v > 0.0;
    half_size: "finite and >= 0", |v| v >= 0.0;
}

/// `previous_position` where given: every component finite.
pub fn previous_position<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[f32; 3]>, D::Error> {
    vec3_where(d, "previous_position", "finite", |_v| true).map(Some)
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
