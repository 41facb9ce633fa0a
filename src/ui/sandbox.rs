//! The running scene: which scenario is loaded, building the bodies from it
//! (at start and on restart), and the planet and moons drawn as spheres.

use std::path::{Path, PathBuf};

use bevy::prelude::*;

use crate::components::{BodyId, BodyState, GravityRole, HalfExtents, Interacts, Position};
use crate::resources::{SimulationSettings, StageTimings};
use crate::scenario::{DEFAULT_SCENARIO, DEFAULT_SCENARIO_NAME, Scenario};
use crate::simulation::spawn_bodies;
use crate::systems::{CollisionStats, OverlappingPairs};

use super::body_colors::is_celestial;
use super::clock::UpdateClock;
use super::settings::SandboxSettings;

/// State of the sandbox beyond its settings.
#[derive(Resource, Debug)]
pub struct SandboxState {
    /// The loaded scenario, as read from its file.
    pub scenario: Scenario,
    /// File name or `built-in` of the loaded scenario.
    pub scenario_name: String,
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
    /// Counts scene builds (so views know the bodies were replaced).
    pub generation: u64,
    /// File of the loaded scenario (`None`: built-in).
    pub loaded_path: Option<PathBuf>,
}

impl SandboxState {
    pub fn new(scenario: Scenario, scenario_name: String, settings: &SandboxSettings) -> Self {
        Self {
            scenario,
            scenario_name,
            first_fragment_id: 0,
            paused: false,
            step_requested: false,
            restart_requested: true,
            built_with: settings.clone(),
            error: None,
            generation: 0,
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
        if settings.seed != built.seed {
            pending.push("seed");
        }
        if settings.scenario != built.scenario {
            pending.push("scenario");
        }
        pending
    }
}

/// Reads the scenario at `path` (or the built-in one); the error is one line
/// naming the file.
pub fn read_scenario(path: Option<&Path>) -> Result<(Scenario, String), String> {
    match path {
        Some(path) => Scenario::load(path)
            .map(|s| (s, path.display().to_string()))
            .map_err(|e| e.to_string()),
        None => Scenario::parse(DEFAULT_SCENARIO, DEFAULT_SCENARIO_NAME)
            .map(|s| (s, DEFAULT_SCENARIO_NAME.to_owned()))
            .map_err(|e| e.to_string()),
    }
}

/// The scenario files in `dir` (sorted), for the picker.
pub fn scenario_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .into_iter()
        .flatten()
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "ron"))
        .collect();
    files.sort();
    files
}

/// The bodies a restart builds: the scenario with the chosen seed and body
/// count.
pub fn build_bodies(
    scenario: &Scenario,
    name: &str,
    settings: &SandboxSettings,
) -> Result<(Vec<BodyState>, SimulationSettings), String> {
    let mut scenario = scenario.clone();
    scenario.seed = settings.seed;
    if let Some(count) = settings.body_count {
        scenario = scenario
            .with_generated(count)
            .ok_or_else(|| format!("{name}: has no generators, so its body count cannot be changed"))?;
    }
    let bodies = scenario.bodies(name).map_err(|e| e.to_string())?;
    let mut physics = scenario.settings();
    settings.apply_physics(&mut physics);
    Ok((bodies, physics))
}

/// A sphere standing for a celestial body.
#[derive(Component, Debug)]
pub struct CelestialVisual {
    pub body: Entity,
}

/// The translucent collision box of a celestial body.
#[derive(Component, Debug)]
pub struct CollisionBoxVisual;

/// Rebuilds the scene when a restart is requested: all bodies despawned,
/// the scenario's bodies spawned with the current settings.
pub fn restart_scene(world: &mut World) {
    if !world.resource::<SandboxState>().restart_requested {
        return;
    }
    world.resource_mut::<SandboxState>().restart_requested = false;
    let mut settings = world.resource::<SandboxSettings>().clone();
    if settings.scenario != world.resource::<SandboxState>().loaded_path {
        // A newly picked scenario: read it, and take its own seed and
        // shatter values.
        match read_scenario(settings.scenario.as_deref()) {
            Ok((scenario, name)) => {
                settings.adopt_scenario(&scenario.settings());
                world.insert_resource(settings.clone());
                let mut state = world.resource_mut::<SandboxState>();
                state.scenario = scenario;
                state.scenario_name = name;
                state.loaded_path = settings.scenario.clone();
            }
            Err(e) => {
                warn!("{e}");
                world.resource_mut::<SandboxState>().error = Some(e);
                return;
            }
        }
    }
    let result = {
        let state = world.resource::<SandboxState>();
        build_bodies(&state.scenario, &state.scenario_name, &settings)
    };
    let mut state = world.resource_mut::<SandboxState>();
    let (bodies, physics) = match result {
        Ok(built) => built,
        Err(e) => {
            warn!("{e}");
            state.error = Some(e);
            return;
        }
    };
    state.error = None;
    state.built_with = settings;

    let old: Vec<Entity> = world
        .query_filtered::<Entity, Or<(With<BodyId>, With<CelestialVisual>)>>()
        .iter(world)
        .collect();
    for entity in old {
        world.despawn(entity);
    }
    let next = spawn_bodies(world, &bodies);
    world.insert_resource(physics);
    let mut state = world.resource_mut::<SandboxState>();
    state.first_fragment_id = next;
    state.generation += 1;
    *world.resource_mut::<CollisionStats>() = CollisionStats::default();
    world.resource_mut::<OverlappingPairs>().0.clear();
    world.resource_mut::<StageTimings>().reset();
    world.resource_mut::<UpdateClock>().reset_owed();
    spawn_celestial_visuals(world);
    info!("scene built: {} bodies", bodies.len());
}

fn spawn_celestial_visuals(world: &mut World) {
    let celestials: Vec<(Entity, Vec3, Vec3, f32)> = world
        .query::<(
            Entity,
            &Position,
            &HalfExtents,
            &GravityRole,
            &Interacts,
            &crate::components::Mass,
        )>()
        .iter(world)
        .filter(|(_, _, _, role, interacts, _)| is_celestial(**role, **interacts))
        .map(|(e, p, h, _, _, m)| (e, p.0, h.0, m.0))
        .collect();
    let heaviest = celestials.iter().map(|c| c.3).fold(0.0f32, f32::max);
    let sphere = world
        .resource_mut::<Assets<Mesh>>()
        .add(Sphere::new(1.0).mesh().uv(64, 32));
    let cube = world.resource_mut::<Assets<Mesh>>().add(Cuboid::new(2.0, 2.0, 2.0));
    let mut materials = world.resource_mut::<Assets<StandardMaterial>>();
    let planet = materials.add(StandardMaterial {
        base_color: Color::srgb(0.18, 0.38, 0.72),
        perceptual_roughness: 0.7,
        ..default()
    });
    let moon = materials.add(StandardMaterial {
        base_color: Color::srgb(0.6, 0.58, 0.55),
        perceptual_roughness: 0.95,
        ..default()
    });
    let box_material = materials.add(StandardMaterial {
        base_color: Color::srgba(0.4, 0.9, 0.5, 0.12),
        alpha_mode: AlphaMode::Blend,
        unlit: true,
        ..default()
    });
    for (body, position, half, mass) in celestials {
        let radius = half.min_element();
        let material = if mass >= heaviest { planet.clone() } else { moon.clone() };
        world
            .spawn((
                Name::new("Celestial"),
                CelestialVisual { body },
                Mesh3d(sphere.clone()),
                MeshMaterial3d(material),
                Transform::from_translation(position).with_scale(Vec3::splat(radius)),
            ))
            .with_child((
                CollisionBoxVisual,
                Mesh3d(cube.clone()),
                MeshMaterial3d(box_material.clone()),
                Transform::from_scale(half / radius),
                Visibility::Hidden,
            ));
    }
}

/// Moves the spheres with their bodies and shows or hides collision boxes.
pub fn follow_celestials(
    mut visuals: Query<(Entity, &CelestialVisual, &mut Transform)>,
    bodies: Query<&Position, With<BodyId>>,
    mut boxes: Query<&mut Visibility, With<CollisionBoxVisual>>,
    settings: Res<SandboxSettings>,
    mut commands: Commands,
) {
    for (entity, visual, mut transform) in &mut visuals {
        match bodies.get(visual.body) {
            Ok(body) => transform.translation = body.0,
            Err(_) => commands.entity(entity).despawn(),
        }
    }
    let wanted = if settings.show_collision_boxes {
        Visibility::Inherited
    } else {
        Visibility::Hidden
    };
    for mut visibility in &mut boxes {
        visibility.set_if_neq(wanted);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn restart_builds_the_chosen_body_count_and_seed() {
        let (scenario, name) = read_scenario(None).unwrap();
        let settings = SandboxSettings {
            body_count: Some(500),
            seed: 7,
            ..SandboxSettings::default()
        };
        let (bodies, physics) = build_bodies(&scenario, &name, &settings).unwrap();
        assert_eq!(bodies.len(), scenario.bodies.len() + 500);
        assert_eq!(physics.seed, 7);
        let other = SandboxSettings { seed: 8, ..settings };
        let (reseeded, _) = build_bodies(&scenario, &name, &other).unwrap();
        assert_ne!(bodies, reseeded, "the seed reaches the generators");
    }

    #[test]
    fn live_switches_reach_the_physics() {
        let (scenario, name) = read_scenario(None).unwrap();
        let settings = SandboxSettings {
            body_count: Some(10),
            gravity: false,
            collision_effects: false,
            shatter_fragments: 9,
            shatter_threshold: 1.5,
            ..SandboxSettings::default()
        };
        let (_, physics) = build_bodies(&scenario, &name, &settings).unwrap();
        assert!(!physics.gravity && physics.collisions && !physics.collision_response);
        assert_eq!((physics.shatter_fragments, physics.shatter_threshold), (9, 1.5));
        assert_eq!(physics.time_step, scenario.time_step);
    }

    #[test]
    fn a_scenario_without_generators_refuses_a_body_count() {
        let text = "Scenario(bodies: [Body(position: (0.0, 0.0, 0.0))])";
        let scenario = Scenario::parse(text, "one.ron").unwrap();
        let settings = SandboxSettings {
            body_count: Some(10),
            ..SandboxSettings::default()
        };
        let err = build_bodies(&scenario, "one.ron", &settings).unwrap_err();
        assert!(err.contains("one.ron") && err.contains("generators"), "{err}");
    }

    #[test]
    fn restart_only_settings_are_reported_as_pending() {
        let settings = SandboxSettings::default();
        let state = SandboxState::new(read_scenario(None).unwrap().0, "x".into(), &settings);
        let changed = SandboxSettings {
            seed: 42,
            gravity: false,
            updates_per_second: 300,
            ..settings
        };
        assert_eq!(state.pending_restart(&changed), vec!["seed"]);
    }

    /// A world with what [`restart_scene`] touches, no renderer.
    fn sandbox_world(settings: SandboxSettings) -> World {
        let mut app = App::new();
        app.add_plugins((MinimalPlugins, crate::systems::SimulationPlugins))
            .insert_resource(crate::resources::Execution::new(settings.mode, 1).unwrap())
            .insert_resource(Assets::<Mesh>::default())
            .insert_resource(Assets::<StandardMaterial>::default())
            .init_resource::<UpdateClock>();
        let (scenario, name) = read_scenario(None).unwrap();
        let state = SandboxState::new(scenario, name, &settings);
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
        let spheres = world.query::<&CelestialVisual>().iter(&world).len();
        assert_eq!(spheres, 2, "planet and moon drawn as spheres");

        // Pick another scenario and restart: the old bodies are gone, the
        // scenario's own seed is taken.
        let two_body = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/two_body.ron"));
        {
            let mut settings = world.resource_mut::<SandboxSettings>();
            settings.scenario = Some(two_body.clone());
            settings.body_count = None;
            settings.seed = 12345;
        }
        world.resource_mut::<SandboxState>().restart_requested = true;
        restart_scene(&mut world);
        let state = world.resource::<SandboxState>();
        assert!(state.error.is_none(), "{:?}", state.error);
        assert_eq!(state.loaded_path.as_deref(), Some(two_body.as_path()));
        assert_eq!(state.generation, 2);
        assert_ne!(world.resource::<SandboxSettings>().seed, 12345);
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

    #[test]
    fn picker_lists_the_shipped_scenarios() {
        let files = scenario_files(Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios")));
        assert!(files.iter().any(|f| f.ends_with("debris_orbit.ron")), "{files:?}");
        assert!(files.windows(2).all(|w| w[0] <= w[1]));
    }
}
