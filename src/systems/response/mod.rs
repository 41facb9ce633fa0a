//! The response stage: [`stage`] matches the overlapping pairs and writes
//! the outcomes back; [`contact`] is its kernel, one pair's bounce,
//! push-back, separation or shatter decision.

mod contact;
mod stage;
mod swept;

pub use contact::{ContactBody, Motion, Outcome, apart_axes, collision_axes, elastic, respond, respond_to_ball};
pub use stage::{Absorbed, CollisionStats, Matched, ResponsePlugin, refuse_shatters};
pub use swept::{Meeting, contact_states, first_contact, respond_swept};
