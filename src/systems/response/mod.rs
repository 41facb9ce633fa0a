//! The response stage: bounce, push-back, separate, or mark for
//! shattering (docs/design.md, "Response").
//!
//! Pairs are taken in sorted order (with swept detection, in the order of
//! their first touch) and each interacting body takes part in at most one
//! response per update (a greedy matching); the rest wait for the next
//! update while they still overlap. Non-interacting bodies are never
//! changed by a response, so they may meet any number of bodies at once.
//! The matched pairs are disjoint, so their responses are computed in
//! parallel with the same result.

mod contact;
mod matching;
mod outcomes;
mod swept;

use bevy::ecs::system::SystemParam;
use bevy::math::DVec3;
use bevy::platform::collections::HashSet;
use bevy::prelude::*;

pub use contact::{ContactBody, Outcome, respond};
pub use outcomes::refuse_shatters;
pub use swept::respond_swept;

use crate::components::Absorbs;
use crate::resources::{CollisionDetection, NextBodyId, SimulationSettings};
use crate::systems::shatter::ShatterQueue;
use crate::systems::sweep::OverlappingPairs;
use crate::systems::{SimulationSystems, SimulationUpdate, Stage};
use matching::{ContactQuery, find_reentries, match_pairs, swept_matching};
use outcomes::apply_outcomes;

/// Counts of what collisions did, for summaries and the HUD.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CollisionStats {
    /// Overlapping pairs found this update.
    pub pairs: usize,
    /// Pairs responded to this update (bounces and separations).
    pub responses: usize,
    /// Pairs that shattered this update.
    pub shatters: usize,
    /// Pairs that shattered since the start.
    pub shatters_total: u64,
    /// Pairs that met fast enough to shatter this update but bounced: their
    /// fragments would have been below `min_fragment_size`, there would
    /// have been more than `max_bodies` bodies, or a fragment's id would
    /// have passed [`MAX_ID`](crate::resources::MAX_ID).
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
            .add_systems(SimulationUpdate, respond_to_pairs.in_set(SimulationSystems::Response));
    }
}

/// What the response reads besides the bodies: the pairs the broad phase
/// found, whether any absorber is there, and the next fresh id (which
/// bounds the shatters).
#[derive(SystemParam)]
struct Found<'w, 's> {
    pairs: Res<'w, OverlappingPairs>,
    absorbers: Query<'w, 's, (), With<Absorbs>>,
    next_id: Res<'w, NextBodyId>,
}

/// What the response records: the mass the absorbers took and the
/// update's collision statistics.
#[derive(SystemParam)]
struct Records<'w> {
    absorbed: ResMut<'w, Absorbed>,
    stats: ResMut<'w, CollisionStats>,
}

fn respond_to_pairs(
    settings: Res<SimulationSettings>,
    mut stage: Stage,
    found: Found,
    queue: ShatterQueue,
    records: Records,
    mut busy: Local<HashSet<Entity>>,
    mut bodies: ContactQuery,
) {
    let clock = stage.start(SimulationSystems::Response);
    let Found {
        pairs,
        absorbers,
        next_id,
    } = found;
    let ShatterQueue {
        mut pending,
        mut reentering,
    } = queue;
    let Records {
        mut absorbed,
        mut stats,
    } = records;
    pending.0.clear();
    reentering.0.clear();
    if !(settings.stages.collisions && settings.stages.collision_response) {
        *stats = CollisionStats {
            shatters_total: stats.shatters_total,
            refused_total: stats.refused_total,
            reentries_total: stats.reentries_total,
            ..CollisionStats::default()
        };
        return;
    }
    busy.clear();
    let dt = settings.time_step;
    let body_count = bodies.iter().len();
    let (reentries, matched, meetings) = if settings.collision_detection == CollisionDetection::Swept {
        swept_matching(&pairs.0, &bodies, &mut busy, clock.execution(body_count))
    } else {
        // Without an absorber (the thesis scene), no pass over the pairs for one.
        let reentries = if absorbers.is_empty() {
            Vec::new()
        } else {
            find_reentries(&pairs.0, &bodies, &mut busy)
        };
        let matched = match_pairs(&pairs.0, &bodies, &mut busy);
        (reentries, matched, Vec::new())
    };
    for (entity, body) in &reentries {
        let mass = f64::from(body.mass);
        absorbed.mass += mass;
        absorbed.momentum += body.velocity.as_dvec3() * mass;
        reentering.0.push(*entity);
    }
    // Fewer than two fragments cannot keep volume: then nothing shatters.
    let threshold = if settings.shatter_fragments >= 2 {
        settings.shatter_threshold
    } else {
        f32::INFINITY
    };
    let body_count = body_count - reentries.len();
    // One pair's outcome: by its meeting with swept detection, else by today's rule.
    let outcome = |index: usize, threshold: f32| {
        let (_, [a, b]) = &matched[index];
        let (a, b): (ContactBody, ContactBody) = (a.into(), b.into());
        match meetings.get(index) {
            Some(&meeting) => respond_swept(&a, &b, meeting, threshold, dt),
            None => respond(&a, &b, threshold, dt),
        }
    };
    let mut outcomes: Vec<Outcome> = clock
        .execution(body_count)
        .map_chunks_of_at_least(0..matched.len(), PAIRS_PER_CHUNK, |range| {
            range.map(|index| outcome(index, threshold)).collect::<Vec<_>>()
        })
        .concat();
    let refused = refuse_shatters(&matched, &mut outcomes, &settings, body_count, *next_id, |index| {
        outcome(index, f32::INFINITY)
    });
    let responses = apply_outcomes(&matched, (outcomes, &meetings, dt), &mut bodies, &mut pending);
    *stats = CollisionStats {
        pairs: pairs.0.len(),
        responses,
        shatters: pending.0.len(),
        shatters_total: stats.shatters_total + pending.0.len() as u64,
        refused_shatters: refused,
        refused_total: stats.refused_total + refused as u64,
        reentries: reentries.len(),
        reentries_total: stats.reentries_total + reentries.len() as u64,
    };
    clock.finish();
}
