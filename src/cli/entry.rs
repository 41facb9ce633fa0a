//! The binary's entry point: parsing, dispatch, and the one-line error.

use std::process::ExitCode;

use clap::error::ErrorKind;
use clap::{Parser, Subcommand};

use crate::output::printable;

use super::{
    Cli, Command, EXIT_BAD_INPUT, EnsembleAction, Failure, RunArgs, bench, calibrate, ensemble, headless, pairs,
    validate, window,
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
            let message = misspelt_subcommand().unwrap_or_else(|| one_line(&e.render().to_string()));
            eprintln!("kessler: error: {message}");
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

/// Where the command line did not parse: a word after `ensemble` that is
/// no file but nearly one of its subcommands (`kessler ensemble stauts
/// DIR`), which clap takes for the config and then complains about what
/// follows it.
fn misspelt_subcommand() -> Option<String> {
    let args: Vec<String> = std::env::args().skip(1).take(2).collect();
    let [command, word] = args.as_slice() else {
        return None;
    };
    if command != "ensemble" || std::path::Path::new(word).exists() {
        return None;
    }
    let subcommands = EnsembleAction::augment_subcommands(clap::Command::new("ensemble"));
    let name = subcommands
        .get_subcommands()
        .map(clap::Command::get_name)
        .find(|name| name != word && crate::input::nearly(word, name))?;
    Some(printable(&format!(
        "`{word}` is neither a config file nor a subcommand of `ensemble`: did you mean `kessler ensemble {name}`?"
    )))
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
