//! The physics that is not a stage: axis-aligned boxes, the fragments a shatter or a breakup
//! makes (the response and the events both make them), and the totals
//! (mass, kinetic energy, momentum) that the records and the HUD show.

mod aabb;
mod fragments;
mod totals;

pub use aabb::Aabb;
pub use fragments::{
    LEAST_SOUND, PowerLaw, box_volume, breakup_fragments, fragment_half_extent, fragments, fragments_for,
    fragments_sound, power_law_fragments, power_law_halves, smallest_fragment_edge, sound_floor,
};
pub use totals::Totals;
