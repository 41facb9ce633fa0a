//! [`OutputFailures`]: the outputs of a window run that could not be
//! written after it started (a film's picture, the state at the close).
//! Each says so on stderr as it fails, and the run then ends with exit
//! status 1, as every command does when an output fails.

use std::fmt::Display;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use bevy::prelude::*;

/// How many outputs failed so far; shared, so that a screenshot's callback
/// can count too.
#[derive(Resource, Clone, Debug, Default)]
pub struct OutputFailures(Arc<AtomicU64>);

impl OutputFailures {
    /// Says on stderr that an output failed (`kessler: error: …`), and
    /// counts it.
    pub fn failed(&self, what: impl Display) {
        eprintln!("kessler: error: {what}");
        self.0.fetch_add(1, Ordering::Relaxed);
    }

    /// The outputs that failed.
    pub fn count(&self) -> u64 {
        self.0.load(Ordering::Relaxed)
    }
}
