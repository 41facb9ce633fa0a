//! `kessler run`: the window app — its plugins, resources and the order of
//! its systems.

use std::time::Instant;

use bevy::prelude::*;
use bevy::transform::TransformSystems;
use bevy::window::WindowResolution;
use bevy_egui::{EguiPlugin, EguiPrimaryContextPass};
use bevy_panorbit_camera::{PanOrbitCamera, PanOrbitCameraPlugin};

use crate::cli::{Failure, RenderArg, RunArgs};
use crate::components::{BodyId, Position};
use crate::resources::Execution;
use crate::systems::SimulationPlugins;

use super::body_colors::gather_instances;
use super::camera::{MainCamera, camera_key, fly_camera, orbit_and_follow, spawn_camera};
use super::capture::{ScriptedRun, report_frames, scripted_run};
use super::clock::UpdateClock;
use super::drive::{apply_live_settings, drive_simulation};
use super::frame_stats::{FrameStats, record_frame_stats};
use super::hud::hud;
use super::instancing::{InstancingPlugin, spawn_instanced_bodies};
use super::meshes::{init_body_mesh_assets, place_body_meshes, sync_body_meshes};
use super::panel::panel;
use super::sandbox::{SandboxState, follow_celestials, read_scenario, restart_scene};
use super::scene::spawn_backdrop;
use super::selection::{Selection, select_on_click};
use super::settings::{MAX_BODY_COUNT, RenderMethod, SandboxSettings, SettingsFile, default_settings_path};

/// Opens the window and runs until it is closed (or a scripted run ends).
pub fn run(args: RunArgs) -> Result<(), Failure> {
    check_screenshot_path(&args)?;
    check_display()?;
    if let Some(n) = args.bodies.filter(|&n| n > MAX_BODY_COUNT) {
        return Err(Failure::input(format!(
            "--bodies: {n} is more than the sandbox's {MAX_BODY_COUNT}"
        )));
    }
    let (mut file, mut settings) = SettingsFile::open(args.settings.clone().unwrap_or_else(default_settings_path));
    if let Some(warning) = &file.warning {
        eprintln!("kessler: warning: {warning}");
    }
    let (scenario, name) = match &args.scenario {
        Some(path) => {
            let (scenario, name) = read_scenario(Some(path)).map_err(Failure::input)?;
            settings.scenario = Some(path.clone());
            settings.adopt_scenario(&scenario.settings());
            (scenario, name)
        }
        None => read_scenario(settings.scenario.as_deref()).or_else(|e| {
            // The saved scenario went missing or broke: say so, use the built-in.
            let warning = format!("saved scenario: {e}; using the built-in scene");
            eprintln!("kessler: warning: {warning}");
            file.warning = Some(warning);
            settings.scenario = None;
            read_scenario(None).map_err(Failure::input)
        })?,
    };
    if let Some(render) = args.render {
        settings.render_method = match render {
            RenderArg::Instanced => RenderMethod::Instanced,
            RenderArg::Meshes => RenderMethod::Meshes,
        };
    }
    if let Some(count) = args.bodies {
        if scenario.generators.is_empty() {
            return Err(Failure::input(format!(
                "{name}: has no generators, so --bodies cannot apply"
            )));
        }
        settings.body_count = Some(count);
    }
    // Command-line choices are not "changes" that would rewrite the file.
    file.initial = settings.clone();
    let execution = Execution::new(settings.mode, usize::from(settings.threads)).map_err(Failure::input)?;
    let mut state = SandboxState::new(scenario, name, &settings);
    state.paused = args.paused;

    let mut app = App::new();
    app.add_plugins(DefaultPlugins.set(WindowPlugin {
        primary_window: Some(Window {
            title: "Kessler".into(),
            resolution: WindowResolution::new(1280, 800),
            ..default()
        }),
        ..default()
    }))
    .add_plugins((
        EguiPlugin::default(),
        PanOrbitCameraPlugin,
        SimulationPlugins,
        InstancingPlugin,
    ))
    .insert_resource(execution)
    .insert_resource(settings)
    .insert_resource(file)
    .insert_resource(state)
    .insert_resource(FrameStats::new(args.frames.is_some()))
    .init_resource::<UpdateClock>()
    .init_resource::<Selection>()
    .add_systems(Startup, (spawn_backdrop, setup_view, init_body_mesh_assets))
    .add_systems(
        Update,
        (
            (restart_scene, frame_scene, apply_live_settings, drive_simulation).chain(),
            (camera_key, select_on_click, fly_camera, orbit_and_follow).chain(),
        ),
    )
    .add_systems(
        PostUpdate,
        (
            (follow_celestials, gather_instances, sync_body_meshes),
            place_body_meshes.after(TransformSystems::Propagate),
        ),
    )
    .add_systems(EguiPrimaryContextPass, (panel, hud).chain())
    .add_systems(Last, (record_frame_stats, save_settings_on_exit, report_frames));
    if let Some(frames) = args.frames {
        app.insert_resource(ScriptedRun {
            frames,
            screenshot: args.screenshot.clone(),
            started: Instant::now(),
            capturing: false,
        })
        .add_systems(Update, scripted_run);
    }
    match app.run() {
        AppExit::Success => Ok(()),
        AppExit::Error(code) => Err(Failure {
            message: "the window app stopped with an error (see the log above)".into(),
            code: code.get(),
        }),
    }
}

/// A screenshot must be a new `.png` file in an existing folder.
fn check_screenshot_path(args: &RunArgs) -> Result<(), Failure> {
    let Some(path) = &args.screenshot else {
        return Ok(());
    };
    let shown = path.display();
    if path.extension().is_none_or(|e| !e.eq_ignore_ascii_case("png")) {
        return Err(Failure::input(format!("--screenshot {shown}: must be a .png file")));
    }
    if path.exists() {
        return Err(Failure::input(format!(
            "--screenshot {shown}: already exists; screenshots never overwrite, choose another name"
        )));
    }
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty())
        && !dir.is_dir()
    {
        return Err(Failure::input(format!(
            "--screenshot {shown}: folder {} does not exist",
            dir.display()
        )));
    }
    Ok(())
}

/// The window is X11-only (the lean build leaves Wayland out): without a
/// display, say so instead of letting the event loop panic.
fn check_display() -> Result<(), Failure> {
    if cfg!(target_os = "linux") && std::env::var_os("DISPLAY").is_none_or(|d| d.is_empty()) {
        return Err(Failure::input(
            "no X11 display (DISPLAY is not set): run the window in a desktop session, \
             under `xvfb-run kessler run`, or use `kessler headless`",
        ));
    }
    Ok(())
}

fn setup_view(mut commands: Commands, mut meshes: ResMut<Assets<Mesh>>) {
    spawn_camera(&mut commands, 4000.0);
    spawn_instanced_bodies(&mut commands, &mut meshes);
}

/// Once, after the first scene is built: backs the orbit camera off far
/// enough to see most bodies.
fn frame_scene(
    bodies: Query<&Position, With<BodyId>>,
    mut camera: Single<&mut PanOrbitCamera, With<MainCamera>>,
    mut framed: Local<bool>,
) {
    if *framed || bodies.is_empty() {
        return;
    }
    *framed = true;
    let mut radii: Vec<f32> = bodies.iter().step_by(97).map(|t| t.0.length()).collect();
    if radii.is_empty() {
        return;
    }
    radii.sort_by(f32::total_cmp);
    let reach = radii[(radii.len() - 1) * 9 / 10].max(10.0);
    camera.target_radius = reach * 2.6;
    camera.radius = Some(reach * 2.6);
    camera.force_update = true;
}

/// Saves the settings when the app exits, if the user changed any.
fn save_settings_on_exit(
    mut exits: MessageReader<AppExit>,
    settings: Res<SandboxSettings>,
    mut file: ResMut<SettingsFile>,
) {
    if exits.read().next().is_none() {
        return;
    }
    match file.save_if_changed(&settings) {
        Ok(true) => info!("settings saved to {}", file.path.display()),
        Ok(false) => {}
        Err(e) => eprintln!("kessler: warning: {}: cannot save settings: {e}", file.path.display()),
    }
}
