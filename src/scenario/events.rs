//! Timed events in scenario files (docs/design.md, "Events"): bodies
//! spawned, an impactor fired, a body broken up or removed, live settings
//! changed, each after a given number of updates. This file is their
//! format; `src/timed_events/` applies them.

use std::fmt;

use serde::de::{self, DeserializeSeed, Deserializer, MapAccess, Visitor};
use serde::ser::{SerializeStruct, Serializer};
use serde::{Deserialize, Serialize};

use super::field_checks;
use super::format::{Body, Generator, Template, given};
use crate::input::FieldName;
use crate::resources::{Applies, FragmentSizes, SETTINGS, SimulationSettings, setting};

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
    /// The new values: the defaults with those of `keys` changed.
    pub values: SimulationSettings,
    /// The settings it changes, in file order.
    pub keys: Vec<&'static str>,
}

impl Set {
    /// A `Set` at `update` of the live settings in which `to` differs
    /// from `from` (none: `None`).
    pub fn between(update: u64, from: &SimulationSettings, to: &SimulationSettings) -> Option<Self> {
        let keys: Vec<&'static str> = SETTINGS
            .iter()
            .filter(|s| s.applies == Applies::Live && from.shown(s.key) != to.shown(s.key))
            .map(|s| s.key)
            .collect();
        (!keys.is_empty()).then(|| Self {
            update,
            values: to.clone(),
            keys,
        })
    }

    /// Takes its values over into `settings`.
    pub fn apply(&self, settings: &mut SimulationSettings) {
        for key in &self.keys {
            settings.take(key, &self.values);
        }
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

impl<'de> Deserialize<'de> for Set {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct SetVisitor;
        impl<'de> Visitor<'de> for SetVisitor {
            type Value = Set;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a Set(update: U, <setting>: value, ...)")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Set, A::Error> {
                let mut update = None;
                let mut values = SimulationSettings::DEFAULT;
                let mut keys: Vec<&'static str> = Vec::new();
                while let Some(FieldName(key)) = map.next_key()? {
                    if key == "update" {
                        if update.is_some() {
                            return Err(de::Error::custom("duplicate field `update`"));
                        }
                        update = Some(map.next_value_seed(Update)?);
                        continue;
                    }
                    let live: Vec<String> = SETTINGS
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
                    if keys.contains(&info.key) {
                        return Err(de::Error::custom(format!("duplicate field `{key}`")));
                    }
                    values.read_field(info.key, &mut map)?;
                    keys.push(info.key);
                }
                let update = update.ok_or_else(|| de::Error::custom("missing field `update`"))?;
                if keys.is_empty() {
                    return Err(de::Error::custom(
                        "field `update`: a Set needs at least one live setting beside it",
                    ));
                }
                Ok(Set { update, values, keys })
            }
        }
        d.deserialize_struct("Set", &["update"], SetVisitor)
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
        /// One setting's value, written as the list writes it.
        struct Value<'a>(&'a SimulationSettings, &'static str);
        impl Serialize for Value<'_> {
            fn serialize<S: Serializer>(&self, out: S) -> Result<S::Ok, S::Error> {
                self.0.serialize_value(self.1, out)
            }
        }
        let mut s = out.serialize_struct("Set", 1 + self.keys.len())?;
        s.serialize_field("update", &self.update)?;
        for key in &self.keys {
            s.serialize_field(key, &Value(&self.values, key))?;
        }
        s.end()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::Scenario;

    fn parse(events: &str) -> Result<Vec<Event>, String> {
        Scenario::parse(
            &format!("Scenario(bodies: [Body(position: (0, 0, 0)), Body(position: (5, 0, 0))], events: [{events}])"),
            "e.ron",
        )
        .map(|s| s.events)
        .map_err(|e| e.to_string())
    }

    #[test]
    fn every_kind_reads_with_its_defaults() {
        let events = parse(
            "Spawn(update: 3, bodies: [Body(position: (9, 9, 9))]),
             Fire(update: 4, target: 1, speed: 5, distance: 50),
             Breakup(update: 5, body: 0, fragments: 8, speed: 0.5, sizes: PowerLaw(exponent: 1.6)),
             Remove(update: 6, body: 1),
             Set(update: 7, shatter_threshold: 10, fragment_sizes: PowerLaw(exponent: 1.71))",
        )
        .unwrap();
        assert_eq!(
            events.iter().map(|e| (e.kind(), e.update())).collect::<Vec<_>>(),
            [("Spawn", 3), ("Fire", 4), ("Breakup", 5), ("Remove", 6), ("Set", 7)]
        );
        let Event::Fire(fire) = &events[1] else { unreachable!() };
        assert_eq!((fire.from, fire.body), (None, Template::default()));
        let Event::Set(set) = &events[4] else { unreachable!() };
        assert_eq!(set.keys, ["shatter_threshold", "fragment_sizes"]);
        let mut settings = SimulationSettings::DEFAULT;
        set.apply(&mut settings);
        assert_eq!(settings.shatter_threshold, 10.0);
        assert_eq!(settings.fragment_sizes, FragmentSizes::PowerLaw { exponent: 1.71 });
        assert_eq!(
            settings.shatter_fragments,
            SimulationSettings::DEFAULT.shatter_fragments
        );
    }

    #[test]
    fn bad_events_name_the_event_and_the_field() {
        for (events, needle) in [
            (
                "Fire(update: 4, target: 1, speed: -5, distance: 50)",
                "field `events[0].speed`",
            ),
            (
                "Remove(update: 1), Fire(update: 4, target: 1, speed: NaN, distance: 50)",
                "events[0]",
            ),
            (
                "Remove(update: 1, body: 0), Fire(update: 4, target: 1, speed: NaN, distance: 50)",
                "field `events[1].speed`",
            ),
            ("Remove(update: 1e13, body: 0)", "events[0].update"),
            ("Remove(update: 1000000000001, body: 0)", "events[0].update"),
            (
                "Breakup(update: 1, body: 0, fragments: 1, speed: 1)",
                "events[0].fragments",
            ),
            ("Explode(update: 1, body: 0)", "events[0]"),
            ("Remove(update: 1, body: 0, when: 3)", "`when`"),
            (
                "Set(update: 1, time_step: 2)",
                "events[0].time_step`: is applied on restart",
            ),
            ("Set(update: 1, shatter_threshold: -1)", "events[0].shatter_threshold"),
            ("Set(update: 1, threshold: 1)", "unknown field `threshold`"),
            ("Set(update: 1)", "at least one live setting"),
        ] {
            let e = parse(events).unwrap_err();
            assert!(e.contains(needle) && e.starts_with("e.ron:"), "{events}: {e}");
            assert_eq!(e.lines().count(), 1, "{e}");
        }
    }

    #[test]
    fn a_set_writes_what_it_reads() {
        let text = "Set(update: 9, shatter_fragments: 12, gravity: Tree(theta: 0.5))";
        let events = parse(text).unwrap();
        let written = ron::ser::to_string_pretty(
            &events,
            ron::ser::PrettyConfig::new()
                .struct_names(true)
                .extensions(ron::extensions::Extensions::UNWRAP_VARIANT_NEWTYPES),
        )
        .unwrap();
        let again: Vec<Event> = ron::from_str(&written).unwrap_or_else(|e| panic!("{e}\n{written}"));
        assert_eq!(again, events, "{written}");
    }
}
