//! A scenario file's top-level fields, read and written: its own (`name`,
//! `next_id`, `bodies`, `generators`, `events`) and every physics setting,
//! by its name in files and its rule ([`crate::resources::rules`]). Written
//! by hand rather than derived because RON cannot flatten the settings'
//! struct into one that denies unknown fields, and denying them is what
//! turns a misspelled field into an error.

use serde::de::{Deserializer, MapAccess};
use serde::ser::{SerializeStruct, Serializer};
use serde::{Deserialize, Serialize};

use super::contents::Scenario;
use super::field_checks;
use super::listed::Listed;
use crate::input::{ReadByHand, deserialize_by_hand, read_fields};
use crate::resources::{settings, unknown_setting};

/// The scenario's own fields, in file order (the settings come after
/// `name`).
const OWN: [&str; 5] = ["name", "next_id", "bodies", "generators", "events"];

/// A checked `name`.
#[derive(Deserialize)]
#[serde(transparent)]
struct Name(#[serde(deserialize_with = "field_checks::name")] String);

/// A checked `next_id`.
#[derive(Deserialize)]
#[serde(transparent)]
struct NextId(#[serde(deserialize_with = "field_checks::next_id")] Option<u64>);

impl ReadByHand for Scenario {
    const NAME: &'static str = "Scenario";
    const FIELDS: &'static [&'static str] = &OWN;
    const EXPECTING: &'static str = "a Scenario(...)";

    fn read<'de, A: MapAccess<'de>>(map: A) -> Result<Self, A::Error> {
        let mut scenario = Scenario::default();
        read_fields(
            map,
            |key, map| {
                match key {
                    "name" => scenario.name = map.next_value::<Name>()?.0,
                    "next_id" => scenario.next_id = map.next_value::<NextId>()?.0,
                    "bodies" => scenario.bodies = map.next_value_seed(Listed::new("bodies"))?,
                    "generators" => scenario.generators = map.next_value_seed(Listed::new("generators"))?,
                    "events" => scenario.events = map.next_value_seed(Listed::new("events"))?,
                    other => return scenario.physics.read_field(other, map),
                }
                Ok(true)
            },
            |key| unknown_setting(key, &OWN),
        )?;
        Ok(scenario)
    }
}

impl<'de> Deserialize<'de> for Scenario {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        deserialize_by_hand(d)
    }
}

impl Serialize for Scenario {
    fn serialize<S: Serializer>(&self, out: S) -> Result<S::Ok, S::Error> {
        let mut s = out.serialize_struct("Scenario", OWN.len() + settings().len())?;
        s.serialize_field("name", &self.name)?;
        self.physics.serialize_fields(&mut s)?;
        if let Some(next_id) = self.next_id {
            s.serialize_field("next_id", &next_id)?;
        }
        s.serialize_field("bodies", &self.bodies)?;
        if !self.generators.is_empty() {
            s.serialize_field("generators", &self.generators)?;
        }
        if !self.events.is_empty() {
            s.serialize_field("events", &self.events)?;
        }
        s.end()
    }
}
