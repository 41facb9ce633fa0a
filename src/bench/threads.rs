//! The thesis's core-count axis: the speed-up of the whole update and of
//! each stage against the thread count, per body count, from a config's
//! thread sweeps (`Threads(...)` runs), written as `<stem>-threads.csv`
//! (docs/design.md, "Benchmark results").

use std::io;

use super::config::ThreadsRun;
use super::measured_run::RunResult;
use super::report::times_by_stage;
use crate::execution::{ExecutionMode, WorkerPool};
use crate::output::{Cells, CsvRow};
use crate::systems::STAGES;

/// One thread count of a sweep: the speed-ups over the sequential run.
#[derive(Clone, Debug, PartialEq)]
pub struct ThreadsRow {
    /// Bodies at the start.
    pub bodies: u64,
    /// Threads of the parallel run.
    pub threads: usize,
    /// Sequential time over parallel time, whole update first, then each
    /// stage in stage order (`None` where either took no time).
    pub speedups: Vec<Option<f64>>,
}

impl ThreadsRow {
    /// The whole update's speed-up.
    pub fn update(&self) -> Option<f64> {
        self.speedups[0]
    }
}

/// The rows of every sweep of `sweeps` found in `results` (medians): for
/// each sweep's sequential run, one row per thread count of its parallel
/// runs (the first result of each), in thread order. A second sweep at a
/// body count already swept adds no rows (its thread counts are the
/// first's).
pub fn thread_rows(sweeps: &[ThreadsRun], results: &[RunResult]) -> Vec<ThreadsRow> {
    let mut rows = Vec::new();
    for (k, sweep) in sweeps.iter().enumerate() {
        if sweeps[..k].iter().any(|s| s.bodies == sweep.bodies) {
            continue;
        }
        let same = |r: &&RunResult| r.bodies == sweep.bodies;
        let Some(sequential) = results
            .iter()
            .filter(same)
            .find(|r| r.mode == ExecutionMode::Sequential)
        else {
            continue;
        };
        let mut parallel: Vec<&RunResult> = results
            .iter()
            .filter(same)
            .filter(|r| r.mode == ExecutionMode::Parallel && r.split == sweep.split && r.pool == WorkerPool::Kessler)
            .collect();
        parallel.sort_by_key(|r| r.threads);
        parallel.dedup_by_key(|r| r.threads);
        for run in parallel {
            let speedups = times_by_stage(sequential)
                .zip(times_by_stage(run))
                .map(|((_, s), (_, p))| (s > 0.0 && p > 0.0).then(|| s / p))
                .collect();
            rows.push(ThreadsRow {
                bodies: sweep.bodies,
                threads: run.threads,
                speedups,
            });
        }
    }
    rows
}

// The columns: bodies, threads, then `update_speedup` and a
// `<stage>_speedup` per stage of the stage list; an empty cell where a
// stage took no time.
impl CsvRow for ThreadsRow {
    fn columns() -> Vec<String> {
        ["bodies".to_owned(), "threads".to_owned()]
            .into_iter()
            .chain(
                std::iter::once("update")
                    .chain(STAGES.iter().map(|s| s.name))
                    .map(|name| format!("{name}_speedup")),
            )
            .collect()
    }

    fn write_cells(&self, out: &mut Cells<'_>) -> io::Result<()> {
        out.cell(self.bodies)?;
        out.cell(self.threads)?;
        for speedup in &self.speedups {
            match speedup {
                Some(s) => out.cell(format_args!("{s:.3}"))?,
                None => out.cell("")?,
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::measured_run::test_result;
    use crate::execution::SplitPolicy;
    use crate::output::header;
    use crate::systems::STAGE_COUNT;

    fn result(bodies: u64, mode: ExecutionMode, threads: usize, split: SplitPolicy, ns: f64) -> RunResult {
        let mut result = test_result(bodies, mode, threads, split, ns);
        result.stage_ns = [ns / 10.0; STAGE_COUNT];
        result.stage_ns[STAGE_COUNT - 1] = 0.0;
        result
    }

    #[test]
    fn speedups_are_sequential_over_parallel_per_thread_count() {
        use ExecutionMode::{Parallel, Sequential};
        let sweep = ThreadsRun {
            bodies: 1000,
            updates: 10,
            split: SplitPolicy::Always,
        };
        let results = [
            result(1000, Sequential, 1, SplitPolicy::Auto, 8e6),
            result(1000, Parallel, 2, SplitPolicy::Always, 5e6),
            result(1000, Parallel, 1, SplitPolicy::Always, 1e7),
            // Another split or another body count is not the sweep's.
            result(1000, Parallel, 3, SplitPolicy::Auto, 1e6),
            result(50, Parallel, 4, SplitPolicy::Always, 1e6),
        ];
        let rows = thread_rows(&[sweep], &results);
        assert_eq!(rows.iter().map(|r| r.threads).collect::<Vec<_>>(), [1, 2]);
        assert_eq!(rows[0].update(), Some(0.8));
        assert_eq!(rows[1].update(), Some(1.6));
        assert_eq!(rows[1].speedups[1], Some(1.6), "a stage's own ratio");
        assert_eq!(rows[1].speedups[STAGE_COUNT], None, "a stage that took no time");
        assert!(header::<ThreadsRow>().starts_with("bodies,threads,update_speedup,gravity_speedup,"));
        let line = crate::output::line(&rows[1]).unwrap();
        assert!(line.starts_with("1000,2,1.600,1.600,") && line.ends_with(','), "{line}");
    }
}
