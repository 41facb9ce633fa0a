//! `kessler bench CONFIG [--out results.csv]`: the runs of a benchmark
//! config, measured headless, written as CSV (plus an overhead report and an
//! SVG plot beside it). Existing results are never overwritten.

use std::path::{Path, PathBuf};

use indicatif::{ProgressBar, ProgressStyle};

use super::{Failure, load_scenario};
use crate::bench::{self, BenchConfig, RunResult};
use crate::dump::write_atomically;
use crate::scenario::{Scenario, THESIS_SCENARIO, THESIS_SCENARIO_NAME};

/// The files a benchmark writes, all beside `--out`.
struct Outputs {
    results: PathBuf,
    overhead: PathBuf,
    plot: PathBuf,
    plot_png: PathBuf,
}

impl Outputs {
    fn beside(results: &Path) -> Self {
        let stem = results
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "results".into());
        let sibling = |suffix: &str| results.with_file_name(format!("{stem}{suffix}"));
        Self {
            results: results.to_owned(),
            overhead: sibling("-overhead.csv"),
            plot: sibling(".svg"),
            plot_png: sibling(".png"),
        }
    }

    /// Refuses to start if any output exists or its folder does not.
    fn check(&self) -> Result<(), Failure> {
        for path in [&self.results, &self.overhead, &self.plot, &self.plot_png] {
            if path.exists() {
                return Err(Failure::input(format!(
                    "--out: {} exists already; remove it or choose another --out (results are never overwritten)",
                    path.display()
                )));
            }
        }
        let folder = self
            .results
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        if !folder.is_dir() {
            return Err(Failure::input(format!(
                "--out: folder {} does not exist",
                folder.display()
            )));
        }
        Ok(())
    }
}

pub fn bench(config_path: &Path, out: &Path) -> Result<(), Failure> {
    let config = BenchConfig::load(config_path).map_err(Failure::input)?;
    let outputs = Outputs::beside(out);
    outputs.check()?;
    let (scenario, origin) = match config.scenario_path(config_path) {
        Some(path) => load_scenario(Some(&path)).map_err(|f| Failure {
            message: format!("{}: field `scenario`: {}", config_path.display(), f.message),
            ..f
        })?,
        None => (
            Scenario::parse(THESIS_SCENARIO, THESIS_SCENARIO_NAME).map_err(Failure::input)?,
            THESIS_SCENARIO_NAME.to_owned(),
        ),
    };
    // Size every run before measuring any, so a bad run fails fast.
    let mut sized = Vec::with_capacity(config.runs.len());
    for (i, run) in config.runs.iter().enumerate() {
        let scaled = scenario.with_generated(run.bodies).ok_or_else(|| {
            Failure::input(format!(
                "{}: runs[{i}]: scenario {origin} has no generators to make {} bodies with",
                config_path.display(),
                run.bodies
            ))
        })?;
        sized.push(scaled);
    }

    let passes = u64::from(config.repeat);
    let total: u64 = config.runs.iter().map(|r| r.updates + 1).sum::<u64>() * passes;
    let progress = ProgressBar::new(total).with_style(
        ProgressStyle::with_template("{spinner} [{bar:30}] {pos}/{len} updates, eta {eta} — {msg}")
            .expect("template is valid")
            .progress_chars("=> "),
    );
    // Every pass goes through all runs, so that a slow spell of the machine
    // falls on several runs rather than on all passes of one.
    let mut measured: Vec<Vec<RunResult>> = vec![Vec::new(); config.runs.len()];
    let mut finished = 0;
    for pass in 1..=passes {
        for (i, (run, scenario)) in config.runs.iter().zip(&sized).enumerate() {
            let of_passes = if passes > 1 {
                format!(" (pass {pass}/{passes})")
            } else {
                String::new()
            };
            progress.set_message(format!(
                "run {}/{}{of_passes}: {} bodies, {}",
                i + 1,
                config.runs.len(),
                run.bodies,
                run.mode
            ));
            bench::reset_peak_memory();
            let result = bench::measure(i + 1, scenario, &origin, run, |done| {
                progress.set_position(finished + 1 + done)
            })
            .map_err(|e| Failure::input(format!("{}: runs[{i}]: {e}", config_path.display())))?;
            finished += run.updates + 1;
            let memory = bench::peak_memory().map_or(String::new(), |peak| {
                format!(
                    ", peak memory {:.0} MiB ({:.0} B/body)",
                    peak as f64 / f64::from(1 << 20),
                    peak as f64 / result.bodies_start.max(1) as f64
                )
            });
            let line = format!(
                "run {:>3}{of_passes}: {:>8} bodies, {:>10} on {:>2} thread(s): {:>12.3} ms/update{memory}",
                result.run,
                result.bodies_start,
                result.mode.name(),
                result.threads,
                result.update_ns / 1e6
            );
            // A hidden bar (stderr not a terminal) drops its lines: print them.
            if progress.is_hidden() {
                eprintln!("{line}");
            } else {
                progress.println(line);
            }
            measured[i].push(result);
        }
    }
    progress.finish_and_clear();
    let results: Vec<RunResult> = measured.into_iter().filter_map(bench::median_pass).collect();

    fn io(path: &Path) -> impl Fn(std::io::Error) -> Failure + '_ {
        move |e| Failure {
            message: format!("{}: {e}", path.display()),
            code: 1,
        }
    }
    write_atomically(&outputs.results, |w| bench::write_results(&results, w)).map_err(io(&outputs.results))?;
    let overhead = bench::overhead_rows(&results);
    if !overhead.is_empty() {
        write_atomically(&outputs.overhead, |w| {
            writeln!(w, "{}", bench::OVERHEAD_HEADER)?;
            overhead.iter().try_for_each(|row| writeln!(w, "{row}"))
        })
        .map_err(io(&outputs.overhead))?;
    }
    let title = format!("Kessler: {}, time per update", scenario.name);
    let svg = bench::svg(&results, &title);
    write_atomically(&outputs.plot, |w| w.write_all(svg.as_bytes())).map_err(io(&outputs.plot))?;
    let png = bench::png(&svg).map_err(|message| Failure { message, code: 1 })?;
    write_atomically(&outputs.plot_png, |w| w.write_all(&png)).map_err(io(&outputs.plot_png))?;
    println!(
        "{} runs written to {}{}, plot {} and {}",
        results.len(),
        outputs.results.display(),
        if overhead.is_empty() {
            String::new()
        } else {
            format!(", overhead of going parallel {}", outputs.overhead.display())
        },
        outputs.plot.display(),
        outputs.plot_png.display()
    );
    Ok(())
}
