//! The interactive window (feature `gui`): GPU-instanced bodies, cameras,
//! the egui settings panel and HUD, saved settings. The simulation itself is
//! the same headless core (`crate::systems`), driven at a chosen update rate.

mod app;
pub mod body_colors;
pub mod camera;
pub mod capture;
pub mod clock;
pub mod drive;
pub mod frame_stats;
pub mod hud;
pub mod instancing;
pub mod meshes;
pub mod panel;
pub mod sandbox;
pub mod scene;
pub mod selection;
pub mod settings;

pub use app::run;
