//! Lists of a scenario file read so that an error names the item it is
//! in, at every depth: ``field `events[1].bodies[0].mass`: …``. The
//! scenario's `bodies`, `generators` and `events`, and a `Spawn` event's
//! `bodies` and `generators`, are read through [`Listed`].

use std::fmt;
use std::marker::PhantomData;

use serde::Deserialize;
use serde::de::{self, DeserializeSeed, Deserializer, SeqAccess, Visitor};

/// The list named `name` (as its field is), read item by item.
pub struct Listed<T> {
    name: &'static str,
    item: PhantomData<T>,
}

impl<T> Listed<T> {
    /// The reader of the list in field `name`.
    pub fn new(name: &'static str) -> Self {
        Self {
            name,
            item: PhantomData,
        }
    }
}

impl<'de, T: Deserialize<'de>> DeserializeSeed<'de> for Listed<T> {
    type Value = Vec<T>;

    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Vec<T>, D::Error> {
        d.deserialize_seq(self)
    }
}

impl<'de, T: Deserialize<'de>> Visitor<'de> for Listed<T> {
    type Value = Vec<T>;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "a list, as `{}: [...]`", self.name)
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<T>, A::Error> {
        let mut items = Vec::new();
        loop {
            match seq.next_element::<T>() {
                Ok(Some(item)) => items.push(item),
                Ok(None) => return Ok(items),
                Err(e) => {
                    let place = format!("{}[{}]", self.name, items.len());
                    return Err(de::Error::custom(within(&place, &e.to_string())));
                }
            }
        }
    }
}

/// `message` (``field `speed`: …`` or anything else) as said of the field
/// or list item `place`: ``field `place.speed`: …``, ``field `place`: …``.
pub fn within(place: &str, message: &str) -> String {
    match message.strip_prefix("field `") {
        Some(rest) => format!("field `{place}.{rest}"),
        None => format!("field `{place}`: {message}"),
    }
}

/// A `Spawn`'s `bodies`, read as a [`Listed`].
pub fn bodies<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<super::format::Body>, D::Error> {
    Listed::new("bodies").deserialize(d)
}

/// A `Spawn`'s `generators`, read as a [`Listed`].
pub fn generators<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<super::format::Generator>, D::Error> {
    Listed::new("generators").deserialize(d)
}

#[cfg(test)]
mod tests {
    use crate::scenario::Scenario;

    #[test]
    fn an_error_in_a_list_names_its_item_at_every_depth() {
        for (text, field) in [
            (
                "Scenario(bodies: [Body(position: (0, 0, 0)), Body(position: (9, 0, 0), mass: -1)])",
                "field `bodies[1].mass`",
            ),
            (
                "Scenario(generators: [Cloud(count: 1, center: (0, 0, 0), half_size: (1, 1, -1))])",
                "field `generators[0].half_size`",
            ),
            (
                "Scenario(bodies: [Body(position: (0, 0, 0))], events: [Remove(update: 1, body: 0), \
                 Spawn(update: 2, bodies: [Body(position: (5, 0, 0)), Body(position: (9, 0, 0), mass: -1)])])",
                "field `events[1].bodies[1].mass`",
            ),
            (
                "Scenario(events: [Spawn(update: 2, generators: [Cloud(count: 1.5, center: (0, 0, 0), half_size: (1, 1, 1))])])",
                "field `events[0].generators[0].count`: must be a whole number from 0 to 20000000, got 1.5",
            ),
        ] {
            let error = Scenario::parse(text, "s.ron").unwrap_err().to_string();
            assert!(error.contains(field), "{field} not in {error}");
        }
    }
}
