//! The view: the cameras (orbit, free fly, follow) and picking a body with
//! the mouse, sharing the [`MainCamera`] marker. It reads the session's
//! settings and bodies; the drawing and the overlay read its selection.

pub mod camera;
pub mod main_camera;
pub mod selection;

pub use camera::CameraPlugin;
pub use main_camera::MainCamera;
pub use selection::{Selection, SelectionPlugin, find_holders, follow_selection, selected_info};
