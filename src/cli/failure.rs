//! [`Failure`]: how a command fails — one line for stderr and an exit code —
//! and how the typed errors of the library become one.

use std::fmt;

use crate::bench::{BenchOutputError, RunError};
use crate::ensemble::EnsembleError;
use crate::execution::ExecutionError;
use crate::input::InputError;
use crate::output::{OutputError, WriteError};
use crate::scenario::CannotResize;
use crate::simulation::HeadlessError;

/// Exit code for bad input (arguments, scenario files, output paths).
pub const EXIT_BAD_INPUT: u8 = 2;

/// Exit code for a failure that is not the input's fault (a disk that
/// fills up, a window that cannot open).
pub const EXIT_FAILURE: u8 = 1;

/// Exit code for a simulation that stopped because its state could not be
/// computed any more (a non-finite value, a pile-up of bodies).
pub const EXIT_SIMULATION_STOPPED: u8 = 3;

/// Exit code for a command stopped by Ctrl-C (128 + SIGINT).
pub const EXIT_INTERRUPTED: u8 = 130;

/// Why a command failed: one line for stderr and an exit code.
#[derive(Debug)]
pub struct Failure {
    /// The line, without the `kessler: error: ` prefix.
    pub message: String,
    /// The process's exit code.
    pub code: u8,
}

impl Failure {
    /// Bad user input: exit code 2.
    pub fn input(message: impl fmt::Display) -> Self {
        Self {
            message: message.to_string(),
            code: EXIT_BAD_INPUT,
        }
    }

    /// Anything else: exit code 1.
    pub fn other(message: impl fmt::Display) -> Self {
        Self {
            message: message.to_string(),
            code: EXIT_FAILURE,
        }
    }

    /// A simulation that stopped at a fault: exit code 3.
    pub fn stopped(message: impl fmt::Display) -> Self {
        Self {
            message: message.to_string(),
            code: EXIT_SIMULATION_STOPPED,
        }
    }

    /// The same failure with `context` (an option, a file) before its message.
    pub fn context(self, context: impl fmt::Display) -> Self {
        Self {
            message: format!("{context}: {}", self.message),
            ..self
        }
    }
}

/// The typed errors a command may end with, by exit code.
macro_rules! failure_from {
    ($code:expr => $($error:ty),*) => {$(
        impl From<$error> for Failure {
            fn from(e: $error) -> Self {
                Self {
                    message: e.to_string(),
                    code: $code,
                }
            }
        }
    )*};
}

failure_from!(EXIT_BAD_INPUT => InputError, OutputError, CannotResize, ExecutionError);
failure_from!(EXIT_FAILURE => WriteError, BenchOutputError);

impl From<RunError> for Failure {
    fn from(e: RunError) -> Self {
        let code = match e {
            RunError::Stopped(_) => EXIT_SIMULATION_STOPPED,
            _ => EXIT_BAD_INPUT,
        };
        Self {
            message: e.to_string(),
            code,
        }
    }
}

impl From<HeadlessError> for Failure {
    fn from(e: HeadlessError) -> Self {
        let code = match e {
            HeadlessError::Scenario(_) => EXIT_BAD_INPUT,
            HeadlessError::Stopped(_) => EXIT_SIMULATION_STOPPED,
            HeadlessError::Write(_) => EXIT_FAILURE,
        };
        Self {
            message: e.to_string(),
            code,
        }
    }
}

impl From<EnsembleError> for Failure {
    fn from(e: EnsembleError) -> Self {
        let code = match e {
            EnsembleError::Input(_)
            | EnsembleError::Output(_)
            | EnsembleError::Execution(_)
            | EnsembleError::Arguments(_) => EXIT_BAD_INPUT,
            EnsembleError::Write(_) | EnsembleError::Failed(_) => EXIT_FAILURE,
            EnsembleError::Stopped(_) => EXIT_SIMULATION_STOPPED,
            EnsembleError::Interrupted(_) => EXIT_INTERRUPTED,
        };
        Self {
            message: e.to_string(),
            code,
        }
    }
}

#[cfg(feature = "gui")]
impl From<crate::ui::WindowError> for Failure {
    fn from(e: crate::ui::WindowError) -> Self {
        let code = match e {
            crate::ui::WindowError::App(code) => code,
            crate::ui::WindowError::Outputs(_) => EXIT_FAILURE,
            crate::ui::WindowError::Stopped(_) => EXIT_SIMULATION_STOPPED,
            _ => EXIT_BAD_INPUT,
        };
        Self {
            message: e.to_string(),
            code,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn input_errors_exit_2_and_write_errors_exit_1() {
        let bad: Failure = InputError::new("f.ron", "field `mass`: must be > 0").into();
        assert_eq!(
            (bad.code, bad.message.as_str()),
            (2, "f.ron: field `mass`: must be > 0")
        );
        let write: Failure = WriteError {
            path: "out.csv".into(),
            source: std::io::Error::other("disk full"),
        }
        .into();
        assert_eq!((write.code, write.message.as_str()), (1, "out.csv: disk full"));
        assert_eq!(bad.context("--x").message, "--x: f.ron: field `mass`: must be > 0");
    }
}
