//! The `kessler` command line: one file per subcommand, the arguments, and
//! the one-line failure every command ends with on bad input.

mod args;
mod bench;
mod calibrate;
mod ensemble;
mod entry;
mod failure;
mod headless;
mod pairs;
mod validate;
mod window;

pub use args::{Cli, Command, EnsembleAction, EnsembleArgs, Executor, HeadlessArgs, OnOff, RenderArg, RunArgs};
pub use entry::main;
pub use failure::{EXIT_BAD_INPUT, EXIT_FAILURE, EXIT_INTERRUPTED, EXIT_SIMULATION_STOPPED, Failure};
