//! The two comparison methods of the thesis: every body its own Bevy mesh
//! entity, either all sharing one cube mesh and one material (its "same
//! model", Table 2: Bevy batches the draws, but extracts, culls and uploads
//! every entity every frame), or each with its own copy of the cube's
//! geometry (its "redundant objects", Table 1: distinct meshes cannot be
//! batched, so every body is a draw of its own). The per-body meshes carry
//! the bodies' colors as vertex colors, rewritten when a color changes.

use bevy::prelude::*;
use bevy::transform::TransformSystems;

use super::body_colors::{LookTracker, PLAIN, body_color, is_celestial};
use crate::components::{BodyId, GravityRole, HalfExtents, NonInteracting, Position, Velocity};
use crate::resources::DrawMethod;
use crate::systems::OverlappingPairs;
use crate::ui::session::SandboxSettings;
use crate::ui::session::SandboxState;

/// The shared mesh and materials of per-entity bodies.
#[derive(Resource, Clone)]
pub struct BodyMeshAssets {
    /// A unit cube, scaled per body.
    pub mesh: Handle<Mesh>,
    /// Plain gray, for the shared mesh.
    pub material: Handle<StandardMaterial>,
    /// White, tinted by each own mesh's vertex colors.
    pub vertex_colored: Handle<StandardMaterial>,
}

/// Marks a body drawn by a mesh entity of its own, and how.
#[derive(Component, Debug, Clone, Copy, PartialEq, Eq)]
pub struct MeshedBody(pub DrawMethod);

/// The color last written into a body's own mesh.
#[derive(Component, Debug, Clone, Copy, PartialEq, Eq)]
pub struct OwnMeshColor(pub [u8; 4]);

/// Gives every body a mesh entity when a mesh method is chosen.
pub struct MeshesPlugin;

impl Plugin for MeshesPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(Startup, init_body_mesh_assets).add_systems(
            PostUpdate,
            (
                (sync_body_meshes, color_own_meshes).chain(),
                place_body_meshes.after(TransformSystems::Propagate),
            ),
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
        vertex_colored: materials.add(Color::WHITE),
    });
}

/// A unit cube of its own, all vertices in `color`.
fn own_cube(color: [u8; 4]) -> Mesh {
    let mesh = Mesh::from(Cuboid::new(1.0, 1.0, 1.0));
    let vertices = mesh.count_vertices();
    // Kept in the main world too (the default), so that its colors can be
    // rewritten: redundant, as the method is meant to be.
    mesh.with_inserted_attribute(Mesh::ATTRIBUTE_COLOR, vec![linear(color); vertices])
}

fn linear(color: [u8; 4]) -> [f32; 4] {
    let [r, g, b, a] = color;
    Color::srgba_u8(r, g, b, a).to_linear().to_f32_array()
}

/// The mesh method wanted now, if any.
fn wanted_method(settings: &SandboxSettings) -> Option<DrawMethod> {
    (settings.render_bodies && settings.render_method != DrawMethod::Instanced).then_some(settings.render_method)
}

/// Gives every cube a mesh in a mesh method (new fragments included), and
/// takes them away from cubes meshed another way or when no mesh method is
/// chosen.
#[expect(clippy::type_complexity, reason = "queries select bodies by their drawing state")]
fn sync_body_meshes(
    mut commands: Commands,
    settings: Res<SandboxSettings>,
    assets: Res<BodyMeshAssets>,
    mut meshes: ResMut<Assets<Mesh>>,
    bare: Query<(Entity, Option<&GravityRole>, Has<NonInteracting>), (With<BodyId>, Without<MeshedBody>)>,
    meshed: Query<(Entity, &MeshedBody)>,
) {
    let wanted = wanted_method(&settings);
    for (entity, MeshedBody(method)) in &meshed {
        if Some(*method) != wanted {
            commands
                .entity(entity)
                .remove::<(MeshedBody, OwnMeshColor, Mesh3d, MeshMaterial3d<StandardMaterial>)>();
        }
    }
    let cubes = bare
        .iter()
        .filter(|&(_, role, non_interacting)| !is_celestial(GravityRole::of(role), non_interacting));
    match wanted {
        Some(DrawMethod::SharedMesh) => {
            let batch: Vec<_> = cubes
                .map(|(e, ..)| {
                    (
                        e,
                        (
                            MeshedBody(DrawMethod::SharedMesh),
                            Mesh3d(assets.mesh.clone()),
                            MeshMaterial3d(assets.material.clone()),
                        ),
                    )
                })
                .collect();
            commands.insert_batch(batch);
        }
        Some(DrawMethod::MeshPerBody) => {
            let batch: Vec<_> = cubes
                .map(|(e, ..)| {
                    (
                        e,
                        (
                            MeshedBody(DrawMethod::MeshPerBody),
                            OwnMeshColor(PLAIN),
                            Mesh3d(meshes.add(own_cube(PLAIN))),
                            MeshMaterial3d(assets.vertex_colored.clone()),
                        ),
                    )
                })
                .collect();
            commands.insert_batch(batch);
        }
        Some(DrawMethod::Instanced) | None => {}
    }
}

/// Writes each body's color into its own mesh when the color changed (the
/// redundant method uploads that body's whole mesh again).
fn color_own_meshes(
    settings: Res<SandboxSettings>,
    state: Res<SandboxState>,
    pairs: Res<OverlappingPairs>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut looks: Local<LookTracker>,
    mut bodies: Query<(Entity, &BodyId, &Velocity, &Mesh3d, &mut OwnMeshColor)>,
) {
    if wanted_method(&settings) != Some(DrawMethod::MeshPerBody) {
        return;
    }
    looks.start(&pairs);
    for (entity, id, velocity, mesh, mut shown) in &mut bodies {
        let color = body_color(
            looks.look(entity, *id, velocity.0, state.first_fragment_id),
            settings.visual_effects,
        );
        if shown.0 == color {
            continue;
        }
        if let Some(mut mesh) = meshes.get_mut(&mesh.0) {
            let vertices = mesh.count_vertices();
            mesh.insert_attribute(Mesh::ATTRIBUTE_COLOR, vec![linear(color); vertices]);
            shown.0 = color;
        }
    }
    looks.finish();
}

/// The renderer reads `GlobalTransform` (which `Mesh3d` brings along); the
/// stages move [`Position`], so the mesh methods copy it over (sized by the
/// half extents) every frame.
fn place_body_meshes(mut bodies: Query<(&Position, &HalfExtents, &mut GlobalTransform), With<MeshedBody>>) {
    bodies.par_iter_mut().for_each(|(position, half, mut global)| {
        *global = GlobalTransform::from(Transform::from_translation(position.0).with_scale(half.0 * 2.0));
    });
}
