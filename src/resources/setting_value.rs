//! [`SettingValue`]: what a physics setting's type must do to be read from a
//! file, checked against its rule and shown in a message — the same way
//! for every setting of the list in [`settings`](super::settings).

use std::fmt::Debug;

use serde::de::{Deserializer, Error};
use serde::{Deserialize, Serialize};

use super::GravityMethod;
use crate::input::{read, whole};

/// A physics setting's type.
pub trait SettingValue: Copy + PartialEq + Debug + Serialize + for<'de> Deserialize<'de> {
    /// Reads a value of this type, naming `field` if it is of the wrong
    /// type; `rule` is the setting's rule, which a whole number's message
    /// repeats.
    fn read<'de, D: Deserializer<'de>>(d: D, field: &str, rule: &str) -> Result<Self, D::Error>;

    /// Whether the value is usable at all, whatever the setting's rule: a
    /// number must be finite.
    fn sound(&self) -> bool {
        true
    }

    /// The value as a message shows it (`got …`).
    fn shown(&self) -> String;
}

impl SettingValue for f32 {
    fn read<'de, D: Deserializer<'de>>(d: D, field: &str, _rule: &str) -> Result<Self, D::Error> {
        read(d, field)
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
            fn read<'de, D: Deserializer<'de>>(d: D, field: &str, rule: &str) -> Result<Self, D::Error> {
                whole(d, field, rule)
            }

            fn shown(&self) -> String {
                self.to_string()
            }
        }
    )*};
}

whole_setting!(u32, u64);

impl SettingValue for GravityMethod {
    fn read<'de, D: Deserializer<'de>>(d: D, field: &str, _rule: &str) -> Result<Self, D::Error> {
        Self::deserialize(d).map_err(|e| {
            D::Error::custom(format!(
                "field `{field}`: {e} (write `Auto`, `Direct` or `Tree(theta: 0.5)`)"
            ))
        })
    }

    fn shown(&self) -> String {
        match self {
            Self::Auto => "Auto".to_owned(),
            Self::Direct => "Direct".to_owned(),
            Self::Tree { theta } => format!("Tree(theta: {theta})"),
        }
    }
}

/// Reads a `T` and holds it to `ok`: ``field `NAME`: must be RULE, got
/// VALUE`` where it fails.
pub fn read_checked<'de, T: SettingValue, D: Deserializer<'de>>(
    d: D,
    field: &str,
    rule: &str,
    ok: impl Fn(T) -> bool,
) -> Result<T, D::Error> {
    let value = T::read(d, field, rule)?;
    problem(value, rule, ok).map_or(Ok(value), |problem| {
        Err(D::Error::custom(format!("field `{field}`: {problem}")))
    })
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
}
