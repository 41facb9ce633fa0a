//! Films (`kessler run --frames-out DIR --every K`): a numbered PNG of the
//! window (or the offscreen image) every K updates — at most one a frame,
//! so a frame that runs past several multiples of K gives one picture; the
//! first once the pipelines are compiled.

use std::path::PathBuf;

use bevy::prelude::*;
use bevy::render::view::screenshot::ScreenshotCaptured;

use super::capture::ScriptedRun;
use super::picture::{save_png, screenshot_of};
use super::pipelines::PipelinesSettled;
use crate::ui::session::{OffscreenTarget, UpdateClock, frame_path};

/// Where a film goes and how far it is.
#[derive(Resource, Clone, Debug)]
pub struct Film {
    /// The folder.
    pub dir: PathBuf,
    /// Updates between two pictures.
    pub every: u64,
    /// Pictures asked for so far.
    taken: u64,
    /// The multiple of `every` of the last picture.
    last: Option<u64>,
}

impl Film {
    /// A film into `dir`, a picture every `every` updates.
    pub fn new(dir: PathBuf, every: u64) -> Self {
        Self {
            dir,
            every: every.max(1),
            taken: 0,
            last: None,
        }
    }
}

/// Takes the film's pictures.
pub struct FilmPlugin(pub Film);

impl Plugin for FilmPlugin {
    fn build(&self, app: &mut App) {
        app.insert_resource(self.0.clone()).add_systems(Last, take_picture);
    }
}

/// A picture when the update count passed the next multiple of `every`
/// (and one at the start), once the scene is drawn in full (the first
/// picture waits for the pipelines: before, it would be black or half
/// drawn).
fn take_picture(
    mut commands: Commands,
    clock: Res<UpdateClock>,
    mut film: ResMut<Film>,
    target: Option<Res<OffscreenTarget>>,
    run: Option<Res<ScriptedRun>>,
    settled: Res<PipelinesSettled>,
) {
    if !settled.get() {
        return;
    }
    // A scripted run's last screenshot is being taken: the app is ending,
    // and one render target takes one screenshot a frame.
    if run.is_some_and(|run| run.capturing) {
        return;
    }
    let multiple = clock.updates_total / film.every;
    if film.last == Some(multiple) {
        return;
    }
    film.last = Some(multiple);
    film.taken += 1;
    let path = frame_path(&film.dir, film.taken);
    commands
        .spawn(screenshot_of(target.as_deref()))
        .observe(move |captured: On<ScreenshotCaptured>| {
            if let Err(e) = save_png(&captured.image, &path) {
                eprintln!("kessler: error: {}: cannot save a film's picture: {e}", path.display());
            }
        });
}
