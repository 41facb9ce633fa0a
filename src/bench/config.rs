//! The benchmark configuration file (RON), like the thesis's test
//! configuration: a scenario and a list of runs.

use std::path::{Path, PathBuf};

use ron::extensions::Extensions;
use serde::de::MapAccess;
use serde::{Deserialize, Deserializer};

use crate::WINDOW_BUILD;
use crate::execution::{ExecutionMode, SplitPolicy, WorkerPool};
use crate::input::{
    ExecutionOptions, InputError, ReadByHand, body_count, deserialize_by_hand, load_ron, read, read_fields, require,
    unknown_field, whole_between,
};
use crate::resources::{DrawMethod, SettingsPatch, Stages, unknown_setting};
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
    /// The runs, measured in this order in every pass; once loaded, each
    /// `Threads` entry stands as the runs it expands to.
    pub runs: Vec<BenchRun>,
    /// Once loaded, the position in the file's `runs` of each of
    /// [`Self::runs`] (a `Threads` entry's runs share its position).
    #[serde(skip)]
    pub origins: Vec<usize>,
    /// The file's `Threads` entries: the thread sweeps whose speed-ups
    /// `<stem>-threads.csv` gives.
    #[serde(skip)]
    pub sweeps: Vec<ThreadsRun>,
}

/// One entry of a config's `runs`.
#[derive(Clone, Debug, PartialEq, Deserialize)]
pub enum BenchRun {
    /// Updates measured headless.
    Run(Run),
    /// Frames measured in the window (the window build only).
    Render(RenderRun),
    /// The thesis's core-count axis at one body count: the run sequential,
    /// then parallel on 1, 2, … up to every hardware thread of the machine
    /// (as many runs), each with the sweep's split policy.
    Threads(ThreadsRun),
}

/// A thread sweep (`Threads(...)` in a config's `runs`).
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, rename = "Threads")]
pub struct ThreadsRun {
    /// Bodies in the run.
    #[serde(deserialize_with = "bodies")]
    pub bodies: u64,
    /// Updates measured.
    #[serde(deserialize_with = "updates")]
    pub updates: u64,
    /// Split policy of the parallel runs (default `Always`, the thesis's
    /// parallel mode, so that every thread count splits every stage).
    #[serde(default = "always", deserialize_with = "sweep_split")]
    pub split: SplitPolicy,
}

fn always() -> SplitPolicy {
    SplitPolicy::Always
}

fn sweep_split<'de, D: Deserializer<'de>>(d: D) -> Result<SplitPolicy, D::Error> {
    read(d, "split")
}

impl ThreadsRun {
    /// The runs the sweep stands for on a machine with `threads` hardware
    /// threads: sequential, then parallel on 1 to `threads` threads.
    pub fn runs(&self, threads: usize) -> impl Iterator<Item = Run> + '_ {
        let run = |mode, threads| Run {
            bodies: self.bodies,
            updates: self.updates,
            execution: ExecutionOptions {
                mode: Some(mode),
                threads,
                split: (mode == ExecutionMode::Parallel).then_some(self.split),
                pool: Some(WorkerPool::Kessler),
            },
            ..Run::default()
        };
        std::iter::once(run(ExecutionMode::Sequential, Some(1)))
            .chain((1..=threads.max(1)).map(move |t| run(ExecutionMode::Parallel, Some(t))))
    }
}

/// Most passes a config may ask for.
pub const MAX_REPEAT: u32 = 1000;

fn one_pass() -> u32 {
    1
}

/// One measured run; how it executes: its own `mode`, `threads`, `split`
/// and `pool`, else the command line's (`kessler bench --split …`), else
/// the defaults (parallel on every hardware thread, split `auto`). In a
/// file its execution options and physics settings stand flat beside its
/// own fields: `Run(bodies: 1000, updates: 50, mode: Sequential, seed: 5)`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Run {
    /// Generated bodies (the scenario's explicit bodies, e.g. the planet,
    /// come on top), shared among its generators in proportion.
    pub bodies: u64,
    /// Updates to run and average over.
    pub updates: u64,
    /// Which stages are on (default: all).
    pub stages: Stages,
    /// This run's own values of physics settings, laid over the
    /// scenario's: `seed: 5, shatter_threshold: 2.0` (any setting a
    /// scenario file takes, by its name there).
    pub settings: SettingsPatch,
    /// How it executes (`mode`, `threads`, `split`, `pool`); what it
    /// leaves out, the command line decides.
    pub execution: ExecutionOptions,
}

/// [`Run`]'s own fields in a file.
const RUN_FIELDS: [&str; 3] = ["bodies", "updates", "stages"];

impl ReadByHand for Run {
    const NAME: &'static str = "Run";
    const FIELDS: &'static [&'static str] = &RUN_FIELDS;
    const EXPECTING: &'static str = "a Run(bodies: …, updates: …)";

    fn read<'de, A: MapAccess<'de>>(map: A) -> Result<Self, A::Error> {
        let mut run = Run::default();
        let seen = read_fields(
            map,
            |key, map| {
                match key {
                    "bodies" => run.bodies = map.next_value::<Bodies>()?.0,
                    "updates" => run.updates = map.next_value::<Updates>()?.0,
                    "stages" => run.stages = map.next_value()?,
                    _ => return Ok(run.execution.read_field(key, map)? || run.settings.read_field(key, map)?),
                }
                Ok(true)
            },
            |key| unknown_setting(key, &[&RUN_FIELDS[..], &ExecutionOptions::FIELDS].concat()),
        )?;
        require(&seen, &["bodies", "updates"])?;
        Ok(run)
    }
}

impl<'de> Deserialize<'de> for Run {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        deserialize_by_hand(d)
    }
}

impl Run {
    /// `scenario` with this run's own values of the physics settings,
    /// where it gives them.
    pub fn apply_to(&self, scenario: &Scenario) -> Scenario {
        let mut scenario = scenario.clone();
        self.settings.apply(&mut scenario.physics);
        scenario
    }
}

/// A run that opens the window and measures frames (the thesis's
/// Tables 1–3 and 5); its simulation executes as its `mode`, `threads`,
/// `split` and `pool` say, else as the saved settings do.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderRun {
    /// Generated bodies, as in [`Run::bodies`].
    pub bodies: u64,
    /// Frames to measure (after a short warm-up that is not measured).
    pub frames: u64,
    /// How the bodies are drawn.
    pub method: DrawMethod,
    /// Whether the simulation runs while drawing (default: paused, to
    /// measure drawing alone).
    pub simulate: bool,
    /// Target updates per second of the simulation (default 60).
    pub ups: Option<u32>,
    /// Wait for the display's refresh (default off: as fast as possible,
    /// as the thesis measured).
    pub vsync: bool,
    /// Draw into an image instead of a window (`kessler run --offscreen`):
    /// no display needed, as on a GPU server (default off).
    pub offscreen: bool,
    /// How its simulation executes (`mode`, `threads`, `split`, `pool`,
    /// flat in the file); what it leaves out, the saved settings decide.
    pub execution: ExecutionOptions,
}

/// [`RenderRun`]'s own fields in a file.
const RENDER_FIELDS: [&str; 7] = ["bodies", "frames", "method", "simulate", "ups", "vsync", "offscreen"];

impl ReadByHand for RenderRun {
    const NAME: &'static str = "Render";
    const FIELDS: &'static [&'static str] = &RENDER_FIELDS;
    const EXPECTING: &'static str = "a Render(bodies: …, frames: …, method: …)";

    fn read<'de, A: MapAccess<'de>>(map: A) -> Result<Self, A::Error> {
        let mut run = RenderRun {
            bodies: 0,
            frames: 0,
            method: DrawMethod::default(),
            simulate: false,
            ups: None,
            vsync: false,
            offscreen: false,
            execution: ExecutionOptions::default(),
        };
        let seen = read_fields(
            map,
            |key, map| {
                match key {
                    "bodies" => run.bodies = map.next_value::<Bodies>()?.0,
                    "frames" => run.frames = map.next_value::<Frames>()?.0,
                    "method" => run.method = map.next_value()?,
                    "simulate" => run.simulate = map.next_value()?,
                    "ups" => run.ups = Some(map.next_value::<Ups>()?.0),
                    "vsync" => run.vsync = map.next_value()?,
                    "offscreen" => run.offscreen = map.next_value()?,
                    _ => return run.execution.read_field(key, map),
                }
                Ok(true)
            },
            |key| unknown_field(key, &[&RENDER_FIELDS[..], &ExecutionOptions::FIELDS].concat()),
        )?;
        require(&seen, &["bodies", "frames", "method"])?;
        Ok(run)
    }
}

impl<'de> Deserialize<'de> for RenderRun {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        deserialize_by_hand(d)
    }
}

/// A checked `bodies` on its own.
#[derive(Deserialize)]
#[serde(transparent)]
struct Bodies(#[serde(deserialize_with = "bodies")] u64);

/// A checked `updates` on its own.
#[derive(Deserialize)]
#[serde(transparent)]
struct Updates(#[serde(deserialize_with = "updates")] u64);

/// A checked `frames` on its own.
#[derive(Deserialize)]
#[serde(transparent)]
struct Frames(#[serde(deserialize_with = "frames")] u64);

/// A checked `ups` on its own.
#[derive(Deserialize)]
#[serde(transparent)]
struct Ups(#[serde(deserialize_with = "ups")] u32);

fn repeat<'de, D: Deserializer<'de>>(d: D) -> Result<u32, D::Error> {
    whole_between(d, "repeat", 1, MAX_REPEAT)
}

fn bodies<'de, D: Deserializer<'de>>(d: D) -> Result<u64, D::Error> {
    body_count(d, "bodies", MAX_BODIES)
}

fn updates<'de, D: Deserializer<'de>>(d: D) -> Result<u64, D::Error> {
    whole_between(d, "updates", 1, crate::input::MAX_UPDATES)
}

fn frames<'de, D: Deserializer<'de>>(d: D) -> Result<u64, D::Error> {
    whole_between(d, "frames", 1, 1_000_000)
}

fn ups<'de, D: Deserializer<'de>>(d: D) -> Result<u32, D::Error> {
    whole_between(d, "ups", 1, 600)
}

impl BenchConfig {
    /// Reads and parses a config file.
    pub fn load(path: &Path) -> Result<Self, InputError> {
        let mut config: Self = load_ron(path, Extensions::IMPLICIT_SOME | Extensions::UNWRAP_VARIANT_NEWTYPES)?;
        let origin = || path.display().to_string();
        if config.runs.is_empty() {
            return Err(InputError::new(origin(), "field `runs`: lists no runs"));
        }
        if !WINDOW_BUILD && let Some(i) = config.runs.iter().position(|r| matches!(r, BenchRun::Render(_))) {
            return Err(InputError::new(
                origin(),
                format!(
                    "runs[{i}]: `Render` runs open the window, which this build of Kessler lacks \
                     (build it with the default features, without --no-default-features)"
                ),
            ));
        }
        config.expand_sweeps(crate::execution::available_threads());
        Ok(config)
    }

    /// Stands each `Threads` entry as its runs on a machine with `threads`
    /// hardware threads, keeping where each run came from.
    pub fn expand_sweeps(&mut self, threads: usize) {
        let mut runs = Vec::new();
        self.origins.clear();
        self.sweeps.clear();
        for (i, run) in std::mem::take(&mut self.runs).into_iter().enumerate() {
            match run {
                BenchRun::Threads(sweep) => {
                    for run in sweep.runs(threads) {
                        runs.push(BenchRun::Run(run));
                        self.origins.push(i);
                    }
                    self.sweeps.push(sweep);
                }
                other => {
                    runs.push(other);
                    self.origins.push(i);
                }
            }
        }
        self.runs = runs;
    }

    /// Where the `i`-th run stands in the file's `runs`.
    pub fn origin(&self, i: usize) -> usize {
        self.origins.get(i).copied().unwrap_or(i)
    }

    /// The headless runs, with their positions in `runs`.
    pub fn update_runs(&self) -> impl Iterator<Item = (usize, &Run)> {
        self.runs.iter().enumerate().filter_map(|(i, r)| match r {
            BenchRun::Run(run) => Some((i, run)),
            BenchRun::Render(_) | BenchRun::Threads(_) => None,
        })
    }

    /// The window runs, with their positions in `runs`.
    pub fn render_runs(&self) -> impl Iterator<Item = (usize, &RenderRun)> {
        self.runs.iter().enumerate().filter_map(|(i, r)| match r {
            BenchRun::Render(run) => Some((i, run)),
            BenchRun::Run(_) | BenchRun::Threads(_) => None,
        })
    }

    /// The path of the scenario the config names (relative to the config's
    /// folder), if it names one.
    pub fn scenario_path(&self, config_path: &Path) -> Option<PathBuf> {
        self.scenario
            .as_ref()
            .map(|path| config_path.parent().unwrap_or(Path::new(".")).join(path))
    }

    /// The scenario the runs scale: the file named in the config (relative
    /// to the config's folder), or the built-in thesis scene.
    pub fn load_scenario(&self, config_path: &Path) -> Result<Scenario, InputError> {
        match self.scenario_path(config_path) {
            Some(path) => Scenario::load(&path)
                .map_err(|e| InputError::new(config_path.display().to_string(), format!("field `scenario`: {e}"))),
            None => Ok(Scenario::builtin_thesis()),
        }
    }

    /// The scenario resized for each run (headless and window runs), with
    /// the run's seed and shatter settings, before any is measured, so that
    /// a bad run fails fast.
    pub fn size_runs(&self, scenario: &Scenario, config_path: &Path) -> Result<Vec<Scenario>, InputError> {
        self.runs
            .iter()
            .enumerate()
            .map(|(i, run)| {
                let (bodies, scenario) = match run {
                    BenchRun::Run(run) => (run.bodies, run.apply_to(scenario)),
                    BenchRun::Render(run) => (run.bodies, scenario.clone()),
                    BenchRun::Threads(sweep) => (sweep.bodies, scenario.clone()),
                };
                let i = self.origin(i);
                let in_run = |e: &dyn std::fmt::Display| {
                    InputError::new(config_path.display().to_string(), format!("runs[{i}]: {e}"))
                };
                let sized = scenario.with_generated(bodies).map_err(|e| in_run(&e))?;
                // Its start is made (and checked: no pile-up, a finite first
                // update, with the events of update 0) before any run is
                // measured, one run at a time.
                crate::simulation::Simulation::check_start(&sized).map_err(|e| in_run(&e))?;
                Ok(sized)
            })
            .collect()
    }
}
