//! Scripted runs: close after `--frames N` frames, save a `--screenshot`,
//! print frame-time statistics. Used by the window test and the rendering
//! comparison.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use bevy::ecs::system::SystemParam;
use bevy::prelude::*;
use bevy::render::view::screenshot::ScreenshotCaptured;

use super::frame_stats::{FrameStats, record_frame_stats, summarize};
use super::gpu_memory::GpuMemory;
use super::picture::{save_png, screenshot_of};
use super::pipelines::PipelinesSettled;
use crate::bench::{FrameReport, peak_memory};
use crate::components::{BodyId, GravityRole, NonInteracting};
use crate::output::write_atomically;
use crate::resources::DrawMethod;
use crate::ui::draw::InstancedBodies;
use crate::ui::draw::is_celestial;
use crate::ui::session::UpdateClock;
use crate::ui::session::{OffscreenTarget, OutputFailures, SandboxSettings};

/// Frames skipped, after the scene is first drawn in full, before frame
/// times count (buffers fill, caches warm).
pub const WARMUP_FRAMES: usize = crate::bench::WINDOW_WARMUP_FRAMES as usize;
/// Longest a scripted run waits for the scene to be drawn in full, for its
/// screenshot, and for the pipelines to settle before it ends; and longest
/// a film's picture waits for the pipelines (shader compilation under
/// software rendering is slow).
pub const READY_TIMEOUT: Duration = Duration::from_secs(120);

/// What a scripted run does, and how far it is.
#[derive(Resource, Clone, Debug)]
pub struct ScriptedRun {
    /// Frames to run, counted from the first frame drawn in full.
    pub frames: u64,
    /// Where to save a screenshot at the end (a new file).
    pub screenshot: Option<PathBuf>,
    /// Since when the run has waited: for the scene to be drawn in full,
    /// for the screenshot, then for the pipelines to settle before it ends.
    pub waiting_since: Instant,
    /// The frame (counted from the app's first) from which frames count:
    /// the first drawn in full; `None` until then.
    pub first_frame: Option<u64>,
    /// Screenshot requested (waiting for it to be written).
    pub capturing: bool,
    /// How the app is to end, once the pipelines are settled.
    pub ending: Option<AppExit>,
    /// Where to write what the run measured (a new file), if anywhere.
    pub frame_report: Option<PathBuf>,
}

/// What a scripted run does this frame.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Step {
    /// Nothing: frames to go, or waiting.
    Wait,
    /// Take the screenshot.
    Capture,
    /// End the app.
    Exit(AppExit),
}

impl ScriptedRun {
    /// A run of `frames` frames that saves `screenshot`, starting now.
    pub fn new(frames: u64, screenshot: Option<PathBuf>) -> Self {
        Self {
            frames,
            screenshot,
            waiting_since: Instant::now(),
            first_frame: None,
            capturing: false,
            ending: None,
            frame_report: None,
        }
    }

    /// The times of the frames that count, of `all` (the time recorded in
    /// each frame since the app started, which is the frame before's: Bevy's
    /// real-time delta): the run's `frames` from the first frame drawn in
    /// full; none before it, nor the frames after them that waited for the
    /// screenshot or for the pipelines to settle.
    pub fn counted<'a>(&self, all: &'a [f64]) -> &'a [f64] {
        let index = |frame: u64| usize::try_from(frame).unwrap_or(usize::MAX).min(all.len());
        let Some(first) = self.first_frame else {
            return &[];
        };
        // Frame `first`'s time is recorded in frame `first + 1`.
        let start = first.saturating_add(1);
        &all[index(start)..index(start.saturating_add(self.frames))]
    }

    /// Marks the run to end with `exit` once the pipelines are settled.
    fn end(&mut self, exit: AppExit, now: Instant) {
        self.ending = Some(exit);
        self.waiting_since = now;
    }

    /// The next step at frame `frame` (frames since the app started),
    /// given whether the scene is drawn in full (`drawn`: the pipelines
    /// settled and the bodies drawn; read only until the first frame
    /// counts, so a caller may pass `false` after) and whether the
    /// pipelines are settled now. A wait longer than [`READY_TIMEOUT`] goes
    /// on as if it were over; a screenshot not captured by then ends the
    /// run with exit code 1.
    fn step(&mut self, frame: u64, drawn: bool, settled: bool, now: Instant) -> Step {
        let waited_too_long = now.duration_since(self.waiting_since) > READY_TIMEOUT;
        if let Some(exit) = &self.ending {
            if !settled && !waited_too_long {
                return Step::Wait;
            }
            if !settled {
                warn!("pipelines still compiling after {READY_TIMEOUT:?}; ending anyway");
            }
            return Step::Exit(exit.clone());
        }
        if self.capturing {
            if waited_too_long {
                eprintln!("kessler: error: the screenshot was not captured within {READY_TIMEOUT:?}; ending the run");
                self.end(AppExit::from_code(1), now);
                return self.step(frame, drawn, settled, now);
            }
            return Step::Wait;
        }
        let Some(first) = self.first_frame else {
            if !drawn && !waited_too_long {
                return Step::Wait;
            }
            if !drawn {
                warn!("the scene was not drawn in full within {READY_TIMEOUT:?}; counting frames anyway");
            }
            self.first_frame = Some(frame);
            return Step::Wait;
        };
        if frame < first + self.frames {
            return Step::Wait;
        }
        if self.screenshot.is_some() {
            self.capturing = true;
            self.waiting_since = now;
            return Step::Capture;
        }
        self.end(AppExit::Success, now);
        self.step(frame, drawn, settled, now)
    }
}

/// A scripted run: ends the app after its frames, saves the screenshot and
/// prints the frame-time summary.
pub struct CapturePlugin(pub ScriptedRun);

impl Plugin for CapturePlugin {
    fn build(&self, app: &mut App) {
        app.insert_resource(self.0.clone())
            .init_resource::<OutputFailures>()
            .add_systems(Update, scripted_run)
            .add_systems(Last, report_frames.after(record_frame_stats));
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
type Cubes<'w, 's> = Query<'w, 's, (Option<&'static GravityRole>, Has<NonInteracting>), With<BodyId>>;

/// Counts the frames once the scene is drawn in full, then takes the
/// screenshot, and ends the app once the pipelines are settled.
/// What a scripted run asks of the scene before it counts frames: how the
/// bodies are drawn, the cubes there are and the draws the instanced
/// pipeline made of them, whether every pipeline is compiled, and the
/// offscreen image, if it draws into one.
#[derive(SystemParam)]
struct Scene<'w, 's> {
    settings: Res<'w, SandboxSettings>,
    instanced: Query<'w, 's, &'static InstancedBodies>,
    cubes: Cubes<'w, 's>,
    settled: Res<'w, PipelinesSettled>,
    target: Option<Res<'w, OffscreenTarget>>,
}

fn scripted_run(
    mut commands: Commands,
    mut run: ResMut<ScriptedRun>,
    stats: Res<FrameStats>,
    scene: Scene,
    mut exit: MessageWriter<AppExit>,
) {
    let Scene {
        settings,
        instanced,
        cubes,
        settled,
        target,
    } = scene;
    let settled = settled.get();
    // Only a run still waiting for its first counted frame asks whether the
    // scene is drawn in full: the answer walks every body, which would
    // otherwise weigh on every timed frame (about 0.25 ms at a million).
    let drawn = settled && run.first_frame.is_none() && {
        let cubes = cubes
            .iter()
            .filter(|&(role, non_interacting)| !is_celestial(GravityRole::of(role), non_interacting))
            .count();
        let draws = instanced.iter().map(|InstancedBodies(slot)| slot.draws()).min();
        bodies_ready(&settings, cubes, draws)
    };
    match run.step(stats.frames, drawn, settled, Instant::now()) {
        Step::Wait => {}
        Step::Exit(code) => {
            exit.write(code);
        }
        Step::Capture => {
            let path = run.screenshot.clone().unwrap_or_default();
            commands.spawn(screenshot_of(target.as_deref())).observe(
                move |captured: On<ScreenshotCaptured>, mut run: ResMut<ScriptedRun>, failures: Res<OutputFailures>| {
                    // Too late: the run gave up waiting and ends with an error.
                    if run.ending.is_some() {
                        return;
                    }
                    match save_png(&captured.image, &path) {
                        Ok(()) => eprintln!("kessler: screenshot saved to {}", path.display()),
                        Err(e) => failures.failed(format_args!("{}: cannot save screenshot: {e}", path.display())),
                    }
                    run.end(AppExit::Success, Instant::now());
                },
            );
        }
    }
}

/// What a scripted run measured: its frames, its updates, the GPU's
/// memory.
#[derive(SystemParam)]
struct Measured<'w> {
    stats: Res<'w, FrameStats>,
    clock: Res<'w, UpdateClock>,
    gpu: Option<Res<'w, GpuMemory>>,
}

/// Prints the frame-time summary of a scripted run when the app exits, and
/// writes its frame report if asked.
fn report_frames(
    mut exits: MessageReader<AppExit>,
    measured: Measured,
    settings: Res<SandboxSettings>,
    run: Res<ScriptedRun>,
    bodies: Query<(), With<BodyId>>,
    failures: Res<OutputFailures>,
) {
    let Measured { stats, clock, gpu } = measured;
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
    let summary = summarize(run.counted(&stats.all), WARMUP_FRAMES);
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
            failures.failed(format_args!("--frame-report {e}"));
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

    /// Steps a run through `frames`, each `(drawn, settled)`, one frame
    /// apart in time; what it did at each.
    fn steps(run: &mut ScriptedRun, frames: &[(bool, bool)]) -> Vec<Step> {
        let now = run.waiting_since;
        (0..)
            .zip(frames)
            .map(|(frame, &(drawn, settled))| run.step(frame, drawn, settled, now + Duration::from_millis(frame)))
            .collect()
    }

    #[test]
    fn frames_count_from_the_first_frame_drawn_in_full() {
        let mut run = ScriptedRun::new(3, None);
        // Three frames while the pipelines compile, then drawn from frame 3:
        // frames 3, 4 and 5 count, and the run ends at frame 6.
        let mut frames = vec![(false, false); 3];
        frames.extend([(true, true); 4]);
        let steps = steps(&mut run, &frames);
        assert_eq!(run.first_frame, Some(3));
        assert_eq!(steps[..6], vec![Step::Wait; 6]);
        assert_eq!(steps[6], Step::Exit(AppExit::Success));
        // Each frame's time is recorded in the next frame: frame 3's at 4.
        let times: Vec<f64> = (0..8).map(f64::from).collect();
        assert_eq!(
            run.counted(&times),
            &[4.0, 5.0, 6.0],
            "frames 3, 4 and 5; not the frames after"
        );
        assert_eq!(run.counted(&times[..6]), &[4.0, 5.0], "as far as they were timed");
    }

    #[test]
    fn nothing_counts_before_the_scene_is_drawn() {
        let run = ScriptedRun::new(3, None);
        assert!(run.counted(&[1.0, 2.0]).is_empty());
    }

    #[test]
    fn the_run_ends_only_once_the_pipelines_are_settled() {
        let mut run = ScriptedRun::new(1, Some(PathBuf::from("shot.png")));
        let steps = steps(&mut run, &[(true, true), (true, true), (true, true)]);
        assert_eq!(
            steps,
            [Step::Wait, Step::Capture, Step::Wait],
            "one screenshot, then its saving"
        );
        // Saved while the screenshot's own pipeline compiles: the run waits.
        let now = Instant::now();
        run.end(AppExit::Success, now);
        assert_eq!(run.step(3, false, false, now), Step::Wait);
        assert_eq!(run.step(4, true, true, now), Step::Exit(AppExit::Success));
        // A failed save ends with its code.
        run.end(AppExit::from_code(1), now);
        assert_eq!(run.step(5, true, true, now), Step::Exit(AppExit::from_code(1)));
    }

    #[test]
    fn a_screenshot_never_captured_ends_the_run_with_an_error() {
        let mut run = ScriptedRun::new(1, Some(PathBuf::from("shot.png")));
        let steps = steps(&mut run, &[(true, true), (true, true), (true, true)]);
        assert_eq!(steps, [Step::Wait, Step::Capture, Step::Wait]);
        let late = run.waiting_since + READY_TIMEOUT + Duration::from_secs(1);
        assert_eq!(run.step(3, true, true, late), Step::Exit(AppExit::from_code(1)));
    }

    #[test]
    fn a_wait_past_the_timeout_goes_on() {
        let mut run = ScriptedRun::new(1, None);
        let late = run.waiting_since + READY_TIMEOUT + Duration::from_secs(1);
        assert_eq!(run.step(0, false, false, run.waiting_since), Step::Wait);
        assert_eq!(run.step(1, false, false, late), Step::Wait, "counting starts");
        assert_eq!(run.first_frame, Some(1));
        // Its frame done, the run waits for the pipelines, then ends anyway.
        let now = Instant::now();
        assert_eq!(run.step(2, false, false, now), Step::Wait);
        assert_eq!(
            run.step(3, false, false, now + READY_TIMEOUT + Duration::from_secs(1)),
            Step::Exit(AppExit::Success)
        );
    }
}
