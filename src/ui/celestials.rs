//! The planet and moons — sources that do not collide — drawn as lit
//! spheres that follow their bodies, each with its collision box, shown on
//! request.

use bevy::prelude::*;
use bevy::transform::TransformSystems;

use super::body_colors::is_celestial;
use super::settings::SandboxSettings;
use crate::components::{BodyId, GravityRole, HalfExtents, Interacts, Mass, Position};

/// A sphere standing for a celestial body.
#[derive(Component, Debug)]
pub struct CelestialVisual {
    /// The body it stands for.
    pub body: Entity,
}

/// The translucent collision box of a celestial body.
#[derive(Component, Debug)]
pub struct CollisionBoxVisual;

/// The meshes and materials of the celestial visuals.
#[derive(Resource, Clone, Debug)]
pub struct CelestialAssets {
    sphere: Handle<Mesh>,
    cube: Handle<Mesh>,
    planet: Handle<StandardMaterial>,
    moon: Handle<StandardMaterial>,
    collision_box: Handle<StandardMaterial>,
}

/// Spheres for new celestial bodies; spheres follow their bodies and go
/// with them.
pub struct CelestialsPlugin;

impl Plugin for CelestialsPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(Startup, init_celestial_assets).add_systems(
            PostUpdate,
            (spawn_celestial_visuals, follow_celestials)
                .chain()
                .before(TransformSystems::Propagate),
        );
    }
}

fn init_celestial_assets(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    commands.insert_resource(CelestialAssets {
        sphere: meshes.add(Sphere::new(1.0).mesh().uv(64, 32)),
        cube: meshes.add(Cuboid::new(2.0, 2.0, 2.0)),
        planet: materials.add(StandardMaterial {
            base_color: Color::srgb(0.18, 0.38, 0.72),
            perceptual_roughness: 0.7,
            ..default()
        }),
        moon: materials.add(StandardMaterial {
            base_color: Color::srgb(0.6, 0.58, 0.55),
            perceptual_roughness: 0.95,
            ..default()
        }),
        collision_box: materials.add(StandardMaterial {
            base_color: Color::srgba(0.4, 0.9, 0.5, 0.12),
            alpha_mode: AlphaMode::Blend,
            unlit: true,
            ..default()
        }),
    });
}

/// The components that tell a celestial body and its size.
type CelestialQuery<'w, 's, F> = Query<
    'w,
    's,
    (
        Entity,
        &'static Position,
        &'static HalfExtents,
        &'static Mass,
        &'static GravityRole,
        &'static Interacts,
    ),
    F,
>;

/// Spawns a sphere (radius: the smallest half extent) for every new
/// celestial body; the heaviest celestial body looks like a planet, the
/// others like moons.
fn spawn_celestial_visuals(
    mut commands: Commands,
    assets: Res<CelestialAssets>,
    added: CelestialQuery<Added<BodyId>>,
    all: CelestialQuery<()>,
) {
    let celestial = |(.., role, interacts): &(Entity, &Position, &HalfExtents, &Mass, &GravityRole, &Interacts)| {
        is_celestial(**role, **interacts)
    };
    if !added.iter().any(|body| celestial(&body)) {
        return;
    }
    let heaviest = all
        .iter()
        .filter(celestial)
        .map(|(.., mass, _, _)| mass.0)
        .fold(0.0f32, f32::max);
    for (body, position, half, mass, ..) in added.iter().filter(celestial) {
        let radius = half.0.min_element();
        let material = if mass.0 >= heaviest {
            &assets.planet
        } else {
            &assets.moon
        };
        commands
            .spawn((
                Name::new("Celestial"),
                CelestialVisual { body },
                Mesh3d(assets.sphere.clone()),
                MeshMaterial3d(material.clone()),
                Transform::from_translation(position.0).with_scale(Vec3::splat(radius)),
            ))
            .with_child((
                CollisionBoxVisual,
                Mesh3d(assets.cube.clone()),
                MeshMaterial3d(assets.collision_box.clone()),
                Transform::from_scale(half.0 / radius),
                Visibility::Hidden,
            ));
    }
}

/// Moves the spheres with their bodies, despawns those whose body is gone,
/// and shows or hides the collision boxes.
fn follow_celestials(
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
    use crate::components::BodyState;
    use crate::scenario::Scenario;

    fn app_with(bodies: &[BodyState]) -> App {
        let mut app = App::new();
        app.add_plugins(MinimalPlugins)
            .init_resource::<Assets<Mesh>>()
            .init_resource::<Assets<StandardMaterial>>()
            .insert_resource(SandboxSettings::default())
            .add_plugins(CelestialsPlugin);
        crate::simulation::spawn_bodies(app.world_mut(), bodies);
        app
    }

    fn visuals(app: &mut App) -> Vec<Entity> {
        let world = app.world_mut();
        world.query::<&CelestialVisual>().iter(world).map(|v| v.body).collect()
    }

    #[test]
    fn planet_and_moon_get_spheres_that_go_with_their_bodies() {
        let scenario = Scenario::builtin_default().with_generated(50).unwrap();
        let mut app = app_with(&scenario.bodies().unwrap());
        app.update();
        let spheres = visuals(&mut app);
        assert_eq!(spheres.len(), 2, "planet and moon, not the debris");
        app.update();
        assert_eq!(visuals(&mut app).len(), 2, "spawned once");
        app.world_mut().despawn(spheres[0]);
        app.update();
        assert_eq!(visuals(&mut app), [spheres[1]], "a body's sphere goes with it");
    }
}
