//! The sandbox's settings: every setting of the thesis, plus the window's
//! own. Saved between sessions by [`settings_file`](super::settings_file).

use std::path::PathBuf;

use bevy::prelude::*;
use serde::{Deserialize, Serialize};

use crate::draw_method::DrawMethod;
use crate::execution::{ExecutionMode, MAX_THREADS, SplitPolicy, available_threads};
use crate::resources::{DEFAULT_THETA, GravityMethod, SimulationSettings};

/// Slowest and fastest target update rate, updates per second.
pub const UPS_RANGE: std::ops::RangeInclusive<u32> = 1..=600;
/// Slowest and fastest simulation speed (a factor on the update rate).
pub const SPEED_RANGE: std::ops::RangeInclusive<f32> = 0.05..=8.0;
/// Smallest and largest fragment spread (a share of the impact speed).
pub const FRAGMENT_SPREAD_RANGE: std::ops::RangeInclusive<f32> = 0.0..=10.0;
/// Most bodies the panel offers.
pub const MAX_BODY_COUNT: u64 = 2_000_000;
/// Smallest and largest size floor the panel offers, edge lengths.
pub const MIN_FRAGMENT_SIZE_RANGE: std::ops::RangeInclusive<f32> = 0.0..=100.0;
/// Smallest and largest body budget.
pub const MAX_BODIES_RANGE: std::ops::RangeInclusive<u64> = 1..=crate::scenario::MAX_BODIES;
/// Fewest and most fragments drawn with a trail.
pub const TRAIL_COUNT_RANGE: std::ops::RangeInclusive<u32> = 1..=200;

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

/// Everything the panel sets. Fields missing from a settings file take their
/// default, so files written by older versions still load.
#[derive(Resource, Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SandboxSettings {
    /// Sequential or parallel stages (live).
    pub mode: ExecutionMode,
    /// Worker threads in parallel mode (live).
    pub threads: usize,
    /// From which body count stages split their work in parallel mode
    /// (live).
    pub split: SplitPolicy,
    /// Wait for the display's refresh (live); off draws as fast as
    /// possible, as the thesis measured.
    pub vsync: bool,
    /// Draw the bodies at all (live).
    pub render_bodies: bool,
    /// Color cubes by state: colliding, fragment, speed (live).
    pub visual_effects: bool,
    /// Broad phase on/off (live).
    pub collisions: bool,
    /// Bounce and shatter on/off (live; the thesis's "collision effects",
    /// which older settings files call it).
    #[serde(alias = "collision_effects")]
    pub collision_response: bool,
    /// Gravity on/off (live).
    pub gravity: bool,
    /// Direct sum or Barnes–Hut tree (live).
    pub gravity_method: GravityMethod,
    /// Target simulation updates per second, 1–600 (live).
    pub updates_per_second: u32,
    /// Factor on the update rate (live).
    pub speed: f32,
    /// Generated bodies; `None` keeps the scenario's count (on restart).
    pub body_count: Option<u64>,
    /// Seed of the generators and of fragment spread (on restart).
    pub seed: u64,
    /// Fragments per shatter, ≥ 2 (live).
    pub shatter_fragments: u32,
    /// Impact speed from which bodies shatter (live).
    pub shatter_threshold: f32,
    /// Fragments' spread as a share of the impact speed, 0–10 (live; the
    /// thesis's "Streuung").
    pub fragment_spread: f32,
    /// Edge below which a collision bounces instead of shattering (live).
    pub min_fragment_size: f32,
    /// Most bodies; a shatter beyond bounces instead (live).
    pub max_bodies: u64,
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
    /// How many bodies [`Self::trails`] picks, in [`TRAIL_COUNT_RANGE`] (live).
    pub trail_count: u32,
}

impl Default for SandboxSettings {
    fn default() -> Self {
        let physics = SimulationSettings::default();
        Self {
            mode: ExecutionMode::Parallel,
            threads: available_threads(),
            split: SplitPolicy::Auto,
            vsync: true,
            render_bodies: true,
            visual_effects: true,
            collisions: true,
            collision_response: true,
            gravity: true,
            gravity_method: physics.gravity_method,
            updates_per_second: 60,
            speed: 1.0,
            body_count: None,
            seed: physics.seed,
            shatter_fragments: physics.shatter_fragments,
            shatter_threshold: physics.shatter_threshold,
            fragment_spread: physics.fragment_spread,
            min_fragment_size: physics.min_fragment_size,
            max_bodies: physics.max_bodies,
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
    /// Values out of range replaced by the nearest allowed one; returns the
    /// names of the fields that were changed.
    pub fn sanitize(&mut self) -> Vec<&'static str> {
        let mut fixed = Vec::new();
        if !(1..=MAX_THREADS).contains(&self.threads) {
            self.threads = self.threads.clamp(1, MAX_THREADS);
            fixed.push("threads");
        }
        if !UPS_RANGE.contains(&self.updates_per_second) {
            self.updates_per_second = self.updates_per_second.clamp(*UPS_RANGE.start(), *UPS_RANGE.end());
            fixed.push("updates_per_second");
        }
        if !SPEED_RANGE.contains(&self.speed) {
            self.speed = if self.speed.is_nan() {
                1.0
            } else {
                self.speed.clamp(*SPEED_RANGE.start(), *SPEED_RANGE.end())
            };
            fixed.push("speed");
        }
        if self.body_count.is_some_and(|n| n > MAX_BODY_COUNT) {
            self.body_count = Some(MAX_BODY_COUNT);
            fixed.push("body_count");
        }
        if self.shatter_fragments < 2 {
            self.shatter_fragments = 2;
            fixed.push("shatter_fragments");
        }
        if !(self.shatter_threshold.is_finite() && self.shatter_threshold >= 0.0) {
            self.shatter_threshold = SimulationSettings::default().shatter_threshold;
            fixed.push("shatter_threshold");
        }
        if self.gravity_method.check().is_err() {
            self.gravity_method = GravityMethod::Tree { theta: DEFAULT_THETA };
            fixed.push("gravity_method");
        }
        if !TRAIL_COUNT_RANGE.contains(&self.trail_count) {
            self.trail_count = self
                .trail_count
                .clamp(*TRAIL_COUNT_RANGE.start(), *TRAIL_COUNT_RANGE.end());
            fixed.push("trail_count");
        }
        if !MIN_FRAGMENT_SIZE_RANGE.contains(&self.min_fragment_size) {
            self.min_fragment_size = SimulationSettings::default().min_fragment_size;
            fixed.push("min_fragment_size");
        }
        if !MAX_BODIES_RANGE.contains(&self.max_bodies) {
            self.max_bodies = self
                .max_bodies
                .clamp(*MAX_BODIES_RANGE.start(), *MAX_BODIES_RANGE.end());
            fixed.push("max_bodies");
        }
        if !FRAGMENT_SPREAD_RANGE.contains(&self.fragment_spread) {
            self.fragment_spread = SimulationSettings::default().fragment_spread;
            fixed.push("fragment_spread");
        }
        fixed
    }

    /// Copies the live physics switches into the simulation's settings.
    pub fn apply_physics(&self, physics: &mut SimulationSettings) {
        physics.gravity = self.gravity;
        physics.collisions = self.collisions;
        physics.collision_response = self.collision_response;
        physics.shatter_fragments = self.shatter_fragments.max(2);
        physics.shatter_threshold = self.shatter_threshold;
        physics.fragment_spread = self.fragment_spread;
        physics.min_fragment_size = self.min_fragment_size;
        physics.max_bodies = self.max_bodies;
        physics.gravity_method = self.gravity_method;
    }

    /// Takes a freshly loaded scenario's own values (seed, fragments,
    /// threshold, spread) into the settings.
    pub fn adopt_scenario(&mut self, physics: &SimulationSettings) {
        self.seed = physics.seed;
        self.shatter_fragments = physics.shatter_fragments;
        self.shatter_threshold = physics.shatter_threshold;
        self.fragment_spread = physics.fragment_spread;
        self.min_fragment_size = physics.min_fragment_size;
        self.max_bodies = physics.max_bodies;
        self.gravity_method = physics.gravity_method;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
            assert_eq!(settings.sanitize(), ["fragment_spread"], "{bad}");
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
}
