//! The HUD: frame rate, update rate (target against achieved, dropped),
//! bodies, pairs, shatters, and per-stage timings with a rolling plot.

use bevy::ecs::system::SystemParam;
use bevy::prelude::*;
use bevy_egui::{EguiContexts, EguiPrimaryContextPass, egui};

use super::cascade::{Cascade, curve_plot};
use crate::components::BodyId;
use crate::resources::GravityMethod;
use crate::systems::{CollisionStats, GravityInUse, STAGES, StageTimings, Timing, UpdateCount};
use crate::ui::measure::{FrameStats, HISTORY};
use crate::ui::session::SandboxSettings;
use crate::ui::session::SandboxState;
use crate::ui::session::SettingsFile;
use crate::ui::session::UpdateClock;
use crate::ui::sets::SandboxSystems;

/// The HUD window at the top right.
pub struct HudPlugin;

impl Plugin for HudPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(EguiPrimaryContextPass, hud.in_set(SandboxSystems::Hud));
    }
}

/// A stage's color in the HUD, from the stage list.
fn stage_color(rgb: [u8; 3]) -> egui::Color32 {
    let [r, g, b] = rgb;
    egui::Color32::from_rgb(r, g, b)
}

/// What the HUD shows of the window's session: the settings, the run's
/// state, the settings file's warnings, the frames and the update clock.
#[derive(SystemParam)]
struct Window<'w> {
    settings: Res<'w, SandboxSettings>,
    state: Res<'w, SandboxState>,
    file: Res<'w, SettingsFile>,
    stats: Res<'w, FrameStats>,
    clock: Res<'w, UpdateClock>,
}

/// What the HUD shows of the simulation.
#[derive(SystemParam)]
struct Run<'w, 's> {
    timings: Res<'w, StageTimings>,
    collisions: Res<'w, CollisionStats>,
    cascade: Res<'w, Cascade>,
    gravity: Res<'w, GravityInUse>,
    bodies: Query<'w, 's, (), With<BodyId>>,
    updates: Res<'w, UpdateCount>,
}

fn hud(mut contexts: EguiContexts, window: Window, run: Run) -> Result {
    let ctx = contexts.ctx_mut()?;
    let Window {
        settings,
        state,
        file,
        stats,
        clock,
    } = window;
    let Run {
        timings,
        collisions,
        cascade,
        gravity,
        bodies,
        updates,
    } = run;
    egui::Window::new("HUD")
        .anchor(egui::Align2::RIGHT_TOP, [-8.0, 8.0])
        .resizable(false)
        .collapsible(true)
        .show(ctx, |ui| {
            ui.label(format!("{:.0} FPS ({:.1} ms/frame)", stats.fps(), stats.smoothed * 1e3));
            let target = f64::from(settings.updates_per_second) * f64::from(settings.speed);
            let achieved = clock.achieved_ups();
            let status = if state.paused { " — paused" } else { "" };
            ui.label(format!("UPS {achieved:.0} of {target:.0}{status}"));
            ui.label(format!("update {}", updates.0));
            let dropped = clock.dropped_per_second();
            if dropped > 0.5 {
                ui.colored_label(
                    egui::Color32::from_rgb(255, 170, 60),
                    format!("dropping {dropped:.0} updates/s (can't keep up)"),
                );
            }
            ui.label(format!("bodies {}", bodies.iter().len()));
            ui.label(format!(
                "pairs {}   shatters {} (total {})",
                collisions.pairs, collisions.shatters, collisions.shatters_total
            ));
            if collisions.reentries_total > 0 {
                ui.label(format!(
                    "reentries {} (total {}): absorbed by a planet",
                    collisions.reentries, collisions.reentries_total
                ));
            }
            if collisions.refused_total > 0 {
                ui.label(format!(
                    "refused shatters {} (total {}): size floor, body budget or a fragment's first update",
                    collisions.refused_shatters, collisions.refused_total
                ));
            }
            ui.label(if settings.physics.stages.gravity {
                gravity_line(&gravity)
            } else {
                "gravity: off".to_owned()
            });
            ui.separator();
            stage_table(ui, &timings);
            stage_plot(ui, &stats);
            ui.label("Kessler curve");
            curve_plot(ui, &cascade);
            if let Some(warning) = &file.warning {
                ui.separator();
                ui.colored_label(egui::Color32::from_rgb(255, 170, 60), warning);
            }
        });
    Ok(())
}

/// How gravity was summed in the last update, and whether `Auto` chose it.
fn gravity_line(in_use: &GravityInUse) -> String {
    let method = match in_use.method {
        GravityMethod::Tree { theta } => format!("tree θ {theta}"),
        GravityMethod::Direct | GravityMethod::Auto => "direct sum".to_owned(),
    };
    let auto = if in_use.auto { " (auto)" } else { "" };
    format!("gravity: {method}{auto}, {} sources", in_use.sources)
}

/// Last and mean time of each stage and of the whole update, in the
/// stages' colors.
fn stage_table(ui: &mut egui::Ui, timings: &StageTimings) {
    let row = |ui: &mut egui::Ui, timing: &Timing| {
        ui.label(format!("{:.3}", timing.last_ns as f64 / 1e6));
        ui.label(format!("{:.3}", timing.mean_ns / 1e6));
        ui.end_row();
    };
    egui::Grid::new("stage_times").num_columns(3).show(ui, |ui| {
        ui.label("stage");
        ui.label("last ms");
        ui.label("mean ms");
        ui.end_row();
        for stage in &STAGES {
            ui.colored_label(stage_color(stage.color), stage.name);
            row(ui, timings.stage(stage.stage));
        }
        ui.label("update");
        row(ui, &timings.update);
    });
}

/// Stacked per-stage update time over the last updates.
fn stage_plot(ui: &mut egui::Ui, stats: &FrameStats) {
    let (rect, _) = ui.allocate_exact_size(egui::vec2(260.0, 70.0), egui::Sense::hover());
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 2.0, egui::Color32::from_black_alpha(90));
    let history = &stats.stage_history;
    let peak = history
        .iter()
        .map(|s| s.iter().sum::<f32>())
        .fold(0.0f32, f32::max)
        .max(1e-3);
    let x = |i: usize| rect.left() + rect.width() * i as f32 / (HISTORY - 1) as f32;
    let y = |ms: f32| rect.bottom() - rect.height() * (ms / peak).min(1.0);
    let mut below = vec![0.0f32; history.len()];
    for (k, stage) in STAGES.iter().enumerate() {
        let mut top: Vec<egui::Pos2> = Vec::with_capacity(history.len());
        for (i, sample) in history.iter().enumerate() {
            below[i] += sample[k];
            top.push(egui::pos2(x(i), y(below[i])));
        }
        if top.len() > 1 {
            painter.add(egui::Shape::line(top, egui::Stroke::new(1.5, stage_color(stage.color))));
        }
    }
    painter.text(
        rect.left_top() + egui::vec2(4.0, 2.0),
        egui::Align2::LEFT_TOP,
        format!("{peak:.2} ms"),
        egui::FontId::monospace(10.0),
        egui::Color32::LIGHT_GRAY,
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_gravity_line_says_what_was_used_and_whether_auto_chose_it() {
        let tree = GravityInUse {
            method: GravityMethod::Tree { theta: 0.5 },
            auto: true,
            sources: 1834,
        };
        assert_eq!(gravity_line(&tree), "gravity: tree θ 0.5 (auto), 1834 sources");
        let direct = GravityInUse {
            method: GravityMethod::Direct,
            auto: false,
            sources: 2,
        };
        assert_eq!(gravity_line(&direct), "gravity: direct sum, 2 sources");
    }
}
