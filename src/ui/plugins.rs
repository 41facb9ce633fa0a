//! [`SandboxPlugins`]: the window's own plugins, one per concern.

use bevy::app::PluginGroupBuilder;
use bevy::prelude::*;

use super::draw::{
    AtmospherePlugin, BackdropPlugin, CelestialsPlugin, InstancingPlugin, MeshesPlugin, PresentModePlugin, TrailsPlugin,
};
use super::measure::{FrameStatsPlugin, PipelinesPlugin};
use super::overlay::{CascadePlugin, HudPlugin, PanelPlugin};
use super::session::{DrivePlugin, ScenePlugin, SettingsFilePlugin, SnapshotSavePlugin};
use super::tools::ToolsPlugin;
use super::view::{CameraPlugin, SelectionPlugin};

/// Every plugin of the window beside Bevy's, egui's and the simulation's,
/// in the order they are built. Each orders its own systems within the
/// phases (`SandboxSystems`) that `app.rs` chains; a scripted run adds its
/// two plugins (GPU memory, capture) after these.
pub struct SandboxPlugins {
    /// Keep every frame time (a scripted run reports them).
    pub record_all_frames: bool,
}

impl PluginGroup for SandboxPlugins {
    fn build(self) -> PluginGroupBuilder {
        PluginGroupBuilder::start::<Self>()
            .add(ScenePlugin)
            .add(DrivePlugin)
            .add(BackdropPlugin)
            .add(AtmospherePlugin)
            .add(CelestialsPlugin)
            .add(InstancingPlugin)
            .add(MeshesPlugin)
            .add(PresentModePlugin)
            .add(CameraPlugin)
            .add(SelectionPlugin)
            .add(ToolsPlugin)
            .add(PanelPlugin)
            .add(HudPlugin)
            .add(FrameStatsPlugin {
                record_all: self.record_all_frames,
            })
            .add(PipelinesPlugin)
            .add(SettingsFilePlugin)
            .add(SnapshotSavePlugin)
            .add(CascadePlugin)
            .add(TrailsPlugin)
    }
}
