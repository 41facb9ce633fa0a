//! The sandbox's settings (every setting of the thesis, plus the app's own)
//! and their persistence as a RON file.
//!
//! The file is read at start; a missing file means defaults, a broken or
//! foreign one means defaults and a warning, and it is left alone until the
//! user changes a setting. Saving writes a temporary file beside it and
//! renames it over, so a crash mid-write never leaves half a file.

use std::fmt;
use std::path::{Path, PathBuf};

use bevy::prelude::*;
use serde::{Deserialize, Serialize};

use crate::resources::{ExecutionMode, MAX_THREADS, SimulationSettings, available_threads};

/// Slowest and fastest target update rate, updates per second.
pub const UPS_RANGE: std::ops::RangeInclusive<u32> = 1..=600;
/// Slowest and fastest simulation speed (a factor on the update rate).
pub const SPEED_RANGE: std::ops::RangeInclusive<f32> = 0.05..=8.0;
/// Most bodies the panel offers.
pub const MAX_BODY_COUNT: u64 = 2_000_000;

/// How the bodies are drawn.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum RenderMethod {
    /// One instanced draw for all cubes (the fast way).
    #[default]
    Instanced,
    /// One Bevy mesh entity per body, sharing one mesh and one material
    /// (Bevy batches them, but every entity is extracted and culled).
    Meshes,
}

impl RenderMethod {
    pub fn name(self) -> &'static str {
        match self {
            Self::Instanced => "instanced",
            Self::Meshes => "meshes",
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
    pub const ALL: [Self; 3] = [Self::Orbit, Self::Fly, Self::Follow];

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
    pub threads: u16,
    /// Draw the bodies at all (live).
    pub render_bodies: bool,
    /// Colour cubes by state: colliding, fragment, speed (live).
    pub visual_effects: bool,
    /// Broad phase on/off (live).
    pub collisions: bool,
    /// Bounce and shatter on/off (live).
    pub collision_effects: bool,
    /// Gravity on/off (live).
    pub gravity: bool,
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
    /// Scenario file; `None` is the built-in debris field (on restart).
    pub scenario: Option<PathBuf>,
    /// Camera (live).
    pub camera: CameraMode,
    /// Drawing method (live).
    pub render_method: RenderMethod,
    /// Show the planet's collision box (live).
    pub show_collision_boxes: bool,
}

impl Default for SandboxSettings {
    fn default() -> Self {
        let physics = SimulationSettings::default();
        Self {
            mode: ExecutionMode::Parallel,
            threads: u16::try_from(available_threads()).unwrap_or(u16::MAX),
            render_bodies: true,
            visual_effects: true,
            collisions: true,
            collision_effects: true,
            gravity: true,
            updates_per_second: 60,
            speed: 1.0,
            body_count: None,
            seed: physics.seed,
            shatter_fragments: physics.shatter_fragments,
            shatter_threshold: physics.shatter_threshold,
            scenario: None,
            camera: CameraMode::Orbit,
            render_method: RenderMethod::Instanced,
            show_collision_boxes: false,
        }
    }
}

impl SandboxSettings {
    /// Values out of range replaced by the nearest allowed one; returns the
    /// names of the fields that were changed.
    pub fn sanitize(&mut self) -> Vec<&'static str> {
        let mut fixed = Vec::new();
        let max_threads = u16::try_from(MAX_THREADS).unwrap_or(u16::MAX);
        if !(1..=max_threads).contains(&self.threads) {
            self.threads = self.threads.clamp(1, max_threads);
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
        fixed
    }

    /// Copies the live physics switches into the simulation's settings.
    pub fn apply_physics(&self, physics: &mut SimulationSettings) {
        physics.gravity = self.gravity;
        physics.collisions = self.collisions;
        physics.collision_response = self.collision_effects;
        physics.shatter_fragments = self.shatter_fragments.max(2);
        physics.shatter_threshold = self.shatter_threshold;
    }

    /// Takes a freshly loaded scenario's own values (seed, fragments,
    /// threshold) into the settings.
    pub fn adopt_scenario(&mut self, physics: &SimulationSettings) {
        self.seed = physics.seed;
        self.shatter_fragments = physics.shatter_fragments;
        self.shatter_threshold = physics.shatter_threshold;
    }
}

/// Why the settings file could not be used.
#[derive(Debug)]
pub struct SettingsWarning(pub String);

impl fmt::Display for SettingsWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

/// The settings file, what was last read from or written to it, and any
/// warning about it.
#[derive(Resource, Clone, Debug)]
pub struct SettingsFile {
    pub path: PathBuf,
    /// The settings as the file holds them (`None`: unreadable or missing),
    /// so an unchanged session does not rewrite it.
    pub saved: Option<SandboxSettings>,
    /// The settings that were in force at start; nothing is saved while the
    /// settings still equal them.
    pub initial: SandboxSettings,
    /// Problem with the file, shown in the HUD.
    pub warning: Option<String>,
}

/// Where the settings live: `$XDG_CONFIG_HOME/kessler/settings.ron`, else
/// `$HOME/.config/kessler/settings.ron`, else `kessler-settings.ron`.
pub fn default_settings_path() -> PathBuf {
    let base = std::env::var_os("XDG_CONFIG_HOME")
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".config")));
    match base {
        Some(base) => base.join("kessler").join("settings.ron"),
        None => PathBuf::from("kessler-settings.ron"),
    }
}

/// Reads the settings at `path`. Never fails: a missing file gives defaults
/// silently, an unreadable, broken or out-of-range one gives defaults (or
/// the sanitised values) and a warning naming the file and the problem.
pub fn load_settings(path: &Path) -> (SandboxSettings, Option<SandboxSettings>, Option<SettingsWarning>) {
    let text = match std::fs::read_to_string(path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return (SandboxSettings::default(), None, None),
        Err(e) => {
            let warning = SettingsWarning(format!(
                "{}: cannot read settings ({e}); using defaults",
                path.display()
            ));
            return (SandboxSettings::default(), None, Some(warning));
        }
    };
    match ron::from_str::<SandboxSettings>(&text) {
        Ok(mut settings) => {
            let as_read = settings.clone();
            let fixed = settings.sanitize();
            let warning = (!fixed.is_empty()).then(|| {
                SettingsWarning(format!(
                    "{}: out-of-range {} replaced by the nearest allowed value",
                    path.display(),
                    fixed.join(", ")
                ))
            });
            (settings, Some(as_read), warning)
        }
        Err(e) => {
            let warning = SettingsWarning(format!(
                "{}:{}: {}; using default settings (the file is kept until you change a setting)",
                path.display(),
                e.span.start,
                e.code
            ));
            (SandboxSettings::default(), None, Some(warning))
        }
    }
}

/// Writes `settings` to `path` atomically: a temporary file in the same
/// folder, then a rename over the old one.
pub fn save_settings(path: &Path, settings: &SandboxSettings) -> std::io::Result<()> {
    let text = ron::ser::to_string_pretty(settings, ron::ser::PrettyConfig::default())
        .map_err(|e| std::io::Error::other(e.to_string()))?;
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }
    let mut tmp_name = path.file_name().unwrap_or_default().to_owned();
    tmp_name.push(".tmp");
    let tmp = path.with_file_name(tmp_name);
    std::fs::write(&tmp, text + "\n")?;
    std::fs::rename(&tmp, path).inspect_err(|_| {
        let _ = std::fs::remove_file(&tmp);
    })
}

impl SettingsFile {
    /// Loads the file at `path`; see [`load_settings`].
    pub fn open(path: PathBuf) -> (Self, SandboxSettings) {
        let (settings, saved, warning) = load_settings(&path);
        let file = Self {
            path,
            saved,
            initial: settings.clone(),
            warning: warning.map(|w| w.0),
        };
        (file, settings)
    }

    /// Saves `settings` if the user changed something since start and the
    /// file does not already hold them. Returns whether it wrote.
    pub fn save_if_changed(&mut self, settings: &SandboxSettings) -> std::io::Result<bool> {
        if *settings == self.initial || self.saved.as_ref() == Some(settings) {
            return Ok(false);
        }
        save_settings(&self.path, settings)?;
        self.saved = Some(settings.clone());
        Ok(true)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn saved_settings_load_back_equal() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("nested").join("settings.ron");
        let settings = SandboxSettings {
            mode: ExecutionMode::Sequential,
            threads: 3,
            updates_per_second: 240,
            body_count: Some(50_000),
            seed: 99,
            scenario: Some(PathBuf::from("scenarios/cascade.ron")),
            camera: CameraMode::Fly,
            render_method: RenderMethod::Meshes,
            ..SandboxSettings::default()
        };
        save_settings(&path, &settings).unwrap();
        let (loaded, saved, warning) = load_settings(&path);
        assert!(warning.is_none());
        assert_eq!(loaded, settings);
        assert_eq!(saved, Some(settings));
        assert!(
            !path.with_file_name("settings.ron.tmp").exists(),
            "temporary file left behind"
        );
    }

    #[test]
    fn missing_file_is_defaults_without_warning() {
        let dir = tempfile::tempdir().unwrap();
        let (settings, saved, warning) = load_settings(&dir.path().join("none.ron"));
        assert_eq!(settings, SandboxSettings::default());
        assert!(saved.is_none() && warning.is_none());
    }

    #[test]
    fn broken_file_warns_gives_defaults_and_survives_an_unchanged_session() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("settings.ron");
        let garbage = "(mode: Sideways, threads: \"many\"";
        std::fs::write(&path, garbage).unwrap();
        let (mut file, settings) = SettingsFile::open(path.clone());
        assert_eq!(settings, SandboxSettings::default());
        let warning = file.warning.clone().expect("a warning");
        assert!(warning.contains("settings.ron"), "{warning}");
        assert!(!file.save_if_changed(&settings).unwrap());
        assert_eq!(std::fs::read_to_string(&path).unwrap(), garbage);
        // Once the user changes something, the file is replaced.
        let changed = SandboxSettings {
            gravity: false,
            ..settings
        };
        assert!(file.save_if_changed(&changed).unwrap());
        assert_eq!(load_settings(&path).0, changed);
    }

    #[test]
    fn foreign_fields_are_rejected_not_ignored() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("settings.ron");
        std::fs::write(&path, "(window_title: \"other app\")").unwrap();
        let (settings, saved, warning) = load_settings(&path);
        assert_eq!(settings, SandboxSettings::default());
        assert!(saved.is_none());
        assert!(warning.unwrap().0.contains("window_title"));
    }

    #[test]
    fn out_of_range_values_are_clamped_with_a_warning() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("settings.ron");
        std::fs::write(&path, "(updates_per_second: 5000, shatter_fragments: 0, threads: 0)").unwrap();
        let (settings, _, warning) = load_settings(&path);
        assert_eq!(settings.updates_per_second, 600);
        assert_eq!(settings.shatter_fragments, 2);
        assert_eq!(settings.threads, 1);
        let warning = warning.unwrap().0;
        for field in ["updates_per_second", "shatter_fragments", "threads"] {
            assert!(warning.contains(field), "{warning}");
        }
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
}
