//! [`OutputFailures`]: the outputs of a window run that could not be
//! written after it started (a film's picture, a screenshot, a saved
//! session or scenario, a frame report, the state at the close), and
//! whether the simulation had stopped when the window closed. Each failed
//! output says so on stderr as it fails, and the run then ends with exit
//! status 1, as every command does when an output fails; a run that closes
//! stopped ends as a stopped headless run does (exit 3).

use std::fmt::Display;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, PoisonError};

use bevy::prelude::*;

/// How many outputs failed so far, and why the simulation stopped if it
/// was stopped at the close; shared, so that a screenshot's callback can
/// count too and the caller of the app reads them after it ends.
#[derive(Resource, Clone, Debug, Default)]
pub struct OutputFailures {
    /// Outputs that failed.
    failed: Arc<AtomicU64>,
    /// The fault the simulation was stopped by when the window closed.
    stopped: Arc<Mutex<Option<String>>>,
}

impl OutputFailures {
    /// Says on stderr that an output failed (`kessler: error: …`), and
    /// counts it.
    pub fn failed(&self, what: impl Display) {
        eprintln!("kessler: error: {what}");
        self.failed.fetch_add(1, Ordering::Relaxed);
    }

    /// The outputs that failed.
    pub fn count(&self) -> u64 {
        self.failed.load(Ordering::Relaxed)
    }

    /// Notes that the window closed with the simulation stopped, by
    /// `fault` (its message).
    pub fn closed_stopped(&self, fault: String) {
        *self.stopped.lock().unwrap_or_else(PoisonError::into_inner) = Some(fault);
    }

    /// The fault the window closed stopped by, if it did.
    pub fn stopped(&self) -> Option<String> {
        self.stopped.lock().unwrap_or_else(PoisonError::into_inner).clone()
    }
}
