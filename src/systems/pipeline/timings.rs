//! Wall-clock cost of each simulation stage.

use std::time::Duration;

use bevy::prelude::*;

use super::{STAGE_COUNT, SimulationSystems};

/// Last and mean duration of one kind of work, in nanoseconds.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Timing {
    /// Duration of the most recent sample.
    pub last_ns: u64,
    /// Mean over all samples since the last reset.
    pub mean_ns: f64,
    /// Samples since the last reset.
    pub samples: u64,
}

impl Timing {
    /// Adds one sample to the running mean.
    pub fn record(&mut self, elapsed: Duration) {
        let ns = u64::try_from(elapsed.as_nanos()).unwrap_or(u64::MAX);
        self.last_ns = ns;
        self.samples += 1;
        self.mean_ns += (ns as f64 - self.mean_ns) / self.samples as f64;
    }
}

/// Per-stage timings of the simulation, and of whole updates.
#[derive(Resource, Clone, Debug, Default)]
pub struct StageTimings {
    stages: [Timing; STAGE_COUNT],
    /// One whole update, all stages and scheduling included.
    pub update: Timing,
}

impl StageTimings {
    /// The timing of one stage.
    pub fn stage(&self, stage: SimulationSystems) -> &Timing {
        &self.stages[stage as usize]
    }

    /// Adds a sample of `stage`.
    pub fn record(&mut self, stage: SimulationSystems, elapsed: Duration) {
        self.stages[stage as usize].record(elapsed);
    }

    /// Forgets all samples (e.g. between benchmark runs).
    pub fn reset(&mut self) {
        *self = Self::default();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn running_mean_of_samples() {
        let mut t = StageTimings::default();
        for ns in [100, 200, 600] {
            t.record(SimulationSystems::Integrate, Duration::from_nanos(ns));
        }
        let i = t.stage(SimulationSystems::Integrate);
        assert_eq!((i.last_ns, i.samples), (600, 3));
        assert!((i.mean_ns - 300.0).abs() < 1e-9);
        assert_eq!(t.stage(SimulationSystems::Gravity).samples, 0);
    }
}
