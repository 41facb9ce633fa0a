//! [`StageClocks`]: what every stage system takes to time itself and to run its
//! kernels, so that a stage names itself once — in [`StageClocks::start`], by its
//! [`SimulationSystems`] value — and the clock and the execution call are
//! written here only.

use std::time::Instant;

use bevy::ecs::system::SystemParam;
use bevy::prelude::*;

use super::{SimulationSystems, StageTimings};
use crate::execution::{Execution, StageExecution};

/// A stage system's parameter: the execution and the stage timings.
#[derive(SystemParam)]
pub struct StageClocks<'w> {
    execution: Res<'w, Execution>,
    timings: ResMut<'w, StageTimings>,
}

impl StageClocks<'_> {
    /// Starts `stage`'s clock. The time counts only once
    /// `StageClock::finish` is called: a stage that returns early (switched
    /// off) records no sample, as no work was done.
    pub fn start(&mut self, stage: SimulationSystems) -> StageClock<'_> {
        StageClock {
            stage,
            started: Instant::now(),
            execution: &self.execution,
            timings: &mut self.timings,
        }
    }
}

/// One stage's running clock, and its way to its kernels' execution.
#[must_use = "a stage's time counts once `finish` is called"]
pub struct StageClock<'a> {
    stage: SimulationSystems,
    started: Instant,
    execution: &'a Execution,
    timings: &'a mut StageTimings,
}

impl<'a> StageClock<'a> {
    /// How this stage runs its kernels in a world of `bodies` bodies: whole
    /// or in chunks, as the split policy decides for this stage.
    pub fn execution(&self, bodies: usize) -> StageExecution<'a> {
        self.execution.for_stage(self.stage.name(), bodies)
    }

    /// The execution itself, for a stage that weighs its work in another
    /// unit than bodies before it asks how to split it (gravity: pulls).
    pub fn executor(&self) -> &'a Execution {
        self.execution
    }

    /// Records the time since [`StageClocks::start`] as this update's sample of
    /// the stage.
    pub fn finish(self) {
        self.timings.record(self.stage, self.started.elapsed());
    }
}
