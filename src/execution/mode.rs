//! The execution mode: every stage on one thread, or split over a pool.

use std::fmt;

use serde::{Deserialize, Serialize};

/// How the simulation stages run.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize, clap::ValueEnum,
)]
pub enum ExecutionMode {
    /// Every stage on the calling thread.
    Sequential,
    /// Stages split into chunks on a pool of worker threads (run whole where
    /// the work is too small to pay for the dispatch).
    #[default]
    Parallel,
}

impl ExecutionMode {
    /// Both modes, sequential first.
    pub const ALL: [Self; 2] = [Self::Sequential, Self::Parallel];

    /// Lower-case name as used on the command line and in CSV files.
    pub fn name(self) -> &'static str {
        match self {
            Self::Sequential => "sequential",
            Self::Parallel => "parallel",
        }
    }
}

impl fmt::Display for ExecutionMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}
