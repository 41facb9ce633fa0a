//! The panel's execution section: mode, threads, split and pool, and what
//! the steps really run on.

use bevy_egui::egui;

use crate::execution::{Execution, ExecutionMode, FALLBACK_SPLIT_FROM, SplitPolicy, WorkerPool};
use crate::input::ExecutionOptions;
use crate::ui::session::{MAX_BODY_COUNT, SandboxSettings, max_threads};
use crate::ui::widgets::{drag_value, slider};

/// The execution settings, and the threads the steps really run on where
/// that is fewer than asked (the window leaves a core to the drawing; a
/// step runs on no more threads than the machine has).
pub(super) fn execution(ui: &mut egui::Ui, settings: &mut SandboxSettings, running: &Execution) {
    ui.label("Execution");
    let options = &mut settings.execution;
    let (mut mode, mut threads, mut split, mut pool) =
        (options.mode(), options.threads(), options.split(), options.pool());
    ui.horizontal(|ui| {
        ui.radio_value(&mut mode, ExecutionMode::Sequential, "sequential");
        ui.radio_value(&mut mode, ExecutionMode::Parallel, "parallel");
    });
    let parallel = mode == ExecutionMode::Parallel;
    ui.add_enabled(parallel, slider(&mut threads, 1..=max_threads()).text("threads"));
    if let Some(note) = fewer_threads_note(options, running) {
        ui.label(note)
            .on_hover_text("a step runs on no more threads than the hardware threads left to it");
    }
    ui.add_enabled_ui(parallel, |ui| split_policy(ui, &mut split));
    ui.add_enabled_ui(parallel, |ui| {
        ui.horizontal(|ui| {
            ui.label("pool")
                .on_hover_text("which worker pool runs the split work: the same results, another cost per dispatch");
            ui.radio_value(&mut pool, WorkerPool::Kessler, "Kessler's")
                .on_hover_text("its own: exactly `threads` workers, kept polling between the steps of an update");
            ui.radio_value(&mut pool, WorkerPool::Bevy, "Bevy's")
                .on_hover_text("Bevy's ComputeTaskPool, shared with the app; its threads are fixed at start");
        });
    });
    let chosen = ExecutionOptions {
        mode: Some(mode),
        threads: Some(threads),
        split: Some(split),
        pool: Some(pool),
    };
    // Written only where changed: the resource is then changed only by a
    // choice.
    if chosen != *options {
        *options = chosen;
    }
}

/// What the panel says where parallel steps on Kessler's pool run on fewer
/// threads than `options` ask for (and `running` has applied them).
fn fewer_threads_note(options: &ExecutionOptions, running: &Execution) -> Option<String> {
    let applied = options.mode() == ExecutionMode::Parallel
        && options.pool() == WorkerPool::Kessler
        && running.pool() == WorkerPool::Kessler
        && running.threads() == options.threads();
    let on = running.step_threads();
    (applied && on < options.threads()).then(|| format!("steps run on {on} of them: the cores beside the drawing"))
}

/// The split policy: auto (this machine's calibration), always, or from a
/// body count.
fn split_policy(ui: &mut egui::Ui, split: &mut SplitPolicy) {
    ui.horizontal(|ui| {
        ui.label("split")
            .on_hover_text("from which body count a stage cuts its work into chunks for the threads");
        ui.radio_value(split, SplitPolicy::Auto, "auto")
            .on_hover_text("from the counts `kessler calibrate` measured on this machine");
        ui.radio_value(split, SplitPolicy::Always, "always")
            .on_hover_text("at every body count, as the thesis did");
        let mut from = match *split {
            SplitPolicy::Above(n) => n,
            _ => FALLBACK_SPLIT_FROM,
        };
        let above = matches!(split, SplitPolicy::Above(_));
        if ui.radio(above, "from").clicked() {
            *split = SplitPolicy::Above(from);
        }
        let field = ui.add_enabled(above, drag_value(&mut from, 0..=MAX_BODY_COUNT).speed(100.0));
        if field.changed() {
            *split = SplitPolicy::Above(from);
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_panel_says_when_steps_run_on_fewer_threads_than_asked() {
        let settings = ExecutionOptions {
            mode: Some(ExecutionMode::Parallel),
            threads: Some(3),
            pool: Some(WorkerPool::Kessler),
            split: None,
        };
        let running = |cores: usize| {
            Execution::new(ExecutionMode::Parallel, 3)
                .unwrap()
                .as_if_hardware_threads(cores)
        };
        let note = fewer_threads_note(&settings, &running(2));
        assert_eq!(
            note.as_deref(),
            Some("steps run on 2 of them: the cores beside the drawing")
        );
        assert_eq!(fewer_threads_note(&settings, &running(4)), None, "all three run");
        let sequential = ExecutionOptions {
            mode: Some(ExecutionMode::Sequential),
            ..settings
        };
        assert_eq!(fewer_threads_note(&sequential, &running(1)), None);
        // Not yet applied: the pool still has its old thread count.
        let asked_more = ExecutionOptions {
            threads: Some(5),
            ..settings
        };
        assert_eq!(fewer_threads_note(&asked_more, &running(2)), None);
    }
}
