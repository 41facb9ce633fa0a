//! The benchmark configuration file (RON), like the thesis's test
//! configuration: a scenario and a list of runs.

use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::resources::{ExecutionMode, MAX_THREADS};
use crate::scenario::ScenarioError;
use crate::scenario::checked::MAX_BODIES;

/// A benchmark: runs of one scenario at several sizes and execution modes.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, rename = "Bench")]
pub struct BenchConfig {
    /// Scenario whose generators are scaled to each run's body count;
    /// relative paths are taken from the config file's folder. Default: the
    /// thesis scene.
    #[serde(default)]
    pub scenario: Option<PathBuf>,
    /// How often every run is measured: the passes go through all runs in
    /// turn, and each run reports its median pass (by update time).
    #[serde(default = "one_pass", deserialize_with = "repeat")]
    pub repeat: u32,
    pub runs: Vec<Run>,
}

/// Most passes a config may ask for.
pub const MAX_REPEAT: u32 = 1000;

fn one_pass() -> u32 {
    1
}

fn repeat<'de, D: serde::Deserializer<'de>>(d: D) -> Result<u32, D::Error> {
    one_to(d, "repeat", MAX_REPEAT)
}

/// One measured run.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, rename = "Run")]
pub struct Run {
    /// Generated bodies (the scenario's explicit bodies, e.g. the planet,
    /// come on top), shared among its generators in proportion.
    #[serde(deserialize_with = "bodies")]
    pub bodies: u64,
    /// Updates to run and average over.
    #[serde(deserialize_with = "updates")]
    pub updates: u64,
    #[serde(default)]
    pub mode: ExecutionMode,
    /// Worker threads in parallel mode; all hardware threads if omitted.
    #[serde(default, deserialize_with = "threads")]
    pub threads: Option<usize>,
    /// Which stages are on (default: all).
    #[serde(default)]
    pub stages: Stages,
}

/// Stage switches of a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Stages {
    pub gravity: bool,
    pub collisions: bool,
    pub response: bool,
}

impl Default for Stages {
    fn default() -> Self {
        Self {
            gravity: true,
            collisions: true,
            response: true,
        }
    }
}

fn bodies<'de, D: serde::Deserializer<'de>>(d: D) -> Result<u64, D::Error> {
    use serde::de::Error;
    let value = u64::deserialize(d).map_err(|e| D::Error::custom(format!("field `bodies`: {e}")))?;
    if value > MAX_BODIES {
        return Err(D::Error::custom(format!(
            "field `bodies`: {value} bodies would not fit in memory (at most {MAX_BODIES})"
        )));
    }
    Ok(value)
}

fn updates<'de, D: serde::Deserializer<'de>>(d: D) -> Result<u64, D::Error> {
    use serde::de::Error;
    let value = u64::deserialize(d).map_err(|e| D::Error::custom(format!("field `updates`: {e}")))?;
    if value == 0 {
        return Err(D::Error::custom("field `updates`: must be at least 1"));
    }
    Ok(value)
}

fn threads<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<usize>, D::Error> {
    one_to(d, "threads", MAX_THREADS).map(Some)
}

/// A whole number from 1 to `max` in the field named `field`.
fn one_to<'de, D, T>(d: D, field: &str, max: T) -> Result<T, D::Error>
where
    D: serde::Deserializer<'de>,
    T: Deserialize<'de> + PartialOrd + From<u8> + std::fmt::Display,
{
    use serde::de::Error;
    let value = T::deserialize(d).map_err(|e| D::Error::custom(format!("field `{field}`: {e}")))?;
    if value < T::from(1) || value > max {
        return Err(D::Error::custom(format!(
            "field `{field}`: must be between 1 and {max}, got {value}"
        )));
    }
    Ok(value)
}

impl BenchConfig {
    /// Reads and parses a config file.
    pub fn load(path: &Path) -> Result<Self, ScenarioError> {
        let origin = path.display().to_string();
        let error = |location, message: String| ScenarioError {
            origin: origin.clone(),
            location,
            message,
        };
        let text = std::fs::read_to_string(path).map_err(|e| error(None, format!("cannot read the file: {e}")))?;
        let options = ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
        let config: Self = options
            .from_str(&text)
            .map_err(|e| error(Some((e.span.start.line, e.span.start.col)), e.code.to_string()))?;
        if config.runs.is_empty() {
            return Err(error(None, "field `runs`: lists no runs".to_owned()));
        }
        Ok(config)
    }

    /// The scenario file a relative path in the config refers to.
    pub fn scenario_path(&self, config_path: &Path) -> Option<PathBuf> {
        self.scenario
            .as_ref()
            .map(|p| config_path.parent().unwrap_or(Path::new(".")).join(p))
    }
}
