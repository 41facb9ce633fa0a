//! The binary's entry point: parsing, dispatch, and the one-line error.

use std::process::ExitCode;

use clap::Parser;
use clap::error::ErrorKind;

use crate::output::printable;

use super::{
    Cli, Command, EXIT_BAD_INPUT, Failure, RunArgs, bench, calibrate, ensemble, headless, pairs, validate, window,
};

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
            eprintln!("kessler: error: {}", printable(&f.message));
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
    printable(&format!("{} (see `kessler --help`)", parts.join(" ")))
}

fn dispatch(command: Option<Command>) -> Result<(), Failure> {
    match command.unwrap_or(Command::Run(RunArgs::default())) {
        Command::Run(args) => window::run(args),
        Command::Headless(args) => headless::headless(&args),
        Command::Bench {
            config,
            out,
            execution,
            gravity,
        } => bench::bench(&config, &out, execution, gravity),
        Command::Calibrate { threads, out } => calibrate::calibrate_command(threads, out.as_deref()),
        Command::Pairs { scenario, execution } => pairs::pairs(&scenario, &execution),
        Command::Ensemble(args) => ensemble::ensemble(&args),
        Command::Validate { scenario } => validate::validate(&scenario),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clap_errors_fold_into_one_line() {
        let rendered = "error: invalid value 'x' for '--steps <STEPS>'\n\nUsage: kessler headless\n\nFor more information, try '--help'.\n";
        assert_eq!(
            one_line(rendered),
            "invalid value 'x' for '--steps <STEPS>' (see `kessler --help`)"
        );
    }
}
