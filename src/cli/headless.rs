//! `kessler headless SCENARIO --steps N [--mode M] [--threads T] [--dump FILE]`.

use indicatif::{ProgressBar, ProgressStyle};

use super::{Failure, HeadlessArgs};
use crate::calibration::machine_auto_split;
use crate::execution::{Execution, ExecutionMode, SplitPolicy, WorkerPool};
use crate::input::ExecutionOptions;
use crate::input::default_calibration_path;
use crate::output::{Output, check_outputs, printable};
use crate::resources::MemoryBudget;
use crate::scenario::Scenario;
use crate::simulation::{HeadlessReport, Outputs, run_headless};
use crate::systems::SimulationSystems;

/// Makes the execution the options ask for (split policy `auto` with
/// this machine's calibration).
pub fn execution(options: &ExecutionOptions) -> Result<Execution, Failure> {
    options
        .build(machine_auto_split())
        .map_err(|e| Failure::from(e).context("--threads"))
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

/// Runs `updates` updates of `scenario` with a progress bar on a terminal,
/// writes the outputs asked for (all of them, or none) and prints a
/// one-line summary ending with the state's hash.
pub fn simulate(scenario: &Scenario, execution: Execution, updates: u64, outputs: Outputs<'_>) -> Result<(), Failure> {
    let how = execution_text(&execution);
    let progress = ProgressBar::new(updates).with_style(
        ProgressStyle::with_template("{spinner} {pos}/{len} updates [{bar:30}] {per_sec} eta {eta}")
            .expect("template is valid")
            .progress_chars("=> "),
    );
    let report = run_headless(scenario, execution, updates, outputs, |done| {
        progress.set_position(done)
    });
    progress.finish_and_clear();
    let report = report?;
    if let Some(first) = &report.events.first_skipped {
        eprintln!(
            "kessler: warning: {}: {}",
            printable(&scenario.origin),
            printable(first)
        );
    }
    // One line, whatever the paths hold.
    println!("{}", printable(&summary(scenario, &report, &how, outputs)));
    Ok(())
}

/// How the run executes, as the summary says it: `parallel on 2 threads,
/// split auto (…)`.
fn execution_text(execution: &Execution) -> String {
    let (mode, threads) = (execution.mode(), execution.threads_used());
    let split = match (mode, execution.split()) {
        (ExecutionMode::Sequential, _) => String::new(),
        (_, SplitPolicy::Auto) => format!(", split auto ({})", execution.auto_split().origin()),
        (_, split) => format!(", split {split}"),
    };
    let pool = match (mode, execution.pool()) {
        (ExecutionMode::Parallel, WorkerPool::Bevy) => ", on Bevy's ComputeTaskPool",
        _ => "",
    };
    format!(
        "{mode} on {threads} thread{}{split}{pool}",
        if threads == 1 { "" } else { "s" }
    )
}

/// The summary line of a run.
fn summary(scenario: &Scenario, report: &HeadlessReport, how: &str, outputs: Outputs<'_>) -> String {
    let timings = &report.timings;
    let stages: Vec<String> = SimulationSystems::ALL
        .iter()
        .map(|&stage| format!("{} {:.3}", stage.name(), timings.stage(stage).mean_ns / 1e6))
        .collect();
    let events = if scenario.events.is_empty() {
        String::new()
    } else {
        format!(
            ", {} events applied, {} skipped",
            report.events.applied, report.events.skipped
        )
    };
    let written: String = [
        ("state", outputs.dump),
        ("scenario", outputs.scenario),
        ("timeline", outputs.timeline.map(|(path, _)| path)),
    ]
    .iter()
    .filter_map(|(what, path)| path.map(|p| format!("; {what} written to {}", p.display())))
    .collect();
    let collisions = &report.collisions;
    // Contacts past the bound of an update (docs/design.md, "Contacts in
    // time order"), said only where there were any.
    let deferred = match collisions.deferred_total {
        0 => String::new(),
        n => format!(", {n} contacts deferred to the next update"),
    };
    format!(
        "{}: {} updates of {} bodies ({} at the end, {} shatters, {} refused, {} reentries{deferred}{events}) in {:.3} s, \
         {:.3} ms/update ({} ms), {how}{written}; state hash {}",
        scenario.name,
        report.updates,
        report.bodies.0,
        report.bodies.1,
        collisions.shatters_total,
        collisions.refused_total,
        collisions.reentries_total,
        report.elapsed.as_secs_f64(),
        report.ms_per_update(),
        stages.join(", "),
        report.hash,
    )
}
