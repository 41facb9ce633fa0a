//! The settings file: read at start, saved on exit if the user changed a
//! setting.
//!
//! A missing file means defaults; a broken or foreign one means defaults and
//! a warning; an out-of-range value means the nearest allowed value (or the
//! default) for this session and a warning naming the field, the value and
//! what is used instead. Nothing else changes a loaded value: the panel's
//! widgets leave alone what the user does not edit.
//!
//! The file is rewritten only when the user changed a setting during the
//! session, and then only the fields the user changed take the session's
//! value: every other field keeps the file's own value, as read. So the
//! command line's one-run choices (`--bodies`, a scenario, `--render`, …)
//! never reach the file, and an out-of-range value the user did not touch
//! is written back as it was (and warned about again next time) rather
//! than silently replaced. Saving writes a temporary file beside it and
//! renames it over, so a crash mid-write never leaves half a file.
//!
//! Over 600 lines with its unit tests, which stay beside the code they
//! test; the code itself is about 300 lines.

use std::path::{Path, PathBuf};

use bevy::prelude::*;
use ron::extensions::Extensions;
use serde::de::{self, Deserialize, Deserializer, MapAccess, Visitor};

use super::sandbox_settings::SandboxSettings;
use crate::input::{ExecutionOptions, FieldName, parse_ron, read_text_if_present};
use crate::output::{WriteError, through_link, write_atomically};

/// The settings file, what it holds, what was in force at start, and any
/// warning about it.
#[derive(Resource, Clone, Debug)]
pub struct SettingsFile {
    /// Where the settings are read from and saved to.
    pub path: PathBuf,
    /// The file's own values, as read (out-of-range ones included) or as
    /// last saved; `None`: missing or unreadable, the defaults stand in.
    /// Saving keeps them for every field the user did not change.
    pub saved: Option<SandboxSettings>,
    /// The settings in force at start: the file's, within range, with the
    /// command line's one-run choices. A field that still equals it at exit
    /// was not changed by the user and is not saved.
    pub initial: SandboxSettings,
    /// Problems with the file, shown in the HUD (one per line).
    pub warning: Option<String>,
}

/// Saves the settings when the app exits.
pub struct SettingsFilePlugin;

impl Plugin for SettingsFilePlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(Last, save_settings_on_exit);
    }
}

pub use crate::input::default_settings_path;

/// Reads the settings at `path`: the settings to use, the settings as the
/// file holds them, and a warning. Never fails: a missing file gives
/// defaults silently, an unreadable or broken one gives defaults and a
/// warning naming the file and the problem, an out-of-range value the
/// allowed value and a warning naming the file, the field, the value and
/// what is used instead.
pub fn load_settings(path: &Path) -> (SandboxSettings, Option<SandboxSettings>, Option<String>) {
    let text = match read_text_if_present(path) {
        Ok(Some(text)) => text,
        Ok(None) => return (SandboxSettings::default(), None, None),
        Err(e) => return (SandboxSettings::default(), None, Some(format!("{e}; using defaults"))),
    };
    match parse_ron::<SandboxSettings>(&text, &path.display().to_string(), Extensions::empty()) {
        Ok(mut settings) => {
            let as_read = settings.clone();
            let mut fixed = settings.sanitize();
            // A number beyond f32's range was read as infinite: say it as
            // the file writes it.
            for fix in fixed.iter_mut().filter(|f| f.found.ends_with("inf")) {
                if let Some(written) = written_number(&text, fix.field) {
                    fix.found = written;
                }
            }
            let warning = (!fixed.is_empty()).then(|| {
                let fixed: Vec<String> = fixed.iter().map(ToString::to_string).collect();
                format!(
                    "{}: {} (the file keeps its values unless you change those settings)",
                    path.display(),
                    fixed.join("; ")
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

/// The number the field `field` of the settings file's `text` holds, at
/// the top or within `physics`, as written (at full width, where an `f32`
/// took it as infinite).
fn written_number(text: &str, field: &str) -> Option<String> {
    let ron::Value::Map(map) = ron::from_str::<ron::Value>(text).ok()? else {
        return None;
    };
    let key = |name: &str| ron::Value::String(name.to_owned());
    let value = map.get(&key(field)).or_else(|| match map.get(&key("physics")) {
        Some(ron::Value::Map(physics)) => physics.get(&key(field)),
        _ => None,
    })?;
    match value {
        ron::Value::Number(n) => Some(crate::input::shown_number(n.into_f64())),
        _ => None,
    }
}

/// The execution options as the settings file holds them: a thread count
/// of any size, held to this machine's range once read
/// ([`SandboxSettings::sanitize`]).
struct AsStored(ExecutionOptions);

impl<'de> Deserialize<'de> for AsStored {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct OptionsVisitor;
        impl<'de> Visitor<'de> for OptionsVisitor {
            type Value = AsStored;

            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("execution options, as (mode: Parallel, threads: 2)")
            }

            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<AsStored, A::Error> {
                let mut options = ExecutionOptions::default();
                while let Some(FieldName(key)) = map.next_key()? {
                    if !options.read_field_unchecked(&key, &mut map)? {
                        return Err(de::Error::unknown_field(&key, &["mode", "threads", "split", "pool"]));
                    }
                }
                Ok(AsStored(options))
            }
        }
        d.deserialize_struct("Execution", &["mode", "threads", "split", "pool"], OptionsVisitor)
    }
}

/// The fields of the settings file, as [`SandboxSettings`] has them.
const FIELDS: &[&str] = &[
    "execution",
    "physics",
    "vsync",
    "render_bodies",
    "visual_effects",
    "updates_per_second",
    "speed",
    "body_count",
    "scenario",
    "camera",
    "render_method",
    "show_collision_boxes",
    "trails",
    "trail_count",
];

/// Read by hand rather than derived so that files written before
/// `execution` and `physics` were fields of their own still load: their
/// options, settings (by field name) and stage switches stood at the top.
impl<'de> Deserialize<'de> for SandboxSettings {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct SettingsVisitor;
        impl<'de> Visitor<'de> for SettingsVisitor {
            type Value = SandboxSettings;

            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("the window's settings, as (execution: (...), physics: (...), vsync: true, ...)")
            }

            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<SandboxSettings, A::Error> {
                let mut s = SandboxSettings::default();
                while let Some(FieldName(key)) = map.next_key()? {
                    match key.as_str() {
                        "execution" => s.execution = map.next_value::<AsStored>()?.0.or(s.execution),
                        "physics" => s.physics = map.next_value()?,
                        "vsync" => s.vsync = map.next_value()?,
                        "render_bodies" => s.render_bodies = map.next_value()?,
                        "visual_effects" => s.visual_effects = map.next_value()?,
                        "updates_per_second" => s.updates_per_second = map.next_value()?,
                        "speed" => s.speed = map.next_value()?,
                        "body_count" => s.body_count = map.next_value()?,
                        "scenario" => s.scenario = map.next_value()?,
                        "camera" => s.camera = map.next_value()?,
                        "render_method" => s.render_method = map.next_value()?,
                        "show_collision_boxes" => s.show_collision_boxes = map.next_value()?,
                        "trails" => s.trails = map.next_value()?,
                        "trail_count" => s.trail_count = map.next_value()?,
                        "gravity" => s.physics.stages.gravity = map.next_value()?,
                        "collisions" => s.physics.stages.collisions = map.next_value()?,
                        "collision_response" | "collision_effects" => {
                            s.physics.stages.collision_response = map.next_value()?;
                        }
                        other => {
                            if !s.execution.read_field_unchecked(other, &mut map)?
                                && !s.physics.read_field_unchecked(other, &mut map)?
                            {
                                return Err(de::Error::unknown_field(other, FIELDS));
                            }
                        }
                    }
                }
                Ok(s)
            }
        }
        d.deserialize_struct("SandboxSettings", FIELDS, SettingsVisitor)
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
    // A link (a dotfiles setup) is written through, to the file it names;
    // anything else that is not a regular file (a FIFO, a device) is left
    // alone.
    let target = through_link(path)?;
    if let Ok(m) = target.metadata()
        && !m.is_file()
    {
        return Err(WriteError {
            path: target,
            source: std::io::Error::other(format!(
                "is {}; settings are saved to regular files only",
                crate::input::node_kind(m.file_type())
            )),
        });
    }
    write_atomically(&target, |w| writeln!(w, "{text}"))
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

    /// Adds a problem to the warning the HUD shows.
    pub fn add_warning(&mut self, warning: String) {
        self.warning = Some(match self.warning.take() {
            Some(earlier) => format!("{earlier}\n{warning}"),
            None => warning,
        });
    }

    /// Saves the fields in which `settings` differs from the settings at
    /// start, over the file's own values (see the module's doc), if there
    /// are any and the file does not already hold the result. Returns the
    /// fields saved; empty if it did not write.
    pub fn save_if_changed(&mut self, settings: &SandboxSettings) -> Result<Vec<&'static str>, WriteError> {
        let mut merged = self.saved.clone().unwrap_or_default();
        let changed = merged.take_changes(&self.initial, settings);
        if changed.is_empty() || self.saved.as_ref() == Some(&merged) {
            return Ok(Vec::new());
        }
        save_settings(&self.path, &merged)?;
        self.saved = Some(merged);
        Ok(changed)
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
        Ok(changed) if changed.is_empty() => {}
        Ok(changed) => info!("settings saved to {} ({})", file.path.display(), changed.join(", ")),
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
    use crate::execution::{ExecutionMode, SplitPolicy};
    use crate::resources::DrawMethod;
    use crate::ui::session::sandbox_settings::CameraMode;

    #[cfg(unix)]
    #[test]
    fn a_linked_file_is_saved_through_the_link_and_a_fifo_is_left_alone() {
        use std::os::unix::fs::FileTypeExt;

        let dir = tempfile::tempdir().unwrap();
        let real = dir.path().join("real.ron");
        let link = dir.path().join("settings.ron");
        std::os::unix::fs::symlink(&real, &link).unwrap();
        let mut settings = SandboxSettings::default();
        settings.physics.seed = 5;
        save_settings(&link, &settings).unwrap();
        assert!(
            link.symlink_metadata().unwrap().file_type().is_symlink(),
            "the link stays"
        );
        assert_eq!(load_settings(&real).0, settings);

        let fifo = dir.path().join("fifo.ron");
        crate::input::make_fifo(&fifo);
        let (loaded, _, warning) = load_settings(&fifo);
        assert_eq!(loaded, SandboxSettings::default());
        assert!(warning.unwrap().contains("is a FIFO (named pipe)"));
        let e = save_settings(&fifo, &settings).unwrap_err();
        assert!(e.source.to_string().contains("regular files only"), "{e}");
        assert!(fifo.symlink_metadata().unwrap().file_type().is_fifo());
    }

    #[test]
    fn saved_settings_load_back_equal() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("nested").join("settings.ron");
        let mut settings = SandboxSettings {
            execution: ExecutionOptions {
                mode: Some(ExecutionMode::Sequential),
                threads: Some(3),
                split: Some(SplitPolicy::Above(5000)),
                pool: Some(crate::execution::WorkerPool::Bevy),
            },
            updates_per_second: 240,
            body_count: Some(50_000),
            scenario: Some(PathBuf::from("scenarios/cascade.ron")),
            camera: CameraMode::Fly,
            render_method: DrawMethod::MeshPerBody,
            vsync: false,
            ..SandboxSettings::default()
        };
        settings.physics.seed = 99;
        settings.physics.stages.collision_response = false;
        settings.physics.gravity_method = crate::resources::GravityMethod::Tree { theta: 0.25 };
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
        assert_eq!(loaded.execution.threads, Some(2));
        assert_eq!(
            (loaded.execution.split, loaded.vsync),
            (Some(SplitPolicy::Auto), true),
            "defaults for new fields"
        );
    }

    /// Files written before the execution options and the physics were
    /// fields of their own held them at the top, with the physics settings
    /// by their field names and the stage switches beside them.
    #[test]
    fn older_flat_files_load_as_they_did() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("settings.ron");
        std::fs::write(
            &path,
            "(mode: Sequential, split: Always, gravity_method: Direct, integrator: SemiImplicitEuler, \
             shatter_fragments: 5000, gravity: false, vsync: false)",
        )
        .unwrap();
        let (loaded, saved, warning) = load_settings(&path);
        let warning = warning.unwrap();
        assert!(warning.contains("shatter_fragments 5000 is out of range"), "{warning}");
        assert_eq!(saved.unwrap().physics.shatter_fragments, 5000, "as read");
        assert_eq!(loaded.execution.mode, Some(ExecutionMode::Sequential));
        assert_eq!(loaded.execution.split, Some(SplitPolicy::Always));
        assert_eq!(loaded.physics.gravity_method, crate::resources::GravityMethod::Direct);
        assert_eq!(
            loaded.physics.integrator,
            crate::resources::Integrator::SemiImplicitEuler
        );
        assert_eq!(loaded.physics.shatter_fragments, 1000);
        assert!(!loaded.physics.stages.gravity && !loaded.vsync);
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
        assert!(file.save_if_changed(&settings).unwrap().is_empty());
        assert_eq!(std::fs::read_to_string(&path).unwrap(), garbage);
        // Once the user changes something, the file is replaced.
        let mut changed = settings;
        changed.physics.stages.gravity = false;
        assert_eq!(file.save_if_changed(&changed).unwrap(), ["gravity"]);
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
        std::fs::write(
            &path,
            "(updates_per_second: 5000, physics: (shatter_fragments: 0), execution: (threads: 0))",
        )
        .unwrap();
        let (settings, saved, warning) = load_settings(&path);
        assert_eq!(settings.updates_per_second, 600);
        assert_eq!(settings.physics.shatter_fragments, 2);
        assert_eq!(settings.execution.threads, Some(1));
        let saved = saved.unwrap();
        assert_eq!(
            (
                saved.updates_per_second,
                saved.physics.shatter_fragments,
                saved.execution.threads
            ),
            (5000, 0, Some(0)),
            "the file's own values, as read"
        );
        let warning = warning.unwrap();
        for said in [
            "settings.ron: ",
            "updates_per_second 5000 is out of range (1 to 600), using 600",
            "shatter_fragments 0 is out of range",
            "threads 0 is out of range",
        ] {
            assert!(warning.contains(said), "{said:?} not in {warning}");
        }
    }

    #[test]
    fn numbers_beyond_f32_are_named_as_written() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("settings.ron");
        std::fs::write(
            &path,
            "SandboxSettings(speed: 1e39, physics: (shatter_threshold: -3e40))",
        )
        .unwrap();
        let (settings, _, warning) = load_settings(&path);
        assert_eq!((settings.speed, settings.physics.shatter_threshold), (8.0, 3.0));
        let warning = warning.unwrap();
        assert!(warning.contains("speed 1e39 is out of range"), "{warning}");
        assert!(warning.contains("shatter_threshold -3e40 is out of range"), "{warning}");
        assert!(!warning.contains("inf"), "{warning}");
    }

    /// Opens `text` as a settings file, as the window does: the settings at
    /// start are the file's, within range.
    fn open(dir: &Path, text: &str) -> (PathBuf, SettingsFile, SandboxSettings) {
        let path = dir.join("settings.ron");
        std::fs::write(&path, text).unwrap();
        let (file, settings) = SettingsFile::open(path.clone());
        (path, file, settings)
    }

    #[test]
    fn out_of_range_values_survive_a_session_that_changes_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let text = "(threads: 100000, shatter_fragments: 5000, shatter_threshold: -1.0)";
        let (path, mut file, settings) = open(dir.path(), text);
        let warning = file.warning.clone().unwrap();
        for said in ["threads 100000", "shatter_fragments 5000", "shatter_threshold -1.0"] {
            assert!(warning.contains(said), "{said:?} not in {warning}");
        }
        assert!(file.save_if_changed(&settings).unwrap().is_empty());
        assert_eq!(std::fs::read_to_string(&path).unwrap(), text, "byte for byte");
    }

    #[test]
    fn a_change_saves_that_field_and_keeps_the_files_own_values_for_the_rest() {
        let dir = tempfile::tempdir().unwrap();
        let (path, mut file, settings) = open(
            dir.path(),
            "(threads: 100000, shatter_fragments: 5000, seed: 3, body_count: Some(7))",
        );
        let mut changed = settings.clone();
        changed.physics.stages.gravity = false;
        assert_eq!(file.save_if_changed(&changed).unwrap(), ["gravity"]);
        let (_, saved, _) = load_settings(&path);
        let saved = saved.unwrap();
        assert!(!saved.physics.stages.gravity);
        assert_eq!(
            (
                saved.execution.threads,
                saved.physics.shatter_fragments,
                saved.physics.seed,
                saved.body_count
            ),
            (Some(100_000), 5000, 3, Some(7)),
            "untouched, even out of range: written back as the file had them"
        );
        // A second save of the same settings writes nothing new.
        assert!(file.save_if_changed(&changed).unwrap().is_empty());

        // Changing the out-of-range value itself saves the new one.
        let mut threads = changed;
        threads.execution.threads = Some(1);
        assert_eq!(file.save_if_changed(&threads).unwrap(), ["threads", "gravity"]);
        assert_eq!(load_settings(&path).1.unwrap().execution.threads, Some(1));
    }

    #[test]
    fn a_missing_file_saves_defaults_with_the_users_change_only() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("none").join("settings.ron");
        let (mut file, settings) = SettingsFile::open(path.clone());
        // A one-run choice at start, then a change in the panel.
        file.initial = SandboxSettings {
            body_count: Some(200),
            ..settings
        };
        let now = SandboxSettings {
            trails: crate::ui::session::sandbox_settings::TrailChoice::Newest,
            ..file.initial.clone()
        };
        assert_eq!(file.save_if_changed(&now).unwrap(), ["trails"]);
        let saved = load_settings(&path).1.unwrap();
        assert_eq!(
            saved,
            SandboxSettings {
                trails: crate::ui::session::sandbox_settings::TrailChoice::Newest,
                ..SandboxSettings::default()
            }
        );
    }

    #[test]
    fn warnings_add_up_one_per_line() {
        let dir = tempfile::tempdir().unwrap();
        let (_, mut file, _) = open(dir.path(), "(threads: 0)");
        file.add_warning("saved scenario: gone".into());
        let warning = file.warning.unwrap();
        assert_eq!(warning.lines().count(), 2, "{warning}");
        assert!(warning.ends_with("saved scenario: gone"));
    }

    #[test]
    fn older_files_with_the_thesis_name_of_the_response_switch_still_load() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("settings.ron");
        std::fs::write(&path, "(collision_effects: false)").unwrap();
        let (settings, _, warning) = load_settings(&path);
        assert!(warning.is_none(), "{warning:?}");
        assert!(!settings.physics.stages.collision_response);
    }
}
