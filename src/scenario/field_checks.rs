//! The checked fields of scenario files other than the physics settings
//! (whose rules are [`crate::resources::rules`]): each
//! a `deserialize_with` reader named after its field, built on the shared
//! checks of [`crate::input`], so that an error names the line, the field
//! and the rule.

use serde::de::{Deserializer, Error};

use crate::input::{body_count, f32_where, vec3_where, whole_between};
use crate::resources::{FragmentSizes, SettingValue};
pub use crate::resources::{MAX_BODIES, MAX_FRAGMENTS, MAX_GRAVITATIONAL_CONSTANT, MAX_ID, MAX_LENGTH, MAX_TIME_STEP};

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

/// Largest coordinate or speed of a body: 1e30.
pub const MAX_STATE: f32 = 1e30;
/// Smallest shell radius: 1e-6.
pub const MIN_RADIUS: f32 = 1e-6;
/// Largest mass.
pub const MAX_MASS: f32 = 1e12;

checked_f32! {
    mass: "finite, > 0 and at most 1e12", |v| v > 0.0 && v <= MAX_MASS;
    max_speed: "finite, from 0 to 1e9", |v| (0.0..=MAX_LENGTH).contains(&v);
    inner_radius: "finite, from 1e-6 to 1e9", |v| (MIN_RADIUS..=MAX_LENGTH).contains(&v);
    outer_radius: "finite, from 1e-6 to 1e9", |v| (MIN_RADIUS..=MAX_LENGTH).contains(&v);
    inclination: "finite and between 0 and 180 degrees", |v| (0.0..=180.0).contains(&v);
    speed_jitter: "finite and between 0 and 1", |v| (0.0..=1.0).contains(&v);
    retrograde_fraction: "finite and between 0 and 1", |v| (0.0..=1.0).contains(&v);
    radius: "finite, > 0 and at most 1e9", |v| v > 0.0 && v <= MAX_LENGTH;
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

/// A body's `id` where given: below [`MAX_ID`] (the next id, which a
/// snapshot writes, is above every id and at most [`MAX_ID`]).
pub fn id<'de, D: Deserializer<'de>>(d: D) -> Result<Option<u64>, D::Error> {
    whole_between(d, "id", 0, MAX_ID - 1).map(Some)
}

/// `next_id` where given: at most [`MAX_ID`].
pub fn next_id<'de, D: Deserializer<'de>>(d: D) -> Result<Option<u64>, D::Error> {
    whole_between(d, "next_id", 0, MAX_ID).map(Some)
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

/// The latest update an event may name: 1e12 (about 30 years at 1 000
/// updates a second).
pub const MAX_EVENT_UPDATE: u64 = 1_000_000_000_000;

/// An event's `update`: at most [`MAX_EVENT_UPDATE`].
pub fn update<'de, D: Deserializer<'de>>(d: D) -> Result<u64, D::Error> {
    whole_between(d, "update", 0, MAX_EVENT_UPDATE)
}

/// A `Fire`'s `target`: a body id, below [`MAX_ID`].
pub fn target<'de, D: Deserializer<'de>>(d: D) -> Result<u64, D::Error> {
    whole_between(d, "target", 0, MAX_ID - 1)
}

/// A `Breakup`'s or `Remove`'s `body`: a body id, below [`MAX_ID`].
pub fn body<'de, D: Deserializer<'de>>(d: D) -> Result<u64, D::Error> {
    whole_between(d, "body", 0, MAX_ID - 1)
}

/// A `Breakup`'s `fragments`: between 2 and [`MAX_FRAGMENTS`].
pub fn fragments<'de, D: Deserializer<'de>>(d: D) -> Result<u32, D::Error> {
    whole_between(d, "fragments", 2, MAX_FRAGMENTS)
}

checked_f32! {
    speed: "finite, from 0 to 1e9", |v| (0.0..=MAX_LENGTH).contains(&v);
    distance: "finite, > 0 and at most 1e9", |v| v > 0.0 && v <= MAX_LENGTH;
}

/// A `Fire`'s `from` where given: every component finite, from -1e9 to
/// 1e9 (that it is not (0, 0, 0) is checked with the scenario).
pub fn from<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[f32; 3]>, D::Error> {
    vec3_where(d, "from", "finite, from -1e9 to 1e9", |v| v.abs() <= MAX_LENGTH).map(Some)
}

/// A `Breakup`'s `sizes` where given: by the rule of the setting
/// `fragment_sizes`.
pub fn sizes<'de, D: Deserializer<'de>>(d: D) -> Result<Option<FragmentSizes>, D::Error> {
    let rule = &crate::resources::rules::FRAGMENT_SIZES;
    FragmentSizes::read_checked(d, "sizes", rule.rule, rule.ok).map(Some)
}
