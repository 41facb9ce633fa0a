//! Where parallel starts to pay (the thesis's Figures 22–24): from the
//! passes of sequential runs and of parallel runs with split `Always` at
//! the same body counts, the smallest count from which `Always` beats
//! sequential in every pass — for the whole update and for each stage —
//! and how close `Auto` came to the better of the two.
//!
//! `Auto` is compared by each run's fastest pass: on a shared machine the
//! noise only ever adds time, so the fastest of several passes is the
//! steadiest estimate of what a setting costs, and a slow spell that hits
//! one of three adjacent runs in one pass does not decide the comparison.

use std::collections::{BTreeMap, BTreeSet};

use super::measured_run::RunResult;
use super::report::times_by_stage;
use crate::execution::{ExecutionMode, SplitPolicy, WorkerPool};

/// The crossover of one stage (or `update`) on one thread count.
#[derive(Clone, Debug, PartialEq)]
pub struct Crossover {
    /// `update` or a stage name.
    pub stage: &'static str,
    /// Threads of the `Always` runs.
    pub threads: usize,
    /// Smallest measured body count from which `Always` beat sequential in
    /// every pass, at that count and every larger one; `None` if it did not
    /// at the largest.
    pub from_bodies: Option<u64>,
    /// Body counts measured both ways.
    pub counts: usize,
    /// The largest excess of `Auto`'s fastest pass over the better of
    /// sequential's and `Always`'s fastest, in percent, and where; `None`
    /// without `Auto` runs at those counts.
    pub auto_worst: Option<(f64, u64)>,
}

// A row of `<stem>-crossover.csv`: an empty cell where nothing was found.
crate::csv_row!(Crossover, |c| {
    stage: c.stage,
    threads: c.threads,
    crossover_bodies: Blank(c.from_bodies),
    counts: c.counts,
    auto_worst_percent: Blank(c.auto_worst.map(|(p, _)| format!("{p:.1}"))),
    auto_worst_bodies: Blank(c.auto_worst.map(|(_, at)| at)),
});

/// A cell that is empty where there is no value.
struct Blank<T>(Option<T>);

impl<T: std::fmt::Display> std::fmt::Display for Blank<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.0 {
            Some(value) => value.fmt(f),
            None => Ok(()),
        }
    }
}

/// Every pass of the runs that match `select`, by configured body count.
fn series(passes: &[Vec<RunResult>], select: impl Fn(&RunResult) -> bool) -> BTreeMap<u64, &[RunResult]> {
    passes
        .iter()
        .filter(|p| p.first().is_some_and(&select))
        .map(|p| (p[0].bodies, p.as_slice()))
        .collect()
}

/// The time of `stage` (or `update`) in `r`.
fn time_of(r: &RunResult, stage: &str) -> f64 {
    times_by_stage(r).find(|(s, _)| *s == stage).map_or(0.0, |(_, t)| t)
}

/// Fastest time of `stage` over passes.
fn fastest_of(passes: &[RunResult], stage: &str) -> f64 {
    passes.iter().map(|r| time_of(r, stage)).fold(f64::INFINITY, f64::min)
}

/// When split counts as faster than whole at one body count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wins {
    /// In every pass (each pass ran both, one after the other): the
    /// report's strict reading.
    EveryPass,
    /// In the fastest pass of each: the calibration's, which disturbed
    /// passes do not move.
    Fastest,
}

impl Wins {
    fn split_wins(self, split: &[RunResult], whole: &[RunResult], stage: &str) -> bool {
        if split.is_empty() || split.len() != whole.len() {
            return false;
        }
        match self {
            Self::EveryPass => split
                .iter()
                .zip(whole)
                .all(|(s, w)| time_of(s, stage) < time_of(w, stage)),
            Self::Fastest => fastest_of(split, stage) < fastest_of(whole, stage),
        }
    }
}

/// The crossovers of the whole update and of every stage, for each thread
/// count that has `Always` runs, from all passes of all runs (in config
/// order; a run's passes all share its settings), `Always` winning as
/// `wins` says. Empty without a sequential and an `Always` run at the same
/// body count.
pub fn crossovers(passes: &[Vec<RunResult>], wins: Wins) -> Vec<Crossover> {
    let is_always = |r: &RunResult| {
        r.mode == ExecutionMode::Parallel && r.split == SplitPolicy::Always && r.pool == WorkerPool::Kessler
    };
    let sequential = series(passes, |r| r.mode == ExecutionMode::Sequential);
    let threads: BTreeSet<usize> = passes
        .iter()
        .flatten()
        .filter(|r| is_always(r))
        .map(|r| r.threads)
        .collect();
    let stages: Vec<&'static str> = passes
        .iter()
        .flatten()
        .next()
        .map(|r| times_by_stage(r).map(|(s, _)| s).collect())
        .unwrap_or_default();
    let mut found = Vec::new();
    for threads in threads {
        let always = series(passes, |r| is_always(r) && r.threads == threads);
        let auto = series(passes, |r| {
            r.mode == ExecutionMode::Parallel
                && r.split == SplitPolicy::Auto
                && r.threads == threads
                && r.pool == WorkerPool::Kessler
        });
        let counts: Vec<u64> = always.keys().filter(|n| sequential.contains_key(n)).copied().collect();
        if counts.is_empty() {
            continue;
        }
        for &stage in &stages {
            let mut from_bodies = None;
            for n in counts.iter().rev() {
                if !wins.split_wins(always[n], sequential[n], stage) {
                    break;
                }
                from_bodies = Some(*n);
            }
            let auto_worst = counts
                .iter()
                .filter_map(|n| {
                    let auto = auto.get(n)?;
                    let best = fastest_of(sequential[n], stage).min(fastest_of(always[n], stage));
                    let excess = if best > 0.0 {
                        (fastest_of(auto, stage) / best - 1.0) * 100.0
                    } else {
                        0.0
                    };
                    Some((excess, *n))
                })
                .max_by(|a, b| a.0.total_cmp(&b.0));
            found.push(Crossover {
                stage,
                threads,
                from_bodies,
                counts: counts.len(),
                auto_worst,
            });
        }
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::measured_run::test_result;
    use crate::systems::STAGE_COUNT;

    fn pass(bodies: u64, mode: ExecutionMode, split: SplitPolicy, update_ns: f64) -> RunResult {
        let threads = if mode == ExecutionMode::Sequential { 1 } else { 2 };
        test_result(bodies, mode, threads, split, update_ns)
    }

    /// Each run's passes from its update times.
    fn runs<const P: usize>(mode: ExecutionMode, split: SplitPolicy, times: &[(u64, [f64; P])]) -> Vec<Vec<RunResult>> {
        times
            .iter()
            .map(|(n, passes)| passes.iter().map(|&t| pass(*n, mode, split, t)).collect())
            .collect()
    }

    #[test]
    fn the_crossover_is_where_always_wins_every_pass_from_then_on() {
        let mut all = runs(
            ExecutionMode::Sequential,
            SplitPolicy::Auto,
            &[
                (100, [10.0; 3]),
                (1000, [100.0; 3]),
                (2000, [200.0; 3]),
                (5000, [500.0; 3]),
            ],
        );
        all.extend(runs(
            ExecutionMode::Parallel,
            SplitPolicy::Always,
            // 1000 wins two passes of three only; 100 wins, but 1000 above
            // it does not, so the crossover is 2000.
            &[
                (100, [9.0; 3]),
                (1000, [90.0, 120.0, 90.0]),
                (2000, [150.0; 3]),
                (5000, [300.0; 3]),
            ],
        ));
        all.extend(runs(
            ExecutionMode::Parallel,
            SplitPolicy::Auto,
            &[
                (100, [11.0; 3]),
                (1000, [95.0; 3]),
                (2000, [150.0; 3]),
                (5000, [330.0; 3]),
            ],
        ));
        let found = crossovers(&all, Wins::EveryPass);
        let update = found.iter().find(|c| c.stage == "update").unwrap();
        assert_eq!(update.from_bodies, Some(2000));
        assert_eq!((update.threads, update.counts), (2, 4));
        // Auto at 100: 11 against the better 9 → 22 % over; at 5000: 10 %
        // (fastest passes: all passes are equal here but at 1000).
        let (worst, at) = update.auto_worst.unwrap();
        assert!(
            (worst - 100.0 * (11.0 / 9.0 - 1.0)).abs() < 1e-9 && at == 100,
            "{worst} at {at}"
        );
        assert_eq!(found.len(), 1 + STAGE_COUNT, "the update and every stage");
        assert_eq!(crate::output::line(update).unwrap(), "update,2,2000,4,22.2,100");
    }

    #[test]
    fn no_crossover_when_always_loses_at_the_largest_count() {
        let mut all = runs(
            ExecutionMode::Sequential,
            SplitPolicy::Auto,
            &[(100, [10.0; 2]), (200, [20.0; 2])],
        );
        all.extend(runs(
            ExecutionMode::Parallel,
            SplitPolicy::Always,
            &[(100, [5.0; 2]), (200, [25.0; 2])],
        ));
        let update = crossovers(&all, Wins::EveryPass)
            .into_iter()
            .find(|c| c.stage == "update")
            .unwrap();
        assert_eq!((update.from_bodies, update.auto_worst), (None, None));
        assert_eq!(crate::output::line(&update).unwrap(), "update,2,,2,,");
        assert!(
            crossovers(&all[..2], Wins::EveryPass).is_empty(),
            "no Always runs: nothing to say"
        );
    }
}
