//! All body cubes in one instanced draw call: the main world's half.
//!
//! Each frame in which the bodies moved, the main world packs every body
//! into a 28-byte [`InstanceData`] (center, half extents, color) and hands
//! the vector to the render world through a shared
//! [`InstanceSlot`](super::instance_slot::InstanceSlot), without copying it
//! again. The render world's half
//! ([`instanced_draw`](super::instanced_draw)) writes it into one reused GPU
//! buffer and draws every cube with one `draw_indexed` call (the pattern of
//! Bevy's `custom_shader_instancing` example, with a reused buffer).

use std::sync::Arc;

use bevy::camera::visibility::NoFrustumCulling;
use bevy::prelude::*;
use bevy::render::extract_component::ExtractComponentPlugin;

use super::body_colors::{LookTracker, body_color, is_celestial};
use super::instance_slot::{InstanceData, InstancedBodies};
use super::instanced_draw::InstancedDrawPlugin;
use crate::components::{BodyId, GravityRole, HalfExtents, NonInteracting, Position, Velocity};
use crate::resources::DrawMethod;
use crate::systems::OverlappingPairs;
use crate::ui::session::SandboxSettings;
use crate::ui::session::SandboxState;
use crate::ui::session::UpdateClock;

/// Draws the bodies as instanced cubes when that method is chosen.
pub struct InstancingPlugin;

impl Plugin for InstancingPlugin {
    fn build(&self, app: &mut App) {
        app.add_plugins((
            ExtractComponentPlugin::<InstancedBodies>::default(),
            InstancedDrawPlugin,
        ))
        .add_systems(Startup, spawn_instanced_bodies)
        .add_systems(PostUpdate, gather_instances);
    }
}

/// Spawns the instanced-bodies entity.
fn spawn_instanced_bodies(mut commands: Commands, mut meshes: ResMut<Assets<Mesh>>) {
    commands.spawn((
        Name::new("Instanced bodies"),
        Mesh3d(meshes.add(Cuboid::new(1.0, 1.0, 1.0))),
        InstancedBodies(Arc::default()),
        // The instances are everywhere; the mesh's own box says nothing.
        NoFrustumCulling,
    ));
}

/// Buffers of [`gather_instances`], kept between frames.
#[derive(Default)]
struct GatherScratch {
    staging: Vec<InstanceData>,
    looks: LookTracker,
    /// (updates run, scene generation, edits) of the last publish.
    published: Option<(u64, u64, u64)>,
}

/// The components a cube's instance is made of.
type CubeQuery<'w, 's> = Query<
    'w,
    's,
    (
        Entity,
        &'static BodyId,
        &'static Position,
        &'static HalfExtents,
        &'static Velocity,
        Option<&'static GravityRole>,
        Has<NonInteracting>,
    ),
>;

/// Packs every cube into the instance slot (instanced method, bodies
/// shown), an empty slot otherwise — but only when the bodies moved, the
/// scene was rebuilt or a setting changed: the positions are never marked
/// changed (see `components`), so the update count tells.
fn gather_instances(
    bodies: CubeQuery,
    instanced: Query<&InstancedBodies>,
    pairs: Res<OverlappingPairs>,
    settings: Res<SandboxSettings>,
    state: Res<SandboxState>,
    clock: Res<UpdateClock>,
    mut scratch: Local<GatherScratch>,
) {
    let Some(InstancedBodies(slot)) = instanced.iter().next() else {
        return;
    };
    let now = (clock.updates_total, state.generation, state.edits);
    if scratch.published == Some(now) && !settings.is_changed() {
        return;
    }
    scratch.published = Some(now);
    let mut staging = std::mem::take(&mut scratch.staging);
    staging.clear();
    if settings.render_bodies && settings.render_method == DrawMethod::Instanced {
        let looks = &mut scratch.looks;
        looks.start(&pairs);
        let cubes = bodies
            .iter()
            .filter(|&(.., role, non_interacting)| !is_celestial(GravityRole::of(role), non_interacting));
        staging.extend(cubes.map(|(entity, id, position, half, velocity, ..)| {
            let look = looks.look(entity, *id, velocity.0, state.first_fragment_id);
            InstanceData {
                center: position.0.to_array(),
                half_extents: half.0.to_array(),
                color: body_color(look, settings.visual_effects),
            }
        }));
        looks.finish();
    }
    slot.publish(&mut staging);
    scratch.staging = staging;
}
