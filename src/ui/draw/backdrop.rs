//! The static backdrop: sunlight, ambient light and a starfield.

use bevy::asset::RenderAssetUsages;
use bevy::light::GlobalAmbientLight;
use bevy::mesh::{Indices, PrimitiveTopology};
use bevy::prelude::*;

use crate::maths::Rng;

/// Distance of the stars from the origin, world units.
pub const STAR_DISTANCE: f32 = 200_000.0;
/// Stars in the sky.
pub const STAR_COUNT: usize = 4000;

/// Direction the sunlight comes from (towards the sun); the instanced
/// shader lights the cubes from the same direction.
pub fn sun_direction() -> Vec3 {
    Vec3::ONE.normalize()
}

/// The sun, the ambient light and the stars, spawned at start.
pub struct BackdropPlugin;

impl Plugin for BackdropPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(Startup, spawn_backdrop);
    }
}

/// Spawns the sun, the ambient light and the stars.
fn spawn_backdrop(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    commands.insert_resource(ClearColor(Color::srgb(0.005, 0.006, 0.015)));
    commands.insert_resource(GlobalAmbientLight {
        color: Color::WHITE,
        brightness: 250.0,
        ..default()
    });
    commands.spawn((
        Name::new("Sun"),
        DirectionalLight {
            illuminance: 4_000.0,
            ..default()
        },
        Transform::default().looking_to(-sun_direction(), Vec3::Y),
    ));
    commands.spawn((
        Name::new("Stars"),
        Mesh3d(meshes.add(starfield_mesh(STAR_COUNT, STAR_DISTANCE, 7))),
        MeshMaterial3d(materials.add(StandardMaterial {
            // Dimmer than any lit body, so the bodies stand out.
            base_color: Color::srgb(0.42, 0.43, 0.47),
            unlit: true,
            // Seen from inside the sphere, whichever way they wind.
            cull_mode: None,
            ..default()
        })),
        Transform::default(),
    ));
}

/// One mesh of `count` small triangles on a sphere of `radius`, each facing
/// the center, their sizes varied for a few brighter stars.
pub fn starfield_mesh(count: usize, radius: f32, seed: u64) -> Mesh {
    let mut rng = Rng::stream(seed, 0);
    let mut positions = Vec::with_capacity(count * 3);
    for _ in 0..count {
        // Uniform direction on the sphere.
        let z = (rng.unit() as f32) * 2.0 - 1.0;
        let phi = (rng.unit() as f32) * std::f32::consts::TAU;
        let r = (1.0 - z * z).max(0.0).sqrt();
        let dir = Vec3::new(r * phi.cos(), r * phi.sin(), z);
        // About 0.7 px from the center to a corner in an 800-px-high window
        // (at most 1 px for the brightest): smaller than any body's least
        // size on screen (the instanced shader's 1.25 px half-extent).
        let size = radius * 0.0007 * (1.0 + 0.5 * (rng.unit() as f32).powi(6));
        let center = dir * radius;
        let (u, v) = dir.any_orthonormal_pair();
        for k in 0..3 {
            let angle = k as f32 * std::f32::consts::TAU / 3.0;
            positions.push((center + (u * angle.cos() + v * angle.sin()) * size).to_array());
        }
    }
    let normals: Vec<[f32; 3]> = positions
        .iter()
        .map(|p| (-Vec3::from_array(*p).normalize()).to_array())
        .collect();
    let indices: Vec<u32> = (0..positions.len() as u32).collect();
    Mesh::new(PrimitiveTopology::TriangleList, RenderAssetUsages::RENDER_WORLD)
        .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, positions)
        .with_inserted_attribute(Mesh::ATTRIBUTE_NORMAL, normals)
        .with_inserted_indices(Indices::U32(indices))
}
