//! The ensemble config (RON): one scenario, how long and how often each
//! member records, how many members per combination of settings, the
//! ensemble's own seed, the physics settings to vary, and how each member
//! executes (docs/guide.md, "Ensembles").

use std::fmt;
use std::path::{Path, PathBuf};

use ron::extensions::Extensions;
use serde::de::{self, Deserializer, MapAccess, Visitor};
use serde::ser::{SerializeSeq, SerializeStruct, Serializer};
use serde::{Deserialize, Serialize};

use crate::execution::ExecutionMode;
use crate::input::{
    ExecutionOptions, FieldName, InputError, MAX_UPDATES, ReadByHand, deserialize_by_hand, parse_ron, read_fields,
    read_text, require, unknown_field, whole_between,
};
use crate::resources::{self as physics, SimulationSettings, settings};

/// Most members one ensemble may have, over all its combinations.
pub const MAX_MEMBERS: u64 = 1_000_000;

/// An ensemble: `members` runs of one scenario for every combination of
/// the varied settings, each with a seed of its own. Each member executes
/// as its `mode`, `threads`, `split` and `pool` say (results are the same
/// either way), else as [`MEMBER_EXECUTION`] does. In a file the execution
/// options stand flat beside the other fields:
/// `Ensemble(steps: 100, members: 8, mode: Sequential)`.
#[derive(Clone, Debug, PartialEq)]
pub struct EnsembleConfig {
    /// The scenario, relative to the config's folder; the built-in default
    /// scene if omitted.
    pub scenario: Option<PathBuf>,
    /// Updates each member runs.
    pub steps: u64,
    /// Updates between two timeline rows (and a row after the last;
    /// default 100).
    pub every: u64,
    /// Members per combination of settings.
    pub members: u64,
    /// The ensemble's own seed, from which every member's is mixed
    /// (default 1).
    pub seed: u64,
    /// Physics settings to vary: every combination of their values.
    pub vary: Vary,
    /// How each member executes; what it leaves out, [`MEMBER_EXECUTION`]
    /// gives.
    pub execution: ExecutionOptions,
}

/// [`EnsembleConfig`]'s own fields in a file, in the order it is written.
const OWN: [&str; 6] = ["scenario", "steps", "every", "members", "seed", "vary"];

impl ReadByHand for EnsembleConfig {
    const NAME: &'static str = "Ensemble";
    const FIELDS: &'static [&'static str] = &OWN;
    const EXPECTING: &'static str = "an Ensemble(steps: …, members: …)";

    fn read<'de, A: MapAccess<'de>>(map: A) -> Result<Self, A::Error> {
        let mut config = EnsembleConfig {
            scenario: None,
            steps: 0,
            every: 100,
            members: 0,
            seed: 1,
            vary: Vary::default(),
            execution: ExecutionOptions::default(),
        };
        let seen = read_fields(
            map,
            |key, map| {
                match key {
                    "scenario" => config.scenario = Some(map.next_value()?),
                    "steps" => config.steps = map.next_value::<Steps>()?.0,
                    "every" => config.every = map.next_value::<Every>()?.0,
                    "members" => config.members = map.next_value::<Members>()?.0,
                    "seed" => config.seed = map.next_value::<Seed>()?.0,
                    "vary" => config.vary = map.next_value()?,
                    _ => return config.execution.read_field(key, map),
                }
                Ok(true)
            },
            |key| unknown_field(key, &[&OWN[..], &ExecutionOptions::FIELDS].concat()),
        )?;
        require(&seen, &["steps", "members"])?;
        Ok(config)
    }
}

impl<'de> Deserialize<'de> for EnsembleConfig {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        deserialize_by_hand(d)
    }
}

impl Serialize for EnsembleConfig {
    fn serialize<S: Serializer>(&self, out: S) -> Result<S::Ok, S::Error> {
        let mut s = out.serialize_struct("Ensemble", OWN.len() + ExecutionOptions::FIELDS.len())?;
        if let Some(scenario) = &self.scenario {
            s.serialize_field("scenario", scenario)?;
        }
        s.serialize_field("steps", &self.steps)?;
        s.serialize_field("every", &self.every)?;
        s.serialize_field("members", &self.members)?;
        s.serialize_field("seed", &self.seed)?;
        if !self.vary.is_empty() {
            s.serialize_field("vary", &self.vary)?;
        }
        self.execution.serialize_fields(&mut s)?;
        s.end()
    }
}

/// How a member executes where the config does not say: parallel on one
/// thread (members run side by side, each on its own core), the rest at
/// [`ExecutionOptions`]' defaults.
pub const MEMBER_EXECUTION: ExecutionOptions = ExecutionOptions {
    mode: Some(ExecutionMode::Parallel),
    threads: Some(1),
    split: None,
    pool: None,
};

/// A checked `steps` on its own.
#[derive(Deserialize)]
#[serde(transparent)]
struct Steps(#[serde(deserialize_with = "steps")] u64);

/// A checked `every` on its own.
#[derive(Deserialize)]
#[serde(transparent)]
struct Every(#[serde(deserialize_with = "every")] u64);

/// A checked `members` on its own.
#[derive(Deserialize)]
#[serde(transparent)]
struct Members(#[serde(deserialize_with = "members")] u64);

/// A checked ensemble `seed` on its own.
#[derive(Deserialize)]
#[serde(transparent)]
struct Seed(#[serde(deserialize_with = "seed")] u64);

fn seed<'de, D: Deserializer<'de>>(d: D) -> Result<u64, D::Error> {
    physics::rules::SEED.read(d)
}

fn steps<'de, D: Deserializer<'de>>(d: D) -> Result<u64, D::Error> {
    whole_between(d, "steps", 0, MAX_UPDATES)
}

fn every<'de, D: Deserializer<'de>>(d: D) -> Result<u64, D::Error> {
    whole_between(d, "every", 1, MAX_UPDATES)
}

fn members<'de, D: Deserializer<'de>>(d: D) -> Result<u64, D::Error> {
    whole_between(d, "members", 1, MAX_MEMBERS)
}

/// One varied setting: its name and its values, each held as the default
/// settings with that one value (see [`SimulationSettings::take`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Varied {
    /// The setting's name in files.
    pub key: &'static str,
    /// Its values, in file order.
    pub values: Vec<SimulationSettings>,
}

/// The varied settings, in file order. Combination `c` takes, for each
/// setting, the value at `c`'s digit in the mixed radix of the lists'
/// lengths, the last setting's digit the fastest: `(a: [1, 2], b: [x, y])`
/// gives `a=1 b=x`, `a=1 b=y`, `a=2 b=x`, `a=2 b=y`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Vary(pub Vec<Varied>);

impl Vary {
    /// Whether nothing is varied (one combination: the scenario's own).
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// How many combinations there are (1 when nothing is varied); at most
    /// `u64::MAX`, which a checked config never reaches.
    pub fn combinations(&self) -> u64 {
        self.counted().unwrap_or(u64::MAX)
    }

    /// How many combinations there are, where a `u64` can count them.
    fn counted(&self) -> Option<u64> {
        self.0
            .iter()
            .try_fold(1_u64, |product, v| product.checked_mul(v.values.len() as u64))
    }

    /// The value of every varied setting in combination `c`: the setting
    /// and the settings that hold its value.
    pub fn combination(&self, c: u64) -> Vec<(&'static str, &SimulationSettings)> {
        let mut rest = c;
        let mut picked: Vec<_> = self
            .0
            .iter()
            .rev()
            .map(|varied| {
                let n = varied.values.len() as u64;
                let value = &varied.values[(rest % n) as usize];
                rest /= n;
                (varied.key, value)
            })
            .collect();
        picked.reverse();
        picked
    }

    /// Puts combination `c`'s values into `settings`.
    pub fn apply(&self, c: u64, settings: &mut SimulationSettings) {
        for (key, from) in self.combination(c) {
            settings.take(key, from);
        }
    }

    /// Combination `c` in words, `key=value` separated by spaces; empty
    /// when nothing is varied.
    pub fn label(&self, c: u64) -> String {
        self.combination(c)
            .iter()
            .map(|(key, from)| format!("{key}={}", from.shown(key).unwrap_or_default()))
            .collect::<Vec<_>>()
            .join(" ")
    }
}

impl<'de> Deserialize<'de> for Vary {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct VaryVisitor;
        impl<'de> Visitor<'de> for VaryVisitor {
            type Value = Vary;

            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("settings and their values, as (shatter_threshold: [2.0, 3.0])")
            }

            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Vary, A::Error> {
                let mut vary = Vec::new();
                while let Some(FieldName(key)) = map.next_key()? {
                    let field = format!("vary.{key}");
                    let Some(info) = physics::setting(&key) else {
                        let names: Vec<String> = settings().iter().map(|s| format!("`{}`", s.key)).collect();
                        return Err(de::Error::custom(format!(
                            "field `vary`: no physics setting is named `{key}`; the settings: {}",
                            names.join(", ")
                        )));
                    };
                    if info.key == "seed" {
                        return Err(de::Error::custom(format!(
                            "field `{field}`: every member has a seed of its own, mixed from the ensemble's `seed`; vary another setting"
                        )));
                    }
                    if vary.iter().any(|v: &Varied| v.key == info.key) {
                        return Err(de::Error::custom(format!("field `{field}`: named twice")));
                    }
                    let values = SimulationSettings::read_values(info.key, &mut map)
                        .map_err(|e| {
                            // The setting's reader names the setting; the
                            // message names it within `vary`.
                            let text = e.to_string();
                            let own = format!("field `{}`: ", info.key);
                            de::Error::custom(match text.strip_prefix(&own) {
                                Some(problem) => format!("field `{field}`: {problem}"),
                                None => format!("field `{field}`: {text}"),
                            })
                        })?
                        .unwrap_or_default();
                    if values.is_empty() {
                        return Err(de::Error::custom(format!("field `{field}`: lists no values")));
                    }
                    let shown: Vec<String> = values.iter().map(|s| s.shown(info.key).unwrap_or_default()).collect();
                    if let Some(k) = (1..shown.len()).find(|&k| shown[..k].contains(&shown[k])) {
                        return Err(de::Error::custom(format!("field `{field}`: lists {} twice", shown[k])));
                    }
                    vary.push(Varied { key: info.key, values });
                }
                Ok(Vary(vary))
            }
        }
        d.deserialize_struct("Vary", &[], VaryVisitor)
    }
}

impl Serialize for Vary {
    fn serialize<S: Serializer>(&self, out: S) -> Result<S::Ok, S::Error> {
        /// One setting's values, as a list.
        struct Values<'a>(&'a Varied);
        impl Serialize for Values<'_> {
            fn serialize<S: Serializer>(&self, out: S) -> Result<S::Ok, S::Error> {
                let mut seq = out.serialize_seq(Some(self.0.values.len()))?;
                for settings in &self.0.values {
                    seq.serialize_element(&Value(self.0.key, settings))?;
                }
                seq.end()
            }
        }
        /// One value of a setting.
        struct Value<'a>(&'static str, &'a SimulationSettings);
        impl Serialize for Value<'_> {
            fn serialize<S: Serializer>(&self, out: S) -> Result<S::Ok, S::Error> {
                self.1.serialize_value(self.0, out)
            }
        }
        let mut s = out.serialize_struct("Vary", self.0.len())?;
        for varied in &self.0 {
            s.serialize_field(varied.key, &Values(varied))?;
        }
        s.end()
    }
}

impl EnsembleConfig {
    /// How each member executes: the config's options, else
    /// [`MEMBER_EXECUTION`]'s.
    pub fn member_execution(&self) -> ExecutionOptions {
        self.execution.or(MEMBER_EXECUTION)
    }

    /// Reads and checks a config file.
    pub fn load(path: &Path) -> Result<Self, InputError> {
        Self::parse(&read_text(path)?, &path.display().to_string())
    }

    /// Parses a config from RON text; `origin` names it in errors.
    pub fn parse(text: &str, origin: &str) -> Result<Self, InputError> {
        let config: Self = parse_ron(
            text,
            origin,
            Extensions::IMPLICIT_SOME | Extensions::UNWRAP_VARIANT_NEWTYPES,
        )?;
        config.check().map_err(|e| InputError::new(origin, e))?;
        Ok(config)
    }

    /// Checks that span fields: the members over all combinations.
    fn check(&self) -> Result<(), String> {
        let combinations = self
            .vary
            .counted()
            .map_or_else(|| format!("more than {}", u64::MAX), |n| n.to_string());
        match self.vary.counted().and_then(|n| n.checked_mul(self.members)) {
            Some(total) if total <= MAX_MEMBERS => Ok(()),
            _ => Err(format!(
                "field `members`: {} members for each of {combinations} combinations of `vary` make more than {MAX_MEMBERS} members",
                self.members,
            )),
        }
    }

    /// Members over all combinations.
    pub fn total_members(&self) -> u64 {
        self.members * self.vary.combinations()
    }

    /// The combination member `index` runs, and its place within it.
    pub fn place(&self, index: u64) -> (u64, u64) {
        (index / self.members, index % self.members)
    }

    /// The scenario's path, relative paths taken from `config_path`'s
    /// folder; `None` for the built-in default scene.
    pub fn scenario_path(&self, config_path: &Path) -> Option<PathBuf> {
        self.scenario
            .as_ref()
            .map(|path| config_path.parent().unwrap_or(Path::new(".")).join(path))
    }

    /// The fields, each as the file writes it, in file order (how two
    /// configs are compared, field by field).
    pub fn fields(&self) -> Vec<(&'static str, String)> {
        let vary = ron::to_string(&self.vary).unwrap_or_default();
        vec![
            ("steps", self.steps.to_string()),
            ("every", self.every.to_string()),
            ("members", self.members.to_string()),
            ("seed", self.seed.to_string()),
            ("vary", if self.vary.is_empty() { "()".to_owned() } else { vary }),
            ("mode", format!("{:?}", self.member_execution().mode())),
            ("threads", self.member_execution().threads().to_string()),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<EnsembleConfig, String> {
        EnsembleConfig::parse(text, "e.ron").map_err(|e| e.to_string())
    }

    #[test]
    fn a_config_reads_with_its_defaults_and_its_combinations() {
        let config = parse(
            "Ensemble(steps: 10, members: 3, vary: (shatter_threshold: [2.0, 3.0], gravity: [Direct, Tree(theta: 0.5)], shatter_fragments: [4, 5, 6]))",
        )
        .unwrap();
        assert_eq!(
            (config.every, config.seed, config.member_execution().threads()),
            (100, 1, 1)
        );
        assert_eq!(config.member_execution().mode(), ExecutionMode::Parallel);
        assert_eq!(config.vary.combinations(), 12);
        assert_eq!(config.total_members(), 36);
        assert_eq!(
            config.vary.label(0),
            "shatter_threshold=2 gravity=Direct shatter_fragments=4"
        );
        assert_eq!(
            config.vary.label(5),
            "shatter_threshold=2 gravity=Tree(theta: 0.5) shatter_fragments=6"
        );
        assert_eq!(
            config.vary.label(11),
            "shatter_threshold=3 gravity=Tree(theta: 0.5) shatter_fragments=6"
        );
        let mut settings = SimulationSettings::DEFAULT;
        config.vary.apply(7, &mut settings);
        assert_eq!((settings.shatter_threshold, settings.shatter_fragments), (3.0, 5));
        assert_eq!(settings.gravity_method, physics::GravityMethod::Direct);
        assert_eq!(settings.time_step, SimulationSettings::DEFAULT.time_step);
        assert_eq!(config.place(7), (2, 1));
    }

    #[test]
    fn a_config_writes_and_reads_back_the_same() {
        let config = parse(
            "Ensemble(scenario: \"s.ron\", steps: 10, every: 5, members: 2, seed: 9, vary: (fragment_spread: [0.1, 0.30000001]), mode: Sequential, threads: 2, split: Above(9), pool: Bevy)",
        )
        .unwrap();
        let text = ron::ser::to_string_pretty(&config, ron::ser::PrettyConfig::new().struct_names(true)).unwrap();
        assert_eq!(parse(&text).unwrap(), config, "{text}");
        let bare = parse("Ensemble(steps: 1, members: 1)").unwrap();
        assert_eq!(parse(&ron::to_string(&bare).unwrap()).unwrap(), bare);
    }

    #[test]
    fn bad_configs_name_the_field() {
        for (text, expected) in [
            (
                "Ensemble(steps: 1, members: 0)",
                "field `members`: must be between 1 and 1000000, got 0",
            ),
            (
                "Ensemble(steps: 1, members: 1000001)",
                "field `members`: must be between 1 and 1000000",
            ),
            (
                "Ensemble(steps: 1, members: 1000, vary: (shatter_fragments: [2, 3, 4, 5, 6, 7, 8, 9, 10, 11], max_bodies: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26, 27, 28, 29, 30, 31, 32, 33, 34, 35, 36, 37, 38, 39, 40, 41, 42, 43, 44, 45, 46, 47, 48, 49, 50, 51, 52, 53, 54, 55, 56, 57, 58, 59, 60, 61, 62, 63, 64, 65, 66, 67, 68, 69, 70, 71, 72, 73, 74, 75, 76, 77, 78, 79, 80, 81, 82, 83, 84, 85, 86, 87, 88, 89, 90, 91, 92, 93, 94, 95, 96, 97, 98, 99, 100, 101]))",
                "1000 members for each of 1010 combinations",
            ),
            (
                "Ensemble(steps: 1, members: 1, colour: 3)",
                "unknown field `colour`, expected one of `scenario`, `steps`, `every`, `members`, `seed`, `vary`, `mode`, `threads`, `split`, `pool`",
            ),
            (
                "Ensemble(steps: 1, members: 1, vary: (warp: [1]))",
                "field `vary`: no physics setting is named `warp`",
            ),
            (
                "Ensemble(steps: 1, members: 1, vary: (shatter_threshold: [1.0, -2.0]))",
                "field `vary.shatter_threshold`: must be finite and >= 0, got -2",
            ),
            (
                "Ensemble(steps: 1, members: 1, vary: (seed: [1, 2]))",
                "field `vary.seed`: every member has a seed",
            ),
            (
                "Ensemble(steps: 1, members: 1, vary: (time_step: []))",
                "field `vary.time_step`: lists no values",
            ),
            (
                "Ensemble(steps: 1, members: 1, vary: (time_step: [1.0, 1.0]))",
                "field `vary.time_step`: lists 1 twice",
            ),
            (
                "Ensemble(steps: 1, members: 1, vary: (time_step: [1.0], time_step: [2.0]))",
                "field `vary.time_step`: named twice",
            ),
            (
                "Ensemble(steps: 1, members: 1, threads: 0)",
                "field `threads`: must be between 1 and 256",
            ),
            (
                "Ensemble(steps: 1, members: 1, mode: Fast)",
                "field `mode`: Unexpected variant named `Fast`",
            ),
            (
                "Ensemble(steps: 1, members: 1, seed: 2, seed: 3)",
                "duplicate field `seed`",
            ),
            ("Ensemble(members: 1)", "missing field `steps`"),
            (
                "Ensemble(steps: 1, members: 1, every: 0)",
                "field `every`: must be between 1",
            ),
            ("Ensemble(steps: 1e13, members: 1)", "field `steps`"),
        ] {
            let e = parse(text).unwrap_err();
            assert!(e.contains(expected), "{text}: {e}");
            assert!(e.starts_with("e.ron"), "{e}");
        }
    }
}
