//! Timed events in scenario files (docs/design.md, "Events"): bodies
//! spawned, an impactor fired, a body broken up or removed, live settings
//! changed, each after a given number of updates. This file is their
//! format; `src/timed_events/` applies them.

use serde::de::{self, DeserializeSeed, Deserializer, MapAccess};
use serde::ser::{SerializeStruct, Serializer};
use serde::{Deserialize, Serialize};

use super::field_checks;
use super::format::{Body, Generator, Template, given};
use crate::input::{FieldName, ReadByHand, deserialize_by_hand};
use crate::resources::{Applies, FragmentSizes, SettingsPatch, SimulationSettings, setting, settings as settings_list};

/// One event. Each happens after `update` updates have run, before the
/// next; events of one update in file order.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
pub enum Event {
    /// Bodies appear.
    Spawn(Spawn),
    /// An impactor is fired at a body.
    Fire(Fire),
    /// A body explodes into fragments.
    Breakup(Breakup),
    /// A body is taken away.
    Remove(Remove),
    /// Live physics settings change.
    Set(Set),
}

/// See [`Event::Spawn`]: bodies written as in a scenario's `bodies` and
/// `generators`, with fresh ids.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Spawn {
    /// Updates run before it happens.
    #[serde(deserialize_with = "field_checks::update")]
    pub update: u64,
    /// Explicit bodies (without `id`: they get fresh ones, in order).
    #[serde(
        default,
        deserialize_with = "super::listed::bodies",
        skip_serializing_if = "Vec::is_empty"
    )]
    pub bodies: Vec<Body>,
    /// Seeded random bodies; a `Shell`'s `around` is an index into the
    /// scenario's `bodies`, orbited where that body is at the event.
    #[serde(
        default,
        deserialize_with = "super::listed::generators",
        skip_serializing_if = "Vec::is_empty"
    )]
    pub generators: Vec<Generator>,
}

/// See [`Event::Fire`].
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Fire {
    /// Updates run before it happens.
    #[serde(deserialize_with = "field_checks::update")]
    pub update: u64,
    /// The id of the body fired at.
    #[serde(deserialize_with = "field_checks::target")]
    pub target: u64,
    /// The impactor's speed towards the target, relative to it.
    #[serde(deserialize_with = "field_checks::speed")]
    pub speed: f32,
    /// How far from the target's center the impactor starts.
    #[serde(deserialize_with = "field_checks::distance")]
    pub distance: f32,
    /// The direction, from the target, in which the impactor starts (any
    /// length but zero); default: a seeded random direction.
    #[serde(
        default,
        deserialize_with = "field_checks::from",
        skip_serializing_if = "Option::is_none",
        serialize_with = "given"
    )]
    pub from: Option<[f32; 3]>,
    /// What the impactor is made of (default: a unit cube of mass 1).
    #[serde(default)]
    pub body: Template,
}

/// See [`Event::Breakup`].
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Breakup {
    /// Updates run before it happens.
    #[serde(deserialize_with = "field_checks::update")]
    pub update: u64,
    /// The id of the body that breaks up.
    #[serde(deserialize_with = "field_checks::body")]
    pub body: u64,
    /// How many fragments (with `PowerLaw` sizes, the most).
    #[serde(deserialize_with = "field_checks::fragments")]
    pub fragments: u32,
    /// About how fast the fragments fly apart.
    #[serde(deserialize_with = "field_checks::speed")]
    pub speed: f32,
    /// How the fragments are sized; default: the `fragment_sizes` in force.
    #[serde(
        default,
        deserialize_with = "field_checks::sizes",
        skip_serializing_if = "Option::is_none",
        serialize_with = "given"
    )]
    pub sizes: Option<FragmentSizes>,
}

/// See [`Event::Remove`].
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Remove {
    /// Updates run before it happens.
    #[serde(deserialize_with = "field_checks::update")]
    pub update: u64,
    /// The id of the body taken away.
    #[serde(deserialize_with = "field_checks::body")]
    pub body: u64,
}

/// See [`Event::Set`]: live physics settings by their names in scenario
/// files, each checked by its rule.
#[derive(Clone, Debug, PartialEq)]
pub struct Set {
    /// Updates run before it happens.
    pub update: u64,
    /// The live settings it changes, and their new values.
    pub settings: SettingsPatch,
}

impl Set {
    /// A `Set` at `update` of the live settings in which `to` differs
    /// from `from` (none: `None`).
    pub fn between(update: u64, from: &SimulationSettings, to: &SimulationSettings) -> Option<Self> {
        let live = from.differing(to).into_iter().filter(|s| s.applies == Applies::Live);
        let settings = SettingsPatch::of(to, live.map(|s| s.key));
        (!settings.is_empty()).then_some(Self { update, settings })
    }

    /// Takes its values over into `settings`.
    pub fn apply(&self, settings: &mut SimulationSettings) {
        self.settings.apply(settings);
    }
}

impl Event {
    /// Holds the event to the rules an event of a scenario file follows,
    /// by writing it as a file would and reading it back with the file's
    /// own readers: what a tool or an action script records is then what a
    /// file may hold, so every way a body enters the world passes the same
    /// checks (docs/design.md, "Events"). The problem as a file's would be
    /// said.
    pub fn check(&self) -> Result<(), String> {
        let text =
            ron::ser::to_string_pretty(self, super::ron_form::layout().depth_limit(0)).map_err(|e| e.to_string())?;
        crate::input::parse_ron::<Self>(&text, "", super::ron_form::EXTENSIONS)
            .map(drop)
            .map_err(|e| e.message)
    }

    /// Updates run before it happens.
    pub fn update(&self) -> u64 {
        match self {
            Self::Spawn(e) => e.update,
            Self::Fire(e) => e.update,
            Self::Breakup(e) => e.update,
            Self::Remove(e) => e.update,
            Self::Set(e) => e.update,
        }
    }

    /// The same event at another update (a snapshot's, counted from its
    /// own start).
    pub fn at(&self, update: u64) -> Self {
        let mut event = self.clone();
        match &mut event {
            Self::Spawn(e) => e.update = update,
            Self::Fire(e) => e.update = update,
            Self::Breakup(e) => e.update = update,
            Self::Remove(e) => e.update = update,
            Self::Set(e) => e.update = update,
        }
        event
    }

    /// The kind, as files write it.
    pub fn kind(&self) -> &'static str {
        match self {
            Self::Spawn(_) => "Spawn",
            Self::Fire(_) => "Fire",
            Self::Breakup(_) => "Breakup",
            Self::Remove(_) => "Remove",
            Self::Set(_) => "Set",
        }
    }

    /// The body the event acts on, if it names one.
    pub fn body(&self) -> Option<u64> {
        match self {
            Self::Fire(e) => Some(e.target),
            Self::Breakup(e) => Some(e.body),
            Self::Remove(e) => Some(e.body),
            Self::Spawn(_) | Self::Set(_) => None,
        }
    }
}

impl ReadByHand for Set {
    const NAME: &'static str = "Set";
    const FIELDS: &'static [&'static str] = &["update"];
    const EXPECTING: &'static str = "a Set(update: U, <setting>: value, ...)";

    fn read<'de, A: MapAccess<'de>>(mut map: A) -> Result<Self, A::Error> {
        let mut update = None;
        let mut settings = SettingsPatch::default();
        while let Some(FieldName(key)) = map.next_key()? {
            if key == "update" {
                if update.is_some() {
                    return Err(de::Error::custom("duplicate field `update`"));
                }
                update = Some(map.next_value_seed(Update)?);
                continue;
            }
            let live: Vec<String> = settings_list()
                .iter()
                .filter(|s| s.applies == Applies::Live)
                .map(|s| format!("`{}`", s.key))
                .collect();
            let Some(info) = setting(&key) else {
                return Err(de::Error::custom(format!(
                    "unknown field `{key}`, expected `update` or a live setting: {}",
                    live.join(", ")
                )));
            };
            if info.applies != Applies::Live {
                return Err(de::Error::custom(format!(
                    "field `{key}`: is applied on restart, so no event changes it; a Set changes the live \
                     settings: {}",
                    live.join(", ")
                )));
            }
            settings.read_field(info.key, &mut map)?;
        }
        let update = update.ok_or_else(|| de::Error::custom("missing field `update`"))?;
        if settings.is_empty() {
            return Err(de::Error::custom(
                "field `update`: a Set needs at least one live setting beside it",
            ));
        }
        Ok(Set { update, settings })
    }
}

impl<'de> Deserialize<'de> for Set {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        deserialize_by_hand(d)
    }
}

/// An event's checked `update`, as a seed.
struct Update;

impl<'de> DeserializeSeed<'de> for Update {
    type Value = u64;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<u64, D::Error> {
        field_checks::update(d)
    }
}

impl Serialize for Set {
    fn serialize<S: Serializer>(&self, out: S) -> Result<S::Ok, S::Error> {
        let mut s = out.serialize_struct("Set", 1 + self.settings.keys.len())?;
        s.serialize_field("update", &self.update)?;
        self.settings.serialize_fields(&mut s)?;
        s.end()
    }
}
