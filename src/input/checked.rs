//! Value checks done while a file is parsed, so that the parser's error
//! carries the line and column of the offending value. Input files name
//! these in `#[serde(deserialize_with = ...)]` through small wrappers, one
//! per field; every message starts with ``field `NAME`: `` and says the rule
//! and the value (``must be RULE, got VALUE``, or for a body count, how many
//! fit).

use std::fmt::Display;

use serde::de::{Deserialize, Deserializer, Error};

/// Reads a `T`, naming `field` if the value is of the wrong type.
pub fn read<'de, T: Deserialize<'de>, D: Deserializer<'de>>(d: D, field: &str) -> Result<T, D::Error> {
    T::deserialize(d).map_err(|e| D::Error::custom(format!("field `{field}`: {e}")))
}

/// A `T` for which `ok` holds; `rule` says which in words.
fn checked<'de, D, T>(d: D, field: &str, rule: impl Display, ok: impl Fn(&T) -> bool) -> Result<T, D::Error>
where
    D: Deserializer<'de>,
    T: Deserialize<'de> + Display,
{
    let value: T = read(d, field)?;
    if ok(&value) {
        Ok(value)
    } else {
        Err(D::Error::custom(format!(
            "field `{field}`: must be {rule}, got {value}"
        )))
    }
}

/// A finite `f32` for which `ok` holds; `rule` says which in words.
pub fn f32_where<'de, D: Deserializer<'de>>(
    d: D,
    field: &str,
    rule: &str,
    ok: impl Fn(f32) -> bool,
) -> Result<f32, D::Error> {
    checked(d, field, rule, |v: &f32| v.is_finite() && ok(*v))
}

/// Three finite `f32`s (a vector) for each of which `ok` holds.
pub fn vec3_where<'de, D: Deserializer<'de>>(
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

/// A whole number, with the rule it must follow said if the value is not
/// one of its type (negative, too large, not a number).
pub fn whole<'de, T: Deserialize<'de>, D: Deserializer<'de>>(d: D, field: &str, rule: &str) -> Result<T, D::Error> {
    T::deserialize(d).map_err(|e| D::Error::custom(format!("field `{field}`: must be a whole number {rule} ({e})")))
}

/// A whole number from `min` to `max`.
pub fn whole_between<'de, D, T>(d: D, field: &str, min: T, max: T) -> Result<T, D::Error>
where
    D: Deserializer<'de>,
    T: Deserialize<'de> + PartialOrd + Display,
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
    T: Deserialize<'de> + PartialOrd + Display,
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
}
