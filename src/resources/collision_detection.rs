//! [`CollisionDetection`]: how the broad phase and the response find a
//! pair's contact — along each body's path over the update, or only where
//! the update ends, as the thesis did (docs/design.md, "Broad phase" and
//! "Response").

use serde::{Deserialize, Serialize};

/// How collisions are found.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum CollisionDetection {
    /// Along the straight line from each body's position at the update's
    /// start to its position at the end: two bodies that meet anywhere on
    /// the way collide, at the time they first touch, however fast.
    #[default]
    Swept,
    /// Where the update ends (the thesis): two bodies collide when their
    /// boxes overlap there, so bodies faster than their size per update
    /// may pass through one another unseen. The thesis's tables measured it.
    Discrete,
}

impl CollisionDetection {
    /// Its name in files and messages.
    pub fn name(self) -> &'static str {
        match self {
            Self::Swept => "Swept",
            Self::Discrete => "Discrete",
        }
    }
}
