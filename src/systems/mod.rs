//! The simulation stages, one plugin per stage; the stage list and the
//! schedule that orders them. Every stage is a module named after it
//! (`gravity`, `integrate`, `sort`, `sweep`, `response`, `shatter`) that
//! holds its plugin and its system — in `<stage>/stage.rs` where the stage
//! is a folder with its kernels beside it, else in `<stage>.rs`; the sort
//! and sweep kernels are the broad phase's (`broad_phase/`). Each stage
//! system takes a [`Stage`] and names itself once, in [`Stage::start`].

mod broad_phase;
mod fault;
mod gravity;
mod integrate;
mod plugins;
mod response;
mod schedule;
mod shatter;
mod sort;
mod stage_clock;
mod stages;
mod sweep;
mod timings;
mod totals;

pub use broad_phase::{
    Aabb, BodyColumns, BoxSource, BroadPhaseQuery, MIN_PAIR_LIMIT, PAIRS_PER_BOX, SortedBoxes, TableColumns,
    TooManyPairs, id_pairs, pair_limit, sort_boxes, sweep_and_prune, sweep_sorted, swept_box,
};
pub use fault::{Fault, SimulationFault, first_non_finite, no_fault};
pub use gravity::{
    GROUP_SIZE, GravityColumns, GravityInUse, GravityPlugin, GravitySource, Kernel, LEAF_SIZE, Octree, Pull,
    PullScratch, REGION_SIZE, SourceColumns, acceleration_at, add_pulls, collect_sources, gravity_kernel, half_drift,
    prepare_pull, pull_factor,
};
pub use integrate::{Drift, IntegrateColumns, IntegratePlugin, integrate_kernel};
pub use plugins::SimulationPlugins;
pub use response::{
    Absorbed, CollisionStats, ContactBody, Matched, Meeting, Motion, Outcome, ResponsePlugin, apart_axes,
    collision_axes, contact_states, elastic, first_contact, refuse_shatters, respond, respond_swept, respond_to_ball,
};
pub use schedule::{BetweenUpdates, NextEventAt, SchedulePlugin, SimulationUpdate, run_due_events, run_updates};
pub use shatter::{
    PendingShatters, Reentering, ShatterPair, ShatterPlugin, box_volume, breakup_fragments, fragment_half_extent,
    fragments, fragments_for, move_on, power_law_fragments, power_law_halves, smallest_fragment_edge,
};
pub use sort::SortPlugin;
pub use stage_clock::{Stage, StageClock};
pub use stages::{STAGE_COUNT, STAGES, SimulationSystems, StageInfo};
pub use sweep::{OverlappingPairs, Pair, SweepPlugin};
pub use timings::{StageTimings, Timing};
pub use totals::Totals;
