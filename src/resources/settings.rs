//! The physics settings, declared once: `physics_settings!` is the one
//! list that gives every setting its name in files, type, default, rule,
//! doc line and whether the window applies it live or on restart. From it
//! come [`SimulationSettings`], the scenario files' fields and their
//! messages ([`SimulationSettings::read_field`]), the checks every other
//! reader uses ([`check`], [`read`]), the table of [`SETTINGS`] that
//! docs/design.md's "Physics settings" table is tested against, and what a
//! snapshot writes ([`SimulationSettings::serialize_fields`]). Adding a
//! setting is a line here and the code that uses it.

use bevy::prelude::*;
use serde::de::{Error, MapAccess};
use serde::ser::SerializeStruct;

use super::setting_value::{SettingValue, problem};
use super::{CollisionDetection, FragmentSizes, GravityMethod, Integrator};

/// Most bodies one run may hold: about 200 bytes each in memory, so this
/// bounds a run to a few GiB.
pub const MAX_BODIES: u64 = 20_000_000;
/// Most fragments one shatter may create.
pub const MAX_FRAGMENTS: u32 = 1000;
/// Largest fragment spread, as a share of the impact speed.
pub const MAX_FRAGMENT_SPREAD: f32 = 10.0;
/// Largest gravitational constant.
pub const MAX_GRAVITATIONAL_CONSTANT: f32 = 1e6;
/// Largest time step.
pub const MAX_TIME_STEP: f32 = 1e3;
/// Largest softening length (and generator coordinate, speed or size).
pub const MAX_LENGTH: f32 = 1e9;

/// When the window applies a setting changed in its panel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Applies {
    /// At once, to the running simulation.
    Live,
    /// When the scene is rebuilt (a restart or another scenario).
    OnRestart,
}

impl Applies {
    /// As the settings table writes it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Live => "live",
            Self::OnRestart => "on restart",
        }
    }
}

/// One row of the settings list, as data.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SettingInfo {
    /// The name in scenario files, `Set` events and messages.
    pub key: &'static str,
    /// The field of [`SimulationSettings`].
    pub field: &'static str,
    /// What it means, in one line.
    pub doc: &'static str,
    /// The rule its values follow, as messages say it (`must be …`).
    pub rule: &'static str,
    /// When the window applies a change.
    pub applies: Applies,
    /// Who else keeps a value of it: `window`, `bench`.
    pub holders: &'static [&'static str],
}

/// The list. `$then!` is called with every setting, in file order, as
/// `/// doc  field (as "key")?: Type = default, "rule", |v| ok, Applies,
/// [holders];`. The holders are who else keeps a value of the setting:
/// `window` (the sandbox's saved settings and its panel) and `bench` (a
/// benchmark run's own value); [`held_by!`] picks the rows of one.
macro_rules! physics_settings {
    ([$($then:tt)*] $($args:tt)*) => {
        $($then)*! { $($args)*
            /// `G`, the gravitational constant (the thesis: 6.674).
            gravitational_constant: f32 = 6.674,
                "finite, from 0 to 1e6", |v| (0.0..=MAX_GRAVITATIONAL_CONSTANT).contains(&v), OnRestart, [];
            /// Simulated time per update, `dt`.
            time_step: f32 = 1.0,
                "finite, > 0 and at most 1e3", |v| v > 0.0 && v <= MAX_TIME_STEP, OnRestart, [];
            /// How an update moves the bodies: `Leapfrog` (drift–kick–drift, second order) or `SemiImplicitEuler` (the thesis: kick, then drift).
            integrator: Integrator = Integrator::Leapfrog,
                "Leapfrog or SemiImplicitEuler", |_| true, Live, [window];
            /// Softening length `ε`: gravity uses `(r² + ε²)^{3/2}`; 0 means none.
            softening: f32 = 0.0,
                "finite, from 0 to 1e9", |v| (0.0..=MAX_LENGTH).contains(&v), OnRestart, [];
            /// How gravity is summed: `Auto` (direct below 512 sources, else the tree), `Direct`, or `Tree(theta: θ)` (Barnes–Hut).
            gravity_method as "gravity": GravityMethod = GravityMethod::Auto,
                "Auto, Direct, or Tree(theta: θ) with θ finite from 0 to 2", |v: GravityMethod| v.check().is_ok(), Live, [window];
            /// How collisions are found: `Swept` (along each body's path over the update, at the time the pair first touches) or `Discrete` (the thesis: where the update ends).
            collision_detection: CollisionDetection = CollisionDetection::Swept,
                "Swept or Discrete", |_| true, Live, [window];
            /// Impact speed (the size of `v1 − v2`) from which two interacting bodies shatter.
            shatter_threshold: f32 = 3.0,
                "finite and >= 0", |v| v >= 0.0, Live, [window, bench];
            /// Fragments one shatter makes (with `PowerLaw` sizes, the most it makes).
            shatter_fragments: u32 = 5,
                "between 2 and 1000", |v| (2..=MAX_FRAGMENTS).contains(&v), Live, [window, bench];
            /// How a shatter sizes its fragments: `Equal` cubes (the thesis), or `PowerLaw(exponent: α)`, edges from the NASA standard breakup model's `N(>L) ∝ L^−α` (1.71 for collisions, 1.6 for explosions).
            fragment_sizes: FragmentSizes = FragmentSizes::Equal,
                "Equal, or PowerLaw(exponent: α) with α finite, > 0 and at most 10", |v: FragmentSizes| v.is_valid(), Live, [window];
            /// Fragments' speed away from their center of mass, as a share of the impact speed (the thesis's "Streuung").
            fragment_spread: f32 = 0.2,
                "finite and between 0 and 10", |v| (0.0..=MAX_FRAGMENT_SPREAD).contains(&v), Live, [window];
            /// Edge length below which a collision bounces instead of making fragments; 0: no floor (the thesis).
            min_fragment_size: f32 = 1.0,
                "finite and >= 0", |v| v >= 0.0, Live, [window];
            /// Most bodies there may be: a shatter that would exceed it bounces instead.
            max_bodies: u64 = 1_000_000,
                "between 1 and 20000000", |v| (1..=MAX_BODIES).contains(&v), Live, [window];
            /// Seed of every random choice: the generators and the fragments' spread.
            seed: u64 = 1,
                "between 0 and 18446744073709551615", |_| true, OnRestart, [window, bench];
        }
    };
}

/// A setting's name in files: its field's, unless the list gives another.
macro_rules! key {
    ($field:ident) => {
        stringify!($field)
    };
    ($field:ident $key:literal) => {
        $key
    };
}

/// Calls `$then!` with the rows that `window` or `bench` holds, in file
/// order, as `/// doc  field (as "key")?: Type = default, "rule", |v| ok,
/// Applies;`. The rule's check is [`check`]`::field` wherever the row is
/// used outside this file.
macro_rules! held_by {
    ($holder:ident $then:ident) => {
        $crate::resources::physics_settings!([$crate::resources::pick_rows] ($holder $then) []);
    };
}

/// [`held_by!`]'s row filter: `(holder then) [rows kept] rows to look at`.
macro_rules! pick_rows {
    (($holder:ident $then:ident) [$($kept:tt)*]) => {
        $then! { $($kept)* }
    };
    ((window $then:ident) [$($kept:tt)*]
        $(#[doc = $doc:literal])* $field:ident $(as $key:literal)?: $ty:ty = $default:expr,
            $rule:literal, $ok:expr, $applies:ident, [window $(, $others:ident)*];
        $($rest:tt)*
    ) => {
        $crate::resources::pick_rows! { (window $then) [$($kept)*
            $(#[doc = $doc])* $field $(as $key)?: $ty = $default, $rule, $ok, $applies;
        ] $($rest)* }
    };
    ((bench $then:ident) [$($kept:tt)*]
        $(#[doc = $doc:literal])* $field:ident $(as $key:literal)?: $ty:ty = $default:expr,
            $rule:literal, $ok:expr, $applies:ident, [$(window,)? bench];
        $($rest:tt)*
    ) => {
        $crate::resources::pick_rows! { (bench $then) [$($kept)*
            $(#[doc = $doc])* $field $(as $key)?: $ty = $default, $rule, $ok, $applies;
        ] $($rest)* }
    };
    (($holder:ident $then:ident) [$($kept:tt)*]
        $(#[doc = $doc:literal])* $field:ident $(as $key:literal)?: $ty:ty = $default:expr,
            $rule:literal, $ok:expr, $applies:ident, [$($holders:ident),*];
        $($rest:tt)*
    ) => {
        $crate::resources::pick_rows! { ($holder $then) [$($kept)*] $($rest)* }
    };
}

pub(crate) use {held_by, key, physics_settings, pick_rows};

/// A setting as a type: what reads its values by its rule. [`rows`] has
/// one for each setting.
pub trait Row {
    /// The setting's type.
    type Value: SettingValue;

    /// Reads a value, checked by the setting's rule.
    fn read<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Self::Value, D::Error>;
}

/// A setting a file may give to override another's value (a benchmark
/// run's own seed, else the scenario's): absent (with `#[serde(default)]`)
/// or the value written plainly, checked by the setting's rule.
pub struct Override<R: Row>(pub Option<R::Value>);

impl<R: Row> Override<R> {
    /// `value` overridden, where a value is given.
    pub fn over(&self, value: &mut R::Value) {
        if let Some(given) = self.0 {
            *value = given;
        }
    }
}

impl<R: Row> Default for Override<R> {
    fn default() -> Self {
        Self(None)
    }
}

impl<R: Row> Clone for Override<R> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<R: Row> Copy for Override<R> {}

impl<R: Row> PartialEq for Override<R> {
    fn eq(&self, other: &Self) -> bool {
        self.0 == other.0
    }
}

impl<R: Row> std::fmt::Debug for Override<R> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.0.fmt(f)
    }
}

impl<'de, R: Row> serde::Deserialize<'de> for Override<R> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        R::read(d).map(|value| Self(Some(value)))
    }
}

/// Everything derived from the list.
macro_rules! derive_settings {
    ($(
        $(#[doc = $doc:literal])*
        $field:ident $(as $key:literal)?: $ty:ty = $default:expr,
            $rule:literal, $ok:expr, $applies:ident, [$($holder:ident),*];
    )*) => {
        /// The physics of one simulation and its stage switches: set from
        /// the scenario, some changeable live (docs/design.md, "Physics
        /// settings").
        #[derive(Resource, Clone, Debug, PartialEq)]
        pub struct SimulationSettings {
            $(
                $(#[doc = $doc])*
                pub $field: $ty,
            )*
            /// Gravity stage on/off. Off: adopters keep their velocity.
            pub gravity: bool,
            /// Broad phase on/off. Off: no pairs, so no responses.
            pub collisions: bool,
            /// Bounce and shatter on/off. Off: pairs are found but not acted on.
            pub collision_response: bool,
        }

        impl SimulationSettings {
            /// Every setting at its default and every stage on: the
            /// defaults of scenario files and of the window's settings.
            pub const DEFAULT: Self = Self {
                $($field: $default,)*
                gravity: true,
                collisions: true,
                collision_response: true,
            };

            /// Reads the value of the setting named `key` from `map` into
            /// `self`, checked by its rule; `Ok(false)` where no setting has
            /// that name (the value is then not read).
            pub fn read_field<'de, A: MapAccess<'de>>(&mut self, key: &str, map: &mut A) -> Result<bool, A::Error> {
                match key {
                    $(key!($field $($key)?) => self.$field = map.next_value_seed(read::Seed::<$ty, _>::new(
                        key!($field $($key)?), $rule, $ok,
                    ))?,)*
                    _ => return Ok(false),
                }
                Ok(true)
            }

            /// Writes every setting, by its name in files, into `out`.
            pub fn serialize_fields<S: SerializeStruct>(&self, out: &mut S) -> Result<(), S::Error> {
                $(out.serialize_field(key!($field $($key)?), &self.$field)?;)*
                Ok(())
            }

            /// Each setting whose value breaks its rule: its name and the
            /// problem (``must be RULE, got VALUE``).
            pub fn problems(&self) -> Vec<(&'static str, String)> {
                let mut found = Vec::new();
                $(if let Err(p) = check::$field(self.$field) {
                    found.push((key!($field $($key)?), p));
                })*
                found
            }

            /// Takes `from`'s value of every setting the window applies
            /// live.
            pub fn take_live(&mut self, from: &Self) {
                $(if Applies::$applies == Applies::Live {
                    self.$field = from.$field;
                })*
            }

            /// Reads a list of values of the setting named `key` from
            /// `map`, each checked by the setting's rule; each value comes
            /// back as the defaults with that one setting changed (take it
            /// over with [`Self::take`]). `Ok(None)` where no setting has
            /// that name (the value is then not read).
            pub fn read_values<'de, A: MapAccess<'de>>(key: &str, map: &mut A) -> Result<Option<Vec<Self>>, A::Error> {
                match key {
                    $(key!($field $($key)?) => {
                        let values = map.next_value_seed(read::ListSeed(read::Seed::<$ty, _>::new(
                            key!($field $($key)?), $rule, $ok,
                        )))?;
                        Ok(Some(values.into_iter().map(|value| Self { $field: value, ..Self::DEFAULT }).collect()))
                    })*
                    _ => Ok(None),
                }
            }

            /// Takes `from`'s value of the setting named `key`; `false`
            /// where no setting has that name.
            pub fn take(&mut self, key: &str, from: &Self) -> bool {
                match key {
                    $(key!($field $($key)?) => self.$field = from.$field,)*
                    _ => return false,
                }
                true
            }

            /// Writes the value of the setting named `key` through `out`.
            pub fn serialize_value<S: serde::Serializer>(&self, key: &str, out: S) -> Result<S::Ok, S::Error> {
                match key {
                    $(key!($field $($key)?) => serde::Serialize::serialize(&self.$field, out),)*
                    _ => Err(serde::ser::Error::custom(format!("no setting is named `{key}`"))),
                }
            }

            /// The value of the setting named `key`, as a file writes it.
            pub fn shown(&self, key: &str) -> Option<String> {
                match key {
                    $(key!($field $($key)?) => Some(self.$field.shown()),)*
                    _ => None,
                }
            }
        }

        /// Every setting, in file order.
        pub const SETTINGS: &[SettingInfo] = &[$(SettingInfo {
            key: key!($field $($key)?),
            field: stringify!($field),
            doc: concat!($($doc),*),
            rule: $rule,
            applies: Applies::$applies,
            holders: &[$(stringify!($holder)),*],
        },)*];

        /// Each setting's rule as a check: `Err(must be RULE, got VALUE)`.
        pub mod check {
            use super::*;
            $(
                #[doc = concat!("`", key!($field $($key)?), "`: ", $rule, ".")]
                pub fn $field(value: $ty) -> Result<(), String> {
                    problem(value, $rule, $ok).map_or(Ok(()), Err)
                }
            )*
        }

        /// Each setting as a type (a [`Row`]), named after its field.
        pub mod rows {
            use super::*;

            $(
                #[doc = concat!("The setting `", key!($field $($key)?), "`.")]
                #[expect(non_camel_case_types, reason = "named after the setting's field, as in `check` and `read`")]
                pub struct $field;

                impl Row for $field {
                    type Value = $ty;

                    fn read<'de, D: serde::Deserializer<'de>>(d: D) -> Result<$ty, D::Error> {
                        read::$field(d)
                    }
                }
            )*
        }

        /// Each setting as a checked `deserialize_with` reader, for files
        /// that take a setting under its own name (benchmark runs).
        pub mod read {
            use std::marker::PhantomData;

            use serde::de::{DeserializeSeed, Deserializer};

            use super::*;

            $(
                #[doc = concat!("Reads `", key!($field $($key)?), "`: ", $rule, ".")]
                pub fn $field<'de, D: Deserializer<'de>>(d: D) -> Result<$ty, D::Error> {
                    <$ty as SettingValue>::read_checked(d, key!($field $($key)?), $rule, $ok)
                }
            )*

            /// A setting's checked reader as a seed, for maps read key by
            /// key.
            pub struct Seed<T, F> {
                key: &'static str,
                rule: &'static str,
                ok: F,
                value: PhantomData<T>,
            }

            impl<T, F> Seed<T, F> {
                /// The reader of `key`, by its rule.
                pub fn new(key: &'static str, rule: &'static str, ok: F) -> Self {
                    Self { key, rule, ok, value: PhantomData }
                }
            }

            impl<'de, T: SettingValue, F: Fn(T) -> bool> DeserializeSeed<'de> for Seed<T, F> {
                type Value = T;

                fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<T, D::Error> {
                    T::read_checked(d, self.key, self.rule, self.ok)
                }
            }

            /// A list of a setting's values, each read by the seed.
            pub struct ListSeed<S>(pub S);

            impl<'de, T: SettingValue, F: Fn(T) -> bool + Copy> DeserializeSeed<'de> for ListSeed<Seed<T, F>> {
                type Value = Vec<T>;

                fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Vec<T>, D::Error> {
                    struct Values<T, F>(Seed<T, F>);
                    impl<'de, T: SettingValue, F: Fn(T) -> bool + Copy> serde::de::Visitor<'de> for Values<T, F> {
                        type Value = Vec<T>;

                        fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                            write!(f, "a list of values of `{}`", self.0.key)
                        }

                        fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<T>, A::Error> {
                            let mut values = Vec::new();
                            while let Some(value) = seq.next_element_seed(Seed::new(self.0.key, self.0.rule, self.0.ok))? {
                                values.push(value);
                            }
                            Ok(values)
                        }
                    }
                    d.deserialize_seq(Values(self.0))
                }
            }
        }
    };
}

physics_settings!([derive_settings]);

impl Default for SimulationSettings {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// The row of the setting named `key`.
pub fn setting(key: &str) -> Option<&'static SettingInfo> {
    SETTINGS.iter().find(|s| s.key == key)
}

/// An error for a key that names no setting, listing the names.
pub fn unknown_setting<E: Error>(key: &str, others: &[&str]) -> E {
    let names: Vec<String> = others
        .iter()
        .copied()
        .chain(SETTINGS.iter().map(|s| s.key))
        .map(|name| format!("`{name}`"))
        .collect();
    E::custom(format!("unknown field `{key}`, expected one of {}", names.join(", ")))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The settings as the Markdown table in docs/design.md ("Physics
    /// settings"), which a test holds to this list.
    pub fn settings_table() -> String {
        let mut table =
            String::from("| setting | default | rule | the window applies it | meaning |\n|---|---|---|---|---|\n");
        for s in SETTINGS {
            let default = SimulationSettings::DEFAULT.shown(s.key).unwrap_or_default();
            table += &format!(
                "| `{}` | `{default}` | {} | {} | {} |\n",
                s.key,
                s.rule,
                s.applies.name(),
                s.doc.trim()
            );
        }
        table
    }

    #[test]
    fn every_default_keeps_its_own_rule() {
        assert_eq!(SimulationSettings::DEFAULT.problems(), []);
        let keys: Vec<_> = SETTINGS.iter().map(|s| s.key).collect();
        let mut unique = keys.clone();
        unique.sort_unstable();
        unique.dedup();
        unique.sort_by_key(|k| keys.iter().position(|o| o == k));
        assert_eq!(keys, unique);
        assert_eq!(setting("gravity").unwrap().field, "gravity_method");
    }

    #[test]
    fn values_against_their_rules_are_named_with_the_rule() {
        let bad = SimulationSettings {
            time_step: 0.0,
            shatter_fragments: 1,
            gravity_method: GravityMethod::Tree { theta: f32::NAN },
            ..SimulationSettings::DEFAULT
        };
        assert_eq!(
            bad.problems(),
            [
                ("time_step", "must be finite, > 0 and at most 1e3, got 0".to_owned()),
                (
                    "gravity",
                    "must be Auto, Direct, or Tree(theta: θ) with θ finite from 0 to 2, got Tree(theta: NaN)"
                        .to_owned()
                ),
                ("shatter_fragments", "must be between 2 and 1000, got 1".to_owned()),
            ]
        );
    }

    #[test]
    fn the_design_documents_table_is_the_list() {
        let design = include_str!("../../docs/design.md");
        let table = settings_table();
        assert!(
            design.contains(&table),
            "docs/design.md's \"Physics settings\" table differs from the list; it should read:\n{table}"
        );
    }

    #[test]
    fn the_rules_say_the_bounds_the_code_holds() {
        let rule = |key| setting(key).unwrap().rule;
        assert_eq!(rule("max_bodies"), format!("between 1 and {MAX_BODIES}"));
        assert_eq!(rule("shatter_fragments"), format!("between 2 and {MAX_FRAGMENTS}"));
        assert_eq!(rule("seed"), format!("between 0 and {}", u64::MAX));
        assert!(rule("fragment_sizes").ends_with(&format!("at most {}", crate::resources::MAX_EXPONENT)));
        assert!(rule("gravity").ends_with(&format!("from 0 to {}", crate::resources::MAX_THETA)));
        for (key, just_inside, just_outside) in [
            (
                "gravitational_constant",
                MAX_GRAVITATIONAL_CONSTANT,
                MAX_GRAVITATIONAL_CONSTANT * 1.001,
            ),
            ("time_step", MAX_TIME_STEP, MAX_TIME_STEP * 1.001),
            ("softening", MAX_LENGTH, MAX_LENGTH * 1.001),
        ] {
            let with = |v: f32| {
                let mut s = SimulationSettings::DEFAULT;
                match key {
                    "gravitational_constant" => s.gravitational_constant = v,
                    "time_step" => s.time_step = v,
                    _ => s.softening = v,
                }
                s.problems().len()
            };
            assert_eq!((with(just_inside), with(just_outside)), (0, 1), "{key}");
        }
    }

    #[test]
    fn live_settings_are_taken_and_the_others_kept() {
        let mut running = SimulationSettings::DEFAULT;
        let panel = SimulationSettings {
            time_step: 0.5,
            shatter_threshold: 9.0,
            seed: 77,
            ..SimulationSettings::DEFAULT
        };
        running.take_live(&panel);
        assert_eq!(running.shatter_threshold, 9.0);
        assert_eq!((running.time_step, running.seed), (1.0, 1), "applied on restart");
    }
}
