//! A struct read field by field, by hand: for files whose structs take
//! fields of several owners side by side — a benchmark run's own fields
//! beside its execution options and physics settings, all written flat —
//! which RON cannot flatten into a struct that denies unknown fields.

use serde::de::{Error, MapAccess};

use super::FieldName;

/// Reads every field of `map`: `field` reads the value of the field named
/// by its key and says whether it knows that name; a name it does not know
/// gets `unknown`'s error, a name given twice a "duplicate field" error.
/// Returns the names read, in file order.
pub fn read_fields<'de, A: MapAccess<'de>>(
    mut map: A,
    mut field: impl FnMut(&str, &mut A) -> Result<bool, A::Error>,
    unknown: impl Fn(&str) -> A::Error,
) -> Result<Vec<String>, A::Error> {
    let mut seen: Vec<String> = Vec::new();
    while let Some(FieldName(key)) = map.next_key()? {
        if seen.contains(&key) {
            return Err(A::Error::custom(format!("duplicate field `{key}`")));
        }
        if !field(&key, &mut map)? {
            return Err(unknown(&key));
        }
        seen.push(key);
    }
    Ok(seen)
}

/// An error naming the first of `required` that `seen` lacks, if any.
pub fn require<E: Error>(seen: &[String], required: &[&'static str]) -> Result<(), E> {
    match required.iter().find(|name| !seen.iter().any(|s| s == *name)) {
        Some(name) => Err(E::missing_field(name)),
        None => Ok(()),
    }
}

/// The error for a field that is none of `names` (backticked, in order).
pub fn unknown_field<E: Error>(key: &str, names: &[&str]) -> E {
    let names: Vec<String> = names.iter().map(|name| format!("`{name}`")).collect();
    E::custom(format!("unknown field `{key}`, expected one of {}", names.join(", ")))
}
