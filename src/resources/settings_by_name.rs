//! The physics settings by their names in files: what reads a setting's
//! value from a file, checked by its [`Rule`], writes it back, shows it in a
//! message, or takes it from other settings. Each is a small [`Visit`] of
//! [`SimulationSettings::visit`], so that every setting is handled alike.

use std::sync::LazyLock;

use serde::de::{DeserializeSeed, Deserializer, Error, MapAccess, SeqAccess, Visitor};
use serde::ser::SerializeStruct;

use super::setting_value::{SettingValue, problem};
use super::settings::{Applies, Rule, SimulationSettings, Visit};

/// A setting's rule without its type: what tables and messages need.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SettingInfo {
    /// The name in scenario files, `Set` events and messages.
    pub key: &'static str,
    /// The field of [`SimulationSettings`].
    pub field: &'static str,
    /// What it means, in one line.
    pub doc: &'static str,
    /// The values allowed, as messages say it (`must be …`).
    pub rule: &'static str,
    /// When the window applies a change.
    pub applies: Applies,
}

/// Every setting, in file order.
pub fn settings() -> &'static [SettingInfo] {
    static LIST: LazyLock<Vec<SettingInfo>> = LazyLock::new(|| {
        struct List(Vec<SettingInfo>);
        impl Visit for List {
            fn setting<T: SettingValue>(&mut self, rule: &Rule<T>, _: &mut T, _: &T) {
                self.0.push(rule.info());
            }
        }
        let mut list = List(Vec::new());
        let mut defaults = SimulationSettings::DEFAULT;
        defaults.visit(&SimulationSettings::DEFAULT, &mut list);
        list.0
    });
    &LIST
}

/// The setting named `key`.
pub fn setting(key: &str) -> Option<&'static SettingInfo> {
    settings().iter().find(|s| s.key == key)
}

/// An error for a key that names no setting, listing the names.
pub fn unknown_setting<E: Error>(key: &str, others: &[&str]) -> E {
    let names: Vec<&str> = others.iter().copied().chain(settings().iter().map(|s| s.key)).collect();
    crate::input::unknown_field(key, &names)
}

impl<T: SettingValue> Rule<T> {
    /// The rule without its type.
    pub fn info(&self) -> SettingInfo {
        SettingInfo {
            key: self.key,
            field: self.field,
            doc: self.doc,
            rule: self.rule,
            applies: self.applies,
        }
    }

    /// What is wrong with `value` by this rule (``must be RULE, got
    /// VALUE``), if anything.
    pub fn problem(&self, value: T) -> Option<String> {
        problem(value, self.rule, self.ok)
    }

    /// Reads a value, checked by this rule: ``field `KEY`: must be RULE,
    /// got VALUE`` where it breaks it (a `deserialize_with` reader's body,
    /// for files that take a setting under its own name).
    pub fn read<'de, D: Deserializer<'de>>(&self, d: D) -> Result<T, D::Error> {
        T::read_checked(d, self.key, self.rule, self.ok)
    }
}

/// A setting's checked reader as a seed, for maps read key by key.
struct Seed<'a, T>(&'a Rule<T>);

impl<'de, T: SettingValue> DeserializeSeed<'de> for Seed<'_, T> {
    type Value = T;

    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<T, D::Error> {
        self.0.read(d)
    }
}

/// A list of values of the setting named `key`, each read by the
/// setting's rule into the defaults with that one setting changed.
struct ListSeed<'k>(&'k str);

impl<'de> DeserializeSeed<'de> for ListSeed<'_> {
    type Value = Vec<SimulationSettings>;

    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Self::Value, D::Error> {
        struct Values<'k>(&'k str);
        impl<'de> Visitor<'de> for Values<'_> {
            type Value = Vec<SimulationSettings>;

            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                write!(f, "a list of values of `{}`", self.0)
            }

            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
                let mut values = Vec::new();
                while let Some(value) = seq.next_element_seed(OneValue(self.0))? {
                    values.push(value);
                }
                Ok(values)
            }
        }
        d.deserialize_seq(Values(self.0))
    }
}

/// One value of the setting named `key`, read by its rule into the
/// defaults with that one setting changed.
struct OneValue<'k>(&'k str);

impl<'de> DeserializeSeed<'de> for OneValue<'_> {
    type Value = SimulationSettings;

    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<SimulationSettings, D::Error> {
        struct ReadOne<D>(D);
        impl<'de, D: Deserializer<'de>> OneSetting<Result<(), D::Error>> for ReadOne<D> {
            fn act<T: SettingValue>(self, rule: &Rule<T>, value: &mut T, _: &T) -> Result<(), D::Error> {
                *value = rule.read(self.0)?;
                Ok(())
            }
        }
        let mut one = SimulationSettings::DEFAULT;
        with_setting(&mut one, &SimulationSettings::DEFAULT, self.0, ReadOne(d))
            .unwrap_or_else(|| Err(D::Error::custom(format!("no setting is named `{}`", self.0))))?;
        Ok(one)
    }
}

/// Visits the one setting named `key` with `act`, which gets its rule, its
/// value here and in `other`; `None` where no setting has that name.
fn with_setting<R>(
    settings: &mut SimulationSettings,
    other: &SimulationSettings,
    key: &str,
    act: impl OneSetting<R>,
) -> Option<R> {
    struct Find<'k, A, R> {
        key: &'k str,
        act: Option<A>,
        out: Option<R>,
    }
    impl<A: OneSetting<R>, R> Visit for Find<'_, A, R> {
        fn setting<T: SettingValue>(&mut self, rule: &Rule<T>, value: &mut T, other: &T) {
            if rule.key == self.key
                && let Some(act) = self.act.take()
            {
                self.out = Some(act.act(rule, value, other));
            }
        }
    }
    let mut find = Find {
        key,
        act: Some(act),
        out: None,
    };
    settings.visit(other, &mut find);
    find.out
}

/// What [`with_setting`] does with the setting it finds.
trait OneSetting<R> {
    /// Acts on the setting.
    fn act<T: SettingValue>(self, rule: &Rule<T>, value: &mut T, other: &T) -> R;
}

impl SimulationSettings {
    /// Reads the value of the setting named `key` from `map` into `self`,
    /// checked by its rule; `Ok(false)` where no setting has that name
    /// (the value is then not read).
    pub fn read_field<'de, A: MapAccess<'de>>(&mut self, key: &str, map: &mut A) -> Result<bool, A::Error> {
        struct Read<'m, A>(&'m mut A);
        impl<'de, A: MapAccess<'de>> OneSetting<Result<(), A::Error>> for Read<'_, A> {
            fn act<T: SettingValue>(self, rule: &Rule<T>, value: &mut T, _: &T) -> Result<(), A::Error> {
                *value = self.0.next_value_seed(Seed(rule))?;
                Ok(())
            }
        }
        let other = self.clone();
        with_setting(self, &other, key, Read(map))
            .transpose()
            .map(|found| found.is_some())
    }

    /// Reads the value of the setting whose field is named `field` from
    /// `map`, of its type but not held to its rule (a file whose values are
    /// fixed afterwards, not refused: the window's settings); `Ok(false)`
    /// where no setting has that field (the value is then not read).
    pub fn read_field_unchecked<'de, A: MapAccess<'de>>(&mut self, field: &str, map: &mut A) -> Result<bool, A::Error> {
        struct Read<'m, A>(&'m mut A);
        impl<'de, A: MapAccess<'de>> OneSetting<Result<(), A::Error>> for Read<'_, A> {
            fn act<T: SettingValue>(self, _: &Rule<T>, value: &mut T, _: &T) -> Result<(), A::Error> {
                *value = self.0.next_value()?;
                Ok(())
            }
        }
        let Some(key) = settings().iter().find(|s| s.field == field).map(|s| s.key) else {
            return Ok(false);
        };
        let other = self.clone();
        with_setting(self, &other, key, Read(map))
            .transpose()
            .map(|found| found.is_some())
    }

    /// Reads a list of values of the setting named `key` from `map`, each
    /// checked by the setting's rule; each value comes back as the
    /// defaults with that one setting changed (take it over with
    /// [`Self::take`]). `Ok(None)` where no setting has that name (the
    /// value is then not read).
    pub fn read_values<'de, A: MapAccess<'de>>(key: &str, map: &mut A) -> Result<Option<Vec<Self>>, A::Error> {
        if setting(key).is_none() {
            return Ok(None);
        }
        map.next_value_seed(ListSeed(key)).map(Some)
    }

    /// Writes every setting, by its name in files, into `out`.
    pub fn serialize_fields<S: SerializeStruct>(&self, out: &mut S) -> Result<(), S::Error> {
        struct Write<'o, S: SerializeStruct>(&'o mut S, Result<(), S::Error>);
        impl<S: SerializeStruct> Visit for Write<'_, S> {
            fn setting<T: SettingValue>(&mut self, rule: &Rule<T>, value: &mut T, _: &T) {
                if self.1.is_ok() {
                    self.1 = self.0.serialize_field(rule.key, value);
                }
            }
        }
        let mut write = Write(out, Ok(()));
        self.clone().visit(self, &mut write);
        write.1
    }

    /// Writes the value of the setting named `key` through `out`.
    pub fn serialize_value<S: serde::Serializer>(&self, key: &str, out: S) -> Result<S::Ok, S::Error> {
        struct Write<S>(S);
        impl<S: serde::Serializer> OneSetting<Result<S::Ok, S::Error>> for Write<S> {
            fn act<T: SettingValue>(self, _: &Rule<T>, value: &mut T, _: &T) -> Result<S::Ok, S::Error> {
                value.serialize(self.0)
            }
        }
        let mut own = self.clone();
        with_setting(&mut own, self, key, Write(out))
            .unwrap_or_else(|| Err(serde::ser::Error::custom(format!("no setting is named `{key}`"))))
    }

    /// The value of the setting named `key`, as a file writes it.
    pub fn shown(&self, key: &str) -> Option<String> {
        struct Show;
        impl OneSetting<String> for Show {
            fn act<T: SettingValue>(self, _: &Rule<T>, value: &mut T, _: &T) -> String {
                value.shown()
            }
        }
        with_setting(&mut self.clone(), self, key, Show)
    }

    /// Takes `from`'s value of the setting named `key`; `false` where no
    /// setting has that name.
    pub fn take(&mut self, key: &str, from: &Self) -> bool {
        struct Take;
        impl OneSetting<()> for Take {
            fn act<T: SettingValue>(self, _: &Rule<T>, value: &mut T, other: &T) {
                *value = *other;
            }
        }
        with_setting(self, from, key, Take).is_some()
    }

    /// Takes `from`'s value of every setting the window applies live.
    pub fn take_live(&mut self, from: &Self) {
        struct TakeLive;
        impl Visit for TakeLive {
            fn setting<T: SettingValue>(&mut self, rule: &Rule<T>, value: &mut T, other: &T) {
                if rule.applies == Applies::Live {
                    *value = *other;
                }
            }
        }
        self.visit(from, &mut TakeLive);
    }

    /// The settings whose values differ between `self` and `other` (as a
    /// file writes them, so a NaN equals a NaN), by their names, in file
    /// order.
    pub fn differing(&self, other: &Self) -> Vec<&'static SettingInfo> {
        settings()
            .iter()
            .filter(|s| self.shown(s.key) != other.shown(s.key))
            .collect()
    }

    /// Each setting whose value breaks its rule: its name and the problem
    /// (``must be RULE, got VALUE``).
    pub fn problems(&self) -> Vec<(&'static str, String)> {
        struct Problems(Vec<(&'static str, String)>);
        impl Visit for Problems {
            fn setting<T: SettingValue>(&mut self, rule: &Rule<T>, value: &mut T, _: &T) {
                if let Some(problem) = rule.problem(*value) {
                    self.0.push((rule.key, problem));
                }
            }
        }
        let mut found = Problems(Vec::new());
        self.clone().visit(self, &mut found);
        found.0
    }

    /// Each setting whose value breaks its rule replaced by the nearest
    /// allowed value (or the default, where there is none, see
    /// [`SettingValue::nearest_allowed`]); calls `fixed` with the setting,
    /// the value as a file writes it, and the value used instead.
    pub fn fix_problems(&mut self, mut fixed: impl FnMut(&SettingInfo, String, String)) {
        struct Fix<F>(F);
        impl<F: FnMut(&SettingInfo, String, String)> Visit for Fix<F> {
            fn setting<T: SettingValue>(&mut self, rule: &Rule<T>, value: &mut T, default: &T) {
                if rule.problem(*value).is_some() {
                    let used = value.nearest_allowed(*default, |v| rule.problem(v).is_none());
                    (self.0)(&rule.info(), as_written(value), as_written(&used));
                    *value = used;
                }
            }
        }
        self.visit(&Self::DEFAULT, &mut Fix(&mut fixed));
    }
}

/// `value` as a settings file writes it, on one line: `Tree(theta: NaN)`,
/// `2.5`.
pub fn as_written<T: serde::Serialize>(value: &T) -> String {
    let one_line = ron::ser::PrettyConfig::new().depth_limit(0);
    ron::ser::to_string_pretty(value, one_line).unwrap_or_else(|e| format!("(not writable: {e})"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::resources::settings::{
        MAX_BODIES, MAX_FRAGMENTS, MAX_GRAVITATIONAL_CONSTANT, MAX_LENGTH, MAX_TIME_STEP,
    };
    use crate::resources::{FragmentSizes, GravityMethod};

    /// One setting's value, written by its name.
    struct Shown<'a>(&'a SimulationSettings, &'static str);

    impl serde::Serialize for Shown<'_> {
        fn serialize<S: serde::Serializer>(&self, out: S) -> Result<S::Ok, S::Error> {
            self.0.serialize_value(self.1, out)
        }
    }

    /// The settings as the Markdown table in docs/design.md ("Physics
    /// settings"), which a test holds to the rules.
    pub fn settings_table() -> String {
        let mut table =
            String::from("| setting | default | rule | the window applies it | meaning |\n|---|---|---|---|---|\n");
        for s in settings() {
            let default = SimulationSettings::DEFAULT.shown(s.key).unwrap_or_default();
            table += &format!(
                "| `{}` | `{default}` | {} | {} | {} |\n",
                s.key,
                s.rule,
                s.applies.name(),
                s.doc.trim()
            );
        }
        table
    }

    #[test]
    fn every_default_keeps_its_own_rule() {
        assert_eq!(SimulationSettings::DEFAULT.problems(), []);
        let keys: Vec<_> = settings().iter().map(|s| s.key).collect();
        let mut unique = keys.clone();
        unique.sort_unstable();
        unique.dedup();
        assert_eq!(keys.len(), unique.len(), "{keys:?}");
        assert_eq!(setting("gravity").unwrap().field, "gravity_method");
    }

    /// Every rule names the field it is visited with: each setting's value
    /// is read, written and taken under its own name.
    #[test]
    fn each_name_reaches_its_own_field() {
        let mut changed = SimulationSettings::DEFAULT;
        let mut by_key = SimulationSettings::DEFAULT;
        let other = SimulationSettings {
            gravitational_constant: 2.0,
            time_step: 0.5,
            integrator: crate::resources::Integrator::SemiImplicitEuler,
            softening: 3.0,
            gravity_method: GravityMethod::Direct,
            collision_detection: crate::resources::CollisionDetection::Discrete,
            shatter_threshold: 4.0,
            shatter_fragments: 7,
            fragment_sizes: FragmentSizes::PowerLaw { exponent: 1.6 },
            fragment_spread: 0.4,
            min_fragment_size: 0.5,
            max_bodies: 9,
            seed: 8,
            ..SimulationSettings::DEFAULT
        };
        assert_eq!(
            SimulationSettings::DEFAULT.differing(&other).len(),
            settings().len(),
            "the test changes every setting"
        );
        // The field a rule names holds the value read and written by its
        // key.
        let ron::Value::Map(fields) = ron::from_str(&ron::to_string(&other).unwrap()).unwrap() else {
            panic!("settings are written as a map");
        };
        for s in settings() {
            assert!(by_key.take(s.key, &other), "{}", s.key);
            let by_name: ron::Value = ron::from_str(&as_written(&Shown(&other, s.key))).unwrap();
            assert_eq!(
                fields.get(&ron::Value::String(s.field.to_owned())),
                Some(&by_name),
                "{}",
                s.key
            );
        }
        assert_eq!(by_key, other);
        changed.take_live(&other);
        for s in settings() {
            let taken = changed.shown(s.key) == other.shown(s.key);
            assert_eq!(taken, s.applies == Applies::Live, "{}", s.key);
        }
    }

    #[test]
    fn values_against_their_rules_are_named_with_the_rule() {
        let bad = SimulationSettings {
            time_step: 0.0,
            shatter_fragments: 1,
            gravity_method: GravityMethod::Tree { theta: f32::NAN },
            ..SimulationSettings::DEFAULT
        };
        assert_eq!(
            bad.problems(),
            [
                ("time_step", "must be finite, > 0 and at most 1e3, got 0".to_owned()),
                (
                    "gravity",
                    "must be Auto, Direct, or Tree(theta: θ) with θ finite from 0 to 2, got Tree(theta: NaN)"
                        .to_owned()
                ),
                ("shatter_fragments", "must be between 2 and 1000, got 1".to_owned()),
            ]
        );
        let mut fixed = bad.clone();
        let mut said = Vec::new();
        fixed.fix_problems(|info, found, used| said.push(format!("{} {found} -> {used}", info.field)));
        assert_eq!(
            said,
            [
                "time_step 0.0 -> 1.0",
                "gravity_method Tree(theta: NaN) -> Auto",
                "shatter_fragments 1 -> 2"
            ]
        );
        assert_eq!(fixed.problems(), []);
    }

    #[test]
    fn the_design_documents_table_is_the_list() {
        let design = include_str!("../../docs/design.md");
        let table = settings_table();
        assert!(
            design.contains(&table),
            "docs/design.md's \"Physics settings\" table differs from the rules; it should read:\n{table}"
        );
    }

    #[test]
    fn the_rules_say_the_bounds_the_code_holds() {
        let rule = |key| setting(key).unwrap().rule;
        assert_eq!(rule("max_bodies"), format!("between 1 and {MAX_BODIES}"));
        assert_eq!(rule("shatter_fragments"), format!("between 2 and {MAX_FRAGMENTS}"));
        assert_eq!(rule("seed"), format!("between 0 and {}", u64::MAX));
        assert!(rule("fragment_sizes").ends_with(&format!("at most {}", crate::resources::MAX_EXPONENT)));
        assert!(rule("gravity").ends_with(&format!("from 0 to {}", crate::resources::MAX_THETA)));
        for (key, just_inside, just_outside) in [
            (
                "gravitational_constant",
                MAX_GRAVITATIONAL_CONSTANT,
                MAX_GRAVITATIONAL_CONSTANT * 1.001,
            ),
            ("time_step", MAX_TIME_STEP, MAX_TIME_STEP * 1.001),
            ("softening", MAX_LENGTH, MAX_LENGTH * 1.001),
        ] {
            let with = |v: f32| {
                let mut s = SimulationSettings::DEFAULT;
                match key {
                    "gravitational_constant" => s.gravitational_constant = v,
                    "time_step" => s.time_step = v,
                    _ => s.softening = v,
                }
                s.problems().len()
            };
            assert_eq!((with(just_inside), with(just_outside)), (0, 1), "{key}");
        }
    }

    #[test]
    fn a_list_of_values_reads_each_by_its_rule() {
        #[derive(Debug)]
        struct Lists(Vec<SimulationSettings>);
        impl<'de> serde::Deserialize<'de> for Lists {
            fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                struct V;
                impl<'de> Visitor<'de> for V {
                    type Value = Lists;
                    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                        f.write_str("lists")
                    }
                    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Lists, A::Error> {
                        let key: String = map.next_key()?.unwrap();
                        Ok(Lists(SimulationSettings::read_values(&key, &mut map)?.unwrap()))
                    }
                }
                d.deserialize_map(V)
            }
        }
        let read: Lists = ron::from_str("{\"shatter_threshold\": [2.0, 3.5]}").unwrap();
        let thresholds: Vec<f32> = read.0.iter().map(|s| s.shatter_threshold).collect();
        assert_eq!(thresholds, [2.0, 3.5]);
        assert_eq!(read.0[0].seed, SimulationSettings::DEFAULT.seed);
        let e = ron::from_str::<Lists>("{\"shatter_fragments\": [5, 1]}").unwrap_err();
        assert!(e.to_string().contains("must be between 2 and 1000, got 1"), "{e}");
    }
}
