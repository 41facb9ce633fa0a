//! Results files: the per-run CSV (docs/design.md, "Benchmark results"),
//! its per-pass twin, and the overhead report. Their stage columns come
//! from the stage list.

use std::io;

use super::measured_run::RunResult;
use crate::execution::{ExecutionMode, SplitPolicy, WorkerPool};
use crate::output::{Cells, CsvRow};
use crate::systems::STAGES;

/// The results CSV's stage columns in the order the contract fixes (each
/// written `<name>_ns`). Columns that stages name beyond these follow them,
/// in stage order: see [`stage_columns`].
pub const CONTRACT_STAGE_COLUMNS: [&str; 4] = ["broad_phase", "response", "gravity", "integrate"];

/// The stage columns of the results CSV: the contract's, then any other
/// column a stage counts in.
pub fn stage_columns() -> Vec<&'static str> {
    let mut columns = CONTRACT_STAGE_COLUMNS.to_vec();
    let others = columns_in_stage_order()
        .into_iter()
        .filter(|c| !CONTRACT_STAGE_COLUMNS.contains(c));
    columns.extend(others);
    columns
}

// A row of the results CSV — its header a stable contract: mean
// nanoseconds per update, rounded, the stage columns from the stage list.
impl CsvRow for RunResult {
    fn columns() -> Vec<String> {
        let own = [
            "run",
            "bodies_start",
            "bodies_end",
            "updates",
            "mode",
            "threads",
            "update_ns",
        ];
        own.iter()
            .map(|c| (*c).to_owned())
            .chain(stage_columns().iter().map(|c| format!("{c}_ns")))
            .collect()
    }

    fn write_cells(&self, out: &mut Cells<'_>) -> io::Result<()> {
        let r = self;
        out.cell(r.run)?;
        out.cell(r.bodies_start)?;
        out.cell(r.bodies_end)?;
        out.cell(r.updates)?;
        out.cell(r.mode)?;
        out.cell(r.threads)?;
        out.cell(format_args!("{:.0}", r.update_ns))?;
        for column in stage_columns() {
            out.cell(format_args!("{:.0}", column_ns(r, column)))?;
        }
        Ok(())
    }
}

/// A row of the per-pass results: the pass, then the results columns.
#[derive(Clone, Debug)]
pub struct PassRow {
    /// The pass, from 1.
    pub pass: u64,
    /// What the pass measured.
    pub result: RunResult,
}

impl CsvRow for PassRow {
    fn columns() -> Vec<String> {
        std::iter::once("pass".to_owned()).chain(RunResult::columns()).collect()
    }

    fn write_cells(&self, out: &mut Cells<'_>) -> io::Result<()> {
        out.cell(self.pass)?;
        self.result.write_cells(out)
    }
}

/// The results' stage columns in update order (each once).
pub fn columns_in_stage_order() -> Vec<&'static str> {
    let mut columns: Vec<&'static str> = Vec::new();
    for column in STAGES.iter().flat_map(|s| s.columns) {
        if !columns.contains(column) {
            columns.push(column);
        }
    }
    columns
}

/// Mean time per update of the stages that count in `column`.
pub fn column_ns(result: &RunResult, column: &str) -> f64 {
    STAGES
        .iter()
        .filter(|s| s.columns.contains(&column))
        .map(|s| result.stage(s.stage))
        .sum()
}

/// The whole update and each stage of a result, by name, in ns per update.
pub fn times_by_stage(r: &RunResult) -> impl Iterator<Item = (&'static str, f64)> + '_ {
    std::iter::once(("update", r.update_ns)).chain(STAGES.iter().map(|s| (s.name, r.stage(s.stage))))
}

/// One row of the overhead report (the thesis's Table 6).
#[derive(Clone, Debug, PartialEq)]
pub struct OverheadRow {
    /// Bodies of the runs compared (0 for `empty_step`).
    pub bodies: u64,
    /// `update`, a stage's name, or `empty_step`.
    pub stage: &'static str,
    /// Threads of the split run.
    pub threads: usize,
    /// Time with the work split, ns per update (per step for `empty_step`).
    pub with_ns: f64,
    /// Time with the work whole, ns.
    pub without_ns: f64,
}

impl OverheadRow {
    /// The difference as a share of the time without, in percent (0 where
    /// that time is 0).
    fn percent(&self) -> f64 {
        if self.without_ns > 0.0 {
            (self.with_ns - self.without_ns) / self.without_ns * 100.0
        } else {
            0.0
        }
    }
}

// The columns, in µs per update (per step for `empty_step`).
crate::csv_row!(OverheadRow, |r| {
    bodies: r.bodies,
    stage: r.stage,
    threads: r.threads,
    with_overhead_us: format_args!("{:.3}", r.with_ns / 1e3),
    without_overhead_us: format_args!("{:.3}", r.without_ns / 1e3),
    overhead_us: format_args!("{:.3}", (r.with_ns - r.without_ns) / 1e3),
    overhead_percent: format_args!("{:.1}", r.percent()),
});

/// One row of the overhead report.
fn overhead_row(bodies: u64, stage: &'static str, threads: usize, with_ns: f64, without_ns: f64) -> OverheadRow {
    OverheadRow {
        bodies,
        stage,
        threads,
        with_ns,
        without_ns,
    }
}

/// What splitting costs (the thesis's Table 6): for every body count run
/// both sequentially (each stage whole) and in parallel mode on one thread
/// with split `Always` (each stage cut into chunks, but no second thread to
/// gain from), the whole update and every stage in both, and the
/// difference. Empty if no such pair was run.
pub fn overhead_rows(results: &[RunResult]) -> Vec<OverheadRow> {
    let mut rows = Vec::new();
    for seq in results.iter().filter(|r| r.mode == ExecutionMode::Sequential) {
        let Some(split) = results.iter().find(|r| {
            r.mode == ExecutionMode::Parallel
                && r.pool == WorkerPool::Kessler
                && r.threads == 1
                && r.split == SplitPolicy::Always
                && r.bodies == seq.bodies
        }) else {
            continue;
        };
        for ((stage, with_ns), (_, without_ns)) in times_by_stage(split).zip(times_by_stage(seq)) {
            rows.push(overhead_row(seq.bodies, stage, 1, with_ns, without_ns));
        }
    }
    rows
}

/// The bare cost of one parallel step on `threads` threads of `pool`: a
/// near-empty kernel split into chunks (`with_ns`) against the same kernel
/// called whole (`without_ns`), per step; `empty_step` on Kessler's pool,
/// `empty_step_bevy` on Bevy's.
pub fn empty_step_row(threads: usize, pool: WorkerPool, with_ns: f64, without_ns: f64) -> OverheadRow {
    let stage = match pool {
        WorkerPool::Kessler => "empty_step",
        WorkerPool::Bevy => "empty_step_bevy",
    };
    overhead_row(0, stage, threads, with_ns, without_ns)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::measured_run::test_result;
    use crate::output::{header, line};
    use crate::systems::{STAGE_COUNT, SimulationSystems};

    fn result(run: usize, bodies: u64, mode: ExecutionMode, threads: usize, split: SplitPolicy, ns: f64) -> RunResult {
        RunResult {
            run,
            bodies_start: bodies as usize + 1,
            bodies_end: bodies as usize + 4,
            updates: 10,
            stage_ns: [ns / 8.0; STAGE_COUNT],
            ..test_result(bodies, mode, threads, split, ns)
        }
    }

    #[test]
    fn results_rows_follow_the_contract_header_then_sort_and_sweep() {
        assert_eq!(
            header::<RunResult>(),
            "run,bodies_start,bodies_end,updates,mode,threads,update_ns,broad_phase_ns,response_ns,gravity_ns,integrate_ns,sort_ns,sweep_ns"
        );
        let mut r = result(1, 1000, ExecutionMode::Parallel, 2, SplitPolicy::Auto, 1600.0);
        r.stage_ns[SimulationSystems::Sort as usize] = 30.0;
        r.stage_ns[SimulationSystems::Sweep as usize] = 70.0;
        // Broad phase = sort + sweep; response and shatter both count in
        // `response_ns`.
        assert_eq!(
            line(&r).unwrap(),
            "1,1001,1004,10,parallel,2,1600,100,400,200,200,30,70"
        );
        assert_eq!(header::<PassRow>(), format!("pass,{}", header::<RunResult>()));
        assert_eq!(
            line(&PassRow {
                pass: 3,
                result: r.clone()
            })
            .unwrap(),
            format!("3,{}", line(&r).unwrap())
        );
    }

    #[test]
    fn every_stage_counts_in_a_column_and_every_column_has_a_stage() {
        let columns = stage_columns();
        for stage in &STAGES {
            assert!(stage.columns.iter().all(|c| columns.contains(c)), "{}", stage.name);
        }
        for column in &columns {
            assert!(
                STAGES.iter().any(|s| s.columns.contains(column)),
                "no stage counts in {column}"
            );
        }
    }

    #[test]
    fn overhead_pairs_whole_stages_with_always_split_on_one_thread() {
        let rows: Vec<String> = overhead_rows(&[
            result(1, 100, ExecutionMode::Sequential, 1, SplitPolicy::Auto, 1000.0),
            result(2, 100, ExecutionMode::Parallel, 1, SplitPolicy::Always, 1100.0),
            result(3, 100, ExecutionMode::Parallel, 2, SplitPolicy::Always, 600.0),
            result(4, 500, ExecutionMode::Sequential, 1, SplitPolicy::Auto, 5000.0),
            // Auto on one thread may not split at all: not an overhead pair.
            result(5, 500, ExecutionMode::Parallel, 1, SplitPolicy::Auto, 5000.0),
        ])
        .iter()
        .map(|r| line(r).unwrap())
        .collect();
        let names: Vec<&str> = rows.iter().map(|r| r.split(',').nth(1).unwrap()).collect();
        let mut expected = vec!["update"];
        expected.extend(STAGES.iter().map(|s| s.name));
        assert_eq!(names, expected, "one body count with both: the update, then each stage");
        assert_eq!(rows[0], "100,update,1,1.100,1.000,0.100,10.0");
        assert!(rows[1].starts_with("100,gravity,1,"), "{}", rows[1]);
        assert_eq!(
            line(&empty_step_row(2, WorkerPool::Kessler, 3500.0, 500.0)).unwrap(),
            "0,empty_step,2,3.500,0.500,3.000,600.0"
        );
        assert_eq!(
            line(&empty_step_row(2, WorkerPool::Bevy, 9000.0, 500.0)).unwrap(),
            "0,empty_step_bevy,2,9.000,0.500,8.500,1700.0"
        );
    }
}
