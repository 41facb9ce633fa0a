//! The record of a run (`kessler headless ... --timeline FILE [--every
//! K]`): a CSV row every K updates with the body count, what collisions
//! did, the totals the physics conserves, and the state's hash. The window's HUD and panel
//! show the same numbers ([`Totals`], [`CollisionStats`](crate::systems::CollisionStats)). Written
//! atomically, like the dump.

use std::io::{self, Write};

use super::Simulation;
use crate::physics::Totals;
use crate::record::StateHash;

/// The updates at which [`Timeline::run`] records its rows for a run of
/// `updates` updates, a row every `every`, when no fault stops it: 0,
/// `every`, `2·every`, …, and `updates`.
pub fn row_updates(updates: u64, every: u64) -> Vec<u64> {
    let every = every.max(1);
    let mut rows = vec![0];
    let mut done = 0;
    while done < updates {
        done += every.min(updates - done);
        rows.push(done);
    }
    rows
}

/// One row: the state after `update` updates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TimelineRow {
    /// Updates run.
    pub update: u64,
    /// The pairs the last update's broad phase found (0 before the first):
    /// boxes overlapping where the update ends under `Discrete` detection,
    /// swept boxes overlapping along the update under `Swept`.
    pub pairs: u64,
    /// Shatters since the previous row.
    pub shatters: u64,
    /// Shatters refused (size floor, body budget, ids, a fragment made in
    /// the same update) since the previous row.
    pub refused_shatters: u64,
    /// Bodies, mass, kinetic energy and momentum now.
    pub totals: Totals,
    /// Bodies absorbed (re-entries) since the previous row.
    pub reentries: u64,
    /// Mass absorbed since the start: with `mass`, what the physics keeps.
    pub absorbed_mass: f64,
    /// Contacts left for the next update since the previous row: swept
    /// detection acts on a bounded number of contacts an update
    /// (`MAX_CONTACTS_PER_BODY`, `systems/response/time_order.rs`).
    pub deferred: u64,
    /// The state's hash now (the last column, after those that came
    /// before it).
    pub state_hash: StateHash,
}

// The columns (the header, a stable contract) and cells of a row.
crate::csv_row!(TimelineRow, |r| {
    update: r.update,
    bodies: r.totals.bodies,
    pairs: r.pairs,
    shatters: r.shatters,
    refused_shatters: r.refused_shatters,
    mass: r.totals.mass,
    kinetic_energy: r.totals.kinetic_energy,
    momentum_x: r.totals.momentum.x,
    momentum_y: r.totals.momentum.y,
    momentum_z: r.totals.momentum.z,
    reentries: r.reentries,
    absorbed_mass: r.absorbed_mass,
    deferred: r.deferred,
    state_hash: r.state_hash,
});

/// Rows taken every `every` updates, and after the last.
#[derive(Clone, Debug)]
pub struct Timeline {
    every: u64,
    rows: Vec<TimelineRow>,
    /// Shatters, refusals, re-entries and deferred contacts since the
    /// start at the last row.
    counted: (u64, u64, u64, u64),
}

impl Timeline {
    /// A timeline with a row every `every` updates (at least 1).
    pub fn new(every: u64) -> Self {
        Self {
            every: every.max(1),
            rows: Vec::new(),
            counted: (0, 0, 0, 0),
        }
    }

    /// Updates between rows.
    pub fn every(&self) -> u64 {
        self.every
    }

    /// The rows so far.
    pub fn rows(&self) -> &[TimelineRow] {
        &self.rows
    }

    /// Adds the row of `sim` after `update` updates.
    pub fn record(&mut self, sim: &mut Simulation, update: u64) {
        let stats = sim.collision_stats();
        let pairs = if update == 0 { 0 } else { stats.pairs as u64 };
        let (shatters, refused, reentries, deferred) = self.counted;
        self.rows.push(TimelineRow {
            update,
            pairs,
            shatters: stats.shatters_total - shatters,
            refused_shatters: stats.refused_total - refused,
            totals: sim.totals(),
            reentries: stats.reentries_total - reentries,
            absorbed_mass: sim.absorbed().mass,
            deferred: stats.deferred_total - deferred,
            state_hash: sim.state_hash(),
        });
        self.counted = (
            stats.shatters_total,
            stats.refused_total,
            stats.reentries_total,
            stats.deferred_total,
        );
    }

    /// Runs `updates` updates of `sim`, a row before the first (see
    /// [`row_updates`]), every
    /// [`Self::every`] updates and after the last; `progress` hears the
    /// updates done after each row.
    pub fn run(&mut self, sim: &mut Simulation, updates: u64, mut progress: impl FnMut(u64)) {
        self.record(sim, 0);
        let mut done = 0;
        while done < updates && sim.fault().is_none() {
            let n = self.every.min(updates - done);
            sim.step(n);
            done += n;
            self.record(sim, done);
            progress(done);
        }
    }

    /// Writes the header and the rows, floats in Rust's shortest
    /// round-trip form.
    pub fn write_csv(&self, out: impl Write) -> io::Result<()> {
        crate::output::write_csv(out, &self.rows)
    }
}
