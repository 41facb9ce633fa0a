//! ECS components.

mod body;
mod body_state;

pub use body::*;
pub use body_state::*;
