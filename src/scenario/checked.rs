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

// The bounds on magnitudes (docs/design.md, "Scenario files"). The
// physics settings and the generators' parameters are bounded so that
// everything one update computes from them stays finite in f32 (at most
// 3.4e38): a drift v·dt at most 1e9 · 1e3, G·m at most 1e6 · 1e12, a
// shell's orbital speed √(G·m / r) at most 1e12. A body's own state may
// go further, as a run takes it (a snapshot of an escaped fragment, a
// fragment of a fragment), up to 1e30 for coordinates and speeds; what
// its first update makes of all of it is checked when the bodies are
// made (`start.rs`). A run that still overflows later stops with a
// message naming the update and the body.

/// Largest generator coordinate, speed or size, and softening length: 1e9.
pub const MAX_LENGTH: f32 = 1e9;
/// Largest coordinate or speed of a body: 1e30.
pub const MAX_STATE: f32 = 1e30;
/// Smallest shell radius: 1e-6.
pub const MIN_RADIUS: f32 = 1e-6;
/// Largest mass.
pub const MAX_MASS: f32 = 1e12;
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
    mass: "finite, > 0 and at most 1e12", |v| v > 0.0 && v <= MAX_MASS;
    max_speed: "finite, from 0 to 1e9", |v| (0.0..=MAX_LENGTH).contains(&v);
    inner_radius: "finite, from 1e-6 to 1e9", |v| (MIN_RADIUS..=MAX_LENGTH).contains(&v);
    outer_radius: "finite, from 1e-6 to 1e9", |v| (MIN_RADIUS..=MAX_LENGTH).contains(&v);
    inclination: "finite and between 0 and 180 degrees", |v| (0.0..=180.0).contains(&v);
    speed_jitter: "finite and between 0 and 1", |v| (0.0..=1.0).contains(&v);
    retrograde_fraction: "finite and between 0 and 1", |v| (0.0..=1.0).contains(&v);
    radius: "finite, > 0 and at most 1e9", |v| v > 0.0 && v <= MAX_LENGTH;
    min_fragment_size: "finite and >= 0", |v| v >= 0.0;
}

checked_vec3! {
    position: "finite, from -1e30 to 1e30", |v| v.abs() <= MAX_STATE;
    velocity: "finite, from -1e30 to 1e30", |v| v.abs() <= MAX_STATE;
    center: "finite, from -1e9 to 1e9", |v| v.abs() <= MAX_LENGTH;
    half_extents: "finite, > 0 and at most 1e9", |v| v > 0.0 && v <= MAX_LENGTH;
    half_size: "finite, from 0 to 1e9", |v| (0.0..=MAX_LENGTH).contains(&v);
}

/// `previous_position` where given: every component finite, from -1e30 to
/// 1e30.
pub fn previous_position<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[f32; 3]>, D::Error> {
    vec3_where(d, "previous_position", "finite, from -1e30 to 1e30", |v| {
        v.abs() <= MAX_STATE
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

/// `gravity`: `Auto`, `Direct`, or `Tree(theta: θ)` with θ from 0 to
/// [`MAX_THETA`](crate::resources::MAX_THETA).
pub fn gravity<'de, D: Deserializer<'de>>(d: D) -> Result<GravityMethod, D::Error> {
    let method = GravityMethod::deserialize(d).map_err(|e| {
        D::Error::custom(format!(
            "field `gravity`: {e} (write `Auto`, `Direct` or `Tree(theta: 0.5)`)"
        ))
    })?;
    method
        .check()
        .map_err(|problem| D::Error::custom(format!("field `gravity`: {problem}")))
}

/// `max_bodies`: from 1 to [`MAX_BODIES`].
pub fn max_bodies<'de, D: Deserializer<'de>>(d: D) -> Result<u64, D::Error> {
    whole_between(d, "max_bodies", 1, MAX_BODIES)
}

/// Longest scenario name, in characters.
pub const MAX_NAME: usize = 200;

/// `name`: at most [`MAX_NAME`] characters, none of them a control
/// character (it is printed in one-line summaries and plot titles).
pub fn name<'de, D: Deserializer<'de>>(d: D) -> Result<String, D::Error> {
    let name: String = crate::input::read(d, "name")?;
    let count = name.chars().count();
    if count > MAX_NAME {
        Err(D::Error::custom(format!(
            "field `name`: must be at most {MAX_NAME} characters, got {count}"
        )))
    } else if name.chars().any(char::is_control) {
        Err(D::Error::custom(
            "field `name`: must not hold control characters (a newline, a tab, an escape)",
        ))
    } else {
        Ok(name)
    }
}

/// Largest body id and `next_id`: 2^62, so that the ids of every body a
/// run can make after it (fragments, one id each) stay far below `u64`'s
/// limit and never wrap.
pub const MAX_ID: u64 = 1 << 62;

/// A body's `id` where given: at most [`MAX_ID`].
pub fn id<'de, D: Deserializer<'de>>(d: D) -> Result<Option<u64>, D::Error> {
    whole_between(d, "id", 0, MAX_ID).map(Some)
}

/// `next_id` where given: at most [`MAX_ID`].
pub fn next_id<'de, D: Deserializer<'de>>(d: D) -> Result<Option<u64>, D::Error> {
    whole_between(d, "next_id", 0, MAX_ID).map(Some)
}

/// `seed`: any whole number from 0 to 2^64 − 1.
pub fn seed<'de, D: Deserializer<'de>>(d: D) -> Result<u64, D::Error> {
    whole_between(d, "seed", 0, u64::MAX)
}

/// A shell's `around`: an index into `bodies` (checked against them
/// later).
pub fn around<'de, D: Deserializer<'de>>(d: D) -> Result<usize, D::Error> {
    whole_between(d, "around", 0, usize::MAX)
}

/// A generator's `count`: at most [`MAX_BODIES`].
pub fn count<'de, D: Deserializer<'de>>(d: D) -> Result<u64, D::Error> {
    body_count(d, "count", MAX_BODIES)
}
