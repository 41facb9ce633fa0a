//! A struct read field by field, by hand: for files whose structs take
//! fields of several owners side by side — a benchmark run's own fields
//! beside its execution options and physics settings, all written flat —
//! which RON cannot flatten into a struct that denies unknown fields.

use std::fmt;
use std::marker::PhantomData;

use serde::de::{Deserializer, Error, MapAccess, Visitor};

use super::FieldName;

/// A struct whose fields a file gives as `Name(field: value, …)`, read by
/// hand (with [`read_fields`]); [`deserialize_by_hand`] is then the whole
/// of its `Deserialize`.
pub trait ReadByHand: Sized {
    /// Its name in files.
    const NAME: &'static str;
    /// Its own fields' names, as RON is told them.
    const FIELDS: &'static [&'static str];
    /// What a message says a file should give instead of a wrong value,
    /// as "a Run(bodies: …, updates: …)".
    const EXPECTING: &'static str;
    /// Reads it from its fields.
    fn read<'de, A: MapAccess<'de>>(map: A) -> Result<Self, A::Error>;
}

/// A [`ReadByHand`] struct from `d`.
pub fn deserialize_by_hand<'de, T: ReadByHand, D: Deserializer<'de>>(d: D) -> Result<T, D::Error> {
    struct ByHand<T>(PhantomData<T>);
    impl<'de, T: ReadByHand> Visitor<'de> for ByHand<T> {
        type Value = T;
        fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            f.write_str(T::EXPECTING)
        }
        fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<T, A::Error> {
            T::read(map)
        }
    }
    d.deserialize_struct(T::NAME, T::FIELDS, ByHand(PhantomData))
}

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
