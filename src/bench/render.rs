//! Window runs of a benchmark (`Render` in a config): each opens the
//! window in a child process — `kessler run` with `--frames` and
//! `--frame-report` — and reads back what it measured: frame times, FPS,
//! the process's memory and the GPU memory.

use std::path::{Path, PathBuf};
use std::process::Command;

use super::config::RenderRun;

/// Frames a window run draws before it starts timing (pipelines compile,
/// buffers fill).
pub const WINDOW_WARMUP_FRAMES: u64 = 10;

/// What a window run measured, as its child wrote it to the frame report.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FrameReport {
    /// Bodies in the scene.
    pub bodies: u64,
    /// Frames timed (after the warm-up).
    pub frames: u64,
    /// Mean frame time, ms.
    pub mean_ms: f64,
    /// 95th percentile frame time, ms.
    pub p95_ms: f64,
    /// Simulation updates per second while drawing.
    pub updates_per_second: f64,
    /// Peak resident memory of the process, bytes.
    pub peak_ram_bytes: u64,
    /// GPU memory in use, bytes (see `gpu_source`).
    pub gpu_bytes: u64,
    /// GPU memory the allocator holds, in use or not, bytes (0 if unknown).
    pub gpu_reserved_bytes: u64,
    /// Where `gpu_bytes` comes from.
    pub gpu_source: String,
    /// The GPU adapter's name.
    pub adapter: String,
}

impl FrameReport {
    /// `key=value` lines, as the child writes them.
    pub fn to_text(&self) -> String {
        format!(
            "bodies={}\nframes={}\nmean_ms={}\np95_ms={}\nupdates_per_second={}\npeak_ram_bytes={}\ngpu_bytes={}\ngpu_reserved_bytes={}\ngpu_source={}\nadapter={}\n",
            self.bodies,
            self.frames,
            self.mean_ms,
            self.p95_ms,
            self.updates_per_second,
            self.peak_ram_bytes,
            self.gpu_bytes,
            self.gpu_reserved_bytes,
            self.gpu_source,
            self.adapter
        )
    }

    /// Reads [`to_text`](Self::to_text)'s lines; `None` if a number is
    /// missing or malformed.
    pub fn parse(text: &str) -> Option<Self> {
        let get = |key: &str| {
            text.lines()
                .find_map(|l| l.strip_prefix(key)?.strip_prefix('='))
                .map(str::trim)
        };
        Some(Self {
            bodies: get("bodies")?.parse().ok()?,
            frames: get("frames")?.parse().ok()?,
            mean_ms: get("mean_ms")?.parse().ok()?,
            p95_ms: get("p95_ms")?.parse().ok()?,
            updates_per_second: get("updates_per_second")?.parse().ok()?,
            peak_ram_bytes: get("peak_ram_bytes")?.parse().ok()?,
            gpu_bytes: get("gpu_bytes")?.parse().ok()?,
            gpu_reserved_bytes: get("gpu_reserved_bytes")?.parse().ok()?,
            gpu_source: get("gpu_source")?.to_owned(),
            adapter: get("adapter")?.to_owned(),
        })
    }
}

/// A window run failed.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct RenderRunError(String);

/// CSV-safe text: no commas, quotes or line ends.
fn plain(text: &str) -> String {
    text.chars()
        .map(|c| if matches!(c, ',' | '"' | '\n' | '\r') { ' ' } else { c })
        .collect()
}

/// The row of `<stem>-render.csv` for one window run.
#[derive(Clone, Debug)]
pub struct RenderRow {
    /// The run's place in the config, from 1.
    pub index: usize,
    /// What the config asked for.
    pub run: RenderRun,
    /// What the child measured.
    pub report: FrameReport,
}

impl RenderRow {
    /// Frames per second from the mean frame time (0 without frames).
    fn fps(&self) -> f64 {
        if self.report.mean_ms > 0.0 {
            1e3 / self.report.mean_ms
        } else {
            0.0
        }
    }
}

crate::csv_row!(RenderRow, |r| {
    run: r.index,
    bodies: r.report.bodies,
    method: r.run.method,
    simulate: r.run.simulate,
    mode: r.run.execution.mode(),
    vsync: if r.run.vsync { "on" } else { "off" },
    frames: r.report.frames,
    mean_fps: format_args!("{:.2}", r.fps()),
    mean_frame_ms: format_args!("{:.3}", r.report.mean_ms),
    p95_frame_ms: format_args!("{:.3}", r.report.p95_ms),
    updates_per_second: format_args!("{:.1}", r.report.updates_per_second),
    peak_ram_bytes: r.report.peak_ram_bytes,
    gpu_bytes: r.report.gpu_bytes,
    gpu_reserved_bytes: r.report.gpu_reserved_bytes,
    gpu_bytes_source: plain(&r.report.gpu_source),
    adapter: plain(&r.report.adapter),
});

/// The `kessler run` arguments of `run` on `scenario` (`None`: the
/// window's default scene), reporting to `report` and keeping its settings
/// in `settings` (never the user's own file).
pub fn child_args(run: &RenderRun, scenario: Option<&Path>, report: &Path, settings: &Path) -> Vec<String> {
    let mut args = vec!["run".to_owned()];
    if let Some(path) = scenario {
        args.push(path.display().to_string());
    }
    args.extend(
        [
            "--bodies",
            &run.bodies.to_string(),
            "--frames",
            &(run.frames + WINDOW_WARMUP_FRAMES).to_string(),
            "--render",
            run.method.name(),
            "--vsync",
            if run.vsync { "on" } else { "off" },
            "--mode",
            run.execution.mode().name(),
            "--ups",
            &run.ups.unwrap_or(60).to_string(),
            "--settings",
            &settings.display().to_string(),
            "--frame-report",
            &report.display().to_string(),
        ]
        .map(str::to_owned),
    );
    if !run.simulate {
        args.push("--paused".into());
    }
    if run.offscreen {
        args.push("--offscreen".into());
    }
    let options = run.execution;
    let given = [
        ("--threads", options.threads.map(|t| t.to_string())),
        ("--split", options.split.map(|s| s.to_string())),
        ("--pool", options.pool.map(|p| p.name().to_owned())),
    ];
    for (flag, value) in given {
        if let Some(value) = value {
            args.extend([flag.to_owned(), value]);
        }
    }
    args
}

/// Runs `run` in a child `kessler` (this executable) and reads its report.
pub fn measure_render(run: &RenderRun, scenario: Option<&Path>) -> Result<FrameReport, RenderRunError> {
    let exe = std::env::current_exe().map_err(|e| RenderRunError(format!("cannot find this executable: {e}")))?;
    let dir = tempfile::tempdir().map_err(|e| RenderRunError(format!("cannot make a temporary folder: {e}")))?;
    let report: PathBuf = dir.path().join("frames.txt");
    let settings = dir.path().join("settings.ron");
    let output = Command::new(&exe)
        .args(child_args(run, scenario, &report, &settings))
        .output()
        .map_err(|e| RenderRunError(format!("cannot start {}: {e}", exe.display())))?;
    if !output.status.success() {
        let stderr = String::from_utf8_lossy(&output.stderr);
        let last = stderr
            .lines()
            .rev()
            .find(|l| !l.trim().is_empty())
            .unwrap_or("no message");
        return Err(RenderRunError(format!(
            "the window run failed ({}): {last}",
            output.status
        )));
    }
    let text = std::fs::read_to_string(&report)
        .map_err(|e| RenderRunError(format!("the window run wrote no frame report: {e}")))?;
    FrameReport::parse(&text).ok_or_else(|| RenderRunError(format!("malformed frame report:\n{text}")))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::execution::ExecutionMode;
    use crate::resources::DrawMethod;

    fn run() -> RenderRun {
        RenderRun {
            bodies: 1000,
            frames: 50,
            method: DrawMethod::MeshPerBody,
            simulate: false,
            ups: None,
            vsync: false,
            offscreen: false,
            execution: crate::input::ExecutionOptions {
                mode: Some(ExecutionMode::Parallel),
                ..crate::input::ExecutionOptions::default()
            },
        }
    }

    #[test]
    fn a_frame_report_reads_back_and_becomes_a_row() {
        let report = FrameReport {
            bodies: 1001,
            frames: 50,
            mean_ms: 4.0,
            p95_ms: 6.5,
            updates_per_second: 0.0,
            peak_ram_bytes: 123_456,
            gpu_bytes: 7890,
            gpu_reserved_bytes: 65536,
            gpu_source: "wgpu allocator".into(),
            adapter: "llvmpipe (LLVM 19, 256 bits)".into(),
        };
        assert_eq!(FrameReport::parse(&report.to_text()), Some(report.clone()));
        let row = RenderRow {
            index: 3,
            run: run(),
            report: report.clone(),
        };
        assert_eq!(
            crate::output::line(&row).unwrap(),
            "3,1001,mesh-per-body,false,parallel,off,50,250.00,4.000,6.500,0.0,123456,7890,65536,wgpu allocator,llvmpipe (LLVM 19  256 bits)"
        );
        assert_eq!(
            crate::output::header::<RenderRow>(),
            "run,bodies,method,simulate,mode,vsync,frames,mean_fps,mean_frame_ms,p95_frame_ms,\
             updates_per_second,peak_ram_bytes,gpu_bytes,gpu_reserved_bytes,gpu_bytes_source,adapter"
        );
        assert_eq!(FrameReport::parse("bodies=x"), None);
    }

    #[test]
    fn the_child_is_paused_unless_it_simulates_and_never_uses_the_user_settings() {
        let args = child_args(&run(), None, Path::new("/t/r.txt"), Path::new("/t/s.ron"));
        let joined = args.join(" ");
        assert!(
            joined.starts_with("run --bodies 1000 --frames 60 --render mesh-per-body --vsync off"),
            "{joined}"
        );
        assert!(
            joined.contains("--settings /t/s.ron") && joined.ends_with("--paused"),
            "{joined}"
        );
        let offscreen = RenderRun {
            offscreen: true,
            ..run()
        };
        let args = child_args(&offscreen, None, Path::new("/t/r.txt"), Path::new("/t/s.ron"));
        assert!(args.join(" ").ends_with("--paused --offscreen"), "{args:?}");
    }
}
