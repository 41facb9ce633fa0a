//! Results files: the per-run CSV (DESIGN §7) and the overhead report.

use std::io::{self, Write};

use super::run::RunResult;
use crate::resources::ExecutionMode;

/// Header of the results CSV — a stable contract.
pub const HEADER: &str =
    "run,bodies_start,bodies_end,updates,mode,threads,update_ns,broad_phase_ns,response_ns,gravity_ns,integrate_ns";

/// Header of the overhead report.
pub const OVERHEAD_HEADER: &str = "bodies,stage,sequential_ns,parallel_1_thread_ns,overhead_ns,overhead_percent";

/// Writes the results CSV: mean nanoseconds per update, rounded.
pub fn write_results(results: &[RunResult], mut out: impl Write) -> io::Result<()> {
    writeln!(out, "{HEADER}")?;
    for r in results {
        writeln!(
            out,
            "{},{},{},{},{},{},{:.0},{:.0},{:.0},{:.0},{:.0}",
            r.run,
            r.bodies_start,
            r.bodies_end,
            r.updates,
            r.mode,
            r.threads,
            r.update_ns,
            r.broad_phase_ns,
            r.response_ns,
            r.gravity_ns,
            r.integrate_ns
        )?;
    }
    out.flush()
}

/// The fixed cost of going parallel (the thesis's Table 6): for every body
/// count measured both sequentially and in parallel mode on one thread, each
/// stage's time in both and the difference. Empty if no such pair was run.
pub fn overhead_rows(results: &[RunResult]) -> Vec<String> {
    let mut rows = Vec::new();
    for seq in results.iter().filter(|r| r.mode == ExecutionMode::Sequential) {
        let Some(par) = results
            .iter()
            .find(|r| r.mode == ExecutionMode::Parallel && r.threads == 1 && r.bodies_start == seq.bodies_start)
        else {
            continue;
        };
        let stages = [
            ("update", seq.update_ns, par.update_ns),
            ("gravity", seq.gravity_ns, par.gravity_ns),
            ("integrate", seq.integrate_ns, par.integrate_ns),
            ("broad_phase", seq.broad_phase_ns, par.broad_phase_ns),
            ("response", seq.response_ns, par.response_ns),
        ];
        for (stage, s, p) in stages {
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

#[cfg(test)]
mod tests {
    use super::*;

    fn result(run: usize, bodies: usize, mode: ExecutionMode, threads: usize, ns: f64) -> RunResult {
        RunResult {
            run,
            bodies_start: bodies,
            bodies_end: bodies + 3,
            updates: 10,
            mode,
            threads,
            update_ns: ns,
            gravity_ns: ns / 4.0,
            integrate_ns: ns / 4.0,
            broad_phase_ns: ns / 4.0,
            response_ns: ns / 4.0,
        }
    }

    #[test]
    fn results_csv_has_the_contract_header_and_one_row_per_run() {
        let mut out = Vec::new();
        write_results(&[result(1, 1001, ExecutionMode::Parallel, 2, 1234.4)], &mut out).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert_eq!(
            text,
            format!("{HEADER}\n1,1001,1004,10,parallel,2,1234,309,309,309,309\n")
        );
    }

    #[test]
    fn overhead_pairs_sequential_with_parallel_on_one_thread() {
        let rows = overhead_rows(&[
            result(1, 100, ExecutionMode::Sequential, 1, 1000.0),
            result(2, 100, ExecutionMode::Parallel, 1, 1100.0),
            result(3, 100, ExecutionMode::Parallel, 2, 600.0),
            result(4, 500, ExecutionMode::Sequential, 1, 5000.0),
        ]);
        assert_eq!(rows.len(), 5, "one body count with both, five stages");
        assert_eq!(rows[0], "100,update,1000,1100,100,10.0");
    }
}
