//! The egui overlay: the settings panel on the left and the HUD over the view, and the cascade they show (the
//! Kessler curve and the totals). It reads the session, the view's
//! selection and the frame statistics.

pub mod cascade;
pub mod hud;
pub mod panel;

pub use cascade::CascadePlugin;
pub use hud::HudPlugin;
pub use panel::PanelPlugin;
