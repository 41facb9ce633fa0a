//! The benchmark configuration file (RON), like the thesis's test
//! configuration: a scenario and a list of runs.

use std::path::{Path, PathBuf};

use ron::extensions::Extensions;
use serde::{Deserialize, Deserializer};

use crate::execution::{ExecutionMode, MAX_THREADS};
use crate::input::{InputError, body_count, load_ron, whole_at_least, whole_between};
use crate::scenario::{MAX_BODIES, Scenario};

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
    /// The runs, measured in this order in every pass.
    pub runs: Vec<Run>,
}

/// Most passes a config may ask for.
pub const MAX_REPEAT: u32 = 1000;

fn one_pass() -> u32 {
    1
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
    /// Sequential or parallel; default parallel.
    #[serde(default)]
    pub mode: ExecutionMode,
    /// Worker threads in parallel mode; all hardware threads if omitted.
    #[serde(default, deserialize_with = "threads")]
    pub threads: Option<usize>,
    /// Which stages are on (default: all).
    #[serde(default)]
    pub stages: Stages,
}

/// Stage switches of a run; the names are
/// [`SimulationSettings`](crate::resources::SimulationSettings)'s.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Stages {
    /// The gravity stage.
    pub gravity: bool,
    /// Collision detection (the broad phase).
    pub collisions: bool,
    /// Bounce and shatter (`response` in older configs).
    #[serde(alias = "response")]
    pub collision_response: bool,
}

impl Default for Stages {
    fn default() -> Self {
        Self {
            gravity: true,
            collisions: true,
            collision_response: true,
        }
    }
}

fn repeat<'de, D: Deserializer<'de>>(d: D) -> Result<u32, D::Error> {
    whole_between(d, "repeat", 1, MAX_REPEAT)
}

fn bodies<'de, D: Deserializer<'de>>(d: D) -> Result<u64, D::Error> {
    body_count(d, "bodies", MAX_BODIES)
}

fn updates<'de, D: Deserializer<'de>>(d: D) -> Result<u64, D::Error> {
    whole_at_least(d, "updates", 1)
}

fn threads<'de, D: Deserializer<'de>>(d: D) -> Result<Option<usize>, D::Error> {
    whole_between(d, "threads", 1, MAX_THREADS).map(Some)
}

impl BenchConfig {
    /// Reads and parses a config file.
    pub fn load(path: &Path) -> Result<Self, InputError> {
        let config: Self = load_ron(path, Extensions::IMPLICIT_SOME)?;
        if config.runs.is_empty() {
            return Err(InputError::new(
                path.display().to_string(),
                "field `runs`: lists no runs",
            ));
        }
        Ok(config)
    }

    /// The scenario the runs scale: the file named in the config (relative
    /// to the config's folder), or the built-in thesis scene.
    pub fn load_scenario(&self, config_path: &Path) -> Result<Scenario, InputError> {
        match &self.scenario {
            Some(path) => {
                let path = config_path.parent().unwrap_or(Path::new(".")).join(path);
                Scenario::load(&path)
                    .map_err(|e| InputError::new(config_path.display().to_string(), format!("field `scenario`: {e}")))
            }
            None => Ok(Scenario::builtin_thesis()),
        }
    }

    /// The scenario resized for each run, before any is measured, so that
    /// a bad run fails fast.
    pub fn size_runs(&self, scenario: &Scenario, config_path: &Path) -> Result<Vec<Scenario>, InputError> {
        self.runs
            .iter()
            .enumerate()
            .map(|(i, run)| {
                scenario
                    .with_generated(run.bodies)
                    .map_err(|e| InputError::new(config_path.display().to_string(), format!("runs[{i}]: {e}")))
            })
            .collect()
    }
}
