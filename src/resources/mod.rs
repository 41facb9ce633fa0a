//! ECS resources shared by the stages.

mod body_ids;
mod gravity_method;
mod settings;

pub use body_ids::*;
pub use gravity_method::*;
pub use settings::*;
