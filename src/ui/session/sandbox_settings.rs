//! The sandbox's settings: every setting of the thesis, plus the window's
//! own. Saved between sessions by [`settings_file`](super::settings_file).

use std::path::PathBuf;

use bevy::prelude::*;
use serde::{Deserialize, Serialize};

use crate::execution::{ExecutionMode, MAX_THREADS, SplitPolicy, WorkerPool, available_threads};
use crate::input::ExecutionOptions;
use crate::resources::DrawMethod;
use crate::resources::{
    Applies, CollisionDetection, FragmentSizes, GravityMethod, Integrator, MAX_BODIES, MAX_FRAGMENT_SPREAD,
    MAX_FRAGMENTS, SettingValue, SimulationSettings, check,
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
/// `$start`, pushing its name onto `$taken`. Every field must be named: a
/// new one fails to compile.
macro_rules! take_changed {
    ($this:ident, $start:ident, $now:ident, $taken:ident; $($name:ident),* $(,)?) => {
        let SandboxSettings { $($name: _),* } = $now;
        $(
            if $now.$name != $start.$name {
                $this.$name = $now.$name.clone();
                $taken.push(stringify!($name));
            }
        )*
    };
}

/// Declares [`SandboxSettings`] with a field for each physics setting the
/// window holds (`[window]` in the settings list), named, documented and
/// defaulted as the list says, and the code that moves those fields between
/// the window and the simulation.
macro_rules! declare_sandbox_settings {
    ($(
        $(#[doc = $doc:literal])* $field:ident $(as $key:literal)?: $ty:ty = $default:expr,
            $rule:literal, $ok:expr, $applies:ident;
    )*) => {
        /// Everything the panel sets. Fields missing from a settings file
        /// take their default, so files written by older versions still
        /// load. The physics settings are named as their fields
        /// ([`SimulationSettings`]) are, which is the name in files except
        /// for `gravity_method` (`gravity` in scenarios).
        #[derive(Resource, Clone, Debug, PartialEq, Serialize, Deserialize)]
        #[serde(default, deny_unknown_fields)]
        pub struct SandboxSettings {
            /// Sequential or parallel stages (live).
            pub mode: ExecutionMode,
            /// Worker threads in parallel mode (live).
            pub threads: usize,
            /// From which body count stages split their work in parallel
            /// mode (live).
            pub split: SplitPolicy,
            /// Which pool runs the parallel steps (live): Kessler's own or
            /// Bevy's `ComputeTaskPool`.
            pub pool: WorkerPool,
            /// Wait for the display's refresh (live); off draws as fast as
            /// possible, as the thesis measured.
            pub vsync: bool,
            /// Draw the bodies at all (live).
            pub render_bodies: bool,
            /// Color cubes by state: colliding, fragment, speed (live).
            pub visual_effects: bool,
            /// Broad phase on/off (live).
            pub collisions: bool,
            /// Bounce and shatter on/off (live; the thesis's "collision
            /// effects", which older settings files call it).
            #[serde(alias = "collision_effects")]
            pub collision_response: bool,
            /// Gravity on/off (live).
            pub gravity: bool,
            $(
                $(#[doc = $doc])*
                #[doc = concat!("(The window applies it: `", stringify!($applies), "`.)")]
                pub $field: $ty,
            )*
            /// Target simulation updates per second, 1–600 (live).
            pub updates_per_second: u32,
            /// Factor on the update rate (live).
            pub speed: f32,
            /// Generated bodies; `None` keeps the scenario's count (on
            /// restart).
            pub body_count: Option<u64>,
            /// Scenario file; `None` is the built-in debris field (on
            /// restart).
            pub scenario: Option<PathBuf>,
            /// Camera (live).
            pub camera: CameraMode,
            /// Drawing method (live).
            pub render_method: DrawMethod,
            /// Show the planet's collision box (live).
            pub show_collision_boxes: bool,
            /// Trails besides the selected body's (live).
            pub trails: TrailChoice,
            /// How many bodies [`Self::trails`] picks, in
            /// [`TRAIL_COUNT_RANGE`] (live).
            pub trail_count: u32,
        }

        impl Default for SandboxSettings {
            fn default() -> Self {
                Self {
                    mode: ExecutionMode::Parallel,
                    threads: available_threads(),
                    split: SplitPolicy::Auto,
                    pool: WorkerPool::Kessler,
                    vsync: true,
                    render_bodies: true,
                    visual_effects: true,
                    collisions: true,
                    collision_response: true,
                    gravity: true,
                    $($field: SimulationSettings::DEFAULT.$field,)*
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
            /// Takes into `self` every field in which `now` differs from
            /// `start`, keeping its own value for the rest; returns the
            /// names of the fields taken. Saving uses it with the file's own
            /// values as `self`, the settings in force at start (after the
            /// command line's one-run choices) as `start` and the settings
            /// at exit as `now`: only what the user changed during the
            /// session reaches the file.
            pub fn take_changes(&mut self, start: &Self, now: &Self) -> Vec<&'static str> {
                let mut taken = Vec::new();
                take_changed!(self, start, now, taken;
                    mode, threads, split, pool, vsync, render_bodies, visual_effects, collisions,
                    collision_response, gravity, $($field,)* updates_per_second, speed, body_count,
                    scenario, camera, render_method, show_collision_boxes, trails, trail_count,
                );
                taken
            }

            /// The physics settings held to the settings list's rules: a
            /// value against its rule is replaced by the nearest allowed
            /// one, or the default.
            fn fix_physics(&mut self, fixes: &mut Fixes) {
                $(
                    fixes.check(stringify!($field), &mut self.$field, $rule, |&v| {
                        let ok = |v| check::$field(v).is_ok();
                        (!ok(v)).then(|| v.nearest_allowed(SimulationSettings::DEFAULT.$field, ok))
                    });
                )*
            }

            /// The panel's values in `base`: its physics settings and stage
            /// switches.
            fn physics_over(&self, base: &SimulationSettings) -> SimulationSettings {
                SimulationSettings {
                    $($field: self.$field,)*
                    gravity: self.gravity,
                    collisions: self.collisions,
                    collision_response: self.collision_response,
                    ..base.clone()
                }
            }

            /// The physics settings the panel holds that apply on restart
            /// and differ between `self` and `built`, by their names in
            /// files.
            pub fn restart_physics_changed(&self, built: &Self) -> Vec<&'static str> {
                let mut changed = Vec::new();
                $(
                    if self.$field != built.$field && Applies::$applies == Applies::OnRestart {
                        changed.push(crate::resources::key!($field $($key)?));
                    }
                )*
                changed
            }

            /// Takes `physics`' values of the physics settings the panel
            /// holds: those the window applies live, or all.
            fn adopt(&mut self, physics: &SimulationSettings, live_only: bool) {
                $(
                    if !live_only || Applies::$applies == Applies::Live {
                        self.$field = physics.$field;
                    }
                )*
            }
        }
    };
}

crate::resources::held_by!(window declare_sandbox_settings);

impl SandboxSettings {
    /// How the simulation executes, every option given.
    pub fn execution(&self) -> ExecutionOptions {
        ExecutionOptions {
            mode: Some(self.mode),
            threads: Some(self.threads),
            split: Some(self.split),
            pool: Some(self.pool),
        }
    }

    /// Takes each option `options` gives.
    pub fn set_execution(&mut self, options: ExecutionOptions) {
        self.mode = options.mode.unwrap_or(self.mode);
        self.threads = options.threads.unwrap_or(self.threads);
        self.split = options.split.unwrap_or(self.split);
        self.pool = options.pool.unwrap_or(self.pool);
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

/// `value` as a settings file writes it, on one line: `Tree(theta: NaN)`,
/// `Some(5000000)`, `2.5`.
fn as_written<T: Serialize>(value: &T) -> String {
    let one_line = ron::ser::PrettyConfig::new().depth_limit(0);
    ron::ser::to_string_pretty(value, one_line).unwrap_or_else(|e| format!("(not writable: {e})"))
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
        let threads = 1..=max_threads();
        fixes.check(
            "threads",
            &mut self.threads,
            &format!("1 to {} on this machine, twice its hardware threads", threads.end()),
            |&n| clamped(n, &threads),
        );
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
        self.fix_physics(&mut fixes);
        fixes.check(
            "trail_count",
            &mut self.trail_count,
            &range_text(&TRAIL_COUNT_RANGE),
            |&n| clamped(n, &TRAIL_COUNT_RANGE),
        );
        fixes.0
    }

    /// Copies the live physics settings and the stage switches into the
    /// simulation's settings.
    pub fn apply_physics(&self, physics: &mut SimulationSettings) {
        let panel = self.physics_over(physics);
        physics.take_live(&panel);
        physics.gravity = panel.gravity;
        physics.collisions = panel.collisions;
        physics.collision_response = panel.collision_response;
    }

    /// The physics a scene is rebuilt with: the scenario's, with every
    /// setting the panel holds (live or on restart) and its stage switches.
    pub fn physics_for_restart(&self, scenario: &SimulationSettings) -> SimulationSettings {
        self.physics_over(scenario)
    }

    /// Takes the running simulation's values of the live physics settings
    /// (after a `Set` event or a rewind changed them).
    pub fn adopt_live(&mut self, physics: &SimulationSettings) {
        self.adopt(physics, true);
    }

    /// Takes a freshly loaded scenario's own values of the physics
    /// settings the panel holds.
    pub fn adopt_scenario(&mut self, physics: &SimulationSettings) {
        self.adopt(physics, false);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_window_holds_the_settings_the_list_gives_it_and_no_others() {
        let file = ron::ser::to_string(&SandboxSettings::default()).unwrap();
        for row in crate::resources::SETTINGS {
            let held = file.contains(&format!("{}:", row.field));
            assert_eq!(held, row.holders.contains(&"window"), "{}: {file}", row.field);
        }
        // The window's defaults are the list's, and what it does not hold
        // comes from the scenario.
        assert_eq!(
            SandboxSettings::default().physics_over(&SimulationSettings::DEFAULT),
            SimulationSettings::DEFAULT
        );
        let scenario = SimulationSettings {
            time_step: 0.5,
            softening: 2.0,
            ..SimulationSettings::DEFAULT
        };
        assert_eq!(SandboxSettings::default().physics_over(&scenario), scenario);
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
            let mut settings = SandboxSettings {
                fragment_spread: bad,
                ..SandboxSettings::default()
            };
            let fixed: Vec<_> = settings.sanitize().into_iter().map(|f| f.field).collect();
            assert_eq!(fixed, ["fragment_spread"], "{bad}");
            assert_eq!(settings.fragment_spread, 0.2);
        }
        let mut physics = SimulationSettings::default();
        SandboxSettings {
            fragment_spread: 0.7,
            ..SandboxSettings::default()
        }
        .apply_physics(&mut physics);
        assert_eq!(physics.fragment_spread, 0.7, "live");
    }

    #[test]
    fn every_value_out_of_range_is_named_with_what_is_used_instead() {
        let mut settings = SandboxSettings {
            threads: max_threads() + 1,
            shatter_fragments: crate::scenario::MAX_FRAGMENTS + 1,
            shatter_threshold: -1.0,
            updates_per_second: 0,
            ..SandboxSettings::default()
        };
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
        assert_eq!(settings.threads, max_threads());
        assert_eq!(settings.shatter_fragments, crate::scenario::MAX_FRAGMENTS);
        assert_eq!(
            settings.shatter_threshold,
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
            gravity_method: GravityMethod::Tree { theta: f32::NAN },
            body_count: Some(MAX_BODY_COUNT + 1),
            ..SandboxSettings::default()
        };
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
        let mut settings = SandboxSettings {
            threads: 1,
            shatter_fragments: 50,
            shatter_threshold: 100.0,
            gravity_method: GravityMethod::Tree { theta: 1.9 },
            ..SandboxSettings::default()
        };
        let before = settings.clone();
        assert!(settings.sanitize().is_empty());
        assert_eq!(settings, before);
    }

    #[test]
    fn only_the_fields_changed_since_start_are_taken() {
        // The file's own values (one out of range), the settings at start
        // (sanitized, with one-run choices from the command line), and at
        // exit (the user changed the threads).
        let file = SandboxSettings {
            threads: 999,
            seed: 5,
            body_count: None,
            ..SandboxSettings::default()
        };
        let start = SandboxSettings {
            threads: max_threads(),
            body_count: Some(200),
            scenario: Some(PathBuf::from("other.ron")),
            seed: 6,
            ..file.clone()
        };
        let now = SandboxSettings {
            threads: 1,
            ..start.clone()
        };
        let mut saved = file.clone();
        assert_eq!(saved.take_changes(&start, &now), ["threads"]);
        assert_eq!(
            saved,
            SandboxSettings {
                threads: 1,
                ..file.clone()
            }
        );

        let mut untouched = file.clone();
        assert!(untouched.take_changes(&start, &start).is_empty());
        assert_eq!(untouched, file, "an out-of-range value nobody touched is kept");
    }
}
