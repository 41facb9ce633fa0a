//! `kessler calibrate`'s measurement: the thesis scene at a ladder of body
//! counts, each stage sequential and split (`Always`) on this machine's
//! threads, in interleaved passes; a stage's split count is its crossover
//! ([`crossovers`]) — the smallest count from which splitting won every
//! pass, there and above.

use std::collections::BTreeMap;

use super::Calibration;
use crate::bench::{Crossover, Run, RunDefaults, RunError, RunResult, Wins, crossovers, measure, this_cpu, utc_now};
use crate::execution::{ExecutionMode, MAX_THREADS, SplitPolicy, WorkerPool};
use crate::input::ExecutionOptions;
use crate::scenario::Scenario;

/// Body counts measured.
pub const LADDER: [u64; 9] = [250, 500, 1_000, 2_000, 4_000, 8_000, 16_000, 32_000, 64_000];

/// Passes through the ladder.
pub const PASSES: usize = 3;

/// Split count of a stage that did not win at the ladder's top: beyond it,
/// on the guess that more work pays for the split eventually.
pub const NOT_FOUND: u64 = 2 * LADDER[LADDER.len() - 1];

/// The thread count `kessler calibrate` measures when asked for `asked`
/// on a machine of `hardware` threads: `asked`, bounded to twice the
/// hardware threads (at least 2), as the window's thread choice is; with a
/// warning where it was bounded. Beyond that, workers only wait on one
/// another — 256 threads on 2 cores took 40 s to measure that — and `Auto`
/// uses the counts whatever the thread count.
pub fn threads_to_measure(asked: usize, hardware: usize) -> (usize, Option<String>) {
    let most = hardware.saturating_mul(2).clamp(2, MAX_THREADS);
    if asked <= most {
        return (asked, None);
    }
    let warning = format!(
        "--threads {asked}: this machine has {hardware} hardware thread{}; calibrating on {most}, twice that \
         (more threads only wait on one another, and would take minutes to measure)",
        if hardware == 1 { "" } else { "s" }
    );
    (most, Some(warning))
}

/// Updates measured at `bodies`: about the same time per run at every
/// count, enough updates at small counts for a stable mean.
fn updates_for(bodies: u64) -> u64 {
    (1_000_000 / bodies.max(1)).clamp(12, 300)
}

/// The runs at one count: sequential, then split on `threads` threads.
fn runs_at(bodies: u64, threads: usize) -> [Run; 2] {
    let run = |mode, split| Run {
        bodies,
        updates: updates_for(bodies),
        execution: ExecutionOptions {
            mode: Some(mode),
            threads: Some(threads),
            split: Some(split),
            pool: Some(WorkerPool::Kessler),
        },
        ..Run::default()
    };
    [
        run(ExecutionMode::Sequential, SplitPolicy::Always),
        run(ExecutionMode::Parallel, SplitPolicy::Always),
    ]
}

/// Measures this machine on `threads` threads; `progress` is told the runs
/// done and the total after each.
pub fn calibrate(threads: usize, mut progress: impl FnMut(usize, usize)) -> Result<Calibration, RunError> {
    let scene = Scenario::builtin_thesis();
    let sized: Vec<Scenario> = LADDER
        .iter()
        .map(|&n| scene.with_generated(n).expect("the thesis scene has generators"))
        .collect();
    let runs: Vec<(usize, Run)> = LADDER
        .iter()
        .enumerate()
        .flat_map(|(k, &n)| runs_at(n, threads).map(|run| (k, run)))
        .collect();
    let mut passes: Vec<Vec<RunResult>> = vec![Vec::new(); runs.len()];
    let total = runs.len() * PASSES;
    for pass in 0..PASSES {
        for (i, (k, run)) in runs.iter().enumerate() {
            passes[i].push(measure(i + 1, &sized[*k], run, &RunDefaults::default(), |_| {})?);
            progress(pass * runs.len() + i + 1, total);
        }
    }
    Ok(Calibration {
        threads,
        date: utc_now(),
        cpu: this_cpu(),
        split_from: split_counts(&passes),
    })
}

/// Each stage's split count from the passes: its own crossover or the whole
/// update's, whichever is lower — a stage that gains little on its own
/// still splits where the update as a whole gains, which keeps `Auto` at
/// least as fast as `Always` wherever `Always` is the faster of the two.
fn split_counts(passes: &[Vec<RunResult>]) -> BTreeMap<String, u64> {
    let found = crossovers(passes, Wins::Fastest);
    let from = |c: &Crossover| c.from_bodies.unwrap_or(NOT_FOUND);
    let update = found.iter().find(|c| c.stage == "update").map_or(NOT_FOUND, from);
    found
        .iter()
        .filter(|c| c.stage != "update")
        .map(|c| (c.stage.to_owned(), from(c).min(update)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::systems::{STAGE_COUNT, SimulationSystems};

    /// Passes where the update wins split from 2000 bodies, gravity from
    /// 1000, and the sweep never.
    fn passes() -> Vec<Vec<RunResult>> {
        let mut all = Vec::new();
        for (bodies, whole, split) in [(1000, 10.0, 12.0), (2000, 20.0, 15.0), (4000, 40.0, 25.0)] {
            for (mode, update) in [(ExecutionMode::Sequential, whole), (ExecutionMode::Parallel, split)] {
                let mut result = crate::bench::test_result(bodies, mode, 2, SplitPolicy::Always, update);
                let gravity_wins = mode == ExecutionMode::Parallel;
                result.stage_ns[SimulationSystems::Gravity as usize] = if gravity_wins { 1.0 } else { 2.0 };
                result.stage_ns[SimulationSystems::Sweep as usize] = if gravity_wins { 9.0 } else { 1.0 };
                all.push(vec![result.clone(), result.clone(), result]);
            }
        }
        all
    }

    #[test]
    fn the_threads_measured_are_at_most_twice_the_hardware() {
        assert_eq!(threads_to_measure(2, 2), (2, None));
        assert_eq!(threads_to_measure(4, 2), (4, None));
        assert_eq!(threads_to_measure(2, 1), (2, None), "two threads anywhere");
        let (threads, warning) = threads_to_measure(256, 2);
        assert_eq!(threads, 4);
        let warning = warning.unwrap();
        assert!(
            warning.starts_with("--threads 256: this machine has 2 hardware threads; calibrating on 4"),
            "{warning}"
        );
        assert_eq!(threads_to_measure(256, 64).0, 128);
        assert_eq!(threads_to_measure(256, 200).0, 256);
    }

    #[test]
    fn a_stage_splits_from_its_own_crossover_or_the_updates_whichever_is_lower() {
        let counts = split_counts(&passes());
        assert_eq!(counts["gravity"], 1000, "its own, below the update's");
        assert_eq!(counts["sweep"], 2000, "never on its own: the update's");
        assert_eq!(counts.len(), STAGE_COUNT);
    }
}
