//! Which pool runs a parallel step: Kessler's own (a rayon pool of exactly
//! `threads` workers, each claiming its own block of chunks first:
//! `claims.rs`), or Bevy's `ComputeTaskPool` (the chunks spawned as tasks
//! of one `scope`). The chunks, and so the results, are the same either
//! way; what differs is what a dispatch costs (docs/benchmarks.md, "Bevy's
//! pool").

use std::fmt;

use serde::{Deserialize, Serialize};

/// The pool a parallel step runs on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize, clap::ValueEnum)]
pub enum WorkerPool {
    /// Kessler's own pool (the default).
    #[default]
    Kessler,
    /// Bevy's `ComputeTaskPool`, shared with the app's systems; its
    /// thread count is fixed when it is first made.
    Bevy,
}

impl WorkerPool {
    /// Both, Kessler's first.
    pub const ALL: [Self; 2] = [Self::Kessler, Self::Bevy];

    /// Lower-case name as on the command line and in CSV files.
    pub fn name(self) -> &'static str {
        match self {
            Self::Kessler => "kessler",
            Self::Bevy => "bevy",
        }
    }
}

impl fmt::Display for WorkerPool {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}
