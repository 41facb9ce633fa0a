//! ECS resources shared by the stages.

mod body_ids;
mod settings;

pub use body_ids::*;
pub use settings::*;
