//! Frame times: a smoothed FPS for the HUD, a short history for the plots,
//! and every frame of a `--frames` run for its report.

use std::collections::VecDeque;

use bevy::prelude::*;

use crate::systems::{STAGE_COUNT, SimulationSystems, StageTimings};

/// Entries kept for the HUD's rolling plots.
pub const HISTORY: usize = 240;

/// Records every frame's time and each update's stage times.
pub struct FrameStatsPlugin {
    /// Keep every frame time (a scripted run reports them).
    pub record_all: bool,
}

impl Plugin for FrameStatsPlugin {
    fn build(&self, app: &mut App) {
        app.insert_resource(FrameStats::new(self.record_all))
            .add_systems(Last, record_frame_stats);
    }
}

/// Frame times and stage-time history.
#[derive(Resource, Debug, Default)]
pub struct FrameStats {
    /// Exponentially smoothed frame time, seconds.
    pub smoothed: f64,
    /// Frames so far.
    pub frames: u64,
    /// Every frame time, seconds (kept only when `record_all`).
    pub all: Vec<f64>,
    /// Whether every frame time is kept.
    pub record_all: bool,
    /// Last [`HISTORY`] samples of each stage's last update time, ms.
    pub stage_history: VecDeque<[f32; STAGE_COUNT]>,
    /// Last samples-count seen, to add one history entry per new update.
    last_update_samples: u64,
}

impl FrameStats {
    /// Stats that keep every frame time when `record_all` (scripted runs).
    pub fn new(record_all: bool) -> Self {
        Self {
            record_all,
            ..Self::default()
        }
    }

    /// Frames per second, smoothed.
    pub fn fps(&self) -> f64 {
        if self.smoothed > 0.0 { 1.0 / self.smoothed } else { 0.0 }
    }

    /// Adds a frame of `seconds`.
    pub fn record_frame(&mut self, seconds: f64) {
        self.frames += 1;
        self.smoothed = if self.smoothed == 0.0 {
            seconds
        } else {
            self.smoothed + (seconds - self.smoothed) * 0.05
        };
        if self.record_all {
            self.all.push(seconds);
        }
    }
}

/// Summary of frame times: mean, median and 95th percentile in ms.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameSummary {
    /// Frames summarized.
    pub frames: usize,
    /// Mean frame time.
    pub mean_ms: f64,
    /// Median frame time.
    pub median_ms: f64,
    /// 95th percentile of the frame times.
    pub p95_ms: f64,
}

/// Frame time summary of `times` (seconds), skipping the first `warmup`
/// frames (pipeline compilation, first uploads). `None` if nothing is left.
pub fn summarize(times: &[f64], warmup: usize) -> Option<FrameSummary> {
    let mut ms: Vec<f64> = times.iter().skip(warmup).map(|t| t * 1e3).collect();
    if ms.is_empty() {
        return None;
    }
    ms.sort_by(f64::total_cmp);
    let rank = |q: f64| ms[((ms.len() - 1) as f64 * q).round() as usize];
    Some(FrameSummary {
        frames: ms.len(),
        mean_ms: ms.iter().sum::<f64>() / ms.len() as f64,
        median_ms: rank(0.5),
        p95_ms: rank(0.95),
    })
}

/// Records the frame's time and the last update's stage times.
pub fn record_frame_stats(time: Res<Time<Real>>, timings: Res<StageTimings>, mut stats: ResMut<FrameStats>) {
    stats.record_frame(time.delta_secs_f64());
    if timings.update.samples != stats.last_update_samples {
        stats.last_update_samples = timings.update.samples;
        let sample = SimulationSystems::ALL.map(|s| timings.stage(s).last_ns as f32 / 1e6);
        if stats.stage_history.len() == HISTORY {
            stats.stage_history.pop_front();
        }
        stats.stage_history.push_back(sample);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn summary_skips_warmup_and_ranks() {
        // A 1 s first frame (shader compilation), then 1..=100 ms.
        let mut times = vec![1.0];
        times.extend((1..=100).map(|ms| f64::from(ms) / 1e3));
        let s = summarize(&times, 1).unwrap();
        assert_eq!(s.frames, 100);
        assert!((s.mean_ms - 50.5).abs() < 1e-9);
        assert!((s.median_ms - 51.0).abs() < 1e-9 || (s.median_ms - 50.0).abs() < 1e-9);
        assert!((s.p95_ms - 95.0).abs() <= 1.0);
        assert!(summarize(&times, 101).is_none());
    }

    #[test]
    fn fps_follows_steady_frames() {
        let mut stats = FrameStats::default();
        for _ in 0..500 {
            stats.record_frame(1.0 / 50.0);
        }
        assert!((stats.fps() - 50.0).abs() < 1e-6);
        assert!(stats.all.is_empty(), "all frames are kept only on request");
    }
}
