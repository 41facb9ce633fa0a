//! `kessler bench CONFIG [--out results.csv] [--split auto|always|N]`: the
//! runs of a benchmark config — headless runs measured in passes, window
//! runs in a child window — written as they finish, then the overhead of
//! splitting, the crossover and a plot. Existing results are never
//! overwritten.

use std::path::Path;

use indicatif::{ProgressBar, ProgressStyle};

use super::Failure;
use crate::bench::{
    self, BenchConfig, BenchOutputs, GrowingOutputs, OverheadRow, PassError, PassProgress, RenderRow, RunDefaults,
    RunResult, Wins, crossovers, machine_report, measure_render, thread_rows,
};
use crate::calibration::machine_auto_split;
use crate::execution::{ExecutionMode, WorkerPool};
use crate::input::ExecutionOptions;
use crate::input::default_calibration_path;
use crate::resources::GravityMethod;
use crate::scenario::Scenario;

/// Runs the command: load and check everything, measure, write. `gravity`
/// replaces the scenario's gravity method in every run.
pub fn bench(
    config_path: &Path,
    out: &Path,
    execution: ExecutionOptions,
    gravity: Option<GravityMethod>,
) -> Result<(), Failure> {
    let config = BenchConfig::load(config_path)?;
    // (A build without the window refused `Render` runs as it loaded.)
    #[cfg(feature = "gui")]
    if let Some((i, _)) = config.render_runs().find(|(_, run)| !run.offscreen)
        && crate::ui::session::no_display()
    {
        let i = config.origin(i);
        return Err(Failure::input(format!(
            "{}: runs[{i}]: `Render` runs open the window, and there is no X11 display (DISPLAY is not set): \
             run the benchmark in a desktop session, under `xvfb-run -a kessler bench ...`, or give the run \
             `offscreen: true`",
            config_path.display()
        )));
    }
    let outputs = BenchOutputs::beside(out);
    let scenario_path = config.scenario_path(config_path);
    let calibration = default_calibration_path();
    let mut inputs: Vec<(&str, &Path)> = vec![("the bench config", config_path)];
    if let Some(path) = &scenario_path {
        inputs.push(("the scenario the bench config names", path));
    }
    inputs.push(("the split calibration", &calibration));
    outputs.check(&inputs)?;
    let mut scenario = config.load_scenario(config_path)?;
    if let Some(gravity) = gravity {
        scenario.physics.gravity_method = gravity;
    }
    let sized = config.size_runs(&scenario, config_path)?;
    super::headless::warn_of_memory(&scenario);
    let defaults = RunDefaults {
        execution,
        auto: machine_auto_split(),
    };
    let headless = config.update_runs().next().is_some();
    let render = config.render_runs().next().is_some();
    let command: Vec<String> = std::env::args().collect();
    let machine = format!(
        "{}split auto: {}\n",
        machine_report(&command.join(" ")),
        defaults.auto.origin()
    );
    let mut growing = outputs.start(&machine, headless, render)?;
    let (results, passes) = measure_passes(&config, &sized, &defaults, &mut growing, config_path)?;
    for (i, run) in config.render_runs() {
        eprintln!(
            "window run {}: {} bodies, {}, {} frames…",
            i + 1,
            run.bodies,
            run.method,
            run.frames
        );
        let report = measure_render(run, scenario_path.as_deref())
            .map_err(|e| Failure::other(format!("{}: runs[{}]: {e}", config_path.display(), config.origin(i))))?;

        eprintln!(
            "  {:.1} FPS, mean {:.2} ms, p95 {:.2} ms",
            1e3 / report.mean_ms.max(1e-9),
            report.mean_ms,
            report.p95_ms
        );
        growing.add_render(&RenderRow {
            index: i + 1,
            run: run.clone(),
            report,
        })?;
    }
    let empty_steps = if headless { measure_empty_steps()? } else { Vec::new() };
    let crossovers = crossovers(&passes, Wins::EveryPass);
    let title = format!("Kessler: {}, time per update", scenario.name);
    let threads = thread_rows(&config.sweeps, &results);
    let finished = outputs.finish(&results, &empty_steps, &crossovers, &threads, &title)?;
    print_summary(&outputs, &results, &crossovers, finished, render);
    Ok(())
}

/// The bare cost of a parallel step as overhead rows, each said on stderr.
fn measure_empty_steps() -> Result<Vec<OverheadRow>, Failure> {
    Ok(bench::empty_step_rows(|threads, pool, split, whole| {
        eprintln!(
            "one parallel step of a near-empty kernel on {threads} thread{} of {}'s pool: {:.2} µs (whole: {:.3} µs)",
            if threads == 1 { "" } else { "s" },
            if pool == WorkerPool::Bevy { "Bevy" } else { "Kessler" },
            split / 1e3,
            whole / 1e3
        );
    })?)
}

fn print_summary(
    outputs: &BenchOutputs,
    results: &[RunResult],
    crossovers: &[bench::Crossover],
    finished: bench::Finished,
    render: bool,
) {
    for c in crossovers.iter().filter(|c| c.stage == "update") {
        let from = c
            .from_bodies
            .map_or("at no measured count".to_owned(), |n| format!("from {n} bodies"));
        let auto = c.auto_worst.map_or(String::new(), |(p, at)| {
            format!("; auto at most {p:.1} % over the better of the two (at {at} bodies)")
        });
        eprintln!(
            "parallel (split always, {} threads) beats sequential in every pass {from}{auto}",
            c.threads
        );
    }
    let mut written: Vec<String> = Vec::new();
    if !results.is_empty() {
        written.push(format!("{} runs to {}", results.len(), outputs.results.display()));
        written.push(format!("every pass to {}", outputs.passes.display()));
    }
    let named = [
        (finished.overhead, "the overhead of splitting", &outputs.overhead),
        (finished.crossover, "the crossover", &outputs.crossover),
        (render, "window runs", &outputs.render),
    ];
    for (done, what, path) in named {
        if done {
            written.push(format!("{what} to {}", path.display()));
        }
    }
    written.push(format!("the machine to {}", outputs.machine.display()));
    if finished.plot {
        written.push(format!(
            "plot {} and {}",
            outputs.plot_svg.display(),
            outputs.plot_png.display()
        ));
    }
    if finished.threads {
        written.push(format!(
            "the speed-ups against threads to {}, plotted in {} and {}",
            outputs.threads.display(),
            outputs.threads_svg.display(),
            outputs.threads_png.display()
        ));
    }
    println!("written: {}", written.join("; "));
}

/// Measures every headless run with a progress bar (`bench::measure_passes`).
fn measure_passes(
    config: &BenchConfig,
    sized: &[Scenario],
    defaults: &RunDefaults,
    growing: &mut GrowingOutputs,
    config_path: &Path,
) -> Result<(Vec<RunResult>, Vec<Vec<RunResult>>), Failure> {
    let mut progress = BenchProgress::new(config, u64::from(config.repeat));
    let measured = bench::measure_passes(config, sized, defaults, growing, &mut progress);
    progress.clear();
    measured.map_err(|e| match e {
        PassError::Run { index, error } => Failure::from(error).context(format_args!(
            "{}: runs[{}]",
            config_path.display(),
            config.origin(index)
        )),
        PassError::Write(e) => Failure::from(e),
    })
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

impl PassProgress for BenchProgress {
    fn start(&mut self, index: usize, pass: u64, run: &bench::Run, mode: ExecutionMode) {
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
            mode
        ));
    }

    fn advance(&self, done: u64) {
        self.bar.set_position(self.finished + 1 + done);
    }

    fn finish(&mut self, run: &bench::Run, result: &RunResult, peak_memory: Option<u64>) {
        self.finished += run.updates + 1;
        let memory = peak_memory.map_or(String::new(), |peak| {
            format!(
                ", peak memory {:.0} MiB ({:.0} B/body)",
                peak as f64 / f64::from(1 << 20),
                peak as f64 / result.bodies_start.max(1) as f64
            )
        });
        // A sequential run uses one thread, whatever the run's `threads`.
        let (threads, split) = match result.mode {
            crate::execution::ExecutionMode::Sequential => (1, String::new()),
            _ => (result.threads, format!(", split {}", result.split)),
        };
        let line = format!(
            "run {:>3}{}: {:>8} bodies, {:>10} on {:>2} thread(s){split}: {:>12.3} ms/update{memory}",
            result.run,
            self.of_passes,
            result.bodies_start,
            result.mode.name(),
            threads,
            result.update_ns / 1e6
        );
        // A hidden bar (stderr not a terminal) drops its lines: print them.
        if self.bar.is_hidden() {
            eprintln!("{line}");
        } else {
            self.bar.println(line);
        }
    }
}

impl BenchProgress {
    fn new(config: &BenchConfig, passes: u64) -> Self {
        // Each count is at most 10^12 (MAX_UPDATES); saturating all the same.
        let total = config
            .update_runs()
            .fold(0_u64, |sum, (_, r)| sum.saturating_add(r.updates + 1))
            .saturating_mul(passes);
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

    fn clear(&self) {
        self.bar.finish_and_clear();
    }
}
