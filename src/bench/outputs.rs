//! The files a benchmark writes, all beside its results CSV, none of them
//! ever over an existing file.

use std::path::{Path, PathBuf};

use super::{RunResult, overhead_rows, png, svg, write_overhead, write_results};
use crate::output::{OutputError, WriteError, check_new, write_atomically};

/// What to do when an output exists already.
const NEVER_OVERWRITE: &str = "remove it or choose another --out (results are never overwritten)";

/// The results CSV and, beside it, `<stem>-overhead.csv`, `<stem>.svg` and
/// `<stem>.png`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BenchOutputs {
    /// The results CSV (`--out`).
    pub results: PathBuf,
    /// The overhead report.
    pub overhead: PathBuf,
    /// The plot as SVG.
    pub plot_svg: PathBuf,
    /// The plot as PNG.
    pub plot_png: PathBuf,
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
            overhead: sibling("-overhead.csv"),
            plot_svg: sibling(".svg"),
            plot_png: sibling(".png"),
        }
    }

    /// Every output path, results first.
    pub fn paths(&self) -> [&Path; 4] {
        [&self.results, &self.overhead, &self.plot_svg, &self.plot_png]
    }

    /// Refuses, before any run, if an output exists or its folder does not.
    pub fn check(&self) -> Result<(), OutputError> {
        self.paths()
            .into_iter()
            .try_for_each(|path| check_new("--out", path, NEVER_OVERWRITE))
    }

    /// Writes the results, the overhead report (when a body count was run
    /// both sequentially and in parallel on one thread; returns whether)
    /// and the plot titled `title`.
    pub fn write(&self, results: &[RunResult], title: &str) -> Result<bool, BenchOutputError> {
        write_atomically(&self.results, |w| write_results(results, w))?;
        let overhead = overhead_rows(results);
        if !overhead.is_empty() {
            write_atomically(&self.overhead, |w| write_overhead(&overhead, w))?;
        }
        let plot = svg(results, title)?;
        write_atomically(&self.plot_svg, |w| w.write_all(plot.as_bytes()))?;
        let plot = png(results, title)?;
        write_atomically(&self.plot_png, |w| w.write_all(&plot))?;
        Ok(!overhead.is_empty())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outputs_sit_beside_the_results() {
        let outputs = BenchOutputs::beside(Path::new("out/thesis.csv"));
        assert_eq!(outputs.overhead, Path::new("out/thesis-overhead.csv"));
        assert_eq!(outputs.plot_svg, Path::new("out/thesis.svg"));
        assert_eq!(outputs.plot_png, Path::new("out/thesis.png"));
    }
}
