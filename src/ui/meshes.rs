//! The comparison method: every body its own Bevy mesh entity, all sharing
//! one cube mesh and one material (the thesis's "shared model"). Bevy
//! batches the draws, but extracts, culls and uploads every entity every
//! frame; the instanced pipeline skips all of that.

use bevy::prelude::*;
use bevy::transform::TransformSystems;

use super::body_colors::{PLAIN, is_celestial};
use super::settings::{RenderMethod, SandboxSettings};
use crate::components::{BodyId, GravityRole, HalfExtents, Interacts, Position};

/// The shared mesh and material of per-entity bodies.
#[derive(Resource, Clone)]
pub struct BodyMeshAssets {
    /// A unit cube, scaled per body.
    pub mesh: Handle<Mesh>,
    /// Plain gray.
    pub material: Handle<StandardMaterial>,
}

/// Marks a body drawn by its own mesh entity.
#[derive(Component, Debug)]
pub struct MeshedBody;

/// Gives every body a mesh entity when that method is chosen.
pub struct MeshesPlugin;

impl Plugin for MeshesPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(Startup, init_body_mesh_assets).add_systems(
            PostUpdate,
            (sync_body_meshes, place_body_meshes.after(TransformSystems::Propagate)),
        );
    }
}

fn init_body_mesh_assets(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    let [r, g, b, _] = PLAIN;
    commands.insert_resource(BodyMeshAssets {
        mesh: meshes.add(Cuboid::new(1.0, 1.0, 1.0)),
        material: materials.add(Color::srgb_u8(r, g, b)),
    });
}

/// Gives every cube a mesh in the meshes method (new fragments included)
/// and takes them away otherwise.
#[expect(clippy::type_complexity, reason = "queries select bodies by their drawing state")]
fn sync_body_meshes(
    mut commands: Commands,
    settings: Res<SandboxSettings>,
    assets: Res<BodyMeshAssets>,
    bare: Query<(Entity, &GravityRole, &Interacts), (With<BodyId>, Without<MeshedBody>)>,
    meshed: Query<Entity, With<MeshedBody>>,
) {
    let wanted = settings.render_bodies && settings.render_method == RenderMethod::Meshes;
    if wanted {
        let batch: Vec<(Entity, (MeshedBody, Mesh3d, MeshMaterial3d<StandardMaterial>))> = bare
            .iter()
            .filter(|(_, role, interacts)| !is_celestial(**role, **interacts))
            .map(|(e, ..)| {
                (
                    e,
                    (
                        MeshedBody,
                        Mesh3d(assets.mesh.clone()),
                        MeshMaterial3d(assets.material.clone()),
                    ),
                )
            })
            .collect();
        if !batch.is_empty() {
            commands.insert_batch(batch);
        }
    } else {
        for entity in &meshed {
            commands
                .entity(entity)
                .remove::<(MeshedBody, Mesh3d, MeshMaterial3d<StandardMaterial>)>();
        }
    }
}

/// The renderer reads `GlobalTransform` (which `Mesh3d` brings along); the
/// stages move [`Position`], so the meshes method copies it over (sized by
/// the half extents) every frame.
fn place_body_meshes(mut bodies: Query<(&Position, &HalfExtents, &mut GlobalTransform), With<MeshedBody>>) {
    bodies.par_iter_mut().for_each(|(position, half, mut global)| {
        *global = GlobalTransform::from(Transform::from_translation(position.0).with_scale(half.0 * 2.0));
    });
}
