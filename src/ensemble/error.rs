//! [`EnsembleError`]: why an ensemble command stopped, by kind, so that the
//! command line gives each its exit code.

use crate::execution::ExecutionError;
use crate::input::InputError;
use crate::output::{OutputError, WriteError};

/// Why an ensemble command (or one member) stopped.
#[derive(Debug, thiserror::Error)]
pub enum EnsembleError {
    /// Bad input: the config, its scenario, an argument (exit code 2).
    #[error(transparent)]
    Input(#[from] InputError),
    /// An output folder that cannot be used (exit code 2).
    #[error(transparent)]
    Output(#[from] OutputError),
    /// Execution options out of range (exit code 2).
    #[error(transparent)]
    Execution(#[from] ExecutionError),
    /// Arguments that do not go together (exit code 2).
    #[error("{0}")]
    Arguments(String),
    /// A file could not be written (exit code 1).
    #[error(transparent)]
    Write(#[from] WriteError),
    /// A member's simulation stopped at a fault (exit code 3).
    #[error("{0}")]
    Stopped(String),
    /// Members failed, or Slurm did not take the job (exit code 1).
    #[error("{0}")]
    Failed(String),
    /// Ctrl-C: the finished members are kept (exit code 130).
    #[error("{0}")]
    Interrupted(String),
}
