//! Results files: the per-run CSV (docs/design.md, "Benchmark results") and
//! the overhead report. Both take their stage columns from the stage list.

use std::io::{self, Write};

use super::run::RunResult;
use crate::execution::ExecutionMode;
use crate::systems::STAGES;

/// The results CSV's stage columns in the order the contract fixes (each
/// written `<name>_ns`). Columns that stages name beyond these follow them,
/// in stage order: see [`stage_columns`].
pub const CONTRACT_STAGE_COLUMNS: [&str; 4] = ["broad_phase", "response", "gravity", "integrate"];

/// Header of the overhead report.
pub const OVERHEAD_HEADER: &str = "bodies,stage,sequential_ns,parallel_1_thread_ns,overhead_ns,overhead_percent";

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

/// The results CSV's header — a stable contract.
pub fn results_header() -> String {
    let stages: Vec<String> = stage_columns().iter().map(|c| format!("{c}_ns")).collect();
    format!(
        "run,bodies_start,bodies_end,updates,mode,threads,update_ns,{}",
        stages.join(",")
    )
}

/// The results' stage columns in update order (each once): the rows of the
/// overhead report.
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

/// Writes the results CSV: mean nanoseconds per update, rounded.
pub fn write_results(results: &[RunResult], mut out: impl Write) -> io::Result<()> {
    let columns = stage_columns();
    writeln!(out, "{}", results_header())?;
    for r in results {
        write!(
            out,
            "{},{},{},{},{},{},{:.0}",
            r.run, r.bodies_start, r.bodies_end, r.updates, r.mode, r.threads, r.update_ns
        )?;
        for column in &columns {
            write!(out, ",{:.0}", column_ns(r, column))?;
        }
        writeln!(out)?;
    }
    out.flush()
}

/// The fixed cost of going parallel (the thesis's Table 6): for every body
/// count measured both sequentially and in parallel mode on one thread, the
/// time of the whole update and of each results column in both, and the
/// difference. Empty if no such pair was run.
pub fn overhead_rows(results: &[RunResult]) -> Vec<String> {
    let mut rows = Vec::new();
    for seq in results.iter().filter(|r| r.mode == ExecutionMode::Sequential) {
        let Some(par) = results
            .iter()
            .find(|r| r.mode == ExecutionMode::Parallel && r.threads == 1 && r.bodies_start == seq.bodies_start)
        else {
            continue;
        };
        let update = ("update", seq.update_ns, par.update_ns);
        let columns = columns_in_stage_order()
            .into_iter()
            .map(|c| (c, column_ns(seq, c), column_ns(par, c)));
        for (stage, s, p) in std::iter::once(update).chain(columns) {
            let percent = if s > 0.0 { (p - s) / s * 100.0 } else { 0.0 };
            rows.push(format!(
                "{},{stage},{s:.0},{p:.0},{:.0},{percent:.1}",
                seq.bodies_start,
                p - s
            ));
        }
    }
    rows
}

/// Writes the overhead report.
pub fn write_overhead(rows: &[String], mut out: impl Write) -> io::Result<()> {
    writeln!(out, "{OVERHEAD_HEADER}")?;
    rows.iter().try_for_each(|row| writeln!(out, "{row}"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::systems::STAGE_COUNT;

    fn result(run: usize, bodies: usize, mode: ExecutionMode, threads: usize, ns: f64) -> RunResult {
        RunResult {
            run,
            bodies_start: bodies,
            bodies_end: bodies + 3,
            updates: 10,
            mode,
            threads,
            update_ns: ns,
            stage_ns: [ns / 8.0; STAGE_COUNT],
        }
    }

    #[test]
    fn results_csv_has_the_contract_header_and_one_row_per_run() {
        assert_eq!(
            results_header(),
            "run,bodies_start,bodies_end,updates,mode,threads,update_ns,broad_phase_ns,response_ns,gravity_ns,integrate_ns"
        );
        let mut out = Vec::new();
        write_results(&[result(1, 1001, ExecutionMode::Parallel, 2, 1600.0)], &mut out).unwrap();
        let text = String::from_utf8(out).unwrap();
        // Response and shatter both count in `response_ns`.
        assert_eq!(
            text,
            format!("{}\n1,1001,1004,10,parallel,2,1600,200,400,200,200\n", results_header())
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
    fn overhead_pairs_sequential_with_parallel_on_one_thread() {
        let rows = overhead_rows(&[
            result(1, 100, ExecutionMode::Sequential, 1, 1000.0),
            result(2, 100, ExecutionMode::Parallel, 1, 1100.0),
            result(3, 100, ExecutionMode::Parallel, 2, 600.0),
            result(4, 500, ExecutionMode::Sequential, 1, 5000.0),
        ]);
        let names: Vec<&str> = rows.iter().map(|r| r.split(',').nth(1).unwrap()).collect();
        assert_eq!(
            names,
            ["update", "gravity", "integrate", "broad_phase", "response"],
            "one body count with both: the update and each column, in update order"
        );
        assert_eq!(rows[0], "100,update,1000,1100,100,10.0");
        // Response and shatter count together, as in the results CSV.
        assert_eq!(rows[4], "100,response,250,275,25,10.0");
    }
}
