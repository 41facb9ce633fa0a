//! What the two halves of the instanced drawing share: the instances of
//! this frame, handed from the main world to the render world without a
//! copy.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

use bevy::ecs::query::QueryItem;
use bevy::prelude::*;
use bevy::render::extract_component::ExtractComponent;
use bevy::render::sync_component::SyncComponent;
use bytemuck::{Pod, Zeroable};

/// One cube as the GPU sees it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct InstanceData {
    /// Center, world units.
    pub center: [f32; 3],
    /// Half the edge lengths, world units.
    pub half_extents: [f32; 3],
    /// sRGB color bytes, alpha unused.
    pub color: [u8; 4],
}

/// What the main world and the render world share: this frame's instances
/// and a count of instanced draws actually submitted.
#[derive(Debug, Default)]
pub struct InstanceSlot {
    data: Mutex<Vec<InstanceData>>,
    /// Bumped by every publish; the render world uploads only new data.
    generation: AtomicU64,
    draws: AtomicU64,
}

impl InstanceSlot {
    /// Puts `instances` in the slot, handing back the previous vector for
    /// reuse (no allocation in steady state).
    pub fn publish(&self, instances: &mut Vec<InstanceData>) {
        let mut slot = self.data.lock().unwrap_or_else(PoisonError::into_inner);
        std::mem::swap(&mut *slot, instances);
        self.generation.fetch_add(1, Ordering::Release);
    }

    /// The instances last published, and how many publishes there were.
    pub fn read(&self) -> (MutexGuard<'_, Vec<InstanceData>>, u64) {
        let data = self.data.lock().unwrap_or_else(PoisonError::into_inner);
        (data, self.generation.load(Ordering::Acquire))
    }

    /// Counts an instanced draw submitted to the GPU.
    pub fn count_draw(&self) {
        self.draws.fetch_add(1, Ordering::Relaxed);
    }

    /// Instanced draws submitted so far (0 until the pipeline is compiled).
    pub fn draws(&self) -> u64 {
        self.draws.load(Ordering::Relaxed)
    }
}

/// The entity that stands for all instanced bodies: a unit cube mesh plus
/// the shared slot.
#[derive(Component, Clone)]
pub struct InstancedBodies(pub Arc<InstanceSlot>);

impl SyncComponent for InstancedBodies {
    type Target = Self;
}

impl ExtractComponent for InstancedBodies {
    type QueryData = &'static InstancedBodies;
    type QueryFilter = ();
    type Out = Self;

    fn extract_component(item: QueryItem<'_, '_, Self::QueryData>) -> Option<Self> {
        Some(item.clone())
    }
}
