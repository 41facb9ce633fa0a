//! Value checks done while a file is parsed, so that the parser's error
//! carries the line and column of the offending value. Input files name
//! these in `#[serde(deserialize_with = ...)]` through small wrappers, one
//! per field; every message starts with ``field `NAME`: `` and says the rule
//! and the value (``must be RULE, got VALUE``, or for a body count, how many
//! fit).

use std::fmt::Display;

use serde::de::{Deserialize, Deserializer, Error, Visitor};

/// A field's name, as the file writes it (an identifier): the key of a
/// struct read field by field.
pub struct FieldName(pub String);

impl<'de> Deserialize<'de> for FieldName {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Name;
        impl Visitor<'_> for Name {
            type Value = FieldName;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a field name")
            }
            fn visit_str<E: Error>(self, v: &str) -> Result<FieldName, E> {
                Ok(FieldName(v.to_owned()))
            }
        }
        d.deserialize_identifier(Name)
    }
}

/// Reads a `T`, naming `field` if the value is of the wrong type.
pub fn read<'de, T: Deserialize<'de>, D: Deserializer<'de>>(d: D, field: &str) -> Result<T, D::Error> {
    T::deserialize(d).map_err(|e| D::Error::custom(format!("field `{field}`: {e}")))
}

/// A number as a message shows what the file wrote: read as an `f64`
/// (wider than every number a file holds), so a value beyond `f32`'s range
/// is shown as itself (`1e39`, not `inf`); written in exponent form where
/// plain digits would run long (`1e39`, `1e-45`), else plainly (`-1`,
/// `0.25`).
pub fn shown_number(value: f64) -> String {
    let magnitude = value.abs();
    if value.is_finite() && value != 0.0 && !(1e-5..1e16).contains(&magnitude) {
        format!("{value:e}")
    } else {
        value.to_string()
    }
}

/// `value` narrowed to a finite `f32` for which `ok` holds, if it is one.
fn narrowed(value: f64, ok: &impl Fn(f32) -> bool) -> Option<f32> {
    // Beyond f32's range this is infinite, and refused.
    let narrow = value as f32;
    (narrow.is_finite() && ok(narrow)).then_some(narrow)
}

/// A finite `f32` for which `ok` holds; `rule` says which in words. Read
/// as an `f64` and narrowed once checked, so that the message shows the
/// value as written ([`shown_number`]).
pub fn f32_where<'de, D: Deserializer<'de>>(
    d: D,
    field: &str,
    rule: &str,
    ok: impl Fn(f32) -> bool,
) -> Result<f32, D::Error> {
    let wide: f64 = read(d, field)?;
    narrowed(wide, &ok)
        .ok_or_else(|| D::Error::custom(format!("field `{field}`: must be {rule}, got {}", shown_number(wide))))
}

/// Three finite `f32`s (a vector) for each of which `ok` holds; read and
/// shown as [`f32_where`] does.
pub fn vec3_where<'de, D: Deserializer<'de>>(
    d: D,
    field: &str,
    rule: &str,
    ok: impl Fn(f32) -> bool,
) -> Result<[f32; 3], D::Error> {
    let wide: [f64; 3] = read(d, field)?;
    match wide.map(|c| narrowed(c, &ok)) {
        [Some(x), Some(y), Some(z)] => Ok([x, y, z]),
        _ => {
            let [x, y, z] = wide.map(shown_number);
            Err(D::Error::custom(format!(
                "field `{field}`: every component must be {rule}, got ({x}, {y}, {z})"
            )))
        }
    }
}

/// A number as a file writes it, read whatever its kind, so that a whole
/// number's reader can name the value it refuses: RON reads `1.5` as a
/// whole number `1` followed by `.5`, which the struct around it then
/// refuses as "Expected comma".
enum Written {
    /// A whole number of at least 0 that a `u64` holds.
    Whole(u64),
    /// Anything else that is a number (a fraction, a negative number, one
    /// too large), as the file wrote it.
    Other(String),
}

impl<'de> Deserialize<'de> for Written {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Number;
        impl Visitor<'_> for Number {
            type Value = Written;

            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a number")
            }

            fn visit_u64<E: Error>(self, v: u64) -> Result<Written, E> {
                Ok(Written::Whole(v))
            }

            fn visit_i64<E: Error>(self, v: i64) -> Result<Written, E> {
                Ok(u64::try_from(v).map_or_else(|_| Written::Other(v.to_string()), Written::Whole))
            }

            fn visit_u128<E: Error>(self, v: u128) -> Result<Written, E> {
                Ok(u64::try_from(v).map_or_else(|_| Written::Other(v.to_string()), Written::Whole))
            }

            fn visit_i128<E: Error>(self, v: i128) -> Result<Written, E> {
                Ok(u64::try_from(v).map_or_else(|_| Written::Other(v.to_string()), Written::Whole))
            }

            fn visit_f64<E: Error>(self, v: f64) -> Result<Written, E> {
                Ok(Written::Other(shown_number(v)))
            }
        }
        d.deserialize_any(Number)
    }
}

/// A whole number, with the rule it must follow said if the value is not
/// one of its type (a fraction, negative, too large, not a number).
pub fn whole<'de, T: TryFrom<u64>, D: Deserializer<'de>>(d: D, field: &str, rule: &str) -> Result<T, D::Error> {
    let not_whole =
        |got: &dyn Display| D::Error::custom(format!("field `{field}`: must be a whole number {rule}, got {got}"));
    match Written::deserialize(d)
        .map_err(|e| D::Error::custom(format!("field `{field}`: must be a whole number {rule} ({e})")))?
    {
        Written::Whole(n) => T::try_from(n).map_err(|_| not_whole(&n)),
        Written::Other(text) => Err(not_whole(&text)),
    }
}

/// A whole number from `min` to `max`.
pub fn whole_between<'de, D, T>(d: D, field: &str, min: T, max: T) -> Result<T, D::Error>
where
    D: Deserializer<'de>,
    T: TryFrom<u64> + PartialOrd + Display,
{
    let rule = format!("between {min} and {max}");
    let value: T = whole(d, field, &rule)?;
    if min <= value && value <= max {
        Ok(value)
    } else {
        Err(D::Error::custom(format!(
            "field `{field}`: must be {rule}, got {value}"
        )))
    }
}

/// A whole number of at least `min`.
pub fn whole_at_least<'de, D, T>(d: D, field: &str, min: T) -> Result<T, D::Error>
where
    D: Deserializer<'de>,
    T: TryFrom<u64> + PartialOrd + Display,
{
    let rule = format!("at least {min}");
    let value: T = whole(d, field, &rule)?;
    if min <= value {
        Ok(value)
    } else {
        Err(D::Error::custom(format!(
            "field `{field}`: must be {rule}, got {value}"
        )))
    }
}

/// A count of bodies of at most `max`: more would not fit in memory.
pub fn body_count<'de, D: Deserializer<'de>>(d: D, field: &str, max: u64) -> Result<u64, D::Error> {
    let value: u64 = whole(d, field, &format!("from 0 to {max}"))?;
    if value <= max {
        Ok(value)
    } else {
        Err(D::Error::custom(format!(
            "field `{field}`: {value} bodies would not fit in memory (at most {max})"
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, serde::Deserialize)]
    struct Checked {
        #[serde(deserialize_with = "positive")]
        x: f32,
        #[serde(deserialize_with = "small")]
        n: u32,
    }

    fn positive<'de, D: Deserializer<'de>>(d: D) -> Result<f32, D::Error> {
        f32_where(d, "x", "finite and > 0", |v| v > 0.0)
    }

    fn small<'de, D: Deserializer<'de>>(d: D) -> Result<u32, D::Error> {
        whole_between(d, "n", 1, 9)
    }

    fn parse(text: &str) -> Result<Checked, String> {
        ron::from_str(text).map_err(|e| e.code.to_string())
    }

    #[test]
    fn values_outside_the_rule_name_the_field_the_rule_and_the_value() {
        assert_eq!(parse("(x: 2.5, n: 3)").unwrap().x, 2.5);
        assert_eq!(parse("(x: 2.5, n: 3)").unwrap().n, 3);
        assert_eq!(
            parse("(x: -1.0, n: 3)").unwrap_err(),
            "field `x`: must be finite and > 0, got -1"
        );
        assert_eq!(
            parse("(x: inf, n: 3)").unwrap_err(),
            "field `x`: must be finite and > 0, got inf"
        );
        assert_eq!(
            parse("(x: 1.0, n: 10)").unwrap_err(),
            "field `n`: must be between 1 and 9, got 10"
        );
        assert!(parse("(x: 1.0, n: \"three\")").unwrap_err().starts_with("field `n`: "));
    }

    #[derive(Debug, serde::Deserialize)]
    struct Vector(#[serde(deserialize_with = "finite")] [f32; 3]);

    fn finite<'de, D: Deserializer<'de>>(d: D) -> Result<[f32; 3], D::Error> {
        vec3_where(d, "position", "finite", |_| true)
    }

    #[test]
    fn numbers_beyond_f32_are_shown_as_written_not_as_inf() {
        assert_eq!(
            parse("(x: 1e39, n: 3)").unwrap_err(),
            "field `x`: must be finite and > 0, got 1e39"
        );
        assert_eq!(
            parse("(x: 1e-50, n: 3)").unwrap_err(),
            "field `x`: must be finite and > 0, got 1e-50",
            "it would be 0 as an f32"
        );
        assert_eq!(parse("(x: 3.4e38, n: 3)").unwrap().x, 3.4e38);
        let vector = |text: &str| {
            ron::from_str::<Vector>(text)
                .map(|v| v.0)
                .map_err(|e| e.code.to_string())
        };
        assert_eq!(vector("((1, -2.5, 3e38))"), Ok([1.0, -2.5, 3e38]));
        assert_eq!(
            vector("((1e39, 0, 0))").unwrap_err(),
            "field `position`: every component must be finite, got (1e39, 0, 0)"
        );
        assert_eq!(
            vector("((NaN, -inf, 0.5))").unwrap_err(),
            "field `position`: every component must be finite, got (NaN, -inf, 0.5)"
        );
        for (value, shown) in [
            (-1.0, "-1"),
            (0.0, "0"),
            (0.25, "0.25"),
            (1e-45, "1e-45"),
            (1e16, "1e16"),
        ] {
            assert_eq!(shown_number(value), shown);
        }
    }
}
