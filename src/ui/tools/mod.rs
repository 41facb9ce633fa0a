//! The sandbox's tools (docs/design.md, "The window"): launch, fire, break
//! up, remove — each recorded as the event it makes — and rewind, with
//! their keys, the values the panel sets for them, scripted actions and
//! the dump at a scripted run's close. It depends on the session and the
//! view (the selection, the camera); the overlay's panel sends its
//! [`ToolAction`]s.

mod actions;
mod panel_section;
mod rewind;
mod script;

use bevy::prelude::*;
use bevy_egui::input::EguiWantsInput;

pub use actions::{ToolAction, apply_tool_actions, ring};
pub use panel_section::tools_section;
pub use rewind::{CHECKPOINT_BYTES, CHECKPOINT_EVERY, Checkpoints, rewind, take_checkpoints};
pub use script::{ActionScript, DumpAtClose, ScriptedAction, dump_at_close, send_scripted_actions};

use crate::ui::sets::SandboxSystems;

/// The values the tools use, set in the panel (not saved).
#[derive(Resource, Clone, Debug, PartialEq)]
pub struct ToolSettings {
    /// Launch: the gap between the planet's surface and a satellite.
    pub altitude: f32,
    /// Launch: the ring's tilt from the equator, degrees.
    pub inclination: f32,
    /// Launch: satellites on the ring (1: one).
    pub count: u32,
    /// Launch: half the edge of each satellite.
    pub half_size: f32,
    /// Launch: the mass of each.
    pub mass: f32,
    /// Fire: the impactor's speed towards the target.
    pub fire_speed: f32,
    /// Fire: its start distance.
    pub fire_distance: f32,
    /// Fire: from the camera's side, else a seeded direction.
    pub from_camera: bool,
    /// Break up: fragments.
    pub fragments: u32,
    /// Break up: their speed apart.
    pub breakup_speed: f32,
}

impl Default for ToolSettings {
    fn default() -> Self {
        Self {
            altitude: 300.0,
            inclination: 0.0,
            count: 1,
            half_size: 1.0,
            mass: 1.0,
            fire_speed: 8.0,
            fire_distance: 40.0,
            from_camera: true,
            fragments: 8,
            breakup_speed: 1.0,
        }
    }
}

impl ToolSettings {
    /// The launch these settings ask for.
    pub fn launch(&self) -> ToolAction {
        ToolAction::Launch {
            altitude: self.altitude,
            inclination: self.inclination,
            count: self.count,
            half_size: self.half_size,
            mass: self.mass,
        }
    }

    /// The fire these settings ask for.
    pub fn fire(&self) -> ToolAction {
        ToolAction::Fire {
            speed: self.fire_speed,
            distance: self.fire_distance,
            from_camera: self.from_camera,
        }
    }

    /// The breakup these settings ask for.
    pub fn breakup(&self) -> ToolAction {
        ToolAction::Breakup {
            fragments: self.fragments,
            speed: self.breakup_speed,
        }
    }
}

/// The tools: their message, keys, checkpoints, scripts.
pub struct ToolsPlugin;

impl Plugin for ToolsPlugin {
    fn build(&self, app: &mut App) {
        app.add_message::<ToolAction>()
            .init_resource::<ToolSettings>()
            .init_resource::<Checkpoints>()
            .init_resource::<ActionScript>()
            .add_systems(
                Update,
                (tool_keys, send_scripted_actions, apply_tool_actions)
                    .chain()
                    .in_set(SandboxSystems::Tools),
            )
            // Before the frame's tool actions: a checkpoint at update U
            // holds the state before every event of U, the recorded ones
            // included, which a rewind to it drops.
            .add_systems(
                Update,
                take_checkpoints
                    .after(SandboxSystems::BuildScene)
                    .before(SandboxSystems::Tools),
            )
            .init_resource::<crate::ui::session::OutputFailures>()
            .add_systems(Last, dump_at_close.run_if(resource_exists::<DumpAtClose>));
    }
}

/// The tools' keys: L launch, F fire, B break up, X or Delete remove,
/// Backspace rewind.
fn tool_keys(
    keys: Res<ButtonInput<KeyCode>>,
    egui: Res<EguiWantsInput>,
    tools: Res<ToolSettings>,
    mut actions: MessageWriter<ToolAction>,
) {
    if egui.wants_keyboard_input() {
        return;
    }
    let pressed = |key| keys.just_pressed(key);
    if pressed(KeyCode::KeyL) {
        actions.write(tools.launch());
    }
    if pressed(KeyCode::KeyF) {
        actions.write(tools.fire());
    }
    if pressed(KeyCode::KeyB) {
        actions.write(tools.breakup());
    }
    if pressed(KeyCode::KeyX) || pressed(KeyCode::Delete) {
        actions.write(ToolAction::Remove);
    }
    if pressed(KeyCode::Backspace) {
        actions.write(ToolAction::Rewind);
    }
}
