//! ECS resources shared by the stages.

mod body_ids;
mod execution;
mod keep_warm;
mod settings;
mod timings;

pub use body_ids::*;
pub use execution::*;
pub use keep_warm::*;
pub use settings::*;
pub use timings::*;
