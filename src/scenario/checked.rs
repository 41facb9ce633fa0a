//! Field readers that reject bad numbers while the file is parsed, so that
//! the parser's error carries the line and column of the offending value.
//!
//! Each public function is a `#[serde(deserialize_with = ...)]` target named
//! after the rule it checks; the message names the field.

use serde::de::{Deserialize, Deserializer, Error};

/// Most bodies one scenario may create: about 200 bytes each in memory, so
/// this bounds a run to a few GiB.
pub const MAX_BODIES: u64 = 20_000_000;

/// Most fragments one shatter may create.
pub const MAX_FRAGMENTS: u32 = 1000;

/// Reads a `T`, naming `field` if the value is of the wrong type.
fn read<'de, T: Deserialize<'de>, D: Deserializer<'de>>(d: D, field: &str) -> Result<T, D::Error> {
    T::deserialize(d).map_err(|e| D::Error::custom(format!("field `{field}`: {e}")))
}

fn check_f32<'de, D: Deserializer<'de>>(
    d: D,
    field: &str,
    rule: &str,
    ok: impl Fn(f32) -> bool,
) -> Result<f32, D::Error> {
    let value: f32 = read(d, field)?;
    if value.is_finite() && ok(value) {
        Ok(value)
    } else {
        Err(D::Error::custom(format!(
            "field `{field}`: must be {rule}, got {value}"
        )))
    }
}

fn check_vec3<'de, D: Deserializer<'de>>(
    d: D,
    field: &str,
    rule: &str,
    ok: impl Fn(f32) -> bool,
) -> Result<[f32; 3], D::Error> {
    let value: [f32; 3] = read(d, field)?;
    if value.iter().all(|c| c.is_finite() && ok(*c)) {
        Ok(value)
    } else {
        let [x, y, z] = value;
        Err(D::Error::custom(format!(
            "field `{field}`: every component must be {rule}, got ({x}, {y}, {z})"
        )))
    }
}

macro_rules! checked_f32 {
    ($($name:ident: $field:literal, $rule:literal, |$v:ident| $ok:expr;)*) => {$(
        #[doc = concat!("`", $field, "`: ", $rule, ".")]
        pub fn $name<'de, D: Deserializer<'de>>(d: D) -> Result<f32, D::Error> {
            check_f32(d, $field, $rule, |$v| $ok)
        }
    )*};
}

macro_rules! checked_vec3 {
    ($($name:ident: $field:literal, $rule:literal, |$v:ident| $ok:expr;)*) => {$(
        #[doc = concat!("`", $field, "`: ", $rule, ".")]
        pub fn $name<'de, D: Deserializer<'de>>(d: D) -> Result<[f32; 3], D::Error> {
            check_vec3(d, $field, $rule, |$v| $ok)
        }
    )*};
}

checked_f32! {
    gravitational_constant: "gravitational_constant", "finite and >= 0", |v| v >= 0.0;
    time_step: "time_step", "finite and > 0", |v| v > 0.0;
    softening: "softening", "finite and >= 0", |v| v >= 0.0;
    shatter_threshold: "shatter_threshold", "finite and >= 0", |v| v >= 0.0;
    mass: "mass", "finite and > 0", |v| v > 0.0;
    max_speed: "max_speed", "finite and >= 0", |v| v >= 0.0;
    inner_radius: "inner_radius", "finite and > 0", |v| v > 0.0;
    outer_radius: "outer_radius", "finite and > 0", |v| v > 0.0;
    inclination: "inclination", "finite and between 0 and 180 degrees", |v| (0.0..=180.0).contains(&v);
    speed_jitter: "speed_jitter", "finite and between 0 and 1", |v| (0.0..=1.0).contains(&v);
    retrograde_fraction: "retrograde_fraction", "finite and between 0 and 1", |v| (0.0..=1.0).contains(&v);
}

checked_vec3! {
    position: "position", "finite", |_v| true;
    velocity: "velocity", "finite", |_v| true;
    center: "center", "finite", |_v| true;
    half_extents: "half_extents", "finite and > 0", |v| v > 0.0;
    half_size: "half_size", "finite and >= 0", |v| v >= 0.0;
}

/// `shatter_fragments`: between 2 and [`MAX_FRAGMENTS`] (0 or 1 fragments
/// would not conserve volume, or divide by zero).
pub fn shatter_fragments<'de, D: Deserializer<'de>>(d: D) -> Result<u32, D::Error> {
    let value: u32 = read(d, "shatter_fragments")?;
    if (2..=MAX_FRAGMENTS).contains(&value) {
        Ok(value)
    } else {
        Err(D::Error::custom(format!(
            "field `shatter_fragments`: must be between 2 and {MAX_FRAGMENTS}, got {value}"
        )))
    }
}

/// A generator's `count`: at most [`MAX_BODIES`].
pub fn count<'de, D: Deserializer<'de>>(d: D) -> Result<u64, D::Error> {
    let value: u64 = read(d, "count")?;
    if value <= MAX_BODIES {
        Ok(value)
    } else {
        Err(D::Error::custom(format!(
            "field `count`: {value} bodies would not fit in memory (at most {MAX_BODIES})"
        )))
    }
}
