//! `kessler bench CONFIG [--out results.csv]`: the runs of a benchmark
//! config, measured headless, written as CSV (plus an overhead report and a
//! plot beside it). Existing results are never overwritten.

use std::path::Path;

use indicatif::{ProgressBar, ProgressStyle};

use super::Failure;
use crate::bench::{self, BenchConfig, BenchOutputs, Run, RunResult};
use crate::scenario::Scenario;

/// Runs the command: load and check everything, measure, write.
pub fn bench(config_path: &Path, out: &Path) -> Result<(), Failure> {
    let config = BenchConfig::load(config_path)?;
    let outputs = BenchOutputs::beside(out);
    outputs.check()?;
    let scenario = config.load_scenario(config_path)?;
    let sized = config.size_runs(&scenario, config_path)?;
    let results = measure_passes(&config, &sized, config_path)?;
    let title = format!("Kessler: {}, time per update", scenario.name);
    let overhead = outputs.write(&results, &title)?;
    println!(
        "{} runs written to {}{}, plot {} and {}",
        results.len(),
        outputs.results.display(),
        if overhead {
            format!(", overhead of going parallel {}", outputs.overhead.display())
        } else {
            String::new()
        },
        outputs.plot_svg.display(),
        outputs.plot_png.display()
    );
    Ok(())
}

/// Measures every run `config.repeat` times, pass after pass through all
/// runs — so that a slow spell of the machine falls on several runs rather
/// than on all passes of one — and keeps each run's median pass.
fn measure_passes(config: &BenchConfig, sized: &[Scenario], config_path: &Path) -> Result<Vec<RunResult>, Failure> {
    let passes = u64::from(config.repeat);
    let mut progress = BenchProgress::new(config, passes);
    let mut measured: Vec<Vec<RunResult>> = vec![Vec::new(); config.runs.len()];
    for pass in 1..=passes {
        for (i, (run, scenario)) in config.runs.iter().zip(sized).enumerate() {
            progress.start(i, pass, run);
            bench::reset_peak_memory();
            let result = bench::measure(i + 1, scenario, run, |done| progress.advance(done))
                .map_err(|e| Failure::from(e).context(format_args!("{}: runs[{i}]", config_path.display())))?;
            progress.finish(run, &result, bench::peak_memory());
            measured[i].push(result);
        }
    }
    progress.clear();
    Ok(measured.into_iter().filter_map(bench::median_pass).collect())
}

/// The progress bar over all passes, and a line per measured run.
struct BenchProgress {
    bar: ProgressBar,
    runs: usize,
    passes: u64,
    /// Updates of the runs finished so far (each with its warm-up).
    finished: u64,
    /// `(pass k/N)`, or nothing for a single pass.
    of_passes: String,
}

impl BenchProgress {
    fn new(config: &BenchConfig, passes: u64) -> Self {
        let total: u64 = config.runs.iter().map(|r| r.updates + 1).sum::<u64>() * passes;
        let bar = ProgressBar::new(total).with_style(
            ProgressStyle::with_template("{spinner} [{bar:30}] {pos}/{len} updates, eta {eta} — {msg}")
                .expect("template is valid")
                .progress_chars("=> "),
        );
        Self {
            bar,
            runs: config.runs.len(),
            passes,
            finished: 0,
            of_passes: String::new(),
        }
    }

    fn start(&mut self, index: usize, pass: u64, run: &Run) {
        self.of_passes = if self.passes > 1 {
            format!(" (pass {pass}/{})", self.passes)
        } else {
            String::new()
        };
        self.bar.set_message(format!(
            "run {}/{}{}: {} bodies, {}",
            index + 1,
            self.runs,
            self.of_passes,
            run.bodies,
            run.mode
        ));
    }

    /// `done` measured updates of the current run.
    fn advance(&self, done: u64) {
        self.bar.set_position(self.finished + 1 + done);
    }

    fn finish(&mut self, run: &Run, result: &RunResult, peak_memory: Option<u64>) {
        self.finished += run.updates + 1;
        let memory = peak_memory.map_or(String::new(), |peak| {
            format!(
                ", peak memory {:.0} MiB ({:.0} B/body)",
                peak as f64 / f64::from(1 << 20),
                peak as f64 / result.bodies_start.max(1) as f64
            )
        });
        let line = format!(
            "run {:>3}{}: {:>8} bodies, {:>10} on {:>2} thread(s): {:>12.3} ms/update{memory}",
            result.run,
            self.of_passes,
            result.bodies_start,
            result.mode.name(),
            result.threads,
            result.update_ns / 1e6
        );
        // A hidden bar (stderr not a terminal) drops its lines: print them.
        if self.bar.is_hidden() {
            eprintln!("{line}");
        } else {
            self.bar.println(line);
        }
    }

    fn clear(&self) {
        self.bar.finish_and_clear();
    }
}
