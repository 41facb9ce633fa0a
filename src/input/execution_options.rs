//! [`ExecutionOptions`]: how a simulation executes, as a user asks for it —
//! one struct everywhere. The command line's `--mode`, `--threads`,
//! `--split` and `--pool` (every command that simulates flattens it), a
//! benchmark run's and an ensemble's `mode`, `threads`, `split` and `pool`
//! (flat among their own fields), and the window's saved settings
//! (`execution: (…)`) all hold it, and all become an [`Execution`] here, in
//! [`ExecutionOptions::build`].

use clap::Args;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use super::{read, whole_between};
use crate::execution::{
    AutoSplit, Execution, ExecutionError, ExecutionMode, MAX_THREADS, SplitPolicy, WorkerPool, available_threads,
};

/// How a simulation executes; an option left out takes the default of
/// whoever asks (the command line's: parallel, every hardware thread,
/// split `auto`, Kessler's pool). In files, `(mode: Parallel, threads: 2)`:
/// each option checked as the command line checks it, and written without
/// `Some(…)`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Args, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields, rename = "Execution")]
pub struct ExecutionOptions {
    /// Sequential or parallel stages.
    #[arg(long, value_enum)]
    #[serde(
        deserialize_with = "read_mode",
        serialize_with = "write_some",
        skip_serializing_if = "Option::is_none"
    )]
    pub mode: Option<ExecutionMode>,
    /// Worker threads in parallel mode, at most 256.
    #[arg(long, value_parser = super::threads_arg, allow_negative_numbers = true)]
    #[serde(
        deserialize_with = "read_threads",
        serialize_with = "write_some",
        skip_serializing_if = "Option::is_none"
    )]
    pub threads: Option<usize>,
    /// From which body count stages split their work in parallel mode:
    /// `auto` (this machine's calibration, see `kessler calibrate`),
    /// `always`, or a body count.
    #[arg(long, value_name = "auto|always|N", allow_negative_numbers = true)]
    #[serde(
        deserialize_with = "read_split",
        serialize_with = "write_some",
        skip_serializing_if = "Option::is_none"
    )]
    pub split: Option<SplitPolicy>,
    /// Which pool runs the parallel steps: Kessler's own, or Bevy's
    /// `ComputeTaskPool` (the same results).
    #[arg(long, value_enum)]
    #[serde(
        deserialize_with = "read_pool",
        serialize_with = "write_some",
        skip_serializing_if = "Option::is_none"
    )]
    pub pool: Option<WorkerPool>,
}

/// [`ExecutionOptions`]' own defaults, as the help says them.
macro_rules! defaults {
    () => {
        "[default: parallel, every hardware thread, split auto, pool kessler]"
    };
}

/// The help's heading over the execution options of a command whose
/// left-out options take [`ExecutionOptions`]' own defaults.
pub const EXECUTION_HEADING: &str = concat!("Execution ", defaults!());

/// The help's heading over `kessler bench`'s execution options.
pub const BENCH_EXECUTION_HEADING: &str = concat!("Execution of the runs that do not say ", defaults!());

impl ExecutionOptions {
    /// Every option given, at its default (parallel, every hardware
    /// thread, split `auto`, Kessler's pool).
    pub fn defaults() -> Self {
        Self::default().resolved()
    }

    /// Every option given: the left-out ones at their defaults.
    pub fn resolved(self) -> Self {
        Self {
            mode: Some(self.mode()),
            threads: Some(self.threads()),
            split: Some(self.split()),
            pool: Some(self.pool()),
        }
    }

    /// The options `execution` runs with, every one given.
    pub fn of(execution: &Execution) -> Self {
        Self {
            mode: Some(execution.mode()),
            threads: Some(execution.threads()),
            split: Some(execution.split()),
            pool: Some(execution.pool()),
        }
    }

    /// Makes `execution` run as these options ask (the left-out ones at
    /// their defaults), changing only what differs.
    pub fn apply_to(self, execution: &mut Execution) -> Result<(), ExecutionError> {
        let wanted = self.resolved();
        let now = Self::of(execution);
        if now.mode != wanted.mode {
            execution.set_mode(self.mode());
        }
        if now.split != wanted.split {
            execution.set_split(self.split());
        }
        if now.pool != wanted.pool {
            execution.set_pool(self.pool());
        }
        if now.threads != wanted.threads {
            execution.set_threads(self.threads())?;
        }
        Ok(())
    }

    /// The options' names in files, in order.
    pub const FIELDS: [&'static str; 4] = ["mode", "threads", "split", "pool"];

    /// Reads the option named `key` from `map`, checked as the command
    /// line checks it; `Ok(false)` where no option has that name (the value
    /// is then not read). How a file that holds the options flat beside
    /// its own fields (a benchmark run, an ensemble) reads them.
    pub fn read_field<'de, A: serde::de::MapAccess<'de>>(&mut self, key: &str, map: &mut A) -> Result<bool, A::Error> {
        match key {
            "mode" => self.mode = map.next_value::<Mode>()?.0,
            "threads" => self.threads = map.next_value::<Threads>()?.0,
            "split" => self.split = map.next_value::<Split>()?.0,
            "pool" => self.pool = map.next_value::<Pool>()?.0,
            _ => return Ok(false),
        }
        Ok(true)
    }

    /// Writes each option given, flat, into `out` (as
    /// [`Self::read_field`] reads them).
    pub fn serialize_fields<S: serde::ser::SerializeStruct>(&self, out: &mut S) -> Result<(), S::Error> {
        if let Some(mode) = self.mode {
            out.serialize_field("mode", &mode)?;
        }
        if let Some(threads) = self.threads {
            out.serialize_field("threads", &threads)?;
        }
        if let Some(split) = self.split {
            out.serialize_field("split", &split)?;
        }
        if let Some(pool) = self.pool {
            out.serialize_field("pool", &pool)?;
        }
        Ok(())
    }

    /// Reads the option named `key` from `map`, of its type but with a
    /// thread count of any size (the window's settings, which hold it to
    /// this machine's range afterwards rather than refuse it); `Ok(false)`
    /// where no option has that name (the value is then not read).
    pub fn read_field_unchecked<'de, A: serde::de::MapAccess<'de>>(
        &mut self,
        key: &str,
        map: &mut A,
    ) -> Result<bool, A::Error> {
        match key {
            "mode" => self.mode = Some(map.next_value()?),
            "threads" => self.threads = Some(map.next_value()?),
            "split" => self.split = Some(map.next_value()?),
            "pool" => self.pool = Some(map.next_value()?),
            _ => return Ok(false),
        }
        Ok(true)
    }

    /// Whether every option is left out.
    pub fn is_empty(&self) -> bool {
        *self == Self::default()
    }

    /// Every option as given, each left-out one as in `under`.
    pub fn or(self, under: Self) -> Self {
        Self {
            mode: self.mode.or(under.mode),
            threads: self.threads.or(under.threads),
            split: self.split.or(under.split),
            pool: self.pool.or(under.pool),
        }
    }

    /// The execution mode asked for, or the default (parallel).
    pub fn mode(&self) -> ExecutionMode {
        self.mode.unwrap_or_default()
    }

    /// The threads asked for, or every hardware thread.
    pub fn threads(&self) -> usize {
        self.threads.unwrap_or_else(available_threads)
    }

    /// The split policy asked for, or `Auto`.
    pub fn split(&self) -> SplitPolicy {
        self.split.unwrap_or_default()
    }

    /// The pool asked for, or Kessler's.
    pub fn pool(&self) -> WorkerPool {
        self.pool.unwrap_or_default()
    }

    /// The execution these options ask for, the left-out ones at their
    /// defaults; split `auto` uses `auto`'s counts.
    pub fn build(&self, auto: AutoSplit) -> Result<Execution, ExecutionError> {
        Ok(Execution::new(self.mode(), self.threads())?
            .with_split(self.split())
            .with_auto_split(auto)
            .with_pool(self.pool()))
    }
}

/// A checked `mode` on its own.
#[derive(Deserialize)]
#[serde(transparent)]
struct Mode(#[serde(deserialize_with = "read_mode")] Option<ExecutionMode>);

/// A checked `threads` on its own.
#[derive(Deserialize)]
#[serde(transparent)]
struct Threads(#[serde(deserialize_with = "read_threads")] Option<usize>);

/// A checked `split` on its own.
#[derive(Deserialize)]
#[serde(transparent)]
struct Split(#[serde(deserialize_with = "read_split")] Option<SplitPolicy>);

/// A checked `pool` on its own.
#[derive(Deserialize)]
#[serde(transparent)]
struct Pool(#[serde(deserialize_with = "read_pool")] Option<WorkerPool>);

/// `mode` in a file.
fn read_mode<'de, D: Deserializer<'de>>(d: D) -> Result<Option<ExecutionMode>, D::Error> {
    read(d, "mode").map(Some)
}

/// `threads` in a file: 1 to [`MAX_THREADS`].
fn read_threads<'de, D: Deserializer<'de>>(d: D) -> Result<Option<usize>, D::Error> {
    whole_between(d, "threads", 1, MAX_THREADS).map(Some)
}

/// `split` in a file.
fn read_split<'de, D: Deserializer<'de>>(d: D) -> Result<Option<SplitPolicy>, D::Error> {
    read(d, "split").map(Some)
}

/// `pool` in a file.
fn read_pool<'de, D: Deserializer<'de>>(d: D) -> Result<Option<WorkerPool>, D::Error> {
    read(d, "pool").map(Some)
}

/// An option that is there, written as its value.
fn write_some<T: Serialize, S: Serializer>(value: &Option<T>, s: S) -> Result<S::Ok, S::Error> {
    match value {
        Some(value) => value.serialize(s),
        None => s.serialize_none(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn left_out_options_take_the_defaults_or_those_under_them() {
        let none = ExecutionOptions::default();
        assert_eq!(none.mode(), ExecutionMode::Parallel);
        assert_eq!(none.threads(), available_threads());
        assert_eq!(none.split(), SplitPolicy::Auto);
        assert_eq!(none.pool(), WorkerPool::Kessler);
        let given = ExecutionOptions {
            mode: Some(ExecutionMode::Sequential),
            split: Some(SplitPolicy::Always),
            ..ExecutionOptions::default()
        };
        let under = ExecutionOptions {
            mode: Some(ExecutionMode::Parallel),
            threads: Some(3),
            split: Some(SplitPolicy::Above(7)),
            pool: None,
        };
        assert_eq!(
            given.or(under),
            ExecutionOptions {
                mode: Some(ExecutionMode::Sequential),
                threads: Some(3),
                split: Some(SplitPolicy::Always),
                pool: None,
            }
        );
    }

    #[test]
    fn a_file_gives_the_options_as_the_command_line_does() {
        let read = |text: &str| ron::from_str::<ExecutionOptions>(text).map_err(|e| e.to_string());
        let options = read("(mode: Sequential, threads: 3, split: Above(500), pool: Bevy)").unwrap();
        assert_eq!(
            options,
            ExecutionOptions {
                mode: Some(ExecutionMode::Sequential),
                threads: Some(3),
                split: Some(SplitPolicy::Above(500)),
                pool: Some(WorkerPool::Bevy),
            }
        );
        assert_eq!(read(&ron::to_string(&options).unwrap()), Ok(options), "written as read");
        assert_eq!(read("()"), Ok(ExecutionOptions::default()));
        for (text, needle) in [
            ("(threads: 0)", "threads"),
            ("(threads: 257)", "threads"),
            ("(mode: Fast)", "mode"),
            ("(cores: 2)", "Unexpected field named `cores`"),
        ] {
            assert!(read(text).unwrap_err().contains(needle), "{text}: {:?}", read(text));
        }
        assert_eq!(ExecutionOptions::defaults().threads, Some(available_threads()));
    }

    #[test]
    fn the_execution_is_the_one_asked_for() {
        let options = ExecutionOptions {
            mode: Some(ExecutionMode::Parallel),
            threads: Some(2),
            split: Some(SplitPolicy::Above(9)),
            pool: Some(WorkerPool::Bevy),
        };
        let execution = options.build(AutoSplit::default()).unwrap();
        assert_eq!(execution.mode(), ExecutionMode::Parallel);
        assert_eq!(execution.threads_used(), 2);
        assert_eq!(execution.split(), SplitPolicy::Above(9));
        assert_eq!(execution.pool(), WorkerPool::Bevy);
    }
}
