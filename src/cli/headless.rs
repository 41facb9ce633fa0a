//! `kessler headless SCENARIO --steps N [--mode M] [--threads T] [--dump FILE]`.

use std::path::Path;
use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};

use super::{ExecutionArgs, Failure, HeadlessArgs};
use crate::Simulation;
use crate::calibration::machine_auto_split;
use crate::dump;
use crate::execution::{Execution, ExecutionMode, SplitPolicy, WorkerPool, available_threads};
use crate::output::{Output, WriteError, check_outputs, commit_all, printable, stage};
use crate::resources::MemoryBudget;
use crate::scenario::{Scenario, Snapshot, beyond_a_scenario, write_snapshot};
use crate::systems::SimulationSystems;
use crate::timeline::Timeline;
use crate::user_files::default_calibration_path;

/// Makes the execution the arguments ask for (split policy `auto` with
/// this machine's calibration).
pub fn execution(args: &ExecutionArgs) -> Result<Execution, Failure> {
    let threads = args.threads.unwrap_or_else(available_threads);
    let execution = Execution::new(args.mode.into(), threads).map_err(|e| Failure::from(e).context("--threads"))?;
    Ok(execution
        .with_split(args.split)
        .with_auto_split(machine_auto_split())
        .with_pool(args.pool.into()))
}

/// Says on stderr where the scenario's `max_bodies` would not fit in the
/// memory this process may use.
pub fn warn_of_memory(scenario: &Scenario) {
    if let Some(warning) = MemoryBudget::default().warning(scenario.physics.max_bodies) {
        eprintln!(
            "kessler: warning: {}: {}",
            printable(&scenario.origin),
            printable(&warning)
        );
    }
}

/// Runs the command.
pub fn headless(args: &HeadlessArgs) -> Result<(), Failure> {
    let mut scenario = Scenario::load(&args.scenario)?;
    if let Some(gravity) = args.gravity {
        scenario.physics.gravity_method = gravity;
    }
    warn_of_memory(&scenario);
    let named: Vec<Output<'_>> = [
        ("--dump", &args.dump),
        ("--save-scenario", &args.save_scenario),
        ("--timeline", &args.timeline),
    ]
    .into_iter()
    .filter_map(|(flag, path)| path.as_deref().map(|p| Output::replacing(flag, p)))
    .collect();
    let calibration = default_calibration_path();
    check_outputs(
        &named,
        &[
            ("the scenario", &args.scenario),
            ("the split calibration", &calibration),
        ],
    )?;
    let outputs = Outputs {
        dump: args.dump.as_deref(),
        scenario: args.save_scenario.as_deref(),
        timeline: args.timeline.as_deref().map(|path| (path, args.every)),
    };
    simulate(&scenario, execution(&args.execution)?, args.steps, outputs)
}

/// Where a headless run writes its final state, if anywhere.
#[derive(Clone, Copy, Debug, Default)]
pub struct Outputs<'a> {
    /// The CSV dump (`--dump`).
    pub dump: Option<&'a Path>,
    /// The snapshot scenario (`--save-scenario`).
    pub scenario: Option<&'a Path>,
    /// The timeline (`--timeline`) and the updates between its rows.
    pub timeline: Option<(&'a Path, u64)>,
}

/// Runs `updates` updates of `scenario` with a progress bar on a terminal,
/// prints a one-line summary ending with the state's hash, and writes the dump, the timeline and the
/// snapshot if asked: all of them, or none.
pub fn simulate(scenario: &Scenario, execution: Execution, updates: u64, outputs: Outputs<'_>) -> Result<(), Failure> {
    let dump_path = outputs.dump;
    let (mode, threads) = (execution.mode(), execution.threads_used());
    let split = match (mode, execution.split()) {
        (ExecutionMode::Sequential, _) => String::new(),
        (_, SplitPolicy::Auto) => format!(", split auto ({})", execution.auto_split().origin()),
        (_, split) => format!(", split {split}"),
    };
    let split = match (mode, execution.pool()) {
        (ExecutionMode::Parallel, WorkerPool::Bevy) => format!("{split}, on Bevy's ComputeTaskPool"),
        _ => split,
    };
    let mut sim = Simulation::from_scenario(scenario, execution)?;
    let bodies_start = sim.body_count();

    let progress = ProgressBar::new(updates).with_style(
        ProgressStyle::with_template("{spinner} {pos}/{len} updates [{bar:30}] {per_sec} eta {eta}")
            .expect("template is valid")
            .progress_chars("=> "),
    );
    let mut timeline = outputs.timeline.map(|(_, every)| Timeline::new(every));
    let start = Instant::now();
    match timeline.as_mut() {
        Some(timeline) => timeline.run(&mut sim, updates, |done| progress.set_position(done)),
        None => sim.step_reporting(updates, 200, |done| progress.set_position(done)),
    }
    progress.finish_and_clear();
    let elapsed = start.elapsed();
    // A state that is not finite is never written: no output is touched.
    if let Some(fault) = sim.check_state() {
        return Err(Failure::stopped(format!("{}: {fault}", scenario.origin)));
    }

    // The final state's hash, read where the bodies lie, in the memory the
    // sort's buffers took; the state is gathered only for the outputs that
    // write it.
    sim.release_buffers();
    let hash = sim.state_hash_in_place();
    let bodies = if dump_path.is_some() || outputs.scenario.is_some() {
        sim.snapshot()
    } else {
        Vec::new()
    };
    let pending = sim.pending_events();
    let next_id = sim.next_body_id();
    // A state a scenario cannot hold stops the run like a fault, before any
    // output is touched.
    if outputs.scenario.is_some()
        && let Some(problem) = beyond_a_scenario(&bodies)
    {
        return Err(Failure::stopped(format!(
            "{}: after {updates} updates, {problem} (--save-scenario); the simulation stopped and no output was written",
            scenario.origin
        )));
    }
    // Every output is written in full beside its target first, and only
    // when all are written are they put in place: a run whose outputs
    // cannot all be written writes none of them.
    let failed = |flag: &str, e: WriteError| Failure::other(format!("{flag} {e}; no output was written"));
    let mut staged = Vec::new();
    if let Some(path) = dump_path {
        staged.push(stage(path, |w| dump::write_csv(&bodies, hash, w)).map_err(|e| failed("--dump", e))?);
    }
    if let (Some((path, _)), Some(timeline)) = (outputs.timeline, &timeline) {
        staged.push(stage(path, |w| timeline.write_csv(w)).map_err(|e| failed("--timeline", e))?);
    }
    if let Some(path) = outputs.scenario {
        let snapshot = Snapshot {
            name: &scenario.name,
            updates,
            settings: sim.settings(),
            bodies: &bodies,
            next_id,
            events: &pending,
        };
        staged.push(stage(path, |w| write_snapshot(&snapshot, w)).map_err(|e| failed("--save-scenario", e))?);
    }
    commit_all(staged).map_err(|e| Failure::other(format!("{e} (putting the outputs in place)")))?;
    let per_update_ms = if updates == 0 {
        0.0
    } else {
        elapsed.as_secs_f64() * 1e3 / updates as f64
    };
    let timings = sim.timings();
    let stages: Vec<String> = SimulationSystems::ALL
        .iter()
        .map(|&stage| format!("{} {:.3}", stage.name(), timings.stage(stage).mean_ns / 1e6))
        .collect();
    let log = sim.event_log();
    if let Some(first) = &log.first_skipped {
        eprintln!(
            "kessler: warning: {}: {}",
            printable(&scenario.origin),
            printable(first)
        );
    }
    let events = if scenario.events.is_empty() {
        String::new()
    } else {
        format!(", {} events applied, {} skipped", log.applied, log.skipped)
    };
    let summary = format!(
        "{}: {} updates of {} bodies ({} at the end, {} shatters, {} refused, {} reentries{events}) in {:.3} s, {:.3} ms/update ({} ms), {mode} on {threads} thread{}{split}{}; state hash {hash}",
        scenario.name,
        updates,
        bodies_start,
        sim.body_count(),
        sim.collision_stats().shatters_total,
        sim.collision_stats().refused_total,
        sim.collision_stats().reentries_total,
        elapsed.as_secs_f64(),
        per_update_ms,
        stages.join(", "),
        if threads == 1 { "" } else { "s" },
        [
            ("state", dump_path),
            ("scenario", outputs.scenario),
            ("timeline", outputs.timeline.map(|(path, _)| path))
        ]
        .iter()
        .filter_map(|(what, path)| path.map(|p| format!("; {what} written to {}", p.display())))
        .collect::<String>(),
    );
    // One line, whatever the paths hold.
    println!("{}", printable(&summary));
    Ok(())
}
