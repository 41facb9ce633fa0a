//! Vsync on or off, live: the window's present mode follows the setting
//! (`kessler run --vsync on|off`, the panel, the settings file).

use bevy::prelude::*;
use bevy::window::{PresentMode, PrimaryWindow};

use crate::ui::session::SandboxSettings;

/// Keeps the primary window's present mode in line with the vsync setting.
pub struct PresentModePlugin;

impl Plugin for PresentModePlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(Update, follow_vsync_setting);
    }
}

/// The present mode for a vsync setting: wait for the display's refresh, or
/// present as fast as possible (tearing allowed), falling back to what the
/// driver offers.
pub fn present_mode(vsync: bool) -> PresentMode {
    if vsync {
        PresentMode::AutoVsync
    } else {
        PresentMode::AutoNoVsync
    }
}

fn follow_vsync_setting(settings: Res<SandboxSettings>, mut windows: Query<&mut Window, With<PrimaryWindow>>) {
    let wanted = present_mode(settings.vsync);
    for mut window in &mut windows {
        if window.present_mode != wanted {
            window.present_mode = wanted;
        }
    }
}
