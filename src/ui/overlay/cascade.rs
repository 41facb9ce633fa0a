//! Looking at the cascade: the Kessler curve (body count and shatters per
//! 100 updates over the whole run) for the HUD, and the totals the panel
//! shows (mass, kinetic energy, momentum), refreshed after each frame that
//! ran updates.

use bevy::prelude::*;
use bevy_egui::egui;

use crate::components::{Mass, Velocity};
use crate::physics::Totals;
use crate::systems::{Absorbed, CollisionStats};
use crate::ui::session::SandboxState;
use crate::ui::session::UpdateClock;
use crate::ui::sets::SandboxSystems;

/// Updates per point of the curve at the start of a run.
pub const CURVE_BUCKET: u64 = 100;
/// Most points the curve keeps; beyond, neighbours merge (the bucket
/// doubles), so a long run still fits whole.
pub const CURVE_POINTS: usize = 512;

/// One point of the Kessler curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurvePoint {
    /// Updates run when it was taken.
    pub update: u64,
    /// Bodies then.
    pub bodies: u64,
    /// Shatters per 100 updates since the previous point.
    pub shatters_per_100: f64,
}

/// The run's curve and the latest totals.
#[derive(Resource, Debug, Default)]
pub struct Cascade {
    /// The curve, oldest first.
    pub curve: Vec<CurvePoint>,
    /// Updates per point now.
    bucket: u64,
    /// Totals over all bodies after the last update seen.
    pub totals: Totals,
    /// What absorbing bodies took by then.
    pub absorbed: Absorbed,
    /// Update count, total shatters and scene at the last point.
    last_point: (u64, u64),
    /// Update count and scene at the last look.
    seen: (u64, u64),
}

impl Cascade {
    /// Adds a point for `update` when a bucket has passed since the last;
    /// merges neighbours when the curve is full.
    pub fn observe(&mut self, update: u64, bodies: u64, shatters_total: u64) {
        if self.bucket == 0 {
            self.bucket = CURVE_BUCKET;
        }
        let (last_update, last_shatters) = self.last_point;
        if self.curve.is_empty() {
            self.curve.push(CurvePoint {
                update,
                bodies,
                shatters_per_100: 0.0,
            });
            self.last_point = (update, shatters_total);
            return;
        }
        if update < last_update + self.bucket {
            return;
        }
        let span = (update - last_update) as f64;
        self.curve.push(CurvePoint {
            update,
            bodies,
            shatters_per_100: shatters_total.saturating_sub(last_shatters) as f64 * 100.0 / span,
        });
        self.last_point = (update, shatters_total);
        if self.curve.len() > CURVE_POINTS {
            self.merge();
        }
    }

    /// Halves the curve: each pair of points after the first becomes one,
    /// at the later update, with the mean rate over both.
    fn merge(&mut self) {
        let mut merged = vec![self.curve[0]];
        let mut previous = self.curve[0].update;
        for pair in self.curve[1..].chunks(2) {
            let last = pair[pair.len() - 1];
            let span = (last.update - previous).max(1) as f64;
            let mut shatters = 0.0;
            let mut start = previous;
            for p in pair {
                shatters += p.shatters_per_100 * (p.update - start) as f64 / 100.0;
                start = p.update;
            }
            merged.push(CurvePoint {
                shatters_per_100: shatters * 100.0 / span,
                ..last
            });
            previous = last.update;
        }
        self.curve = merged;
        self.bucket *= 2;
    }
}

/// Keeps [`Cascade`] current.
pub struct CascadePlugin;

impl Plugin for CascadePlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<Cascade>()
            .add_systems(Update, observe_cascade.after(SandboxSystems::Simulate));
    }
}

/// After a frame that ran updates (or a rebuilt scene): the totals anew,
/// and a curve point when one is due.
fn observe_cascade(
    mut cascade: ResMut<Cascade>,
    clock: Res<UpdateClock>,
    state: Res<SandboxState>,
    collisions: Res<CollisionStats>,
    absorbed: Res<Absorbed>,
    bodies: Query<(&Mass, &Velocity)>,
) {
    let now = (clock.updates_total, state.generation);
    if cascade.seen == now && cascade.totals.bodies > 0 {
        return;
    }
    if cascade.seen.1 != now.1 {
        *cascade = Cascade::default();
    }
    cascade.seen = now;
    cascade.totals = Totals::of(bodies.iter().map(|(m, v)| (m.0, v.0)));
    cascade.absorbed = *absorbed;
    let count = cascade.totals.bodies;
    cascade.observe(clock.updates_total, count, collisions.shatters_total);
}

/// The Kessler curve: body count (white, between the run's fewest and
/// most) and shatters per 100 updates (orange, from zero) over the whole
/// run, updates along x.
pub fn curve_plot(ui: &mut egui::Ui, cascade: &Cascade) {
    let (rect, _) = ui.allocate_exact_size(egui::vec2(260.0, 70.0), egui::Sense::hover());
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 2.0, egui::Color32::from_black_alpha(90));
    let curve = &cascade.curve;
    let (Some(first), Some(last)) = (curve.first(), curve.last()) else {
        return;
    };
    let span = (last.update - first.update).max(1) as f32;
    let x = |u: u64| rect.left() + rect.width() * (u - first.update) as f32 / span;
    // Bodies between the run's fewest and most; shatters from zero.
    let fewest = curve.iter().map(|p| p.bodies).min().unwrap_or(0) as f32;
    let most = curve.iter().map(|p| p.bodies).max().unwrap_or(0) as f32;
    let most_shatters = curve.iter().map(|p| p.shatters_per_100).fold(1e-9, f64::max) as f32;
    let plot_height = rect.height() - 14.0;
    let y = |share: f32| rect.bottom() - 2.0 - plot_height * share.clamp(0.0, 1.0);
    let series = |share: &dyn Fn(&CurvePoint) -> f32| -> Vec<egui::Pos2> {
        curve.iter().map(|p| egui::pos2(x(p.update), y(share(p)))).collect()
    };
    let orange = egui::Color32::from_rgb(255, 150, 50);
    painter.add(egui::Shape::line(
        series(&|p| p.shatters_per_100 as f32 / most_shatters),
        egui::Stroke::new(1.5, orange),
    ));
    let body_share = |p: &CurvePoint| {
        if most > fewest {
            (p.bodies as f32 - fewest) / (most - fewest)
        } else {
            0.5
        }
    };
    painter.add(egui::Shape::line(
        series(&body_share),
        egui::Stroke::new(1.5, egui::Color32::WHITE),
    ));
    let font = egui::FontId::monospace(10.0);
    painter.text(
        rect.left_top() + egui::vec2(4.0, 1.0),
        egui::Align2::LEFT_TOP,
        format!("bodies {fewest:.0}–{most:.0}"),
        font.clone(),
        egui::Color32::WHITE,
    );
    painter.text(
        rect.right_top() + egui::vec2(-4.0, 1.0),
        egui::Align2::RIGHT_TOP,
        format!("shatters/100 ≤ {most_shatters:.0}"),
        font,
        orange,
    );
}

/// The totals, as the panel shows them.
pub fn totals_readout(ui: &mut egui::Ui, totals: &Totals, absorbed: &Absorbed) {
    let p = totals.momentum;
    ui.label(format!("total mass {:.6e}", totals.mass))
        .on_hover_text("kept by bouncing and shattering; with the absorbed mass, by absorbing too");
    if absorbed.mass > 0.0 {
        ui.label(format!("absorbed mass {:.6e}", absorbed.mass))
            .on_hover_text("taken by planets that absorb what falls on them (re-entries)");
    }
    ui.label(format!("kinetic energy {:.6e}", totals.kinetic_energy))
        .on_hover_text("kept by bounces; a shatter loses the pair's relative motion and gains the fragments' spread; gravity trades it with potential energy");
    ui.label(format!("momentum ({:.4e}, {:.4e}, {:.4e})", p.x, p.y, p.z))
        .on_hover_text("kept by bouncing and shattering; fixed sources (the planet) change it");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_per_bucket_with_the_shatter_rate_since_the_last() {
        let mut c = Cascade::default();
        c.observe(0, 10, 0);
        c.observe(50, 12, 3);
        c.observe(100, 20, 8);
        c.observe(150, 30, 9);
        c.observe(250, 40, 20);
        let points: Vec<(u64, u64, f64)> = c
            .curve
            .iter()
            .map(|p| (p.update, p.bodies, p.shatters_per_100))
            .collect();
        assert_eq!(points, [(0, 10, 0.0), (100, 20, 8.0), (250, 40, 8.0)]);
    }

    #[test]
    fn a_long_run_fits_whole_with_the_same_total_shatters() {
        let mut c = Cascade::default();
        let mut shatters = 0;
        for update in 0..=(CURVE_BUCKET * 3 * CURVE_POINTS as u64) {
            shatters += update % 7;
            c.observe(update, update, shatters);
        }
        assert!(c.curve.len() <= CURVE_POINTS + 1, "{} points", c.curve.len());
        let last = c.curve.last().unwrap();
        assert_eq!(last.bodies, last.update, "the newest point stays exact");
        let mut counted = 0.0;
        for pair in c.curve.windows(2) {
            counted += pair[1].shatters_per_100 * (pair[1].update - pair[0].update) as f64 / 100.0;
        }
        let expected = (0..=last.update).map(|u| u % 7).sum::<u64>() as f64;
        assert!(expected > 0.5 * shatters as f64, "the curve reaches near the end");
        assert!(
            (counted - expected).abs() < 1e-6 * expected,
            "{counted} of {expected} shatters"
        );
    }
}
