//! The numbers that decide the state: the transcendental functions and
//! rotations from `libm` (`functions.rs`), the same bits on every
//! processor, and the seeded random stream (`rng.rs`).

mod functions;
mod rng;

pub use functions::{cbrt, pow, rotation_x, rotation_y, rotation_yxz, rotation_z, sin_cos};
pub use rng::Rng;
