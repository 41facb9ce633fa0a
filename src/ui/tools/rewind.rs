//! Rewind: the window keeps checkpoints of the state (one every
//! [`CHECKPOINT_EVERY`] updates, at most [`CHECKPOINT_BYTES`] in all, the
//! oldest dropped first); ⏪ returns to the previous one and drops the
//! events recorded after it. A checkpoint holds what a snapshot holds —
//! every body, the next id, the physics — and the update count, so running
//! on from it is the run it was taken from, bit for bit.

use std::collections::VecDeque;

use bevy::prelude::*;

use crate::components::{BodyId, BodyState, spawn_states};
use crate::resources::{NextBodyId, SimulationSettings};
use crate::systems::{Absorbed, CollisionStats, NextEventAt, OverlappingPairs, SimulationFault, UpdateCount};
use crate::timed_events::{EventLog, EventQueue};
use crate::ui::session::{SandboxSettings, SandboxState};

/// Updates between two checkpoints: 10 s at the default 60 updates a
/// second.
pub const CHECKPOINT_EVERY: u64 = 600;
/// Most memory the checkpoints hold together: 256 MiB.
pub const CHECKPOINT_BYTES: usize = 256 << 20;

/// One saved state.
#[derive(Clone, Debug)]
struct Checkpoint {
    /// Updates run when it was taken (after that update's scenario events,
    /// before any a tool records then).
    updates: u64,
    bodies: Vec<BodyState>,
    next_id: u64,
    physics: SimulationSettings,
    stats: CollisionStats,
    absorbed: Absorbed,
    log: EventLog,
}

impl Checkpoint {
    /// What it holds in memory, about.
    fn bytes(&self) -> usize {
        self.bodies.len() * size_of::<BodyState>() + size_of::<Self>()
    }
}

/// The checkpoints, oldest first.
#[derive(Resource, Debug, Default)]
pub struct Checkpoints {
    list: VecDeque<Checkpoint>,
    bytes: usize,
    /// The scene generation they belong to.
    generation: u64,
}

impl Checkpoints {
    /// How many there are.
    pub fn len(&self) -> usize {
        self.list.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// The update of the one ⏪ returns to now: the latest before
    /// `updates` (or at it, when it is the only one).
    pub fn target(&self, updates: u64) -> Option<u64> {
        self.index_for(updates).map(|i| self.list[i].updates)
    }

    fn index_for(&self, updates: u64) -> Option<usize> {
        let before = self.list.iter().rposition(|c| c.updates < updates);
        before.or_else(|| (!self.list.is_empty()).then_some(0))
    }

    fn push(&mut self, checkpoint: Checkpoint) {
        self.bytes += checkpoint.bytes();
        self.list.push_back(checkpoint);
        while self.bytes > CHECKPOINT_BYTES && self.list.len() > 1 {
            let oldest = self.list.pop_front().expect("more than one");
            self.bytes -= oldest.bytes();
        }
    }
}

/// Takes a checkpoint at the start of a scene and every
/// [`CHECKPOINT_EVERY`] updates (at the start of a frame, before its tool
/// actions and updates).
pub fn take_checkpoints(world: &mut World) {
    let generation = world.resource::<SandboxState>().generation;
    let updates = world.resource::<UpdateCount>().0;
    let checkpoints = world.resource::<Checkpoints>();
    let stale = checkpoints.generation != generation;
    let due = checkpoints
        .list
        .back()
        .is_none_or(|c| updates >= c.updates + CHECKPOINT_EVERY);
    if !stale && !due {
        return;
    }
    let bodies = BodyState::all_in(world);
    let checkpoint = Checkpoint {
        updates,
        bodies,
        next_id: world.resource::<NextBodyId>().0,
        physics: world.resource::<SimulationSettings>().clone(),
        stats: *world.resource::<CollisionStats>(),
        absorbed: *world.resource::<Absorbed>(),
        log: world.resource::<EventLog>().clone(),
    };
    let mut checkpoints = world.resource_mut::<Checkpoints>();
    if stale {
        *checkpoints = Checkpoints {
            generation,
            ..Checkpoints::default()
        };
    }
    checkpoints.push(checkpoint);
}

/// Returns to the latest checkpoint before the update the run is at (the
/// first one, at the scene's start, if there is none before), dropping the
/// events recorded since, and the checkpoints after it.
pub fn rewind(world: &mut World) -> Result<(), String> {
    let updates = world.resource::<UpdateCount>().0;
    let mut checkpoints = world.resource_mut::<Checkpoints>();
    let index = checkpoints.index_for(updates).ok_or("rewind: no checkpoint yet")?;
    while checkpoints.list.len() > index + 1 {
        let dropped = checkpoints.list.pop_back().expect("more than index");
        checkpoints.bytes -= dropped.bytes();
    }
    let checkpoint = checkpoints.list[index].clone();
    let old: Vec<Entity> = world.query_filtered::<Entity, With<BodyId>>().iter(world).collect();
    for entity in old {
        world.despawn(entity);
    }
    spawn_states(world, &checkpoint.bodies);
    world.insert_resource(NextBodyId(checkpoint.next_id));
    world.insert_resource(checkpoint.physics.clone());
    world.insert_resource(checkpoint.stats);
    world.insert_resource(checkpoint.absorbed);
    world.insert_resource(checkpoint.log);
    world.resource_mut::<OverlappingPairs>().0.clear();
    world.resource_mut::<SimulationFault>().clear();
    world.insert_resource(UpdateCount(checkpoint.updates));
    let mut queue = world.resource_mut::<EventQueue>();
    queue.rewind(checkpoint.updates);
    let next = queue.next_at();
    world.insert_resource::<NextEventAt>(next);
    // The panel shows the physics the run is back at.
    world.resource_mut::<SandboxSettings>().adopt_live(&checkpoint.physics);
    let mut state = world.resource_mut::<SandboxState>();
    state.edits += 1;
    // A run that stopped at a fault runs again from the checkpoint.
    state.error = None;
    info!("rewound to update {}", checkpoint.updates);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::execution::{Execution, ExecutionMode};
    use crate::scenario::{Event, Remove, Scenario};
    use crate::simulation::spawn_bodies;
    use crate::systems::{SimulationPlugins, run_updates};
    use crate::timed_events::{EventsPlugin, install_events, record_event};

    /// A window's world without the window: the simulation, the events,
    /// what the rewind touches; `scenario` built.
    fn world(scenario: &Scenario) -> World {
        let mut app = App::new();
        app.add_plugins((MinimalPlugins, SimulationPlugins, EventsPlugin))
            .insert_resource(Execution::new(ExecutionMode::Sequential, 1).unwrap())
            .insert_resource(scenario.settings())
            .insert_resource(SandboxSettings::default())
            .insert_resource(SandboxState::new(scenario.clone(), &SandboxSettings::default()))
            .init_resource::<Checkpoints>();
        let world = app.world_mut();
        spawn_bodies(world, &scenario.bodies().unwrap());
        world.insert_resource(NextBodyId(scenario.next_id()));
        install_events(world, scenario);
        std::mem::take(world)
    }

    /// Runs `updates` one at a time, taking checkpoints as the window does.
    fn run(world: &mut World, updates: u64) {
        for _ in 0..updates {
            run_updates(world, 1);
            take_checkpoints(world);
        }
    }

    fn state(world: &mut World) -> Vec<BodyState> {
        BodyState::all_in(world)
    }

    /// Rewound to a checkpoint and run on, the run is the straight run (with
    /// the scenario's events after the checkpoint happening again, and the
    /// events recorded after it gone).
    #[test]
    fn rewind_then_run_on_equals_a_straight_run() {
        let text = "Scenario(seed: 3, bodies: [
                Body(position: (0, 0, 0), shape: Sphere(radius: 100), mass: 4000, role: Source, interacts: false),
            ], generators: [Shell(count: 400, around: 0, inner_radius: 200, outer_radius: 260, inclination: 60,
                                  retrograde_fraction: 0.3)],
            events: [Breakup(update: 700, body: 9, fragments: 30, speed: 2),
                     Set(update: 900, shatter_threshold: 1.0)])";
        let scenario = Scenario::parse(text, "rewind.ron").unwrap();
        let mut straight = world(&scenario);
        run(&mut straight, 1300);
        let mut rewound = world(&scenario);
        take_checkpoints(&mut rewound);
        run(&mut rewound, 1000);
        // A recorded event after the checkpoint at 600, then back to it.
        record_event(&mut rewound, Event::Remove(Remove { update: 1000, body: 20 }));
        assert_eq!(rewound.resource::<Checkpoints>().target(1000), Some(600));
        rewind(&mut rewound).unwrap();
        assert_eq!(rewound.resource::<UpdateCount>().0, 600);
        assert_eq!(rewound.resource::<SimulationSettings>().shatter_threshold, 3.0);
        run(&mut rewound, 700);
        let straight_state = state(&mut straight);
        assert!(straight_state.len() > 400, "the breakup happened");
        assert_eq!(state(&mut rewound), straight_state);
        assert_eq!(rewound.resource::<NextBodyId>(), straight.resource::<NextBodyId>());
        assert_eq!(rewound.resource::<EventLog>(), straight.resource::<EventLog>());
    }

    #[test]
    fn the_oldest_checkpoints_go_first_past_the_memory_bound() {
        let mut checkpoints = Checkpoints::default();
        let body = BodyState::new_box(
            BodyId(0),
            Vec3::ZERO,
            Vec3::ZERO,
            1.0,
            Vec3::ONE,
            crate::components::GravityRole::Adopter,
            true,
        );
        let per = CHECKPOINT_BYTES / 3 / size_of::<BodyState>();
        for updates in [0, 600, 1200, 1800] {
            checkpoints.push(Checkpoint {
                updates,
                bodies: vec![body; per],
                next_id: 1,
                physics: SimulationSettings::default(),
                stats: CollisionStats::default(),
                absorbed: Absorbed::default(),
                log: EventLog::default(),
            });
        }
        assert!(checkpoints.bytes <= CHECKPOINT_BYTES);
        assert_eq!(
            checkpoints.list.iter().map(|c| c.updates).collect::<Vec<_>>(),
            [1200, 1800]
        );
        assert_eq!(checkpoints.target(1800), Some(1200));
        assert_eq!(checkpoints.target(1801), Some(1800));
    }
}
