//! The session: what one window runs with and how it runs the simulation —
//! the command line's options and the checks before the window opens, the
//! sandbox's settings and the file they are saved in, the loaded scene and
//! its restart, the update clock and the drive that steps the simulation
//! each frame, and saving the running state as a scenario. It depends on
//! nothing else of the window but its phases ([`crate::ui::sets`]).

pub mod drive;
pub mod offscreen;
mod output_failures;
pub mod sandbox_settings;
pub mod scene;
pub mod settings_file;
pub mod snapshot_save;
pub mod startup;
pub mod update_clock;
mod window_options;

pub use drive::DrivePlugin;
pub use offscreen::{OFFSCREEN_SIZE, OffscreenTarget, frame_path};
pub use output_failures::OutputFailures;
pub use sandbox_settings::{
    CameraMode, FRAGMENT_SPREAD_RANGE, MAX_BODIES_RANGE, MAX_BODY_COUNT, MIN_FRAGMENT_SIZE_RANGE,
    SHATTER_FRAGMENTS_RANGE, SPEED_RANGE, SandboxSettings, TRAIL_COUNT_RANGE, TrailChoice, UPS_RANGE, max_threads,
};
pub use scene::{SandboxState, ScenePlugin};
pub use settings_file::{SettingsFile, SettingsFilePlugin};
pub use snapshot_save::{SnapshotSave, SnapshotSavePlugin};
pub use startup::{Start, no_display};
pub use update_clock::UpdateClock;
pub use window_options::{WindowError, WindowOptions};
