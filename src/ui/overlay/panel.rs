//! The settings panel: every thesis setting, the run controls, the scenario
//! picker, the camera and the selected body.

use std::path::{Path, PathBuf};

use bevy::prelude::*;
use bevy_egui::{EguiContexts, EguiPrimaryContextPass, egui};

use super::cascade::{Cascade, totals_readout};
use super::widgets::{drag_value, slider};
use crate::components::{BodyId, GravityRole, Mass, Position, Velocity};
use crate::execution::{Execution, ExecutionMode, FALLBACK_SPLIT_FROM, SplitPolicy, WorkerPool};
use crate::input::ExecutionOptions;
use crate::maths::Rng;
use crate::resources::DrawMethod;
use crate::resources::{
    AUTO_TREE_FROM, CollisionDetection, DEFAULT_THETA, FragmentSizes, GravityMethod, Integrator, SimulationSettings,
};
use crate::systems::UpdateCount;
use crate::ui::session::SandboxState;
use crate::ui::session::SnapshotSave;
use crate::ui::session::{
    CameraMode, FRAGMENT_SPREAD_RANGE, MAX_BODIES_RANGE, MAX_BODY_COUNT, MIN_FRAGMENT_SIZE_RANGE,
    SHATTER_FRAGMENTS_RANGE, SPEED_RANGE, SandboxSettings, TRAIL_COUNT_RANGE, TrailChoice, UPS_RANGE, max_threads,
};
use crate::ui::sets::SandboxSystems;
use crate::ui::tools::{CHECKPOINT_EVERY, Checkpoints, ToolAction, ToolSettings};
use crate::ui::view::{Selection, selected_info};

/// Folder the scenario picker lists.
pub const SCENARIO_DIR: &str = "scenarios";

/// The settings panel at the left, and the run keys (Space, N, R); the
/// tools' keys are the tools' own.
pub struct PanelPlugin;

impl Plugin for PanelPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(EguiPrimaryContextPass, panel.in_set(SandboxSystems::Panel));
    }
}

/// Text of the "any path" field of the scenario picker.
#[derive(Default)]
struct PathField(String);

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

#[expect(clippy::too_many_arguments, reason = "the panel edits settings, state and selection")]
fn panel(
    mut contexts: EguiContexts,
    mut settings: ResMut<SandboxSettings>,
    mut state: ResMut<SandboxState>,
    mut selection: ResMut<Selection>,
    bodies: Query<(&BodyId, &Mass, &Velocity, &Position, Option<&GravityRole>)>,
    keys: Res<ButtonInput<KeyCode>>,
    mut path_field: Local<PathField>,
    mut files: Local<Option<Vec<PathBuf>>>,
    mut save: ResMut<SnapshotSave>,
    mut save_field: Local<SaveField>,
    cascade: Res<Cascade>,
    (mut tool_settings, mut actions, checkpoints, updates): (
        ResMut<ToolSettings>,
        MessageWriter<ToolAction>,
        Res<Checkpoints>,
        Res<UpdateCount>,
    ),
    running: Res<Execution>,
    mut session_field: Local<SessionField>,
) -> Result {
    let ctx = contexts.ctx_mut()?;
    if !ctx.egui_wants_keyboard_input() {
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
    // Edit a copy, so the resource is marked changed only by real edits.
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
                let mut tools = tool_settings.clone();
                let has_selection = selection.entity.is_some();
                let sent = tools_section(ui, &mut tools, has_selection, &checkpoints, updates.0);
                if let Some(problem) = &state.tool_problem {
                    ui.colored_label(egui::Color32::from_rgb(255, 200, 90), problem);
                }
                if tools != *tool_settings {
                    *tool_settings = tools;
                }
                for action in sent {
                    actions.write(action);
                }
                ui.separator();
                scene(ui, &mut edited, &mut state, &mut path_field.0, &mut files);
                save_scenario(ui, &mut save, &mut save_field.0);
                save_session(ui, &mut actions, &mut session_field.0);
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

fn run_controls(ui: &mut egui::Ui, settings: &mut SandboxSettings, state: &mut SandboxState) {
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

/// The execution settings, and the threads the steps really run on where
/// that is fewer than asked (the window leaves a core to the drawing; a
/// step runs on no more threads than the machine has).
fn execution(ui: &mut egui::Ui, settings: &mut SandboxSettings, running: &Execution) {
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

fn physics(ui: &mut egui::Ui, settings: &mut SimulationSettings) {
    ui.label("Stages");
    ui.checkbox(&mut settings.stages.gravity, "gravity");
    gravity_method(ui, settings);
    ui.horizontal(|ui| {
        ui.label("integrator");
        ui.radio_value(&mut settings.integrator, Integrator::Leapfrog, "leapfrog")
            .on_hover_text("drift–kick–drift, second order: orbits stay round");
        ui.radio_value(
            &mut settings.integrator,
            Integrator::SemiImplicitEuler,
            "semi-implicit Euler",
        )
        .on_hover_text("the thesis: kick, then drift; first order, orbits swing by a few % of their radius");
    });
    ui.checkbox(&mut settings.stages.collisions, "collision detection");
    ui.add_enabled_ui(settings.stages.collisions, |ui| {
        ui.horizontal(|ui| {
            ui.radio_value(&mut settings.collision_detection, CollisionDetection::Swept, "swept")
                .on_hover_text("along each body's path over the update: fast bodies cannot pass through one another");
            ui.radio_value(
                &mut settings.collision_detection,
                CollisionDetection::Discrete,
                "discrete",
            )
            .on_hover_text("the thesis: only where the update ends; bodies faster than their size may tunnel");
        });
    });
    ui.add_enabled(
        settings.stages.collisions,
        egui::Checkbox::new(
            &mut settings.stages.collision_response,
            "collision response (bounce, shatter)",
        ),
    );
    ui.add(slider(&mut settings.shatter_fragments, 2..=20).text("shatter fragments"));
    fragment_sizes(ui, settings);
    ui.add(
        slider(&mut settings.shatter_threshold, 0.0..=50.0)
            .logarithmic(true)
            .text("impact threshold"),
    );
    ui.add(
        slider(&mut settings.min_fragment_size, MIN_FRAGMENT_SIZE_RANGE)
            .logarithmic(true)
            .text("smallest fragment"),
    )
    .on_hover_text("edge length: a collision whose fragments would be smaller bounces (0: no floor, the thesis)");
    ui.add(
        slider(&mut settings.max_bodies, MAX_BODIES_RANGE)
            .logarithmic(true)
            .text("body budget"),
    )
    .on_hover_text("a shatter that would make more bodies bounces");
    ui.add(slider(&mut settings.fragment_spread, FRAGMENT_SPREAD_RANGE).text("fragment spread"))
        .on_hover_text("the fragments' speed apart, as a share of the impact speed (the thesis's \"Streuung\")");
}

/// How gravity is summed: auto, direct, or the tree and its θ.
fn gravity_method(ui: &mut egui::Ui, settings: &mut SimulationSettings) {
    ui.horizontal(|ui| {
        let method = settings.gravity_method;
        if ui
            .radio(method == GravityMethod::Auto, "auto")
            .on_hover_text(format!(
                "the direct sum below {AUTO_TREE_FROM} sources, else the tree at θ {DEFAULT_THETA}"
            ))
            .clicked()
        {
            settings.gravity_method = GravityMethod::Auto;
        }
        if ui.radio(method == GravityMethod::Direct, "direct sum").clicked() {
            settings.gravity_method = GravityMethod::Direct;
        }
        let tree = matches!(method, GravityMethod::Tree { .. });
        if ui
            .radio(tree, "tree")
            .on_hover_text("Barnes–Hut: for thousands of sources")
            .clicked()
            && !tree
        {
            settings.gravity_method = GravityMethod::Tree { theta: DEFAULT_THETA };
        }
        if let GravityMethod::Tree { theta } = &mut settings.gravity_method {
            ui.add(slider(theta, 0.0..=1.5).text("θ"))
                .on_hover_text("opening angle: 0 is the direct sum; 0.5 errs about 0.1 %");
        }
    });
}

/// How a shatter sizes its fragments: equal, or the power law and its α.
fn fragment_sizes(ui: &mut egui::Ui, settings: &mut SimulationSettings) {
    ui.horizontal(|ui| {
        ui.label("sizes");
        let sizes = settings.fragment_sizes;
        if ui
            .radio(sizes == FragmentSizes::Equal, "equal")
            .on_hover_text("the thesis: equal cubes that keep the pair's volume")
            .clicked()
        {
            settings.fragment_sizes = FragmentSizes::Equal;
        }
        let law = matches!(sizes, FragmentSizes::PowerLaw { .. });
        if ui
            .radio(law, "power law")
            .on_hover_text("the NASA standard breakup model: N(>L) ∝ L^−α, at most the fragments above")
            .clicked()
            && !law
        {
            settings.fragment_sizes = FragmentSizes::PowerLaw { exponent: 1.71 };
        }
        if let FragmentSizes::PowerLaw { exponent } = &mut settings.fragment_sizes {
            ui.add(slider(exponent, 0.5..=3.0).text("α"))
                .on_hover_text("1.71 for collisions, 1.6 for explosions");
        }
    });
}

fn scene(
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

/// The snapshot file name the panel offers, edited in place.
struct SaveField(String);

impl Default for SaveField {
    fn default() -> Self {
        Self("snapshot.ron".into())
    }
}

/// "Save scenario…": the running state to a new scenario file.
fn save_scenario(ui: &mut egui::Ui, save: &mut SnapshotSave, field: &mut String) {
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
struct SessionField(String);

impl Default for SessionField {
    fn default() -> Self {
        Self("session.ron".into())
    }
}

/// "Save session…": the scenario the scene started from with every event
/// so far (the tools' and the panel's included), to a new file.
fn save_session(ui: &mut egui::Ui, actions: &mut MessageWriter<ToolAction>, field: &mut String) {
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

/// The tools: what they use, and the actions the buttons ask for.
fn tools_section(
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

fn rendering(ui: &mut egui::Ui, settings: &mut SandboxSettings) {
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

fn camera(
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
                selection.entity = None;
            }
        }
        None => {
            ui.small("click a body to select it");
        }
    }
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

#[cfg(test)]
mod tests {
    use super::*;

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

    #[test]
    fn picker_lists_the_shipped_scenarios() {
        let files = scenario_files(Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios")));
        assert!(files.iter().any(|f| f.ends_with("debris_orbit.ron")), "{files:?}");
        assert!(files.windows(2).all(|w| w[0] <= w[1]));
    }
}
