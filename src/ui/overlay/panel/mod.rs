//! The settings panel: every thesis setting, the run controls, the scenario
//! picker, the camera and the selected body, a section a file; the tools'
//! section is the tools' own ([`crate::ui::tools::tools_section`]). The run
//! keys (Space, N, R) are a system of their own.

mod execution;
mod physics;
mod rendering;
mod run;
mod scene;

use std::path::PathBuf;

use bevy::ecs::system::SystemParam;
use bevy::prelude::*;
use bevy_egui::input::EguiWantsInput;
use bevy_egui::{EguiContexts, EguiPrimaryContextPass, egui};

use super::cascade::{Cascade, totals_readout};
use crate::components::{BodyId, GravityRole, Mass, Position, Velocity};
use crate::execution::Execution;
use crate::systems::UpdateCount;
use crate::ui::session::{SandboxSettings, SandboxState, SnapshotSave};
use crate::ui::sets::SandboxSystems;
use crate::ui::tools::{Checkpoints, ToolAction, ToolSettings, tools_section};
use crate::ui::view::Selection;
use execution::execution;
use physics::physics;
use rendering::{camera, rendering};
use run::run_controls;
pub use scene::{SCENARIO_DIR, scenario_files};
use scene::{SaveField, SessionField, save_scenario, save_session, scene};

/// The settings panel at the left, and the run keys (Space, N, R); the
/// tools' keys are the tools' own.
pub struct PanelPlugin;

impl Plugin for PanelPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(
            EguiPrimaryContextPass,
            (run_keys, panel).chain().in_set(SandboxSystems::Panel),
        );
    }
}

/// The run keys: Space pauses and resumes, N steps, R restarts (unless a
/// text field has the keyboard).
fn run_keys(keys: Res<ButtonInput<KeyCode>>, egui: Res<EguiWantsInput>, mut state: ResMut<SandboxState>) {
    if egui.wants_keyboard_input() {
        return;
    }
    if keys.just_pressed(KeyCode::Space) {
        state.paused = !state.paused;
    }
    if keys.just_pressed(KeyCode::KeyN) {
        state.step_requested = true;
    }
    if keys.just_pressed(KeyCode::KeyR) {
        state.restart_requested = true;
    }
}

/// Text of the "any path" field of the scenario picker.
#[derive(Default)]
struct PathField(String);

/// What the tools' section reads and writes.
#[derive(SystemParam)]
struct Tools<'w> {
    settings: ResMut<'w, ToolSettings>,
    actions: MessageWriter<'w, ToolAction>,
    checkpoints: Res<'w, Checkpoints>,
    updates: Res<'w, UpdateCount>,
}

/// The text fields and lists the panel keeps between frames.
#[derive(SystemParam)]
struct Fields<'s> {
    path: Local<'s, PathField>,
    files: Local<'s, Option<Vec<PathBuf>>>,
    save: Local<'s, SaveField>,
    session: Local<'s, SessionField>,
}

/// What the panel edits of the session.
#[derive(SystemParam)]
struct Session<'w> {
    settings: ResMut<'w, SandboxSettings>,
    state: ResMut<'w, SandboxState>,
    save: ResMut<'w, SnapshotSave>,
}

/// What the panel shows of the running simulation and the view.
#[derive(SystemParam)]
struct Shown<'w, 's> {
    selection: ResMut<'w, Selection>,
    bodies: Query<
        'w,
        's,
        (
            &'static BodyId,
            &'static Mass,
            &'static Velocity,
            &'static Position,
            Option<&'static GravityRole>,
        ),
    >,
    cascade: Res<'w, Cascade>,
    running: Res<'w, Execution>,
}

/// The panel: edits a copy of the settings, so the resource is marked
/// changed only by real edits.
fn panel(mut contexts: EguiContexts, session: Session, shown: Shown, mut tools: Tools, mut fields: Fields) -> Result {
    let ctx = contexts.ctx_mut()?;
    let Session {
        mut settings,
        mut state,
        mut save,
    } = session;
    let Shown {
        mut selection,
        bodies,
        cascade,
        running,
    } = shown;
    let mut edited = settings.clone();
    let mut viewport = egui::Ui::new(
        ctx.clone(),
        "viewport".into(),
        egui::UiBuilder::new()
            .layer_id(egui::LayerId::background())
            .max_rect(ctx.viewport_rect()),
    );
    egui::Panel::left("settings")
        .default_size(270.0)
        .show_inside(&mut viewport, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                ui.heading("Kessler");
                ui.label(format!("scenario: {}", state.scenario.origin));
                run_controls(ui, &mut edited, &mut state);
                ui.separator();
                execution(ui, &mut edited, &running);
                ui.separator();
                physics(ui, &mut edited.physics);
                totals_readout(ui, &cascade.totals, &cascade.absorbed);
                ui.separator();
                let mut values = tools.settings.clone();
                let has_selection = selection.entity.is_some();
                let sent = tools_section(ui, &mut values, has_selection, &tools.checkpoints, tools.updates.0);
                if let Some(problem) = &state.tool_problem {
                    ui.colored_label(egui::Color32::from_rgb(255, 200, 90), problem);
                }
                if values != *tools.settings {
                    *tools.settings = values;
                }
                for action in sent {
                    tools.actions.write(action);
                }
                ui.separator();
                scene(ui, &mut edited, &mut state, &mut fields.path.0, &mut fields.files);
                save_scenario(ui, &mut save, &mut fields.save.0);
                save_session(ui, &mut tools.actions, &mut fields.session.0);
                ui.separator();
                rendering(ui, &mut edited);
                ui.separator();
                camera(ui, &mut edited, &mut selection, &bodies);
            });
        });
    if edited != *settings {
        *settings = edited;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::execution::{ExecutionMode, SplitPolicy};
    use crate::resources::GravityMethod;
    use crate::ui::session::{MAX_BODY_COUNT, TrailChoice, max_threads};

    #[test]
    fn an_idle_panel_changes_no_setting_even_beyond_its_widgets_ranges() {
        // Allowed values the widgets do not reach (see `widgets.rs`); a
        // change here would be saved as if the user had made it.
        let mut loaded = SandboxSettings {
            trails: TrailChoice::Fastest,
            ..SandboxSettings::default()
        };
        loaded.execution.threads = Some(max_threads());
        loaded.execution.split = Some(SplitPolicy::Above(MAX_BODY_COUNT * 10));
        loaded.physics.shatter_fragments = 50;
        loaded.physics.shatter_threshold = 100.0;
        loaded.physics.gravity_method = GravityMethod::Tree { theta: 1.9 };
        let mut settings = loaded.clone();
        let mut state = SandboxState::new(crate::scenario::Scenario::builtin_default(), &settings);
        let (mut path_field, mut files) = (String::new(), Some(Vec::new()));
        let running = Execution::new(ExecutionMode::Parallel, 2).unwrap();
        let ctx = egui::Context::default();
        for _ in 0..3 {
            let _ = ctx.run_ui(egui::RawInput::default(), |ui| {
                run_controls(ui, &mut settings, &mut state);
                execution(ui, &mut settings, &running);
                physics(ui, &mut settings.physics);
                scene(ui, &mut settings, &mut state, &mut path_field, &mut files);
                rendering(ui, &mut settings);
            });
        }
        assert_eq!(settings, loaded);
    }
}
