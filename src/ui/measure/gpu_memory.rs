//! GPU memory for the window's scripted runs (benchmark `Render` runs):
//! what wgpu's allocator reports where the backend has one (Vulkan, DX12,
//! Metal), else the bytes Kessler itself holds in GPU buffers — labelled
//! with their source either way. Read in the render world now and then,
//! shared with the main world.

use std::sync::{Arc, Mutex, PoisonError};

use bevy::prelude::*;
use bevy::render::renderer::{RenderAdapterInfo, RenderDevice};

use crate::ui::draw::BodyInstanceBuffer;

/// Frames between two readings (an allocator report lists every
/// allocation, so it is not free).
const EVERY: u64 = 10;

/// The latest reading.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct GpuMemoryReading {
    /// Bytes of GPU memory in use.
    pub bytes: u64,
    /// Bytes the allocator holds, in use or not (0 if unknown).
    pub reserved: u64,
    /// Where the figure comes from.
    pub source: String,
    /// The GPU adapter's name and backend.
    pub adapter: String,
}

/// The latest reading, shared by the render world (which writes it) and
/// the main world.
#[derive(Resource, Clone, Debug, Default)]
pub struct GpuMemory(Arc<Mutex<GpuMemoryReading>>);

impl GpuMemory {
    /// The latest reading.
    pub fn reading(&self) -> GpuMemoryReading {
        self.0.lock().unwrap_or_else(PoisonError::into_inner).clone()
    }
}

/// Reads the GPU memory every [`EVERY`] frames.
pub struct GpuMemoryPlugin;

impl Plugin for GpuMemoryPlugin {
    fn build(&self, app: &mut App) {
        super::share_with_render_world(app, GpuMemory::default(), read_gpu_memory);
    }
}

fn read_gpu_memory(
    device: Res<RenderDevice>,
    adapter: Res<RenderAdapterInfo>,
    instances: Option<Res<BodyInstanceBuffer>>,
    memory: Res<GpuMemory>,
    mut frame: Local<u64>,
) {
    *frame += 1;
    if *frame % EVERY != 1 {
        return;
    }
    let info = &adapter.0;
    let (bytes, reserved, source) = match device.wgpu_device().generate_allocator_report() {
        Some(report) => (
            report.total_allocated_bytes,
            report.total_reserved_bytes,
            "wgpu allocator".to_owned(),
        ),
        None => (
            instances.map_or(0, |b| b.bytes()),
            0,
            "kessler's own GPU buffers (instances only; the backend has no allocator report)".to_owned(),
        ),
    };
    *memory.0.lock().unwrap_or_else(PoisonError::into_inner) = GpuMemoryReading {
        bytes,
        reserved,
        source,
        adapter: format!("{} ({:?})", info.name, info.backend),
    };
}
