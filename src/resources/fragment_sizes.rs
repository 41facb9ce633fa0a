//! [`FragmentSizes`]: how a shatter sizes its fragments — the thesis's
//! equal cubes, or edge lengths drawn from the power law of the NASA
//! standard breakup model (docs/design.md, "Shatter").

use serde::{Deserialize, Serialize};

/// The largest exponent accepted (the breakup model's are 1.6 and 1.71).
pub const MAX_EXPONENT: f32 = 10.0;

/// How a shatter sizes its fragments.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub enum FragmentSizes {
    /// `shatter_fragments` equal cubes that keep the pair's volume (the
    /// thesis).
    #[default]
    Equal,
    /// Edge lengths `L` drawn from the cumulative law `N(>L) ∝ L^−exponent`
    /// of the NASA standard breakup model (1.71 for collisions, 1.6 for
    /// explosions), truncated to the smallest fragment and the parent's
    /// edge, until the pair's volume is used (the last fragment takes the
    /// rest), at most `shatter_fragments` of them.
    PowerLaw {
        /// The law's exponent, > 0 and at most [`MAX_EXPONENT`].
        exponent: f32,
    },
}

impl FragmentSizes {
    /// Whether its exponent (if any) is finite, > 0 and at most
    /// [`MAX_EXPONENT`].
    pub fn is_valid(self) -> bool {
        match self {
            Self::Equal => true,
            Self::PowerLaw { exponent } => exponent > 0.0 && exponent <= MAX_EXPONENT,
        }
    }
}
