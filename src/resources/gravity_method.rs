//! [`GravityMethod`]: how the gravity stage sums the sources — every one
//! for every adopter, or through a Barnes–Hut octree.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

/// The opening angle of `Tree` when none is given.
pub const DEFAULT_THETA: f32 = 0.5;
/// The largest opening angle accepted (beyond, the error is large).
pub const MAX_THETA: f32 = 2.0;

/// How gravity is summed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub enum GravityMethod {
    /// Every source for every adopter, exact: for a planet and a moon, or up
    /// to a few hundred sources.
    #[default]
    Direct,
    /// A Barnes–Hut octree with opening angle `theta` (0 opens every node
    /// and gives the direct sum): for thousands of sources.
    Tree {
        /// Opening angle, 0 to [`MAX_THETA`].
        theta: f32,
    },
}

impl GravityMethod {
    /// The problem with the opening angle, if any.
    pub fn check(self) -> Result<Self, String> {
        match self {
            Self::Tree { theta } if !(0.0..=MAX_THETA).contains(&theta) => Err(format!(
                "theta must be finite and between 0 and {MAX_THETA}, got {theta}"
            )),
            ok => Ok(ok),
        }
    }
}

impl fmt::Display for GravityMethod {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Direct => f.write_str("direct"),
            Self::Tree { theta } => write!(f, "tree:{theta}"),
        }
    }
}

/// A `--gravity` value that is not `direct`, `tree` or `tree:THETA`.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("expected `direct`, `tree` or `tree:THETA` (THETA from 0 to {MAX_THETA}), got `{0}`")]
pub struct BadGravityMethod(pub String);

impl FromStr for GravityMethod {
    type Err = BadGravityMethod;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let bad = || BadGravityMethod(s.to_owned());
        let lower = s.trim().to_ascii_lowercase();
        let method = match lower.split_once(':') {
            None if lower == "direct" => Self::Direct,
            None if lower == "tree" => Self::Tree { theta: DEFAULT_THETA },
            Some(("tree", theta)) => Self::Tree {
                theta: theta.trim().parse().map_err(|_| bad())?,
            },
            _ => return Err(bad()),
        };
        method.check().map_err(|_| bad())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_direct_tree_and_tree_with_theta() {
        assert_eq!("direct".parse(), Ok(GravityMethod::Direct));
        assert_eq!("Tree".parse(), Ok(GravityMethod::Tree { theta: 0.5 }));
        assert_eq!("tree:0.7".parse(), Ok(GravityMethod::Tree { theta: 0.7 }));
        for bad in ["", "barnes", "tree:", "tree:-1", "tree:NaN", "tree:3", "direct:1"] {
            assert!(bad.parse::<GravityMethod>().is_err(), "{bad}");
        }
        let tree = GravityMethod::Tree { theta: 0.25 };
        assert_eq!(tree.to_string().parse(), Ok(tree), "round trip");
    }
}
