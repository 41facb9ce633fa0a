//! Where Kessler keeps a user's own files: the window's settings and this
//! machine's split calibration, side by side.

use std::path::PathBuf;

/// `$XDG_CONFIG_HOME/kessler`, else `$HOME/.config/kessler`; `None` if
/// neither variable is set.
fn config_dir() -> Option<PathBuf> {
    std::env::var_os("XDG_CONFIG_HOME")
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".config")))
        .map(|base| base.join("kessler"))
}

/// `<config dir>/<name>`, else `kessler-<name>` in the working folder.
fn user_file(name: &str) -> PathBuf {
    config_dir().map_or_else(|| PathBuf::from(format!("kessler-{name}")), |dir| dir.join(name))
}

/// Where the window's settings live: `settings.ron` in
/// `$XDG_CONFIG_HOME/kessler`, else `$HOME/.config/kessler`, else
/// `kessler-settings.ron`.
pub fn default_settings_path() -> PathBuf {
    user_file("settings.ron")
}

/// Where `kessler calibrate` stores this machine's split calibration:
/// `calibration.ron` beside the settings.
pub fn default_calibration_path() -> PathBuf {
    user_file("calibration.ron")
}
