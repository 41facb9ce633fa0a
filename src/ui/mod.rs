//! The interactive window (feature `gui`): one plugin per concern, added by
//! `app.rs`. The simulation itself is the same headless core
//! (`crate::systems`), driven at a chosen update rate.

mod app;
pub mod atmosphere;
pub mod backdrop;
pub mod body_colors;
pub mod camera;
pub mod capture;
pub mod cascade;
pub mod celestials;
pub mod clock;
pub mod drive;
pub mod frame_stats;
pub mod gpu_memory;
pub mod hud;
pub mod instance_slot;
pub mod instanced_draw;
pub mod instancing;
pub mod main_camera;
pub mod meshes;
pub mod panel;
pub mod planet_texture;
pub mod present_mode;
pub mod scene;
pub mod selection;
pub mod sets;
pub mod settings;
pub mod settings_file;
pub mod snapshot_save;
pub mod startup;
pub mod trails;
pub mod widgets;
mod window_options;

pub use crate::draw_method::DrawMethod;
pub use app::run;
pub use window_options::*;
