//! The panel's drawing and camera sections, and the selected body.

use bevy::prelude::*;
use bevy_egui::egui;

use crate::components::{BodyId, GravityRole, Mass, Position, Velocity};
use crate::resources::DrawMethod;
use crate::ui::session::{CameraMode, SandboxSettings, TRAIL_COUNT_RANGE, TrailChoice};
use crate::ui::view::{Selection, selected_info};
use crate::ui::widgets::slider;

pub(super) fn rendering(ui: &mut egui::Ui, settings: &mut SandboxSettings) {
    ui.label("Rendering");
    ui.checkbox(&mut settings.render_bodies, "render bodies");
    ui.checkbox(&mut settings.visual_effects, "visual effects (color by state)");
    ui.checkbox(&mut settings.show_collision_boxes, "planet collision box");
    ui.horizontal(|ui| {
        for method in DrawMethod::ALL {
            ui.radio_value(&mut settings.render_method, method, method.label());
        }
    });
    ui.checkbox(&mut settings.vsync, "vsync")
        .on_hover_text("off: draw as fast as possible, as the thesis measured");
    ui.horizontal(|ui| {
        ui.label("trails:");
        egui::ComboBox::from_id_salt("trails")
            .selected_text(settings.trails.name())
            .show_ui(ui, |ui| {
                for choice in TrailChoice::ALL {
                    ui.selectable_value(&mut settings.trails, choice, choice.name());
                }
            });
    })
    .response
    .on_hover_text("the selected body always draws its path");
    if settings.trails != TrailChoice::Off {
        ui.add(slider(&mut settings.trail_count, TRAIL_COUNT_RANGE).text("bodies with trails"));
    }
}

pub(super) fn camera(
    ui: &mut egui::Ui,
    settings: &mut SandboxSettings,
    selection: &mut Selection,
    bodies: &Query<(&BodyId, &Mass, &Velocity, &Position, Option<&GravityRole>)>,
) {
    ui.label("Camera (C cycles)");
    ui.horizontal(|ui| {
        for mode in CameraMode::ALL {
            ui.radio_value(&mut settings.camera, mode, mode.name());
        }
    });
    ui.small(match settings.camera {
        CameraMode::Orbit | CameraMode::Follow => "drag: orbit · right-drag: pan · wheel: zoom",
        CameraMode::Fly => "WASD move · Q/E down/up · Shift fast · right-drag look",
    });
    match selected_info(selection, bodies) {
        Some(info) => {
            ui.label(format!("selected body {}", info.id.0));
            ui.label(format!("mass {:.3}   speed {:.3}", info.mass, info.speed));
            ui.label(format!(
                "role {}   at ({:.0}, {:.0}, {:.0})",
                info.role.name(),
                info.position.x,
                info.position.y,
                info.position.z
            ));
            if ui.button("clear selection").clicked() {
                selection.clear();
            }
        }
        None => {
            ui.small("click a body to select it");
        }
    }
}
