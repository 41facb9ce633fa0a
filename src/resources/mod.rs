//! ECS resources shared by the stages.

mod body_ids;
mod execution;
mod settings;
mod timings;

pub use body_ids::*;
pub use execution::*;
pub use settings::*;
pub use timings::*;
