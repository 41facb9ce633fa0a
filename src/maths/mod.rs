//! The numbers that decide the state: the transcendental functions and
//! rotations from `libm` (`functions.rs`), the same bits on every
//! processor, the seeded random stream (`rng.rs`), and floats as integers
//! in the same order (`float_order.rs`).

mod float_order;
mod functions;
mod rng;

pub use float_order::{from_order_key, order_key};
pub use functions::{cbrt, pow, rotation_x, rotation_y, rotation_yxz, rotation_z, sin_cos};
pub use rng::Rng;
