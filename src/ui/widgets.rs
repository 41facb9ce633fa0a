//! The panel's number widgets: they never change a value the user did not
//! edit.
//!
//! egui's sliders and ranged drag values clamp the value they show into
//! their range on every frame, edited or not; a value from the settings file
//! or a scenario beyond a slider's (convenient, narrower) range would be
//! changed silently, and the changed setting saved. These widgets clamp
//! only what the user enters. The bounds a value is held to are checked
//! once, where it is loaded ([`SandboxSettings::sanitize`](crate::ui::session::SandboxSettings::sanitize)),
//! with a warning.

use std::ops::RangeInclusive;

use bevy_egui::egui::{self, emath::Numeric};

/// A slider over `range` that leaves a value outside it as it is until the
/// user moves it.
pub fn slider<Num: Numeric>(value: &mut Num, range: RangeInclusive<Num>) -> egui::Slider<'_> {
    egui::Slider::new(value, range).clamping(egui::SliderClamping::Edits)
}

/// A drag value limited to `range` for what the user enters, leaving a value
/// outside it as it is.
pub fn drag_value<Num: Numeric>(value: &mut Num, range: RangeInclusive<Num>) -> egui::DragValue<'_> {
    egui::DragValue::new(value).range(range).clamp_existing_to_range(false)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Draws `add` for a few frames without input, as an idle panel does.
    fn idle_frames(mut add: impl FnMut(&mut egui::Ui)) {
        let ctx = egui::Context::default();
        for _ in 0..3 {
            let _ = ctx.run_ui(egui::RawInput::default(), |ui| add(ui));
        }
    }

    #[test]
    fn values_beyond_the_range_are_left_alone() {
        let (mut fragments, mut threshold, mut count) = (50u32, 100.0f32, 9_000_000u64);
        idle_frames(|ui| {
            ui.add(slider(&mut fragments, 2..=20));
            ui.add(slider(&mut threshold, 0.0..=50.0).logarithmic(true));
            ui.add(drag_value(&mut count, 0..=2_000_000));
        });
        assert_eq!((fragments, threshold, count), (50, 100.0, 9_000_000));
    }

    #[test]
    fn egui_alone_would_clamp_them() {
        // What these widgets are for: the plain ones change an idle value.
        let (mut fragments, mut count) = (50u32, 9_000_000u64);
        idle_frames(|ui| {
            ui.add(egui::Slider::new(&mut fragments, 2..=20));
            ui.add(egui::DragValue::new(&mut count).range(0..=2_000_000));
        });
        assert_eq!((fragments, count), (20, 2_000_000));
    }
}
