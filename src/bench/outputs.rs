//! The files a benchmark writes, all beside its results CSV, none of them
//! ever over an existing file. The results, their passes, the window runs'
//! frames and the machine report are written as the benchmark goes, so an
//! interrupted benchmark keeps what it measured; the overhead report, the
//! crossover and the plot when it ends.

use std::path::{Path, PathBuf};

use super::{
    Crossover, Labels, OverheadRow, PassRow, RenderRow, RunResult, ThreadsRow, overhead_rows, plot_footer, png, svg,
    threads_png, threads_svg,
};
use crate::output::{
    AppendedFile, Output, OutputError, OutputProblem, WriteError, check_outputs, write_atomically, write_csv,
};

/// What to do when an output exists already.
const NEVER_OVERWRITE: &str = "remove it or choose another --out (results are never overwritten)";

/// The results CSV (`--out`) and, beside it, files named after its stem.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BenchOutputs {
    /// The results: a row per headless run (its median pass).
    pub results: PathBuf,
    /// `<stem>-passes.csv`: a row per pass of every headless run.
    pub passes: PathBuf,
    /// `<stem>-overhead.csv`: what splitting costs (the thesis's Table 6).
    pub overhead: PathBuf,
    /// `<stem>-crossover.csv`: where parallel starts to pay.
    pub crossover: PathBuf,
    /// `<stem>-machine.txt`: the machine and build.
    pub machine: PathBuf,
    /// `<stem>-render.csv`: the window runs' frames.
    pub render: PathBuf,
    /// `<stem>.svg`: the plot.
    pub plot_svg: PathBuf,
    /// `<stem>.png`: the plot.
    pub plot_png: PathBuf,
    /// `<stem>-threads.csv`: the thread sweeps' speed-ups.
    pub threads: PathBuf,
    /// `<stem>-threads.svg`: their plot.
    pub threads_svg: PathBuf,
    /// `<stem>-threads.png`: their plot.
    pub threads_png: PathBuf,
}

/// Why the outputs could not be written.
#[derive(Debug, thiserror::Error)]
pub enum BenchOutputError {
    /// A file could not be written.
    #[error(transparent)]
    Write(#[from] WriteError),
    /// The plot could not be drawn.
    #[error(transparent)]
    Plot(#[from] super::PlotError),
}

/// The files that grow while the benchmark runs.
#[derive(Debug)]
pub struct GrowingOutputs {
    /// Results rows, as each run's last pass ends.
    pub results: Option<AppendedFile<RunResult>>,
    /// Pass rows, as each pass of a run ends.
    pub passes: Option<AppendedFile<PassRow>>,
    /// Window rows, as each window run ends.
    pub render: Option<AppendedFile<RenderRow>>,
}

impl GrowingOutputs {
    /// Adds `result`, measured in pass `pass`, to the passes.
    pub fn add_pass(&mut self, pass: u64, result: &RunResult) -> Result<(), WriteError> {
        match &mut self.passes {
            Some(file) => file.append(&PassRow {
                pass,
                result: result.clone(),
            }),
            None => Ok(()),
        }
    }

    /// Adds a run's final figure to the results.
    pub fn add_result(&mut self, result: &RunResult) -> Result<(), WriteError> {
        match &mut self.results {
            Some(file) => file.append(result),
            None => Ok(()),
        }
    }

    /// Adds a window run's row.
    pub fn add_render(&mut self, row: &RenderRow) -> Result<(), WriteError> {
        match &mut self.render {
            Some(file) => file.append(row),
            None => Ok(()),
        }
    }
}

/// What [`BenchOutputs::finish`] wrote besides the plot.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Finished {
    /// The overhead report.
    pub overhead: bool,
    /// The crossover.
    pub crossover: bool,
    /// The plot.
    pub plot: bool,
    /// The thread speed-ups and their plot.
    pub threads: bool,
}

impl BenchOutputs {
    /// The outputs of results written to `results`.
    pub fn beside(results: &Path) -> Self {
        let stem = results
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "results".into());
        let sibling = |suffix: &str| results.with_file_name(format!("{stem}{suffix}"));
        Self {
            results: results.to_owned(),
            passes: sibling("-passes.csv"),
            overhead: sibling("-overhead.csv"),
            crossover: sibling("-crossover.csv"),
            machine: sibling("-machine.txt"),
            render: sibling("-render.csv"),
            plot_svg: sibling(".svg"),
            plot_png: sibling(".png"),
            threads: sibling("-threads.csv"),
            threads_svg: sibling("-threads.svg"),
            threads_png: sibling("-threads.png"),
        }
    }

    /// Every output path, results first.
    pub fn paths(&self) -> [&Path; 11] {
        [
            &self.results,
            &self.passes,
            &self.overhead,
            &self.crossover,
            &self.machine,
            &self.render,
            &self.plot_svg,
            &self.plot_png,
            &self.threads,
            &self.threads_svg,
            &self.threads_png,
        ]
    }

    /// What each of [`Self::paths`] holds, in words.
    const WHAT: [&'static str; 11] = [
        "results",
        "passes",
        "overhead",
        "crossover",
        "machine report",
        "window runs",
        "SVG plot",
        "PNG plot",
        "thread speed-ups",
        "SVG thread plot",
        "PNG thread plot",
    ];

    /// Refuses, before any run, if two outputs would be one file (`--out
    /// r.svg` names the plot's path), if an output is one of the files the
    /// benchmark reads, `inputs` (what, in words, and path: see
    /// [`check_outputs`]), or if an output exists or its folder does not.
    pub fn check(&self, inputs: &[(&str, &Path)]) -> Result<(), OutputError> {
        let paths = self.paths();
        for (i, path) in paths.iter().enumerate() {
            if let Some(j) = paths[i + 1..].iter().position(|other| other == path) {
                return Err(OutputError {
                    flag: "--out".to_owned(),
                    path: path.to_path_buf(),
                    problem: OutputProblem::Shared(Self::WHAT[i + 1 + j]),
                });
            }
        }
        let outputs: Vec<Output<'_>> = paths
            .into_iter()
            .map(|path| Output::new_only("--out", path, NEVER_OVERWRITE))
            .collect();
        check_outputs(&outputs, inputs)
    }

    /// Writes the machine report and creates the files that grow while the
    /// benchmark runs: the results and passes if there are headless runs,
    /// the window rows if there are window runs.
    pub fn start(&self, machine: &str, headless: bool, render: bool) -> Result<GrowingOutputs, WriteError> {
        write_atomically(&self.machine, |w| w.write_all(machine.as_bytes()))?;
        let results = headless.then(|| AppendedFile::create(&self.results)).transpose()?;
        let passes = headless.then(|| AppendedFile::create(&self.passes)).transpose()?;
        let render = render.then(|| AppendedFile::create(&self.render)).transpose()?;
        Ok(GrowingOutputs {
            results,
            passes,
            render,
        })
    }

    /// Writes the overhead report (the runs' pairs, then `empty_steps`),
    /// the crossovers, the plot titled `title` of the headless results,
    /// and the thread sweeps' speed-ups and their plot if there are any.
    pub fn finish(
        &self,
        results: &[RunResult],
        empty_steps: &[OverheadRow],
        crossovers: &[Crossover],
        threads: &[ThreadsRow],
        title: &str,
    ) -> Result<Finished, BenchOutputError> {
        let mut finished = Finished::default();
        if results.is_empty() {
            return Ok(finished);
        }
        let mut overhead = overhead_rows(results);
        overhead.extend_from_slice(empty_steps);
        if !overhead.is_empty() {
            write_atomically(&self.overhead, |w| write_csv(w, &overhead))?;
            finished.overhead = true;
        }
        if !crossovers.is_empty() {
            write_atomically(&self.crossover, |w| write_csv(w, crossovers))?;
            finished.crossover = true;
        }
        let footer = plot_footer();
        let labels = Labels { title, footer: &footer };
        let plot = svg(results, crossovers, labels)?;
        write_atomically(&self.plot_svg, |w| w.write_all(plot.as_bytes()))?;
        let plot = png(results, crossovers, labels)?;
        write_atomically(&self.plot_png, |w| w.write_all(&plot))?;
        finished.plot = true;
        if !threads.is_empty() {
            write_atomically(&self.threads, |w| write_csv(w, threads))?;
            let title = title.replace("time per update", "speed-up against threads");
            let labels = Labels {
                title: &title,
                footer: &footer,
            };
            let plot = threads_svg(threads, labels)?;
            write_atomically(&self.threads_svg, |w| w.write_all(plot.as_bytes()))?;
            let plot = threads_png(threads, labels)?;
            write_atomically(&self.threads_png, |w| w.write_all(&plot))?;
            finished.threads = true;
        }
        Ok(finished)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outputs_sit_beside_the_results() {
        let outputs = BenchOutputs::beside(Path::new("out/thesis.csv"));
        assert_eq!(outputs.passes, Path::new("out/thesis-passes.csv"));
        assert_eq!(outputs.overhead, Path::new("out/thesis-overhead.csv"));
        assert_eq!(outputs.crossover, Path::new("out/thesis-crossover.csv"));
        assert_eq!(outputs.machine, Path::new("out/thesis-machine.txt"));
        assert_eq!(outputs.render, Path::new("out/thesis-render.csv"));
        assert_eq!(outputs.plot_svg, Path::new("out/thesis.svg"));
        assert_eq!(outputs.plot_png, Path::new("out/thesis.png"));
    }
}
