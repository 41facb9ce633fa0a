//! The panel's scene section: the body count, the seed, the scenario
//! picker (and the folder it lists), and saving a snapshot or a session.

use std::path::{Path, PathBuf};

use bevy::prelude::*;
use bevy_egui::egui;

use crate::maths::Rng;
use crate::ui::session::{MAX_BODY_COUNT, SandboxSettings, SandboxState, SnapshotSave};
use crate::ui::tools::ToolAction;
use crate::ui::widgets::drag_value;

/// Folder the scenario picker lists.
pub const SCENARIO_DIR: &str = "scenarios";

/// The scenario files in `dir` (sorted), for the picker.
pub fn scenario_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .into_iter()
        .flatten()
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "ron"))
        .collect();
    files.sort();
    files
}

pub(super) fn scene(
    ui: &mut egui::Ui,
    settings: &mut SandboxSettings,
    state: &mut SandboxState,
    path_field: &mut String,
    files: &mut Option<Vec<PathBuf>>,
) {
    ui.label("Scene (applies on restart)");
    let mut own_count = settings.body_count.is_some();
    ui.horizontal(|ui| {
        ui.checkbox(&mut own_count, "body count");
        let mut count = settings.body_count.unwrap_or_else(|| generated_count(state));
        ui.add_enabled(own_count, drag_value(&mut count, 0..=MAX_BODY_COUNT).speed(100.0));
        settings.body_count = own_count.then_some(count);
    });
    ui.horizontal(|ui| {
        ui.label("seed");
        ui.add(egui::DragValue::new(&mut settings.physics.seed));
        if ui.button("🎲 randomize").clicked() {
            settings.physics.seed = random_seed();
        }
    });
    scenario_picker(ui, settings, path_field, files);
    let pending = state.pending_restart(settings);
    if !pending.is_empty() {
        ui.colored_label(
            egui::Color32::from_rgb(255, 200, 90),
            format!("restart to apply: {}", pending.join(", ")),
        );
    }
    if let Some(error) = &state.error {
        ui.colored_label(egui::Color32::from_rgb(255, 110, 110), error);
    }
}

/// The scenario: one of `scenarios/`, the built-in one, or any path.
fn scenario_picker(
    ui: &mut egui::Ui,
    settings: &mut SandboxSettings,
    path_field: &mut String,
    files: &mut Option<Vec<PathBuf>>,
) {
    let files = files.get_or_insert_with(|| scenario_files(Path::new(SCENARIO_DIR)));
    let shown = settings
        .scenario
        .as_ref()
        .map_or_else(|| "built-in debris field".to_owned(), |p| p.display().to_string());
    egui::ComboBox::from_label("scenario")
        .selected_text(shown)
        .show_ui(ui, |ui| {
            ui.selectable_value(&mut settings.scenario, None, "built-in debris field");
            for file in files.iter() {
                ui.selectable_value(&mut settings.scenario, Some(file.clone()), file.display().to_string());
            }
        });
    ui.horizontal(|ui| {
        ui.add(
            egui::TextEdit::singleline(path_field)
                .hint_text("any scenario path")
                .desired_width(170.0),
        );
        if ui
            .add_enabled(!path_field.trim().is_empty(), egui::Button::new("use"))
            .clicked()
        {
            settings.scenario = Some(PathBuf::from(path_field.trim()));
        }
    });
}

/// Bodies the loaded scenario's generators make.
fn generated_count(state: &SandboxState) -> u64 {
    state.scenario.generators.iter().map(|g| g.count()).sum()
}

/// A fresh seed from the clock.
fn random_seed() -> u64 {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos() as u64);
    Rng::new(nanos).next_u64()
}

/// The snapshot file name the panel offers, edited in place.
pub(super) struct SaveField(pub(super) String);

impl Default for SaveField {
    fn default() -> Self {
        Self("snapshot.ron".into())
    }
}

/// "Save scenario…": the running state to a new scenario file.
pub(super) fn save_scenario(ui: &mut egui::Ui, save: &mut SnapshotSave, field: &mut String) {
    ui.horizontal(|ui| {
        ui.add(egui::TextEdit::singleline(field).desired_width(150.0));
        let button = ui
            .add_enabled(!field.trim().is_empty(), egui::Button::new("Save scenario…"))
            .on_hover_text(
                "every body and setting now, as a scenario file any command loads (never over an existing file)",
            );
        if button.clicked() {
            save.requested = Some(PathBuf::from(field.trim()));
        }
    });
    match &save.outcome {
        Some(Ok(done)) => {
            ui.small(done);
        }
        Some(Err(e)) => {
            ui.colored_label(egui::Color32::from_rgb(255, 110, 110), e);
        }
        None => {}
    }
}

/// The session file name the panel offers, edited in place.
pub(super) struct SessionField(pub(super) String);

impl Default for SessionField {
    fn default() -> Self {
        Self("session.ron".into())
    }
}

/// "Save session…": the scenario the scene started from with every event
/// so far (the tools' and the panel's included), to a new file.
pub(super) fn save_session(ui: &mut egui::Ui, actions: &mut MessageWriter<ToolAction>, field: &mut String) {
    ui.horizontal(|ui| {
        ui.add(egui::TextEdit::singleline(field).desired_width(150.0));
        let button = ui
            .add_enabled(!field.trim().is_empty(), egui::Button::new("Save session…"))
            .on_hover_text(
                "the scenario this scene started from with every event so far: `kessler headless` replays it \
                 exactly (never over an existing file)",
            );
        if button.clicked() {
            actions.write(ToolAction::SaveSession(PathBuf::from(field.trim())));
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn picker_lists_the_shipped_scenarios() {
        let files = scenario_files(Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios")));
        assert!(files.iter().any(|f| f.ends_with("debris_orbit.ron")), "{files:?}");
        assert!(files.windows(2).all(|w| w[0] <= w[1]));
    }
}
