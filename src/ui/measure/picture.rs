//! A picture of what the run draws — the window, or the offscreen image —
//! and saving it as a PNG: what a scripted run's screenshot and a film's
//! pictures share.

use bevy::prelude::*;
use bevy::render::view::screenshot::Screenshot;

use crate::output::{Staged, stage, write_atomically, write_png};
use crate::ui::session::OffscreenTarget;

/// A screenshot of the window, or of the offscreen image.
pub fn screenshot_of(target: Option<&OffscreenTarget>) -> Screenshot {
    match target {
        Some(OffscreenTarget(image)) => Screenshot::image(image.clone()),
        None => Screenshot::primary_window(),
    }
}

/// Saves `image` as an RGB PNG at `path` (written in full beside it, then
/// put in place).
pub fn save_png(image: &Image, path: &std::path::Path) -> Result<(), String> {
    let rgb = image.clone().try_into_dynamic().map_err(|e| e.to_string())?.to_rgb8();
    write_atomically(path, |w| write_png(w, rgb.width(), rgb.height(), rgb.as_raw())).map_err(|e| e.source.to_string())
}

/// Saves `image` as a PNG at `path` where nothing is there yet (a film's
/// picture never replaces anything: see [`Staged::commit_new`]).
pub fn save_new_png(image: &Image, path: &std::path::Path) -> Result<(), String> {
    let rgb = image.clone().try_into_dynamic().map_err(|e| e.to_string())?.to_rgb8();
    stage(path, |w| write_png(w, rgb.width(), rgb.height(), rgb.as_raw()))
        .and_then(Staged::commit_new)
        .map_err(|e| e.source.to_string())
}
