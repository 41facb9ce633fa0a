//! [`GravityMethod`]: how the gravity stage sums the sources — every one
//! for every adopter, through a Barnes–Hut octree, or (the default) the
//! one of the two that suits the number of sources.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

/// The opening angle of `Tree` when none is given.
pub const DEFAULT_THETA: f32 = 0.5;
/// The largest opening angle accepted (beyond, the error is large).
pub const MAX_THETA: f32 = 2.0;
/// From how many sources `Auto` sums through the tree: below, the direct
/// sum costs at most about a millisecond per 500 adopters (measured: 500
/// mutually attracting bodies, 1.0 ms an update on one core direct, 0.2
/// through the tree; 2 000, 16 against 2.2).
pub const AUTO_TREE_FROM: usize = 512;

/// How gravity is summed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub enum GravityMethod {
    /// `Direct` while there are fewer than [`AUTO_TREE_FROM`] sources, else
    /// `Tree` at [`DEFAULT_THETA`], decided each update: a planet and a
    /// moon are summed exactly, a self-gravitating cluster whose fragments
    /// multiply moves to the tree when they pass the count.
    #[default]
    Auto,
    /// Every source for every adopter, exact: for a planet and a moon, or up
    /// to a few hundred sources.
    Direct,
    /// A Barnes–Hut octree with opening angle `theta` (0 opens every node
    /// and gives the direct sum): for thousands of sources.
    Tree {
        /// Opening angle, 0 to [`MAX_THETA`].
        theta: f32,
    },
}

impl GravityMethod {
    /// What `--gravity` says in `--help` (the one place it is written, with
    /// [`AUTO_TREE_FROM`]'s value).
    pub fn help() -> String {
        format!(
            "How gravity is summed: `auto` (`direct` below {AUTO_TREE_FROM} sources, else `tree`), `direct`, \
             or `tree` / `tree:THETA` (Barnes–Hut) [default: the scenario's]"
        )
    }

    /// The method used with `sources` sources: `Auto` decided, the others
    /// as they are.
    pub fn resolve(self, sources: usize) -> Self {
        match self {
            Self::Auto if sources < AUTO_TREE_FROM => Self::Direct,
            Self::Auto => Self::Tree { theta: DEFAULT_THETA },
            chosen => chosen,
        }
    }

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
            Self::Auto => f.write_str("auto"),
            Self::Direct => f.write_str("direct"),
            Self::Tree { theta } => write!(f, "tree:{theta}"),
        }
    }
}

/// A `--gravity` value that is not `auto`, `direct`, `tree` or
/// `tree:THETA`.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("expected `auto`, `direct`, `tree` or `tree:THETA` (THETA from 0 to {MAX_THETA}), got `{0}`")]
pub struct BadGravityMethod(pub String);

impl FromStr for GravityMethod {
    type Err = BadGravityMethod;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let bad = || BadGravityMethod(s.to_owned());
        let lower = s.trim().to_ascii_lowercase();
        let method = match lower.split_once(':') {
            None if lower == "auto" => Self::Auto,
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
    fn parses_auto_direct_tree_and_tree_with_theta() {
        assert_eq!("Auto".parse(), Ok(GravityMethod::Auto));
        assert_eq!(GravityMethod::Auto.to_string().parse(), Ok(GravityMethod::Auto));
        assert_eq!("direct".parse(), Ok(GravityMethod::Direct));
        assert_eq!("Tree".parse(), Ok(GravityMethod::Tree { theta: 0.5 }));
        assert_eq!("tree:0.7".parse(), Ok(GravityMethod::Tree { theta: 0.7 }));
        for bad in [
            "", "barnes", "tree:", "tree:-1", "tree:NaN", "tree:3", "direct:1", "auto:0.5",
        ] {
            assert!(bad.parse::<GravityMethod>().is_err(), "{bad}");
        }
        let tree = GravityMethod::Tree { theta: 0.25 };
        assert_eq!(tree.to_string().parse(), Ok(tree), "round trip");
    }

    #[test]
    fn auto_sums_directly_below_the_count_and_through_the_tree_from_it() {
        let auto = GravityMethod::Auto;
        assert_eq!(auto.resolve(0), GravityMethod::Direct);
        assert_eq!(auto.resolve(AUTO_TREE_FROM - 1), GravityMethod::Direct);
        let tree = GravityMethod::Tree { theta: DEFAULT_THETA };
        assert_eq!(auto.resolve(AUTO_TREE_FROM), tree);
        assert_eq!(GravityMethod::Direct.resolve(1_000_000), GravityMethod::Direct);
        assert_eq!(tree.resolve(2), tree, "a chosen method stays");
    }
}
