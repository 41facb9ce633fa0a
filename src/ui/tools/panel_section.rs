//! The tools' section of the panel: what each tool uses and the buttons
//! that send its action (the panel shows it; the tools are here).

use bevy_egui::egui;

use super::{CHECKPOINT_EVERY, Checkpoints, ToolAction, ToolSettings};
use crate::ui::session::SHATTER_FRAGMENTS_RANGE;
use crate::ui::widgets::{drag_value, slider};

/// The tools: what they use, and the actions the buttons ask for.
pub fn tools_section(
    ui: &mut egui::Ui,
    tools: &mut ToolSettings,
    has_selection: bool,
    checkpoints: &Checkpoints,
    updates: u64,
) -> Vec<ToolAction> {
    let mut sent = Vec::new();
    ui.label("Tools (each recorded as an event)");
    launch_tools(ui, tools, &mut sent);
    body_tools(ui, tools, has_selection, &mut sent);
    rewind_tool(ui, checkpoints, updates, &mut sent);
    sent
}

/// Launch: the ring and the satellites' size and mass.
fn launch_tools(ui: &mut egui::Ui, tools: &mut ToolSettings, sent: &mut Vec<ToolAction>) {
    ui.horizontal(|ui| {
        if ui
            .button("🚀 Launch")
            .on_hover_text("L: satellites on circular orbits around the heaviest planet")
            .clicked()
        {
            sent.push(tools.launch());
        }
        ui.add(drag_value(&mut tools.count, 1..=10_000).speed(1.0))
            .on_hover_text("satellites on the ring (1: one)");
        ui.label("on a ring");
    });
    ui.add(
        slider(&mut tools.altitude, 1.0..=5000.0)
            .logarithmic(true)
            .text("altitude"),
    );
    ui.add(slider(&mut tools.inclination, 0.0..=180.0).text("inclination °"));
    ui.horizontal(|ui| {
        ui.add(
            slider(&mut tools.half_size, 0.1..=10.0)
                .logarithmic(true)
                .text("half size"),
        );
    });
    ui.add(slider(&mut tools.mass, 0.01..=1000.0).logarithmic(true).text("mass"));
}

/// Fire, break up and remove: the tools that act on the selected body.
fn body_tools(ui: &mut egui::Ui, tools: &mut ToolSettings, has_selection: bool, sent: &mut Vec<ToolAction>) {
    ui.horizontal(|ui| {
        if ui
            .add_enabled(has_selection, egui::Button::new("🎯 Fire at selected"))
            .on_hover_text("F: an impactor at the selected body")
            .clicked()
        {
            sent.push(tools.fire());
        }
        ui.checkbox(&mut tools.from_camera, "from the camera");
    });
    ui.add(
        slider(&mut tools.fire_speed, 0.1..=100.0)
            .logarithmic(true)
            .text("speed"),
    );
    ui.add(
        slider(&mut tools.fire_distance, 1.0..=1000.0)
            .logarithmic(true)
            .text("distance"),
    );
    ui.horizontal(|ui| {
        if ui
            .add_enabled(has_selection, egui::Button::new("💥 Break up selected"))
            .on_hover_text("B")
            .clicked()
        {
            sent.push(tools.breakup());
        }
        if ui
            .add_enabled(has_selection, egui::Button::new("✖ Remove selected"))
            .on_hover_text("X or Delete")
            .clicked()
        {
            sent.push(ToolAction::Remove);
        }
    });
    ui.add(
        slider(&mut tools.fragments, SHATTER_FRAGMENTS_RANGE)
            .logarithmic(true)
            .text("fragments"),
    );
    ui.add(
        slider(&mut tools.breakup_speed, 0.01..=50.0)
            .logarithmic(true)
            .text("speed apart"),
    );
}

/// Rewind to the last checkpoint.
fn rewind_tool(ui: &mut egui::Ui, checkpoints: &Checkpoints, updates: u64, sent: &mut Vec<ToolAction>) {
    ui.horizontal(|ui| {
        let target = checkpoints.target(updates);
        let hover = match target {
            Some(at) => format!("Backspace: back to update {at}; the events recorded since are dropped"),
            None => "no checkpoint yet".to_owned(),
        };
        if ui
            .add_enabled(target.is_some(), egui::Button::new("⏪ Rewind"))
            .on_hover_text(hover)
            .clicked()
        {
            sent.push(ToolAction::Rewind);
        }
        ui.small(format!(
            "{} checkpoints, one every {CHECKPOINT_EVERY} updates",
            checkpoints.len()
        ));
    });
}
