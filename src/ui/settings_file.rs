//! The settings file: read at start, saved on exit if the user changed a
//! setting.
//!
//! A missing file means defaults; a broken, foreign or out-of-range one
//! means defaults (or the nearest allowed values) and a warning, and it is
//! left alone until the user changes a setting. Saving writes a temporary
//! file beside it and renames it over, so a crash mid-write never leaves
//! half a file.

use std::path::{Path, PathBuf};

use bevy::prelude::*;
use ron::extensions::Extensions;

use super::settings::SandboxSettings;
use crate::input::{parse_ron, read_text_if_present};
use crate::output::{WriteError, write_atomically};

/// The settings file, what was last read from or written to it, and any
/// warning about it.
#[derive(Resource, Clone, Debug)]
pub struct SettingsFile {
    /// Where the settings are read from and saved to.
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

/// Saves the settings when the app exits.
pub struct SettingsFilePlugin;

impl Plugin for SettingsFilePlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(Last, save_settings_on_exit);
    }
}

pub use crate::user_files::default_settings_path;

/// Reads the settings at `path`: the settings to use, the settings as the
/// file holds them, and a warning. Never fails: a missing file gives
/// defaults silently, an unreadable, broken or out-of-range one gives
/// defaults (or the sanitized values) and a warning naming the file and the
/// problem.
pub fn load_settings(path: &Path) -> (SandboxSettings, Option<SandboxSettings>, Option<String>) {
    let text = match read_text_if_present(path) {
        Ok(Some(text)) => text,
        Ok(None) => return (SandboxSettings::default(), None, None),
        Err(e) => return (SandboxSettings::default(), None, Some(format!("{e}; using defaults"))),
    };
    match parse_ron::<SandboxSettings>(&text, &path.display().to_string(), Extensions::empty()) {
        Ok(mut settings) => {
            let as_read = settings.clone();
            let fixed = settings.sanitize();
            let warning = (!fixed.is_empty()).then(|| {
                format!(
                    "{}: out-of-range {} replaced by the nearest allowed value",
                    path.display(),
                    fixed.join(", ")
                )
            });
            (settings, Some(as_read), warning)
        }
        Err(e) => {
            let warning = format!("{e}; using default settings (the file is kept until you change a setting)");
            (SandboxSettings::default(), None, Some(warning))
        }
    }
}

/// Writes `settings` to `path` atomically, making its folder if needed.
pub fn save_settings(path: &Path, settings: &SandboxSettings) -> Result<(), WriteError> {
    let text = ron::ser::to_string_pretty(settings, ron::ser::PrettyConfig::default()).map_err(|e| WriteError {
        path: path.to_owned(),
        source: std::io::Error::other(e.to_string()),
    })?;
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|source| WriteError {
            path: dir.to_owned(),
            source,
        })?;
    }
    write_atomically(path, |w| writeln!(w, "{text}"))
}

impl SettingsFile {
    /// Loads the file at `path`; see [`load_settings`].
    pub fn open(path: PathBuf) -> (Self, SandboxSettings) {
        let (settings, saved, warning) = load_settings(&path);
        let file = Self {
            path,
            saved,
            initial: settings.clone(),
            warning,
        };
        (file, settings)
    }

    /// Saves `settings` if the user changed something since start and the
    /// file does not already hold them. Returns whether it wrote.
    pub fn save_if_changed(&mut self, settings: &SandboxSettings) -> Result<bool, WriteError> {
        if *settings == self.initial || self.saved.as_ref() == Some(settings) {
            return Ok(false);
        }
        save_settings(&self.path, settings)?;
        self.saved = Some(settings.clone());
        Ok(true)
    }
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
        Err(e) => eprintln!(
            "kessler: warning: {}: cannot save settings: {}",
            e.path.display(),
            e.source
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::draw_method::DrawMethod;
    use crate::execution::{ExecutionMode, SplitPolicy};
    use crate::ui::settings::CameraMode;

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
            render_method: DrawMethod::MeshPerBody,
            collision_response: false,
            split: SplitPolicy::Above(5000),
            vsync: false,
            ..SandboxSettings::default()
        };
        save_settings(&path, &settings).unwrap();
        let (loaded, saved, warning) = load_settings(&path);
        assert!(warning.is_none());
        assert_eq!(loaded, settings);
        assert_eq!(saved, Some(settings));
        let files = std::fs::read_dir(path.parent().unwrap()).unwrap().count();
        assert_eq!(files, 1, "temporary file left behind");
    }

    #[test]
    fn older_files_keep_loading_with_their_drawing_method() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("settings.ron");
        std::fs::write(&path, "(render_method: Meshes, threads: 2)").unwrap();
        let (loaded, _, warning) = load_settings(&path);
        assert!(warning.is_none(), "{warning:?}");
        assert_eq!(loaded.render_method, DrawMethod::SharedMesh);
        assert_eq!(
            (loaded.split, loaded.vsync),
            (SplitPolicy::Auto, true),
            "defaults for new fields"
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
        assert!(warning.unwrap().contains("window_title"));
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
        let warning = warning.unwrap();
        for field in ["updates_per_second", "shatter_fragments", "threads"] {
            assert!(warning.contains(field), "{warning}");
        }
    }

    #[test]
    fn older_files_with_the_thesis_name_of_the_response_switch_still_load() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("settings.ron");
        std::fs::write(&path, "(collision_effects: false)").unwrap();
        let (settings, _, warning) = load_settings(&path);
        assert!(warning.is_none(), "{warning:?}");
        assert!(!settings.collision_response);
    }
}
