//! What every stage runs in: the stage list ([`STAGES`]: order, names,
//! colors, CSV columns), the [`SimulationUpdate`] schedule chained from it,
//! the [`StageClocks`] parameter each stage times itself with and gets its
//! execution from, the timings, the [`UpdateCount`], and the run's
//! [`SimulationFault`] with the limits that raise it.

mod fault;
pub(in crate::systems) mod pair_limit;
mod schedule;
mod stage_clock;
mod stages;
mod timings;
mod update_count;

pub use fault::{Fault, SimulationFault, first_non_finite, no_fault};
pub use pair_limit::{TooManyPairs, Travel, pair_limit, swept_pair_limit};
pub use schedule::{BetweenUpdates, NextEventAt, SchedulePlugin, SimulationUpdate, run_due_events, run_updates};
pub use stage_clock::StageClocks;
pub use stages::{STAGE_COUNT, STAGES, SimulationSystems};
pub use timings::{StageTimings, Timing};
pub use update_count::UpdateCount;
