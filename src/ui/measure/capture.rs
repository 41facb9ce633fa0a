//! Scripted runs: close after `--frames N` frames, save a `--screenshot`,
//! print frame-time statistics. Used by the window test and the rendering
//! comparison.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use bevy::prelude::*;
use bevy::render::view::screenshot::ScreenshotCaptured;

use super::frame_stats::{FrameStats, summarize};
use super::gpu_memory::GpuMemory;
use super::picture::{save_png, screenshot_of};
use crate::bench::{FrameReport, peak_memory};
use crate::components::{BodyId, GravityRole, Interacts};
use crate::draw_method::DrawMethod;
use crate::output::write_atomically;
use crate::ui::draw::InstancedBodies;
use crate::ui::draw::is_celestial;
use crate::ui::session::UpdateClock;
use crate::ui::session::{OffscreenTarget, SandboxSettings};

/// Frames skipped before frame times count (pipelines compile, buffers fill).
pub const WARMUP_FRAMES: usize = crate::bench::WINDOW_WARMUP_FRAMES as usize;
/// Longest a scripted run waits past its frames for the bodies to be drawn
/// (shader compilation under software rendering is slow).
pub const READY_TIMEOUT: Duration = Duration::from_secs(120);

/// What a scripted run does.
#[derive(Resource, Clone, Debug)]
pub struct ScriptedRun {
    /// Frames to run before finishing.
    pub frames: u64,
    /// Where to save a screenshot at the end (a new file).
    pub screenshot: Option<PathBuf>,
    /// When the run started.
    pub started: Instant,
    /// Screenshot requested (waiting for it to be written).
    pub capturing: bool,
    /// Where to write what the run measured (a new file), if anywhere.
    pub frame_report: Option<PathBuf>,
}

impl ScriptedRun {
    /// A run of `frames` frames that saves `screenshot`, starting now.
    pub fn new(frames: u64, screenshot: Option<PathBuf>) -> Self {
        Self {
            frames,
            screenshot,
            started: Instant::now(),
            capturing: false,
            frame_report: None,
        }
    }
}

/// A scripted run: ends the app after its frames, saves the screenshot and
/// prints the frame-time summary.
pub struct CapturePlugin(pub ScriptedRun);

impl Plugin for CapturePlugin {
    fn build(&self, app: &mut App) {
        app.insert_resource(self.0.clone())
            .add_systems(Update, scripted_run)
            .add_systems(Last, report_frames);
    }
}

/// Whether a scripted run may finish as far as the bodies go: they have been
/// drawn at least once, or there is nothing it would wait for — bodies not
/// drawn, drawn by another method (Bevy's own pipelines), no cubes in the
/// scene (planets and moons are drawn apart), or no instanced drawing at
/// all. `cubes` counts the cubes in the scene, `draws` the instanced draws
/// submitted so far (`None`: no instanced drawing).
fn bodies_ready(settings: &SandboxSettings, cubes: usize, draws: Option<u64>) -> bool {
    let waits = settings.render_bodies && settings.render_method == DrawMethod::Instanced && cubes > 0;
    !waits || draws.is_none_or(|n| n > 0)
}

/// The cubes of the scene: the bodies the instanced pipeline draws.
type Cubes<'w, 's> = Query<'w, 's, (&'static GravityRole, &'static Interacts), With<BodyId>>;

/// After the frames (and once the bodies are on screen), takes the
/// screenshot or ends the run.
#[expect(
    clippy::too_many_arguments,
    reason = "a Bevy system's parameters are its data access"
)]
fn scripted_run(
    mut commands: Commands,
    mut run: ResMut<ScriptedRun>,
    stats: Res<FrameStats>,
    settings: Res<SandboxSettings>,
    instanced: Query<&InstancedBodies>,
    cubes: Cubes,
    target: Option<Res<OffscreenTarget>>,
    mut exit: MessageWriter<AppExit>,
) {
    if run.capturing || stats.frames < run.frames {
        return;
    }
    let cubes = cubes
        .iter()
        .filter(|&(&role, &interacts)| !is_celestial(role, interacts))
        .count();
    let draws = instanced.iter().map(|InstancedBodies(slot)| slot.draws()).min();
    let ready = bodies_ready(&settings, cubes, draws);
    let timed_out = run.started.elapsed() > READY_TIMEOUT;
    if !ready && !timed_out {
        return;
    }
    if !ready {
        warn!("the bodies were not drawn within {READY_TIMEOUT:?}; finishing anyway");
    }
    match run.screenshot.clone() {
        Some(path) => {
            run.capturing = true;
            commands.spawn(screenshot_of(target.as_deref())).observe(
                move |captured: On<ScreenshotCaptured>, mut exit: MessageWriter<AppExit>| match save_png(
                    &captured.image,
                    &path,
                ) {
                    Ok(()) => {
                        eprintln!("kessler: screenshot saved to {}", path.display());
                        exit.write(AppExit::Success);
                    }
                    Err(e) => {
                        eprintln!("kessler: error: {}: cannot save screenshot: {e}", path.display());
                        exit.write(AppExit::from_code(1));
                    }
                },
            );
        }
        None => {
            exit.write(AppExit::Success);
        }
    }
}

/// Prints the frame-time summary of a scripted run when the app exits, and
/// writes its frame report if asked.
fn report_frames(
    mut exits: MessageReader<AppExit>,
    stats: Res<FrameStats>,
    clock: Res<UpdateClock>,
    settings: Res<SandboxSettings>,
    run: Res<ScriptedRun>,
    gpu: Option<Res<GpuMemory>>,
    bodies: Query<(), With<BodyId>>,
) {
    if exits.read().next().is_none() {
        return;
    }
    let bodies = bodies.iter().len();
    let method = if settings.render_bodies {
        settings.render_method.name()
    } else {
        "none"
    };
    let seconds: f64 = stats.all.iter().sum();
    let ups = if seconds > 0.0 {
        clock.updates_total as f64 / seconds
    } else {
        0.0
    };
    let summary = summarize(&stats.all, WARMUP_FRAMES);
    if let Some(path) = &run.frame_report {
        let gpu = gpu.map(|g| g.reading()).unwrap_or_default();
        let report = FrameReport {
            bodies: bodies as u64,
            frames: summary.as_ref().map_or(0, |s| s.frames as u64),
            mean_ms: summary.as_ref().map_or(0.0, |s| s.mean_ms),
            p95_ms: summary.as_ref().map_or(0.0, |s| s.p95_ms),
            updates_per_second: ups,
            peak_ram_bytes: peak_memory().unwrap_or(0),
            gpu_bytes: gpu.bytes,
            gpu_reserved_bytes: gpu.reserved,
            gpu_source: gpu.source,
            adapter: gpu.adapter,
        };
        if let Err(e) = write_atomically(path, |w| w.write_all(report.to_text().as_bytes())) {
            eprintln!("kessler: error: --frame-report {e}");
        }
    }
    match summary {
        Some(s) => println!(
            "frames {} (after {WARMUP_FRAMES} warm-up), bodies {bodies}, render {method}: \
             mean {:.2} ms, median {:.2} ms, p95 {:.2} ms ({:.1} FPS); {} updates ({ups:.1} per second)",
            s.frames,
            s.mean_ms,
            s.median_ms,
            s.p95_ms,
            1e3 / s.mean_ms,
            clock.updates_total
        ),
        None => println!(
            "frames {}: too few to time (warm-up is {WARMUP_FRAMES})",
            stats.all.len()
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_run_waits_only_for_cubes_the_instanced_pipeline_has_yet_to_draw() {
        let instanced = SandboxSettings::default();
        assert_eq!(instanced.render_method, DrawMethod::Instanced);
        assert!(!bodies_ready(&instanced, 300, Some(0)), "cubes not drawn yet");
        assert!(bodies_ready(&instanced, 300, Some(1)));
        assert!(bodies_ready(&instanced, 0, Some(0)), "an empty scene: nothing to draw");
        assert!(bodies_ready(&instanced, 300, None), "no instanced drawing to wait for");
        let hidden = SandboxSettings {
            render_bodies: false,
            ..instanced.clone()
        };
        assert!(bodies_ready(&hidden, 300, Some(0)));
        let meshes = SandboxSettings {
            render_method: DrawMethod::MeshPerBody,
            ..instanced
        };
        assert!(bodies_ready(&meshes, 300, Some(0)));
    }
}
