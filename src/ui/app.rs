//! `kessler run`: the window app — Bevy's, egui's and the simulation's
//! plugins, the window's own ([`SandboxPlugins`]), and the order of a frame's
//! phases (`SandboxSystems`), chained here and nowhere else.

use bevy::app::ScheduleRunnerPlugin;
use bevy::prelude::*;
use bevy::window::{ExitCondition, WindowResolution};
use bevy::winit::WinitPlugin;
use bevy_egui::input::EguiWantsInput;
use bevy_egui::{EguiPlugin, EguiPrimaryContextPass};

use super::draw::present_mode;
use super::measure::{CapturePlugin, Film, FilmPlugin, GpuMemoryPlugin, ScriptedRun};
use super::plugins::SandboxPlugins;
use super::session::{OffscreenTarget, OutputFailures, SandboxState, Start, WindowError, WindowOptions};
use super::sets::SandboxSystems;
use super::tools::{ActionScript, DumpAtClose};
use crate::systems::SimulationPlugins;
use crate::timed_events::EventsPlugin;

/// Whether the simulation's idle workers poll for work for a moment after
/// each parallel step in the window too (see `execution/keep_warm.rs`):
/// between the steps of a frame's updates they save the wake-ups, and once
/// the frame's updates are run the drive lets them rest, so that they take
/// no core the drawing needs (ARCHITECTURE.md, "Parallel execution").
const KEEP_WORKERS_WARM: bool = true;

/// Hardware threads the simulation's steps leave to the drawing, which runs
/// beside them (Bevy renders a frame while the next one simulates): on 2
/// cores with a software renderer, steps on both cores made the parallel
/// simulation reach 0.5–0.8 of sequential's updates a second, one thread
/// less the same as sequential (docs/benchmarks.md, Table 5).
const THREADS_FOR_THE_DRAWING: usize = 1;

/// Opens the window and runs until it is closed (or a scripted run ends).
pub fn run(options: WindowOptions) -> Result<(), WindowError> {
    let Start {
        file,
        settings,
        scenario,
    } = Start::from_options(&options)?;
    // Read before the renderer starts, so that a bad script is one line of
    // error and no log of a window that never opens.
    let actions = options.actions.as_deref().map(ActionScript::load).transpose()?;
    let execution = settings
        .execution
        .build(crate::calibration::machine_auto_split())?
        .with_keep_warm(KEEP_WORKERS_WARM)
        .leave_threads(THREADS_FOR_THE_DRAWING);
    let present_mode = present_mode(settings.vsync);
    let mut state = SandboxState::new(scenario, &settings);
    state.paused = options.paused;

    let mut app = App::new();
    let window = WindowPlugin {
        primary_window: (!options.offscreen).then(|| Window {
            title: "Kessler".into(),
            resolution: WindowResolution::new(1280, 800),
            present_mode,
            ..default()
        }),
        // Offscreen, the scripted run ends the app, not a closed window.
        exit_condition: if options.offscreen {
            ExitCondition::DontExit
        } else {
            ExitCondition::OnAllClosed
        },
        ..default()
    };
    if options.offscreen {
        // No window, no event loop: Bevy's headless runner, frames as fast
        // as they come; the panel and the HUD (egui, which draws into a
        // window) are left out.
        app.add_plugins((
            DefaultPlugins.set(window).disable::<WinitPlugin>(),
            ScheduleRunnerPlugin::run_loop(std::time::Duration::ZERO),
        ))
        .init_resource::<EguiWantsInput>();
        let target = OffscreenTarget::new(&mut app.world_mut().resource_mut::<Assets<Image>>());
        app.insert_resource(target);
    } else {
        app.add_plugins((DefaultPlugins.set(window), EguiPlugin::default()));
    }
    app.add_plugins((SimulationPlugins, EventsPlugin))
        .insert_resource(execution)
        .insert_resource(settings)
        .insert_resource(file)
        .insert_resource(state)
        .configure_sets(
            Update,
            (
                SandboxSystems::BuildScene,
                SandboxSystems::Tools,
                SandboxSystems::Simulate,
                SandboxSystems::View,
            )
                .chain(),
        )
        .configure_sets(
            EguiPrimaryContextPass,
            (SandboxSystems::Panel, SandboxSystems::Hud).chain(),
        )
        .add_plugins(SandboxPlugins {
            record_all_frames: options.frames.is_some(),
        });
    if let Some(script) = actions {
        app.insert_resource(script);
    }
    if let Some(path) = &options.dump {
        app.insert_resource(DumpAtClose(path.clone()));
    }
    let failures = OutputFailures::default();
    app.insert_resource(failures.clone());
    if let Some(dir) = &options.frames_out {
        app.add_plugins(FilmPlugin(Film::new(dir.clone(), options.every)));
    }
    if let Some(frames) = options.frames {
        let mut run = ScriptedRun::new(frames, options.screenshot.clone());
        run.frame_report.clone_from(&options.frame_report);
        app.add_plugins((GpuMemoryPlugin, CapturePlugin(run)));
    }
    let exit = app.run();
    // A run that closed stopped ends as a stopped headless run does, its
    // fault before any output that failed.
    if let Some(fault) = failures.stopped() {
        return Err(WindowError::Stopped(fault));
    }
    match exit {
        AppExit::Success if failures.count() > 0 => Err(WindowError::Outputs(failures.count())),
        AppExit::Success => Ok(()),
        AppExit::Error(code) => Err(WindowError::App(code.get())),
    }
}
