//! The response stage: bounce, push-back, separate, or mark for
//! shattering (docs/design.md, "Response").
//!
//! With swept detection every contact of the update is taken in time
//! order, chains included (`time_order.rs`). With discrete detection pairs
//! are taken in sorted order and each interacting body takes part in at
//! most one response per update (a greedy matching); the rest wait for the
//! next update while they still overlap; the matched pairs are disjoint,
//! so their responses are computed in parallel with the same result.
//! Non-interacting bodies are never changed by a response, so they may
//! meet any number of bodies at once.

mod contact;
mod escaped;
mod matching;
mod outcomes;
mod swept;
mod time_order;

use bevy::ecs::system::SystemParam;
use bevy::math::DVec3;
use bevy::platform::collections::HashSet;
use bevy::prelude::*;

pub use contact::{ContactBody, Outcome, respond};

use crate::components::{Absorbs, BodyId, BodyState};
use crate::execution::StageExecution;
use crate::physics::Aabb;
use crate::resources::{CollisionDetection, MemoryBudget, NextBodyId, SimulationSettings};
use crate::systems::shatter::{PendingShatters, ShatterQueue};
use crate::systems::sort::SortedBoxes;
use crate::systems::sweep::{OverlappingPairs, Pair};
use crate::systems::{SimulationSystems, SimulationUpdate, StageClocks};
use matching::{ContactQuery, find_reentries, match_pairs};
use outcomes::{ShatterBudget, apply_outcomes, shatter_or_refuse, write_motion};
use time_order::{Neighbourhood, Resolved, Rules, resolve_in_time_order};

/// Counts of what collisions did, for summaries and the HUD.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CollisionStats {
    /// The pairs the broad phase found this update: boxes overlapping
    /// where the update ends (`Discrete`), swept boxes overlapping along
    /// the update (`Swept`).
    pub pairs: usize,
    /// Pairs responded to this update (bounces and separations).
    pub responses: usize,
    /// Pairs that shattered this update.
    pub shatters: usize,
    /// Pairs that shattered since the start.
    pub shatters_total: u64,
    /// Contacts left for the next update because the update's contacts
    /// reached `MAX_CONTACTS_PER_BODY` (`response/time_order.rs`; swept detection).
    pub deferred: usize,
    /// Contacts deferred since the start.
    pub deferred_total: u64,
    /// Pairs that met fast enough to shatter this update but bounced: their
    /// fragments would have been below `min_fragment_size`, there would
    /// have been more than `max_bodies` bodies, a fragment's id would
    /// have passed [`MAX_ID`](crate::resources::MAX_ID), or (swept
    /// detection) one of the two was a fragment made in this update.
    pub refused_shatters: usize,
    /// Refused shatters since the start.
    pub refused_total: u64,
    /// Bodies absorbed this update (re-entries: see [`Absorbs`]).
    pub reentries: usize,
    /// Bodies absorbed since the start.
    pub reentries_total: u64,
}

/// What absorbing bodies took since the start: the mass and momentum of
/// every body they absorbed, so that the bodies' totals and these still
/// add up to what the shatters and bounces keep (summed in f64 in the
/// order the bodies were absorbed).
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq)]
pub struct Absorbed {
    /// Mass absorbed.
    pub mass: f64,
    /// Momentum absorbed, `Σ m·v` at the touch.
    pub momentum: DVec3,
}

/// Fewest matched pairs a chunk of the outcomes' parallel step holds: an
/// outcome is a fraction of a microsecond's work and a parallel step costs
/// about one (docs/benchmarks.md, "The bare cost of one parallel step"),
/// so the thesis scene's few pairs an update at 10 000 bodies stay on one
/// thread, where cut in two they had made the stage take twice as long.
const PAIRS_PER_CHUNK: usize = 32;

/// Responds to [`OverlappingPairs`] in [`SimulationSystems::Response`].
pub struct ResponsePlugin;

impl Plugin for ResponsePlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<CollisionStats>()
            .init_resource::<Absorbed>()
            .init_resource::<MemoryBudget>()
            .add_systems(SimulationUpdate, respond_to_pairs.in_set(SimulationSystems::Response));
    }
}

/// What the response reads besides the bodies: the pairs the broad phase
/// found, its boxes and each box's body (for what a new path reaches),
/// whether any absorber is there, and the next fresh id (which bounds the
/// shatters).
#[derive(SystemParam)]
struct Found<'w, 's> {
    pairs: Res<'w, OverlappingPairs>,
    sorted: Res<'w, SortedBoxes>,
    owners: Query<'w, 's, (Entity, &'static BodyId)>,
    absorbers: Query<'w, 's, (), With<Absorbs>>,
    next_id: Res<'w, NextBodyId>,
    memory: Res<'w, MemoryBudget>,
}

/// The bodies as the swept contacts look them up: their states, and the
/// broad phase's boxes by the index of their body in table order.
struct Lookup<'a, 'w, 's> {
    bodies: &'a ContactQuery<'w, 's>,
    sorted: &'a SortedBoxes,
    /// Each table's entities, in the order the broad phase read them.
    tables: Vec<&'a [Entity]>,
}

impl Neighbourhood for Lookup<'_, '_, '_> {
    fn state(&self, entity: Entity) -> Option<BodyState> {
        self.bodies.get(entity).ok().map(BodyState::from_components)
    }

    fn cells(&self, region: &Aabb, f: &mut dyn FnMut(u32)) {
        if let Some(grid) = self.sorted.grid() {
            grid.for_each_cell(region, f);
        }
    }

    fn cells_per_unit(&self) -> f32 {
        self.sorted.grid().map_or(0.0, |grid| grid.cells_per_unit())
    }

    fn reached(&self, region: &Aabb, out: &mut Vec<Entity>) {
        self.sorted.overlapping(region, |index| {
            let mut index = index as usize;
            for table in &self.tables {
                if index < table.len() {
                    out.push(table[index]);
                    return;
                }
                index -= table.len();
            }
        });
    }
}

/// What the response records: the mass the absorbers took and the
/// update's collision statistics.
#[derive(SystemParam)]
struct Records<'w> {
    absorbed: ResMut<'w, Absorbed>,
    stats: ResMut<'w, CollisionStats>,
}

/// Discrete detection's response: the absorbers' partners first (where
/// `absorbers` are), then the greedy matching in pair order, each matched
/// pair's outcome (in parallel as `stage` splits them), the shatter
/// `budget` in pair order (less the bodies absorbed), and every outcome
/// written back.
fn respond_discrete(
    pairs: &[Pair],
    (bodies, busy): (&mut ContactQuery, &mut HashSet<Entity>),
    absorbers: bool,
    (settings, threshold, mut budget): (&SimulationSettings, f32, ShatterBudget<'_>),
    stage: StageExecution<'_>,
) -> Resolved {
    let dt = settings.time_step;
    // Without an absorber (the thesis scene), no pass over the pairs for one.
    let reentries = if absorbers {
        find_reentries(pairs, bodies, busy)
    } else {
        Vec::new()
    };
    let matched = match_pairs(pairs, bodies, busy);
    let outcome = |index: usize, threshold: f32| {
        let (_, [a, b]) = &matched[index];
        respond(&a.into(), &b.into(), threshold, dt)
    };
    let mut outcomes: Vec<Outcome> = stage
        .map_chunks_of_at_least(0..matched.len(), PAIRS_PER_CHUNK, |range| {
            range.map(|index| outcome(index, threshold)).collect::<Vec<_>>()
        })
        .concat();
    for _ in &reentries {
        budget.absorbed();
    }
    let mut shatters = PendingShatters::default();
    let refused = shatter_or_refuse(&matched, &mut outcomes, budget, &mut shatters, |index| {
        outcome(index, f32::INFINITY)
    });
    let responses = apply_outcomes(&matched, outcomes, bodies, &mut shatters);
    Resolved {
        reentries: reentries
            .into_iter()
            .map(|(entity, body)| (Some(entity), body))
            .collect(),
        responses,
        refused,
        shatters,
        ..Resolved::default()
    }
}

fn respond_to_pairs(
    settings: Res<SimulationSettings>,
    mut clocks: StageClocks,
    found: Found,
    queue: ShatterQueue,
    records: Records,
    mut busy: Local<HashSet<Entity>>,
    mut bodies: ContactQuery,
) {
    let clock = clocks.start(SimulationSystems::Response);
    let Found {
        pairs,
        sorted,
        owners,
        absorbers,
        next_id,
        memory,
    } = found;
    let ShatterQueue {
        mut pending,
        mut reentering,
    } = queue;
    let Records {
        mut absorbed,
        mut stats,
    } = records;
    pending.clear();
    reentering.0.clear();
    if !(settings.stages.collisions && settings.stages.collision_response) {
        *stats = CollisionStats {
            shatters_total: stats.shatters_total,
            deferred_total: stats.deferred_total,
            refused_total: stats.refused_total,
            reentries_total: stats.reentries_total,
            ..CollisionStats::default()
        };
        return;
    }
    busy.clear();
    let dt = settings.time_step;
    let body_count = bodies.iter().len();
    // Fewer than two fragments cannot keep volume: then nothing shatters.
    let threshold = if settings.shatter_fragments >= 2 {
        settings.shatter_threshold
    } else {
        f32::INFINITY
    };
    let memory = memory.limit.map(|limit| limit.bodies());
    let budget = ShatterBudget::new(&settings, body_count, *next_id, memory);
    let mut resolved = if settings.collision_detection == CollisionDetection::Swept {
        let lookup = Lookup {
            bodies: &bodies,
            sorted: &sorted,
            tables: owners
                .contiguous_iter()
                .expect("body components are table-stored")
                .map(|(entities, _)| entities)
                .collect(),
        };
        let rules = Rules { threshold, dt, budget };
        let resolved = resolve_in_time_order(&pairs.0, &lookup, clock.execution(body_count), rules);
        for &(entity, motion) in &resolved.motions {
            write_motion(&mut bodies, entity, motion);
        }
        resolved
    } else {
        respond_discrete(
            &pairs.0,
            (&mut bodies, &mut busy),
            !absorbers.is_empty(),
            (&settings, threshold, budget),
            clock.execution(body_count),
        )
    };
    for (entity, body) in &resolved.reentries {
        let mass = f64::from(body.mass);
        absorbed.mass += mass;
        absorbed.momentum += body.velocity.as_dvec3() * mass;
        // A fragment made this update was never added.
        reentering.0.extend(entity);
    }
    *pending = std::mem::take(&mut resolved.shatters);
    let refused = resolved.refused;
    *stats = CollisionStats {
        pairs: pairs.0.len(),
        responses: resolved.responses,
        deferred: resolved.deferred,
        deferred_total: stats.deferred_total + resolved.deferred as u64,
        shatters: pending.pairs,
        shatters_total: stats.shatters_total + pending.pairs as u64,
        refused_shatters: refused,
        refused_total: stats.refused_total + refused as u64,
        reentries: resolved.reentries.len(),
        reentries_total: stats.reentries_total + resolved.reentries.len() as u64,
    };
    clock.finish();
}
