//! Where Kessler keeps a user's own files: the window's settings and this
//! machine's split calibration, side by side, in the platform's folder for
//! an application's configuration (the `directories` crate): on Linux
//! `$XDG_CONFIG_HOME/kessler`, else `~/.config/kessler`; on macOS
//! `~/Library/Application Support/kessler`; on Windows
//! `%APPDATA%\kessler\config`.

use std::path::PathBuf;

use directories::ProjectDirs;

/// The platform's configuration folder for Kessler; `None` where the
/// platform names no home folder.
fn config_dir() -> Option<PathBuf> {
    ProjectDirs::from("", "", "kessler").map(|dirs| dirs.config_dir().to_owned())
}

/// `<config dir>/<name>`, else `kessler-<name>` in the working folder.
fn user_file(name: &str) -> PathBuf {
    config_dir().map_or_else(|| PathBuf::from(format!("kessler-{name}")), |dir| dir.join(name))
}

/// Where the window's settings live: `settings.ron` in the configuration
/// folder, else `kessler-settings.ron`.
pub fn default_settings_path() -> PathBuf {
    user_file("settings.ron")
}

/// Where `kessler calibrate` stores this machine's split calibration:
/// `calibration.ron` beside the settings.
pub fn default_calibration_path() -> PathBuf {
    user_file("calibration.ron")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    #[cfg(target_os = "linux")]
    fn the_config_folder_follows_xdg_on_linux() {
        // Read, not set: the variables belong to the whole test process.
        let expected = match std::env::var_os("XDG_CONFIG_HOME").filter(|v| PathBuf::from(v).is_absolute()) {
            Some(base) => PathBuf::from(base).join("kessler"),
            None => PathBuf::from(std::env::var_os("HOME").unwrap()).join(".config/kessler"),
        };
        assert_eq!(default_settings_path(), expected.join("settings.ron"));
        assert_eq!(default_calibration_path(), expected.join("calibration.ron"));
    }
}
