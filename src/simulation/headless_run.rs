//! A headless run of a scenario (`kessler headless`, and `kessler run` in
//! a build without the window): the updates, a fault check, and the final
//! state written where asked — the dump, the timeline and the snapshot,
//! all of them or none. What it did comes back as a [`HeadlessReport`];
//! the command line prints it.

use std::path::Path;
use std::time::{Duration, Instant};

use super::Simulation;
use super::Timeline;
use crate::execution::Execution;
use crate::input::InputError;
use crate::output::{WriteError, commit_all, stage};
use crate::record::{StateHash, write_csv};
use crate::scenario::{Scenario, Snapshot, not_a_scenario, write_snapshot};
use crate::systems::{CollisionStats, StageTimings};
use crate::timed_events::EventLog;

/// Where a headless run writes its final state, if anywhere.
#[derive(Clone, Copy, Debug, Default)]
pub struct Outputs<'a> {
    /// The CSV dump (`--dump`).
    pub dump: Option<&'a Path>,
    /// The snapshot scenario (`--save-scenario`).
    pub scenario: Option<&'a Path>,
    /// The timeline (`--timeline`) and the updates between its rows.
    pub timeline: Option<(&'a Path, u64)>,
}

/// What a headless run did.
#[derive(Clone, Debug)]
pub struct HeadlessReport {
    /// Updates run.
    pub updates: u64,
    /// Bodies at the start, and at the end.
    pub bodies: (usize, usize),
    /// What collisions did, over the run.
    pub collisions: CollisionStats,
    /// The time the updates took (with the timeline's rows, if any).
    pub elapsed: Duration,
    /// The stages' timings.
    pub timings: StageTimings,
    /// The events applied and skipped.
    pub events: EventLog,
    /// The final state's hash.
    pub hash: StateHash,
}

impl HeadlessReport {
    /// Milliseconds an update took on average (0 for no updates).
    pub fn ms_per_update(&self) -> f64 {
        if self.updates == 0 {
            0.0
        } else {
            self.elapsed.as_secs_f64() * 1e3 / self.updates as f64
        }
    }
}

/// Why a headless run wrote nothing.
#[derive(Debug, thiserror::Error)]
pub enum HeadlessError {
    /// The scenario's bodies could not be made.
    #[error(transparent)]
    Scenario(#[from] InputError),
    /// The simulation stopped, or reached a state its outputs cannot hold.
    #[error("{0}")]
    Stopped(String),
    /// An output could not be written.
    #[error("{0}")]
    Write(String),
}

/// Runs `updates` updates of `scenario`, telling `progress` how many are
/// done now and then, then writes `outputs`: each in full beside its
/// target first, and only when all are written are they put in place, so
/// that a run whose outputs cannot all be written writes none of them. A
/// state that is not finite, or that a scenario cannot hold when one is
/// asked for, stops the run before any output is touched.
pub fn run_headless(
    scenario: &Scenario,
    execution: Execution,
    updates: u64,
    outputs: Outputs<'_>,
    progress: impl FnMut(u64),
) -> Result<HeadlessReport, HeadlessError> {
    let mut sim = Simulation::from_scenario(scenario, execution)?;
    let bodies_start = sim.body_count();
    let mut timeline = outputs.timeline.map(|(_, every)| Timeline::new(every));
    let start = Instant::now();
    match timeline.as_mut() {
        Some(timeline) => timeline.run(&mut sim, updates, progress),
        None => sim.step_reporting(updates, 200, progress),
    }
    let elapsed = start.elapsed();
    if let Some(fault) = sim.check_state() {
        return Err(HeadlessError::Stopped(format!("{}: {fault}", scenario.origin)));
    }
    // The final state's hash, read where the bodies lie, in the memory the
    // sort's buffers took; the state is gathered only for the outputs that
    // write it.
    sim.release_buffers();
    let hash = sim.state_hash_in_place();
    write_outputs(&mut sim, scenario, updates, (outputs, timeline.as_ref()))?;
    Ok(HeadlessReport {
        updates,
        bodies: (bodies_start, sim.body_count()),
        collisions: sim.collision_stats(),
        elapsed,
        timings: sim.timings().clone(),
        events: sim.event_log().clone(),
        hash,
    })
}

/// Writes the outputs asked for, all or none.
fn write_outputs(
    sim: &mut Simulation,
    scenario: &Scenario,
    updates: u64,
    (outputs, timeline): (Outputs<'_>, Option<&Timeline>),
) -> Result<(), HeadlessError> {
    let bodies = if outputs.dump.is_some() || outputs.scenario.is_some() {
        sim.snapshot()
    } else {
        Vec::new()
    };
    if outputs.scenario.is_some()
        && let Some(problem) = not_a_scenario(&bodies, sim.settings())
    {
        return Err(HeadlessError::Stopped(format!(
            "{}: after {updates} updates, {problem} (--save-scenario); the simulation stopped and no output was written",
            scenario.origin
        )));
    }
    let failed = |flag: &str, e: WriteError| HeadlessError::Write(format!("{flag} {e}; no output was written"));
    let mut staged = Vec::new();
    if let Some(path) = outputs.dump {
        staged.push(stage(path, |w| write_csv(&bodies, w)).map_err(|e| failed("--dump", e))?);
    }
    if let (Some((path, _)), Some(timeline)) = (outputs.timeline, timeline) {
        staged.push(stage(path, |w| timeline.write_csv(w)).map_err(|e| failed("--timeline", e))?);
    }
    if let Some(path) = outputs.scenario {
        let pending = sim.pending_events(&bodies);
        let snapshot = Snapshot {
            name: &scenario.name,
            updates,
            settings: sim.settings(),
            bodies: &bodies,
            next_id: sim.next_body_id(),
            events: &pending.events,
            left_out: &pending.left_out,
        };
        staged.push(stage(path, |w| write_snapshot(&snapshot, w)).map_err(|e| failed("--save-scenario", e))?);
    }
    commit_all(staged).map_err(|e| HeadlessError::Write(format!("{e} (putting the outputs in place)")))
}
