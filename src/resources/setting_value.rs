//! [`SettingValue`]: what a physics setting's type must do to be read from a
//! file, checked against its rule and shown in a message — the same way
//! for every setting of the list in [`settings`](super::settings).

use std::fmt::Debug;

use serde::de::{Deserializer, Error};
use serde::{Deserialize, Serialize};

use super::{CollisionDetection, FragmentSizes, GravityMethod, Integrator};
use crate::input::{f32_where, shown_number, whole};

/// A physics setting's type.
pub trait SettingValue: Copy + PartialEq + Debug + Serialize + for<'de> Deserialize<'de> + 'static {
    /// Whether the value is usable at all, whatever the setting's rule: a
    /// number must be finite.
    fn sound(&self) -> bool {
        true
    }

    /// The value as a message shows it (`got …`).
    fn shown(&self) -> String;

    /// What replaces this value, which breaks the rule `ok`, where a file
    /// holds it and cannot be refused (the window's saved settings): the
    /// allowed value nearest to it, where the type has an order that makes
    /// one nearest, else `default`, which keeps the rule.
    fn nearest_allowed(self, default: Self, ok: impl Fn(Self) -> bool) -> Self {
        let _ = ok;
        default
    }

    /// Reads a value of this type and holds it to `ok`: ``field `NAME`:
    /// must be RULE, got VALUE`` where it fails, and the field named where
    /// the value is of the wrong type.
    fn read_checked<'de, D: Deserializer<'de>>(
        d: D,
        field: &str,
        rule: &str,
        ok: impl Fn(Self) -> bool,
    ) -> Result<Self, D::Error>;
}

impl SettingValue for f32 {
    /// Read as an `f64` and narrowed once checked, so that a number beyond
    /// `f32`'s range is shown as the file wrote it (`1e39`, not `inf`).
    fn read_checked<'de, D: Deserializer<'de>>(
        d: D,
        field: &str,
        rule: &str,
        ok: impl Fn(Self) -> bool,
    ) -> Result<Self, D::Error> {
        f32_where(d, field, rule, ok)
    }

    fn sound(&self) -> bool {
        self.is_finite()
    }

    fn shown(&self) -> String {
        self.to_string()
    }
}

macro_rules! whole_setting {
    ($($ty:ty),*) => {$(
        impl SettingValue for $ty {
            /// A whole number's message repeats the rule where the value is
            /// not one of its type (negative, too large, not a number).
            fn read_checked<'de, D: Deserializer<'de>>(
                d: D,
                field: &str,
                rule: &str,
                ok: impl Fn(Self) -> bool,
            ) -> Result<Self, D::Error> {
                let value: Self = whole(d, field, rule)?;
                problem(value, rule, ok).map_or(Ok(value), |problem| {
                    Err(D::Error::custom(format!("field `{field}`: {problem}")))
                })
            }

            fn shown(&self) -> String {
                self.to_string()
            }

            /// The allowed end of the rule's range on this value's side of
            /// `default`, found by halving: a whole-number rule is one
            /// range.
            fn nearest_allowed(self, default: Self, ok: impl Fn(Self) -> bool) -> Self {
                let (mut good, mut bad) = (default, self);
                while good.abs_diff(bad) > 1 {
                    let middle = if good < bad {
                        good + (bad - good) / 2
                    } else {
                        bad + (good - bad) / 2
                    };
                    if ok(middle) {
                        good = middle;
                    } else {
                        bad = middle;
                    }
                }
                good
            }
        }
    )*};
}

whole_setting!(u32, u64);

impl SettingValue for GravityMethod {
    fn shown(&self) -> String {
        match self {
            Self::Auto => "Auto".to_owned(),
            Self::Direct => "Direct".to_owned(),
            Self::Tree { theta } => format!("Tree(theta: {theta})"),
        }
    }

    /// Read with `theta` as an `f64`, as [`f32_where`] reads a number, so
    /// that `Tree(theta: 1e39)` is shown so, not as `Tree(theta: inf)`.
    fn read_checked<'de, D: Deserializer<'de>>(
        d: D,
        field: &str,
        rule: &str,
        ok: impl Fn(Self) -> bool,
    ) -> Result<Self, D::Error> {
        /// [`GravityMethod`] as a file writes it, `theta` wide.
        #[derive(Deserialize)]
        #[serde(rename = "GravityMethod")]
        enum Wide {
            Auto,
            Direct,
            Tree { theta: f64 },
        }
        read_wide(
            d,
            field,
            rule,
            "write `Auto`, `Direct` or `Tree(theta: 0.5)`",
            ok,
            |wide| match wide {
                Wide::Auto => (Self::Auto, "Auto".to_owned()),
                Wide::Direct => (Self::Direct, "Direct".to_owned()),
                Wide::Tree { theta } => (
                    // Beyond f32's range this is infinite, and refused.
                    Self::Tree { theta: theta as f32 },
                    format!("Tree(theta: {})", shown_number(theta)),
                ),
            },
        )
    }
}

/// A setting whose values are names alone (`Leapfrog`, `Swept`), each
/// type with its `name()`.
macro_rules! named_setting {
    ($($ty:ty: $hint:literal),*) => {$(
        impl SettingValue for $ty {
            fn shown(&self) -> String {
                self.name().to_owned()
            }

            fn read_checked<'de, D: Deserializer<'de>>(
                d: D,
                field: &str,
                rule: &str,
                ok: impl Fn(Self) -> bool,
            ) -> Result<Self, D::Error> {
                read_wide(d, field, rule, $hint, ok, |value: Self| (value, value.name().to_owned()))
            }
        }
    )*};
}

named_setting!(
    Integrator: "write `Leapfrog` or `SemiImplicitEuler`",
    CollisionDetection: "write `Swept` or `Discrete`"
);

impl SettingValue for FragmentSizes {
    fn sound(&self) -> bool {
        match self {
            Self::Equal => true,
            Self::PowerLaw { exponent } => exponent.is_finite(),
        }
    }

    fn shown(&self) -> String {
        match self {
            Self::Equal => "Equal".to_owned(),
            Self::PowerLaw { exponent } => format!("PowerLaw(exponent: {exponent})"),
        }
    }

    /// Read with `exponent` as an `f64`, as [`f32_where`] reads a number.
    fn read_checked<'de, D: Deserializer<'de>>(
        d: D,
        field: &str,
        rule: &str,
        ok: impl Fn(Self) -> bool,
    ) -> Result<Self, D::Error> {
        /// [`FragmentSizes`] as a file writes it, `exponent` wide.
        #[derive(Deserialize)]
        #[serde(rename = "FragmentSizes")]
        enum Wide {
            Equal,
            PowerLaw { exponent: f64 },
        }
        read_wide(
            d,
            field,
            rule,
            "write `Equal` or `PowerLaw(exponent: 1.71)`",
            ok,
            |wide| match wide {
                Wide::Equal => (Self::Equal, "Equal".to_owned()),
                Wide::PowerLaw { exponent } => (
                    Self::PowerLaw {
                        exponent: exponent as f32,
                    },
                    format!("PowerLaw(exponent: {})", shown_number(exponent)),
                ),
            },
        )
    }
}

/// Reads a setting whose file form `W` holds its numbers wide (`f64`),
/// narrows it with `narrow` (to the value and how the file wrote it), and
/// holds it to `ok`; `hint` says what to write where the form is wrong.
fn read_wide<'de, D, W, T>(
    d: D,
    field: &str,
    rule: &str,
    hint: &str,
    ok: impl Fn(T) -> bool,
    narrow: impl FnOnce(W) -> (T, String),
) -> Result<T, D::Error>
where
    D: Deserializer<'de>,
    W: Deserialize<'de>,
    T: SettingValue,
{
    let wide = W::deserialize(d).map_err(|e| D::Error::custom(format!("field `{field}`: {e} ({hint})")))?;
    let (value, shown) = narrow(wide);
    if value.sound() && ok(value) {
        Ok(value)
    } else {
        Err(D::Error::custom(format!(
            "field `{field}`: must be {rule}, got {shown}"
        )))
    }
}

/// What is wrong with `value` by `rule` (``must be RULE, got VALUE``), if
/// anything.
pub fn problem<T: SettingValue>(value: T, rule: &str, ok: impl Fn(T) -> bool) -> Option<String> {
    (!(value.sound() && ok(value))).then(|| format!("must be {rule}, got {}", value.shown()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_whole_number_against_its_rule_is_replaced_by_the_nearest_allowed() {
        let between = |lo: u32, hi: u32| move |v: u32| (lo..=hi).contains(&v);
        assert_eq!(5000_u32.nearest_allowed(5, between(2, 1000)), 1000);
        assert_eq!(u32::MAX.nearest_allowed(5, between(2, 1000)), 1000);
        assert_eq!(0_u32.nearest_allowed(5, between(2, 1000)), 2);
        assert_eq!(1_u32.nearest_allowed(5, between(2, 1000)), 2);
        assert_eq!(0_u64.nearest_allowed(1_000_000, |v| (1..=20_000_000).contains(&v)), 1);
        assert_eq!(
            f32::NAN.nearest_allowed(0.2, |v: f32| (0.0..=10.0).contains(&v)),
            0.2,
            "no nearest: the default"
        );
        assert_eq!(11.0_f32.nearest_allowed(0.2, |v: f32| (0.0..=10.0).contains(&v)), 0.2);
    }

    #[test]
    fn values_are_shown_as_a_file_writes_them() {
        assert_eq!(GravityMethod::Tree { theta: 0.5 }.shown(), "Tree(theta: 0.5)");
        assert_eq!(GravityMethod::Auto.shown(), "Auto");
        assert_eq!(2.5f32.shown(), "2.5");
        assert_eq!(
            problem(f32::NAN, "finite and >= 0", |v| v >= 0.0).unwrap(),
            "must be finite and >= 0, got NaN"
        );
        assert_eq!(
            problem(-1.0f32, "finite and >= 0", |v| v >= 0.0).unwrap(),
            "must be finite and >= 0, got -1"
        );
        assert_eq!(problem(1.0f32, "finite and >= 0", |v| v >= 0.0), None);
    }

    #[derive(Debug, serde::Deserialize)]
    struct Read(#[serde(deserialize_with = "size")] f32);

    fn size<'de, D: Deserializer<'de>>(d: D) -> Result<f32, D::Error> {
        f32::read_checked(d, "min_fragment_size", "finite and >= 0", |v| v >= 0.0)
    }

    #[derive(Debug, serde::Deserialize)]
    struct Method(#[serde(deserialize_with = "method")] GravityMethod);

    fn method<'de, D: Deserializer<'de>>(d: D) -> Result<GravityMethod, D::Error> {
        GravityMethod::read_checked(d, "gravity", "Tree(theta: θ) with θ finite from 0 to 2", |v| {
            v.check().is_ok()
        })
    }

    #[test]
    fn a_theta_beyond_f32_is_shown_as_written() {
        let read = |text: &str| {
            ron::from_str::<Method>(text)
                .map(|r| r.0)
                .map_err(|e| e.code.to_string())
        };
        assert_eq!(read("(Tree(theta: 0.7))"), Ok(GravityMethod::Tree { theta: 0.7 }));
        assert_eq!(read("(Direct)"), Ok(GravityMethod::Direct));
        for (text, shown) in [
            ("(Tree(theta: 1e39))", "1e39"),
            ("(Tree(theta: 3))", "3"),
            ("(Tree(theta: NaN))", "NaN"),
        ] {
            assert_eq!(
                read(text).unwrap_err(),
                format!("field `gravity`: must be Tree(theta: θ) with θ finite from 0 to 2, got Tree(theta: {shown})")
            );
        }
        assert!(read("(Barnes)").unwrap_err().contains("(write `Auto`"));
    }

    #[test]
    fn a_number_beyond_f32_is_shown_as_written() {
        let read = |text: &str| ron::from_str::<Read>(text).map(|r| r.0).map_err(|e| e.code.to_string());
        assert_eq!(read("(2.5)"), Ok(2.5));
        assert_eq!(read("(3e38)"), Ok(3e38));
        for (text, shown) in [
            ("(1e39)", "1e39"),
            ("(-1e39)", "-1e39"),
            ("(-2)", "-2"),
            ("(-0.5)", "-0.5"),
        ] {
            assert_eq!(
                read(text).unwrap_err(),
                format!("field `min_fragment_size`: must be finite and >= 0, got {shown}")
            );
        }
    }
}
