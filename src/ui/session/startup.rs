//! What the window starts with: the checks made before it opens, the saved
//! settings, the command line's overrides, and the first scenario.

use std::path::Path;

use super::sandbox_settings::SandboxSettings;
use super::settings_file::{SettingsFile, default_settings_path};
use super::window_options::{WindowError, WindowOptions};
use crate::input::default_calibration_path;
use crate::output::{Output, check_extension, check_not_inputs, check_outputs, check_series_folder};
use crate::scenario::Scenario;

/// What the window starts with.
pub struct Start {
    /// The settings file, as read.
    pub file: SettingsFile,
    /// The settings in force: the saved ones, overridden by the command line.
    pub settings: SandboxSettings,
    /// The scenario to build first.
    pub scenario: Scenario,
}

impl Start {
    /// Checks what can be checked before a window opens (the screenshot
    /// path, the display), then reads the settings and the scenario (see
    /// [`Self::read`]).
    pub fn from_options(options: &WindowOptions) -> Result<Self, WindowError> {
        check_outputs_of(options)?;
        if !options.offscreen {
            check_display()?;
        }
        Self::read(options)
    }

    /// Reads the settings and the scenario: the saved ones, overridden by
    /// the command line. The command line's choices are for this run: they
    /// are in force from the start, so they are no change the user made,
    /// and saving keeps the file's own values for them (see
    /// [`settings_file`](super::settings_file)). Warnings about the file are
    /// printed here, once, and shown in the HUD.
    pub fn read(options: &WindowOptions) -> Result<Self, WindowError> {
        let path = options.settings.clone().unwrap_or_else(default_settings_path);
        let (mut file, mut settings) = SettingsFile::open(path);
        if let Some(warning) = &file.warning {
            eprintln!("kessler: warning: {}", crate::output::printable(warning));
        }
        let scenario = match &options.scenario {
            Some(path) => {
                let scenario = Scenario::load(path)?;
                settings.scenario = Some(path.clone());
                settings.adopt_scenario(&scenario.settings());
                scenario
            }
            None => Scenario::load_or_default(settings.scenario.as_deref()).unwrap_or_else(|e| {
                // The saved scenario went missing or broke: say so, use the
                // built-in (the file keeps naming it).
                let warning = format!("saved scenario: {e}; using the built-in scene");
                eprintln!("kessler: warning: {}", crate::output::printable(&warning));
                file.add_warning(warning);
                settings.scenario = None;
                Scenario::builtin_default()
            }),
        };
        if let Some(render) = options.render {
            settings.render_method = render;
        }
        if let Some(vsync) = options.vsync {
            settings.vsync = vsync;
        }
        settings.execution = options.execution.or(settings.execution);
        if let Some(ups) = options.ups {
            settings.updates_per_second = ups;
        }
        if let Some(count) = options.bodies {
            scenario.with_generated(count)?;
            settings.body_count = Some(count);
        }
        file.initial = settings.clone();
        Ok(Self {
            file,
            settings,
            scenario,
        })
    }
}

/// A screenshot must be a new `.png` file in an existing folder; a frame
/// report a new file; neither of them, nor the settings file (which the
/// window writes when a setting changes), is a file the window reads: the
/// scenario named, the settings, the split calibration.
fn check_outputs_of(options: &WindowOptions) -> Result<(), WindowError> {
    let settings = options.settings.clone().unwrap_or_else(default_settings_path);
    let calibration = default_calibration_path();
    let mut inputs: Vec<(&str, &Path)> = Vec::new();
    if let Some(scenario) = &options.scenario {
        inputs.push(("the scenario", scenario));
    }
    if let Some(actions) = &options.actions {
        inputs.push(("the actions", actions));
    }
    inputs.push(("the split calibration", &calibration));
    // Saved through a link if it is one, so checked against the inputs
    // only.
    check_not_inputs(&[("--settings", &settings)], &inputs)?;
    inputs.push(("the window's settings", &settings));
    let mut outputs = Vec::new();
    if let Some(path) = &options.screenshot {
        check_extension("--screenshot", path, "png")?;
        outputs.push(Output::new_only(
            "--screenshot",
            path,
            "screenshots never overwrite, choose another name",
        ));
    }
    if let Some(path) = &options.frame_report {
        outputs.push(Output::new_only(
            "--frame-report",
            path,
            "reports never overwrite, choose another name",
        ));
    }
    if let Some(path) = &options.dump {
        outputs.push(Output::replacing("--dump", path));
    }
    check_outputs(&outputs, &inputs)?;
    // A film never overwrites one: its folder holds no picture yet, and is
    // made where it does not exist. Last, so that nothing is made for a
    // run refused for another reason.
    if let Some(dir) = &options.frames_out {
        check_series_folder(
            "--frames-out",
            dir,
            super::offscreen::FRAME_NAMES,
            "films never overwrite, choose a folder without frame-*.png pictures",
        )?;
    }
    Ok(())
}

/// The window is X11-only (the lean build leaves Wayland out): without a
/// display, say so instead of letting the event loop panic.
fn check_display() -> Result<(), WindowError> {
    if no_display() {
        return Err(WindowError::NoDisplay);
    }
    Ok(())
}

/// True where the window cannot open: Linux without an X11 display.
pub fn no_display() -> bool {
    cfg!(target_os = "linux") && std::env::var_os("DISPLAY").is_none_or(|d| d.is_empty())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::execution::ExecutionMode;
    use crate::input::ExecutionOptions;
    use crate::resources::DrawMethod;

    #[test]
    fn no_output_of_the_window_is_a_file_it_reads() {
        let dir = tempfile::tempdir().unwrap();
        let scenario = dir.path().join("scen.ron");
        std::fs::write(&scenario, "Scenario()").unwrap();
        let settings = dir.path().join("settings.ron");
        let new = dir.path().join("new.png");
        let with = |screenshot: &Path, frame_report: &Path, settings_file: &Path| WindowOptions {
            scenario: Some(scenario.clone()),
            settings: Some(settings_file.to_owned()),
            screenshot: Some(screenshot.to_owned()),
            frame_report: Some(frame_report.to_owned()),
            ..WindowOptions::default()
        };
        let report = dir.path().join("report.txt");
        assert!(check_outputs_of(&with(&new, &report, &settings)).is_ok());
        for (options, needle) in [
            (with(&new, &report, &scenario), "--settings"),
            (with(&new, &scenario, &settings), "--frame-report"),
            (
                with(&new, &settings, &settings),
                "is the window's settings this command reads",
            ),
            (with(&new, &new, &settings), "--screenshot names the same file"),
        ] {
            let e = check_outputs_of(&options).unwrap_err().to_string();
            assert!(e.contains(needle), "{e}");
        }
        let e = check_outputs_of(&with(&new, &report, &scenario))
            .unwrap_err()
            .to_string();
        assert!(e.contains("is the scenario this command reads"), "{e}");
    }

    #[test]
    fn one_run_choices_are_never_saved_but_the_users_changes_are() {
        let dir = tempfile::tempdir().unwrap();
        let settings_path = dir.path().join("settings.ron");
        let text = "(threads: 1, seed: 11, shatter_fragments: 3, render_method: SharedMesh)";
        std::fs::write(&settings_path, text).unwrap();
        let scenario = concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/cascade.ron");
        let options = WindowOptions {
            scenario: Some(scenario.into()),
            settings: Some(settings_path.clone()),
            bodies: Some(200),
            render: Some(DrawMethod::MeshPerBody),
            vsync: Some(false),
            execution: ExecutionOptions {
                mode: Some(ExecutionMode::Sequential),
                ..ExecutionOptions::default()
            },
            ups: Some(30),
            ..WindowOptions::default()
        };
        let Start { mut file, settings, .. } = Start::read(&options).unwrap();
        assert_eq!(settings.body_count, Some(200));
        assert_eq!(settings.scenario.as_deref(), Some(std::path::Path::new(scenario)));
        // An unchanged session writes nothing.
        assert!(file.save_if_changed(&settings).unwrap().is_empty());
        assert_eq!(std::fs::read_to_string(&settings_path).unwrap(), text);

        // The user changes the threads in the panel: only they are saved.
        let mut changed = settings;
        changed.execution.threads = Some(2);
        assert_eq!(file.save_if_changed(&changed).unwrap(), ["threads"]);
        let (_, saved, _) = super::super::settings_file::load_settings(&settings_path);
        let mut expected = SandboxSettings {
            render_method: DrawMethod::SharedMesh,
            ..SandboxSettings::default()
        };
        expected.execution.threads = Some(2);
        expected.physics.seed = 11;
        expected.physics.shatter_fragments = 3;
        assert_eq!(
            saved,
            Some(expected),
            "no body count, scenario, its seed or other one-run choice"
        );
    }
}
