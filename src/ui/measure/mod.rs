//! The window measuring itself: frame times (the HUD's FPS and plots, and
//! every frame of a `--frames` run), GPU memory, whether the pipelines are
//! compiled, the scripted runs that close after N frames and write a
//! screenshot and a frame-time report, and films (a picture every K
//! updates). It reads the session and what the drawing holds on the GPU.

pub mod capture;
pub mod film;
pub mod frame_stats;
pub mod gpu_memory;
pub mod picture;
pub mod pipelines;

pub use capture::{CapturePlugin, ScriptedRun};
pub use film::{Film, FilmPlugin};
pub use frame_stats::{FrameStats, FrameStatsPlugin, HISTORY};
pub use gpu_memory::GpuMemoryPlugin;
pub use pipelines::{PipelinesPlugin, PipelinesSettled};
