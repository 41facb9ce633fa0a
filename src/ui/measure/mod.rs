//! The window measuring itself: frame times (the HUD's FPS and plots, and
//! every frame of a `--frames` run), GPU memory, whether the pipelines are
//! compiled, the scripted runs that close after N frames and write a
//! screenshot and a frame-time report, and films (a picture every K
//! updates). It reads the session and what the drawing holds on the GPU.

pub mod capture;
pub mod film;
pub mod frame_stats;
pub mod gpu_memory;
pub mod picture;
pub mod pipelines;

pub use capture::{CapturePlugin, ScriptedRun};
pub use film::{Film, FilmPlugin};
pub use frame_stats::{FrameStats, FrameStatsPlugin, HISTORY};
pub use gpu_memory::GpuMemoryPlugin;
pub use pipelines::{PipelinesPlugin, PipelinesSettled};

use bevy::ecs::system::ScheduleSystem;
use bevy::prelude::*;
use bevy::render::{Render, RenderApp, RenderSystems};

/// Puts `shared` (a handle both worlds hold) into the main world and the
/// render world, and runs `writer` in the render world at the end of each
/// frame (`RenderSystems::Cleanup`), where it writes what the main world
/// reads. Without a render world (no renderer) only the main world gets it.
fn share_with_render_world<R: Resource + Clone, M>(
    app: &mut App,
    shared: R,
    writer: impl IntoScheduleConfigs<ScheduleSystem, M>,
) {
    app.insert_resource(shared.clone());
    if let Some(render_app) = app.get_sub_app_mut(RenderApp) {
        render_app
            .insert_resource(shared)
            .add_systems(Render, writer.in_set(RenderSystems::Cleanup));
    }
}
