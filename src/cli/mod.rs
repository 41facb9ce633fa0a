//! The `kessler` command line: parsing, dispatch and error reporting.

mod args;
mod bench;
mod headless;
mod pairs;
mod validate;

pub use args::*;

use std::fmt;
use std::process::ExitCode;

use clap::Parser;
use clap::error::ErrorKind;

use crate::scenario::{DEFAULT_SCENARIO, DEFAULT_SCENARIO_NAME, Scenario};

/// Exit code for bad input (arguments, scenario files).
pub const EXIT_BAD_INPUT: u8 = 2;

/// Why a command failed: one line for stderr and an exit code.
#[derive(Debug)]
pub struct Failure {
    pub message: String,
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
}

/// Entry point of the binary.
pub fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) => {
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
        Err(e) => {
            eprintln!("kessler: error: {}", one_line(&e.render().to_string()));
            return ExitCode::from(EXIT_BAD_INPUT);
        }
    };
    match dispatch(cli.command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            eprintln!("kessler: error: {}", f.message);
            ExitCode::from(f.code)
        }
    }
}

/// clap's error folded into one line: the problem and the hints, without
/// the usage block.
fn one_line(rendered: &str) -> String {
    let parts: Vec<&str> = rendered
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with("Usage:") && !l.starts_with("For more information"))
        .map(|l| l.trim_start_matches("error: "))
        .collect();
    format!("{} (see `kessler --help`)", parts.join(" "))
}

fn dispatch(command: Option<Command>) -> Result<(), Failure> {
    match command.unwrap_or(Command::Run(RunArgs::default())) {
        Command::Run(args) => run(args),
        Command::Headless(args) => headless::headless(&args),
        Command::Bench { config, out } => bench::bench(&config, &out),
        Command::Pairs { scenario, execution } => pairs::pairs(&scenario, &execution),
        Command::Validate { scenario } => validate::validate(&scenario),
    }
}

/// Checks that the folder an output file `path` (given with `flag`) goes
/// into exists.
pub fn check_output_folder(flag: &str, path: &std::path::Path) -> Result<(), Failure> {
    let folder = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(std::path::Path::new("."));
    if folder.is_dir() {
        Ok(())
    } else {
        Err(Failure::input(format!(
            "{flag} {}: folder {} does not exist",
            path.display(),
            folder.display()
        )))
    }
}

/// Loads the scenario at `path`, or the built-in default; returns it with
/// the name to use in messages.
pub fn load_scenario(path: Option<&std::path::Path>) -> Result<(Scenario, String), Failure> {
    match path {
        Some(path) => Ok((
            Scenario::load(path).map_err(Failure::input)?,
            path.display().to_string(),
        )),
        None => Ok((
            Scenario::parse(DEFAULT_SCENARIO, DEFAULT_SCENARIO_NAME).map_err(Failure::input)?,
            DEFAULT_SCENARIO_NAME.to_owned(),
        )),
    }
}

/// Updates `kessler run` simulates when the window is not built.
#[cfg(not(feature = "gui"))]
const RUN_UPDATES: u64 = 600;

#[cfg(not(feature = "gui"))]
fn run(args: RunArgs) -> Result<(), Failure> {
    if args.frames.is_some() || args.screenshot.is_some() || args.render.is_some() {
        return Err(Failure::input(
            "this kessler was built without the window (cargo feature `gui`); \
             --frames, --screenshot and --render need it",
        ));
    }
    eprintln!(
        "kessler: the interactive window is not part of this build (cargo feature `gui`); \
         simulating {RUN_UPDATES} updates headless instead (see `kessler headless --help`)"
    );
    let (mut scenario, origin) = load_scenario(args.scenario.as_deref())?;
    if let Some(count) = args.bodies {
        scenario = scenario
            .with_generated(count)
            .ok_or_else(|| Failure::input(format!("{origin}: has no generators, so --bodies cannot apply")))?;
    }
    let execution = crate::resources::Execution::all_cores(Default::default()).map_err(Failure::input)?;
    headless::simulate(&scenario, &origin, execution, RUN_UPDATES, None)
}

#[cfg(feature = "gui")]
fn run(args: RunArgs) -> Result<(), Failure> {
    crate::ui::run(args)
}
