//! Whether the render world has compiled every pipeline asked of it.
//!
//! Bevy compiles pipelines in the background, and a frame leaves out what a
//! pipeline still compiling would draw. Under a software renderer that is a
//! frame or two; on a fast GPU a hundred frames can pass while the driver
//! compiles (seen on an NVIDIA H200: a screenshot after 30 frames was
//! black, and a run's first frames were timed while nothing was drawn).
//! And a process that exits while the driver is compiling can crash in the
//! driver's compiler thread (the same machine: SIGSEGV at exit). So
//! scripted runs time frames, and films take pictures, only once the
//! pipelines are settled, and a scripted run ends only when they are.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use bevy::prelude::*;
use bevy::render::render_resource::PipelineCache;

/// True when, at the end of the last rendered frame, no pipeline was queued
/// or compiling. Written by the render world, read by the main world.
#[derive(Resource, Clone, Debug, Default)]
pub struct PipelinesSettled(Arc<AtomicBool>);

impl PipelinesSettled {
    /// Whether every pipeline asked for so far is compiled (or failed).
    pub fn get(&self) -> bool {
        self.0.load(Ordering::Acquire)
    }

    fn set(&self, settled: bool) {
        self.0.store(settled, Ordering::Release);
    }
}

/// Keeps [`PipelinesSettled`] up to date.
pub struct PipelinesPlugin;

impl Plugin for PipelinesPlugin {
    fn build(&self, app: &mut App) {
        super::share_with_render_world(app, PipelinesSettled::default(), note_pipelines);
    }
}

/// After the frame's pipeline queue was processed: settled when nothing is
/// waiting (a pipeline being compiled waits, one whose shader has yet to
/// load waits too).
fn note_pipelines(cache: Res<PipelineCache>, settled: Res<PipelinesSettled>) {
    settled.set(cache.waiting_pipelines().next().is_none());
}
