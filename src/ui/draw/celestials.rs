//! The planet and moons — sources that do not collide — drawn as lit
//! spheres that follow their bodies, each with its collision box, shown on
//! request. The heaviest is the Earth (generated surface and an atmosphere
//! rim), the others the Moon.

use bevy::asset::RenderAssetUsages;
use bevy::prelude::*;
use bevy::render::render_resource::{Extent3d, TextureDimension, TextureFormat};
use bevy::transform::TransformSystems;

use super::atmosphere::{AtmosphereMaterial, AtmosphereVisual, ring_mesh};
use super::body_colors::is_celestial;
use super::planet_texture::{self, Picture};
use crate::components::{BodyId, GravityRole, HalfExtents, Mass, NonInteracting, Position};
use crate::ui::session::SandboxSettings;

/// A sphere standing for a celestial body.
#[derive(Component, Debug)]
pub struct CelestialVisual {
    /// The entity that holds the body it stands for.
    pub body: Entity,
    /// Its id: the sphere goes when its entity no longer holds this body.
    pub id: BodyId,
}

/// The translucent collision box of a celestial body.
#[derive(Component, Debug)]
pub struct CollisionBoxVisual;

/// The meshes and materials of the celestial visuals.
#[derive(Resource, Clone, Debug)]
pub struct CelestialAssets {
    sphere: Handle<Mesh>,
    ring: Handle<Mesh>,
    cube: Handle<Mesh>,
    planet: Handle<StandardMaterial>,
    moon: Handle<StandardMaterial>,
    atmosphere: Handle<AtmosphereMaterial>,
    collision_box: Handle<StandardMaterial>,
}

/// Turns a UV sphere (poles on ±z) so that its north pole points up (+y),
/// the axis the default scene's orbits turn around.
const NORTH_UP: Quat = Quat::from_xyzw(
    -std::f32::consts::FRAC_1_SQRT_2,
    0.0,
    0.0,
    std::f32::consts::FRAC_1_SQRT_2,
);

/// The Earth's surface texture width (height: half of it), pixels.
const EARTH_TEXTURE_WIDTH: u32 = 1024;
/// The Moon's surface texture width, pixels.
const MOON_TEXTURE_WIDTH: u32 = 512;
/// Seed of the generated surfaces (the same world every start).
const SURFACE_SEED: u32 = 2022;

fn image(picture: Picture) -> Image {
    Image::new(
        Extent3d {
            width: picture.width,
            height: picture.height,
            depth_or_array_layers: 1,
        },
        TextureDimension::D2,
        picture.rgba,
        TextureFormat::Rgba8UnormSrgb,
        RenderAssetUsages::RENDER_WORLD,
    )
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
    mut atmospheres: ResMut<Assets<AtmosphereMaterial>>,
    mut images: ResMut<Assets<Image>>,
) {
    let earth = images.add(image(planet_texture::earth(EARTH_TEXTURE_WIDTH, SURFACE_SEED)));
    let moon = images.add(image(planet_texture::moon(MOON_TEXTURE_WIDTH, SURFACE_SEED)));
    commands.insert_resource(CelestialAssets {
        sphere: meshes.add(Sphere::new(1.0).mesh().uv(64, 32)),
        ring: meshes.add(ring_mesh()),
        cube: meshes.add(Cuboid::new(2.0, 2.0, 2.0)),
        planet: materials.add(StandardMaterial {
            base_color_texture: Some(earth),
            perceptual_roughness: 0.8,
            reflectance: 0.2,
            ..default()
        }),
        moon: materials.add(StandardMaterial {
            base_color_texture: Some(moon),
            perceptual_roughness: 0.95,
            reflectance: 0.1,
            ..default()
        }),
        atmosphere: atmospheres.add(AtmosphereMaterial::default()),
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
        &'static BodyId,
        &'static Position,
        &'static HalfExtents,
        &'static Mass,
        Option<&'static GravityRole>,
        Has<NonInteracting>,
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
    let celestial = |&(.., role, non_interacting): &(
        Entity,
        &BodyId,
        &Position,
        &HalfExtents,
        &Mass,
        Option<&GravityRole>,
        bool,
    )| { is_celestial(GravityRole::of(role), non_interacting) };
    if !added.iter().any(|body| celestial(&body)) {
        return;
    }
    let heaviest = all
        .iter()
        .filter(celestial)
        .map(|(.., mass, _, _)| mass.0)
        .fold(0.0f32, f32::max);
    for (body, &id, position, half, mass, ..) in added.iter().filter(celestial) {
        let radius = half.0.min_element();
        let earth = mass.0 >= heaviest;
        let material = if earth { &assets.planet } else { &assets.moon };
        let mut visual = commands.spawn((
            Name::new("Celestial"),
            CelestialVisual { body, id },
            Mesh3d(assets.sphere.clone()),
            MeshMaterial3d(material.clone()),
            Transform::from_translation(position.0)
                .with_scale(Vec3::splat(radius))
                .with_rotation(NORTH_UP),
        ));
        visual.with_child((
            CollisionBoxVisual,
            Mesh3d(assets.cube.clone()),
            MeshMaterial3d(assets.collision_box.clone()),
            // Unturned: the box stays axis-aligned in the world.
            Transform::from_scale(half.0 / radius).with_rotation(NORTH_UP.inverse()),
            Visibility::Hidden,
        ));
        if earth {
            visual.with_child((
                AtmosphereVisual,
                Mesh3d(assets.ring.clone()),
                MeshMaterial3d(assets.atmosphere.clone()),
                Transform::default(),
            ));
        }
    }
}

/// Moves the spheres with their bodies, despawns those whose body is gone,
/// and shows or hides the collision boxes.
fn follow_celestials(
    mut visuals: Query<(Entity, &CelestialVisual, &mut Transform)>,
    bodies: Query<(&BodyId, &Position)>,
    mut boxes: Query<&mut Visibility, With<CollisionBoxVisual>>,
    settings: Res<SandboxSettings>,
    mut commands: Commands,
) {
    for (entity, visual, mut transform) in &mut visuals {
        // A body spawned anew (a rewind, a restart) gets a sphere of its
        // own (`Added`): this one goes with the entity it stood for.
        match bodies.get(visual.body) {
            Ok((id, position)) if *id == visual.id => transform.translation = position.0,
            _ => commands.entity(entity).despawn(),
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
            .init_resource::<Assets<AtmosphereMaterial>>()
            .init_resource::<Assets<Image>>()
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
        // Every body spawned anew, as a rewind does: two spheres again, on
        // the new entities.
        let bodies = scenario.bodies().unwrap();
        let world = app.world_mut();
        let old: Vec<Entity> = world.query_filtered::<Entity, With<BodyId>>().iter(world).collect();
        for entity in old {
            world.despawn(entity);
        }
        crate::simulation::spawn_bodies(world, &bodies);
        app.update();
        app.update();
        let again = visuals(&mut app);
        assert_eq!(again.len(), 2, "{again:?}");
        assert!(again.iter().all(|e| !spheres.contains(e)), "on the new entities");
    }

    #[test]
    fn the_north_pole_points_up() {
        assert!(NORTH_UP.mul_vec3(Vec3::Z).abs_diff_eq(Vec3::Y, 1e-6));
        assert!(NORTH_UP.is_normalized());
    }
}
