//! [`ExecutionOptions`]: how a simulation executes, as a user asks for it —
//! declared once. The command line's `--mode`, `--threads`, `--split` and
//! `--pool` (every command that simulates flattens this type), the fields
//! of the same names in a benchmark config's runs and an ensemble config
//! ([`execution_fields!`](crate::execution_fields)), and the window's
//! saved settings all become an [`Execution`] here, in [`ExecutionOptions::build`].

use clap::Args;
use serde::{Deserializer, Serialize, Serializer};

use super::{read, whole_between};
use crate::execution::{
    AutoSplit, Execution, ExecutionError, ExecutionMode, MAX_THREADS, SplitPolicy, WorkerPool, available_threads,
};

/// How a simulation executes; an option left out takes the default of
/// whoever asks (the command line's: parallel, every hardware thread,
/// split `auto`, Kessler's pool).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Args)]
pub struct ExecutionOptions {
    /// Sequential or parallel stages.
    #[arg(long, value_enum)]
    pub mode: Option<ExecutionMode>,
    /// Worker threads in parallel mode, at most 256.
    #[arg(long, value_parser = super::threads_arg, allow_negative_numbers = true)]
    pub threads: Option<usize>,
    /// From which body count stages split their work in parallel mode:
    /// `auto` (this machine's calibration, see `kessler calibrate`),
    /// `always`, or a body count.
    #[arg(long, value_name = "auto|always|N", allow_negative_numbers = true)]
    pub split: Option<SplitPolicy>,
    /// Which pool runs the parallel steps: Kessler's own, or Bevy's
    /// `ComputeTaskPool` (the same results).
    #[arg(long, value_enum)]
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

/// Declares a config struct (RON) with its own fields and then the
/// execution options' four, `mode`, `threads`, `split` and `pool`, each
/// optional, checked as the command line checks them, and written back
/// without `Some(…)`; `execution()` hands them over as
/// [`ExecutionOptions`]. (serde's `flatten` would say the same, but RON
/// cannot read a flattened struct.)
macro_rules! execution_fields {
    ($(#[$meta:meta])* pub struct $name:ident { $($body:tt)* }) => {
        $(#[$meta])*
        pub struct $name {
            $($body)*
            /// Sequential or parallel stages.
            #[serde(
                default,
                deserialize_with = "crate::input::execution_options::read_mode",
                serialize_with = "crate::input::execution_options::write_some",
                skip_serializing_if = "Option::is_none"
            )]
            pub mode: Option<crate::execution::ExecutionMode>,
            /// Worker threads in parallel mode, 1 to 256.
            #[serde(
                default,
                deserialize_with = "crate::input::execution_options::read_threads",
                serialize_with = "crate::input::execution_options::write_some",
                skip_serializing_if = "Option::is_none"
            )]
            pub threads: Option<usize>,
            /// From which body count stages split their work in parallel
            /// mode.
            #[serde(
                default,
                deserialize_with = "crate::input::execution_options::read_split",
                serialize_with = "crate::input::execution_options::write_some",
                skip_serializing_if = "Option::is_none"
            )]
            pub split: Option<crate::execution::SplitPolicy>,
            /// Which pool runs the parallel steps.
            #[serde(
                default,
                deserialize_with = "crate::input::execution_options::read_pool",
                serialize_with = "crate::input::execution_options::write_some",
                skip_serializing_if = "Option::is_none"
            )]
            pub pool: Option<crate::execution::WorkerPool>,
        }

        impl $name {
            /// How this executes; what it leaves out, whoever runs it
            /// decides.
            pub fn execution(&self) -> crate::input::ExecutionOptions {
                crate::input::ExecutionOptions {
                    mode: self.mode,
                    threads: self.threads,
                    split: self.split,
                    pool: self.pool,
                }
            }
        }
    };
}
pub(crate) use execution_fields;

/// `mode` in a config.
pub fn read_mode<'de, D: Deserializer<'de>>(d: D) -> Result<Option<ExecutionMode>, D::Error> {
    read(d, "mode").map(Some)
}

/// `threads` in a config: 1 to [`MAX_THREADS`].
pub fn read_threads<'de, D: Deserializer<'de>>(d: D) -> Result<Option<usize>, D::Error> {
    whole_between(d, "threads", 1, MAX_THREADS).map(Some)
}

/// `split` in a config.
pub fn read_split<'de, D: Deserializer<'de>>(d: D) -> Result<Option<SplitPolicy>, D::Error> {
    read(d, "split").map(Some)
}

/// `pool` in a config.
pub fn read_pool<'de, D: Deserializer<'de>>(d: D) -> Result<Option<WorkerPool>, D::Error> {
    read(d, "pool").map(Some)
}

/// An option that is there, written as its value.
pub fn write_some<T: Serialize, S: Serializer>(value: &Option<T>, s: S) -> Result<S::Ok, S::Error> {
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
