//! The running scene: which scenario is loaded, and building the bodies from
//! it (at start and on restart) with the sandbox's settings.

use std::path::PathBuf;

use bevy::prelude::*;

use super::sandbox_settings::SandboxSettings;
use crate::components::{BodyId, BodyState};
use crate::input::InputError;
use crate::resources::{NextBodyId, SimulationSettings};
use crate::scenario::{CannotResize, Scenario};
use crate::simulation::spawn_bodies;
use crate::systems::{Absorbed, CollisionStats, GravityInUse, OverlappingPairs, SimulationFault, StageTimings};
use crate::timed_events::install_events;
use crate::ui::sets::SandboxSystems;

/// State of the sandbox beyond its settings.
#[derive(Resource, Debug)]
pub struct SandboxState {
    /// The loaded scenario, as read from its file.
    pub scenario: Scenario,
    /// Bodies with an id from here on were born in a shatter.
    pub first_fragment_id: u64,
    /// Simulation halted (rendering goes on).
    pub paused: bool,
    /// Run exactly one update next frame (while paused).
    pub step_requested: bool,
    /// Rebuild the scene from the scenario and the settings next frame.
    pub restart_requested: bool,
    /// The settings the scene was last built with, to tell which pending
    /// changes need a restart.
    pub built_with: SandboxSettings,
    /// Last problem (a scenario that would not load), shown in the panel.
    pub error: Option<String>,
    /// Why the last tool action did nothing (no selection, its event
    /// skipped), shown under the tools; `None` after one that worked.
    pub tool_problem: Option<String>,
    /// Counts scene builds (so views know the bodies were replaced).
    pub generation: u64,
    /// Counts tool actions and rewinds: the bodies changed between updates
    /// (so the drawing does not wait for the next update to show it).
    pub edits: u64,
    /// The scenario the running scene was built from, with the settings
    /// and body count it was built with (what *Save session…* writes, with
    /// the events).
    pub started_from: Scenario,
    /// File of the loaded scenario (`None`: built-in).
    pub loaded_path: Option<PathBuf>,
}

impl SandboxState {
    /// The state before the first build of `scenario` with `settings`
    /// (which the first frame does).
    pub fn new(scenario: Scenario, settings: &SandboxSettings) -> Self {
        Self {
            started_from: scenario.clone(),
            scenario,
            first_fragment_id: 0,
            paused: false,
            step_requested: false,
            restart_requested: true,
            built_with: settings.clone(),
            error: None,
            tool_problem: None,
            generation: 0,
            edits: 0,
            loaded_path: settings.scenario.clone(),
        }
    }

    /// Names of the changed settings that only take effect on restart.
    pub fn pending_restart(&self, settings: &SandboxSettings) -> Vec<&'static str> {
        let built = &self.built_with;
        let mut pending = Vec::new();
        if settings.body_count != built.body_count {
            pending.push("body count");
        }
        pending.extend(settings.restart_physics_changed(built));
        if settings.scenario != built.scenario {
            pending.push("scenario");
        }
        pending
    }
}

/// Builds the scene at start and whenever a restart is asked for.
pub struct ScenePlugin;

impl Plugin for ScenePlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(Update, restart_scene.in_set(SandboxSystems::BuildScene));
    }
}

/// Why the scene could not be built.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The scenario is unusable.
    #[error(transparent)]
    Scenario(#[from] InputError),
    /// A body count was chosen for a scenario that cannot take it (no
    /// generators, or ids past their bound).
    #[error(transparent)]
    Resize(#[from] CannotResize),
}

/// The bodies a restart builds: the scenario with the chosen seed and body
/// count, and the physics it runs with.
pub fn build_bodies(
    scenario: &Scenario,
    settings: &SandboxSettings,
) -> Result<(Vec<BodyState>, SimulationSettings), SceneError> {
    let scenario = built_scenario(scenario, settings)?;
    Ok((scenario.bodies()?, scenario.settings()))
}

/// `scenario` as a restart builds it: with the panel's physics settings
/// and the chosen body count.
fn built_scenario(scenario: &Scenario, settings: &SandboxSettings) -> Result<Scenario, SceneError> {
    let mut scenario = scenario.clone();
    scenario.physics = settings.physics_for_restart();
    if let Some(count) = settings.body_count {
        scenario = scenario.with_generated(count)?;
    }
    Ok(scenario)
}

/// Reads a newly picked scenario into the state and takes its own seed and
/// shatter values into the settings.
fn load_picked_scenario(world: &mut World, settings: &mut SandboxSettings) -> Result<(), InputError> {
    let scenario = Scenario::load_or_default(settings.scenario.as_deref())?;
    settings.adopt_scenario(&scenario.settings());
    world.insert_resource(settings.clone());
    let mut state = world.resource_mut::<SandboxState>();
    state.scenario = scenario;
    state.loaded_path = settings.scenario.clone();
    Ok(())
}

/// Rebuilds the scene when a restart is requested: all bodies despawned,
/// the scenario's bodies spawned with the current settings. On an error the
/// running scene stays and the panel shows the error.
pub fn restart_scene(world: &mut World) {
    if !std::mem::take(&mut world.resource_mut::<SandboxState>().restart_requested) {
        return;
    }
    let mut settings = world.resource::<SandboxSettings>().clone();
    let picked = settings.scenario != world.resource::<SandboxState>().loaded_path;
    let loaded = if picked {
        load_picked_scenario(world, &mut settings).map_err(SceneError::from)
    } else {
        Ok(())
    };
    let built = loaded.and_then(|()| {
        let scenario = built_scenario(&world.resource::<SandboxState>().scenario, &settings)?;
        let bodies = scenario.bodies()?;
        Ok((scenario, bodies))
    });
    let (scenario, bodies) = match built {
        Ok(built) => built,
        Err(e) => {
            warn!("{e}");
            world.resource_mut::<SandboxState>().error = Some(e.to_string());
            return;
        }
    };
    let old: Vec<Entity> = world.query_filtered::<Entity, With<BodyId>>().iter(world).collect();
    for entity in old {
        world.despawn(entity);
    }
    // Fresh ids continue from the built scenario's next id (a snapshot's
    // `next_id`), as headless runs of it — a saved session's replay — do.
    let next = spawn_bodies(world, &bodies).max(scenario.next_id());
    world.insert_resource(NextBodyId(next));
    world.insert_resource(scenario.settings());
    install_events(world, &scenario);
    *world.resource_mut::<CollisionStats>() = CollisionStats::default();
    *world.resource_mut::<Absorbed>() = Absorbed::default();
    *world.resource_mut::<GravityInUse>() = GravityInUse::default();
    world.resource_mut::<SimulationFault>().clear();
    // The events of update 0 belong to the start: a session saved before
    // the first update replays with `--steps 0` to this state. A start
    // they leave that cannot run is said (the first update stops it).
    let start = crate::timed_events::run_start_events(world);
    world.resource_mut::<OverlappingPairs>().0.clear();
    world.resource_mut::<StageTimings>().reset();
    let mut state = world.resource_mut::<SandboxState>();
    state.error = start.err().map(|e| {
        warn!("{e}");
        e
    });
    state.built_with = settings;
    state.first_fragment_id = next;
    state.generation += 1;
    state.started_from = scenario;
    info!("scene built: {} bodies", bodies.len());
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn restart_builds_the_chosen_body_count_and_seed() {
        let scenario = Scenario::builtin_default();
        let mut settings = SandboxSettings {
            body_count: Some(500),
            ..SandboxSettings::default()
        };
        settings.physics.seed = 7;
        let (bodies, physics) = build_bodies(&scenario, &settings).unwrap();
        assert_eq!(bodies.len(), scenario.bodies.len() + 500);
        assert_eq!(physics.seed, 7);
        let mut other = settings;
        other.physics.seed = 8;
        let (reseeded, _) = build_bodies(&scenario, &other).unwrap();
        assert_ne!(bodies, reseeded, "the seed reaches the generators");
    }

    #[test]
    fn live_switches_reach_the_physics() {
        let scenario = Scenario::builtin_default();
        let mut settings = SandboxSettings {
            body_count: Some(10),
            ..SandboxSettings::default()
        };
        settings.adopt_scenario(&scenario.physics);
        settings.physics.stages.gravity = false;
        settings.physics.stages.collision_response = false;
        settings.physics.shatter_fragments = 9;
        settings.physics.shatter_threshold = 1.5;
        let (_, physics) = build_bodies(&scenario, &settings).unwrap();
        let stages = physics.stages;
        assert!(!stages.gravity && stages.collisions && !stages.collision_response);
        assert_eq!((physics.shatter_fragments, physics.shatter_threshold), (9, 1.5));
        assert_eq!(physics.time_step, scenario.physics.time_step);
    }

    #[test]
    fn a_scenario_without_generators_refuses_a_body_count() {
        let text = "Scenario(bodies: [Body(position: (0.0, 0.0, 0.0))])";
        let scenario = Scenario::parse(text, "one.ron").unwrap();
        let settings = SandboxSettings {
            body_count: Some(10),
            ..SandboxSettings::default()
        };
        let err = build_bodies(&scenario, &settings).unwrap_err().to_string();
        assert!(err.contains("one.ron") && err.contains("generators"), "{err}");
    }

    #[test]
    fn restart_only_settings_are_reported_as_pending() {
        let settings = SandboxSettings::default();
        let state = SandboxState::new(Scenario::builtin_default(), &settings);
        let mut changed = SandboxSettings {
            updates_per_second: 300,
            ..settings
        };
        changed.physics.seed = 42;
        changed.physics.stages.gravity = false;
        assert_eq!(state.pending_restart(&changed), vec!["seed"]);
    }

    /// A world with what [`restart_scene`] touches, no renderer.
    fn sandbox_world(settings: SandboxSettings) -> World {
        let mut app = App::new();
        app.add_plugins((
            MinimalPlugins,
            crate::systems::SimulationPlugins,
            crate::timed_events::EventsPlugin,
        ))
        .insert_resource(crate::execution::Execution::new(settings.execution.mode(), 1).unwrap());
        let state = SandboxState::new(Scenario::builtin_default(), &settings);
        app.insert_resource(settings).insert_resource(state);
        std::mem::take(app.world_mut())
    }

    fn body_count(world: &mut World) -> usize {
        world.query::<&BodyId>().iter(world).len()
    }

    #[test]
    fn restart_replaces_the_bodies_and_switches_scenarios() {
        let settings = SandboxSettings {
            body_count: Some(300),
            ..SandboxSettings::default()
        };
        let mut world = sandbox_world(settings);
        restart_scene(&mut world);
        assert_eq!(body_count(&mut world), 302, "planet, moon and 300 debris");
        // Fresh ids follow the scene as built (300 debris, not the file's
        // 20 000), as a replay of its session numbers them.
        let started = world.resource::<SandboxState>().started_from.next_id();
        assert_eq!((world.resource::<NextBodyId>().0, started), (302, 302));

        // Pick another scenario and restart: the old bodies are gone, the
        // scenario's own seed is taken.
        let two_body = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/two_body.ron"));
        {
            let mut settings = world.resource_mut::<SandboxSettings>();
            settings.scenario = Some(two_body.clone());
            settings.body_count = None;
            settings.physics.seed = 12345;
        }
        world.resource_mut::<SandboxState>().restart_requested = true;
        restart_scene(&mut world);
        let state = world.resource::<SandboxState>();
        assert!(state.error.is_none(), "{:?}", state.error);
        assert_eq!(state.loaded_path.as_deref(), Some(two_body.as_path()));
        assert_eq!(state.generation, 2);
        assert_ne!(world.resource::<SandboxSettings>().physics.seed, 12345);
        assert_eq!(body_count(&mut world), 2);
    }

    #[test]
    fn a_broken_scenario_pick_keeps_the_running_scene() {
        let dir = tempfile::tempdir().unwrap();
        let broken = dir.path().join("broken.ron");
        std::fs::write(&broken, "Scenario(bodies: [Body(mass: -1.0)])").unwrap();
        let settings = SandboxSettings {
            body_count: Some(50),
            ..SandboxSettings::default()
        };
        let mut world = sandbox_world(settings);
        restart_scene(&mut world);
        world.resource_mut::<SandboxSettings>().scenario = Some(broken);
        world.resource_mut::<SandboxState>().restart_requested = true;
        restart_scene(&mut world);
        let error = world.resource::<SandboxState>().error.clone().expect("an error");
        assert!(error.contains("broken.ron") && error.contains("mass"), "{error}");
        assert_eq!(body_count(&mut world), 52, "the running scene stays");
    }
}
