//! Films (`kessler run --frames-out DIR --every K`): a numbered PNG of the
//! window (or the offscreen image) every K updates — at most one a frame,
//! so a frame that runs past several multiples of K gives one picture; the
//! first once the pipelines are compiled, each in a frame with none compiling
//! (until one has waited [`READY_TIMEOUT`] for that).

use std::path::PathBuf;
use std::time::Instant;

use bevy::prelude::*;
use bevy::render::view::screenshot::ScreenshotCaptured;

use super::capture::{READY_TIMEOUT, ScriptedRun};
use super::picture::{save_new_png, screenshot_of};
use super::pipelines::PipelinesSettled;
use crate::ui::session::{OffscreenTarget, OutputFailures, UpdateClock, frame_path};

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
    /// Since when a picture has waited for the pipelines to settle.
    waiting_since: Option<Instant>,
    /// The pipelines did not settle within [`READY_TIMEOUT`]: pictures no
    /// longer wait for them.
    gave_up_waiting: bool,
}

impl Film {
    /// A film into `dir`, a picture every `every` updates.
    pub fn new(dir: PathBuf, every: u64) -> Self {
        Self {
            dir,
            every: every.max(1),
            taken: 0,
            last: None,
            waiting_since: None,
            gave_up_waiting: false,
        }
    }

    /// Whether a picture due `now` may be taken, given whether the
    /// pipelines are `settled`: once they are, or once a picture has waited
    /// [`READY_TIMEOUT`] for them (from then on, none waits).
    fn may_take(&mut self, settled: bool, now: Instant) -> bool {
        if settled || self.gave_up_waiting {
            self.waiting_since = None;
            return true;
        }
        let since = *self.waiting_since.get_or_insert(now);
        if now.duration_since(since) <= READY_TIMEOUT {
            return false;
        }
        warn!("pipelines still compiling after {READY_TIMEOUT:?}; the film's pictures no longer wait for them");
        self.gave_up_waiting = true;
        self.waiting_since = None;
        true
    }
}

/// Takes the film's pictures.
pub struct FilmPlugin(pub Film);

impl Plugin for FilmPlugin {
    fn build(&self, app: &mut App) {
        app.insert_resource(self.0.clone())
            .init_resource::<OutputFailures>()
            .add_systems(Last, take_picture);
    }
}

/// A picture when the update count passed the next multiple of `every`
/// (and one at the start), in a frame with no pipeline compiling (before
/// the first is compiled a picture would be black or half drawn), waiting
/// at most [`READY_TIMEOUT`] for one.
fn take_picture(
    mut commands: Commands,
    clock: Res<UpdateClock>,
    mut film: ResMut<Film>,
    target: Option<Res<OffscreenTarget>>,
    run: Option<Res<ScriptedRun>>,
    settled: Res<PipelinesSettled>,
    failures: Res<OutputFailures>,
) {
    let multiple = clock.updates_total / film.every;
    if film.last == Some(multiple) {
        return;
    }
    // A scripted run's last screenshot is being taken: the app is ending,
    // and one render target takes one screenshot a frame.
    if run.is_some_and(|run| run.capturing) {
        return;
    }
    if !film.may_take(settled.get(), Instant::now()) {
        return;
    }
    film.last = Some(multiple);
    film.taken += 1;
    let path = frame_path(&film.dir, film.taken);
    let failures = failures.clone();
    commands
        .spawn(screenshot_of(target.as_deref()))
        .observe(move |captured: On<ScreenshotCaptured>| {
            if let Err(e) = save_new_png(&captured.image, &path) {
                failures.failed(format_args!("{}: cannot save a film's picture: {e}", path.display()));
            }
        });
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use super::*;

    #[test]
    fn pictures_wait_for_the_pipelines_at_most_the_timeout_then_no_longer() {
        let mut film = Film::new(PathBuf::from("film"), 10);
        let start = Instant::now();
        assert!(film.may_take(true, start));
        assert!(!film.may_take(false, start), "a pipeline compiling: wait");
        assert!(!film.may_take(false, start + READY_TIMEOUT));
        assert!(film.may_take(true, start + READY_TIMEOUT), "settled in time");
        // A new wait starts with the next picture, and runs out.
        let later = start + 2 * READY_TIMEOUT;
        assert!(!film.may_take(false, later));
        assert!(film.may_take(false, later + READY_TIMEOUT + Duration::from_secs(1)));
        assert!(
            film.may_take(false, later + READY_TIMEOUT + Duration::from_secs(2)),
            "no longer waits"
        );
    }
}
