//! Command-line arguments (DESIGN §5) — a stable contract.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

use crate::resources::{ExecutionMode, MAX_THREADS};

/// Thousands of bodies orbiting a planet: colliding, bouncing, shattering.
#[derive(Debug, Parser)]
#[command(name = "kessler", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Open the interactive window (the default command).
    Run {
        /// Scenario file (RON); the built-in debris field if omitted.
        scenario: Option<PathBuf>,
    },
    /// Simulate without a window, print a summary and optionally dump the state.
    Headless(HeadlessArgs),
    /// Print the overlapping pairs of a scenario's initial state as CSV `a,b`.
    Pairs {
        /// Scenario file (RON).
        scenario: PathBuf,
        #[command(flatten)]
        execution: ExecutionArgs,
    },
    /// Measure the runs of a benchmark config; write CSV results, an overhead
    /// report and an SVG plot beside them (never over existing files).
    Bench {
        /// Benchmark config (RON), e.g. benches/thesis.ron.
        config: PathBuf,
        /// Results CSV; `<stem>-overhead.csv` and `<stem>.svg` go beside it.
        #[arg(long, value_name = "FILE", default_value = "results.csv")]
        out: PathBuf,
    },
    /// Check a scenario file: exit code 0, or a clear error and exit code 2.
    Validate {
        /// Scenario file (RON).
        scenario: PathBuf,
    },
}

/// How a simulation executes.
#[derive(Debug, Clone, Args)]
pub struct ExecutionArgs {
    /// Sequential or parallel stages.
    #[arg(long, value_enum, default_value_t = ExecutionMode::Parallel)]
    pub mode: ExecutionMode,
    /// Worker threads in parallel mode [default: all hardware threads].
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..=MAX_THREADS as i64), allow_negative_numbers = true)]
    pub threads: Option<u16>,
}

#[derive(Debug, Clone, Args)]
pub struct HeadlessArgs {
    /// Scenario file (RON).
    pub scenario: PathBuf,
    /// Number of simulation updates.
    #[arg(long, allow_negative_numbers = true)]
    pub steps: u64,
    #[command(flatten)]
    pub execution: ExecutionArgs,
    /// Write the final state as CSV (`id,x,y,z,vx,vy,vz,mass,hx,hy,hz,role,interacts`).
    #[arg(long, value_name = "FILE")]
    pub dump: Option<PathBuf>,
}
