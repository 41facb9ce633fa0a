//! Command-line arguments (docs/design.md, "Command line") — a stable
//! contract.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

use crate::input::{BENCH_EXECUTION_HEADING, EXECUTION_HEADING, ExecutionOptions};
use crate::resources::{DrawMethod, GravityMethod};

/// Thousands of bodies orbiting a planet: colliding, bouncing, shattering.
#[derive(Debug, Parser)]
#[command(name = "kessler", version, about, long_about = None)]
pub struct Cli {
    /// What to do; `run` if omitted.
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Open the interactive window (the default command).
    Run(RunArgs),
    /// Simulate without a window, print a summary and optionally dump the state.
    Headless(HeadlessArgs),
    /// Print the overlapping pairs of a scenario's initial state as CSV `a,b`.
    Pairs {
        /// Scenario file (RON).
        scenario: PathBuf,
        /// How the sweep executes.
        #[command(flatten, next_help_heading = EXECUTION_HEADING)]
        execution: ExecutionOptions,
    },
    /// Measure the runs of a benchmark config; write CSV results and, beside
    /// them, every pass, the overhead of splitting, the crossover, the
    /// machine, window runs' frames and a plot (never over existing files).
    Bench {
        /// Benchmark config (RON), e.g. benches/crossover.ron.
        config: PathBuf,
        /// Results CSV; `<stem>-passes.csv`, `<stem>-overhead.csv`,
        /// `<stem>-crossover.csv`, `<stem>-machine.txt`, `<stem>-render.csv`,
        /// `<stem>.svg` and `<stem>.png` go beside it.
        #[arg(long, value_name = "FILE", default_value = "results.csv")]
        out: PathBuf,
        /// How the runs that do not say execute.
        #[command(flatten, next_help_heading = BENCH_EXECUTION_HEADING)]
        execution: ExecutionOptions,
        /// How gravity is summed in every run.
        #[arg(long, value_name = "auto|direct|tree[:THETA]", help = GravityMethod::help())]
        gravity: Option<GravityMethod>,
    },
    /// Measure from which body count each stage pays for splitting its work
    /// on this machine (a few seconds: about 2 on 2 cores); split policy
    /// `auto` uses the result.
    Calibrate {
        /// Worker threads to calibrate for, at most twice the hardware
        /// threads (more are bounded to that, with a warning) [default: all
        /// hardware threads].
        #[arg(
            long,
            value_parser = crate::input::threads_arg,
            allow_negative_numbers = true
        )]
        threads: Option<usize>,
        /// Where to store it [default: calibration.ron beside the settings,
        /// ~/.config/kessler/calibration.ron].
        #[arg(long, value_name = "FILE")]
        out: Option<PathBuf>,
    },
    /// Run many seeds and settings of one scenario (an ensemble) on this
    /// machine or as a Slurm job array, resumable, summed up into bands.
    Ensemble(EnsembleArgs),
    /// Check a scenario file: exit code 0, or a clear error and exit code 2.
    Validate {
        /// Scenario file (RON).
        scenario: PathBuf,
    },
}

/// `kessler ensemble CONFIG --out DIR`, or one of its subcommands.
#[derive(Debug, Clone, Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct EnsembleArgs {
    /// Ensemble config (RON), e.g. ensembles/quick.ron.
    #[arg(required = true)]
    pub config: Option<PathBuf>,
    /// The ensemble's folder: made if missing; running the same command
    /// again resumes it (on a file system every node sees, for Slurm).
    #[arg(long, value_name = "DIR", required = true)]
    pub out: Option<PathBuf>,
    /// Where the members run.
    #[arg(long, value_enum, default_value_t = Executor::Local)]
    pub executor: Executor,
    /// Members at once: local processes [default: hardware threads ÷ the
    /// config's threads], or Slurm's array throttle (`%J`) [default: none].
    #[arg(long, value_name = "J", value_parser = crate::input::jobs_arg, allow_negative_numbers = true)]
    pub jobs: Option<usize>,
    /// An option for `sbatch` (partition, account, time limit), e.g.
    /// `--slurm-arg=--partition=short`; repeatable.
    #[arg(long = "slurm-arg", value_name = "ARG", allow_hyphen_values = true)]
    pub slurm_args: Vec<String>,
    /// With `--executor slurm`: wait for the job array, then aggregate.
    #[arg(long)]
    pub wait: bool,
    /// Look at or work on an ensemble's folder.
    #[command(subcommand)]
    pub action: Option<EnsembleAction>,
}

/// Where an ensemble's members run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Executor {
    /// Member processes on this machine.
    Local,
    /// A Slurm job array, submitted with `sbatch`.
    Slurm,
}

/// `kessler ensemble status|aggregate|member`.
#[derive(Debug, Clone, Subcommand)]
pub enum EnsembleAction {
    /// Count the done, failed and missing members of an ensemble's folder.
    Status {
        /// The ensemble's folder.
        dir: PathBuf,
    },
    /// Sum up the finished members: DIR/aggregate.csv and the plot
    /// DIR/bodies.svg and .png.
    Aggregate {
        /// The ensemble's folder.
        dir: PathBuf,
    },
    /// Run one member (what each local process and Slurm task runs).
    Member {
        /// The ensemble's folder.
        dir: PathBuf,
        /// The member's index, from 0.
        #[arg(value_parser = clap::value_parser!(u64), allow_negative_numbers = true)]
        index: u64,
    },
}

/// How the window runs; everything but the scenario is optional.
#[derive(Debug, Clone, Default, Args)]
pub struct RunArgs {
    /// Scenario file (RON); the saved or built-in scenario if omitted.
    pub scenario: Option<PathBuf>,
    /// Close after this many frames and print frame-time statistics.
    #[arg(long, value_name = "N", value_parser = crate::input::positive_count_arg, allow_negative_numbers = true)]
    pub frames: Option<u64>,
    /// Save a PNG of the window after the last frame (needs --frames; the
    /// file must not exist yet).
    #[arg(long, value_name = "FILE", requires = "frames")]
    pub screenshot: Option<PathBuf>,
    /// Settings file to load and save [default: ~/.config/kessler/settings.ron].
    #[arg(long, value_name = "FILE")]
    pub settings: Option<PathBuf>,
    /// How to draw the bodies (overrides the saved setting).
    #[arg(long, value_enum)]
    pub render: Option<RenderArg>,
    /// Generated bodies, at most 2 000 000 (overrides the scenario's count
    /// for this run).
    #[arg(long, value_name = "N", value_parser = crate::input::run_bodies_arg, allow_negative_numbers = true)]
    pub bodies: Option<u64>,
    /// Start with the simulation paused (to measure rendering alone).
    #[arg(long)]
    pub paused: bool,
    /// Wait for the display's refresh, or draw as fast as possible
    /// (overrides the saved setting).
    #[arg(long, value_enum, value_name = "on|off")]
    pub vsync: Option<OnOff>,
    /// How the simulation executes (each overrides the saved setting).
    #[command(flatten, next_help_heading = "Execution (each overrides the saved setting)")]
    pub execution: ExecutionOptions,
    /// Target simulation updates per second, 1–600 (overrides the saved
    /// setting).
    #[arg(long, value_name = "UPS", value_parser = crate::input::ups_arg, allow_negative_numbers = true)]
    pub ups: Option<u32>,
    /// With --frames: write what the run measured (frame times, memory,
    /// GPU memory) to this new file, `key=value` per line (benchmark
    /// `Render` runs read it).
    #[arg(long, value_name = "FILE", requires = "frames")]
    pub frame_report: Option<PathBuf>,
    /// With --frames: at the close, write the state as `headless --dump`
    /// writes it, and print the update count and the state's hash.
    #[arg(long, value_name = "FILE", requires = "frames")]
    pub dump: Option<PathBuf>,
    /// Tool actions to take at given frames, as the panel's buttons take
    /// them: a RON list of `(frame: N, action: Launch(...) | Fire(...) |
    /// Breakup(...) | Remove | Rewind | Select(ID) | SaveSession("FILE"))`.
    #[arg(long, value_name = "FILE")]
    pub actions: Option<PathBuf>,
    /// With --frames: draw into an image instead of a window (no X server
    /// needed: a GPU server, or Mesa's software Vulkan).
    #[arg(long, requires = "frames")]
    pub offscreen: bool,
    /// A numbered PNG (frame-000001.png, …) in this folder every --every
    /// updates: a film of the run.
    #[arg(long, value_name = "DIR")]
    pub frames_out: Option<PathBuf>,
    /// Updates between two pictures of --frames-out.
    #[arg(long, value_name = "K", default_value_t = 1, requires = "frames_out", value_parser = crate::input::positive_count_arg, allow_negative_numbers = true)]
    pub every: u64,
}

/// `--render` on the command line: the thesis's three drawing methods.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum RenderArg {
    /// All cubes in one instanced draw.
    Instanced,
    /// One Bevy mesh entity per body, all sharing one mesh.
    #[value(alias = "meshes")]
    SharedMesh,
    /// One Bevy mesh entity per body, each with its own copy of the mesh.
    MeshPerBody,
}

impl From<RenderArg> for DrawMethod {
    fn from(arg: RenderArg) -> Self {
        match arg {
            RenderArg::Instanced => Self::Instanced,
            RenderArg::SharedMesh => Self::SharedMesh,
            RenderArg::MeshPerBody => Self::MeshPerBody,
        }
    }
}

/// `on` or `off`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum OnOff {
    /// On.
    On,
    /// Off.
    Off,
}

impl From<OnOff> for bool {
    fn from(v: OnOff) -> Self {
        v == OnOff::On
    }
}

/// `kessler headless`.
#[derive(Debug, Clone, Args)]
pub struct HeadlessArgs {
    /// Scenario file (RON).
    pub scenario: PathBuf,
    /// Number of simulation updates (at most 10^12).
    #[arg(long, value_parser = crate::input::updates_arg, allow_negative_numbers = true)]
    pub steps: u64,
    /// How the simulation executes.
    #[command(flatten, next_help_heading = EXECUTION_HEADING)]
    pub execution: ExecutionOptions,
    /// Write the final state as CSV (`id,x,y,z,vx,vy,vz,mass,hx,hy,hz,role,interacts`).
    #[arg(long, value_name = "FILE")]
    pub dump: Option<PathBuf>,
    /// Write the final state as a scenario file: every body with its id, and
    /// the settings; running on from it continues this run exactly.
    #[arg(long, value_name = "FILE")]
    pub save_scenario: Option<PathBuf>,
    /// How gravity is summed.
    #[arg(long, value_name = "auto|direct|tree[:THETA]", help = GravityMethod::help())]
    pub gravity: Option<GravityMethod>,
    /// Write a row every K updates (`--every`) as CSV
    /// (`update,bodies,pairs,shatters,refused_shatters,mass,kinetic_energy,momentum_x,momentum_y,momentum_z,reentries,absorbed_mass,deferred,state_hash`).
    #[arg(long, value_name = "FILE")]
    pub timeline: Option<PathBuf>,
    /// Updates between two timeline rows (needs `--timeline`).
    #[arg(
        long,
        value_name = "K",
        requires = "timeline",
        default_value_t = 1,
        value_parser = crate::input::positive_count_arg,
        allow_negative_numbers = true
    )]
    pub every: u64,
}
