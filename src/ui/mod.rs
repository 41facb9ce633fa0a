//! The interactive window (feature `gui`): one plugin per concern, gathered
//! in [`SandboxPlugins`] and added by `app.rs`, which also chains the
//! frame's phases ([`sets`]). The plugins live in folders by concern, which
//! depend on each other one way: [`session`] (options, settings, scene,
//! update clock) on nothing of the window but the phases; [`view`] (cameras,
//! picking) on it; [`draw`] (what is drawn, and how) on both; [`measure`]
//! (frame times, GPU memory, scripted runs) on `session` and `draw`;
//! [`tools`] (launch, fire, break up, remove, rewind, scripted actions) on
//! `session`, `view` and `measure`, and its panel section on [`widgets`]
//! (the panel's number fields); [`overlay`] (the egui panel and HUD) on
//! `session`, `view`, `measure`, `tools` and `widgets`.
//! The simulation itself is the same headless core (`crate::systems`),
//! driven at a chosen update rate.
//!
//! What is drawn never feeds back into the state, so the drawing may use
//! the platform's trigonometry (which `clippy.toml` keeps out of the
//! simulation): its last bits move a pixel, not a body.

#![expect(
    clippy::disallowed_methods,
    reason = "the drawing's trigonometry does not decide the state (see above)"
)]

mod app;
pub mod draw;
pub mod measure;
pub mod overlay;
mod plugins;
pub mod session;
pub mod sets;
pub mod tools;
pub mod view;
pub mod widgets;

pub use crate::resources::DrawMethod;
pub use app::run;
pub use plugins::SandboxPlugins;
pub use session::{WindowError, WindowOptions};
