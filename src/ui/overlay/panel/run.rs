//! The panel's run controls: pause, step, restart, the update rate and
//! the speed.

use bevy_egui::egui;

use crate::ui::session::{SPEED_RANGE, SandboxSettings, SandboxState, UPS_RANGE};
use crate::ui::widgets::slider;

pub(super) fn run_controls(ui: &mut egui::Ui, settings: &mut SandboxSettings, state: &mut SandboxState) {
    ui.horizontal(|ui| {
        let label = if state.paused { "▶ Resume" } else { "⏸ Pause" };
        if ui.button(label).on_hover_text("Space").clicked() {
            state.paused = !state.paused;
        }
        if ui
            .add_enabled(state.paused, egui::Button::new("Step"))
            .on_hover_text("N")
            .clicked()
        {
            state.step_requested = true;
        }
        if ui
            .button("⟲ Restart")
            .on_hover_text("R: rebuild the scene with these settings")
            .clicked()
        {
            state.restart_requested = true;
        }
    });
    ui.add(slider(&mut settings.updates_per_second, UPS_RANGE).text("updates/s"));
    ui.add(
        slider(&mut settings.speed, SPEED_RANGE)
            .logarithmic(true)
            .text("speed ×"),
    );
}
