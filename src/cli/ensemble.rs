//! `kessler ensemble CONFIG --out DIR [--executor local|slurm] [--jobs J]
//! [--slurm-arg ARG]... [--wait]`, and `kessler ensemble status|aggregate|member`.

use std::path::Path;

use super::{EnsembleAction, EnsembleArgs, Executor, Failure};
use crate::ensemble::{
    self, Census, EnsembleError, EnsembleFolder, Record, Started, aggregate, run_local, sbatch_script, submit,
};
use crate::execution::available_threads;
use crate::output::printable;

/// Runs the command.
pub fn ensemble(args: &EnsembleArgs) -> Result<(), Failure> {
    match &args.action {
        Some(EnsembleAction::Status { dir }) => status(dir),
        Some(EnsembleAction::Aggregate { dir }) => {
            let (folder, record) = EnsembleFolder::open(dir)?;
            let census = folder.checked_census(&record.config);
            left_out(&folder, &record, &census);
            sum_up(&folder, &record, &census)
        }
        Some(EnsembleAction::Member { dir, index }) => member(dir, *index),
        None => {
            let (Some(config), Some(out)) = (&args.config, &args.out) else {
                return Err(Failure::input(
                    "give a config and --out DIR (see `kessler ensemble --help`)",
                ));
            };
            run(args, config, out)
        }
    }
}

fn run(args: &EnsembleArgs, config: &Path, out: &Path) -> Result<(), Failure> {
    if args.executor == Executor::Local {
        if args.wait {
            return Err(Failure::input(
                "--wait: goes with --executor slurm (the local executor always waits for its members)",
            ));
        }
        if let Some(arg) = args.slurm_args.first() {
            return Err(Failure::input(format!("--slurm-arg {arg}: goes with --executor slurm")));
        }
    }
    let Started {
        folder,
        record,
        census,
        resumed,
        warning,
    } = ensemble::start(config, out)?;
    if let Some(warning) = warning {
        eprintln!("kessler: warning: {}", printable(&warning));
    }
    let total = record.config.total_members();
    let to_run = census.to_run();
    let exe = std::env::current_exe()
        .map_err(|e| Failure::other(format!("the path of this kessler binary cannot be found: {e}")))?;
    let root = folder.root().display().to_string();
    if to_run.is_empty() {
        eprintln!("kessler: {root}: all {total} members are done");
        return sum_up(&folder, &record, &census);
    }
    let combinations = record.config.vary.combinations();
    eprintln!(
        "kessler: {root}: {total} members ({combinations} combination{} × {}){}; {} to run",
        if combinations == 1 { "" } else { "s" },
        record.config.members,
        if resumed {
            format!(", resumed: {}", census.line())
        } else {
            String::new()
        },
        to_run.len()
    );
    match args.executor {
        Executor::Local => {
            let jobs = args
                .jobs
                .unwrap_or_else(|| (available_threads() / record.config.member_execution().threads()).max(1));
            let ran = run_local(&folder, &to_run, jobs, &exe)?;
            eprintln!(
                "kessler: {root}: {} members run in {:.1} s, {jobs} at a time ({} failed)",
                to_run.len(),
                ran.seconds,
                ran.failed.len()
            );
            finish(&folder, &record)
        }
        Executor::Slurm => {
            let script = sbatch_script(
                &folder,
                &exe,
                &to_run,
                args.jobs,
                record.config.member_execution().threads(),
            )
            .map_err(Failure::input)?;
            let id = submit(&folder, &script, &args.slurm_args, &to_run)?;
            println!(
                "{}",
                printable(&format!(
                    "{root}: submitted job array {id} to Slurm: {} members (`{}`); logs in {root}/slurm/logs; `kessler ensemble status {root}` counts them",
                    to_run.len(),
                    ensemble::array_spec(&to_run)
                ))
            );
            if !args.wait {
                return Ok(());
            }
            let seconds = ensemble::wait(&folder, &id, &to_run)?;
            eprintln!("kessler: {root}: job array {id} ended after {seconds:.1} s");
            finish(&folder, &record)
        }
    }
}

/// After the members ran: the aggregate, then a failure if any member
/// failed (or is still missing).
fn finish(folder: &EnsembleFolder, record: &Record) -> Result<(), Failure> {
    let census = folder.checked_census(&record.config);
    if !census.done.is_empty() {
        sum_up(folder, record, &census)?;
    }
    if census.failed.is_empty() && census.missing.is_empty() {
        return Ok(());
    }
    Err(Failure::from(EnsembleError::Failed(unfinished(folder, &census))))
}

/// `; member I failed: WHY` for the first member that failed, if any.
fn first_failed(census: &Census) -> String {
    census
        .failed
        .first()
        .map(|(index, why)| format!("; member {index} failed: {why}"))
        .unwrap_or_default()
}

/// Why not every member is done, in one line.
fn unfinished(folder: &EnsembleFolder, census: &Census) -> String {
    let first = first_failed(census);
    format!(
        "{}: {}{first}; run the same command again to run the failed and missing members",
        folder.root().display(),
        census.line()
    )
}

/// `kessler ensemble aggregate DIR`, and the end of a run: sums up the
/// members `census` counts done.
fn sum_up(folder: &EnsembleFolder, record: &Record, census: &Census) -> Result<(), Failure> {
    if census.done.is_empty() {
        return Err(Failure::other(format!(
            "{}: no member is done yet, so there is nothing to aggregate ({})",
            folder.root().display(),
            census.line()
        )));
    }
    let summed = aggregate(folder, record, &census.done)?;
    println!(
        "{}",
        printable(&format!(
            "{}: {} rows from {} members in {} combination{} written to {}, plot {} and {}",
            folder.root().display(),
            summed.rows,
            summed.members,
            summed.combinations,
            if summed.combinations == 1 { "" } else { "s" },
            folder.aggregate_csv().display(),
            folder.plot("svg").display(),
            folder.plot("png").display(),
        ))
    );
    Ok(())
}

/// Says which members `ensemble aggregate` leaves out (failed, damaged or
/// missing) and what runs them.
fn left_out(folder: &EnsembleFolder, record: &Record, census: &Census) {
    let out = census.failed.len() + census.missing.len();
    if out == 0 {
        return;
    }
    let first = first_failed(census);
    eprintln!(
        "kessler: warning: {}",
        printable(&format!(
            "{}: {out} member(s) left out of the aggregate ({}){first}; `kessler ensemble {} --out {}` runs them",
            folder.root().display(),
            census.line(),
            record.source,
            folder.root().display()
        ))
    );
}

/// `kessler ensemble status DIR`.
fn status(dir: &Path) -> Result<(), Failure> {
    let (folder, record) = EnsembleFolder::open(dir)?;
    let census = folder.checked_census(&record.config);
    println!(
        "{}",
        printable(&format!("{}: {}", folder.root().display(), census.line()))
    );
    const SHOWN: usize = 10;
    for (index, why) in census.failed.iter().take(SHOWN) {
        println!("{}", printable(&format!("member {index} failed: {why}")));
    }
    if census.failed.len() > SHOWN {
        println!("… and {} more failed", census.failed.len() - SHOWN);
    }
    Ok(())
}

/// `kessler ensemble member DIR INDEX`.
fn member(dir: &Path, index: u64) -> Result<(), Failure> {
    let (folder, record) = EnsembleFolder::open(dir)?;
    let summary = ensemble::run_member(&folder, &record, index)?;
    println!(
        "{}",
        printable(&format!(
            "member {index} ({}seed {}): {} updates, {} → {} bodies, {} shatters in {:.3} s; state hash {}",
            if summary.settings.is_empty() {
                String::new()
            } else {
                format!("{}, ", summary.settings)
            },
            summary.seed,
            summary.steps,
            summary.bodies_start,
            summary.bodies,
            summary.shatters,
            summary.wall_seconds,
            summary.state_hash
        ))
    );
    Ok(())
}
