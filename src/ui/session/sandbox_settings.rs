//! The sandbox's settings: every setting of the thesis, plus the window's
//! own. Saved between sessions by [`settings_file`](super::settings_file).

use std::path::PathBuf;

use bevy::prelude::*;
use serde::{Deserialize, Serialize};

use crate::execution::{MAX_THREADS, available_threads};
use crate::input::ExecutionOptions;
use crate::resources::{
    Applies, DrawMethod, MAX_BODIES, MAX_FRAGMENT_SPREAD, MAX_FRAGMENTS, SimulationSettings, as_written,
};

/// Slowest and fastest target update rate, updates per second.
pub const UPS_RANGE: std::ops::RangeInclusive<u32> = 1..=600;
/// Slowest and fastest simulation speed (a factor on the update rate).
pub const SPEED_RANGE: std::ops::RangeInclusive<f32> = 0.05..=8.0;
/// Smallest and largest fragment spread the panel's slider offers (a
/// share of the impact speed).
pub const FRAGMENT_SPREAD_RANGE: std::ops::RangeInclusive<f32> = 0.0..=MAX_FRAGMENT_SPREAD;
/// Most bodies the panel offers: as many as `--bodies` accepts.
pub const MAX_BODY_COUNT: u64 = crate::input::MAX_RUN_BODIES;
/// Smallest and largest size floor the panel's slider offers, edge lengths
/// (a settings file may hold more: the settings list's rule is the bound).
pub const MIN_FRAGMENT_SIZE_RANGE: std::ops::RangeInclusive<f32> = 0.0..=100.0;
/// Smallest and largest body budget.
pub const MAX_BODIES_RANGE: std::ops::RangeInclusive<u64> = 1..=MAX_BODIES;
/// Fewest and most fragments a shatter makes (the scenario format's bounds;
/// the panel's slider offers the low end).
pub const SHATTER_FRAGMENTS_RANGE: std::ops::RangeInclusive<u32> = 2..=MAX_FRAGMENTS;
/// Fewest and most fragments drawn with a trail.
pub const TRAIL_COUNT_RANGE: std::ops::RangeInclusive<u32> = 1..=200;

/// `a to b`, as a warning names an allowed range.
fn range_text<T: std::fmt::Debug>(range: &std::ops::RangeInclusive<T>) -> String {
    format!("{:?} to {:?}", range.start(), range.end())
}

/// Which bodies besides the selected one draw their recent path.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum TrailChoice {
    /// Only the selected body (no cost for the rest).
    #[default]
    Off,
    /// The fastest bodies that interact.
    Fastest,
    /// The fragments born last.
    Newest,
}

impl TrailChoice {
    /// Every choice, in panel order.
    pub const ALL: [Self; 3] = [Self::Off, Self::Fastest, Self::Newest];

    /// What the panel calls it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Off => "selected only",
            Self::Fastest => "fastest",
            Self::Newest => "newest fragments",
        }
    }
}

/// Which camera drives the view.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum CameraMode {
    /// Orbit around a focus point (drag to orbit, right-drag to pan, wheel to zoom).
    #[default]
    Orbit,
    /// Free flight: WASD, Q/E down/up, Shift fast, right mouse button to look.
    Fly,
    /// Orbit around the selected body, following it.
    Follow,
}

impl CameraMode {
    /// Every camera, in the order the camera key cycles through them.
    pub const ALL: [Self; 3] = [Self::Orbit, Self::Fly, Self::Follow];

    /// What the panel calls it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Orbit => "orbit",
            Self::Fly => "free fly",
            Self::Follow => "follow",
        }
    }

    /// The next camera in [`Self::ALL`] (the camera key cycles with it).
    pub fn next(self) -> Self {
        Self::ALL[(Self::ALL.iter().position(|&m| m == self).unwrap_or(0) + 1) % Self::ALL.len()]
    }
}

/// In `$this`, takes every field named in which `$now` differs from
/// `$start`, pushing its name onto `$taken`.
macro_rules! take_changed {
    ($this:expr, $start:expr, $now:expr, $taken:ident; $($name:ident),* $(,)?) => {
        $(
            if $now.$name != $start.$name {
                $this.$name = $now.$name.clone();
                $taken.push(stringify!($name));
            }
        )*
    };
}

/// Everything the panel sets. Fields missing from a settings file take
/// their default, so files written by older versions still load (read by
/// [`settings_file`](super::settings_file), which also reads the flat
/// layout of files written before `execution` and `physics` were fields).
#[derive(Resource, Clone, Debug, PartialEq, Serialize)]
#[serde(rename = "SandboxSettings")]
pub struct SandboxSettings {
    /// How the simulation executes (live): every option given.
    pub execution: ExecutionOptions,
    /// The physics and the stage switches: the scenario's when it is
    /// loaded, then as the panel changes them; each setting applied live
    /// or on restart as its rule says ([`crate::resources::rules`]).
    pub physics: SimulationSettings,
    /// Wait for the display's refresh (live); off draws as fast as
    /// possible, as the thesis measured.
    pub vsync: bool,
    /// Draw the bodies at all (live).
    pub render_bodies: bool,
    /// Color cubes by state: colliding, fragment, speed (live).
    pub visual_effects: bool,
    /// Target simulation updates per second, 1–600 (live).
    pub updates_per_second: u32,
    /// Factor on the update rate (live).
    pub speed: f32,
    /// Generated bodies; `None` keeps the scenario's count (on restart).
    pub body_count: Option<u64>,
    /// Scenario file; `None` is the built-in debris field (on restart).
    pub scenario: Option<PathBuf>,
    /// Camera (live).
    pub camera: CameraMode,
    /// Drawing method (live).
    pub render_method: DrawMethod,
    /// Show the planet's collision box (live).
    pub show_collision_boxes: bool,
    /// Trails besides the selected body's (live).
    pub trails: TrailChoice,
    /// How many bodies [`Self::trails`] picks, in [`TRAIL_COUNT_RANGE`]
    /// (live).
    pub trail_count: u32,
}

impl Default for SandboxSettings {
    fn default() -> Self {
        Self {
            execution: ExecutionOptions::defaults(),
            physics: SimulationSettings::DEFAULT,
            vsync: true,
            render_bodies: true,
            visual_effects: true,
            updates_per_second: 60,
            speed: 1.0,
            body_count: None,
            scenario: None,
            camera: CameraMode::Orbit,
            render_method: DrawMethod::Instanced,
            show_collision_boxes: false,
            trails: TrailChoice::Off,
            trail_count: 20,
        }
    }
}

impl SandboxSettings {
    /// Takes into `self` every field in which `now` differs from `start`,
    /// keeping its own value for the rest; returns the names of the fields
    /// taken (an execution option, a physics setting or a stage switch by
    /// its own name). Saving uses it with the file's own values as `self`,
    /// the settings in force at start (after the command line's one-run
    /// choices) as `start` and the settings at exit as `now`: only what the
    /// user changed during the session reaches the file.
    pub fn take_changes(&mut self, start: &Self, now: &Self) -> Vec<&'static str> {
        let mut taken = Vec::new();
        take_changed!(self.execution, start.execution, now.execution, taken; mode, threads, split, pool);
        for setting in start.physics.differing(&now.physics) {
            self.physics.take(setting.key, &now.physics);
            taken.push(setting.field);
        }
        take_changed!(self.physics.stages, start.physics.stages, now.physics.stages, taken;
            gravity, collisions, collision_response);
        take_changed!(self, start, now, taken;
            vsync, render_bodies, visual_effects, updates_per_second, speed, body_count, scenario, camera,
            render_method, show_collision_boxes, trails, trail_count,
        );
        taken
    }

    /// The physics settings that apply on restart and differ between
    /// `self` and `built`, by their names in files.
    pub fn restart_physics_changed(&self, built: &Self) -> Vec<&'static str> {
        built
            .physics
            .differing(&self.physics)
            .into_iter()
            .filter(|s| s.applies == Applies::OnRestart)
            .map(|s| s.key)
            .collect()
    }

    /// Copies the live physics settings and the stage switches into the
    /// simulation's settings.
    pub fn apply_physics(&self, physics: &mut SimulationSettings) {
        physics.take_live(&self.physics);
        physics.stages = self.physics.stages;
    }

    /// The physics a scene is rebuilt with: the panel's, every setting
    /// (live or on restart) and its stage switches.
    pub fn physics_for_restart(&self) -> SimulationSettings {
        self.physics.clone()
    }

    /// Takes the running simulation's values of the live physics settings
    /// (after a `Set` event or a rewind changed them).
    pub fn adopt_live(&mut self, physics: &SimulationSettings) {
        self.physics.take_live(physics);
    }

    /// Takes a freshly loaded scenario's own physics settings; the stage
    /// switches stay as the panel has them.
    pub fn adopt_scenario(&mut self, physics: &SimulationSettings) {
        self.physics = SimulationSettings {
            stages: self.physics.stages,
            ..physics.clone()
        };
    }
}

/// The most worker threads the window offers on this machine: twice its
/// hardware threads (to show what oversubscription costs), at most
/// [`MAX_THREADS`].
pub fn max_threads() -> usize {
    available_threads().saturating_mul(2).clamp(2, MAX_THREADS)
}

/// A value from a settings file outside what the sandbox allows, and what is
/// used instead this session.
#[derive(Clone, Debug, PartialEq)]
pub struct OutOfRange {
    /// The field, as the file names it.
    pub field: &'static str,
    /// The value the file holds.
    pub found: String,
    /// What is allowed.
    pub allowed: String,
    /// The value used instead.
    pub used: String,
}

impl std::fmt::Display for OutOfRange {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} {} is out of range ({}), using {}",
            self.field, self.found, self.allowed, self.used
        )
    }
}

/// Collects the fields [`SandboxSettings::sanitize`] replaces.
struct Fixes(Vec<OutOfRange>);

impl Fixes {
    /// Replaces `value` by what `fix` gives for it, if anything, noting it.
    fn check<T: Serialize>(
        &mut self,
        field: &'static str,
        value: &mut T,
        allowed: &str,
        fix: impl FnOnce(&T) -> Option<T>,
    ) {
        let Some(used) = fix(value) else {
            return;
        };
        self.0.push(OutOfRange {
            field,
            found: as_written(value),
            allowed: allowed.to_owned(),
            used: as_written(&used),
        });
        *value = used;
    }
}

/// The value clamped into `range` if it lies outside.
fn clamped<T: PartialOrd + Copy>(value: T, range: &std::ops::RangeInclusive<T>) -> Option<T> {
    if range.contains(&value) {
        None
    } else if value < *range.start() {
        Some(*range.start())
    } else {
        Some(*range.end())
    }
}

impl SandboxSettings {
    /// Values out of range replaced by the nearest allowed one (or the
    /// default, where there is no nearest); returns what was replaced, for
    /// the warning. These are the only bounds a loaded value is held to:
    /// the panel's widgets never change a value the user did not edit, even
    /// one beyond the widget's own range (a slider offers a convenient part
    /// of what is allowed).
    pub fn sanitize(&mut self) -> Vec<OutOfRange> {
        let mut fixes = Fixes(Vec::new());
        // Every option given: what the file leaves out at its default.
        self.execution = self.execution.resolved();
        let threads = 1..=max_threads();
        if let Some(n) = &mut self.execution.threads {
            fixes.check(
                "threads",
                n,
                &format!("1 to {} on this machine, twice its hardware threads", threads.end()),
                |&n| clamped(n, &threads),
            );
        }
        fixes.check(
            "updates_per_second",
            &mut self.updates_per_second,
            &range_text(&UPS_RANGE),
            |&ups| clamped(ups, &UPS_RANGE),
        );
        fixes.check("speed", &mut self.speed, &range_text(&SPEED_RANGE), |&speed| {
            if speed.is_nan() {
                Some(1.0)
            } else {
                clamped(speed, &SPEED_RANGE)
            }
        });
        fixes.check(
            "body_count",
            &mut self.body_count,
            &format!("None or Some(0 to {MAX_BODY_COUNT})"),
            |&count| {
                count
                    .is_some_and(|n| n > MAX_BODY_COUNT)
                    .then_some(Some(MAX_BODY_COUNT))
            },
        );
        self.physics.fix_problems(|setting, found, used| {
            fixes.0.push(OutOfRange {
                field: setting.field,
                found,
                allowed: setting.rule.to_owned(),
                used,
            });
        });
        fixes.check(
            "trail_count",
            &mut self.trail_count,
            &range_text(&TRAIL_COUNT_RANGE),
            |&n| clamped(n, &TRAIL_COUNT_RANGE),
        );
        fixes.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_restart_builds_with_the_panels_physics_and_a_loaded_scenario_sets_them() {
        let scenario = SimulationSettings {
            time_step: 0.5,
            softening: 2.0,
            ..SimulationSettings::DEFAULT
        };
        let mut settings = SandboxSettings::default();
        settings.physics.stages.collisions = false;
        settings.adopt_scenario(&scenario);
        assert_eq!(settings.physics.time_step, 0.5);
        assert!(
            !settings.physics.stages.collisions,
            "the stage switches stay the panel's"
        );
        settings.physics.seed = 9;
        let built = settings.physics_for_restart();
        assert_eq!((built.time_step, built.seed), (0.5, 9));
        let before = SandboxSettings::default();
        assert_eq!(
            settings.restart_physics_changed(&before),
            ["time_step", "softening", "seed"]
        );
    }

    #[test]
    fn camera_key_cycles_through_all_cameras() {
        let mut mode = CameraMode::Orbit;
        let mut seen = Vec::new();
        for _ in 0..CameraMode::ALL.len() {
            seen.push(mode);
            mode = mode.next();
        }
        assert_eq!(mode, CameraMode::Orbit);
        assert_eq!(seen, CameraMode::ALL);
    }

    #[test]
    fn a_fragment_spread_out_of_range_is_replaced_and_named() {
        for bad in [f32::NAN, -0.1, 11.0] {
            let mut settings = SandboxSettings::default();
            settings.physics.fragment_spread = bad;
            let fixed: Vec<_> = settings.sanitize().into_iter().map(|f| f.field).collect();
            assert_eq!(fixed, ["fragment_spread"], "{bad}");
            assert_eq!(settings.physics.fragment_spread, 0.2);
        }
        let mut physics = SimulationSettings::default();
        let mut settings = SandboxSettings::default();
        settings.physics.fragment_spread = 0.7;
        settings.physics.time_step = 0.25;
        settings.apply_physics(&mut physics);
        assert_eq!(physics.fragment_spread, 0.7, "live");
        assert_eq!(physics.time_step, 1.0, "on restart");
    }

    #[test]
    fn every_value_out_of_range_is_named_with_what_is_used_instead() {
        let mut settings = SandboxSettings {
            updates_per_second: 0,
            ..SandboxSettings::default()
        };
        settings.execution.threads = Some(max_threads() + 1);
        settings.physics.shatter_fragments = crate::scenario::MAX_FRAGMENTS + 1;
        settings.physics.shatter_threshold = -1.0;
        let fixes = settings.sanitize();
        let fields: Vec<_> = fixes.iter().map(|f| f.field).collect();
        assert_eq!(
            fields,
            [
                "threads",
                "updates_per_second",
                "shatter_threshold",
                "shatter_fragments"
            ]
        );
        assert_eq!(settings.execution.threads, Some(max_threads()));
        assert_eq!(settings.physics.shatter_fragments, crate::scenario::MAX_FRAGMENTS);
        assert_eq!(
            settings.physics.shatter_threshold,
            SimulationSettings::default().shatter_threshold
        );
        assert_eq!(settings.updates_per_second, 1);
        let text = fixes[0].to_string();
        assert!(
            text.starts_with(&format!(
                "threads {} is out of range (1 to {}",
                max_threads() + 1,
                max_threads()
            )) && text.ends_with(&format!("using {}", max_threads())),
            "{text}"
        );
        assert_eq!(
            fixes[2].to_string(),
            format!(
                "shatter_threshold -1.0 is out of range (finite and >= 0), using {:?}",
                SimulationSettings::default().shatter_threshold
            )
        );
        assert!(settings.sanitize().is_empty(), "sanitized settings stay as they are");
    }

    #[test]
    fn a_value_out_of_range_is_shown_as_the_file_writes_it() {
        let mut settings = SandboxSettings {
            body_count: Some(MAX_BODY_COUNT + 1),
            ..SandboxSettings::default()
        };
        settings.physics.gravity_method = crate::resources::GravityMethod::Tree { theta: f32::NAN };
        let texts: Vec<String> = settings.sanitize().iter().map(ToString::to_string).collect();
        for said in [
            "body_count Some(2000001) is out of range (None or Some(0 to 2000000)), using Some(2000000)".to_owned(),
            format!(
                "gravity_method Tree(theta: NaN) is out of range ({}), using Auto",
                crate::resources::setting("gravity").unwrap().rule
            ),
        ] {
            assert!(texts.contains(&said), "{said:?} not in {texts:?}");
        }
    }

    #[test]
    fn values_beyond_the_panel_sliders_but_allowed_are_kept() {
        let mut settings = SandboxSettings::default();
        settings.execution.threads = Some(1);
        settings.physics.shatter_fragments = 50;
        settings.physics.shatter_threshold = 100.0;
        settings.physics.gravity_method = crate::resources::GravityMethod::Tree { theta: 1.9 };
        let before = settings.clone();
        assert!(settings.sanitize().is_empty());
        assert_eq!(settings, before);
    }

    #[test]
    fn only_the_fields_changed_since_start_are_taken() {
        // The file's own values (one out of range), the settings at start
        // (sanitized, with one-run choices from the command line), and at
        // exit (the user changed the threads).
        let mut file = SandboxSettings::default();
        file.execution.threads = Some(999);
        file.physics.seed = 5;
        let mut start = SandboxSettings {
            body_count: Some(200),
            scenario: Some(PathBuf::from("other.ron")),
            ..file.clone()
        };
        start.execution.threads = Some(max_threads());
        start.physics.seed = 6;
        let mut now = start.clone();
        now.execution.threads = Some(1);
        now.physics.shatter_threshold = 7.0;
        now.physics.stages.gravity = false;
        let mut saved = file.clone();
        assert_eq!(
            saved.take_changes(&start, &now),
            ["threads", "shatter_threshold", "gravity"]
        );
        let mut expected = file.clone();
        expected.execution.threads = Some(1);
        expected.physics.shatter_threshold = 7.0;
        expected.physics.stages.gravity = false;
        assert_eq!(saved, expected, "the seed the command line chose is not saved");

        let mut untouched = file.clone();
        assert!(untouched.take_changes(&start, &start).is_empty());
        assert_eq!(untouched, file, "an out-of-range value nobody touched is kept");
    }
}
