//! ECS components.

mod body;

pub use body::*;
