//! The window's system sets: the phases of a frame. Their order is chained
//! in one place, `ui/app.rs`; each plugin orders its own systems within a
//! phase.

use bevy::prelude::*;

/// The window's work in a frame.
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SandboxSystems {
    /// `Update`: rebuild the scene when a restart was asked for.
    BuildScene,
    /// `Update`: the tools' actions, each recorded as an event.
    Tools,
    /// `Update`: apply the live settings, run the updates the clock owes.
    Simulate,
    /// `Update`: cameras and picking, on the bodies where they are now.
    View,
    /// `EguiPrimaryContextPass`: the settings panel (left).
    Panel,
    /// `EguiPrimaryContextPass`: the HUD (a window over the view).
    Hud,
}
