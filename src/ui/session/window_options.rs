//! What `kessler run` asks of the window, and why it may refuse.

use std::path::PathBuf;

use crate::execution::ExecutionError;
use crate::input::{ExecutionOptions, InputError};
use crate::output::OutputError;
use crate::resources::DrawMethod;
use crate::scenario::CannotResize;

/// How the window runs; everything is optional.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WindowOptions {
    /// Scenario file; the saved or built-in scenario if `None`.
    pub scenario: Option<PathBuf>,
    /// Close after this many frames and print frame-time statistics.
    pub frames: Option<u64>,
    /// Save a PNG of the window after the last frame (a new file).
    pub screenshot: Option<PathBuf>,
    /// Settings file to load and save instead of the default one.
    pub settings: Option<PathBuf>,
    /// Drawing method for this run (not saved).
    pub render: Option<DrawMethod>,
    /// Generated bodies for this run (not saved; the command line bounds
    /// it: `crate::input::run_bodies_arg`).
    pub bodies: Option<u64>,
    /// Start with the simulation paused (to measure rendering alone).
    pub paused: bool,
    /// Vsync on or off for this run (not saved).
    pub vsync: Option<bool>,
    /// How the simulation executes in this run, each option given over
    /// the saved one (not saved).
    pub execution: ExecutionOptions,
    /// Target updates per second for this run (not saved).
    pub ups: Option<u32>,
    /// Where a scripted run writes what it measured (`key=value` lines, a
    /// new file), for benchmark `Render` runs.
    pub frame_report: Option<PathBuf>,
    /// Where a scripted run writes the state at its close (`headless
    /// --dump`'s format).
    pub dump: Option<PathBuf>,
    /// A file of tool actions to take at given frames.
    pub actions: Option<PathBuf>,
    /// Draw into an image instead of a window: no display needed.
    pub offscreen: bool,
    /// A folder for a numbered PNG every `every` updates (a film).
    pub frames_out: Option<PathBuf>,
    /// Updates between two pictures of `frames_out`.
    pub every: u64,
}

/// Why the window could not run.
#[derive(Debug, thiserror::Error)]
pub enum WindowError {
    /// The screenshot path cannot be written.
    #[error(transparent)]
    Screenshot(#[from] OutputError),
    /// There is no display to open a window on.
    #[error(
        "no X11 display (DISPLAY is not set): run the window in a desktop session, \
         under `xvfb-run kessler run`, or use `kessler headless`"
    )]
    NoDisplay,
    /// The scenario named on the command line is unusable.
    #[error(transparent)]
    Scenario(#[from] InputError),
    /// `--bodies` on a scenario that cannot take it (no generators, or ids
    /// past their bound).
    #[error("--bodies: {0}")]
    Resize(#[from] CannotResize),
    /// The worker pool could not be made.
    #[error(transparent)]
    Execution(#[from] ExecutionError),
    /// The app itself stopped with an error (its log says more).
    #[error("the window app stopped with an error (see the log above)")]
    App(u8),
    /// The simulation was stopped by a fault when the window closed (the
    /// scenario and the fault, in words): its state, half an update, was not written.
    #[error("{0}")]
    Stopped(String),
    /// Outputs failed during the run (each said why as it failed).
    #[error("{0} output(s) of the run could not be written (see the errors above)")]
    Outputs(u64),
}
