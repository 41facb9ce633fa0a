//! Drawing the scene: the body cubes (one instanced draw call, split between
//! the main world's gather and the render world's draw, with
//! `instancing.wgsl`; or the comparison methods' mesh per body), their
//! colors and trails, the Earth and moons as textured spheres with the
//! atmosphere's rim (`atmosphere.wgsl`), the sunlight and stars, and the
//! present mode. The shaders are embedded with `load_internal_asset!` beside
//! the file that loads them. It reads the session and the view.

pub mod atmosphere;
pub mod backdrop;
pub mod body_colors;
pub mod celestials;
pub mod instance_slot;
pub mod instanced_draw;
pub mod instancing;
pub mod meshes;
pub mod planet_texture;
pub mod present_mode;
pub mod trails;

pub use atmosphere::AtmospherePlugin;
pub use backdrop::BackdropPlugin;
pub use body_colors::is_celestial;
pub use celestials::CelestialsPlugin;
pub use instance_slot::InstancedBodies;
pub use instanced_draw::BodyInstanceBuffer;
pub use instancing::InstancingPlugin;
pub use meshes::MeshesPlugin;
pub use present_mode::{PresentModePlugin, present_mode};
pub use trails::TrailsPlugin;
