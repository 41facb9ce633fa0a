//! All body cubes in one instanced draw call: the render world's half.
//!
//! The render world keeps one GPU buffer of [`InstanceData`], grows it only
//! when the bodies outgrow it, and otherwise overwrites it in place when the
//! main world published new instances; one `draw_indexed` call with one
//! instance per body draws them all, with the mesh pipeline's lighting and
//! the shader `instancing.wgsl`.

use std::sync::Arc;

use bevy::asset::{load_internal_asset, uuid_handle};
use bevy::core_pipeline::core_3d::{Transparent3d, TransparentSortingInfo3d};
use bevy::ecs::system::lifetimeless::SRes;
use bevy::ecs::system::{SystemParam, SystemParamItem};
use bevy::mesh::{MeshVertexBufferLayoutRef, VertexBufferLayout};
use bevy::pbr::{
    MeshPipeline, MeshPipelineKey, MeshPipelineSystems, RenderMeshInstances, SetMeshBindGroup, SetMeshViewBindGroup,
    SetMeshViewBindingArrayBindGroup, ViewKeyCache,
};
use bevy::prelude::*;
use bevy::render::mesh::allocator::MeshAllocator;
use bevy::render::mesh::{RenderMesh, RenderMeshBufferInfo};
use bevy::render::render_asset::RenderAssets;
use bevy::render::render_phase::{
    AddRenderCommand, DrawFunctions, PhaseItem, PhaseItemExtraIndex, RenderCommand, RenderCommandResult,
    SetItemPipeline, TrackedRenderPass, ViewSortedRenderPhases,
};
use bevy::render::render_resource::{
    Buffer, BufferDescriptor, BufferUsages, PipelineCache, RenderPipelineDescriptor, SpecializedMeshPipeline,
    SpecializedMeshPipelineError, SpecializedMeshPipelines, VertexAttribute, VertexFormat, VertexStepMode,
};
use bevy::render::renderer::{RenderDevice, RenderQueue};
use bevy::render::sync_world::MainEntity;
use bevy::render::view::ExtractedView;
use bevy::render::{Render, RenderApp, RenderStartup, RenderSystems};

use super::instance_slot::{InstanceData, InstanceSlot, InstancedBodies};

const SHADER: Handle<Shader> = uuid_handle!("5b0c6f1e-2d4a-4e57-9a61-7f3f1c0de5a1");

/// Adds the instanced body pipeline to the renderer.
pub struct InstancedDrawPlugin;

impl Plugin for InstancedDrawPlugin {
    fn build(&self, app: &mut App) {
        load_internal_asset!(app, SHADER, "instancing.wgsl", Shader::from_wgsl);
        app.sub_app_mut(RenderApp)
            .add_render_command::<Transparent3d, DrawBodies>()
            .init_resource::<SpecializedMeshPipelines<BodyPipeline>>()
            .init_resource::<BodyInstanceBuffer>()
            .add_systems(RenderStartup, init_body_pipeline.after(MeshPipelineSystems))
            .add_systems(
                Render,
                (
                    queue_bodies.in_set(RenderSystems::QueueMeshes),
                    prepare_body_buffer.in_set(RenderSystems::PrepareResources),
                ),
            );
    }
}

/// The GPU buffer of instances, reused from frame to frame.
#[derive(Resource, Default)]
pub struct BodyInstanceBuffer {
    buffer: Option<Buffer>,
    /// Instances the buffer can hold.
    capacity: usize,
    /// Instances to draw this frame.
    length: usize,
    /// Generation of the data in the buffer.
    uploaded: Option<u64>,
    slot: Option<Arc<InstanceSlot>>,
}

impl BodyInstanceBuffer {
    /// Bytes of GPU memory the buffer holds.
    pub fn bytes(&self) -> u64 {
        self.buffer.as_ref().map_or(0, |b| b.size())
    }
}

fn prepare_body_buffer(
    bodies: Query<&InstancedBodies>,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    mut gpu: ResMut<BodyInstanceBuffer>,
) {
    let Some(InstancedBodies(slot)) = bodies.iter().next() else {
        gpu.length = 0;
        return;
    };
    let (data, generation) = slot.read();
    if gpu.uploaded == Some(generation) {
        // Nothing new (paused, or the frame ran no update): draw what is there.
        return;
    }
    if data.len() > gpu.capacity || gpu.buffer.is_none() {
        // Grow by half again, so a growing debris field reallocates rarely.
        let capacity = (data.len() + data.len() / 2).max(1024);
        gpu.buffer = Some(device.create_buffer(&BufferDescriptor {
            label: Some("kessler body instances"),
            size: (capacity * size_of::<InstanceData>()) as u64,
            usage: BufferUsages::VERTEX | BufferUsages::COPY_DST,
            mapped_at_creation: false,
        }));
        gpu.capacity = capacity;
    }
    if let Some(buffer) = &gpu.buffer
        && !data.is_empty()
    {
        queue.write_buffer(buffer, 0, bytemuck::cast_slice(data.as_slice()));
    }
    gpu.length = data.len();
    gpu.uploaded = Some(generation);
    drop(data);
    gpu.slot = Some(slot.clone());
}

/// The body pipeline, specialized per mesh and view, and the draw
/// function that draws with it.
#[derive(SystemParam)]
struct Pipelines<'w> {
    draw_functions: Res<'w, DrawFunctions<Transparent3d>>,
    pipeline: Res<'w, BodyPipeline>,
    pipelines: ResMut<'w, SpecializedMeshPipelines<BodyPipeline>>,
    pipeline_cache: Res<'w, PipelineCache>,
}

/// The meshes, and which mesh each instanced entity draws.
#[derive(SystemParam)]
struct Meshes<'w> {
    meshes: Res<'w, RenderAssets<RenderMesh>>,
    mesh_instances: Res<'w, RenderMeshInstances>,
}

fn queue_bodies(
    parts: Pipelines,
    meshes: Meshes,
    bodies: Query<(Entity, &MainEntity), With<InstancedBodies>>,
    mut phases: ResMut<ViewSortedRenderPhases<Transparent3d>>,
    views: Query<&ExtractedView>,
    view_keys: Res<ViewKeyCache>,
) {
    let Pipelines {
        draw_functions,
        pipeline,
        mut pipelines,
        pipeline_cache,
    } = parts;
    let Meshes { meshes, mesh_instances } = meshes;
    let draw = draw_functions.read().id::<DrawBodies>();
    for view in &views {
        let Some(phase) = phases.get_mut(&view.retained_view_entity) else {
            continue;
        };
        let Some(&view_key) = view_keys.get(&view.retained_view_entity) else {
            continue;
        };
        for (entity, main_entity) in &bodies {
            let Some(mesh_instance) = mesh_instances.render_mesh_queue_data(*main_entity) else {
                continue;
            };
            let Some(mesh) = meshes.get(mesh_instance.mesh_asset_id()) else {
                continue;
            };
            let key = view_key
                | MeshPipelineKey::from_primitive_topology_and_strip_index(
                    mesh.primitive_topology(),
                    mesh.index_format(),
                );
            let Ok(pipeline) = pipelines.specialize(&pipeline_cache, &pipeline, key, &mesh.layout) else {
                continue;
            };
            phase.add_retained(Transparent3d {
                sorting_info: TransparentSortingInfo3d::Sorted {
                    mesh_center: Vec3::ZERO,
                    depth_bias: 0.0,
                },
                entity: (entity, *main_entity),
                pipeline,
                draw_function: draw,
                distance: 0.0,
                batch_range: 0..1,
                extra_index: PhaseItemExtraIndex::None,
                indexed: true,
            });
        }
    }
}

/// The mesh pipeline with the body shader and the instance buffer layout.
#[derive(Resource)]
struct BodyPipeline {
    mesh_pipeline: MeshPipeline,
}

fn init_body_pipeline(mut commands: Commands, mesh_pipeline: Res<MeshPipeline>) {
    commands.insert_resource(BodyPipeline {
        mesh_pipeline: mesh_pipeline.clone(),
    });
}

impl SpecializedMeshPipeline for BodyPipeline {
    type Key = MeshPipelineKey;

    fn specialize(
        &self,
        key: Self::Key,
        layout: &MeshVertexBufferLayoutRef,
    ) -> Result<RenderPipelineDescriptor, SpecializedMeshPipelineError> {
        let mut descriptor = self.mesh_pipeline.specialize(key, layout)?;
        descriptor.vertex.shader = SHADER;
        descriptor.vertex.buffers.push(VertexBufferLayout {
            array_stride: size_of::<InstanceData>() as u64,
            step_mode: VertexStepMode::Instance,
            // Locations 0–2 are the mesh's position, normal and uv.
            attributes: vec![
                VertexAttribute {
                    format: VertexFormat::Float32x3,
                    offset: 0,
                    shader_location: 3,
                },
                VertexAttribute {
                    format: VertexFormat::Float32x3,
                    offset: 12,
                    shader_location: 4,
                },
                VertexAttribute {
                    format: VertexFormat::Unorm8x4,
                    offset: 24,
                    shader_location: 5,
                },
            ],
        });
        if let Some(fragment) = descriptor.fragment.as_mut() {
            fragment.shader = SHADER;
        }
        Ok(descriptor)
    }
}

type DrawBodies = (
    SetItemPipeline,
    SetMeshViewBindGroup<0>,
    SetMeshViewBindingArrayBindGroup<1>,
    SetMeshBindGroup<2>,
    DrawBodiesInstanced,
);

struct DrawBodiesInstanced;

impl<P: PhaseItem> RenderCommand<P> for DrawBodiesInstanced {
    type Param = (
        SRes<RenderAssets<RenderMesh>>,
        SRes<RenderMeshInstances>,
        SRes<MeshAllocator>,
        SRes<BodyInstanceBuffer>,
    );
    type ViewQuery = ();
    type ItemQuery = ();

    fn render<'w>(
        item: &P,
        _view: (),
        _entity: Option<()>,
        (meshes, mesh_instances, allocator, instances): SystemParamItem<'w, '_, Self::Param>,
        pass: &mut TrackedRenderPass<'w>,
    ) -> RenderCommandResult {
        let allocator = allocator.into_inner();
        let instances = instances.into_inner();
        let (Some(buffer), length) = (&instances.buffer, instances.length) else {
            return RenderCommandResult::Skip;
        };
        if length == 0 {
            return RenderCommandResult::Skip;
        }
        let Some(mesh_instance) = mesh_instances.render_mesh_queue_data(item.main_entity()) else {
            return RenderCommandResult::Skip;
        };
        let mesh_id = mesh_instance.mesh_asset_id();
        let Some(gpu_mesh) = meshes.into_inner().get(mesh_id) else {
            return RenderCommandResult::Skip;
        };
        let Some(vertices) = allocator.mesh_vertex_slice(&mesh_id) else {
            return RenderCommandResult::Skip;
        };
        pass.set_vertex_buffer(0, vertices.buffer.slice(..));
        pass.set_vertex_buffer(1, buffer.slice(..));
        let instance_range = 0..length as u32;
        match &gpu_mesh.buffer_info {
            RenderMeshBufferInfo::Indexed { index_format, count } => {
                let Some(indices) = allocator.mesh_index_slice(&mesh_id) else {
                    return RenderCommandResult::Skip;
                };
                pass.set_index_buffer(indices.buffer.slice(..), *index_format);
                pass.draw_indexed(
                    indices.range.start..(indices.range.start + count),
                    vertices.range.start as i32,
                    instance_range,
                );
            }
            RenderMeshBufferInfo::NonIndexed => pass.draw(vertices.range, instance_range),
        }
        if let Some(slot) = &instances.slot {
            slot.count_draw();
        }
        RenderCommandResult::Success
    }
}
