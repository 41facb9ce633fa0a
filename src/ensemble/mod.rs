//! Ensembles (docs/guide.md, "Ensembles"): many seeds and settings of one
//! scenario, each member a headless run with a timeline, on this machine or
//! as a Slurm job array; one folder holds everything, so a run can always
//! be resumed; the members are summed up into bands.
//!
//! `config` reads the config; `start` checks it and its folder and writes
//! the folder's record; `seeds` mixes each member's seed; `member` runs
//! one; `local` and `slurm` are the two executors; `aggregate` and `plot`
//! sum the finished members up.

mod aggregate;
mod config;
mod error;
mod folder;
mod local_executor;
mod member;
mod plot;
mod preflight;
mod seeds;
mod slurm_executor;
mod summary;

pub use aggregate::{AggregateRow, Aggregated, Series, Stats, aggregate, combination_rows, percentile, read_series};
pub use config::{EnsembleConfig, MAX_MEMBERS, Varied, Vary};
pub use error::EnsembleError;
pub use folder::{Census, EnsembleFolder, MemberState, Record, SCENARIO_COPY, hash_text};
pub use local_executor::{LocalRun, run_local};
pub use member::{member_scenario, run_member};
pub use plot::{Band, BodiesPlot};
pub use preflight::{Started, start};
pub use seeds::member_seed;
pub use slurm_executor::{array_spec, sbatch_script, submit, wait};
pub use summary::MemberSummary;
