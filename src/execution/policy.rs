//! [`SplitPolicy`]: from which body count a stage's work is split into
//! chunks in parallel mode, and [`AutoSplit`], the per-stage counts that
//! `Auto` uses (a calibration of this machine, or the fallback).

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

/// When a stage's work is split into chunks for the worker pool (parallel
/// mode only; sequential mode never splits). Results are the same bits
/// under every policy.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum SplitPolicy {
    /// From the body count this machine's calibration found for each stage
    /// ([`AutoSplit`]); without a calibration, from
    /// [`FALLBACK_SPLIT_FROM`] bodies.
    #[default]
    Auto,
    /// Every stage at every body count, as the thesis did.
    Always,
    /// Every stage from this many bodies on.
    Above(u64),
}

impl fmt::Display for SplitPolicy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Auto => f.write_str("auto"),
            Self::Always => f.write_str("always"),
            Self::Above(n) => write!(f, "{n}"),
        }
    }
}

/// A `--split` value that is neither `auto`, `always` nor a body count.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("expected `auto`, `always` or a body count (a whole number, 0 or more), got `{0}`")]
pub struct BadSplitPolicy(pub String);

impl FromStr for SplitPolicy {
    type Err = BadSplitPolicy;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "auto" => Ok(Self::Auto),
            "always" => Ok(Self::Always),
            other => other
                .parse::<u64>()
                .map(Self::Above)
                .map_err(|_| BadSplitPolicy(s.to_owned())),
        }
    }
}

/// Body count from which `Auto` splits a stage that no calibration covers:
/// between the crossovers measured on the two kinds of 2-core machine the
/// project ran on (every stage from about 1 000 bodies on an AMD EPYC VM,
/// 8 000–16 000 on an Intel Xeon VM), so that a new user's parallel run
/// pays where it clearly can (docs/design.md, "Sequential and parallel").
pub const FALLBACK_SPLIT_FROM: u64 = 4_096;

/// The body count from which `Auto` splits each stage.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AutoSplit {
    /// `(stage name, split from this many bodies)`.
    stages: Vec<(String, u64)>,
    /// Where the counts come from, for summaries.
    origin: String,
}

impl Default for AutoSplit {
    fn default() -> Self {
        Self::fallback()
    }
}

impl AutoSplit {
    /// No calibration: every stage splits from [`FALLBACK_SPLIT_FROM`].
    pub fn fallback() -> Self {
        Self {
            stages: Vec::new(),
            origin: format!("no calibration: every stage from {FALLBACK_SPLIT_FROM} bodies"),
        }
    }

    /// Counts per stage name, described by `origin` (e.g. the file they
    /// were read from); stages not listed use the fallback.
    pub fn calibrated(stages: Vec<(String, u64)>, origin: impl Into<String>) -> Self {
        Self {
            stages,
            origin: origin.into(),
        }
    }

    /// The body count from which `Auto` splits `stage`.
    pub fn split_from(&self, stage: &str) -> u64 {
        self.stages
            .iter()
            .find(|(name, _)| name == stage)
            .map_or(FALLBACK_SPLIT_FROM, |&(_, n)| n)
    }

    /// The per-stage counts.
    pub fn stages(&self) -> &[(String, u64)] {
        &self.stages
    }

    /// Where the counts come from.
    pub fn origin(&self) -> &str {
        &self.origin
    }
}

impl SplitPolicy {
    /// Whether `stage` splits its work at `bodies` bodies under this policy.
    pub fn splits(self, stage: &str, bodies: usize, auto: &AutoSplit) -> bool {
        let bodies = bodies as u64;
        match self {
            Self::Always => true,
            Self::Above(n) => bodies >= n,
            Self::Auto => bodies >= auto.split_from(stage),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn policies_parse_from_the_command_line_and_print_back() {
        for (text, policy) in [
            ("auto", SplitPolicy::Auto),
            ("Always", SplitPolicy::Always),
            ("5000", SplitPolicy::Above(5000)),
            ("0", SplitPolicy::Above(0)),
        ] {
            assert_eq!(text.parse::<SplitPolicy>(), Ok(policy));
            assert_eq!(policy.to_string().parse::<SplitPolicy>(), Ok(policy));
        }
        for bad in ["-5", "sometimes", "", "1e3", "2.5"] {
            let error = bad.parse::<SplitPolicy>().unwrap_err();
            assert!(error.to_string().contains(&format!("`{bad}`")), "{error}");
        }
    }

    #[test]
    fn each_policy_decides_by_body_count() {
        let auto = AutoSplit::calibrated(vec![("gravity".into(), 300)], "test");
        assert!(SplitPolicy::Always.splits("sweep", 0, &auto));
        assert!(!SplitPolicy::Above(1000).splits("sweep", 999, &auto));
        assert!(SplitPolicy::Above(1000).splits("sweep", 1000, &auto));
        assert!(SplitPolicy::Auto.splits("gravity", 300, &auto));
        assert!(!SplitPolicy::Auto.splits("gravity", 299, &auto));
        let uncalibrated = FALLBACK_SPLIT_FROM as usize;
        assert!(!SplitPolicy::Auto.splits("sweep", uncalibrated - 1, &auto));
        assert!(SplitPolicy::Auto.splits("sweep", uncalibrated, &auto));
    }
}
